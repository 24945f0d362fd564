"""Drawing the menus: the title, pause, level-select and settings screens.

The layout (:func:`menu_layout`, :func:`menu_quads`) is plain numpy in pixels,
origin top-left, so the window's pointer hit-testing and the tests use the very
rectangles that are drawn. The quads are the HUD's (text from the HUD's font
atlas through its text API, solid rectangles from its solid cell), drawn with
the HUD's shader in one instanced call.

Look: a dark panel with a thin cyan frame and corner ticks; the selected row is
a translucent cyan band with a bright bar on its left; disabled rows (locked
levels) are grey; a key bound to two actions is orange with a note saying
which; sliders are a track with a cyan fill left of their value. A finished level's summary
(``view.summary``) stands above the rows, its values at the right, a new best in the prompt's gold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .font import CELL_H, CELL_W, GLYPH_H, text_width
from .hud import HudRenderer
from .quads import QUAD_FLOATS, QuadList
from .text_layout import ellipsized, scaled, wrap

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
#: Screens whose rows have a second, smaller line (the row's note).
NOTE_SCREENS = ("levels", "controls", "conflict")
#: Lines of the warm-up's progress text at most (what, how far, how long), and the rows of text
#: height it takes with its bar above the panel's items.
PROGRESS_LINES = 3
PROGRESS_ROWS = PROGRESS_LINES + 2


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
    big_rows = view.screen in ("title", "pause", "conflict", "complete")
    return small * 3, small + (1 if big_rows else 0), small


def rows_that_fit(view, height: int) -> int:
    """How many of ``view``'s rows fit in its panel in a viewport ``height`` pixels high (at
    least 3): larger text shows fewer rows at once, and the list scrolls."""
    _, s_row, s_small = _scales(view, height)
    pad = CELL_W * s_row
    room = height - 3 * CELL_H * s_small - int(height * 0.22) - 2 * pad
    room -= (PROGRESS_ROWS * CELL_H * s_row if view.progress is not None else 0) + (
        6 * CELL_H * s_row if view.prompt else 0
    )
    room -= _summary_height(view, s_row)
    return max(3, room // _row_height(view, height))


def _panel(view, width: int, height: int) -> tuple[int, int, int, int]:
    """The panel's rectangle: as tall as its rows (up to the space under the title)."""
    s_title, s_row, s_small = _scales(view, height)
    chars = 40 if view.screen in ("title", "pause", "conflict") else 48 if view.screen == "complete" else 64
    pw = min(width - 2 * max(8, width // 40), max(CELL_W * s_row * chars, width // 3))
    top = int(height * 0.22)
    bottom = height - 3 * CELL_H * s_small
    pad = CELL_W * s_row
    rows = min(view.rows, len(view.items))
    content = (
        2 * pad
        + rows * _row_height(view, height)
        + (PROGRESS_ROWS * CELL_H * s_row if view.progress is not None else 0)
        + _summary_height(view, s_row)
    )
    if view.prompt:
        content += 6 * CELL_H * s_row
    return (width - pw) // 2, top, pw, min(bottom - top, max(content, 8 * CELL_H * s_row))


def _row_height(view, height: int) -> int:
    _, s_row, s_small = _scales(view, height)
    two_lines = view.screen in NOTE_SCREENS
    if two_lines:  # the note's line starts a line height down, clear of the label's descenders
        return line_height(s_row) + CELL_H * s_small + CELL_H * s_row * 5 // 8
    return CELL_H * s_row + CELL_H * s_row * 5 // 8


def menu_layout(view, width: int, height: int) -> list[RowBox]:
    """The visible rows of ``view`` (a :class:`~across_dimensions.app.menu.MenuView`) in a
    ``width x height`` viewport."""
    px, py, pw, _ = _panel(view, width, height)
    _, s_row, _ = _scales(view, height)
    rh = _row_height(view, height)
    pad = CELL_W * s_row
    y = py + pad
    if view.progress is not None:
        y += PROGRESS_ROWS * CELL_H * s_row
    y += _summary_height(view, s_row)
    boxes = []
    gutter = _gutter(view, s_row)
    # Rows stop above the prompt's band (a key being waited for, a conflict): none under it.
    ph = _panel(view, width, height)[3]
    limit = py + ph - pad - (_prompt_height(view.prompt, pw, s_row) + pad if view.prompt else 0)
    for index in range(view.first, min(len(view.items), view.first + view.rows)):
        if boxes and y + rh > limit:
            break
        item = view.items[index]
        bar = None
        if item.fraction is not None:
            bar_w = pw // 4
            bar_x = px + pw - gutter - pad - text_width("auto 100%", s_row) - pad - bar_w  # the widest value
            bar = (bar_x, y + CELL_H * s_row // 4, bar_w, CELL_H * s_row // 2)
        boxes.append(RowBox(index, (px + pad // 2, y - CELL_H * s_row // 4, pw - pad - gutter, rh), bar))
        y += rh
    return boxes


def _gutter(view, s_row: int) -> int:
    """Pixels kept free at the panel's right for the scroll marks when the rows do not all fit."""
    return 2 * CELL_W * s_row if view.first > 0 or view.first + view.rows < len(view.items) else 0


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
    q = QuadList()
    s_title, s_row, s_small = _scales(view, height)
    _backdrop(q, view, width, height)
    # Title, and the subtitle on the title screen.
    tw = text_width(view.title, s_title)
    ty = int(height * 0.07)
    q.text(view.title, (width - tw) // 2, ty, s_title, TITLE_COLOR)
    if view.screen == "title":
        sub = "a game in four dimensions"
        q.text(sub, (width - text_width(sub, s_small * 2)) // 2, ty + CELL_H * s_title + 4, s_small * 2, SUBTITLE_COLOR)
    panel = _panel(view, width, height)
    _frame(q, panel, s_row, height)
    if view.progress is not None:
        _progress(q, view, panel, s_row)
    if view.summary:
        _summary(q, view, panel, s_row, max(1, height // 360))
    for box in menu_layout(view, width, height):
        _row(q, view, box, (s_row, s_small), max(1, height // 360))
    _scroll_marks(q, view, panel, s_row, height)
    if view.prompt:  # waiting for a key, a conflict: on a band across the panel's lower part
        _prompt(q, view.prompt, panel, s_row, max(1, height // 360))
    px, py, pw, ph = panel
    pad = CELL_W * s_row
    footer_y = height - 2 * CELL_H * s_small
    show_footer = True
    if view.message:  # under the panel: above it, the title screen's subtitle would share the line
        lines = wrap(view.message, width - 2 * pad, s_row)
        y, lh = py + ph + CELL_H * s_row, line_height(s_row)
        if y + len(lines) * lh > footer_y:  # no room above the footer: in its place
            y, show_footer = min(y, height - len(lines) * lh - CELL_H * s_row), False
        for i, line in enumerate(lines):
            q.text(line, (width - text_width(line, s_row)) // 2, y + i * lh, s_row, PROMPT_COLOR)
    if show_footer:
        footer = ellipsized(view.footer, width - 2 * pad, s_small, "...")
        q.text(footer, (width - text_width(footer, s_small)) // 2, footer_y, s_small, FOOTER_COLOR)
    return q.array()


def _backdrop(q: QuadList, view, width: int, height: int) -> None:
    """The level dimmed behind a menu over it; on the title, a gradient in bands and a faint grid."""
    if view.dim:
        q.rect(0, 0, width, height, DIM_COLOR)
        return
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


def _frame(q: QuadList, panel, s_row: int, height: int) -> None:
    """The panel, its frame and the accent ticks at its corners."""
    px, py, pw, ph = panel
    q.rect(px, py, pw, ph, PANEL_COLOR)
    t = max(1, height // 360)
    for x, y, w, h in ((px, py, pw, t), (px, py + ph - t, pw, t), (px, py, t, ph), (px + pw - t, py, t, ph)):
        q.rect(x, y, w, h, FRAME_COLOR)
    tick = CELL_W * s_row
    for cx, cy in ((px, py), (px + pw - tick, py), (px, py + ph - 2 * t), (px + pw - tick, py + ph - 2 * t)):
        q.rect(cx, cy, tick, 2 * t, ACCENT_COLOR)


def _progress(q: QuadList, view, panel, s_row: int) -> None:
    """The warm-up's line (what is being prepared, how far, for how long) and its bar."""
    px, py, pw, ph = panel
    pad = CELL_W * s_row
    done, total, label = view.progress[:3]
    y = py + pad
    line = f"Preparing the 4D world {done}/{total}: {label}" if done < total else "Ready"
    for part in wrap(line, pw - 2 * pad, s_row)[:PROGRESS_LINES]:
        q.text(part, px + pad, y, s_row, PROMPT_COLOR if done < total else VALUE_COLOR)
        y += line_height(s_row)
    bar = (px + pad, y + 4, pw - 2 * pad, max(3, CELL_H * s_row // 3))
    q.rect(*bar, TRACK_COLOR)
    frac = view.progress[3] if len(view.progress) > 3 else done / max(1, total)
    q.rect(bar[0], bar[1], int(bar[2] * min(max(frac, 0.0), 1.0)), bar[3], FILL_COLOR)


def _summary_height(view, s_row: int) -> int:
    """Pixels the summary's lines and the rule under them take above the rows (0: none)."""
    return len(view.summary) * line_height(s_row) + CELL_H * s_row if view.summary else 0


def _summary(q: QuadList, view, panel, s_row: int, t: int) -> None:
    """A finished level's lines: each label at the left, its value at the right (a highlighted
    one, a new best, in gold), a rule under them."""
    px, py, pw, _ = panel
    pad = CELL_W * s_row
    y = py + pad
    for label, value, highlight in view.summary:
        value = ellipsized(value, pw // 2 - pad, s_row, "...")
        vw = text_width(value, s_row)
        q.text(ellipsized(label, pw - 3 * pad - vw, s_row, "..."), px + pad, y, s_row, NOTE_COLOR)
        q.text(value, px + pw - pad - vw, y, s_row, PROMPT_COLOR if highlight else VALUE_COLOR)
        y += line_height(s_row)
    q.rect(px + pad, y + CELL_H * s_row // 4, pw - 2 * pad, t, FRAME_COLOR)


def _row(q: QuadList, view, box: RowBox, scales, t: int) -> None:
    """One row: its label (cut to fit), its value at the right, its slider, its note."""
    s_row, s_small = scales
    item = view.items[box.index]
    rx, ry, rw, rh = box.rect
    pad = CELL_W * s_row
    if box.index == view.selected and item.enabled:
        q.rect(rx, ry, rw, rh - CELL_H * s_row // 4, SELECT_COLOR)
        q.rect(rx, ry, max(2, t * 3), rh - CELL_H * s_row // 4, ACCENT_COLOR)
    color = WARN_COLOR if item.warn else ITEM_COLOR if item.enabled else DISABLED_COLOR
    y = ry + CELL_H * s_row // 4
    value = ellipsized(item.value, max(pad, rw // 2 - 2 * pad), s_row, "...")
    value_w = text_width(value, s_row)
    label_max = (box.bar[0] if box.bar else rx + rw - pad - value_w - pad) - (rx + pad)
    q.text(ellipsized(item.label, label_max, s_row, "..."), rx + pad, y, s_row, color)
    if item.value:
        vcol = VALUE_COLOR if item.enabled and not item.warn else color
        q.text(value, rx + rw - pad - value_w, y, s_row, vcol)
    if box.bar is not None:
        bx, by, bw, bh = box.bar
        q.rect(bx, by, bw, bh, TRACK_COLOR)
        q.rect(bx, by, int(round(bw * item.fraction)), bh, FILL_COLOR)
        # A knob at the value, so a slider at its low end (render scale "auto" on a software
        # renderer) reads as set there, not as empty.
        kw = max(3, bh // 2)
        q.rect(bx + int(round(bw * item.fraction)) - kw // 2, by - bh // 3, kw, bh + 2 * (bh // 3), ACCENT_COLOR)
    if item.note and view.screen in NOTE_SCREENS:
        ncol = WARN_COLOR if item.warn else NOTE_COLOR
        ncol = ncol if item.enabled else DISABLED_COLOR
        q.text(ellipsized(item.note, rw - 2 * pad, s_small, "..."), rx + pad, y + line_height(s_row), s_small, ncol)


def _scroll_marks(q: QuadList, view, panel, s_row: int, height: int) -> None:
    """More rows above or below: arrows in the gutter at the panel's right (:func:`_gutter`),
    clear of the rows' text and of the panel's corner ticks."""
    px, py, pw, ph = panel
    t = max(1, height // 360)
    x = px + pw - CELL_W * s_row // 2 - _gutter(view, s_row)
    pad = CELL_W * s_row
    if view.first > 0:
        q.text("^", x, py + pad, s_row, ACCENT_COLOR)
    if view.first + view.rows < len(view.items):
        q.text("v", x, py + ph - pad - CELL_H * s_row - 3 * t, s_row, ACCENT_COLOR)


def _prompt(q: QuadList, prompt: str, panel, s_row: int, t: int) -> None:
    px, py, pw, ph = panel
    pad = CELL_W * s_row
    lines = wrap(prompt, pw - 2 * pad, s_row)
    band_h = _prompt_height(prompt, pw, s_row)
    by = py + ph - band_h - pad
    q.rect(px + t, by, pw - 2 * t, band_h, PROMPT_BAND)
    for i, text in enumerate(lines):
        q.text(text, px + pad, by + CELL_H * s_row // 2 + i * line_height(s_row), s_row, PROMPT_COLOR)


def _prompt_height(prompt: str, pw: int, s_row: int) -> int:
    """Pixels of the prompt's band in a panel ``pw`` wide."""
    return len(wrap(prompt, pw - 2 * CELL_W * s_row, s_row)) * line_height(s_row) + CELL_H * s_row


def line_height(scale: int) -> int:
    """Pixels from one line of wrapped text to the next: the glyphs' descenders clear the next
    line's capitals (the HUD's hint panel spaces its lines the same)."""
    return (GLYPH_H + 4) * scale


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
