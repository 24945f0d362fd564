"""HUD quads: the rows every overlay (the HUD, the menus, the cards, the prologue) is drawn from.

Everything drawn over the scene is an axis-aligned textured quad: text samples glyphs from the
font atlas (:mod:`.font`), rectangles a fully lit block of the same atlas, so one instanced draw
call with one shader draws it all (:class:`~.hud.HudRenderer`). :class:`QuadList` collects them
in draw order; :func:`quads_text` reads the words back for tests.
"""

from __future__ import annotations

import functools

import numpy as np

from .font import GLYPH_H, default_font, font_px, solid_uv

#: Floats per HUD quad: rect x, y, w, h (px) | atlas u0, v0, u1, v1 (texels) | r, g, b, a.
QUAD_FLOATS = 12


class QuadList:
    """Collects HUD quads as rows of :data:`QUAD_FLOATS` floats, in draw order.

    Rectangles are kept as tuples; a line of text is kept as its cached glyph run and offset, and
    becomes rows only in :meth:`array` (one numpy block per line, no per-glyph Python work).
    """

    def __init__(self):
        self.rows: list[tuple[float, ...]] = []
        self._runs: list[tuple[int, np.ndarray, int, int, tuple]] = []  # (position in rows, run, x, y, colour)
        self._solid_uv = solid_uv()

    def rect(self, x, y, w, h, color) -> None:
        if w > 0 and h > 0 and color[3] > 0:
            self.rows.append((x, y, w, h, *self._solid_uv, *color))

    def text(self, s: str, x, y, scale: int, color, shadow: bool = True) -> None:
        """Text with the top of its capitals at ``(x, y)``; a 1-scale-pixel drop shadow for contrast."""
        if shadow:
            self._glyphs(s, x + scale, y + scale, scale, (0.0, 0.0, 0.0, 0.6 * color[3]))
        self._glyphs(s, x, y, scale, color)

    def _glyphs(self, s, x, y, scale, color) -> None:
        run = _glyph_run(s, int(scale))
        if len(run):
            self._runs.append((len(self.rows), run, int(round(x)), int(round(y)), tuple(color)))

    def quads(self, block: np.ndarray) -> None:
        """Finished quads, ``(n, QUAD_FLOATS)`` (another list's :meth:`array`), drawn as they are."""
        if len(block):
            self._runs.append((len(self.rows), block, 0, 0, None))

    def array(self) -> np.ndarray:
        rects = np.asarray(self.rows, np.float32).reshape(-1, QUAD_FLOATS)
        if not self._runs:
            return rects
        parts, at = [], 0
        for pos, run, x, y, color in self._runs:
            if pos > at:
                parts.append(rects[at:pos])
                at = pos
            if color is None:
                parts.append(np.asarray(run, np.float32))
                continue
            block = np.empty((len(run), QUAD_FLOATS), np.float32)
            block[:, :8] = run
            block[:, 0] += x
            block[:, 1] += y
            block[:, 8:] = color
            parts.append(block)
        parts.append(rects[at:])
        return np.concatenate(parts)


@functools.lru_cache(maxsize=4096)
def _glyph_run(s: str, scale: int) -> np.ndarray:
    """The glyph quads of one line of text at ``(0, 0)``: ``(n, 8) float64`` rows of rect ``x, y,
    w, h`` and atlas ``u0, v0, u1, v1``. Cached: HUD lines repeat from frame to frame, and a
    glyph's place in the atlas never changes once rasterized."""
    font = default_font()
    px = font_px(scale)
    baseline = GLYPH_H * scale
    pen = 0.0
    rows = []
    for ch in s:
        g = font.glyph(ch, px)
        if g.w:
            gx = int(round(pen)) + g.left
            rows.append((gx, baseline + g.top, g.w, g.h, g.u, g.v, g.u + g.w, g.v + g.h))
        pen += g.advance
    run = np.asarray(rows, np.float64).reshape(-1, 8)
    run.setflags(write=False)
    return run


def quads_text(quads: np.ndarray) -> str:
    """The characters drawn by ``quads``, in draw order (solid rectangles and spaces give nothing).

    Each glyph bitmap has its own place in the atlas, so a quad's atlas origin names its
    character: tests read the HUD's words back from its layout with this.
    """
    font = default_font()
    return "".join(ch for q in quads if (ch := font.char_at(q[4], q[5])) is not None)


def mix(a, b, t):
    """The colour ``t`` of the way from ``a`` to ``b``."""
    return tuple(x + (y - x) * t for x, y in zip(a, b))
