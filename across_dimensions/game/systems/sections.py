"""Every entity with a 4D mesh, drawn as its cross-section at the player's w.

Entities whose bounding radius does not reach the slice are skipped without
slicing (most 4D things in a level are at other w most of the time); the rest
are sliced together, one batch per style (see ``game/entity_sections.py``).
"""

from __future__ import annotations

from ..entity_sections import w_offset
from ..frame import Drawable


def draw(game, frame, alpha) -> None:
    w = float(game.player.position[3])
    shown = game.entity_table().reaching(w)
    # All of them in one kernel call per style, drawn with one call each (game/entity_sections.py).
    game.entity_sections.draw(frame, shown, [e.model(game, alpha) for e in shown], w, game.sections)


def draw_per_object(game, frame, alpha) -> None:
    """The same entities as one drawable each (the path :func:`draw` replaces; tests compare the two)."""
    w = float(game.player.position[3])
    shown = game.entity_table().reaching(w)
    game.sections.keep("draw:", {f"draw:{e.id}" for e in shown})  # the rest left the slice
    for e in shown:
        model = e.model(game, alpha)
        tri, rev = game.sections.section(f"draw:{e.id}", e.mesh, model, w)
        frame.drawables.append(Drawable(f"entity:{e.id}", rev, tri, style=e.style, w_offset=w_offset(e.mesh, model, w)))
