"""The HUD's gauges: the w indicator, energy, health and weapon bars, the slice gauges, hit cues.

Each ``draw_*`` function adds its quads to a :class:`~.quads.QuadList` at the places
:mod:`.hud_layout` gives; :func:`~.hud.hud_quads` calls them in draw order. Colours are
display-space RGBA.
"""

from __future__ import annotations

import numpy as np

from ..game.frame import EnergyGauge, HealthGauge, Hud, SliceGauges, WeaponPanel
from .font import GLYPH_H, GLYPH_W, text_width
from .hud_layout import HudMetrics, damage_cue_points, health_bar_rect, left_lines, slice_gauges_left, slice_marker_x
from .palette import cue
from .quads import QuadList, mix

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
ENERGY_TRACK_COLOR = (0.55, 0.85, 1.0, 0.16)
ENERGY_FILL_COLOR = cue("energy", "default")
ENERGY_FLASH_COLOR = cue("energy_flash", "default")
ENERGY_EMPTY_COLOR = cue("energy_empty", "default")
#: What was just spent, after the fill: warm and bright, so a drain is seen as it happens.
ENERGY_SPENT_COLOR = (1.0, 0.72, 0.35, 0.95)
ENERGY_LABEL_COLOR = (0.75, 0.95, 1.0, 1.0)
WEAPON_COLOR = (1.0, 0.9, 0.6, 1.0)
WEAPON_READY_COLOR = (0.5, 1.0, 0.6, 0.9)
WEAPON_COOL_COLOR = (1.0, 0.6, 0.2, 0.9)
HEALTH_FULL_COLOR = (0.35, 0.95, 0.45, 0.95)
HEALTH_LOW_COLOR = (1.0, 0.2, 0.15, 0.95)
HEALTH_TRACK_COLOR = (1.0, 0.4, 0.35, 0.18)
HEALTH_SAFE_COLOR = (0.6, 0.9, 1.0, 1.0)
DAMAGE_FLASH_COLOR = (0.9, 0.05, 0.0, 0.35)
DAMAGE_VIGNETTE_BANDS = 4  # the red frame after a hit: bands fading inward
DAMAGE_CUE_COLOR = (1.0, 0.2, 0.1, 0.9)
SLICE_MARKER_COLOR = cue("marker", "default")
SLICE_ALIGNED_COLOR = (0.45, 1.0, 0.55, 1.0)
SLICE_MODE_COLOR = (0.6, 0.9, 1.0, 1.0)


def draw_damage_vignette(q: QuadList, k: float, W: int, H: int) -> None:
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


def draw_w_indicator(q: QuadList, hud: Hud, m: HudMetrics) -> None:
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


def draw_slice_gauges(q: QuadList, g: SliceGauges, m: HudMetrics) -> None:
    s = m.text_scale
    gw = max(24, m.width // 12)
    gh = max(3, m.height // 150)
    label_w = text_width("XW", s) + 2 * s
    x = slice_gauges_left(m)
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


def draw_weapon_panel(q: QuadList, panel: WeaponPanel, m: HudMetrics, raised: int = 0) -> None:
    """Above the energy bar (and ``raised`` lines more, over a cost line that takes more than
    one): the weapon's line, a cooldown bar (full when ready) and a refusal line."""
    s = m.text_scale
    x, y, w, h = m.energy_bar()
    line_h = (GLYPH_H + 3) * s
    lines = left_lines(weapon_text(panel), m)  # larger text takes two lines
    top = y - (len(lines) + 1 + raised) * line_h - 3 * h
    flash = min(max(float(panel.flash), 0.0), 1.0)
    for i, line in enumerate(lines):
        q.text(line, x, top + i * line_h, s, mix(WEAPON_COLOR, (1.0, 1.0, 1.0, 1.0), flash))
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


def draw_energy_bar(q: QuadList, gauge: EnergyGauge, m: HudMetrics) -> None:
    """The bar: its fill, then what was just spent as a bright segment after it (it shrinks as the
    spend sinks in), a glow after a pickup. Empty, the track stays dark and empty: only its outline,
    label and number turn red, so an empty bar never reads as a full one."""
    s = m.text_scale
    x, y, w, h = m.energy_bar()
    flash = min(max(float(gauge.flash), 0.0), 1.0)
    if flash > 0:
        # A glow round the bar that fades with the flash.
        g = max(2, h // 3)
        q.rect(x - g, y - g, w + 2 * g, h + 2 * g, cue("energy_flash")[:3] + (0.55 * flash,))
    outline = (cue("energy_empty")[:3] + (0.9,)) if gauge.empty else mix(OUTLINE_COLOR, cue("energy_flash"), flash)
    # The outline as four edges: a whole rectangle under the translucent track would tint it.
    for ex, ey, ew, eh in ((x - 1, y - 1, w + 2, 1), (x - 1, y + h, w + 2, 1), (x - 1, y, 1, h), (x + w, y, 1, h)):
        q.rect(ex, ey, ew, eh, outline)
    q.rect(x, y, w, h, OUTLINE_COLOR)  # a dark backing keeps the fill readable over any scene
    q.rect(x, y, w, h, ENERGY_TRACK_COLOR)
    pad = max(1, h // 6)
    inner_w = w - 2 * pad
    fill_w = energy_fill_width(gauge, inner_w)
    q.rect(x + pad, y + pad, fill_w, h - 2 * pad, mix(cue("energy"), cue("energy_flash"), 0.8 * flash))
    spent_w = energy_spent_width(gauge, inner_w)
    q.rect(x + pad + fill_w, y + pad, spent_w, h - 2 * pad, ENERGY_SPENT_COLOR)
    label_y = y - GLYPH_H * s - 3 * s - 1
    label, color = ("NO ENERGY", cue("energy_empty")) if gauge.empty else ("ENERGY", ENERGY_LABEL_COLOR)
    q.text(label, x, label_y, s, color)
    val = energy_text(gauge)
    val_color = cue("energy_empty") if gauge.empty else mix(TEXT_COLOR, cue("energy_flash"), flash)
    q.text(val, x + w - text_width(val, s), label_y, s, val_color)
    # What each 4D action costs, over the label (under the weapon panel), clear of the gauges.
    costs = left_lines(gauge.costs, m, gauges=True)
    for i, line in enumerate(costs):
        q.text(line, x, label_y - (len(costs) - i) * (GLYPH_H + 3) * s, s, ENERGY_LABEL_COLOR)


def energy_spent_width(gauge: EnergyGauge, inner_w: int) -> int:
    """Pixels of the just-spent segment after the fill: ``spent / maximum`` of the track, within it."""
    if gauge.maximum <= 0 or gauge.spent <= 0:
        return 0
    top = min(max((gauge.value + gauge.spent) / gauge.maximum, 0.0), 1.0)
    return max(1, int(round(inner_w * top)) - energy_fill_width(gauge, inner_w))


def health_fill_width(gauge: HealthGauge, inner_w: int) -> int:
    """Pixels of the bar's inner width filled: ``value / maximum`` of it."""
    frac = 0.0 if gauge.maximum <= 0 else min(max(gauge.value / gauge.maximum, 0.0), 1.0)
    return int(round(frac * inner_w))


def draw_health_bar(q: QuadList, gauge: HealthGauge, m: HudMetrics) -> None:
    s = m.text_scale
    x, y, w, h = health_bar_rect(m)
    pad = max(1, h // 5)
    frac = 0.0 if gauge.maximum <= 0 else min(max(gauge.value / gauge.maximum, 0.0), 1.0)
    fill = mix(HEALTH_LOW_COLOR, HEALTH_FULL_COLOR, frac)
    fill = mix(fill, (1.0, 1.0, 1.0, 1.0), 0.6 * min(gauge.flash, 1.0))
    q.rect(x - 1, y - 1, w + 2, h + 2, OUTLINE_COLOR)
    q.rect(x, y, w, h, HEALTH_TRACK_COLOR)
    q.rect(x + pad, y + pad, health_fill_width(gauge, w - 2 * pad), h - 2 * pad, fill)
    label = "SAFE" if gauge.safe else "HEALTH"
    top = y - GLYPH_H * s - 3 * s
    q.text(label, x, top, s, HEALTH_SAFE_COLOR if gauge.safe else TEXT_COLOR)
    val = f"{gauge.value:.0f}/{gauge.maximum:.0f}"
    q.text(val, x + w - text_width(val, s), top, s, TEXT_COLOR)


def draw_damage_cue(q: QuadList, angle: float, m: HudMetrics) -> None:
    size = max(3, m.height // 80)
    for i, (px, py) in enumerate(damage_cue_points(angle, m)):
        grow = size // 2 if i == 2 else 0  # the middle mark is bigger: the exact direction
        q.rect(px - size // 2 - grow, py - size // 2 - grow, size + 2 * grow, size + 2 * grow, DAMAGE_CUE_COLOR)
