"""Every entity with a 4D mesh, drawn as its cross-section at the player's w.

Entities whose bounding radius does not reach the slice are skipped without
slicing (most 4D things in a level are at other w most of the time).
"""

from __future__ import annotations

from ..frame import Drawable


def draw(game, frame, alpha) -> None:
    w = float(game.player.position[3])
    for e in game.entities:
        if e.mesh is None:
            continue
        key = f"draw:{e.id}"
        if not e.reaches_slice(game, w):  # nothing to slice: skip the kernel
            game.sections.forget(key)
            continue
        tri, rev = game.sections.section(key, e.mesh, e.model(game, alpha), w)
        frame.drawables.append(Drawable(f"entity:{e.id}", rev, tri, style=e.style))
