"""The energy bar on the HUD: layout (pure numpy) and its pixels (offscreen GL)."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from across_dimensions.game.frame import Camera3, EnergyGauge, Frame, Hud
from across_dimensions.render.font import GLYPH_H
from across_dimensions.render.hud import (
    ENERGY_EMPTY_COLOR,
    ENERGY_FILL_COLOR,
    ENERGY_FLASH_COLOR,
    HudMetrics,
    energy_text,
    hud_quads,
    quads_text,
)

SIZES = [(1280, 720), (800, 450), (160, 90)]


def rows_with_color(quads: np.ndarray, color) -> np.ndarray:
    return quads[np.all(np.isclose(quads[:, 8:12], np.float32(color), atol=1e-6), axis=1)]


def shows_text(quads: np.ndarray, text: str) -> bool:
    """True when the glyphs of ``text`` (spaces skipped) are drawn in order somewhere."""
    return text.replace(" ", "") in quads_text(quads)


def fill_rect(hud: Hud, w: int, h: int) -> np.ndarray:
    rows = rows_with_color(hud_quads(hud, w, h), ENERGY_FILL_COLOR)
    assert len(rows) <= 1
    return rows[0, :4] if len(rows) else None


@pytest.mark.parametrize("size", SIZES)
def test_fill_width_is_proportional_to_value_over_maximum(size):
    w, h = size
    bx, by, bw, bh = HudMetrics(w, h).energy_bar()
    widths = {}
    for value in (10.0, 25.0, 50.0, 75.0, 100.0):
        r = fill_rect(Hud(energy=EnergyGauge(value, 100.0)), w, h)
        widths[value] = r[2]
        # The fill starts at the bar's left end and stays inside it.
        assert bx <= r[0] < bx + bw and by <= r[1] and r[1] + r[3] <= by + bh
    inner = widths[100.0]
    assert inner >= bw - 6
    for value, width in widths.items():
        assert abs(width - inner * value / 100.0) <= 0.5 + 1e-6, (value, width, inner)
    # Same fraction, other maximum: same width.
    assert fill_rect(Hud(energy=EnergyGauge(2.5, 5.0)), w, h)[2] == widths[50.0]
    # Nothing to fill at zero; never wider than the track when over-full.
    assert fill_rect(Hud(energy=EnergyGauge(0.0, 100.0)), w, h) is None
    assert fill_rect(Hud(energy=EnergyGauge(150.0, 100.0)), w, h)[2] == inner


def test_value_is_shown_as_a_number():
    quads = hud_quads(Hud(energy=EnergyGauge(64.0, 100.0)), 1280, 720)
    assert energy_text(EnergyGauge(64.0, 100.0)) == "64/100"
    assert shows_text(quads, "64/100") and shows_text(quads, "ENERGY")
    assert energy_text(EnergyGauge(2.5, 5.0)) == "2.5/5.0"
    assert not shows_text(quads, "NO ENERGY")


@pytest.mark.parametrize("size", SIZES)
def test_empty_bar_reads_no_energy_in_red(size):
    w, h = size
    empty = hud_quads(Hud(energy=EnergyGauge(0.0, 100.0, empty=True)), w, h)
    assert shows_text(empty, "NO ENERGY")
    assert len(rows_with_color(empty, ENERGY_EMPTY_COLOR)) >= len("NOENERGY")
    full = hud_quads(Hud(energy=EnergyGauge(0.0, 100.0, empty=False)), w, h)
    assert not shows_text(full, "NO ENERGY") and len(rows_with_color(full, ENERGY_EMPTY_COLOR)) == 0


def test_flash_glows_and_fades():
    def glow_alpha(flash):
        quads = hud_quads(Hud(energy=EnergyGauge(50.0, 100.0, flash=flash)), 1280, 720)
        rows = quads[np.all(np.isclose(quads[:, 8:11], np.float32(ENERGY_FLASH_COLOR[:3])), axis=1)]
        return rows[:, 11].max() if len(rows) else 0.0

    assert glow_alpha(0.0) == 0.0
    assert 0.0 < glow_alpha(0.3) < glow_alpha(1.0)
    # The fill brightens with the flash.
    bright = hud_quads(Hud(energy=EnergyGauge(50.0, 100.0, flash=1.0)), 1280, 720)
    assert len(rows_with_color(bright, ENERGY_FILL_COLOR)) == 0


def test_no_bar_without_energy():
    plain = hud_quads(Hud(), 1280, 720)
    assert not shows_text(plain, "ENERGY")
    assert len(rows_with_color(plain, ENERGY_FILL_COLOR)) == 0


@pytest.mark.parametrize("size", SIZES)
def test_bar_keeps_clear_of_crosshair_w_indicator_and_radar(size):
    w, h = size
    m = HudMetrics(w, h)

    def overlap(a, b):
        return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]

    bar = m.energy_bar()
    label_h = (GLYPH_H + 4) * m.text_scale + 1
    bar_and_label = (bar[0], bar[1] - label_h, bar[2], bar[3] + label_h)
    tx, ty, _, th = m.w_track()
    w_column = (tx - 3 * 6 * m.text_scale, ty - label_h, w - (tx - 3 * 6 * m.text_scale), th + 2 * label_h)
    cross = (w // 2 - m.arm - 1, h // 2 - m.arm - 1, 2 * m.arm + 3, 2 * m.arm + 3)
    radar = m.radar_rect()
    bar_l = bar_and_label
    pairs = ((bar_l, w_column), (bar_l, cross), (bar_l, radar), (radar, w_column), (radar, cross))
    for a, b in pairs:
        assert not overlap(a, b), (a, b)
    assert 0 <= radar[0] and radar[1] >= 0 and radar[1] + radar[3] <= h and bar[1] + bar[3] <= h


@pytest.mark.gl
def test_energy_bar_pixels(gl_ctx):
    from across_dimensions.render.context import Offscreen
    from across_dimensions.render.renderer import Renderer

    sky = (0.05, 0.06, 0.10)
    r = Renderer(gl_ctx)
    try:
        with Offscreen(gl_ctx, 320, 180) as t:
            t.use()

            def shot(energy):
                r.draw(Frame(Camera3(position=np.zeros(3)), hud=Hud(crosshair=False, energy=energy), sky_color=sky))
                return t.read_rgb().astype(int)

            none, half, empty = shot(None), shot(EnergyGauge(50.0, 100.0)), shot(EnergyGauge(0.0, 100.0, empty=True))
            x, y, bw, bh = HudMetrics(320, 180).energy_bar()
            row = y + bh // 2
            # Left half of the bar is filled cyan, the right half is not; without a gauge nothing is drawn there.
            left, right = half[row, x + bw // 4], half[row, x + 3 * bw // 4]
            assert left[2] > 150 and left[1] > 150 and left[0] < 120
            assert right[2] < 120
            assert np.abs(none[row, x : x + bw] - none[row, x + bw + 20]).max() <= 2
            # Empty looks empty: inside, the track is the unfilled half's dark, not a red fill;
            # only the outline (just outside the track) is red.
            assert np.abs(empty[row, x + bw // 2] - half[row, x + 3 * bw // 4]).max() <= 6, "the empty bar looks filled"
            edge = empty[y - 1, x + bw // 2]
            assert edge[0] > edge[1] + 60 and edge[0] > edge[2] + 60, "the empty bar's outline is red"
        assert gl_ctx.error == "GL_NO_ERROR"
    finally:
        r.release()


def test_w_gauge_says_which_side_is_solid():
    from across_dimensions.render.hud import BLOCKED_ANA_COLOR, BLOCKED_KATA_COLOR

    def colours(hud):
        return {tuple(np.round(r[8:], 3)) for r in hud_quads(hud, 1280, 720)}

    free = colours(Hud(w=0.0, w_min=-1.0, w_max=1.0))
    ana = colours(Hud(w=0.0, w_min=-1.0, w_max=1.0, w_blocked=(1,)))
    both = colours(Hud(w=0.0, w_min=-1.0, w_max=1.0, w_blocked=(1, -1)))
    ana_c, kata_c = (tuple(np.round(np.float32(c), 3)) for c in (BLOCKED_ANA_COLOR, BLOCKED_KATA_COLOR))
    assert ana_c not in free and kata_c not in free
    assert ana_c in ana and kata_c not in ana
    assert ana_c in both and kata_c in both
    assert "solid+w" in quads_text(hud_quads(Hud(w=0.0, w_min=-1.0, w_max=1.0, w_blocked=(1,)), 1280, 720))


def test_an_empty_bar_has_no_fill_and_spending_shows_as_a_segment_that_sinks_in():
    from across_dimensions.app.energy_trail import GRACE_SECONDS, EnergyTrail
    from across_dimensions.render.hud_gauges import ENERGY_SPENT_COLOR, energy_spent_width

    empty = hud_quads(Hud(energy=EnergyGauge(0.0, 10.0, empty=True)), 1280, 720)
    assert len(rows_with_color(empty, ENERGY_FILL_COLOR)) == 0  # no fill at all, not a red one
    assert shows_text(empty, "NO ENERGY") and shows_text(empty, "0/10")
    # Holding a w key: 0.1 a tick at 10 FPS. The trail keeps what was spent in sight.
    trail, value, widths = EnergyTrail(), 4.0, []
    trail.update(EnergyGauge(value, 10.0), 0.1)
    for _ in range(5):
        value -= 0.4
        g = trail.update(EnergyGauge(value, 10.0), 0.1)
        widths.append(energy_spent_width(g, 400))
    assert g.spent == pytest.approx(2.0) and widths == sorted(widths) and widths[0] > 0
    quads = hud_quads(Hud(energy=g), 1280, 720)
    assert len(rows_with_color(quads, ENERGY_SPENT_COLOR)) == 1
    # Once the spending stops: whole for the grace, then it sinks in, and it is gone.
    left = [trail.update(EnergyGauge(value, 10.0), 0.1).spent for _ in range(int(GRACE_SECONDS / 0.1) + 12)]
    assert left[0] == pytest.approx(2.0) and left[int(GRACE_SECONDS / 0.1) - 1] == pytest.approx(2.0)
    assert left[-1] == 0.0 and left == sorted(left, reverse=True)


def test_the_first_large_message_of_a_level_rasterizes_no_glyphs(gl_ctx, monkeypatch):
    """A text size's first use rasterizes the font's common characters, 20-40 ms: the HUD's
    first frame at a view size makes both its sizes, so a large message showing mid-level
    (once an enemy is down, say) adds nothing to the atlas on its frame."""
    from across_dimensions.render import font, hud_layout
    from across_dimensions.render import hud as hud_module
    from across_dimensions.render.context import Offscreen

    fresh = functools.lru_cache(maxsize=1)(lambda: font.FontAtlas())  # no size made yet
    monkeypatch.setattr(font, "default_font", fresh)
    monkeypatch.setattr(hud_module, "default_font", fresh)
    hud = hud_module.HudRenderer(gl_ctx)
    try:
        with Offscreen(gl_ctx, 640, 360) as t:
            t.use()
            hud.draw(Hud(), t.viewport)
            atlas = fresh()
            before = atlas.revision
            hud.draw(Hud(message="TARGET DOWN"), t.viewport)  # one line: the large size
            m = HudMetrics(640, 360)
            assert font.font_px(hud_layout.message_scale(m)) > font.font_px(m.text_scale)
            assert atlas.revision == before
            hud.draw(Hud(message="TARGET DOWN"), (0, 0, 1920, 1080))  # a new view size makes its own once
            assert atlas.revision > before
    finally:
        hud.release()
