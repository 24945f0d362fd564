"""The heads-up display, drawn over the 3D scene in pixel coordinates.

Everything on the HUD is an axis-aligned textured quad: text samples glyphs
from the font atlas (:mod:`.font`: DejaVu Sans rasterized by FreeType), and solid
rectangles sample a fully lit block of the same atlas. So the whole HUD is one instanced draw call with one
shader, and the layout (:func:`hud_quads`) is plain numpy that can be tested
without OpenGL.

Layout (pixels, origin top-left, ``W x H`` the viewport):

* crosshair: a plus with a dark outline at ``(W // 2, H // 2)``; hidden while
  paused;
* w indicator: a vertical track on the right, ``w_max`` at the top, with a tick
  at ``w = 0``, a fill from 0 to ``w``, a marker at ``w`` (red when ``w`` is
  outside the range), the label ``w`` above and the value below;
* energy bar (when ``hud.energy`` is not None): bottom-left, a horizontal track whose fill is
  ``value / maximum`` of its inner width, ``ENERGY`` above its left end and the value (``73/100``)
  above its right end; a crystal's ``flash`` brightens the fill and puts a fading glow round the
  bar; when ``empty`` the outline, track and label turn red and the label reads ``NO ENERGY``;
* weapon panel (when ``hud.weapon`` is not None): above the energy bar, the weapon's number,
  name, cost (and bullets in flight), a cooldown bar that fills as the weapon gets ready, and a red
  ``NOT ENOUGH ENERGY`` line above when the last try failed; ``hit_marker`` puts four fading marks
  round the crosshair;
* radar (drawn by :mod:`.radar`, not here): the rectangle :meth:`HudMetrics.radar_rect`,
  bottom-right but left of the w indicator;
* slice gauges (when ``hud.slice`` is not None): top centre, three small tracks
  ``XW YW ZW``, each with ticks at -90, 0 and +90 degrees and a marker at the slice
  axis's angle towards w (green on a 90-degree step), and under them the 4D
  camera's mode (``FRUSTUM 25`` with the orbit angle, ``RETURNING``) when detached;
* FPS (when not None): top-left;
* message: centred horizontally, a third of the way down, on a dark band
  (wrapped to fit);
* paused: the whole view dimmed, then ``PAUSED`` in large text in the middle;
* hint (when ``hud.hint``): its own panel at the top centre, wrapped to 60% of the width, with an
  accent bar on its left and ``hud.hint_label`` in small dim text under it; notices and prompts
  (``message``) never cover it;
* warning (when ``hud.warning``): one line at the bottom centre, between the energy bar and the
  radar, shortened with an ellipsis to fit;
* labels (``hud.labels``): small text on a dark band just right of a point of the world
  (:func:`label_rect`), such as the manipulation keys beside the held object;
* card (when ``hud.card``): drawn over everything by :mod:`.cards`.
* health (when ``hud.health`` is not None): top-left, a bar green when full turning red when low,
  ``HEALTH`` (``SAFE`` just after a death) above its left end and the value above its right end;
  ``damage_flash`` frames the view in red for a moment after a hit, and ``damage_dir`` puts a
  red arc of marks round the crosshair on the side the hit came from (up is ahead).

Colours are display-space RGBA (no gamma applied).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import moderngl
import numpy as np

from ..game.frame import EnergyGauge, HealthGauge, Hud, Radar, SliceGauges, WeaponPanel
from .captions import draw_captions
from .cards import draw_card
from .font import CELL_W, GLYPH_H, GLYPH_W, default_font, font_px, solid_uv
from .font import text_width as text_width
from .palette import cue
from .text_layout import ellipsized, scaled, wrap

#: Colours; the w cues among them are drawn in the palette in use (:mod:`.palette`), these
#: names are their default-palette values.
CROSSHAIR_COLOR = (0.95, 0.95, 0.95, 1.0)
OUTLINE_COLOR = (0.0, 0.0, 0.0, 0.55)
TRACK_COLOR = (1.0, 1.0, 1.0, 0.16)
TICK_COLOR = (1.0, 1.0, 1.0, 0.75)
MARKER_COLOR = cue("marker", "default")
MARKER_OUT_OF_RANGE_COLOR = cue("marker_out", "default")
FILL_POS_COLOR = cue("gauge_ana", "default")
FILL_NEG_COLOR = cue("gauge_kata", "default")
BLOCKED_ANA_COLOR = cue("blocked_ana", "default")
BLOCKED_KATA_COLOR = cue("blocked_kata", "default")
TEXT_COLOR = (0.92, 0.94, 1.0, 1.0)
FPS_COLOR = (0.7, 1.0, 0.7, 0.9)
PAUSE_DIM_COLOR = (0.0, 0.0, 0.0, 0.55)
BAND_COLOR = (0.0, 0.0, 0.0, 0.45)
ENERGY_TRACK_COLOR = (0.55, 0.85, 1.0, 0.16)
ENERGY_FILL_COLOR = cue("energy", "default")
ENERGY_FLASH_COLOR = cue("energy_flash", "default")
ENERGY_EMPTY_COLOR = cue("energy_empty", "default")
ENERGY_EMPTY_TRACK_COLOR = (1.0, 0.15, 0.1, 0.28)
ENERGY_LABEL_COLOR = (0.75, 0.95, 1.0, 1.0)
RADAR_LABEL_COLOR = (0.6, 0.9, 1.0, 0.85)
WEAPON_COLOR = (1.0, 0.9, 0.6, 1.0)
WEAPON_READY_COLOR = (0.5, 1.0, 0.6, 0.9)
WEAPON_COOL_COLOR = (1.0, 0.6, 0.2, 0.9)
HIT_COLOR = (1.0, 0.35, 0.25, 1.0)
HINT_BAND_COLOR = cue("hint_band", "default")
HINT_ACCENT_COLOR = cue("hint_accent", "default")
HINT_TEXT_COLOR = (0.95, 0.97, 1.0, 1.0)
HINT_LABEL_COLOR = (0.6, 0.8, 0.95, 0.8)
WARNING_COLOR = (1.0, 0.8, 0.35, 0.95)
HEALTH_FULL_COLOR = (0.35, 0.95, 0.45, 0.95)
HEALTH_LOW_COLOR = (1.0, 0.2, 0.15, 0.95)
HEALTH_TRACK_COLOR = (1.0, 0.4, 0.35, 0.18)
HEALTH_SAFE_COLOR = (0.6, 0.9, 1.0, 1.0)
DAMAGE_FLASH_COLOR = (0.9, 0.05, 0.0, 0.35)
DAMAGE_VIGNETTE_BANDS = 4  # the red frame after a hit: bands fading inward
DAMAGE_CUE_COLOR = (1.0, 0.2, 0.1, 0.9)
SLICE_MARKER_COLOR = (1.0, 0.75, 0.15, 1.0)
SLICE_ALIGNED_COLOR = (0.45, 1.0, 0.55, 1.0)
SLICE_MODE_COLOR = (0.6, 0.9, 1.0, 1.0)
#: Width over height of the radar's rectangle (the radar view fits itself to it).
RADAR_ASPECT = 0.95

#: Floats per HUD quad: rect x, y, w, h (px) | atlas u0, v0, u1, v1 (texels) | r, g, b, a.
QUAD_FLOATS = 12


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


class _QuadList:
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

    def array(self) -> np.ndarray:
        rects = np.asarray(self.rows, np.float32).reshape(-1, QUAD_FLOATS)
        if not self._runs:
            return rects
        parts, at = [], 0
        for pos, run, x, y, color in self._runs:
            if pos > at:
                parts.append(rects[at:pos])
                at = pos
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


def hud_quads(hud: Hud, width: int, height: int, radar: Radar | None = None) -> np.ndarray:
    """Lay out the HUD for a ``width x height`` viewport.

    With ``radar``, also the radar's labels round its rectangle (the radar itself is drawn by
    :class:`~across_dimensions.render.radar.RadarRenderer`): ``+w`` at the top left, ``-w`` at the
    bottom left (pins stand above for ana, hang below for kata) and the range at the bottom right.

    Returns
    -------
    (n, 12) float32
        One row per quad in draw order (later rows on top): rect ``x, y, w, h``
        in pixels (origin top-left, y down), atlas rect ``u0, v0, u1, v1`` in
        texels, colour ``r, g, b, a``.
    """
    m = HudMetrics(int(width), int(height))
    q = _QuadList()
    s = m.text_scale
    W, H = m.width, m.height

    # --- a hit: the view flashes red (first, so everything else stays readable on top)
    if hud.damage_flash > 0:
        _damage_vignette(q, min(float(hud.damage_flash), 1.0), W, H)

    # --- w indicator (right edge); none in a 3D level (w_min == w_max: nowhere to go along w)
    if hud.w_max > hud.w_min:
        _w_indicator(q, hud, m)

    # --- energy bar (bottom-left)
    if hud.energy is not None:
        _energy_bar(q, hud.energy, m)

    # --- weapon panel (above the energy bar) and hit marks round the crosshair
    if hud.weapon is not None:
        _weapon_panel(q, hud.weapon, m)

    # --- health bar (top-left) and where the last hit came from
    if hud.health is not None:
        _health_bar(q, hud.health, m)
    if hud.damage_dir is not None:
        _damage_cue(q, float(hud.damage_dir), m)

    # --- radar labels
    if radar is not None:
        rx, ry, rw, rh = m.radar_rect()
        q.text("+w", rx + s, ry + s, s, cue("label_ana"))
        q.text("-w", rx + s, ry + rh - GLYPH_H * s - s, s, cue("label_kata"))
        rng = f"{radar.range:.0f} m"
        q.text(rng, rx + rw - text_width(rng, s) - s, ry + rh - GLYPH_H * s - s, s, RADAR_LABEL_COLOR)

    # --- slice gauges (top centre)
    if hud.slice is not None:
        _slice_gauges(q, hud.slice, m)

    # --- FPS (top-left)
    if hud.fps is not None:
        q.text(f"{hud.fps:.0f} FPS", m.margin // 2, m.margin // 2, s, FPS_COLOR)

    # --- crosshair (centre)
    if hud.crosshair and not hud.paused:
        cx, cy, a, t = W // 2, H // 2, m.arm, m.thickness
        left, top = cx - t // 2, cy - t // 2
        for grow, color in ((1, OUTLINE_COLOR), (0, CROSSHAIR_COLOR)):
            q.rect(left - a - grow, top - grow, 2 * a + t + 2 * grow, t + 2 * grow, color)
            q.rect(left - grow, top - a - grow, t + 2 * grow, 2 * a + t + 2 * grow, color)
        if hud.hit_marker > 0:  # four short marks at the corners: the bullet hit something
            k = min(float(hud.hit_marker), 1.0)
            for dx, dy in ((-1, -1), (1, -1), (-1, 1), (1, 1)):
                q.rect(cx + dx * (a + t) - t, cy + dy * (a + t) - t, 2 * t, 2 * t, HIT_COLOR[:3] + (k,))

    # --- pause overlay
    big = 2 * s if H >= 60 else s
    if hud.paused:
        q.rect(0, 0, W, H, PAUSE_DIM_COLOR)
        label = "PAUSED"
        q.text(label, (W - text_width(label, big)) // 2, H // 2 - (GLYPH_H * big) // 2, big, TEXT_COLOR)

    # --- hint panel (top centre) and the warning line (bottom centre)
    if hud.hint:
        _hint_panel(q, hud, m)
    if hud.warning:
        _warning_line(q, hud.warning, m)

    # --- message (centred, a third of the way down; below PAUSED when paused)
    if hud.message:
        scale = big
        lines = wrap(hud.message, W - 2 * m.margin, scale)
        if scale > s and len(lines) > 1:  # large text only for one-liners; longer ones use the small size
            scale = s
            lines = wrap(hud.message, W - 2 * m.margin, scale)
        line_h = (GLYPH_H + 3) * scale
        block_h = len(lines) * line_h
        ytop = H // 2 + GLYPH_H * big + 2 * big if hud.paused else H // 3 - block_h // 2
        band_w = max(text_width(ln, scale) for ln in lines) + 8 * scale
        pad = 2 * scale
        q.rect((W - band_w) // 2, ytop - pad, band_w, block_h + pad, BAND_COLOR)
        for i, ln in enumerate(lines):
            q.text(ln, (W - text_width(ln, scale)) // 2, ytop + i * line_h, scale, TEXT_COLOR)

    # --- labels next to things on screen (the manipulation keys beside the held object)
    if not hud.paused:
        for label in hud.labels:
            _screen_label(q, label, m)
        draw_captions(q, hud.captions, m)  # sounds made visible (a setting)
    # --- teaching card (over everything)
    if hud.card is not None:
        draw_card(q, hud.card, W, H)
    return q.array()


def _damage_vignette(q: _QuadList, k: float, W: int, H: int) -> None:
    """A red frame round the view, strongest at the edge, fading over a tenth of its height.

    Not a wash over the whole view: a software rasterizer blends every pixel it covers, and
    a full-screen quad cost 2.5 ms a frame while enemies kept hitting the player.
    """
    band = max(2, H // (10 * DAMAGE_VIGNETTE_BANDS))
    for i in range(DAMAGE_VIGNETTE_BANDS):
        a = DAMAGE_FLASH_COLOR[3] * k * (1.0 - i / DAMAGE_VIGNETTE_BANDS)
        colour = DAMAGE_FLASH_COLOR[:3] + (a,)
        o = i * band  # this band's inset
        q.rect(o, o, W - 2 * o, band, colour)  # top
        q.rect(o, H - o - band, W - 2 * o, band, colour)  # bottom
        q.rect(o, o + band, band, H - 2 * o - 2 * band, colour)  # left
        q.rect(W - o - band, o + band, band, H - 2 * o - 2 * band, colour)  # right


def _w_indicator(q: _QuadList, hud: Hud, m: HudMetrics) -> None:
    W, H, s = m.width, m.height, m.text_scale
    x0, y0, bw, th = m.w_track()
    q.rect(x0 - 1, y0 - 1, bw + 2, th + 2, OUTLINE_COLOR)
    q.rect(x0, y0, bw, th, TRACK_COLOR)
    my, in_range = m.w_marker_y(hud)
    span = hud.w_max - hud.w_min
    if span > 0 and hud.w_min <= 0.0 <= hud.w_max:
        zy = int(round(y0 + (hud.w_max / span) * th))
        top, bot = sorted((zy, my))
        q.rect(x0, top, bw, bot - top, cue("gauge_ana" if hud.w >= 0 else "gauge_kata"))
        ext = max(2, bw // 2)
        q.rect(x0 - ext, zy - m.thickness // 2, bw + 2 * ext, m.thickness, TICK_COLOR)
    mh = max(2, H // 120)
    mext = max(2, bw // 2 + 1)
    q.rect(x0 - mext - 1, my - mh // 2 - 1, bw + 2 * mext + 2, mh + 2, OUTLINE_COLOR)
    q.rect(x0 - mext, my - mh // 2, bw + 2 * mext, mh, cue("marker" if in_range else "marker_out"))
    # Something solid where the player stands at the next ghost layer ana (top) or kata
    # (bottom): a cap on that end of the track and a word beside it, in the side's colour.
    for side in hud.w_blocked:
        cap_h = 2 * m.thickness
        cap_y = y0 if side > 0 else y0 + th - cap_h
        color = cue("blocked_ana" if side > 0 else "blocked_kata")
        q.rect(x0, cap_y, bw, cap_h, color)
        word = "solid +w" if side > 0 else "solid -w"
        ty = y0 + 2 * s if side > 0 else y0 + th - GLYPH_H * s - 2 * s
        q.text(word, x0 - mext - text_width(word, s) - 2 * s, ty, s, color)
    label_y = y0 - GLYPH_H * s - 3 * s - 1
    q.text("w", x0 + bw // 2 - (GLYPH_W * s) // 2, label_y, s, TEXT_COLOR)
    val = f"{hud.w:+.2f}"
    vx = min(x0 + bw // 2 - text_width(val, s) // 2, W - text_width(val, s) - 2 * s)
    q.text(val, vx, y0 + th + 3 * s + 1, s, TEXT_COLOR)


def hint_rect(hud: Hud, width: int, height: int) -> tuple[int, int, int, int]:
    """The hint panel's band as ``(x, y, w, h)`` pixels (origin top-left); zero size without a hint."""
    if not hud.hint:
        return 0, 0, 0, 0
    m = HudMetrics(int(width), int(height))
    lines, scale, box_w = _hint_lines(hud.hint, m)
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


def _hint_lines(text: str, m: HudMetrics) -> tuple[list[str], int, int]:
    scale = m.text_scale
    # 60% of the width, but clear of the health bar's column on the left (and as much on the
    # right, so the panel stays centred): on a 16:9 screen the bar's value sits under 60%.
    hx, _, hw, _ = health_bar_rect(m)
    clear = m.width - 2 * (hx + hw + m.margin) - 2 * (3 * scale) - 2 * scale
    box_w = max(40, min(int(m.width * 0.6), clear))
    return wrap(text, box_w, scale), scale, box_w


def _hint_panel(q: _QuadList, hud: Hud, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = hint_rect(hud, m.width, m.height)
    lines, scale, _ = _hint_lines(hud.hint, m)
    pad = 3 * s
    q.rect(x, y, w, h, cue("hint_band"))
    q.rect(x, y, max(2, s), h, cue("hint_accent"))  # the accent: a hint, not a notice
    line_h = (GLYPH_H + 4) * scale
    for i, ln in enumerate(lines):
        q.text(ln, x + pad + 2 * s, y + pad + i * line_h, scale, HINT_TEXT_COLOR)
    if hud.hint_label:
        label = hud.hint_label
        q.text(label, x + w - pad - text_width(label, s), y + pad + len(lines) * line_h, s, HINT_LABEL_COLOR)


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


def _warning_line(q: _QuadList, text: str, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = warning_rect(text, m.width, m.height)
    ex, _, ew, _ = m.energy_bar()
    right = m.radar_rect()[0] - m.margin
    line = ellipsized(text, max(10, right - (ex + ew + m.margin) - 4 * s), s)
    q.rect(x, y, w, h, BAND_COLOR)
    q.text(line, x + 2 * s, y + 2 * s, s, WARNING_COLOR)


def label_rect(label, width: int, height: int) -> tuple[int, int, int, int]:
    """Where a :class:`~across_dimensions.game.frame.ScreenLabel` is drawn: its band ``x, y, w, h``
    in pixels (origin top-left), its left edge's middle at the label's point moved a little
    right (or its right edge a little left of ``x_left`` when there is no room on the right),
    kept whole on the screen."""
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
    return x, y, bw, bh


def _screen_label(q: _QuadList, label, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, bw, bh = label_rect(label, m.width, m.height)
    q.rect(x, y, bw, bh, BAND_COLOR)
    for i, ln in enumerate(label.text.split("\n")):
        q.text(ln, x + 4 * s, y + s + i * (GLYPH_H + 3) * s, s, TEXT_COLOR)


def slice_marker_x(angle_deg: float, x0: int, width: int) -> int:
    """Pixel column of a slice gauge's marker: -180 degrees at ``x0``, +180 at ``x0 + width``."""
    t = (min(max(angle_deg, -180.0), 180.0) + 180.0) / 360.0
    return int(round(x0 + t * width))


def _slice_gauges(q: _QuadList, g: SliceGauges, m: HudMetrics) -> None:
    s = m.text_scale
    gw = max(24, m.width // 12)
    gh = max(3, m.height // 150)
    label_w = text_width("XW", s) + 2 * s
    total = 3 * (label_w + gw) + 2 * m.margin
    x = (m.width - total) // 2
    # Bottom centre, above the warning line: the top centre is the hint panel's.
    y = m.height - m.margin - 2 * (GLYPH_H + 4) * s - gh
    for name, angle in zip(("XW", "YW", "ZW"), g.angles):
        q.text(name, x, y - (GLYPH_H * s - gh) // 2, s, TEXT_COLOR)
        x0 = x + label_w
        q.rect(x0 - 1, y - 1, gw + 2, gh + 2, OUTLINE_COLOR)
        q.rect(x0, y, gw, gh, TRACK_COLOR)
        for tick in (-90.0, 0.0, 90.0):
            tx = slice_marker_x(tick, x0, gw)
            q.rect(tx - m.thickness // 2, y - gh // 2, m.thickness, 2 * gh, TICK_COLOR)
        aligned = abs(angle - 90.0 * round(angle / 90.0)) < 0.5
        mx = slice_marker_x(angle, x0, gw)
        mw = max(2, gh)
        q.rect(mx - mw // 2 - 1, y - gh - 1, mw + 2, 3 * gh + 2, OUTLINE_COLOR)
        q.rect(mx - mw // 2, y - gh, mw, 3 * gh, SLICE_ALIGNED_COLOR if aligned else SLICE_MARKER_COLOR)
        x = x0 + gw + m.margin
    if g.mode != "synced":
        text = f"FRUSTUM {g.orbit:+.0f}" if g.mode == "frustum" else "RETURNING"
        q.text(text, (m.width - text_width(text, s)) // 2, y - 2 * gh - (GLYPH_H + 3) * s, s, SLICE_MODE_COLOR)


def weapon_text(panel: WeaponPanel) -> str:
    """The weapon panel's line: ``[1/3] 120-CELL GUN  COST 1`` (or ``AMMO 12``), plus the bullets in flight."""
    pay = f"AMMO {panel.ammo}" if panel.ammo >= 0 else f"COST {panel.cost:g}"
    text = f"[{panel.slot}/{panel.count}] {panel.name.upper()}  {pay}"
    return text + (f"  LIVE {panel.live}" if panel.live >= 0 else "")


def _weapon_panel(q: _QuadList, panel: WeaponPanel, m: HudMetrics) -> None:
    """Above the energy bar: the weapon's line, a cooldown bar (full when ready) and a refusal line."""
    s = m.text_scale
    x, y, w, h = m.energy_bar()
    line_h = (GLYPH_H + 3) * s
    # Wrapped short of the middle, where the slice gauges are (larger text takes two lines).
    limit = max(w, m.width // 2 - 5 * m.margin - x)
    lines: list[str] = []
    for part in weapon_text(panel).split("  "):  # break between its parts (name, cost, bullets)
        if lines and text_width(f"{lines[-1]}  {part}", s) <= limit:
            lines[-1] = f"{lines[-1]}  {part}"
        else:
            lines += wrap(part, limit, s)
    top = y - (len(lines) + 1) * line_h - 3 * h
    flash = min(max(float(panel.flash), 0.0), 1.0)
    for i, line in enumerate(lines):
        q.text(line, x, top + i * line_h, s, _mix(WEAPON_COLOR, (1.0, 1.0, 1.0, 1.0), flash))
    by = top + len(lines) * line_h
    q.rect(x - 1, by - 1, w + 2, h // 2 + 2, OUTLINE_COLOR)
    ready = 1.0 - min(max(float(panel.cooldown), 0.0), 1.0)
    q.rect(x, by, int(round(w * ready)), h // 2, WEAPON_READY_COLOR if ready >= 1.0 else WEAPON_COOL_COLOR)
    if panel.refused:
        q.text(panel.refused, x, top - line_h, s, cue("energy_empty"))


def energy_text(gauge: EnergyGauge) -> str:
    """The number shown by the energy bar: ``value/maximum``, whole numbers unless the maximum is small."""
    if gauge.maximum >= 10:
        return f"{int(np.floor(gauge.value + 1e-9)):d}/{int(round(gauge.maximum)):d}"
    return f"{gauge.value:.1f}/{gauge.maximum:.1f}"


def energy_fill_width(gauge: EnergyGauge, inner_w: int) -> int:
    """Pixels of the fill in a track ``inner_w`` pixels wide: ``value / maximum`` of it, clamped to [0, 1]."""
    frac = gauge.value / gauge.maximum if gauge.maximum > 0 else 0.0
    return int(round(inner_w * min(max(frac, 0.0), 1.0)))


def _mix(a, b, t):
    return tuple(x + (y - x) * t for x, y in zip(a, b))


def _energy_bar(q: _QuadList, gauge: EnergyGauge, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = m.energy_bar()
    flash = min(max(float(gauge.flash), 0.0), 1.0)
    if flash > 0:
        # A glow round the bar that fades with the flash.
        g = max(2, h // 3)
        q.rect(x - g, y - g, w + 2 * g, h + 2 * g, cue("energy_flash")[:3] + (0.55 * flash,))
    outline = (cue("energy_empty")[:3] + (0.9,)) if gauge.empty else _mix(OUTLINE_COLOR, cue("energy_flash"), flash)
    q.rect(x - 1, y - 1, w + 2, h + 2, outline)
    q.rect(x, y, w, h, OUTLINE_COLOR)  # a dark backing inside the (possibly bright) outline keeps the fill readable
    q.rect(x, y, w, h, ENERGY_EMPTY_TRACK_COLOR if gauge.empty else ENERGY_TRACK_COLOR)
    pad = max(1, h // 6)
    inner_w = w - 2 * pad
    fill = cue("energy_empty") if gauge.empty else _mix(cue("energy"), cue("energy_flash"), 0.8 * flash)
    q.rect(x + pad, y + pad, energy_fill_width(gauge, inner_w), h - 2 * pad, fill)
    label_y = y - GLYPH_H * s - 3 * s - 1
    label, color = ("NO ENERGY", cue("energy_empty")) if gauge.empty else ("ENERGY", ENERGY_LABEL_COLOR)
    q.text(label, x, label_y, s, color)
    val = energy_text(gauge)
    q.text(val, x + w - text_width(val, s), label_y, s, _mix(TEXT_COLOR, cue("energy_flash"), flash))
    if gauge.costs:  # what each 4D action costs, over the label (under the weapon panel)
        q.text(gauge.costs, x, label_y - (GLYPH_H + 3) * s, s, ENERGY_LABEL_COLOR)


_HUD_VS = """
#version 330
uniform vec2 u_screen;
in vec2 in_corner;
in vec4 in_rect;
in vec4 in_uv;
in vec4 in_color;
out vec2 v_uv;
out vec4 v_color;
void main() {
    vec2 p = in_rect.xy + in_corner * in_rect.zw;
    v_uv = mix(in_uv.xy, in_uv.zw, in_corner);
    v_color = in_color;
    // Pixels (origin top-left) to clip space (origin centre, y up).
    gl_Position = vec4(p.x / u_screen.x * 2.0 - 1.0, 1.0 - p.y / u_screen.y * 2.0, 0.0, 1.0);
}
"""

_HUD_FS = """
#version 330
uniform sampler2D u_atlas;
uniform vec2 u_atlas_size;
in vec2 v_uv;
in vec4 v_color;
out vec4 f_color;
void main() {
    float a = texture(u_atlas, v_uv / u_atlas_size).r;
    f_color = vec4(v_color.rgb, v_color.a * a);
}
"""


class HudRenderer:
    """Draws a :class:`Hud` with one instanced draw call.

    Parameters
    ----------
    ctx : moderngl.Context
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.program = ctx.program(vertex_shader=_HUD_VS, fragment_shader=_HUD_FS)
        self.atlas = None
        self._atlas_revision = -1
        self.program["u_atlas"].value = 0
        corners = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], np.float32)
        self._corner_vbo = ctx.buffer(corners.tobytes())
        self._instances = ctx.buffer(reserve=256 * QUAD_FLOATS * 4, dynamic=True)
        self._vao = self._make_vao()
        self.last_quads = np.zeros((0, QUAD_FLOATS), np.float32)

    def _make_vao(self) -> moderngl.VertexArray:
        return self.ctx.vertex_array(
            self.program,
            [
                (self._corner_vbo, "2f", "in_corner"),
                (self._instances, "4f 4f 4f/i", "in_rect", "in_uv", "in_color"),
            ],
        )

    def draw(self, hud: Hud, viewport: tuple[int, int, int, int], radar: Radar | None = None) -> None:
        """Draw over whatever is in ``viewport`` (``(x, y, w, h)``, GL convention) of the bound framebuffer.

        ``radar`` adds the radar's labels (see :func:`hud_quads`).
        """
        _, _, w, h = (int(v) for v in viewport)
        quads = hud_quads(hud, w, h, radar)
        self.last_quads = quads
        self.draw_quads(quads, viewport)

    def draw_quads(self, quads: np.ndarray, viewport: tuple[int, int, int, int]) -> None:
        """Draw HUD quads (``(n, QUAD_FLOATS)`` float32, see :func:`hud_quads`) over ``viewport``.

        The menus share it: one instanced call with the font atlas, uploaded when glyphs were added.
        """
        if len(quads) == 0:
            return
        _, _, w, h = (int(v) for v in viewport)
        data = quads.tobytes()
        if len(data) > self._instances.size:
            self._instances.orphan(len(data) * 2)
        self._instances.write(data)
        ctx = self.ctx
        ctx.viewport = viewport
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        self.program["u_screen"].value = (float(w), float(h))
        self._upload_atlas()
        self.atlas.use(0)
        self._vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=len(quads))
        ctx.disable(moderngl.BLEND)

    def _upload_atlas(self) -> None:
        """Send the font atlas to the GPU when glyphs were added since the last upload."""
        font = default_font()
        if font.revision == self._atlas_revision:
            return
        image = font.image
        size = (image.shape[1], image.shape[0])
        if self.atlas is None or self.atlas.size != size:
            if self.atlas is not None:
                self.atlas.release()
            self.atlas = self.ctx.texture(size, 1, alignment=1)
            self.atlas.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self.atlas.repeat_x = self.atlas.repeat_y = False
        # Row 0 of the array is uploaded first, so texel row r is array row r:
        # atlas v coordinates count down from the top like the layout's y.
        self.atlas.write(np.ascontiguousarray(image).tobytes())
        self.program["u_atlas_size"].value = (float(size[0]), float(size[1]))
        self._atlas_revision = font.revision

    def release(self) -> None:
        for obj in (self._vao, self._instances, self._corner_vbo, self.atlas, self.program):
            if obj is not None:
                obj.release()


def health_bar_rect(m: HudMetrics) -> tuple[int, int, int, int]:
    """The health bar's track as ``(x, y, w, h)`` pixels: top-left, below the FPS line."""
    bar_h = max(5, m.height // 45)
    bar_w = max(40, int(round(m.width * 0.2)))
    return m.margin, m.margin + 2 * (GLYPH_H + 3) * m.text_scale, bar_w, bar_h


def health_fill_width(gauge: HealthGauge, inner_w: int) -> int:
    """Pixels of the bar's inner width filled: ``value / maximum`` of it."""
    frac = 0.0 if gauge.maximum <= 0 else min(max(gauge.value / gauge.maximum, 0.0), 1.0)
    return int(round(frac * inner_w))


def _health_bar(q: _QuadList, gauge: HealthGauge, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = health_bar_rect(m)
    pad = max(1, h // 5)
    frac = 0.0 if gauge.maximum <= 0 else min(max(gauge.value / gauge.maximum, 0.0), 1.0)
    fill = _mix(HEALTH_LOW_COLOR, HEALTH_FULL_COLOR, frac)
    fill = _mix(fill, (1.0, 1.0, 1.0, 1.0), 0.6 * min(gauge.flash, 1.0))
    q.rect(x - 1, y - 1, w + 2, h + 2, OUTLINE_COLOR)
    q.rect(x, y, w, h, HEALTH_TRACK_COLOR)
    q.rect(x + pad, y + pad, health_fill_width(gauge, w - 2 * pad), h - 2 * pad, fill)
    label = "SAFE" if gauge.safe else "HEALTH"
    top = y - GLYPH_H * s - 3 * s
    q.text(label, x, top, s, HEALTH_SAFE_COLOR if gauge.safe else TEXT_COLOR)
    val = f"{gauge.value:.0f}/{gauge.maximum:.0f}"
    q.text(val, x + w - text_width(val, s), top, s, TEXT_COLOR)


def damage_cue_points(angle: float, m: HudMetrics) -> list[tuple[int, int]]:
    """Centres of the cue's marks: an arc round the crosshair centred on ``angle`` (0 up, + right)."""
    r = max(12, int(round(m.height * 0.16)))
    cx, cy = m.width // 2, m.height // 2
    return [
        (int(round(cx + r * np.sin(angle + d))), int(round(cy - r * np.cos(angle + d))))
        for d in np.radians([-20.0, -10.0, 0.0, 10.0, 20.0])
    ]


def _damage_cue(q: _QuadList, angle: float, m: HudMetrics) -> None:
    size = max(3, m.height // 80)
    for i, (px, py) in enumerate(damage_cue_points(angle, m)):
        grow = size // 2 if i == 2 else 0  # the middle mark is bigger: the exact direction
        q.rect(px - size // 2 - grow, py - size // 2 - grow, size + 2 * grow, size + 2 * grow, DAMAGE_CUE_COLOR)
