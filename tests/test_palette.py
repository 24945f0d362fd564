"""Every w cue in every palette stays apart for colour-blind players (issue 35, point 2).

The colour-vision-deficiency simulation (Machado, Oliveira and Fernandes 2009, severity 1, on
linear RGB) and the colour difference (CIEDE2000, Sharma, Wu and Dalal 2005) are written out
here, checked against the published test pairs, and applied to each ana / kata pair of each
palette: the ghosts' tints, the HUD's w gauge, its blocked caps and the radar's labels, and the
scene's own ana / kata matter colours.
"""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.render import materials
from across_dimensions.render import palette as w_cues

MACHADO = {
    "protanopia": np.array(
        [[0.152286, 1.052583, -0.204868], [0.114503, 0.786281, 0.099216], [-0.003882, -0.048116, 1.051998]]
    ),
    "deuteranopia": np.array(
        [[0.367322, 0.860646, -0.227968], [0.280085, 0.672501, 0.047413], [-0.011820, 0.042940, 0.968881]]
    ),
    "tritanopia": np.array(
        [[1.255528, -0.076749, -0.178779], [-0.078411, 0.930809, 0.147602], [0.004733, 0.691367, 0.303900]]
    ),
}
#: Least CIEDE2000 distance between the two sides of a pair, for every vision.
MIN_DISTANCE = 40.0
SRGB_TO_XYZ = np.array(
    [[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750], [0.0193339, 0.1191920, 0.9503041]]
)
D65 = np.array([0.95047, 1.0, 1.08883])


def linear(rgb) -> np.ndarray:
    c = np.asarray(rgb, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def srgb(lin) -> np.ndarray:
    c = np.clip(lin, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def simulate(rgb, vision: str) -> np.ndarray:
    """A display colour as seen with ``vision`` (a key of MACHADO, or "normal")."""
    return np.asarray(rgb, dtype=np.float64) if vision == "normal" else srgb(MACHADO[vision] @ linear(rgb))


def lab(rgb) -> np.ndarray:
    xyz = SRGB_TO_XYZ @ linear(rgb) / D65
    f = np.where(xyz > 216 / 24389, np.cbrt(xyz), (24389 / 27 * xyz + 16) / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def ciede2000(lab1, lab2) -> float:
    (l1, a1, b1), (l2, a2, b2) = lab1, lab2
    cbar = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(cbar**7 / (cbar**7 + 25.0**7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1p = np.degrees(np.arctan2(b1, a1p)) % 360
    h2p = np.degrees(np.arctan2(b2, a2p)) % 360
    dh = 0.0 if c1p * c2p == 0 else (h2p - h1p + 180) % 360 - 180
    dhh = 2 * np.sqrt(c1p * c2p) * np.sin(np.radians(dh) / 2)
    lbar, cbarp = (l1 + l2) / 2, (c1p + c2p) / 2
    if c1p * c2p == 0:
        hbar = h1p + h2p
    elif abs(h1p - h2p) <= 180:
        hbar = (h1p + h2p) / 2
    else:
        hbar = (h1p + h2p + (360 if h1p + h2p < 360 else -360)) / 2
    t = (
        1
        - 0.17 * np.cos(np.radians(hbar - 30))
        + 0.24 * np.cos(np.radians(2 * hbar))
        + 0.32 * np.cos(np.radians(3 * hbar + 6))
        - 0.20 * np.cos(np.radians(4 * hbar - 63))
    )
    rt = -np.sin(np.radians(60 * np.exp(-(((hbar - 275) / 25) ** 2)))) * 2 * np.sqrt(cbarp**7 / (cbarp**7 + 25.0**7))
    sl = 1 + 0.015 * (lbar - 50) ** 2 / np.sqrt(20 + (lbar - 50) ** 2)
    sc, sh = 1 + 0.045 * cbarp, 1 + 0.015 * cbarp * t
    dl, dc = (l2 - l1) / sl, (c2p - c1p) / sc
    return float(np.sqrt(dl**2 + dc**2 + (dhh / sh) ** 2 + rt * dc * (dhh / sh)))


@pytest.mark.parametrize(
    "lab1, lab2, expected",  # Sharma, Wu and Dalal's test data, pairs 1, 3, 7 and 17
    [
        ((50.0, 2.6772, -79.7751), (50.0, 0.0, -82.7485), 2.0425),
        ((50.0, -1.3802, -84.2814), (50.0, 0.0, -82.7485), 1.0),
        ((50.0, 0.0, 0.0), (50.0, -1.0, 2.0), 2.3669),
        ((2.0776, 0.0795, -1.135), (0.9033, -0.0636, -0.5514), 0.9082),
        ((60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
    ],
)
def test_the_colour_difference_matches_the_published_pairs(lab1, lab2, expected):
    assert ciede2000(np.array(lab1), np.array(lab2)) == pytest.approx(expected, abs=1e-4)


def test_the_simulation_keeps_greys_and_merges_red_and_green_for_deuteranopes():
    for vision in MACHADO:
        assert simulate((0.5, 0.5, 0.5), vision) == pytest.approx((0.5, 0.5, 0.5), abs=0.01)
    red, green = (0.8, 0.3, 0.2), (0.35, 0.55, 0.2)
    assert ciede2000(lab(red), lab(green)) > 30  # apart with normal vision ...
    assert ciede2000(lab(simulate(red, "deuteranopia")), lab(simulate(green, "deuteranopia"))) < 12  # ... not without


def _pairs(name: str):
    for a, b in w_cues.PAIRS:
        yield a, w_cues.cue(a, name)[:3], w_cues.cue(b, name)[:3]
    scene = materials.palette("colorblind" if name == "colour_blind" else name)
    yield "matter", scene["ana"], scene["kata"]


@pytest.mark.parametrize("name", w_cues.NAMES)
@pytest.mark.parametrize("vision", ["normal", *MACHADO])
def test_every_ana_kata_pair_stays_apart(name, vision):
    for what, ana, kata in _pairs(name):
        d = ciede2000(lab(simulate(ana, vision)), lab(simulate(kata, vision)))
        assert d >= MIN_DISTANCE, f"{name} palette, {what}, {vision}: CIEDE2000 {d:.1f}"


def test_every_palette_changes_the_cues_and_the_renderer_follows_the_settings():
    for name in w_cues.NAMES[1:]:
        changed = [k for a, b in w_cues.PAIRS for k in (a, b) if w_cues.cue(k, name) != w_cues.cue(k, "default")]
        assert len(changed) == 2 * len(w_cues.PAIRS), name
        assert any(w_cues.pin(k, name) != w_cues.pin(k, "default") for k in ("crystal", "enemy", "body"))
    assert w_cues.settings_palette(False, False) == "default"
    assert w_cues.settings_palette(True, False) == "colour_blind"
    assert w_cues.settings_palette(True, True) == "high_contrast"
    try:
        w_cues.use("high_contrast")
        stripes = w_cues.ghost_tint((1.0, 0.4, 0.08, 0.75), "stripes")
        assert stripes == w_cues.cue("ghost_ana") and stripes != (1.0, 0.4, 0.08, 0.75)
        assert w_cues.ghost_tint((0.2, 0.2, 0.2, 0.5), "plain") == (0.2, 0.2, 0.2, 0.5)
    finally:
        w_cues.use("default")


def test_the_hud_and_the_radar_draw_their_w_cues_in_the_palette_in_use():
    from across_dimensions.game.frame import EnergyGauge, Hud
    from across_dimensions.render import radar
    from across_dimensions.render.hud import hud_quads

    hud = Hud(w=0.5, w_blocked=(1, -1), energy=EnergyGauge(3.0, 10.0), hint="a hint")

    def colours() -> set:
        return {tuple(np.round(r[8:12], 3)) for r in hud_quads(hud, 1280, 720)}

    try:
        for name in w_cues.NAMES:
            w_cues.use(name)
            seen = colours()
            for key in ("gauge_ana", "blocked_ana", "blocked_kata", "energy", "hint_accent"):
                assert tuple(np.round(np.float32(w_cues.cue(key)), 3)) in seen, (name, key)
            assert radar._kind_rgb(w_cues.current())[0] == pytest.approx(w_cues.pin(radar.RADAR_KINDS[0]))
    finally:
        w_cues.use("default")
