"""Paying for turning the slice: ``[energy] slice_cost`` energy per degree.

The slice's *rest* is the 90-degree orientation it last landed on (``CameraRig.rest``, the
plain slice at the start). Turning pays for the farthest the slice has been from its rest,
in degrees (the angle of the turn between the two), to the thousandth and rounded up:

- turning back towards the rest is free, and so is turning again within what was paid;
- landing on a 90-degree orientation (a step or a snap) makes it the new rest;
- the bar limits how far a tick may turn, so the slice stops exactly when the bar runs dry
  and never owes energy; a step the bar cannot pay in full is refused before it starts.

So a 90-degree step costs ``ceil(90 * slice_cost * 1000)`` thousandths however it is done
(stepped, held, snapped or a mix), a turn the player undoes costs only what it reached, and
a player whose bar runs dry half way can always turn back to where the slice rested: the
turn never strands anyone. Every payment goes through :meth:`~.energy.EnergyBar.spend_up_to`
with the reason ``"slice_turn"``.
"""

from __future__ import annotations

import numpy as np

#: A full step of the slice, degrees (what the HUD prices).
STEP_DEG = 90.0
#: Thousandths below a whole one that still round down (an exact 90-degree landing is
#: 90 degrees to about 1e-13: it must cost the step's price, not one more).
ROUNDING = 1e-6


def per_degree_milli(game) -> int:
    """Energy per degree in thousandths; 0 when turning is free (no bar, or no cost)."""
    return game.level.energy.slice_cost_milli if game.energy is not None else 0


def away_deg(rig, rot: np.ndarray | None = None) -> float:
    """Degrees between ``rot (4, 4)`` (the slice's rotation by default) and the rest: the angle
    of a turn in one plane, from the Frobenius gap ``2 sqrt(2) sin(angle / 2)``."""
    gap = float(np.linalg.norm((rig.rotation if rot is None else rot) - rig.rest))
    return float(np.degrees(2.0 * np.arcsin(min(1.0, gap / (2.0 * np.sqrt(2.0))))))


def owed_for(game, rig, rot: np.ndarray | None = None) -> int:
    """Thousandths still to pay for the slice to stand at ``rot`` (its rotation by default)."""
    cost = per_degree_milli(game)
    if cost <= 0:
        return 0
    due = int(np.ceil(away_deg(rig, rot) * cost - ROUNDING))
    return max(0, due - rig.turn_paid_milli)


def step_price(per_degree: int) -> int:
    """What a 90-degree step from rest costs at ``per_degree`` thousandths a degree, thousandths."""
    return int(np.ceil(STEP_DEG * per_degree - ROUNDING))


def step_milli(game) -> int:
    """What a 90-degree step from rest costs in ``game``, thousandths."""
    return step_price(per_degree_milli(game))


def room_rad(game, rig, before: np.ndarray) -> float:
    """How much farther from the rest than ``before (4, 4)`` the bar can pay for, radians."""
    cost = per_degree_milli(game)
    reach = (rig.turn_paid_milli + game.energy.milli) / cost
    return max(0.0, float(np.radians(reach - away_deg(rig, before))))


def short(game, rig) -> bool:
    """Does the slice's pose cost more than the bar holds?"""
    return per_degree_milli(game) > 0 and owed_for(game, rig) > game.energy.milli


def pay(game, rig) -> None:
    """Pay what the slice's pose owes (never more than the bar holds)."""
    due = owed_for(game, rig)
    if due > 0:
        rig.turn_paid_milli += game.energy.spend_up_to(game, due, "slice_turn")


def landed(rig) -> None:
    """The slice landed on a 90-degree orientation: turning is measured from there now."""
    rig.rest = rig.rotation.copy()
    rig.turn_paid_milli = 0
