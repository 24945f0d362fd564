"""The radar never hides what the player is after: it gives way when a target lies behind it.

Each level with a radar is drawn at many poses that put its crystals, switches, bodies and enemies
at different places on screen, bottom right (the radar's corner) most of all; the picture with the
HUD is compared with the picture without it at each target's centre. A target whose pixel the HUD
changes by more than a quarter of the range is hidden: none may be. The same poses drawn with a
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
from across_dimensions.render.radar_yield import interest_on_screen, radar_yields
from across_dimensions.render.renderer import Renderer
from across_dimensions.world.level import load_level
from across_dimensions.world.resources import level_files

W, H = 480, 270
#: A pixel the HUD changes by more than this (of 255) in some channel is hidden by it.
HIDDEN = 64
#: Look offsets (yaw to the left, pitch up, radians) that move a target towards the bottom right.
OFFSETS = ((0.0, 0.0), (0.42, 0.28), (0.3, 0.4), (0.5, 0.12))


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
        hidden += int(np.abs(shown[py, px] - bare[py, px]).max() > HIDDEN)
    return behind, hidden


@pytest.mark.gl
def test_the_hud_hides_no_target_of_interest_at_any_pose(gl_ctx, monkeypatch):
    renderer = Renderer(gl_ctx)
    behind = hidden = poses = 0
    control = []  # the same poses with a radar that never gives way
    try:
        with Offscreen(gl_ctx, W, H) as target:
            for path in _radar_levels():
                game = Game(load_level(path))
                for feet, yaw, pitch in _poses(game):
                    game.place_player(feet, yaw, pitch)
                    frame = game.frame()
                    b, h = _hidden(renderer, target, frame)
                    behind, hidden, poses = behind + b, hidden + h, poses + 1
                    if b and len(control) < 12:
                        control.append(frame)
            monkeypatch.setattr(renderer_module, "radar_yields", lambda *a: False)
            stubborn = sum(_hidden(renderer, target, f)[1] for f in control)
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
