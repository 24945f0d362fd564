"""Tests for across_dimensions.render: offscreen rendering through EGL (llvmpipe is fine).

GL tests are marked ``gl`` and skip with the reason when no EGL context can be
created. Pure-numpy parts (PNG codec, font, HUD layout, edge extraction) run
everywhere.

Golden images live in ``tests/golden/``; regenerate with ``REGENERATE_GOLDEN=1``.
"""

from __future__ import annotations

import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

from across_dimensions.core.edges import feature_edges
from across_dimensions.core.mesh import TriMesh3
from across_dimensions.game.frame import Camera3, Drawable, Frame, Hud
from across_dimensions.render import font
from across_dimensions.render.context import Offscreen, RenderError
from across_dimensions.render.demo import box_mesh, plane_mesh
from across_dimensions.render.hud import MARKER_COLOR, HudMetrics, hud_quads
from across_dimensions.render.png import PngError, decode_png, encode_png, read_png, write_png
from across_dimensions.render.renderer import Renderer

W, H = 160, 90
SKY = (0.05, 0.06, 0.10)
SKY_U8 = np.round(np.array(SKY) * 255).astype(int)


# --------------------------------------------------------------------- fixtures
@pytest.fixture
def target(gl_ctx):
    """A bound 160x90 offscreen framebuffer."""
    t = Offscreen(gl_ctx, W, H)
    t.use()
    yield t
    t.release()


@pytest.fixture
def renderer(gl_ctx):
    r = Renderer(gl_ctx, look="flat")  # the base styles; the sci-fi look has its own tests
    yield r
    r.release()


def assert_no_gl_error(ctx):
    assert ctx.error == "GL_NO_ERROR"


def cube_frame(
    camera_pos=(0.0, 0.0, 0.0),
    cube_center=(0.0, 0.0, 3.0),
    style="solid",
    color=(0.9, 0.2, 0.1, 1.0),
    hud=None,
    revision=0,
    key=None,
) -> Frame:
    """A camera at ``camera_pos`` looking along +z at a unit cube.

    The default key names the mesh's content, so a renderer reused across
    frames within a test re-uploads whenever the cube differs (the contract is
    that a key's mesh changes only with its revision).
    """
    if key is None:
        key = f"cube {cube_center} {color}"
    cam = Camera3(position=np.array(camera_pos, float))
    d = Drawable(key, revision, box_mesh(cube_center, (1.0, 1.0, 1.0), color), style=style)
    return Frame(camera=cam, drawables=[d], hud=hud or Hud(crosshair=False), sky_color=SKY)


def render(renderer, target, frame, hud=False) -> np.ndarray:
    """Draw and read back; the HUD only when asked, so scene checks see only the scene."""
    renderer.draw(frame, hud=hud)
    return target.read_rgb()


def non_sky(img: np.ndarray, tol: int = 6) -> np.ndarray:
    """``(h, w) bool``: pixels that differ from the sky colour."""
    return np.abs(img.astype(int) - SKY_U8).max(axis=2) > tol


# ------------------------------------------------------------- pure numpy parts
def _png_with_filters(img: np.ndarray) -> bytes:
    """Encode with every row using a different PNG filter (1-4), to test the decoder."""
    h, w, c = img.shape
    a = img.astype(np.int32).reshape(h, w * c)
    rows = []
    prev = np.zeros(w * c, np.int32)
    for y in range(h):
        f = 1 + y % 4
        cur = a[y]
        left = np.r_[np.zeros(c, np.int32), cur[:-c]]
        ul = np.r_[np.zeros(c, np.int32), prev[:-c]]
        if f == 1:
            pred = left
        elif f == 2:
            pred = prev
        elif f == 3:
            pred = (left + prev) >> 1
        else:
            p = left + prev - ul
            pa, pb, pc = np.abs(p - left), np.abs(p - prev), np.abs(p - ul)
            pred = np.where((pa <= pb) & (pa <= pc), left, np.where(pb <= pc, prev, ul))
        rows.append(bytes([f]) + ((cur - pred) & 0xFF).astype(np.uint8).tobytes())
        prev = cur

    def chunk(k, d):
        return struct.pack(">I", len(d)) + k + d + struct.pack(">I", zlib.crc32(k + d) & 0xFFFFFFFF)

    hdr = struct.pack(">IIBBBBB", w, h, 8, {3: 2, 4: 6}[c], 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", hdr) + chunk(b"IDAT", zlib.compress(b"".join(rows))) + chunk(b"IEND", b"")
    )


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_png_roundtrip(tmp_path, channels):
    rng = np.random.default_rng(1)
    img = rng.integers(0, 256, (7, 11, channels), dtype=np.uint8)
    write_png(tmp_path / "a.png", img)
    back = read_png(tmp_path / "a.png")
    assert back.shape == (7, 11, channels) and back.dtype == np.uint8
    np.testing.assert_array_equal(back, img)


@pytest.mark.parametrize("channels", [3, 4])
def test_png_decoder_handles_all_filters(channels):
    rng = np.random.default_rng(2)
    img = rng.integers(0, 256, (9, 6, channels), dtype=np.uint8)
    np.testing.assert_array_equal(decode_png(_png_with_filters(img)), img)


def test_png_errors():
    with pytest.raises(PngError, match="signature"):
        decode_png(b"GIF89a....")
    with pytest.raises(TypeError, match="uint8"):
        encode_png(np.zeros((2, 2, 3), np.float32))


def test_font_is_a_real_ttf_with_descenders_accents_and_a_licence():
    f = font.default_font()
    px = font.font_px(2)
    assert font.FONT_FILE.suffix == ".ttf" and "Bitstream Vera" in font.FONT_LICENCE.read_text()
    g, nine, e, e_acute = (f.glyph(ch, px) for ch in "g9e\u00e9")
    # 'g' hangs below the baseline and '9' does not (the old pixel font drew them alike).
    assert g.top + g.h > 2 and nine.top + nine.h <= 1
    # An accent: 'é' reaches higher than 'e', and its bitmap is a different one.
    assert e_acute.top < e.top - 2 and (e_acute.u, e_acute.v) != (e.u, e.v)
    bitmap = lambda gl: f.image[gl.v : gl.v + gl.h, gl.u : gl.u + gl.w]  # noqa: E731
    for ch in "AHWgé€ÅßŁ":
        gl = f.glyph(ch, px)
        assert gl.w > 0 and bitmap(gl).max() == 255, ch  # FreeType drew it, anti-aliased to full at its core
    assert f.missing("Déjà vu, Straße, Łódź, naïve ✓") == set()
    assert f.missing("a\u6f22") == {"\u6f22"}  # a CJK ideograph: not in DejaVu Sans
    # Proportional: 'W' is wider than 'i'; widths add up.
    assert font.text_width("W", 2) > 2 * font.text_width("i", 2)
    assert abs(font.text_width("WiWi", 2) - 2 * font.text_width("Wi", 2)) <= 1


def test_hud_text_reads_back_from_its_quads():
    from across_dimensions.render.hud import quads_text

    quads = hud_quads(Hud(message="Crème brûlée à 4D"), W, H)
    assert "Crèmebrûléeà4D" in quads_text(quads)


def test_hud_layout_marker_moves_with_w():
    m = HudMetrics(W, H)
    y_lo, ok_lo = m.w_marker_y(Hud(w=-1.0))
    y_hi, ok_hi = m.w_marker_y(Hud(w=1.0))
    y_mid, _ = m.w_marker_y(Hud(w=0.0))
    assert ok_lo and ok_hi
    assert y_hi < y_mid < y_lo  # w_max at the top
    assert m.w_marker_y(Hud(w=5.0)) == (y_hi, False)  # clamped, flagged out of range
    q = hud_quads(Hud(fps=60.0, message="hello", paused=True), W, H)
    assert q.shape[1] == 12 and q.dtype == np.float32 and len(q) > 10


def test_feature_edges_of_box_drop_diagonals():
    box = box_mesh()
    e = feature_edges(box.vertices, box.faces)
    # 12 cube edges; the 6 face diagonals are between coplanar triangles.
    assert e.shape == (12, 2) and e.dtype == np.uint32
    p = box.vertices[e]
    lengths = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
    np.testing.assert_allclose(lengths, 1.0, atol=1e-6)
    assert feature_edges(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32)).shape == (0, 2)


def test_render_package_layering():
    """render must not import pyglet (it is the only package that may import moderngl)."""
    code = "import sys, across_dimensions.render; sys.exit(1 if 'pyglet' in sys.modules else 0)"
    assert subprocess.run([sys.executable, "-c", code], cwd=Path(__file__).parents[1]).returncode == 0


def test_the_renderer_loads_no_physics_before_a_level_needs_it():
    """The title and the menus draw with the renderer: loading it must not load the physics
    package (and its kernels' modules), a tenth of a second of the first start."""
    code = "import sys, across_dimensions.render.renderer as r; sys.exit('across_dimensions.physics' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], cwd=Path(__file__).parents[1]).returncode == 0


# ----------------------------------------------------------------------- GL
@pytest.mark.gl
def test_cube_is_drawn_lit_and_on_the_correct_side(gl_ctx, target, renderer):
    img = render(renderer, target, cube_frame())
    assert img.shape == (H, W, 3) and img.dtype == np.uint8
    assert img.std() > 5, "image is blank"
    centre = img[H // 2, W // 2].astype(int)
    assert np.abs(centre - SKY_U8).max() > 40, f"centre pixel {centre} is sky {SKY_U8}"
    assert centre[0] > centre[1] and centre[0] > centre[2], "red cube should look red"
    # The world is left-handed (x right): a cube at +x must appear on the right,
    # i.e. the view's built-in reflection is not drawn as a mirror image.
    img = render(renderer, target, cube_frame(cube_center=(1.2, 0.0, 4.0)))
    cols = np.nonzero(non_sky(img))[1]
    assert cols.mean() > W / 2
    img = render(renderer, target, cube_frame(cube_center=(0.0, 1.0, 4.0)))
    rows = np.nonzero(non_sky(img))[0]
    assert rows.mean() < H / 2  # +y is up, image rows go down
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_cube_moves_when_camera_moves(gl_ctx, target, renderer):
    a = render(renderer, target, cube_frame(camera_pos=(0, 0, 0)))
    b = render(renderer, target, cube_frame(camera_pos=(0.6, 0, 0)))
    assert (a != b).any()
    ca, cb = np.nonzero(non_sky(a))[1].mean(), np.nonzero(non_sky(b))[1].mean()
    assert cb < ca - 5, f"camera moved right, cube should move left ({ca:.1f} -> {cb:.1f})"
    # Closer camera: bigger cube.
    c = render(renderer, target, cube_frame(camera_pos=(0, 0, 1.0)))
    assert non_sky(c).sum() > 1.5 * non_sky(a).sum()
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_uploads_only_on_revision_change_and_release(gl_ctx, target, renderer):
    frame = cube_frame()
    first = render(renderer, target, frame)
    for _ in range(3):
        render(renderer, target, frame)
    assert renderer.stats.uploads == 1
    # Changing the mesh without bumping the revision is ignored (the contract).
    frame.drawables[0].mesh.colors[:] = (0.1, 0.9, 0.1, 1.0)
    np.testing.assert_array_equal(render(renderer, target, frame), first)
    assert renderer.stats.uploads == 1
    frame.drawables[0].revision += 1
    green = render(renderer, target, frame)
    assert renderer.stats.uploads == 2
    c = green[H // 2, W // 2].astype(int)
    assert c[1] > c[0], "new revision should show the new colours"
    # A bigger mesh under the same key grows the buffers in place.
    d = frame.drawables[0]
    two = box_mesh((0, 0, 3), (1, 1, 1))
    big = TriMesh3(
        np.concatenate([two.vertices, two.vertices + [2, 0, 0]]),
        np.concatenate([two.faces, two.faces + len(two.vertices)]),
        np.concatenate([two.normals, two.normals]),
        np.concatenate([two.colors, two.colors]),
    )
    frame.drawables[0] = Drawable(d.key, d.revision + 1, big)
    render(renderer, target, frame)
    assert renderer.stats.uploads == 3 and renderer.stats.triangles == 24
    # The key disappears: its buffers are released.
    frame.drawables.clear()
    img = render(renderer, target, frame)
    assert renderer.stats.releases == 1 and renderer.cached_keys() == []
    assert not non_sky(img).any()
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_offscreen_drawables_are_culled(gl_ctx, target, renderer):
    frame = cube_frame(cube_center=(0, 0, -3))  # behind the camera
    frame.drawables.append(Drawable("side", 0, box_mesh((40, 0, 3)), style="wire"))  # far to the right
    frame.drawables.append(Drawable("seen", 0, box_mesh((0.5, 0, 3)), style="ghost"))
    render(renderer, target, frame)
    assert renderer.stats.culled == 2 and renderer.stats.draw_calls == 1
    # A model matrix moves the bounding sphere with the mesh.
    frame.drawables[0].model = np.diag([1.0, 1.0, -1.0, 1.0])  # mirror z: now in front
    img = render(renderer, target, frame)
    assert renderer.stats.culled == 1 and renderer.stats.draw_calls == 2
    assert non_sky(img)[H // 2, W // 2]
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_empty_meshes_and_empty_frames(gl_ctx, target, renderer):
    frame = Frame(
        Camera3(position=np.zeros(3)), [Drawable("e", 0, TriMesh3.empty())], hud=Hud(crosshair=False), sky_color=SKY
    )
    img = render(renderer, target, frame)
    assert not non_sky(img, tol=1).any()
    assert renderer.stats.draw_calls == 0
    # The mesh becomes non-empty under the same key, then empty again.
    frame.drawables[0] = Drawable("e", 1, box_mesh((0, 0, 3)))
    assert non_sky(render(renderer, target, frame)).any()
    frame.drawables[0] = Drawable("e", 2, TriMesh3.empty(with_depth=True))
    assert not non_sky(render(renderer, target, frame)).any()
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_ghost_blends_between_sky_and_object(gl_ctx, target, renderer):
    solid = render(renderer, target, cube_frame(style="solid"))[H // 2, W // 2].astype(int)
    ghost = render(renderer, target, cube_frame(style="ghost", key="g"))[H // 2, W // 2].astype(int)
    sky = SKY_U8
    # Red channel: the object is far brighter than the sky; a ghost lands between.
    assert sky[0] + 10 < ghost[0] < solid[0] - 10, (sky, ghost, solid)
    # A ghost behind a solid is hidden (depth test); one in front tints it.
    back = cube_frame(color=(0.1, 0.3, 0.9, 1.0))
    back.drawables.append(Drawable("g", 0, box_mesh((0, 0, 6), (3, 3, 1), (0.9, 0.9, 0.1, 1.0)), style="ghost"))
    behind = render(renderer, target, back)[H // 2, W // 2]
    only_solid = render(renderer, target, cube_frame(color=(0.1, 0.3, 0.9, 1.0)))[H // 2, W // 2]
    np.testing.assert_array_equal(behind, only_solid)
    front = cube_frame(color=(0.1, 0.3, 0.9, 1.0))
    front.drawables.append(Drawable("g", 0, box_mesh((0, 0, 2), (0.5, 0.5, 0.5), (0.9, 0.9, 0.1, 1.0)), style="ghost"))
    tinted = render(renderer, target, front)[H // 2, W // 2].astype(int)
    assert tinted[0] > int(only_solid[0]) + 10
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_ghosts_are_sorted_back_to_front(gl_ctx, target, renderer):
    near = Drawable("near", 0, box_mesh((0, 0, 2.5), (0.8, 0.8, 0.2), (1.0, 0.1, 0.1, 1.0)), style="ghost")
    far = Drawable("far", 0, box_mesh((0, 0, 4.0), (2.0, 2.0, 0.2), (0.1, 0.2, 1.0, 1.0)), style="ghost")
    cam = Camera3(position=np.zeros(3))
    a = render(renderer, target, Frame(cam, [near, far], sky_color=SKY))
    b = render(renderer, target, Frame(cam, [far, near], sky_color=SKY))
    # Blending is order dependent; sorting by distance makes list order irrelevant.
    np.testing.assert_array_equal(a, b)
    c = a[H // 2, W // 2].astype(int)
    assert c[0] > c[2], "the near red ghost is blended last, so red dominates"
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_wire_draws_edges_only(gl_ctx, target, renderer):
    solid = non_sky(render(renderer, target, cube_frame(style="solid")))
    wire = non_sky(render(renderer, target, cube_frame(style="wire", key="w")))
    assert 0 < wire.sum() < 0.5 * solid.sum()
    assert not wire[H // 2, W // 2], "no diagonal through the face centre"
    assert renderer.stats.lines == 12
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_floor_style_draws_a_grid(gl_ctx, target, renderer):
    cam = Camera3(position=np.array([0.3, 1.6, 0.2]), pitch=-0.5)
    rows = {}
    for style in ("solid", "floor"):
        frame = Frame(cam, [Drawable("f", 0, plane_mesh(30.0), style=style)], hud=Hud(crosshair=False), sky_color=SKY)
        img = render(renderer, target, frame).astype(float)
        row = img[int(H * 0.85), :, :].sum(axis=1)  # a row across the near floor
        # Local contrast (second difference): lighting is smooth, grid lines are not.
        rows[style] = np.abs(row[1:-1] - 0.5 * (row[:-2] + row[2:])).max()
    assert rows["floor"] > 20 and rows["solid"] < 8, rows
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_fog_fades_distant_objects_into_the_sky(gl_ctx, target, renderer):
    near = render(renderer, target, cube_frame(cube_center=(0, 0, 3)))
    far = render(renderer, target, cube_frame(cube_center=(0, 0, 120)))
    d_near = np.abs(near[H // 2, W // 2].astype(int) - SKY_U8).max()
    d_far = np.abs(far[H // 2, W // 2].astype(int) - SKY_U8).max()
    assert d_far < 0.3 * d_near
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_hud_crosshair_on_empty_scene(gl_ctx, target, renderer):
    frame = Frame(Camera3(position=np.zeros(3)), hud=Hud(crosshair=True), sky_color=SKY)
    img = render(renderer, target, frame, hud=True)
    assert (img[H // 2, W // 2] >= 230).all(), img[H // 2, W // 2]
    assert (img[H // 2, W // 2 + 2] >= 230).all() and (img[H // 2 - 2, W // 2] >= 230).all()
    frame.hud.crosshair = False
    img = render(renderer, target, frame, hud=True)
    assert np.abs(img[H // 2, W // 2].astype(int) - SKY_U8).max() <= 1
    assert_no_gl_error(gl_ctx)


def _marker_rows(img: np.ndarray, color=MARKER_COLOR) -> np.ndarray:
    """Rows of pixels in the right fifth of the image that have the marker's colour."""
    want = np.round(np.array(color[:3]) * 255)
    right = img[:, int(W * 0.8) :, :].astype(int)
    hit = np.abs(right - want).max(axis=2) <= 8
    return np.nonzero(hit)[0]


@pytest.mark.gl
def test_w_indicator_marker_moves(gl_ctx, target, renderer):
    ys = {}
    for w in (-0.9, 0.0, 0.9):
        frame = Frame(Camera3(position=np.zeros(3)), hud=Hud(w=w, w_min=-1, w_max=1, crosshair=False), sky_color=SKY)
        rows = _marker_rows(render(renderer, target, frame, hud=True))
        assert len(rows) > 0, f"no marker drawn for w={w}"
        ys[w] = rows.mean()
    assert ys[0.9] < ys[0.0] - 5 < ys[-0.9] - 10  # higher w, higher marker
    # Out of range: clamped to the end and drawn in the warning colour.
    frame = Frame(Camera3(position=np.zeros(3)), hud=Hud(w=3.0, crosshair=False), sky_color=SKY)
    img = render(renderer, target, frame, hud=True)
    assert len(_marker_rows(img)) == 0
    from across_dimensions.render.hud import MARKER_OUT_OF_RANGE_COLOR

    assert len(_marker_rows(img, MARKER_OUT_OF_RANGE_COLOR)) > 0
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_hud_text_fps_message_and_pause(gl_ctx, target, renderer):
    def shot(**kw):
        return render(
            renderer,
            target,
            Frame(Camera3(position=np.zeros(3)), hud=Hud(crosshair=False, **kw), sky_color=SKY),
            hud=True,
        ).astype(int)

    plain = shot()
    fps = shot(fps=59.7)
    corner = (slice(0, 14), slice(0, 50))
    assert (np.abs(fps[corner] - plain[corner]).max(axis=2) > 60).sum() > 10, "FPS text missing"
    msg = shot(message="LEVEL COMPLETE")
    band = (slice(H // 3 - 10, H // 3 + 10), slice(20, W - 20))
    assert (msg[band].max(axis=2) > 200).sum() > 20, "message text missing"
    paused = shot(paused=True)
    # The overlay darkens the scene: a cube low on the left, away from the PAUSED text.
    lit = render(renderer, target, cube_frame(cube_center=(-1.3, -0.6, 2.5)), hud=True)
    dim = render(
        renderer, target, cube_frame(cube_center=(-1.3, -0.6, 2.5), hud=Hud(paused=True, crosshair=False)), hud=True
    )
    cube = non_sky(lit)
    cube[: H // 2 + 10] = False
    assert cube.sum() > 20
    assert dim[cube].mean() < 0.7 * lit[cube].mean()
    assert (paused[H // 2 - 8 : H // 2 + 8].max(axis=2) > 200).sum() > 20, "PAUSED text missing"
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_viewport_limits_drawing(gl_ctx, target, renderer):
    target.fbo.clear(1.0, 0.0, 1.0, 1.0)
    frame = cube_frame()
    renderer.draw(frame, viewport=(W // 2, 0, W // 2, H))
    img = target.read_rgb()
    assert (img[:, : W // 2] == [255, 0, 255]).all()
    assert not (img[:, W // 2 :] == [255, 0, 255]).all(axis=2).any()
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_msaa_offscreen_and_save_png(gl_ctx, renderer, tmp_path):
    with Offscreen(gl_ctx, W, H, samples=4) as t:
        t.use()
        renderer.draw(cube_frame())
        img = t.save_png(tmp_path / "shot.png")
    np.testing.assert_array_equal(read_png(tmp_path / "shot.png"), img)
    assert non_sky(img).any()
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_bad_input_raises_render_error(gl_ctx, target, renderer):
    with pytest.raises(RenderError, match="positive"):
        Offscreen(gl_ctx, 0, 10)
    with pytest.raises(RenderError, match="unknown style"):
        renderer.draw(cube_frame(style="sparkly"))
    frame = cube_frame()
    frame.drawables.append(frame.drawables[0])
    with pytest.raises(RenderError, match="share the key"):
        renderer.draw(frame)
    bad = box_mesh()
    bad.faces = bad.faces.copy()
    bad.faces[0, 0] = 999
    with pytest.raises(RenderError, match="out of range"):
        renderer.draw(Frame(Camera3(position=np.zeros(3)), [Drawable("bad", 0, bad)]))
    assert_no_gl_error(gl_ctx)


@pytest.mark.gl
def test_renderer_does_not_change_the_frame(gl_ctx, target, renderer):
    frame = cube_frame(hud=Hud(w=0.3, fps=30.0, message="hi"))
    before = (
        frame.camera.position.copy(),
        frame.drawables[0].mesh.vertices.copy(),
        frame.drawables[0].model.copy(),
        repr(frame.hud),
    )
    renderer.draw(frame)
    after = (frame.camera.position, frame.drawables[0].mesh.vertices, frame.drawables[0].model, repr(frame.hud))
    for a, b in zip(before, after):
        np.testing.assert_array_equal(a, b) if isinstance(a, np.ndarray) else (a == b) or pytest.fail(f"{a} != {b}")
    assert_no_gl_error(gl_ctx)


# ------------------------------------------------------------------ golden image
def golden_frame() -> Frame:
    """A fixed small scene covering every style and the HUD."""
    cam = Camera3(position=np.array([2.0, 1.5, -3.4]), yaw=-0.42, pitch=-0.22)
    drawables = [
        Drawable("floor", 0, plane_mesh(40.0), style="floor"),
        Drawable("cube", 0, box_mesh((0, 0.6, 0), (1.2, 1.2, 1.2), (0.85, 0.3, 0.18, 1.0))),
        Drawable("pillar", 0, box_mesh((-2.0, 1.2, 2.5), (0.6, 2.4, 0.6), (0.2, 0.5, 0.85, 1.0))),
        Drawable("ghost", 0, box_mesh((1.5, 0.5, 1.0), (1.0, 1.0, 1.0), (0.4, 0.95, 0.8, 1.0)), style="ghost"),
        Drawable("wire", 0, box_mesh((-1.0, 0.4, -0.8), (0.8, 0.8, 0.8), (1.0, 0.95, 0.4, 1.0)), style="wire"),
    ]
    return Frame(cam, drawables, Hud(w=0.4, fps=60.0, message="GOLDEN"), sky_color=SKY)


@pytest.mark.gl
def test_golden_scene(gl_ctx, renderer, compare_golden):
    with Offscreen(gl_ctx, 192, 108) as t:
        t.use()
        renderer.draw(golden_frame())
        img = t.read_rgb()
    assert_no_gl_error(gl_ctx)
    compare_golden("scene_basic", img)


@pytest.mark.gl
def test_a_new_world_under_old_keys_is_uploaded_after_forget_meshes(gl_ctx, target, renderer):
    """A new level restarts keys and revisions (``static``, 0): forget_meshes makes the
    renderer upload it instead of drawing the old level's mesh."""
    old = cube_frame()
    render(renderer, target, old)
    new = cube_frame()
    d = new.drawables[0]
    new.drawables[0] = Drawable(d.key, d.revision, box_mesh((0, 0, 3), (0.4, 0.4, 0.4)))  # same key, same revision
    stale = render(renderer, target, new)
    np.testing.assert_array_equal(stale, render(renderer, target, old))  # the contract: same revision, no upload
    renderer.forget_meshes()
    fresh = render(renderer, target, new)
    assert non_sky(fresh).sum() < 0.5 * non_sky(stale).sum()  # the small box, not the old cube
    assert renderer.stats.uploads >= 2
