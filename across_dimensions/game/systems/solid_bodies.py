"""The level's solid 4D objects as colliders for the rigid bodies, refreshed before the physics tick.

A door removed by a switch stops blocking bodies at once; an object that moves
(spins) is met where it is this tick, and carries the bodies on it by the velocity
of its last move. See :func:`..player_bodies.sync_solids`.
"""

from __future__ import annotations

from ..player_bodies import SolidColliders, sync_solids
from ..system import System, encode


def setup(game) -> SolidColliders:
    return SolidColliders()


def step(game, actions) -> None:
    sync_solids(game)


def state_bytes(game) -> bytes:
    """Where each moving solid was last placed (its next move's velocity is measured from there)."""
    return encode(game.states.solid_bodies)


SYSTEM = System("solid_bodies", setup, step, state_bytes=state_bytes)
