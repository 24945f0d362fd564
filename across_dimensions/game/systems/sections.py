"""Every entity with a 4D mesh, drawn as its cross-section at the player's w."""

from __future__ import annotations

from ..frame import Drawable


def draw(game, frame, alpha) -> None:
    w = float(game.player.position[3])
    for e in game.entities:
        if e.mesh is None:
            continue
        tri, rev = game.sections.section(f"draw:{e.id}", e.mesh, e.model(game, alpha), w)
        frame.drawables.append(Drawable(f"entity:{e.id}", rev, tri, style=e.style))
