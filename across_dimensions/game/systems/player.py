"""The player: walking, looking, moving along w (paid for with energy), falling out.

Moving along w costs the level's ``w_cost`` energy per unit of w travelled. The
bar limits how far the player may move in a tick, so the player stops exactly
when it runs dry and never owes energy; what was travelled is then paid.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..events import Respawned, WBlocked
from ..player import Surroundings, step_player
from ..system import System, encode
from . import seek

FALL_LIMIT = -30.0  # below this y the player has fallen out of the level


@dataclass
class Walk:
    """What the walk carries from tick to tick (``game.states.player``); the player's own
    position and velocity are ``game.player``.

    Attributes
    ----------
    w_blocked : bool
        The player pushed along w into something last tick (a new push is a new event).
    """

    w_blocked: bool = False


def setup(game) -> Walk:
    return Walk()


def state_bytes(game) -> bytes:
    return encode(game.states.player)


def _w_budget(game) -> float:
    """How far along w the bar can pay for this tick (unlimited when w is free)."""
    cost = game.level.energy.w_cost_milli if game.energy is not None else 0
    return np.inf if cost <= 0 else game.energy.milli / cost


def step(game, actions) -> None:
    p = game.player
    w_before = float(p.position[3])
    cut = step_player(
        p,
        actions,
        game.dt,
        float(game.level.gravity[1]),
        Surroundings(
            game.level.w_range,
            game.colliders_at,
            game.bodies_block_w if game.physics is not None else None,
            game.sections_at,
        ),
        _w_budget(game),
        seek.w_goal(game),  # a seek glides through the same w motion, checks and payment
    )
    seek.moved(game, cut)
    travelled = abs(float(p.position[3]) - w_before)
    if game.energy is not None and travelled > 0.0 and game.level.energy.w_cost_milli > 0:
        # Round up so that no run of tiny steps is free, but never past what the bar holds.
        owed = int(np.ceil(travelled * game.level.energy.w_cost_milli - 1e-9))
        game.energy.spend_up_to(game, owed, "w_move")

    walk = game.states.player
    pushing = actions.w != 0.0 and cut is not None
    if pushing and not walk.w_blocked:
        game.emit(WBlocked(cut, 1 if actions.w > 0 else -1))
    walk.w_blocked = pushing

    if p.position[1] < FALL_LIMIT:
        game.respawn()
        game.emit(Respawned())


SYSTEM = System("player", setup, step, state_bytes=state_bytes)
