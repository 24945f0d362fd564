"""Teaching cards drawn with the HUD's quads: the lower-dimensional analogy before the first 4D move.

The ``"flatland"`` card (as in 4D Golf and 4D Miner) shows, animated, a flat being living in a
plane and a ball passing through that plane:

* left, *what is there*: the plane seen at a slant, the flat being standing in it, and a 3D ball
  moving up and down through it; where the ball cuts the plane a bright disc lies in the plane;
* right, *what the flat being sees*: its whole world, the plane seen from above, where the same
  ball is only a circle that appears, grows, shrinks and vanishes, and nothing of the ball off
  the plane is visible at all.

Everything is axis-aligned rectangles (curves are scanlines), so the card is drawn by the HUD's
one shader and can be laid out and tested without OpenGL. The captions come with the
:class:`~across_dimensions.game.frame.Card` (the window fills in the player's keys).
"""

from __future__ import annotations

import math

from ..game.frame import Card
from .font import GLYPH_H, text_width
from .text_layout import scaled, wrap

#: Seconds for the ball to go from above the plane to below it and back.
PERIOD = 6.0
DIM = (0.0, 0.0, 0.0, 0.72)
PANEL = (0.03, 0.05, 0.10, 0.96)
FRAME = (0.3, 0.85, 1.0, 0.9)
PLANE = (0.25, 0.55, 0.9, 0.45)
PLANE_EDGE = (0.55, 0.8, 1.0, 0.9)
BALL = (1.0, 0.62, 0.25, 1.0)
BALL_BEHIND = (0.75, 0.42, 0.2, 0.55)
SECTION = (0.45, 1.0, 0.95, 1.0)
BEING = (0.95, 0.95, 0.4, 1.0)
EYE = (0.05, 0.05, 0.1, 1.0)
TITLE = (0.95, 0.97, 1.0, 1.0)
TEXT = (0.85, 0.9, 1.0, 1.0)
CAPTION = (0.6, 0.8, 0.95, 0.9)
PROMPT = (0.5, 1.0, 0.7, 1.0)


def ball_height(t: float, radius: float) -> float:
    """Height of the ball's centre above the plane at ``t`` seconds, in units of the drawing.

    A cosine from ``1.7 r`` above to ``1.7 r`` below and back, so the ball spends some of each
    period wholly off the plane (invisible to the flat being).
    """
    return 1.7 * radius * math.cos(2.0 * math.pi * t / PERIOD)


def section_radius(height: float, radius: float) -> float:
    """Radius of the circle where a ball of ``radius`` whose centre is ``height`` off the plane cuts it."""
    return math.sqrt(radius * radius - height * height) if abs(height) < radius else 0.0


def _disc(q, cx, cy, rx, ry, color, step: int = 1, keep=lambda y: True) -> None:
    """A filled ellipse as horizontal scanlines ``step`` pixels tall; ``keep(y)`` filters rows."""
    if rx < 0.5 or ry < 0.5:
        return
    y = -ry
    while y < ry:
        mid = y + step / 2.0
        half = rx * math.sqrt(max(0.0, 1.0 - (mid / ry) ** 2))
        row = int(round(cy + y))
        if half >= 0.5 and keep(row):
            q.rect(int(round(cx - half)), row, int(round(2 * half)), step, color)
        y += step


def draw_card(q, card: Card, width: int, height: int) -> None:
    """Append the card's quads to ``q`` (the HUD's quad list) for a ``width x height`` view."""
    if card.kind != "flatland":
        return
    W, H = int(width), int(height)
    pw, ph = int(W * 0.84), int(H * 0.84)
    px, py = (W - pw) // 2, (H - ph) // 2
    pad = max(4, W // 80)
    lines = list(card.lines) or [""]
    art_w = (pw - 3 * pad) // 2
    body = lines[3:-1] if len(lines) > 4 else lines[3:]
    # The player's text size, made smaller again where the words would leave the drawings
    # less than a quarter of the panel (a large text size on a small window).
    base = max(1, H // 300)
    for s in range(scaled(base), base - 1, -1):
        title_scale = min(2 * s if H >= 200 else s, max(1, (pw - 2 * pad) * s // max(1, text_width(lines[0], s))))
        caps = [wrap(cap, art_w, s) for cap in lines[1:3]]
        cap_h = max((len(c) for c in caps), default=1) * (GLYPH_H + 6) * s
        prompt_h = GLYPH_H * s + pad if len(lines) > 4 else 0
        words_h = (GLYPH_H + 5) * title_scale + cap_h + prompt_h
        words_h += sum(len(wrap(para, pw - 2 * pad, s)) * (GLYPH_H + 4) * s + 2 * s for para in body)
        art_h = min(int(ph * 0.5), ph - 2 * pad - pad // 2 - words_h)
        if art_h >= ph // 4:
            break
    q.rect(0, 0, W, H, DIM)
    q.rect(px - s, py - s, pw + 2 * s, ph + 2 * s, FRAME)
    q.rect(px, py, pw, ph, PANEL)
    y = py + pad
    q.text(lines[0], (W - text_width(lines[0], title_scale)) // 2, y, title_scale, TITLE)
    y += (GLYPH_H + 5) * title_scale

    # Two drawings side by side, in the upper part of the panel.
    left = (px + pad, y, art_w, art_h)
    right = (px + 2 * pad + art_w, y, art_w, art_h)
    r = min(art_w, art_h) * 0.16  # the ball's radius, pixels
    h = ball_height(card.time, r)
    cut = section_radius(h, r)
    _side_view(q, left, r, h, cut, s)
    _flat_view(q, right, r, cut, s)
    y += art_h + pad // 2
    # Captions under the drawings.
    for (ax, _, aw, _), cap in zip((left, right), caps):
        for i, ln in enumerate(cap):
            q.text(ln, ax + (aw - text_width(ln, s)) // 2, y + i * (GLYPH_H + 6) * s, s, CAPTION)
    y += cap_h
    # The body text and, last, the prompt.
    for para in body:
        for ln in wrap(para, pw - 2 * pad, s):
            q.text(ln, px + pad, y, s, TEXT)
            y += (GLYPH_H + 4) * s
        y += 2 * s
    if len(lines) > 4:
        prompt = lines[-1]
        blink = 0.75 + 0.25 * math.cos(card.time * 4.0)
        q.text(prompt, (W - text_width(prompt, s)) // 2, py + ph - pad - GLYPH_H * s, s, PROMPT[:3] + (blink,))


def _side_view(q, box, r, h, cut, s) -> None:
    """The plane at a slant (a parallelogram of scanlines), the flat being in it, the ball through it."""
    x, y, w, hh = box
    cx, cy = x + w / 2.0, y + hh / 2.0
    depth = hh * 0.22  # the plane's apparent depth on screen: seen at a slant
    slant = depth * 0.9
    half_w = w * 0.42
    top, bot = int(cy - depth / 2), int(cy + depth / 2)

    def in_plane_rows(row: int) -> bool:
        return top <= row < bot

    # The part of the ball below the plane, seen through it (dim), then the plane, then the rest.
    below = lambda row: row >= cy  # noqa: E731
    above = lambda row: row < cy  # noqa: E731
    _disc(q, cx, cy - h, r, r, BALL_BEHIND, keep=below)
    for row in range(top, bot):
        t = (row - top) / max(1, bot - top)  # 0 at the far edge, 1 at the near one
        shift = slant * (0.5 - t)
        q.rect(int(cx - half_w + shift), row, int(2 * half_w), 1, PLANE)
    q.rect(int(cx - half_w + slant / 2), top - s, int(2 * half_w), s, PLANE_EDGE)
    q.rect(int(cx - half_w - slant / 2), bot, int(2 * half_w), s, PLANE_EDGE)
    # The cut: a disc lying in the plane, flattened as the plane is.
    _disc(q, cx, cy, cut, cut * depth / (2 * half_w) * 2.2, SECTION)
    _disc(q, cx, cy - h, r, r, BALL, keep=lambda row: above(row) and not (in_plane_rows(row) and cut > 0))
    # The flat being: a small triangle lying in the plane, left of the ball, with an eye.
    bx, by = cx - half_w * 0.62, cy
    size = max(3.0, r * 0.45)
    _triangle(q, bx, by, size, size * 0.45, BEING)
    q.rect(int(bx + size * 0.25), int(by - s), max(1, s), max(1, s), EYE)


def _flat_view(q, box, r, cut, s) -> None:
    """The flat being's whole world from above: the being, and the ball's circle when it cuts the plane."""
    x, y, w, hh = box
    q.rect(x, y, w, hh, PLANE[:3] + (0.25,))
    q.rect(x, y, w, s, PLANE_EDGE)
    q.rect(x, y + hh - s, w, s, PLANE_EDGE)
    q.rect(x, y, s, hh, PLANE_EDGE)
    q.rect(x + w - s, y, s, hh, PLANE_EDGE)
    cx, cy = x + w / 2.0, y + hh / 2.0
    _disc(q, cx, cy, cut, cut, SECTION)
    bx = cx - w * 0.42 * 0.62
    size = max(3.0, r * 0.45)
    _triangle(q, bx, cy, size, size, BEING)
    q.rect(int(bx + size * 0.25), int(cy - s / 2), max(1, s), max(1, s), EYE)
    # Its line of sight, towards the ball.
    q.rect(int(bx + size * 0.6), int(cy), int(cx - cut - bx - size * 0.6), max(1, s // 2), BEING[:3] + (0.35,))


def _triangle(q, cx, cy, length, height, color) -> None:
    """A triangle pointing right (+x), centred on ``(cx, cy)``: scanlines narrowing to the tip."""
    rows = max(2, int(round(height)))
    for i in range(rows):
        t = abs((i + 0.5) / rows - 0.5) * 2  # 0 in the middle row, 1 at the edges
        q.rect(int(cx - length / 2), int(cy - height / 2 + i), max(1, int(length * (1 - t))), 1, color)
