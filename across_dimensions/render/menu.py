"""Drawing the menus: the title, pause, level-select and settings screens.

The layout (:func:`menu_layout`, :func:`menu_quads`) is plain numpy in pixels,
origin top-left, so the window's pointer hit-testing and the tests use the very
rectangles that are drawn. The quads are the HUD's (text from the HUD's font
atlas through its text API, solid rectangles from its solid cell), drawn with
the HUD's shader in one instanced call.

Look: a dark panel with a thin cyan frame and corner ticks; the selected row is
a translucent cyan band with a bright bar on its left; disabled rows (locked
levels) are grey; a key bound to two actions is orange with a note saying
which; sliders are a track with a cyan fill left of their value.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .font import CELL_H, CELL_W
from .hud import QUAD_FLOATS, HudRenderer, _QuadList, text_width
from .text_layout import ellipsized, scaled

BACKDROP_TOP = (0.015, 0.02, 0.05, 1.0)
BACKDROP_BOTTOM = (0.04, 0.07, 0.13, 1.0)
GRID_COLOR = (0.3, 0.6, 1.0, 0.07)
DIM_COLOR = (0.0, 0.0, 0.02, 0.62)
PANEL_COLOR = (0.02, 0.04, 0.08, 0.78)
FRAME_COLOR = (0.35, 0.8, 1.0, 0.55)
TITLE_COLOR = (0.8, 0.95, 1.0, 1.0)
SUBTITLE_COLOR = (0.45, 0.75, 1.0, 0.9)
ITEM_COLOR = (0.88, 0.92, 1.0, 1.0)
VALUE_COLOR = (0.6, 0.85, 1.0, 1.0)
DISABLED_COLOR = (0.5, 0.52, 0.58, 0.8)
NOTE_COLOR = (0.62, 0.68, 0.78, 0.95)
WARN_COLOR = (1.0, 0.55, 0.25, 1.0)
SELECT_COLOR = (0.25, 0.65, 1.0, 0.24)
ACCENT_COLOR = (0.4, 0.9, 1.0, 1.0)
TRACK_COLOR = (1.0, 1.0, 1.0, 0.14)
FILL_COLOR = (0.3, 0.85, 1.0, 0.85)
PROMPT_BAND = (0.0, 0.0, 0.0, 0.75)
PROMPT_COLOR = (1.0, 0.9, 0.45, 1.0)
FOOTER_COLOR = (0.55, 0.62, 0.72, 0.9)


@dataclass(frozen=True)
class RowBox:
    """Where one visible row is drawn: ``index`` into the view's items, its rectangle, and a
    slider's bar (None for other rows). Rectangles are ``(x, y, w, h)`` pixels, origin top-left."""

    index: int
    rect: tuple[int, int, int, int]
    bar: tuple[int, int, int, int] | None


def _scales(view, height: int) -> tuple[int, int, int]:
    """Text scales: title, rows, small print (footer, notes), at the player's text size."""
    small = scaled(max(1, height // 360))
    big_rows = view.screen in ("title", "pause", "conflict")
    return small * 3, small + (1 if big_rows else 0), small


def rows_that_fit(view, height: int) -> int:
    """How many of ``view``'s rows fit in its panel in a viewport ``height`` pixels high (at
    least 3): larger text shows fewer rows at once, and the list scrolls."""
    _, s_row, s_small = _scales(view, height)
    pad = CELL_W * s_row
    room = height - 3 * CELL_H * s_small - int(height * 0.22) - 2 * pad
    room -= (3 * CELL_H * s_row if view.progress is not None else 0) + (6 * CELL_H * s_row if view.prompt else 0)
    return max(3, room // _row_height(view, height))


def _panel(view, width: int, height: int) -> tuple[int, int, int, int]:
    """The panel's rectangle: as tall as its rows (up to the space under the title)."""
    s_title, s_row, s_small = _scales(view, height)
    chars = 40 if view.screen in ("title", "pause", "conflict") else 64
    pw = min(width - 2 * max(8, width // 40), max(CELL_W * s_row * chars, width // 3))
    top = int(height * 0.22)
    bottom = height - 3 * CELL_H * s_small
    pad = CELL_W * s_row
    rows = min(view.rows, len(view.items))
    content = 2 * pad + rows * _row_height(view, height) + (3 * CELL_H * s_row if view.progress is not None else 0)
    if view.prompt:
        content += 6 * CELL_H * s_row
    return (width - pw) // 2, top, pw, min(bottom - top, max(content, 8 * CELL_H * s_row))


def _row_height(view, height: int) -> int:
    _, s_row, s_small = _scales(view, height)
    two_lines = view.screen in ("levels", "controls")
    return CELL_H * s_row + (CELL_H * s_small + 2 if two_lines else 0) + CELL_H * s_row * (7 if two_lines else 5) // 8


def menu_layout(view, width: int, height: int) -> list[RowBox]:
    """The visible rows of ``view`` (a :class:`~across_dimensions.app.menu.MenuView`) in a
    ``width x height`` viewport."""
    px, py, pw, _ = _panel(view, width, height)
    _, s_row, _ = _scales(view, height)
    rh = _row_height(view, height)
    pad = CELL_W * s_row
    y = py + pad
    if view.progress is not None:
        y += 3 * CELL_H * s_row
    boxes = []
    for index in range(view.first, min(len(view.items), view.first + view.rows)):
        item = view.items[index]
        bar = None
        if item.fraction is not None:
            bar_w = pw // 4
            bar_x = px + pw - pad - text_width("0000 deg", s_row) - pad - bar_w
            bar = (bar_x, y + CELL_H * s_row // 4, bar_w, CELL_H * s_row // 2)
        boxes.append(RowBox(index, (px + pad // 2, y - CELL_H * s_row // 4, pw - pad, rh), bar))
        y += rh
    return boxes


def hit(view, width: int, height: int, x: float, y: float) -> tuple[int, float | None] | None:
    """The row under the pointer at ``(x, y)`` (pixels, origin top-left) and, on a slider's
    bar (or the row's right part), how far along the bar it is (0..1)."""
    for box in menu_layout(view, width, height):
        rx, ry, rw, rh = box.rect
        if rx <= x < rx + rw and ry <= y < ry + rh:
            frac = None
            if box.bar is not None and x >= box.bar[0] - box.bar[3]:
                bx, _, bw, _ = box.bar
                frac = min(1.0, max(0.0, (x - bx) / bw))
            return box.index, frac
    return None


def menu_quads(view, width: int, height: int) -> np.ndarray:
    """Lay out ``view`` as HUD quads, ``(n, QUAD_FLOATS) float32``."""
    q = _QuadList()
    s_title, s_row, s_small = _scales(view, height)
    if view.dim:
        q.rect(0, 0, width, height, DIM_COLOR)
    else:  # the title backdrop: a vertical gradient in bands, and a faint grid
        bands = 24
        for i in range(bands):
            t = i / (bands - 1)
            c = tuple(a + (b - a) * t for a, b in zip(BACKDROP_TOP, BACKDROP_BOTTOM))
            y0, y1 = height * i // bands, height * (i + 1) // bands
            q.rect(0, y0, width, y1 - y0, c)
        step = max(16, height // 12)
        for x in range(width // 2 % step, width, step):
            q.rect(x, int(height * 0.55), 1, height, GRID_COLOR)
        for y in range(int(height * 0.55), height, step // 2):
            q.rect(0, y, width, 1, GRID_COLOR)
    # Title, and the subtitle on the title screen.
    tw = text_width(view.title, s_title)
    ty = int(height * 0.07)
    q.text(view.title, (width - tw) // 2, ty, s_title, TITLE_COLOR)
    if view.screen == "title":
        sub = "a game in four dimensions"
        q.text(sub, (width - text_width(sub, s_small * 2)) // 2, ty + CELL_H * s_title + 4, s_small * 2, SUBTITLE_COLOR)
    px, py, pw, ph = _panel(view, width, height)
    q.rect(px, py, pw, ph, PANEL_COLOR)
    t = max(1, height // 360)
    for x, y, w, h in ((px, py, pw, t), (px, py + ph - t, pw, t), (px, py, t, ph), (px + pw - t, py, t, ph)):
        q.rect(x, y, w, h, FRAME_COLOR)
    tick = CELL_W * s_row
    for cx, cy in ((px, py), (px + pw - tick, py), (px, py + ph - 2 * t), (px + pw - tick, py + ph - 2 * t)):
        q.rect(cx, cy, tick, 2 * t, ACCENT_COLOR)
    pad = CELL_W * s_row
    if view.progress is not None:
        done, total, label = view.progress
        y = py + pad
        line = f"Preparing the 4D world {done}/{total}: {label}" if done < total else "Ready"
        q.text(
            ellipsized(line, pw - 2 * pad, s_row, "..."),
            px + pad,
            y,
            s_row,
            PROMPT_COLOR if done < total else VALUE_COLOR,
        )
        bar = (px + pad, y + CELL_H * s_row + 4, pw - 2 * pad, max(3, CELL_H * s_row // 3))
        q.rect(*bar, TRACK_COLOR)
        q.rect(bar[0], bar[1], int(bar[2] * done / max(1, total)), bar[3], FILL_COLOR)
    for box in menu_layout(view, width, height):
        item = view.items[box.index]
        rx, ry, rw, rh = box.rect
        selected = box.index == view.selected and item.enabled
        if selected:
            q.rect(rx, ry, rw, rh - CELL_H * s_row // 4, SELECT_COLOR)
            q.rect(rx, ry, max(2, t * 3), rh - CELL_H * s_row // 4, ACCENT_COLOR)
        color = ITEM_COLOR if item.enabled else DISABLED_COLOR
        if item.warn:
            color = WARN_COLOR
        y = ry + CELL_H * s_row // 4
        value_w = text_width(item.value, s_row)
        label_max = (box.bar[0] if box.bar else rx + rw - pad - value_w - pad) - (rx + pad)
        q.text(ellipsized(item.label, label_max, s_row, "..."), rx + pad, y, s_row, color)
        if item.value:
            vcol = VALUE_COLOR if item.enabled and not item.warn else color
            q.text(item.value, rx + rw - pad - value_w, y, s_row, vcol)
        if box.bar is not None:
            bx, by, bw, bh = box.bar
            q.rect(bx, by, bw, bh, TRACK_COLOR)
            q.rect(bx, by, int(round(bw * item.fraction)), bh, FILL_COLOR)
        if item.note and view.screen in ("levels", "controls"):
            ncol = WARN_COLOR if item.warn else NOTE_COLOR
            ncol = ncol if item.enabled else DISABLED_COLOR
            q.text(ellipsized(item.note, rw - 2 * pad, s_small, "..."), rx + pad, y + CELL_H * s_row + 2, s_small, ncol)
    # More rows above or below: arrows at the panel's right edge.
    if view.first > 0:
        q.text("^", px + pw - pad, py + 2, s_row, ACCENT_COLOR)
    if view.first + view.rows < len(view.items):
        q.text("v", px + pw - pad, py + ph - CELL_H * s_row - 2, s_row, ACCENT_COLOR)
    # The prompt (waiting for a key, a conflict) on a band across the panel's lower part.
    if view.prompt:
        words, lines, line = view.prompt.split(" "), [], ""
        max_w = pw - 2 * pad
        for word in words:
            cand = f"{line} {word}" if line else word
            if text_width(cand, s_row) <= max_w or not line:
                line = cand
            else:
                lines.append(line)
                line = word
        lines.append(line)
        band_h = (len(lines) + 1) * CELL_H * s_row
        by = py + ph - band_h - pad if view.screen != "conflict" else py + ph - band_h - pad
        q.rect(px + t, by, pw - 2 * t, band_h, PROMPT_BAND)
        for i, text in enumerate(lines):
            q.text(text, px + pad, by + CELL_H * s_row // 2 + i * CELL_H * s_row, s_row, PROMPT_COLOR)
    if view.message:
        mw = text_width(view.message, s_row)
        # Under the panel: above it, the title screen's subtitle would share the line.
        q.text(view.message, (width - mw) // 2, py + ph + CELL_H * s_row, s_row, PROMPT_COLOR)
    footer = ellipsized(view.footer, width - 2 * pad, s_small, "...")
    q.text(footer, (width - text_width(footer, s_small)) // 2, height - 2 * CELL_H * s_small, s_small, FOOTER_COLOR)
    return q.array()


class MenuRenderer:
    """Draws a menu view over the bound framebuffer with the HUD's shader and font atlas.

    Parameters
    ----------
    hud : HudRenderer
        The renderer's HUD (its program, atlas and instance buffer are shared).
    """

    def __init__(self, hud: HudRenderer):
        self.hud = hud
        self.last_quads = np.zeros((0, QUAD_FLOATS), np.float32)

    def draw(self, view, viewport: tuple[int, int, int, int]) -> None:
        _, _, w, h = (int(v) for v in viewport)
        quads = menu_quads(view, w, h)
        self.last_quads = quads
        self.hud.draw_quads(quads, viewport)
