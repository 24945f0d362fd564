"""The holographic radar: pin layout (pure numpy), drawing (offscreen GL), and views sharing a frame.

Golden images ``radar_1280`` and ``radar_800`` (tests/golden/) show the demo scene with the energy
bar and sixteen pins of every kind at 1280x720 and 800x450; regenerate with ``REGENERATE_GOLDEN=1``
after looking at them.
"""

from __future__ import annotations

import subprocess
import sys

import moderngl
import numpy as np
import pytest

from across_dimensions.bench.hud import demo_pins, hud_demo_frame, random_pins
from across_dimensions.game.frame import (
    RADAR_KINDS,
    Camera3,
    Drawable,
    Frame,
    Hud,
    Radar,
    RadarPin,
)
from across_dimensions.render.context import Offscreen, RenderError
from across_dimensions.render.demo import box_mesh
from across_dimensions.render.hud import HudMetrics
from across_dimensions.render.radar import (
    HEAD_SHAPES,
    HEIGHT_CLAMP,
    RADIUS,
    SHAPES,
    radar_geometry,
    radar_rect_gl,
    radar_view_proj,
    unit_shapes,
)
from across_dimensions.render.radar_disc import DISC_EXTENT, disc_image_size, disc_view_proj
from across_dimensions.render.radar_shapes import disc_vertices
from across_dimensions.render.renderer import Renderer
from across_dimensions.render.shaders import FLAT_VERTEX

SKY = (0.05, 0.06, 0.10)


# ------------------------------------------------------------- pure numpy parts
def test_every_kind_has_its_own_head_shape():
    assert set(HEAD_SHAPES) == set(RADAR_KINDS)
    assert len(set(HEAD_SHAPES.values())) == len(RADAR_KINDS), "two kinds share a shape"
    meshes = unit_shapes()
    heads = [meshes[HEAD_SHAPES[k]] for k in RADAR_KINDS]
    for i in range(len(heads)):
        for j in range(i + 1, len(heads)):
            a, b = heads[i], heads[j]
            assert a.shape != b.shape or not np.allclose(a, b), (RADAR_KINDS[i], RADAR_KINDS[j])
    for name in SHAPES:
        soup = meshes[name]
        assert soup.ndim == 2 and soup.shape[1] == 6 and len(soup) % 3 == 0 and len(soup) > 0
        assert np.isfinite(soup).all()
        if name in HEAD_SHAPES.values():
            assert np.abs(soup[:, :3]).max() <= 1.3


def test_heads_stand_at_height_times_radius_and_stems_reach_them():
    pins = [
        RadarPin(k, 0.1 * i - 0.4, 0.3 - 0.05 * i, h, h == 0.0)
        for i, (k, h) in enumerate(zip(RADAR_KINDS, (0.5, -0.3, 0.0, 0.25, -0.55, 0.1, 0.0, -0.05)))
    ]
    geo = radar_geometry(Radar(range=20.0, w_scale=0.5, pins=pins), px_per_radius=120.0)
    for p, head, shape in zip(pins, geo.heads, geo.shapes):
        np.testing.assert_allclose(head, [p.x * RADIUS, p.height * RADIUS, p.z * RADIUS], atol=1e-9)
        assert shape == HEAD_SHAPES[p.kind]
    assert not geo.clamped.any()
    # Each head instance sits at its pin's head, in the instance list of that pin's shape.
    for p, head in zip(pins, geo.heads):
        rows = geo.instances[HEAD_SHAPES[p.kind]]
        assert np.isclose(rows[:, :3], head, atol=1e-6).all(axis=1).sum() == 1
    # Stems rise from the disc (y = 0) under each head to the head's height: above for ana, below for kata.
    stems = geo.instances["stem"]
    assert len(stems) == len(pins)
    for p, s in zip(pins, stems):
        assert s[1] == 0.0 and np.isclose(s[0], p.x) and np.isclose(s[2], p.z)
        tip = s[1] + s[4]
        assert np.isclose(tip, p.height * RADIUS, atol=2e-4)
        assert np.sign(round(s[4], 6)) == np.sign(p.height) or p.height == 0.0
    # One head instance per pin in all.
    assert sum(len(geo.instances.get(s, [])) for s in set(HEAD_SHAPES.values())) == len(pins)


def test_visible_pins_get_a_ring_on_the_disc():
    pins = [
        RadarPin("crystal", 0.2, 0.3, 0.0, True),
        RadarPin("body", -0.4, 0.1, 0.4, False),
        RadarPin("enemy", 0.5, -0.5, 0.0, True),
    ]
    geo = radar_geometry(Radar(20.0, 1.0, pins))
    rings = geo.instances["seen_ring"]
    assert len(rings) == 2
    np.testing.assert_allclose(rings[:, [0, 2]], [[0.2, 0.3], [0.5, -0.5]], atol=1e-6)
    assert (np.abs(rings[:, 1]) < 0.02).all(), "the ring lies on the disc"
    # Visible heads glow (emission), hidden ones do not.
    assert geo.instances["octahedron"][0, 9] > 0 and geo.instances["cube"][0, 9] == 0
    assert "seen_ring" not in radar_geometry(Radar(20.0, 1.0, pins[1:2])).instances


def test_heights_beyond_the_view_are_clamped_with_an_arrow():
    pins = [
        RadarPin("crystal", 0.0, 0.5, 3.0, False),
        RadarPin("bullet", 0.3, 0.0, -HEIGHT_CLAMP * 2, False),
        RadarPin("body", 0.0, -0.5, HEIGHT_CLAMP * 0.9, False),
    ]
    geo = radar_geometry(Radar(20.0, 1.0, pins))
    assert geo.clamped.tolist() == [True, True, False]
    assert np.isclose(geo.heads[0, 1], HEIGHT_CLAMP * RADIUS) and np.isclose(geo.heads[1, 1], -HEIGHT_CLAMP * RADIUS)
    arrows = geo.instances["arrow"]
    assert len(arrows) == 2
    # Arrows sit beyond their heads and point on: up above the top, down below the bottom.
    up, down = arrows[np.argsort(-arrows[:, 1])]
    assert up[1] > HEIGHT_CLAMP * RADIUS and up[4] > 0
    assert down[1] < -HEIGHT_CLAMP * RADIUS and down[4] < 0


def test_pins_beyond_the_rim_are_pulled_onto_it_and_bad_kinds_refused():
    geo = radar_geometry(Radar(20.0, 1.0, [RadarPin("target", 3.0, 4.0, 0.0, False)]))
    np.testing.assert_allclose(geo.heads[0], [0.6, 0.0, 0.8], atol=1e-9)
    with pytest.raises(RenderError, match="'ghost'.*crystal"):
        radar_geometry(Radar(20.0, 1.0, [RadarPin("ghost", 0.0, 0.0, 0.0, False)]))
    assert radar_geometry(Radar(20.0, 1.0, [])).instances == {}


def test_heads_keep_a_readable_size_on_small_screens():
    pins = [RadarPin("body", 0.0, 0.0, 0.2, False)]
    big = radar_geometry(Radar(20.0, 1.0, pins), px_per_radius=300.0).instances["cube"][0, 3]
    small = radar_geometry(Radar(20.0, 1.0, pins), px_per_radius=40.0).instances["cube"][0, 3]
    assert small * 40.0 >= 5.0 and small > big


@pytest.mark.parametrize("aspect", [0.95, 1.3])
def test_radar_camera_frames_the_disc_and_the_clamp_height(aspect):
    vp, ndc_r = radar_view_proj(aspect)
    ang = np.linspace(0, 2 * np.pi, 64)
    heights = (-HEIGHT_CLAMP, 0, HEIGHT_CLAMP)
    pts = [np.c_[np.cos(ang), np.full_like(ang, y), np.sin(ang), np.ones_like(ang)] for y in heights]
    clip = np.concatenate(pts) @ vp.T
    ndc = clip[:, :3] / clip[:, 3:]
    assert (np.abs(ndc) < 1.0).all(), "disc or clamped pins outside the radar's view"
    assert np.ptp(ndc[:, 0]) > 1.2 or np.ptp(ndc[:, 1]) > 1.7, "the radar uses most of its rectangle"

    # From above and behind: the near rim (z = -1) is lower on screen than the far rim, and up is up.
    def y_of(p):
        c = vp @ np.r_[p, 1.0]
        return c[1] / c[3]

    assert y_of([0, 0, -1]) < y_of([0, 0, 1]) and y_of([0, 0.5, 0]) > y_of([0, 0, 0])
    assert ndc_r > 0


# ---------------------------------------------------------------------- GL parts
@pytest.fixture
def renderer(gl_ctx):
    r = Renderer(gl_ctx, look="flat")  # the radar over the plain look: its goldens stay about the radar
    yield r
    r.release()


def _scene(radar=None):
    frame = hud_demo_frame()
    frame.radar = radar
    return frame


@pytest.mark.gl
@pytest.mark.parametrize("size", [(1280, 720), (320, 180)])
def test_radar_draws_only_in_its_corner(gl_ctx, renderer, size):
    w, h = size
    with Offscreen(gl_ctx, w, h) as t:
        t.use()
        renderer.draw(_scene(None))
        without = t.read_rgb().astype(int)
        renderer.draw(_scene(Radar(30.0, 0.5, demo_pins())))
        with_radar = t.read_rgb().astype(int)
        assert renderer.radar.draw_calls >= 3
    x, y, rw, rh = HudMetrics(w, h).radar_rect()
    changed = np.abs(with_radar - without).max(axis=2) > 8
    inside = changed[y : y + rh, x : x + rw]
    assert inside.mean() > 0.05, "the radar changed too few pixels in its corner"
    outside = changed.copy()
    outside[y : y + rh, x : x + rw] = False
    assert not outside.any(), "the radar drew outside its rectangle"
    assert gl_ctx.error == "GL_NO_ERROR"


@pytest.mark.gl
def test_radar_at_the_render_scale_lands_where_the_full_size_one_does(gl_ctx, renderer):
    """Drawn into the scene at scale 0.5 and upscaled (as the game does on llvmpipe), the radar
    covers the same rectangle as drawn at full size, and its pins are in the same places."""
    w, h = 1280, 720
    frame = _scene(Radar(30.0, 0.5, demo_pins()))
    with Offscreen(gl_ctx, w, h) as t, Offscreen(gl_ctx, w // 2, h // 2) as small:
        t.use()
        renderer.draw(frame, hud=False)
        renderer.draw_radar(frame, t.viewport)
        full = t.read_rgb().astype(int)
        small.use()
        renderer.draw(frame, hud=False)
        plain_small = small.read_rgb().astype(int)
        renderer.draw_radar(frame, t.viewport, scale=0.5)
        halved = small.read_rgb().astype(int)
        t.use()
        renderer.draw(frame, hud=False)
        plain = t.read_rgb().astype(int)
    assert gl_ctx.error == "GL_NO_ERROR"
    x, y, rw, rh = HudMetrics(w, h).radar_rect()
    changed_full = np.abs(full - plain).max(axis=2) > 8
    changed_half = (np.abs(halved - plain_small).max(axis=2) > 8).repeat(2, axis=0).repeat(2, axis=1)
    outside = changed_half.copy()
    outside[y - 1 : y + rh + 1, x - 1 : x + rw + 1] = False
    assert changed_half.mean() > 0.01 and not outside.any(), "the scaled radar left its rectangle"
    # The same pixels change, up to the half-size raster's coarser edges.
    both = changed_full & changed_half
    assert both.sum() > 0.9 * min(changed_full.sum(), changed_half.sum())

    # Pin heads (bright and saturated) in the same places.
    def heads(img):
        return (img.max(axis=2) > 150) & (img.max(axis=2) - img.min(axis=2) > 80)

    hf, hh = heads(full), heads(halved.repeat(2, axis=0).repeat(2, axis=1))
    assert hf.sum() > 50
    # (within a few pixels: the half-size pins keep a minimum size in their own, bigger pixels)
    assert abs(np.argwhere(hf).mean(axis=0) - np.argwhere(hh).mean(axis=0)).max() < 6


@pytest.mark.gl
def test_pins_above_and_below_show_where_expected(gl_ctx, renderer):
    """A lone enemy pin high above the disc lights pixels above the disc's centre; one below, below it."""
    w, h = 640, 360
    rect = radar_rect_gl((0, 0, w, h))
    vp, _ = radar_view_proj(rect[2] / rect[3])

    def screen_y(p):  # pixel row, top-left origin
        c = vp @ np.r_[p, 1.0]
        ndc_y = c[1] / c[3]
        return h - (rect[1] + (ndc_y + 1) / 2 * rect[3])

    def red_rows(height):
        with Offscreen(gl_ctx, w, h) as t:
            t.use()
            frame = Frame(
                Camera3(position=np.zeros(3)),
                hud=Hud(crosshair=False),
                sky_color=SKY,
                radar=Radar(30.0, 1.0, [RadarPin("enemy", 0.0, 0.0, height, False)]),
            )
            renderer.draw(frame)
            img = t.read_rgb().astype(int)
        # Reddish, also when seen through the translucent (blue) disc.
        red = (img[:, :, 0] > 110) & (img[:, :, 0] > img[:, :, 1] + 60) & (img[:, :, 0] > img[:, :, 2] + 45)
        red = red[:, rect[0] : rect[0] + rect[2]]  # the radar's columns only
        # The head is wider than the stem (about 2 px) and the foot.
        return np.flatnonzero(red.sum(axis=1) >= 5)

    up, down = red_rows(0.5), red_rows(-0.5)
    assert len(up) and len(down)
    assert abs(np.median(up) - screen_y([0, 0.5, 0])) < 6
    assert abs(np.median(down) - screen_y([0, -0.5, 0])) < 6
    assert np.median(up) < screen_y([0, 0, 0]) < np.median(down)


def test_disc_image_has_two_texels_per_screen_pixel_within_bounds():
    assert disc_image_size(100.0) == 512  # 2 x 1.2 x 2 x 100 = 480 texels, up to a multiple of 64
    sizes = [disc_image_size(px) for px in (1.0, 50.0, 100.0, 200.0, 1e5)]
    assert sizes == sorted(sizes) and sizes[0] == 128 and sizes[-1] == 2048
    assert all(s % 64 == 0 for s in sizes)


@pytest.mark.gl
def test_disc_image_over_a_colour_equals_its_layers_drawn_one_over_another(gl_ctx, renderer):
    """The disc is drawn as one premultiplied image: over any colour it must give what its
    translucent layers give drawn one by one over that colour (to 8-bit rounding)."""
    radar = renderer.radar
    radar.disc.prepare(100.0)
    image = radar.disc.image
    n = image.size[0]
    back = (0.8, 0.3, 0.1)
    layers = disc_vertices()
    flat_fs = "#version 330\nin vec4 v_color;\nout vec4 f_color;\nvoid main() { f_color = v_color; }\n"
    prog = gl_ctx.program(vertex_shader=FLAT_VERTEX, fragment_shader=flat_fs)
    prog["u_view_proj"].write(np.ascontiguousarray(disc_view_proj().T, np.float32).tobytes())
    vbo = gl_ctx.buffer(layers.tobytes())
    vao = gl_ctx.vertex_array(prog, [(vbo, "3f 4f", "in_pos", "in_color")])
    with Offscreen(gl_ctx, n, n) as t:
        t.use()
        gl_ctx.clear(*back)
        gl_ctx.enable(moderngl.BLEND)
        gl_ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        gl_ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        vao.render(moderngl.TRIANGLES)
        gl_ctx.disable(moderngl.BLEND)
        want = t.read_rgb().astype(int)
    for obj in (vao, vbo, prog):
        obj.release()
    texels = np.frombuffer(image.read(), np.uint8).reshape(n, n, 4).astype(float) / 255.0
    got = texels[:, :, :3] + np.asarray(back) * (1.0 - texels[:, :, 3:4])
    got = np.round(got[::-1] * 255.0).astype(int)  # read_rgb's rows run from the top
    assert np.abs(got - want).max() <= 3
    assert texels[:, :, 3].max() > 0.9 and texels[0, 0, 3] == 0.0  # the rim is there, the corners clear
    assert (texels[:, :, :3] <= texels[:, :, 3:4] + 1e-6).all(), "not premultiplied"
    assert DISC_EXTENT > 1.17  # the forward notch, the outermost piece, fits


@pytest.mark.gl
def test_disc_image_is_drawn_once_and_again_only_for_a_larger_radar(gl_ctx, renderer):
    frame = _scene(Radar(30.0, 0.5, demo_pins()))
    bakes = []
    for w, h in ((1280, 720), (640, 360), (1280, 720), (2560, 1440)):
        with Offscreen(gl_ctx, w, h) as t:
            t.use()
            renderer.draw(frame)
        bakes.append(renderer.radar.disc.bakes)
    assert bakes == [1, 1, 1, 2]


@pytest.mark.gl
def test_backdrop_darkens_the_middle_and_leaves_the_corners_of_the_rectangle(gl_ctx, renderer):
    """The backdrop's glow fades out at 1.05 of the rectangle's half-size: its corners show the
    scene as it was, its middle is darkened towards the backdrop's colour by half."""
    w, h = 1280, 720
    frame = Frame(Camera3(position=np.zeros(3)), hud=Hud(crosshair=False), sky_color=(0.9, 0.9, 0.9))
    with Offscreen(gl_ctx, w, h) as t:
        t.use()
        renderer.draw(frame)
        without = t.read_rgb().astype(int)
        frame.radar = Radar(30.0, 0.5, [])
        renderer.draw(frame)
        with_radar = t.read_rgb().astype(int)
    x, y, rw, rh = HudMetrics(w, h).radar_rect()
    corners = [(y + 1, x + 1), (y + 1, x + rw - 2), (y + rh - 2, x + 1), (y + rh - 2, x + rw - 2)]
    for r, c in corners:
        assert np.abs(with_radar[r, c] - without[r, c]).max() <= 1
    # Just inside the rim of the glow, left of the middle (the disc does not reach out there).
    r, c = y + rh // 2, x + int(rw * 0.03)
    assert with_radar[r, c].sum() < without[r, c].sum()


@pytest.mark.gl
def test_two_hundred_pins_cost_a_handful_of_draw_calls(gl_ctx, renderer):
    with Offscreen(gl_ctx, 640, 360) as t:
        t.use()
        renderer.draw(Frame(Camera3(position=np.zeros(3)), hud=Hud(), radar=Radar(30.0, 0.5, random_pins(200))))
    assert renderer.radar.draw_calls <= len(SHAPES) + 2
    assert sum(len(v) for k, v in renderer.radar.last_geometry.instances.items() if k in HEAD_SHAPES.values()) == 200
    assert gl_ctx.error == "GL_NO_ERROR"


@pytest.mark.gl
def test_second_view_in_a_frame_does_not_evict_or_reupload_the_first(gl_ctx, renderer):
    crate = Drawable("crate", 0, box_mesh((1, 0.5, 1)))
    main = Frame(
        Camera3(position=np.array([0.0, 1.0, -4.0])),
        hud=Hud(),
        sky_color=SKY,
        radar=Radar(30.0, 0.5, demo_pins()),
        drawables=[Drawable("wall", 0, box_mesh((0, 1, 0), (2, 2, 0.3))), crate],
    )
    inset = Frame(
        Camera3(position=np.array([0.0, 6.0, 0.0]), pitch=-1.5),
        sky_color=SKY,
        drawables=[Drawable("map", 0, box_mesh((0, 0, 0), (5, 0.1, 5))), crate],
    )
    with Offscreen(gl_ctx, 320, 180) as t:
        t.use()
        for _ in range(4):
            renderer.draw(main)
            renderer.draw(inset, viewport=(200, 100, 120, 80), hud=False, view="inset")
        # Three distinct keys, each uploaded once; nothing released while both views keep drawing.
        assert renderer.stats.uploads == 3 and renderer.stats.releases == 0
        assert renderer.cached_keys() == ["crate", "map", "wall"]
        # A key only one view still uses stays; a key no view uses goes.
        main.drawables = main.drawables[:1]
        renderer.draw(main)
        renderer.draw(inset, viewport=(200, 100, 120, 80), hud=False, view="inset")
        assert renderer.cached_keys() == ["crate", "map", "wall"] and renderer.stats.uploads == 3
        renderer.forget_view("inset")
        renderer.draw(main)
        assert renderer.cached_keys() == ["wall"] and renderer.stats.releases == 2
        # A view that stops drawing is forgotten after VIEW_TTL draws.
        renderer.draw(inset, viewport=(200, 100, 120, 80), hud=False, view="inset")
        assert renderer.stats.uploads == 5
        for _ in range(Renderer.VIEW_TTL + 1):
            renderer.draw(main)
        assert renderer.cached_keys() == ["wall"]
    assert gl_ctx.error == "GL_NO_ERROR"


@pytest.mark.gl
@pytest.mark.parametrize("size", [(1280, 720), (800, 450)])
def test_golden_radar(gl_ctx, renderer, compare_golden, size):
    w, h = size
    with Offscreen(gl_ctx, w, h) as t:
        t.use()
        renderer.draw(hud_demo_frame())
        img = t.read_rgb()
    assert gl_ctx.error == "GL_NO_ERROR"
    compare_golden(f"radar_{w}", img)


@pytest.mark.gl
def test_bench_hud_command_runs(gl_ctx, tmp_path):
    cmd = [
        sys.executable,
        "-m",
        "across_dimensions.bench.hud",
        "--frames",
        "5",
        "--pins",
        "50",
        "--png",
        str(tmp_path),
    ]
    p = subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "radar of 50 pins" in p.stdout and "ms" in p.stdout
    assert (tmp_path / "radar_1280.png").stat().st_size > 1000 and (tmp_path / "radar_800.png").exists()


def test_bench_hud_command_refuses_bad_arguments():
    p = subprocess.run(
        [sys.executable, "-m", "across_dimensions.bench.hud", "--frames", "many"],
        check=False,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 2 and "--frames" in p.stderr and "Traceback" not in p.stderr
