"""The physics world's tick, and its new contacts as game events."""

from __future__ import annotations

from ..events import Contact


def step(game, actions) -> None:
    if game.physics is None:
        return
    game.physics.tick()
    for c in game.physics.events:
        if not c.began:
            continue
        other = None if isinstance(c.b, str) else game.entity_of_body.get(c.b)
        game.emit(Contact(game.entity_of_body.get(c.a, -1), other, float(c.impulse)))
