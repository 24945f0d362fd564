"""Drawing the prologue offscreen (render/flatland.py): the side view shows the being, the sections
and the z bar where the frame says; after the goal the view turns to the 3D world with its line."""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.game.actions import Actions
from across_dimensions.game.flatland import FlatGame
from across_dimensions.game.flatland.view import CLOSING_LINE, REVEAL_SECONDS, flat_frame
from across_dimensions.render.context import Offscreen
from across_dimensions.render.flatland import BEING, FlatRenderer
from across_dimensions.render.hud import quads_text
from across_dimensions.world.flat_level import load_flat_level
from across_dimensions.world.resources import levels_dir

pytestmark = pytest.mark.gl
W, H = 320, 180


@pytest.fixture(scope="module")
def drawn(gl_ctx):
    target = Offscreen(gl_ctx, W, H)
    renderer = FlatRenderer(gl_ctx)

    def draw(frame, hud=True):
        target.use()
        renderer.draw(frame, target.viewport, hud)
        return target.read_rgb(), renderer.last_quads

    yield draw
    renderer.release()
    target.release()


def _has(quads, words: str) -> bool:
    """Whether the HUD draws ``words`` (spaces draw nothing, so they are left out)."""
    return words.replace(" ", "") in quads_text(quads)


def _pixel(frame, x: float, y: float) -> tuple[int, int]:
    """Where the plane's point (x, y) lands in the image (row, column)."""
    cx, cy = frame.center
    per_px = 2.0 * frame.half_height / H
    return int(round(H / 2 - (y - cy) / per_px)), int(round(W / 2 + (x - cx) / per_px))


def test_the_side_view_shows_the_being_the_ground_and_the_z_bar(drawn):
    game = FlatGame(load_flat_level(levels_dir() / "prologue.toml"))
    game.step(Actions())
    frame = flat_frame(game, hint="Walk with A and D.")
    img, quads = drawn(frame)
    row, col = _pixel(frame, frame.being[0], frame.being[1] + 0.9)
    assert np.abs(img[row, col].astype(int) - np.array(BEING[:3]) * 255).max() < 40  # the being: yellow
    row, col = _pixel(frame, frame.being[0] + 3.0, -1.5)
    assert img[row, col].max() < 110 and img[row, col].min() > 20  # the ground: a dark panel
    assert _has(quads, "Walk with A and D.") and _has(quads, "z +0.00")
    assert _has(quads, "key > 20 m")  # its pin: the key lies 20 m on (at z = -2)
    paused, quads = drawn(frame, hud=False)  # under the pause menu: the view without bar or hint
    assert len(quads) == 0 and np.array_equal(paused[H // 2, : W // 2], img[H // 2, : W // 2])


def test_after_the_goal_the_view_turns_to_the_3d_world(drawn):
    game = FlatGame(load_flat_level(levels_dir() / "prologue.toml"))
    game.completed_tick = 0  # as if the being had just reached the pad
    game.outcome = "complete"
    flat, _ = drawn(flat_frame(game))
    for _ in range(int(REVEAL_SECONDS * 60)):
        game.tick += 1
    frame = flat_frame(game)
    assert frame.reveal == 1.0 and frame.line == CLOSING_LINE and frame.solids3
    img, quads = drawn(frame)
    assert _has(quads, CLOSING_LINE)
    assert not _has(quads, "z +0.00")  # the z bar went with the flat view
    assert np.abs(img.astype(int) - flat.astype(int)).mean() > 10  # a different picture
