"""Drawing sounds made visible: the captions and the marks at the screen's edge.

The captions (``hud.captions``, made by :mod:`across_dimensions.app.captions` when the player
turns them on) are lines on dark bands below the crosshair, above the slice gauges and the
weapon panel and between the energy bar and the radar, newest at the bottom. A sound heard along w also gets
a mark at the edge of the view on its side (left or right): a bar in the palette's ana or
kata colour, higher for ana and lower for kata (as the w gauge and the radar's pins), with
``+w`` or ``-w`` written beside it, so the side is never told by colour alone.
"""

from __future__ import annotations

from .font import CELL_W, GLYPH_H, text_width
from .palette import cue
from .text_layout import ellipsized

BAND = (0.0, 0.0, 0.0, 0.62)
TEXT = (0.95, 0.97, 1.0, 1.0)
#: Where a mark's middle is, as a fraction of the view's height from the top, by side.
MARK_Y = {1: 0.36, -1: 0.62}


def caption_rects(captions, m) -> list[tuple[int, int, int, int]]:
    """Each caption's band ``(x, y, w, h)`` in pixels (origin top-left) for HUD metrics ``m``."""
    s = m.text_scale
    ex, bar_y, ew, bar_h = m.energy_bar()
    left, right = ex + ew + m.margin, m.radar_rect()[0] - m.margin
    line_h = (GLYPH_H + 4) * s
    # Above the weapon panel (up to two lines and a refusal over the energy bar), the slice
    # gauges and the warning line.
    bottom = min(int(m.height * 0.74), bar_y - 5 * (GLYPH_H + 3) * s - 3 * bar_h)
    out = []
    for i, c in enumerate(captions):
        w = min(right - left, text_width(c.text, s) + 4 * s)
        y = bottom - (len(captions) - i) * (line_h + s)
        out.append((left + (right - left - w) // 2, y, w, line_h))
    return out


def mark_rect(caption, m) -> tuple[int, int, int, int]:
    """The edge mark's bar ``(x, y, w, h)`` of a caption heard along w (``side`` not 0)."""
    s = m.text_scale
    bar_w, bar_h = 2 * s + 2, max(8, m.height // 8)
    if caption.pan < 0:
        x = m.margin // 2
    else:  # left of the w gauge and its value on the right
        x = m.w_track()[0] - 4 * CELL_W * s - bar_w
    y = int(m.height * MARK_Y[caption.side]) - bar_h // 2
    return x, y, bar_w, bar_h


def draw_captions(q, captions, m) -> None:
    """Add the captions and their edge marks to the HUD's quad list ``q``."""
    if not captions:
        return
    s = m.text_scale
    for c, (x, y, w, h) in zip(captions, caption_rects(captions, m)):
        a = max(0.0, min(1.0, c.fade))
        q.rect(x, y, w, h, BAND[:3] + (BAND[3] * a,))
        q.text(ellipsized(c.text, w - 4 * s, s), x + 2 * s, y + 2 * s, s, TEXT[:3] + (a,))
    for c in captions:
        if c.side == 0:
            continue
        x, y, w, h = mark_rect(c, m)
        colour = cue("label_ana" if c.side > 0 else "label_kata")
        colour = colour[:3] + (colour[3] * max(0.0, min(1.0, c.fade)),)
        q.rect(x, y, w, h, colour)
        word = "+w" if c.side > 0 else "-w"
        tx = x + w + s if c.pan < 0 else x - text_width(word, s) - s
        q.text(word, tx, y + h // 2 - GLYPH_H * s // 2, s, colour)


__all__ = ["caption_rects", "draw_captions", "mark_rect"]
