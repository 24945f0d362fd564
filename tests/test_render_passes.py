"""The per-pass profile of a frame (``render/passes.py``): what ``bench levels`` prints.

No timing is asserted (speed lives in ``bench``): only that each pass is charged its own
triangles and shaded samples, and that profiling draws the same picture.
"""

from __future__ import annotations

import numpy as np
import pytest

from across_dimensions.game.frame import Camera3, Drawable, Frame, Hud
from across_dimensions.render.context import Offscreen
from across_dimensions.render.passes import PASSES, PassProfile
from across_dimensions.render.renderer import Renderer
from across_dimensions.world.geometry import box_trimesh

W, H = 160, 90


def _frame() -> Frame:
    cam = Camera3(np.array([0.0, 1.6, -6.0]))
    # A wall filling the view and a floor under it: 24 triangles, half of them facing away.
    wall = box_trimesh((0.0, 2.0, 4.0), (40.0, 8.0, 1.0), (0.6, 0.6, 0.7, 1.0))
    floor = box_trimesh((0.0, -0.5, 0.0), (40.0, 1.0, 40.0), (0.5, 0.5, 0.5, 1.0))
    return Frame(
        cam,
        [Drawable("static", 0, wall, outside_only=True), Drawable("floor", 0, floor, style="floor", outside_only=True)],
        hud=Hud(crosshair=False),
        sky="dome",
    )


@pytest.mark.gl
def test_profile_charges_each_pass_and_draws_the_same_picture(gl_ctx):
    target = Offscreen(gl_ctx, W, H)
    renderer = Renderer(gl_ctx)
    try:
        frame = _frame()
        target.use()
        renderer.draw(frame, hud=False)
        plain = target.read_rgb()
        profile = renderer.profile = PassProfile(gl_ctx, W * H)
        profile.start()
        renderer.draw(frame, hud=False)
        profile.stop()
        renderer.profile = None
        assert np.array_equal(target.read_rgb(), plain)
        rows = {r["pass"]: r for r in profile.rows()}
        assert list(rows) == list(PASSES)
        # Two boxes, twelve triangles each, go through the pre-pass and the shading pass.
        assert rows["scenery"]["triangles"] == rows["prepass"]["triangles"] == 24
        # Wall and floor cover the view, each pixel shaded about once (the pre-pass hides the rest).
        assert 0.5 < rows["scenery"]["overdraw"] <= 1.05
        assert rows["matter"]["triangles"] == rows["ghosts"]["triangles"] == 0
        assert all(r["ms"] >= 0.0 for r in rows.values())
    finally:
        renderer.release()
        target.release()
