"""Where each part of the HUD goes: rectangles in pixels (origin top-left) for a viewport.

Sizes scale with the viewport (:class:`HudMetrics`), so the HUD reads at 160x90 and at 4K. The
drawing (:mod:`.hud`, :mod:`.hud_gauges`) and the tests that check nothing overlaps both ask here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..game.frame import Hud
from .font import CELL_W, GLYPH_H, text_width
from .text_layout import ellipsized, scaled, wrap

#: Width over height of the radar's rectangle (the radar view fits itself to it).
RADAR_ASPECT = 0.95


@dataclass(frozen=True)
class HudMetrics:
    """Sizes that scale with the viewport, so the HUD reads at 160x90 and at 4K."""

    width: int
    height: int

    @property
    def text_scale(self) -> int:
        return scaled(max(1, self.height // 300))

    @property
    def margin(self) -> int:
        return max(4, self.width // 64)

    @property
    def arm(self) -> int:
        return max(3, self.height // 60)

    @property
    def thickness(self) -> int:
        return max(1, self.height // 360)

    def w_track(self) -> tuple[int, int, int, int]:
        """The w indicator's track as ``(x, y, w, h)`` pixels, origin top-left."""
        bar_w = max(4, self.width // 128)
        y0 = int(round(self.height * 0.22))
        y1 = int(round(self.height * 0.78))
        x0 = self.width - self.margin - bar_w
        return x0, y0, bar_w, max(1, y1 - y0)

    def energy_bar(self) -> tuple[int, int, int, int]:
        """The energy bar's track as ``(x, y, w, h)`` pixels, origin top-left (bottom-left of the view)."""
        bar_h = max(5, self.height // 45)
        bar_w = max(40, int(round(self.width * 0.24)))
        return self.margin, self.height - self.margin - bar_h, bar_w, bar_h

    def radar_rect(self) -> tuple[int, int, int, int]:
        """The radar's rectangle as ``(x, y, w, h)`` pixels, origin top-left.

        Bottom-right, sized from the viewport height (46%, up to 50% on small screens), left of the
        w indicator and its value.
        """
        h = max(24, int(round(max(self.height * 0.46, min(220, self.height * 0.5)))))
        w = max(24, int(round(h * RADAR_ASPECT)))
        tx = self.w_track()[0]
        # The w value under the track is centred on it and spills about 3 glyph cells left.
        right = tx - 3 * CELL_W * self.text_scale - self.margin // 2
        bottom = self.height - self.margin // 2
        return right - w, bottom - h, w, h

    def w_marker_y(self, hud: Hud) -> tuple[int, bool]:
        """Pixel row (top-left origin) of the w marker's centre, and whether w is in range."""
        x0, y0, bw, th = self.w_track()
        span = hud.w_max - hud.w_min
        t = (hud.w - hud.w_min) / span if span > 0 else 0.5
        in_range = 0.0 <= t <= 1.0
        t = min(max(t, 0.0), 1.0)
        return int(round(y0 + (1.0 - t) * th)), in_range


def health_bar_rect(m: HudMetrics) -> tuple[int, int, int, int]:
    """The health bar's track as ``(x, y, w, h)`` pixels: top-left, below the FPS line."""
    bar_h = max(5, m.height // 45)
    bar_w = max(40, int(round(m.width * 0.2)))
    return m.margin, m.margin + 2 * (GLYPH_H + 3) * m.text_scale, bar_w, bar_h


def hint_rect(hud: Hud, width: int, height: int) -> tuple[int, int, int, int]:
    """The hint panel's band as ``(x, y, w, h)`` pixels (origin top-left); zero size without a hint."""
    if not hud.hint:
        return 0, 0, 0, 0
    m = HudMetrics(int(width), int(height))
    lines, scale, box_w = hint_lines(hud.hint, m)
    s = m.text_scale
    line_h = (GLYPH_H + 4) * scale
    label_h = (GLYPH_H + 4) * s if hud.hint_label else 0
    pad = 3 * s
    band_w = max(text_width(ln, scale) for ln in lines) + 2 * pad + 2 * s
    if hud.hint_label:
        band_w = max(band_w, text_width(hud.hint_label, s) + 2 * pad + 2 * s)
    band_w = min(band_w, box_w + 2 * pad + 2 * s)
    band_h = len(lines) * line_h + label_h + 2 * pad - s
    return (m.width - band_w) // 2, m.margin, band_w, band_h


def hint_lines(text: str, m: HudMetrics) -> tuple[list[str], int, int]:
    scale = m.text_scale
    # 60% of the width, but clear of the health bar's column on the left (and as much on the
    # right, so the panel stays centred): on a 16:9 screen the bar's value sits under 60%.
    hx, _, hw, _ = health_bar_rect(m)
    clear = m.width - 2 * (hx + hw + m.margin) - 2 * (3 * scale) - 2 * scale
    box_w = max(40, min(int(m.width * 0.6), clear))
    return wrap(text, box_w, scale), scale, box_w


def warning_rect(text: str, width: int, height: int) -> tuple[int, int, int, int]:
    """The warning line's band as ``(x, y, w, h)`` pixels: bottom centre, clear of the energy bar
    and the radar."""
    m = HudMetrics(int(width), int(height))
    s = m.text_scale
    ex, _, ew, _ = m.energy_bar()
    left = ex + ew + m.margin
    right = m.radar_rect()[0] - m.margin
    line = ellipsized(text, max(10, right - left - 4 * s), s)
    w = min(right - left, text_width(line, s) + 4 * s)
    h = (GLYPH_H + 4) * s
    return left + (right - left - w) // 2, m.height - m.margin // 2 - h, w, h


def label_rect(label, width: int, height: int, avoid=(0, 0, 0, 0)) -> tuple[int, int, int, int]:
    """Where a :class:`~across_dimensions.game.frame.ScreenLabel` is drawn: its band ``x, y, w, h``
    in pixels (origin top-left), its left edge's middle at the label's point moved a little
    right (or its right edge a little left of ``x_left`` when there is no room on the right),
    kept whole on the screen and clear of the rectangle ``avoid`` (the hint panel: the label moves
    down below it)."""
    m = HudMetrics(int(width), int(height))
    s = m.text_scale
    lines = label.text.split("\n")
    line_h = (GLYPH_H + 3) * s
    bw = max(text_width(ln, s) for ln in lines) + 8 * s
    bh = len(lines) * line_h + 2 * s
    x = int(round(m.width / 2 + label.x * m.height / 2)) + 4 * s
    if x + bw > m.width - m.margin and label.x_left is not None:  # no room on the right: on the left
        left = int(round(m.width / 2 + label.x_left * m.height / 2)) - 4 * s - bw
        if left >= m.margin:
            x = left
    y = int(round(m.height / 2 - label.y * m.height / 2)) - bh // 2
    x = min(max(x, m.margin), max(m.margin, m.width - bw - m.margin))
    y = min(max(y, m.margin), max(m.margin, m.height - bh - m.margin))
    if overlap((x, y, bw, bh), avoid):
        y = avoid[1] + avoid[3] + s
    return x, y, bw, bh


def overlap(a, b) -> bool:
    """Whether two ``(x, y, w, h)`` rectangles share any pixel."""
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]


def message_scale(m: HudMetrics) -> int:
    """The large text scale (PAUSED, one-line messages)."""
    return 2 * m.text_scale if m.height >= 60 else m.text_scale


def message_layout(hud: Hud, width: int, height: int) -> tuple[list[str], int, tuple[int, int, int, int], int]:
    """The message's lines, their scale, its band ``(x, y, w, h)`` and the line height.

    Centred a third of the way down (below PAUSED when paused), wrapped to the view's width less
    the margins; large text only for one line. Never over the hint panel: below it when it
    reaches that far down.
    """
    m = HudMetrics(int(width), int(height))
    s, big = m.text_scale, message_scale(m)
    scale = big
    lines = wrap(hud.message, m.width - 2 * m.margin - 8 * scale, scale)
    if scale > s and len(lines) > 1:
        scale = s
        lines = wrap(hud.message, m.width - 2 * m.margin - 8 * scale, scale)
    line_h = (GLYPH_H + 3) * scale
    pad = 2 * scale
    block_h = len(lines) * line_h
    ytop = m.height // 2 + GLYPH_H * big + 2 * big if hud.paused else m.height // 3 - block_h // 2
    hx, hy, hw, hh = hint_rect(hud, m.width, m.height)
    if hh and ytop - pad < hy + hh + s:
        ytop = hy + hh + s + pad
    band_w = max(text_width(ln, scale) for ln in lines) + 8 * scale
    return lines, scale, ((m.width - band_w) // 2, ytop - pad, band_w, block_h + pad), line_h


def slice_gauges_left(m: HudMetrics) -> int:
    """Pixel column where the slice gauges (bottom centre) begin."""
    label_w = text_width("XW", m.text_scale) + 2 * m.text_scale
    return (m.width - 3 * (label_w + max(24, m.width // 12)) - 2 * m.margin) // 2


def left_lines(text: str, m: HudMetrics, gauges: bool = False) -> list[str]:
    """``text`` (parts two spaces apart) in lines over the energy bar that stop short of the
    middle: of the slice gauges' left end when ``gauges`` (the lines on their row), else of the
    slice mode's label above them. Broken between parts, not inside one, where it can."""
    s = m.text_scale
    x, _, w, _ = m.energy_bar()
    limit = max(w, (slice_gauges_left(m) if gauges else m.width // 2 - 4 * m.margin) - m.margin - x)
    lines: list[str] = []
    for part in text.split("  ") if text else ():
        if lines and text_width(f"{lines[-1]}  {part}", s) <= limit:
            lines[-1] = f"{lines[-1]}  {part}"
        else:
            lines += wrap(part, limit, s)
    return lines


def slice_marker_x(angle_deg: float, x0: int, width: int) -> int:
    """Pixel column of a slice gauge's marker: -180 degrees at ``x0``, +180 at ``x0 + width``."""
    t = (min(max(angle_deg, -180.0), 180.0) + 180.0) / 360.0
    return int(round(x0 + t * width))


def damage_cue_points(angle: float, m: HudMetrics) -> list[tuple[int, int]]:
    """Centres of the cue's marks: an arc round the crosshair centred on ``angle`` (0 up, + right)."""
    r = max(12, int(round(m.height * 0.16)))
    cx, cy = m.width // 2, m.height // 2
    return [
        (int(round(cx + r * np.sin(angle + d))), int(round(cy - r * np.cos(angle + d))))
        for d in np.radians([-20.0, -10.0, 0.0, 10.0, 20.0])
    ]
