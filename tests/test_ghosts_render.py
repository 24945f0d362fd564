"""Ghost drawing on the GPU: tint and pattern, and the benchmark command (issue 18)."""

import subprocess
import sys

import numpy as np
import pytest

from across_dimensions.game.frame import Camera3, Drawable, Frame
from across_dimensions.game.systems import ghosts
from across_dimensions.render.context import Offscreen, RenderError
from across_dimensions.render.demo import box_mesh
from across_dimensions.render.renderer import Renderer

W, H = 160, 90
GREY = (0.6, 0.6, 0.6, 1.0)


@pytest.fixture
def target(gl_ctx):
    t = Offscreen(gl_ctx, W, H)
    t.use()
    yield t
    t.release()


@pytest.fixture
def renderer(gl_ctx):
    r = Renderer(gl_ctx)
    yield r
    r.release()


def ghost_image(renderer, target, tint, pattern, opacity=2.0):
    """A grey wall filling the view, drawn as a ghost over the sky; float RGB (H, W, 3)."""
    frame = Frame(Camera3(np.array([0.0, 0.0, 0.0])))
    wall = Drawable("g", 0, box_mesh((0, 0, 3), (8, 8, 0.1), GREY), style="ghost", tint=tint, pattern=pattern)
    wall.opacity = opacity
    frame.drawables.append(wall)
    renderer.draw(frame, hud=False)
    return target.read_rgb().astype(np.float64)


@pytest.mark.gl
def test_ana_and_kata_ghosts_differ_in_pattern_as_well_as_hue(renderer, target):
    ana = ghost_image(renderer, target, ghosts.ANA_TINT, ghosts.ANA_PATTERN)
    kata = ghost_image(renderer, target, ghosts.KATA_TINT, ghosts.KATA_PATTERN)
    plain = ghost_image(renderer, target, ghosts.ANA_TINT, "")
    # Hue: ana is warm (red over blue), kata cool (blue over red).
    assert ana[..., 0].mean() > ana[..., 2].mean() + 10
    assert kata[..., 2].mean() > kata[..., 0].mean() + 10
    # Pattern: in grey (what a colour-blind player or a greyscale print sees) both are
    # textured, the plain ghost is not, and the two textures are not the same picture.
    grey = lambda img: img.mean(axis=2)  # noqa: E731
    ga, gk, gp = grey(ana), grey(kata), grey(plain)
    assert ga.std() > 4 * gp.std() + 1 and gk.std() > 4 * gp.std() + 1
    mask_a, mask_k = ga > np.median(ga), gk > np.median(gk)
    assert (mask_a != mask_k).mean() > 0.25
    # Stripes run diagonally: shifting one pixel right and one up keeps a stripe; dots do not line up.
    diag = lambda m: (m[1:, 1:] == m[:-1, :-1]).mean()  # noqa: E731
    assert diag(mask_a) > diag(mask_k)


@pytest.mark.gl
def test_ghost_opacity_fades_toward_the_sky(renderer, target):
    sky = np.array((0.05, 0.06, 0.10)) * 255
    strong = ghost_image(renderer, target, ghosts.ANA_TINT, "", opacity=2.0)
    faint = ghost_image(renderer, target, ghosts.ANA_TINT, "", opacity=0.5)
    d = lambda img: np.abs(img - sky).sum(axis=2).mean()  # noqa: E731
    assert d(strong) > 2 * d(faint) > 0


@pytest.mark.gl
def test_unknown_ghost_pattern_is_refused(renderer, target):
    frame = Frame(Camera3(np.array([0.0, 0.0, 0.0])))
    frame.drawables.append(Drawable("g", 0, box_mesh((0, 0, 3), (1, 1, 1), GREY), style="ghost", pattern="plaid"))
    with pytest.raises(RenderError, match="plaid"):
        renderer.draw(frame, hud=False)


@pytest.mark.gl
def test_bench_ghosts_command_runs(gl_ctx):
    cmd = [sys.executable, "-m", "across_dimensions.bench.ghosts", "--frames", "12"]
    p = subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert "ghosts off" in p.stdout and "ghosts on" in p.stdout and "ms" in p.stdout


def test_bench_ghosts_command_refuses_bad_arguments():
    cmd = [sys.executable, "-m", "across_dimensions.bench.ghosts", "--layers", "3"]
    p = subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--layers" in p.stderr and "Traceback" not in p.stderr


def _section_ghost_coverage(renderer, target, eye, outside_only):
    """Pixels a ghost of a cube (a tesseract's section, wound as the slicer winds it) covers."""
    from across_dimensions.core.section import cross_section
    from across_dimensions.core.shapes import tesseract

    cube = cross_section(tesseract(2.0))
    frame = Frame(Camera3(np.asarray(eye, np.float64), yaw=0.0, pitch=0.0))
    frame.drawables.append(Drawable("g", 0, cube, style="ghost", opacity=2.0, outside_only=outside_only))
    renderer.draw(frame, hud=False)
    with_ghost = target.read_rgb().astype(np.float64)
    renderer.draw(Frame(Camera3(np.asarray(eye, np.float64), yaw=0.0, pitch=0.0)), hud=False)
    sky = target.read_rgb().astype(np.float64)
    return np.abs(with_ghost - sky).max(axis=2) > 2, with_ghost


@pytest.mark.gl
def test_outside_only_ghost_keeps_its_silhouette_and_vanishes_around_the_eye(renderer, target):
    # From outside, culling the inner faces keeps every pixel the two-sided ghost covers
    # (the film is thinner, not smaller): the slicer's winding is counter-clockwise from outside.
    both, img_both = _section_ghost_coverage(renderer, target, (0.0, 0.0, -4.0), False)
    outer, img_outer = _section_ghost_coverage(renderer, target, (0.0, 0.0, -4.0), True)
    assert both.mean() > 0.05
    assert (both == outer).mean() > 0.99
    # One film instead of two: the culled ghost is fainter over the sky.
    assert np.abs(img_outer - img_both)[outer].mean() > 1.0
    # From inside the cube every face is an inner face: nothing is drawn.
    inside, _ = _section_ghost_coverage(renderer, target, (0.0, 0.0, 0.0), True)
    assert inside.mean() < 0.001
    around, _ = _section_ghost_coverage(renderer, target, (0.0, 0.0, 0.0), False)
    assert around.mean() > 0.9
