"""The radar never hides what the player is after: it gives way when a target lies behind it.

Each level with a radar is drawn at many poses that put its crystals, switches, bodies and enemies
at different places on screen, bottom right (the radar's corner) most of all; the picture with the
HUD is compared with the picture without it at each target's middle. A target whose middle the
HUD changes by more than a quarter of the range is hidden: none may be. The same poses drawn with a
radar that never gives way hide some, so the measure can see a hidden target.
"""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.game.sim import Game
from across_dimensions.game.systems.radar import INTEREST
from across_dimensions.render import renderer as renderer_module
from across_dimensions.render.context import Offscreen
from across_dimensions.render.hud_layout import HudMetrics
from across_dimensions.render.radar_yield import YIELD_ALPHA, interest_on_screen, radar_yields
from across_dimensions.render.renderer import Renderer
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import level_files

W, H = 480, 270
#: A pixel the HUD changes by more than this (of 255) in some channel is hidden by it.
HIDDEN = 64
#: Look offsets (yaw to the left, pitch up, radians) that move a target towards the bottom right.
OFFSETS = ((0.0, 0.0), (0.42, 0.28), (0.3, 0.4), (0.5, 0.12))


def _radar_middle() -> tuple[float, float]:
    """The look offset that puts the aimed-at point in the middle of the radar's rectangle
    (the game's default field of view, 75 degrees)."""
    rx, ry, rw, rh = HudMetrics(W, H).radar_rect()
    t = np.tan(np.radians(75.0) / 2.0)
    ax = ((rx + rw / 2) / W * 2.0 - 1.0) * t * W / H
    ay = (1.0 - (ry + rh / 2) / H * 2.0) * t
    return float(np.arctan(ax)), float(-np.arctan(ay))


OFFSETS = (*OFFSETS, _radar_middle())


def _radar_levels():
    return [p for p in level_files() if load_level(p).radar is not None]


def _poses(game: Game):
    """Poses ``(position (4,), yaw, pitch)`` looking at each target of interest from 5 m."""
    lo, hi = game.level.w_range
    for e in game.entity_table().entities:
        if e.radar not in INTEREST:
            continue
        c = np.asarray(game.entity_table().centers[game.entity_table().entities.index(e)], np.float64)
        for turn in (0.0, np.pi):
            d = np.array([np.sin(turn), np.cos(turn)])
            feet = np.array([c[0] - 5.0 * d[0], max(0.0, c[1] - 1.6), c[2] - 5.0 * d[1], np.clip(c[3], lo, hi)])
            eye_y = feet[1] + 1.6
            aim_yaw, aim_pitch = turn, np.arctan2(c[1] - eye_y, 5.0)
            for dy, dp in OFFSETS:
                yield feet, aim_yaw - dy, aim_pitch + dp


def _hidden(renderer, target, frame) -> tuple[int, int]:
    """``(targets behind the radar's rectangle, targets the HUD hides)`` in ``frame``."""
    target.use()
    renderer.draw(frame, hud=False)
    bare = target.read_rgb().astype(int)
    renderer.draw(frame, hud=True)
    shown = target.read_rgb().astype(int)
    rx, ry, rw, rh = HudMetrics(W, H).radar_rect()
    behind = hidden = 0
    for x, y, _ in interest_on_screen(frame, W, H):
        px, py = int(round(x)), int(round(y))
        if not (0 <= px < W and 0 <= py < H) or (abs(px - W // 2) < 12 and abs(py - H // 2) < 12):
            continue  # off screen, or under the crosshair (which must sit on what is aimed at)
        behind += rx <= px < rx + rw and ry <= py < ry + rh
        # The w gauge is a track a few pixels wide at the view's right edge: a target cut by it
        # stays in sight on both sides, so its column is not counted.
        tx, _, tw, _ = HudMetrics(W, H).w_track()
        if tx - 3 <= px <= tx + tw + 3:
            continue
        hidden += int(np.abs(shown[py, px] - bare[py, px]).max() > HIDDEN)
    return behind, hidden


@pytest.mark.slow
@pytest.mark.gl
def test_the_hud_hides_no_target_of_interest_at_any_pose(gl_ctx, monkeypatch):
    renderer = Renderer(gl_ctx)
    behind = hidden = poses = stubborn = controls = 0
    stubborn_radar = [False]  # the control: the same pose with a radar that never gives way
    real = renderer_module.radar_yields
    monkeypatch.setattr(renderer_module, "radar_yields", lambda *a: False if stubborn_radar[0] else real(*a))
    try:
        with Offscreen(gl_ctx, W, H) as target:
            for path in _radar_levels():
                game = Game(load_level(path))
                for feet, yaw, pitch in _poses(game):
                    game.place_player(feet, yaw, pitch)
                    frame = game.frame()
                    b, h = _hidden(renderer, target, frame)
                    behind, hidden, poses = behind + b, hidden + h, poses + 1
                    if b and controls < 12:
                        stubborn_radar[0] = True
                        stubborn += _hidden(renderer, target, frame)[1]
                        stubborn_radar[0], controls = False, controls + 1
    finally:
        renderer.release()
    assert poses > 100 and behind >= 10, f"too few poses put a target behind the radar ({behind} of {poses})"
    assert hidden == 0, f"the HUD hid a target at {hidden} of {poses} poses"
    assert stubborn > 0, "a radar that never gives way hid nothing: the measure cannot see a hidden target"


def test_the_radar_gives_way_only_to_what_lies_behind_it():
    game = Game(load_level(_radar_levels()[0]))
    crystal = next(i for i, e in enumerate(game.entity_table().entities) if e.radar == "crystal")
    c = game.entity_table().centers[crystal]
    feet = np.array([c[0], 0.0, c[2] - 5.0, c[3]])
    game.place_player(feet, 0.0, np.arctan2(c[1] - 1.6, 5.0))
    assert not radar_yields(game.frame(), W, H)  # straight ahead: in the middle of the view
    game.place_player(feet, -0.45, 0.4)  # looking up and left: the crystal sits bottom right
    assert radar_yields(game.frame(), W, H)


def test_a_gauge_gives_way_as_a_whole_only_to_what_lies_behind_it():
    from across_dimensions.game.frame import EnergyGauge, Hud
    from across_dimensions.render.hud import hud_quads

    hud = Hud(
        energy=EnergyGauge(4.0, 10.0, costs="W 2/UNIT  GUN 1"), crosshair=False, w_min=0.0, w_max=0.0
    )  # the bar alone
    plain = hud_quads(hud, W, H)
    bar = HudMetrics(W, H).energy_bar()
    far = np.array([[W / 2, 20.0, 5.0]])  # up in the middle of the view
    near = np.array([[bar[0] + bar[2] + 4.0, bar[1] + 2.0, 5.0]])  # reaching the bar's right end
    assert np.array_equal(hud_quads(hud, W, H, interest=far), plain)
    faded = hud_quads(hud, W, H, interest=near)
    assert faded.shape == plain.shape and np.array_equal(faded[:, :11], plain[:, :11])
    assert np.allclose(faded[:, 11], plain[:, 11] * YIELD_ALPHA)  # every quad of the block, none left bright
