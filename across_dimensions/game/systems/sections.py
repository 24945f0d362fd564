"""Every entity with a 4D mesh, drawn as its cross-section at the player's w.

Entities whose bounding radius does not reach the slice are skipped without
slicing (most 4D things in a level are at other w most of the time).
"""

from __future__ import annotations

import numpy as np

from ..frame import Drawable


def draw(game, frame, alpha) -> None:
    w = float(game.player.position[3])
    shown = game.entity_table().reaching(w)
    game.sections.keep("draw:", {f"draw:{e.id}" for e in shown})  # the rest left the slice
    for e in shown:
        model = e.model(game, alpha)
        tri, rev = game.sections.section(f"draw:{e.id}", e.mesh, model, w)
        frame.drawables.append(Drawable(f"entity:{e.id}", rev, tri, style=e.style, w_offset=_w_offset(e, model, w)))


def _w_offset(e, model: np.ndarray, w: float) -> float:
    """Where the slice cuts the entity along w: 0 mid-way through its w extent, -1 or 1 at its
    ends (the renderer's w cue). The extent is the posed mesh's, so a turning thing's changes."""
    ws = e.mesh.vertices @ model[3, :4].astype(np.float32) + np.float32(model[3, 4])
    lo, hi = float(ws.min()), float(ws.max())
    half = 0.5 * (hi - lo)
    return (0.5 * (lo + hi) - w) / half if half > 0.0 else 0.0
