"""The physics world's tick, and its new contacts as game events."""

from __future__ import annotations

from ..events import Contact
from ..system import System


def step(game, actions) -> None:
    if game.physics is None:
        return
    game.physics.tick()
    for c in game.physics.events:
        if not c.began:
            continue
        other = None if isinstance(c.b, str) else game.entity_of_body.get(c.b)
        game.emit(Contact(game.entity_of_body.get(c.a, -1), other, float(c.impulse)))


def state_bytes(game) -> bytes:
    """The physics world's state (bodies, contacts kept between ticks; see ``PhysicsWorld.state_bytes``)."""
    return game.physics.state_bytes() if game.physics is not None else b""


SYSTEM = System("rigid_bodies", step=step, state_bytes=state_bytes)
