"""Crystals: 4D energy the player collects by touching its cross-section.

A crystal can only be touched where it can be seen: the player must be at a w
where the crystal's cross-section exists, and the player's box must reach that
section. A crystal is taken once, adds its energy to the bar (up to the
maximum) and disappears.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..events import CrystalCollected
from ..player import player_box

REACH = 0.15  # metres beyond the player's box that still count as touching (a hand's reach)


@dataclass
class Crystal:
    """A crystal's state (``Entity.data``)."""

    milli: int  # energy it holds, thousandths


def touching(game, entity) -> bool:
    """Does the player's box (plus :data:`REACH`) touch the entity's section in the player's slice?"""
    p = game.player
    model = entity.model(game)
    centre, w = model[:3, 4], float(p.position[3])
    # Cheap rejections before slicing: out of reach in w or in space.
    reach = entity.radius * float(np.linalg.norm(model[:4, :4], axis=0).max()) + REACH
    lo, hi = player_box(p.position)
    if abs(model[3, 4] - w) > reach or np.any(centre < lo - reach) or np.any(centre > hi + reach):
        return False
    key = f"tick:{entity.id}"
    game.sections.section(key, entity.mesh, model, w)
    b = game.sections.bounds(key)
    if np.isnan(b).any():
        return False  # not in the slice: invisible, so untouchable
    return bool(np.all(lo - REACH < b[1]) and np.all(hi + REACH > b[0]))


def step(game, actions) -> None:
    for e in game.entities.of_kind("crystal"):
        if touching(game, e):
            gained = game.energy.gain(e.data.milli) if game.energy is not None else 0
            game.emit(CrystalCollected(e.id, e.data.milli, gained))
            game.remove(e.id)
