"""The level's solid 4D objects as colliders for the rigid bodies, refreshed before the physics tick.

A door removed by a switch stops blocking bodies at once; an object that moves
(spins) is met where it is this tick. See :func:`..player_bodies.solid_boxes`.
"""

from __future__ import annotations

from ..player_bodies import sync_solids


def step(game, actions) -> None:
    sync_solids(game)
