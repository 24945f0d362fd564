"""The holographic 3D radar: a small 3D view of a translucent disc with pins.

The paper's radar (Cavallo 2021, section 5, Fig. "Across Dimensions"): a disc in the player's x-z
plane, centred on the player and turned with the player's yaw, with every 4D entity in range as a
pin whose altitude is its w offset from the player. A pin on the disc is in the slice now; a pin
above (ana, +w) or below (kata, -w) needs a step along w to reach.

Radar space
-----------
The :class:`~across_dimensions.game.frame.RadarPin` data is already in the radar's frame, in disc
radii, so the radar's 3D scene is fixed: the disc is the unit circle in the x-z plane (x to the
player's right, z ahead, y up), and a fixed camera looks at it from behind and above
(:data:`PITCH_DEG` down). Because the camera never turns relative to the disc, a stem drawn as a
flat quad in the x-y plane always faces it.

Pieces
------
* static (uploaded once): the disc fill, range rings at 1/3, 2/3 and the rim, the two axes, the
  player's view wedge, a forward notch at the rim and the player's chevron at the centre;
* per pin: a foot dot on the disc, a stem from the disc to the head, and a head whose shape
  depends on the kind (:data:`HEAD_SHAPES`), coloured by kind (:data:`KIND_COLORS`); pins whose
  cross-section is visible get a bright ring round the foot and a glowing head; heads beyond
  :data:`HEIGHT_CLAMP` stop there with an arrow pointing on (up or down); the pin a seek heads
  for (``RadarPin.sought``) gets wide bright rings round its head and its foot.

Drawing (:class:`RadarRenderer`): its own programs and buffers, in its own viewport (the corner
rectangle from :meth:`~across_dimensions.render.hud.HudMetrics.radar_rect`), after the main view:
a dark backdrop that also resets the depth in that rectangle (one quad, its glow shaded per
pixel), the opaque pins (one instanced, indexed draw per shape that has instances: at most 14
draw calls in all, however many pins), then the translucent disc with depth writes off, so pins
below it show through tinted and pins above it stand in front. The disc is static: its layers
(fills, rings, axes, wedge, notch, chevron: some 700 triangles) are drawn once into an image,
which each frame lays on one square in the disc's plane. On llvmpipe, which sets up every
triangle on the CPU, that took a quarter off the radar's time at the default render scale.
The main view's buffers are never touched. The HUD then labels the rectangle
(``+w`` above, ``-w`` below, the range in metres).

Colours are display-space RGB (no gamma), like the HUD's.

:func:`radar_geometry` is the pure part (a :class:`Radar` to instance arrays) and is tested
without OpenGL.
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field

import moderngl
import numpy as np

from ..game.frame import RADAR_KINDS, Camera3, Radar
from .context import RenderError
from .gl_math import mat4_bytes
from .hud import HudMetrics
from .palette import current, pin
from .radar_disc import DiscImage
from .radar_shapes import unit_shapes, weld

#: The disc's radius in radar space; pin heights and positions are in these units.
RADIUS = 1.0
#: Heads higher or lower than this many disc radii stop there, with an arrow that shows they go on.
HEIGHT_CLAMP = 0.6
#: The radar camera looks down at the disc by this angle, from behind.
PITCH_DEG = 36.0
FOV_Y_DEG = 32.0
CAMERA_DISTANCE = 4.2
#: A head's half-size in disc radii (bullets are smaller), and its minimum in pixels.
HEAD_SIZE = 0.085
HEAD_MIN_PX = 5.5
STEM_MIN_PX = 1.6
STEM_WIDTH = 0.014

#: Head shape per pin kind: the shape alone tells the kind (colour helps, never alone).
HEAD_SHAPES = {
    "crystal": "octahedron",
    "body": "cube",
    "enemy": "star",
    "bullet": "sphere",
    "target": "torus",
    "camera_focus": "cross",
    "camera_eye": "cone",
    "object": "cube_outline",
}
#: Relative head size per kind.
KIND_SIZE = {"bullet": 0.6, "crystal": 1.1}
#: Display-space RGB per kind in the default palette (the palette in use: :func:`.palette.pin`).
KIND_COLORS = {k: pin(k, "default") for k in RADAR_KINDS}
#: Instanced pieces that are not heads.
PIECES = ("stem", "foot", "seen_ring", "arrow")
#: Every instanced mesh, in draw order.
SHAPES = tuple(dict.fromkeys(HEAD_SHAPES.values())) + PIECES
_HEAD_SHAPE_NAMES = tuple(dict.fromkeys(HEAD_SHAPES.values()))
_KIND_CODE = {k: i for i, k in enumerate(RADAR_KINDS)}
_KIND_SCALE = np.array([KIND_SIZE.get(k, 1.0) for k in RADAR_KINDS], np.float64)
_KIND_SHAPE = np.array([SHAPES.index(HEAD_SHAPES[k]) for k in RADAR_KINDS], np.intp)


@functools.cache
def _kind_rgb(palette: str) -> np.ndarray:
    """Pin colours ``(len(RADAR_KINDS), 3) float64`` of ``palette``, by kind code."""
    return np.array([pin(k, palette) for k in RADAR_KINDS], np.float64)


#: Floats per instance: position xyz | scale xyz | colour rgb, emission.
INSTANCE_FLOATS = 10

BACKDROP_COLOR = (0.0, 0.02, 0.05, 0.5)
#: Rings round the pin a seek heads for.
SOUGHT_COLOR = (1.0, 0.97, 0.55)


@dataclass
class RadarGeometry:
    """What to draw for one :class:`Radar`, as instance arrays (no OpenGL).

    Attributes
    ----------
    instances : dict of str to (n, 10) float32
        Per shape in :data:`SHAPES` (only those with instances): position ``x, y, z`` and scale
        ``sx, sy, sz`` in radar space (the unit shape is scaled, then moved), colour ``r, g, b``
        and emission (0 dull, 1 glowing).
    heads : (p, 3) float64
        Each pin's head centre, in pin order.
    shapes : list of str
        Each pin's head shape, in pin order.
    clamped : (p,) bool
        Heads stopped at :data:`HEIGHT_CLAMP` (they carry an arrow).
    """

    instances: dict[str, np.ndarray] = field(default_factory=dict)
    heads: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    shapes: list[str] = field(default_factory=list)
    clamped: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))


def radar_geometry(radar: Radar, px_per_radius: float = 120.0) -> RadarGeometry:
    """Lay out the pins of ``radar`` as instances of the unit shapes.

    Parameters
    ----------
    radar : Radar
        Read only. Pin ``x, z`` beyond the rim are pulled onto it (the game should not list them).
    px_per_radius : float
        Screen pixels per disc radius, so heads and stems keep a readable minimum size on small
        screens.

    Returns
    -------
    RadarGeometry

    Raises
    ------
    RenderError
        A pin's kind is not one of :data:`~across_dimensions.game.frame.RADAR_KINDS`.
    """
    pins = radar.pins
    n = len(pins)
    geo = RadarGeometry()
    if n == 0:
        return geo
    try:
        code = np.fromiter((_KIND_CODE[p.kind] for p in pins), np.intp, n)
    except KeyError as e:
        raise RenderError(f"radar pin kind {e.args[0]!r} is not one of {', '.join(RADAR_KINDS)}") from None
    x = np.fromiter((p.x for p in pins), np.float64, n)
    z = np.fromiter((p.z for p in pins), np.float64, n)
    h = np.fromiter((p.height for p in pins), np.float64, n)
    seen = np.fromiter((p.visible for p in pins), bool, n)
    r = np.hypot(x, z)
    pull = np.where(r > 1.0, 1.0 / np.maximum(r, 1e-12), 1.0)
    x, z = x * pull * RADIUS, z * pull * RADIUS
    clamped = np.abs(h) > HEIGHT_CLAMP
    y = np.clip(h, -HEIGHT_CLAMP, HEIGHT_CLAMP) * RADIUS
    px = 1.0 / max(float(px_per_radius), 1e-6)  # disc radii per pixel

    color = _kind_rgb(current())[code]
    size = _KIND_SCALE[code] * max(HEAD_SIZE, HEAD_MIN_PX * px)
    emission = np.where(seen, 0.8, 0.0)
    ones = np.ones(n)

    inst: dict[str, np.ndarray] = {}
    heads = np.stack([x, y, z], axis=1)
    head_rows = _rows(heads, size[:, None], color, emission)
    # Group the heads by shape with one stable sort (pins of one kind keep their order).
    shape_code = _KIND_SHAPE[code]
    order = np.argsort(shape_code, kind="stable")
    bounds = np.searchsorted(shape_code[order], np.arange(len(SHAPES) + 1))
    for i, name in enumerate(SHAPES[: len(_HEAD_SHAPE_NAMES)]):
        if bounds[i + 1] > bounds[i]:
            inst[name] = head_rows[order[bounds[i] : bounds[i + 1]]]
    # Stems: a unit quad (x in [-0.5, 0.5], y in [0, 1]) stretched from the disc to the head; a
    # minimum height keeps the scale invertible for the normal.
    stem_w = max(STEM_WIDTH, STEM_MIN_PX * px)
    sy = np.where(np.abs(y) < 1e-4, 1e-4, y)
    disc = np.stack([x, 0 * x, z], 1)
    inst["stem"] = _rows(disc, np.stack([stem_w * ones, sy, ones], 1), 0.75 * color, 0.3 * emission)
    # Feet lie just above the disc so the disc (drawn after, depth-tested) never covers them.
    foot = max(0.028, 2.2 * px)
    inst["foot"] = _rows(disc + [0.0, 0.004, 0.0], np.stack([foot * ones, ones, foot * ones], 1), color, emission)
    sought = np.fromiter((getattr(p, "sought", False) for p in pins), bool, n)
    _marks(inst, heads, h, size, color, (seen, sought, clamped), px)
    geo.instances = inst
    geo.heads, geo.clamped = heads, clamped
    geo.shapes = [SHAPES[c] for c in shape_code]
    return geo


def _rows(pos, scale, rgb, em) -> np.ndarray:
    """Instance rows ``(n, INSTANCE_FLOATS) float32``: position, scale, colour, emission."""
    out = np.empty((len(rgb), INSTANCE_FLOATS), np.float32)
    out[:, 0:3] = pos
    out[:, 3:6] = scale
    out[:, 6:9] = rgb
    out[:, 9] = em
    return out


def _marks(inst: dict, heads, h, size, color, flags, px: float) -> None:
    """The rings round visible pins' feet, the seek target's rings, the arrows of clamped heads
    (``flags``: the pins seen, sought and clamped, ``(p,) bool`` each)."""
    seen, sought, clamped = flags
    x, y, z = heads[:, 0], heads[:, 1], heads[:, 2]
    if seen.any():
        # Wider than the head, so the ring shows round a head sitting on the disc.
        ring = np.repeat(np.maximum(1.7 * size[seen], 6.0 * px)[:, None], 3, axis=1)
        ring_rgb = 0.3 * color[seen] + 0.7
        inst["seen_ring"] = _rows(np.stack([x[seen], 0.006 + 0 * x[seen], z[seen]], 1), ring, ring_rgb, 1.0)
    if sought.any():
        # The seek's target: two wide bright rings, round its head and round its foot,
        # so it stands out by shape (rings) and brightness, not by colour alone.
        big = np.repeat(np.maximum(2.6 * size[sought], 9.0 * px)[:, None], 3, axis=1)
        xs, zs = x[sought], z[sought]
        at = [np.stack([xs, y[sought], zs], 1), np.stack([xs, 0.008 + 0 * xs, zs], 1)]
        rings = [_rows(pos, big, np.tile(SOUGHT_COLOR, (len(pos), 1)), 1.0) for pos in at]
        inst["seen_ring"] = np.concatenate([inst.get("seen_ring", rings[0][:0]), *rings])
    if clamped.any():
        sgn = np.sign(h[clamped])
        ay = y[clamped] + sgn * size[clamped] * 1.45
        asz = size[clamped] * 0.9
        arrow_rgb = 0.4 * color[clamped] + 0.6  # lighter than the head, so it reads as a sign, not a second head
        pos = np.stack([x[clamped], ay, z[clamped]], 1)
        inst["arrow"] = _rows(pos, np.stack([asz, sgn * asz * 1.2, asz], 1), arrow_rgb, 0.0)


def radar_view_proj(aspect: float) -> tuple[np.ndarray, float]:
    """The radar camera's view-projection ``(4, 4) float64`` for a viewport of ``aspect = w / h``.

    The view is zoomed and centred so the disc, and pins up to the clamp height with their arrows,
    just fit. Also returns the disc radius in NDC x units (half-viewport widths), for sizing in pixels.
    """
    p = np.radians(PITCH_DEG)
    eye = CAMERA_DISTANCE * np.array([0.0, np.sin(p), -np.cos(p)])
    cam = Camera3(position=eye, yaw=0.0, pitch=-p, fov_y_deg=FOV_Y_DEG, near=0.1, far=20.0)
    vp = cam.projection_matrix(aspect) @ cam.view_matrix()
    ang = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    top = HEIGHT_CLAMP * RADIUS + 3.2 * HEAD_SIZE
    pts = [np.stack([1.02 * np.cos(ang), np.full_like(ang, y), 1.02 * np.sin(ang)], 1) for y in (-top, 0.0, top)]
    pts.append(np.array([[0.0, 0.0, 1.17]]))  # the forward notch
    pts = np.concatenate(pts)
    clip = np.c_[pts, np.ones(len(pts))] @ vp.T
    ndc = clip[:, :2] / clip[:, 3:4]
    lo, hi = ndc.min(axis=0), ndc.max(axis=0)
    s = float(min(1.96 / (hi[0] - lo[0]), 1.96 / (hi[1] - lo[1])))
    c = 0.5 * (lo + hi)
    fit = np.eye(4)
    fit[0, 0] = fit[1, 1] = s
    fit[0, 3], fit[1, 3] = -s * c[0], -s * c[1]  # applied to clip coordinates: offsets scale with w
    vp = fit @ vp
    o = vp @ np.array([0.0, 0.0, 0.0, 1.0])
    x1 = vp @ np.array([RADIUS, 0.0, 0.0, 1.0])
    return vp, float(x1[0] / x1[3] - o[0] / o[3])


_SHAPE_VS = """
#version 330
uniform mat4 u_view_proj;
in vec3 in_pos;
in vec3 in_normal;
in vec3 i_pos;
in vec3 i_scale;
in vec4 i_color;
out vec3 v_normal;
out vec4 v_color;
void main() {
    v_normal = in_normal / i_scale;  // inverse transpose of a diagonal scale
    v_color = i_color;
    gl_Position = u_view_proj * vec4(i_pos + in_pos * i_scale, 1.0);
}
"""

_SHAPE_FS = """
#version 330
uniform vec3 u_light;
uniform vec3 u_to_eye;
uniform float u_alpha;
in vec3 v_normal;
in vec4 v_color;
out vec4 f_color;
void main() {
    vec3 n = normalize(v_normal);
    if (dot(n, u_to_eye) < 0.0) n = -n;  // two-sided: scales may mirror a shape
    float d = max(dot(n, u_light), 0.0);
    vec3 base = v_color.rgb * (0.38 + 0.62 * d);
    // Emission (alpha channel): visible pins glow towards a lighter tint of their colour.
    vec3 glow = mix(v_color.rgb, vec3(1.0), 0.35) * (0.75 + 0.25 * d);
    f_color = vec4(mix(base, glow, v_color.a), u_alpha);
}
"""

#: The backdrop sits at the far plane (depth test "always" writes it there).
_FAR = 0.99999

#: The backdrop: one quad over the radar's rectangle, darkest in the middle and fading out
#: towards a ring (1.05 of the rectangle's half-size; clear beyond, where it only resets the
#: depth). The fade is worked out per pixel: a fan of triangles cost more on llvmpipe, which
#: sets up every triangle on the CPU, than shading the rectangle does.
_BACK_VS = """
#version 330
out vec2 v_ndc;
void main() {
    // A strip over the viewport: (-1, -1), (1, -1), (-1, 1), (1, 1).
    vec2 p = vec2(gl_VertexID == 1 || gl_VertexID == 3 ? 1.0 : -1.0, gl_VertexID >= 2 ? 1.0 : -1.0);
    v_ndc = p;
    gl_Position = vec4(p, FAR, 1.0);
}
""".replace("FAR", repr(_FAR))

_BACK_FS = """
#version 330
uniform float u_alpha;
in vec2 v_ndc;
out vec4 f_color;
void main() {
    float glow = max(1.0 - length(v_ndc) * (1.0 / 1.05), 0.0);
    f_color = vec4(BACKDROP.rgb, BACKDROP.a * glow * u_alpha);
}
""".replace("BACKDROP", "vec4({:.6f}, {:.6f}, {:.6f}, {:.6f})".format(*BACKDROP_COLOR))


def radar_rect_gl(viewport: tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    """The radar's rectangle inside ``viewport`` (both ``(x, y, w, h)``, OpenGL origin bottom-left)."""
    vx, vy, vw, vh = (int(v) for v in viewport)
    x, y, w, h = HudMetrics(vw, vh).radar_rect()
    return vx + x, vy + vh - (y + h), w, h


class RadarRenderer:
    """Draws a :class:`Radar` in a corner of a viewport with its own programs and buffers.

    Parameters
    ----------
    ctx : moderngl.Context

    Attributes
    ----------
    draw_calls : int
        Draw calls of the last :meth:`draw`.
    instance_writes : int
        Instance buffer writes over the renderer's life (the radar's only per-frame uploads).
    disc : DiscImage
        The static disc, drawn once into an image.
    driver_seconds : float
        Time spent inside the draw calls of the last :meth:`draw` (on llvmpipe this includes the
        vertex shading and triangle setup that a GPU would do), for the benchmark.
    last_geometry : RadarGeometry or None
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        try:
            self.shape_prog = ctx.program(vertex_shader=_SHAPE_VS, fragment_shader=_SHAPE_FS)
            self.back_prog = ctx.program(vertex_shader=_BACK_VS, fragment_shader=_BACK_FS)
            self.disc = DiscImage(ctx)
        except Exception as e:
            raise RenderError(f"radar shaders failed to build: {e}") from e
        self._objects: list = [self.shape_prog, self.back_prog]
        self._shapes: dict[str, tuple[moderngl.Buffer, moderngl.VertexArray, int]] = {}
        for name, soup in unit_shapes().items():
            verts, idx = weld(soup)
            vbo = ctx.buffer(verts.tobytes())
            ibo = ctx.buffer(idx.tobytes())
            inst = ctx.buffer(reserve=64 * INSTANCE_FLOATS * 4, dynamic=True)
            vao = ctx.vertex_array(
                self.shape_prog,
                [(vbo, "3f 3f", "in_pos", "in_normal"), (inst, "3f 3f 4f/i", "i_pos", "i_scale", "i_color")],
                index_buffer=ibo,
                index_element_size=4,
            )
            self._shapes[name] = (inst, vao, len(idx))
            self._objects += [vao, vbo, ibo, inst]
        # The backdrop resets the depth in the rectangle and darkens it in one pass (depth test
        # "always", at the far plane); a masked glClear would reset the depth alone, but
        # moderngl applies a colour mask only at the next clear or use of a framebuffer.
        self._back_vao = ctx.vertex_array(self.back_prog, [])
        self._objects.append(self._back_vao)
        self._vp_cache: dict[float, tuple[bytes, float]] = {}
        light = np.array([-0.35, 1.0, -0.55])
        self.shape_prog["u_light"].value = tuple(light / np.linalg.norm(light))
        p = np.radians(PITCH_DEG)
        self.shape_prog["u_to_eye"].value = (0.0, float(np.sin(p)), float(-np.cos(p)))
        self.draw_calls = 0
        self.instance_writes = 0
        self.driver_seconds = 0.0
        self.last_geometry: RadarGeometry | None = None

    def _view_proj(self, aspect: float) -> tuple[bytes, float]:
        key = round(aspect, 4)
        hit = self._vp_cache.get(key)
        if hit is None:
            vp, ndc_r = radar_view_proj(aspect)
            hit = self._vp_cache[key] = (mat4_bytes(vp), ndc_r)
        return hit

    def draw(self, radar: Radar, viewport: tuple[int, int, int, int], scale: float = 1.0, alpha: float = 1.0) -> None:
        """Draw ``radar`` into its corner of ``viewport`` (``(x, y, w, h)``, GL convention) of the bound framebuffer.

        ``alpha`` below 1 draws it see-through (the radar giving way, :mod:`.radar_yield`).

        With ``scale`` below 1, the bound framebuffer is the scene's at that render scale and
        ``viewport`` the window's: the radar goes where the window's rectangle falls in it, so
        it lines up with the labels the HUD draws round it at full size after the upscale.
        """
        ctx = self.ctx
        fbo = ctx.fbo
        previous = ctx.viewport
        rect = radar_rect_gl(viewport)
        if scale != 1.0:
            x0, y0, x1, y1 = (round(scale * v) for v in (rect[0], rect[1], rect[0] + rect[2], rect[1] + rect[3]))
            rect = (x0, y0, x1 - x0, y1 - y0)
        rw, rh = rect[2], rect[3]
        self.draw_calls = 0
        self.driver_seconds = 0.0
        if rw <= 0 or rh <= 0 or fbo is None:
            return
        clock = time.perf_counter
        vp_bytes, ndc_r = self._view_proj(rw / rh)
        geo = radar_geometry(radar, px_per_radius=ndc_r * rw / 2)
        self.last_geometry = geo
        self.disc.prepare(ndc_r * rw / 2)

        ctx.viewport = rect
        # The backdrop resets the depth in the rectangle (to the far plane) and darkens it; the
        # scene's colour stays behind.
        fbo.depth_mask = True
        ctx.disable(moderngl.CULL_FACE)
        ctx.enable(moderngl.BLEND | moderngl.DEPTH_TEST)
        ctx.depth_func = "1"
        # Destination alpha stays 1 so screenshots stay opaque.
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        self.back_prog["u_alpha"].value = float(alpha)
        t0 = clock()
        self._back_vao.render(moderngl.TRIANGLE_STRIP, vertices=4)
        spent = clock() - t0
        if alpha >= 1.0:  # opaque pins need no blending; faded ones do
            ctx.disable(moderngl.BLEND)
        ctx.depth_func = "<"
        self.draw_calls = 1

        self.shape_prog["u_view_proj"].write(vp_bytes)
        self.shape_prog["u_alpha"].value = float(alpha)
        for name in SHAPES:
            rows = geo.instances.get(name)
            if rows is None or len(rows) == 0:
                continue
            inst, vao, n_vert = self._shapes[name]
            data = rows.tobytes()
            if len(data) > inst.size:
                inst.orphan(len(data) * 2)
            inst.write(data)
            self.instance_writes += 1
            t0 = clock()
            vao.render(moderngl.TRIANGLES, vertices=n_vert, instances=len(rows))
            spent += clock() - t0
            self.draw_calls += 1

        # The disc over the pins, its depth tested but not written.
        fbo.depth_mask = False
        t0 = clock()
        self.disc.draw(vp_bytes, alpha)
        self.driver_seconds = spent + clock() - t0
        self.draw_calls += 1
        fbo.depth_mask = True
        ctx.disable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        ctx.viewport = previous

    def release(self) -> None:
        for obj in self._objects:
            obj.release()
        self._objects.clear()
        self.disc.release()
