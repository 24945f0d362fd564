"""The sci-fi look: palettes, the sky dome, fog toward it, panelled scenery and the w cue of
4D matter, drawn offscreen and judged from pixels; and what the game hands the renderer for it."""

from __future__ import annotations

from pathlib import Path

import moderngl
import numpy as np
import pytest
from conftest import per_level, standing_frames

from across_dimensions.core.mesh import TriMesh3
from across_dimensions.game.actions import Actions
from across_dimensions.game.frame import Camera3, Drawable, Frame, Hud
from across_dimensions.game.occlusion import SKY_ROWS
from across_dimensions.render import materials
from across_dimensions.render.context import Offscreen, RenderError
from across_dimensions.render.demo import box_mesh, plane_mesh
from across_dimensions.render.mesh_cache import faceted
from across_dimensions.render.renderer import Renderer
from across_dimensions.render.shaders import PROGRAMS, program_source
from across_dimensions.render.sky import (
    FINE_CELLS_PIXELS,
    SCREEN_TRIANGLE,
    build_dome,
    gradient,
    open_sky,
    open_triangles,
)
from across_dimensions.world.resources import level_files

LEVELS = Path(__file__).resolve().parent.parent / "levels"
W, H = 320, 180


@pytest.fixture
def target(gl_ctx):
    t = Offscreen(gl_ctx, W, H)
    t.use()
    yield t
    t.release()


@pytest.fixture
def renderer(gl_ctx):
    r = Renderer(gl_ctx)  # the sci-fi look is the default
    yield r
    r.release()


def draw(renderer, target, frame) -> np.ndarray:
    renderer.draw(frame, hud=False)
    return target.read_rgb().astype(float)


def luminance(img: np.ndarray) -> np.ndarray:
    return img @ np.array([0.2126, 0.7152, 0.0722])


#: A palette without the dome's features, so pixels can be compared with the gradient alone.
PLAIN_SKY = dict(nebula_a=(0, 0, 0), nebula_b=(0, 0, 0), star=(0, 0, 0), sun=(0, 0, 0), planet=(0, 0, 0))


# ------------------------------------------------------------------ palettes
def test_palettes_name_every_colour_and_reject_bad_ones():
    for name in materials.PALETTES:
        assert set(materials.palette(name)) == set(materials.DEFAULT), name
    p = materials.palette("default", trim=(1.0, 0.0, 0.0))
    assert p["trim"] == (1.0, 0.0, 0.0) and materials.DEFAULT["trim"] != p["trim"]
    with pytest.raises(materials.PaletteError, match="'nope'"):
        materials.palette("nope")
    with pytest.raises(materials.PaletteError, match="'glow'"):
        materials.palette("default", glow=(1, 1, 1))
    with pytest.raises(materials.PaletteError, match="three numbers in 0-1"):
        materials.palette("default", trim=(1.0, 2.0, 0.0))


def test_colorblind_palette_keeps_ana_and_kata_apart_in_lightness():
    # Lightness survives every kind of colour blindness; hue may not.
    p = materials.palette("colorblind")
    la, lk = (float(np.dot(p[k], [0.2126, 0.7152, 0.0722])) for k in ("ana", "kata"))
    assert abs(la - lk) > 0.15, (la, lk)


def test_unknown_look_is_a_render_error(gl_ctx):
    with pytest.raises(RenderError, match="unknown look 'neon'"):
        Renderer(gl_ctx, look="neon")


# ------------------------------------------------------------------------ sky
def test_dome_geometry_is_finite_and_coloured_by_the_gradient():
    p = materials.palette()
    verts, behind, front, star_first = build_dome(p, (0.4, 1.0, 0.25))
    assert verts.dtype == np.float32 and verts.shape[1] == 7 and np.isfinite(verts).all()
    assert np.allclose(np.linalg.norm(verts[:, :3], axis=1), 1.0, atol=1e-5)  # directions
    assert behind.max() < star_first and front.max() < star_first <= len(verts)
    # The gradient: zenith straight up, horizon level, ground below.
    d = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    assert np.allclose(gradient(d, p), [p["sky_zenith"], p["sky_horizon"], p["sky_ground"]])


@pytest.mark.gl
def test_sky_dome_is_a_gradient_behind_the_scene(gl_ctx, target, renderer):
    renderer.palette = materials.palette("default", **PLAIN_SKY)
    p = renderer.palette
    # Looking away from the sun and the planet (-z), level with the horizon.
    cam = Camera3(position=np.zeros(3), yaw=np.pi, fov_y_deg=90.0)
    img = draw(renderer, target, Frame(cam, hud=Hud(crosshair=False), sky="dome"))
    horizon = np.round(np.array(p["sky_horizon"]) * 255)
    assert np.abs(img[H // 2, W // 2] - horizon).max() <= 3, (img[H // 2, W // 2], horizon)
    # Not one colour: the top row (45 degrees up) is nearer the zenith than the horizon is.
    top = np.round(gradient(np.array([0.0, 1.0, -1.0]) / np.sqrt(2), p) * 255)
    assert np.abs(img[0, W // 2] - top).max() <= 4, (img[0, W // 2], top)
    assert np.abs(img[0, W // 2] - img[H // 2, W // 2]).max() > 10
    # Scene geometry covers it: a near cube in the middle is drawn, the sky stays around it.
    cube = Drawable("c", 0, box_mesh((0.0, 0.0, -3.0), (1.0, 1.0, 1.0), (0.9, 0.2, 0.1, 1.0)))
    img2 = draw(renderer, target, Frame(cam, [cube], hud=Hud(crosshair=False), sky="dome"))
    assert img2[H // 2, W // 2, 0] > img2[H // 2, W // 2, 2] + 40  # red cube, not blue sky
    assert np.abs(img2[2, 2] - img[2, 2]).max() <= 1


@pytest.mark.gl
def test_a_dome_frame_writes_every_pixel_without_clearing_its_colour(gl_ctx, target, renderer):
    """With the dome, the colour is not cleared (the sky shades every pixel the scene leaves):
    a frame drawn over a framebuffer full of a marker colour is the frame drawn over a cleared
    one, to the bit."""
    cam = Camera3(position=np.array([0.0, 0.0, 0.0]), yaw=np.pi, pitch=0.2, fov_y_deg=70.0)
    cubes = [
        Drawable(f"c{i}", 0, box_mesh((x, 0.0, -4.0 - i), (1.0, 1.0, 1.0), (0.9, 0.2, 0.1, 1.0)))
        for i, x in enumerate((-1.5, 0.0, 1.5))
    ]  # boxes behind boxes: the pre-pass's depth decides which one is shaded
    frame = Frame(cam, cubes, hud=Hud(crosshair=False), sky="dome")
    target.fbo.clear(0.0, 0.0, 0.0, 1.0)
    clean = draw(renderer, target, frame)
    target.fbo.clear(1.0, 0.0, 1.0, 0.5)  # magenta, half transparent: left anywhere, it shows
    over = draw(renderer, target, frame)
    assert np.array_equal(over, clean)
    assert (target.read_rgba()[..., 3] == 255).all()  # every pixel written, opaque
    assert renderer.stats.depth_calls > 0 and (clean[..., 0] > clean[..., 2] + 40).any()  # cubes drawn


def test_color_writes_turn_on_and_off_at_once(gl_ctx, target):
    """A single-attachment framebuffer's colour mask, set through moderngl, takes effect at the
    next clear or use only: :func:`color_writes` applies it at once, both ways."""
    from across_dimensions.render.context import color_writes

    prog = gl_ctx.program(
        vertex_shader="#version 330\nvoid main() { gl_Position = vec4(vec2(gl_VertexID == 1 ? 3.0 : -1.0, "
        "gl_VertexID == 2 ? 3.0 : -1.0), 0.0, 1.0); }",
        fragment_shader="#version 330\nout vec4 f; void main() { f = vec4(0.0, 1.0, 0.0, 1.0); }",
    )
    vao = gl_ctx.vertex_array(prog, [])
    fbo = target.fbo
    gl_ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
    fbo.clear(1.0, 0.0, 0.0, 1.0)
    color_writes(fbo, False)
    vao.render(moderngl.TRIANGLES, vertices=3)
    assert tuple(target.read_rgb()[H // 2, W // 2]) == (255, 0, 0)  # nothing written
    fbo.clear(0.0, 0.0, 1.0, 1.0)  # a clear under the mask: the colour stays
    color_writes(fbo, True)
    vao.render(moderngl.TRIANGLES, vertices=3)
    assert tuple(target.read_rgb()[H // 2, W // 2]) == (0, 255, 0)  # written again
    vao.release()
    prog.release()


@pytest.mark.gl
def test_sky_has_stars(gl_ctx, target, renderer):
    cam = Camera3(position=np.zeros(3), yaw=np.pi, pitch=0.9, fov_y_deg=90.0)
    img = draw(renderer, target, Frame(cam, hud=Hud(crosshair=False), sky="dome"))
    lum = luminance(img)
    # Points far brighter than the sky around them, a pixel or two each.
    bright = lum > np.median(lum) + 60
    assert 50 < bright.sum() < 0.05 * lum.size, bright.sum()


def test_the_sky_rectangles_become_triangles_on_the_screen():
    assert open_triangles(None, 16 / 9) is SCREEN_TRIANGLE
    rects = np.array([[-3.0, -1.0, 3.0, -0.5], [-5.0, 0.0, -4.5, 0.5], [0.5, 0.5, 1.0, 1.0]])
    tri = open_triangles(rects, 2.0).reshape(-1, 6, 2)
    # The first clipped to the screen's width, the second off the screen, the third halved in x.
    assert len(tri) == 2
    assert np.allclose(tri[0].min(axis=0), [-1.0, -1.0]) and np.allclose(tri[0].max(axis=0), [1.0, -0.5])
    assert np.allclose(tri[1].min(axis=0), [0.25, 0.5]) and np.allclose(tri[1].max(axis=0), [0.5, 1.0])
    # Each rectangle two counter-clockwise triangles covering it, half each.
    for quad in tri:
        for a, b, c in (quad[:3], quad[3:]):
            (ux, uy), (vx, vy) = b - a, c - a
            assert ux * vy - uy * vx > 0
    assert len(open_triangles(np.zeros((0, 4)), 1.0)) == 0
    # Rectangles holding most of the screen: the screen's one triangle costs less than their edges.
    most = np.array([[-2.0, -1.0, 2.0, 0.6]])  # 80 %
    assert open_triangles(most, 2.0) is SCREEN_TRIANGLE
    assert len(open_triangles(most * [1, 1, 1, 0.5], 2.0)) == 6


@pytest.mark.gl
def test_the_sky_over_rectangles_is_the_whole_sky_there_and_nothing_elsewhere(gl_ctx, monkeypatch):
    """Drawn over rectangles, the sky's pixels are those of the sky drawn over the whole view, in
    a viewport anywhere in its framebuffer, but for a few a texel apart (a direction interpolated
    over other triangles may differ in its last bit); outside them nothing is written."""
    from across_dimensions.render import renderer as renderer_module

    cam = Camera3(position=np.zeros(3), yaw=2.5, pitch=0.6, fov_y_deg=70.0)
    renderer = Renderer(gl_ctx)
    whole = Frame(cam, hud=Hud(crosshair=False), sky="dome")
    parts = Frame(cam, hud=Hud(crosshair=False), sky="dome")
    rects = np.array([[-2.0, -1.0, -0.2, -0.3], [0.1, 0.2, 0.9, 0.8]])
    monkeypatch.setattr(renderer_module, "open_sky", lambda frame, w, h: rects if frame is parts else None)
    with Offscreen(gl_ctx, 2 * W, H) as t:
        t.use()
        for frame, x in ((whole, 0), (parts, W)):  # the left half, then the right half
            renderer.draw(frame, (x, 0, W, H), hud=False)
        img = t.read_rgb().astype(int)
    renderer.release()
    left, right = img[:, :W], img[:, W:]
    # Which pixels the rectangles hold (pixel centres, rows from the top; x in units of the height).
    x = ((np.arange(W) + 0.5) / W * 2.0 - 1.0) * (W / H)
    y = 1.0 - (np.arange(H) + 0.5) / H * 2.0
    inside = np.zeros((H, W), bool)
    for x0, y0, x1, y1 in rects:
        inside |= ((x0 < x) & (x < x1))[None, :] & ((y0 < y) & (y < y1))[:, None]
    assert inside.sum() > 0.1 * inside.size
    assert (right[inside] != left[inside]).any(axis=1).sum() <= 0.002 * inside.sum()
    assert (right[~inside] == 0).all()  # the offscreen target starts black: never written
    assert (left.sum(axis=2) > 0).all()


def test_large_views_test_the_sky_in_fine_cells_small_ones_in_three_and_wide_ones_not_at_all():
    # Looking along +z (the view's x is the world's) at a wall over the left of the view: world
    # x < 1 at z = 5, the view's x < 0.2 in its units.
    cam = Camera3(position=np.zeros(3), yaw=0.0, fov_y_deg=90.0, far=100.0)
    frame = Frame(cam, sky="dome", sky_boxes=np.array([[[-100.0, -100.0, 5.0], [1.0, 100.0, 6.0]]]))
    assert open_sky(Frame(cam, sky="dome"), 1280, 720) is None  # no boxes: anywhere
    fine, coarse = open_sky(frame, 1280, 720), open_sky(frame, 640, 360)
    assert FINE_CELLS_PIXELS > 640 * 360
    # Fine cells leave the sky from the first cell wholly right of the wall's edge.
    assert len(fine) == 1 and np.allclose(fine[0, 1:], [-1.0, 3.0, 1.0])
    assert 0.2 - 2.0 / SKY_ROWS < fine[0, 0] <= 0.2
    # Three cells: the middle one (x in -1..1) is not wholly covered, so the sky may show from x = -1.
    assert len(coarse) == 1 and np.allclose(coarse[0], [-1.0, -1.0, 3.0, 1.0])
    # A window wider than a frame is made for: its sides were never tested, the sky is anywhere.
    assert open_sky(frame, 4 * 720, 720) is None


@pytest.mark.gl
def test_sky_shows_the_sun_where_the_light_comes_from_and_is_baked_once(gl_ctx, renderer):
    """The sky is looked up by direction: the sun's disc is at the centre of a view aimed along
    the key light, at any size and aspect; the dome is drawn into its cube map once, not again
    for a smaller view in between (the picture in picture) nor for the same view again."""
    light = np.array([0.4, 1.0, 0.25]) / np.linalg.norm([0.4, 1.0, 0.25])
    yaw, pitch = np.arctan2(light[0], light[2]), np.arcsin(light[1])
    cam = Camera3(position=np.array([3.0, 1.0, -2.0]), yaw=yaw, pitch=pitch, fov_y_deg=60.0)
    frame = Frame(cam, hud=Hud(crosshair=False), sky="dome", light_dir=tuple(light))
    for size in [(320, 180), (160, 160), (320, 180), (96, 54)]:
        with Offscreen(gl_ctx, *size) as t:
            t.use()
            img = draw(renderer, t, frame)
        w, h = size
        centre = luminance(img[h // 2 - 1 : h // 2 + 1, w // 2 - 1 : w // 2 + 1]).min()
        # The sun's disc is white hot; a tenth of the view away, the sky is far darker.
        assert centre > 230, (size, centre)
        assert luminance(img[h // 2, w // 2 + max(4, w // 10)]) < centre - 40
    assert renderer._sky.builds == 1


@pytest.mark.gl
def test_fog_fades_far_things_into_the_sky_behind_them(gl_ctx, target, renderer):
    renderer.palette = materials.palette("default", **PLAIN_SKY)
    cam = Camera3(position=np.zeros(3), yaw=np.pi, fov_y_deg=90.0)

    def centre(z):
        cube = Drawable(f"c{z}", 0, box_mesh((0.0, 0.0, z), (1.0, 1.0, 1.0), (0.9, 0.2, 0.1, 1.0)))
        return draw(renderer, target, Frame(cam, [cube], hud=Hud(crosshair=False), sky="dome"))[H // 2, W // 2]

    sky = np.round(np.array(renderer.palette["sky_horizon"]) * 255)
    near, far = centre(-3.0), centre(-150.0)
    assert np.abs(near - sky).max() > 30
    assert np.abs(far - sky).max() < 8, (far, sky)


def test_scene_fragment_shaders_read_no_uniforms(gl_ctx):
    # llvmpipe reads a uniform in a fragment shader lane by lane, with a bounds check (about
    # 0.25 ms of CPU per component over a full 1280x720 view): what is the same for every
    # pixel reaches the fragment shader as a flat input from the vertex shader instead.
    for look in materials.LOOKS:
        for name in PROGRAMS:
            for flat_normals, per_face in ((False, False), (True, False), (False, True)):
                vs, fs = program_source(name, look, flat_normals=flat_normals, faceted=per_face)
                assert "uniform " not in fs, (name, look)
                gl_ctx.program(vertex_shader=vs, fragment_shader=fs).release()


@pytest.mark.gl
@pytest.mark.parametrize("style", ["solid", "ghost", "glow"])
def test_a_mesh_without_normals_is_lit_by_its_faces_as_one_with_them(gl_ctx, target, style):
    """A mesh whose normals are zero (a frustum projection's) is drawn by its style's program
    for flat normals, which takes each face's normal from the screen: it must look like the
    same mesh carrying its faces' normals, drawn by the program that reads them (which never
    builds the other)."""
    box = box_mesh((1.0, 0.8, 0.7))
    bare = TriMesh3(box.vertices, box.faces, None, box.colors)
    cam = Camera3(position=np.array([1.1, 1.3, -2.2]), yaw=-0.45, pitch=-0.45)
    images = {}
    for name, mesh in (("normals", box), ("none", bare)):
        r = Renderer(gl_ctx)
        frame = Frame(cam, [Drawable("box", 0, mesh, style=style)], hud=Hud(crosshair=False), sky_color=(0.1, 0.1, 0.1))
        images[name] = draw(r, target, frame)
        assert (style + "/flat" in r._programs) == (name == "none")
        r.release()
    lit = np.abs(images["normals"] - 0.1 * 255).max(axis=2) > 30
    assert lit.mean() > 0.05, "the box is not in view"
    diff = np.abs(images["normals"] - images["none"]).max(axis=2)
    # The same light on every face; only pixels along the faces' edges may differ.
    assert diff.mean() < 0.5 and (diff > 8).mean() < 0.005, (diff.mean(), (diff > 8).mean())


def _smooth(mesh: TriMesh3) -> TriMesh3:
    """``mesh`` with each vertex's normal pulled a little toward the box's centre direction:
    the same surface, no longer one normal a triangle."""
    n = mesh.normals + 0.3 * mesh.vertices / np.linalg.norm(mesh.vertices, axis=1, keepdims=True)
    return TriMesh3(mesh.vertices, mesh.faces, n / np.linalg.norm(n, axis=1, keepdims=True), mesh.colors)


def test_faceted_meshes_are_those_of_one_normal_a_triangle():
    box = box_mesh((1.0, 0.8, 0.7))
    assert faceted(np.asarray(box.normals, np.float32), np.asarray(box.faces))
    smooth = _smooth(box)
    assert not faceted(np.asarray(smooth.normals, np.float32), np.asarray(smooth.faces))


@pytest.mark.gl
@pytest.mark.parametrize("style", ["solid", "floor", "hyper"])
def test_a_faceted_mesh_looks_the_same_lit_per_face(gl_ctx, target, style):
    """The level's boxes (one normal a triangle) are drawn by the program that works out per
    vertex what depends on the normal alone (the side facing the eye, the panels' plane, the
    ambient and diffuse light): the picture must be the one the per-pixel program draws, seen
    from outside and from inside (two-sided lighting), and a mesh whose normals vary over its
    triangles keeps the per-pixel program. ``hyper``: 4D matter (a section of a 4D world), with
    its w bands and lattice."""
    box = box_mesh((0.0, 0.0, 0.0), (6.0, 3.0, 5.0), (0.55, 0.6, 0.7, 1.0))
    w_offset = 0.45 if style == "hyper" else None

    def drawable(key, mesh):
        return Drawable(key, 0, mesh, style="solid" if style == "hyper" else style, w_offset=w_offset)

    views = [
        Camera3(position=np.array([4.1, 2.3, -6.2]), yaw=-0.6, pitch=-0.3),
        Camera3(position=np.array([0.4, 0.2, 0.3]), yaw=2.2, pitch=0.2),  # inside: its inner faces
        Camera3(position=np.array([-7.0, 0.5, 1.0]), yaw=1.4, pitch=-0.05),
    ]
    r = Renderer(gl_ctx)
    try:
        for cam in views:
            drawables = [drawable("box", box)]
            frame = Frame(cam, drawables, hud=Hud(crosshair=False), sky_color=(0.1, 0.1, 0.1))
            per_face = draw(r, target, frame)
            assert style + "/faceted" in r._programs
            r.meshes.meshes["box"].faceted = False  # the per-pixel program
            per_pixel = draw(r, target, frame)
            r.meshes.meshes["box"].faceted = True
            assert (np.abs(per_pixel - 0.1 * 255).max(axis=2) > 30).mean() > 0.1, "the box is not in view"
            diff = np.abs(per_face - per_pixel).max(axis=2)
            assert diff.max() <= 4 and (diff > 2).mean() < 1e-3, (diff.max(), (diff > 2).mean())
        smooth = Renderer(gl_ctx)
        frame = Frame(views[0], [drawable("s", _smooth(box))], hud=Hud(crosshair=False))
        draw(smooth, target, frame)
        assert not smooth.meshes.meshes["s"].faceted and style + "/faceted" not in smooth._programs
        smooth.release()
        flat_look = Renderer(gl_ctx, look="flat")  # no panels there: nothing to work out per face
        draw(flat_look, target, Frame(views[0], [drawable("box", box)], hud=Hud(crosshair=False)))
        assert not any(name.endswith("/faceted") for name in flat_look._programs)
        flat_look.release()
    finally:
        r.release()


@pytest.mark.gl
def test_the_levels_boxes_look_the_same_lit_per_face(gl_ctx):
    """Crossfire's and the Tumbling Hall's scenery from standing points over their floors (walls
    close up, the floor, 4D matter in front), drawn with the boxes' faceted program and with the
    per-pixel one: the same picture to the rounding."""
    target = Offscreen(gl_ctx, 320, 180)
    r = Renderer(gl_ctx)
    try:
        for level, pose, frame in standing_frames(("11_crossfire", "03_tumbling_hall")):
            target.use()
            r.draw(frame, hud=False)
            boxes = [gm for gm in r.meshes.meshes.values() if gm.faceted]
            assert {"static", "floor"} <= {gm.key for gm in boxes}
            per_face = target.read_rgb().astype(int)
            for gm in boxes:
                gm.faceted = False
            r.draw(frame, hud=False)
            for gm in boxes:
                gm.faceted = True
            diff = np.abs(per_face - target.read_rgb()).max(axis=2)
            assert diff.max() <= 4 and (diff > 2).mean() < 1e-3, (level, pose, diff.max())
    finally:
        r.release()
        target.release()


# ------------------------------------------------------------------ scenery
def _row_contrast(img: np.ndarray, row: int) -> float:
    r = img[row].sum(axis=1)
    return float(np.abs(r[1:-1] - 0.5 * (r[:-2] + r[2:])).max())


@pytest.mark.gl
def test_scifi_scenery_is_panelled_and_the_flat_look_is_not(gl_ctx, target):
    cam = Camera3(position=np.array([0.3, 1.6, 0.2]), pitch=-0.5)
    frame = Frame(cam, [Drawable("f", 0, plane_mesh(30.0))], hud=Hud(crosshair=False))
    contrast = {}
    for look in materials.LOOKS:
        r = Renderer(gl_ctx, look=look)
        contrast[look] = _row_contrast(draw(r, target, frame), int(H * 0.85))
        r.release()
    # Lighting is smooth; panel seams are not.
    assert contrast["scifi"] > 20 and contrast["flat"] < 8, contrast


@pytest.mark.gl
@pytest.mark.parametrize("elevation", [0.45, 1.0])
def test_the_suns_highlight_lies_where_a_mirror_in_the_floor_would_show_the_sun(gl_ctx, target, elevation):
    """The sun's specular highlight on a flat floor peaks where the sun's reflection reaches the
    eye: at ``eye - h (L / L.y)`` projected onto the floor, for an eye ``h`` above it. Two
    pictures with the sun at one height, ahead and behind, differ only by the highlight."""
    h = 2.0
    ahead = np.array([0.0, elevation, 1.0]) / np.hypot(elevation, 1.0)
    mirror = np.array([0.0, 0.0, h * ahead[2] / ahead[1]])  # the reflection's point on the floor
    cam = Camera3(position=np.array([0.0, h, 0.0]), pitch=-float(np.arctan2(h, mirror[2])))
    r = Renderer(gl_ctx, fog_density=0.0, look="flat")  # one colour, no fog: the light alone
    floor = [Drawable("f", 0, plane_mesh(60.0, color=(0.3, 0.3, 0.3, 1.0)))]
    shots = [
        luminance(draw(r, target, Frame(cam, floor, hud=Hud(crosshair=False), light_dir=tuple(sun))))
        for sun in (ahead, ahead * [1.0, 1.0, -1.0])
    ]
    r.release()
    spec = shots[0] - shots[1]
    top = spec.max()
    ys, xs = np.nonzero(spec >= 0.9 * top)  # the peak's pixels (flat where the colour saturates)
    assert top > 12.0, top  # a highlight...
    assert abs(xs.mean() - W / 2) <= 1.5 and abs(ys.mean() - H / 2) <= 0.03 * H, (xs.mean(), ys.mean())
    assert np.percentile(spec, 50) < 0.25 * top  # ...at the mirror point, and not a sheen


@pytest.mark.gl
def test_walls_carry_an_emissive_trim_near_the_floor(gl_ctx, target, renderer):
    # A wall facing the camera, lit from behind it (the sun does not reach its face).
    cam = Camera3(position=np.array([0.0, 0.4, -2.0]), pitch=-0.1)
    wall = Drawable("w", 0, box_mesh((0.0, 1.5, 0.0), (6.0, 3.0, 0.2), (0.3, 0.3, 0.3, 1.0)))
    frame = Frame(cam, [wall], hud=Hud(crosshair=False), light_dir=(0.0, 0.3, 1.0))
    img = draw(renderer, target, frame)
    col = img[:, W // 3]
    trim = np.asarray(renderer.palette["trim"])
    # The brightest pixel of the column is trim-coloured: blue-green over red.
    y = int(np.argmax(col.sum(axis=1)))
    assert col[y, 2] > col[y, 0] + 60 and col[y].sum() > 2 * np.median(col.sum(axis=1)), (y, col[y])
    assert trim[2] > trim[0]


@pytest.mark.gl
def test_the_palettes_light_colours_are_compiled_in_and_follow_a_new_palette(gl_ctx, target, renderer):
    # The trim's colour is a constant of the scene's programs (an input less per triangle):
    # a new palette builds its own programs, and going back finds the first ones again.
    cam = Camera3(position=np.array([0.0, 0.4, -2.0]), pitch=-0.1)
    wall = Drawable("w", 0, box_mesh((0.0, 1.5, 0.0), (6.0, 3.0, 0.2), (0.3, 0.3, 0.3, 1.0)))
    frame = Frame(cam, [wall], hud=Hud(crosshair=False), light_dir=(0.0, 0.3, 1.0))

    def trim_pixel():
        col = draw(renderer, target, frame)[:, W // 3]
        return col[int(np.argmax(col.sum(axis=1)))]

    default = trim_pixel()
    first = renderer._programs
    renderer.palette = materials.palette("default", trim=(1.0, 0.1, 0.0))
    red = trim_pixel()
    assert red[0] > red[2] + 60 and default[2] > default[0] + 60, (red, default)
    assert renderer._programs is not first
    renderer.palette = materials.palette("default")
    assert np.array_equal(trim_pixel(), default) and renderer._programs is first
    _, fs = program_source("solid", "scifi", renderer.palette)
    assert "uniform " not in fs and "#define TRIM vec3(0.1, 0.75, 1)" in fs


# ------------------------------------------------------------------ the w cue
def _cued(w_offset: float, time: float = 0.0) -> Frame:
    cam = Camera3(position=np.array([0.0, 1.0, -2.2]))
    box = Drawable("x", 0, box_mesh((0.0, 1.0, 0.0), (2.0, 2.0, 2.0), (0.4, 0.5, 0.9, 1.0)), w_offset=w_offset)
    return Frame(cam, [box], hud=Hud(crosshair=False), time=time)


def _transitions(bands: np.ndarray) -> int:
    """Light-dark changes along a column of pixels (band edges): crossings of its mean."""
    hi = bands > bands.mean()
    return int(np.count_nonzero(hi[1:] != hi[:-1]))


@pytest.mark.gl
def test_w_cue_bands_grow_denser_towards_the_edge_of_a_4d_thing(gl_ctx, target, renderer):
    base = luminance(draw(renderer, target, _cued(0.0)))
    column = (slice(H // 8, 7 * H // 8), W // 2 + 7)
    changes = {}
    for off in (0.05, 0.35, 0.95):
        bands = luminance(draw(renderer, target, _cued(off))) - base  # the lattice cancels out
        changes[off] = (np.abs(bands[column]).mean(), _transitions(bands[column]))
    # No bands near the thing's centre along w, then more the farther the slice is from it.
    assert changes[0.05][0] < 1.0 and changes[0.35][0] > 5.0, changes
    assert 2 <= changes[0.35][1] and changes[0.95][1] >= 2 * changes[0.35][1] + 4, changes


@pytest.mark.gl
def test_w_cue_tells_ana_from_kata_without_colour(gl_ctx, target, renderer):
    # Ana and kata in one colour: the patterns must still differ (solid versus dotted bands).
    renderer.palette = materials.palette("default", ana=(0.5, 0.5, 0.5), kata=(0.5, 0.5, 0.5))
    base = luminance(draw(renderer, target, _cued(0.0)))  # the surface without bands
    ana = luminance(draw(renderer, target, _cued(0.8))) - base
    kata = luminance(draw(renderer, target, _cued(-0.8))) - base
    box = (slice(H // 5, 4 * H // 5), slice(W // 3, 2 * W // 3))
    assert np.abs(ana[box]).mean() > 5 and np.abs(kata[box]).mean() > 5  # both banded
    # Along each row inside the box, solid bands are even; dotted bands break up.
    assert kata[box].std(axis=1).mean() > 3 * ana[box].std(axis=1).mean()


@pytest.mark.gl
def test_w_cue_bands_move_with_time(gl_ctx, target, renderer):
    a = luminance(draw(renderer, target, _cued(0.8, time=0.0)))
    b = luminance(draw(renderer, target, _cued(0.8, time=0.4)))
    assert np.abs(a - b).mean() > 1.0


# -------------------------------------------------------- what the game hands over
def test_game_frames_ask_for_the_dome_and_cue_4d_things_by_w():
    from across_dimensions.game.sim import DT, Game
    from across_dimensions.world.level import load_level

    game = Game(load_level(LEVELS / "01_first_steps.toml"))
    frame = game.frame()
    assert frame.sky == "dome"
    worlds = {d.key: d for d in frame.drawables if d.key.startswith("world:")}
    # The blue world is centred on the player's w = 0; the static scenery has no cue.
    assert worlds["world:0"].w_offset == pytest.approx(0.0, abs=1e-9)
    assert next(d for d in frame.drawables if d.key == "static").w_offset is None
    for _ in range(30):
        game.step(Actions(w=1.0))
    w = float(game.player.position[3])
    assert w > 0.2
    frame = game.frame(alpha=0.5)
    assert frame.time == pytest.approx((game.tick + 0.5) * DT)
    cues = {d.key: d.w_offset for d in frame.drawables if d.w_offset is not None}
    # Blue (w = 0, depth 1.6) now lies kata of the slice, green (w = 1.2) ana: sign is the side,
    # size the distance in half depths.
    assert cues["world:0"] == pytest.approx((0.0 - w) / 0.8, rel=0.05)
    assert cues["world:1"] == pytest.approx((1.2 - w) / 0.8, rel=0.05)
    # Entities are drawn in batches: each vertex's colour alpha carries its thing's w offset.
    from across_dimensions.game.entity_sections import ALPHA

    # Seen from past the blue wall, which hides the beacon from the start (game/occlusion.py).
    game.place_player((0.0, float(game.player.position[1]), 5.0, w), 0.0, 0.0)
    frame = game.frame(alpha=0.5)
    solid = next(b for b in frame.batches if b.style == "solid")
    beacon = solid.vertices[:, ALPHA]
    assert len(beacon) and ((beacon > 0.0) & (beacon <= 1.0)).all(), beacon  # the beacon, at w = 0.9


@pytest.mark.gl
@pytest.mark.parametrize("level", per_level(p.stem for p in level_files()))
def test_skipping_inner_faces_of_4d_things_changes_no_pixel_a_player_sees(gl_ctx, level, monkeypatch):
    """Sections of 4D things and the level's boxes are closed surfaces wound counter-clockwise
    from outside, so culling their inner faces must leave every view along the level's replay
    (where a player really stands, looking where they really look) unchanged; if a section or
    a box were open or wound the other way, whole faces would vanish."""
    from across_dimensions.game.playback import play
    from across_dimensions.game.replay import Replay
    from across_dimensions.game.sim import Game
    from across_dimensions.game.systems.ghosts import GhostView
    from across_dimensions.world.level import load_level
    from across_dimensions.world.resources import levels_dir, resolve_level

    replay = Replay.load(levels_dir() / "replays" / f"{level}.json")
    game = Game(load_level(resolve_level(level)), seed=replay.seed)
    # Ghosts show only outer faces on purpose, even around the player (tested on their own).
    game.ghost_view = GhostView(enabled=False)
    target = Offscreen(gl_ctx, 320, 180)
    culled, both = Renderer(gl_ctx), Renderer(gl_ctx)
    monkeypatch.setattr(both, "_cull_inner", lambda outside_only, model=None: gl_ctx.disable(moderngl.CULL_FACE))
    diffs = []

    def compare(g):
        if g.tick % 40:
            return
        frame = g.frame()
        target.use()
        culled.draw(frame, hud=False)
        a = target.read_rgb().astype(np.float64)
        both.draw(frame, hud=False)
        diffs.append((float(np.abs(a - target.read_rgb()).mean()), g.tick))

    try:
        play(replay, game, on_tick=compare, check=False)
    finally:
        culled.release()
        both.release()
        target.release()
    worst, tick = max(diffs)
    assert len(diffs) >= 3
    assert worst < 0.5, f"{level}: mean pixel difference {worst:.2f}/255 at tick {tick} with inner faces culled"


@pytest.mark.gl
def test_depth_prepass_changes_no_pixel(gl_ctx):
    """The 4D things laid down in depth first (the scenery, drawn nearest piece first, needs
    none), then everything shaded with ``<=``: the same picture."""
    from across_dimensions.game.sim import Game
    from across_dimensions.world.level import load_level
    from across_dimensions.world.resources import resolve_level

    game = Game(load_level(resolve_level("03_tumbling_hall")))
    target = Offscreen(gl_ctx, 320, 180)
    with_pass, without = Renderer(gl_ctx), Renderer(gl_ctx)
    without.depth_prepass = False
    depth_calls = 0
    try:
        for yaw in (0.0, 2.0, 4.0):
            game.player.yaw = yaw
            game.reset_interpolation()
            frame = game.frame()
            target.use()
            with_pass.draw(frame, hud=False)
            a = target.read_rgb()
            without.draw(frame, hud=False)
            assert np.array_equal(a, target.read_rgb())
            depth_calls += with_pass.stats.depth_calls
            assert without.stats.depth_calls == 0
        assert depth_calls > 0  # the pre-pass did run
    finally:
        with_pass.release()
        without.release()
        target.release()
