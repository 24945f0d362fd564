"""A procedural sky dome: gradient, nebula band, stars, a planet and a sun, behind the scene.

The dome is geometry, not a per-pixel shader: a sphere of triangles whose vertex colours
hold the gradient, the nebula and the sun's halo (computed once in numpy), a few thousand
stars as points a pixel or two wide, a planet and the sun's disc as small fans. It is drawn
once into a cube map (again only when the palette, the sun's direction or the resolution
changes), so every sky pixel costs one texture lookup and a frame's sky is one triangle,
which matters on llvmpipe, where shading and triangle setup are done on the CPU and a
per-pixel noise sky cost more than the whole scene.

It is drawn *after* the opaque scene, at the far plane, with the depth test ``<=`` against
the cleared depth (1.0), so only the pixels no surface covered are touched, and it stays
put as the player walks (only the view's rotation looks it up).

Every colour comes from the palette (:mod:`.materials`):

- gradient: ground, horizon, zenith (:func:`gradient`, the same function fog uses in the
  scene shaders, :data:`.shaders.SKY_GRADIENT`, so distant walls fade into the sky behind them);
- a nebula band along a tilted great circle, two hues through warped sines;
- stars, denser in the nebula's band, fewer near the horizon;
- a planet low in the sky, lit from the sun's side, with a thin bright rim;
- the sun in the key light's direction, a disc and a halo, so the light on the walls has a source.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..game.frame import WIDEST_VIEW, Frame

SKY_VERTEX = """
#version 330
uniform mat4 u_view_proj;
uniform vec3 u_eye;
in vec3 in_pos;     // a direction (unit), or a point on the unit sphere
in vec4 in_color;   // rgb, and the point size in pixels for stars
out vec3 v_color;
void main() {
    v_color = in_color.rgb;
    vec4 p = u_view_proj * vec4(u_eye + in_pos * 100.0, 1.0);
    // z = w: exactly the far plane, so the depth test '<=' keeps what the scene covered.
    gl_Position = p.xyww;
    gl_PointSize = in_color.a;
}
"""

SKY_FRAGMENT = """
#version 330
in vec3 v_color;
out vec4 f_color;
void main() {
    f_color = vec4(v_color, 1.0);
}
"""

#: Where things sit on the dome (unit vectors are made from these).
BAND_NORMAL = (0.42, 0.78, -0.46)  # the nebula band's great circle is the plane normal to this
PLANET_DIR = (-0.62, 0.26, 0.74)
PLANET_RADIUS = 0.17  # radians
SUN_RADIUS = 0.022  # radians
N_STARS = 6000
#: Dome resolution: longitude x latitude vertices. Features of the nebula are ~0.2 rad, the
#: grid ~0.05 rad; latitudes crowd near the horizon, where the gradient changes fastest.
DOME_GRID = (64, 28)


def _unit(v) -> np.ndarray:
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _smoothstep(e0, e1, x):
    t = np.clip((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def gradient(d: np.ndarray, colours) -> np.ndarray:
    """Sky colour ``(..., 3) float64`` by direction ``d`` ``(..., 3)``: exactly ``sky_gradient`` in GLSL."""
    y = d[..., 1:2]
    hor, zen, gnd = (np.asarray(colours[k], np.float64) for k in ("sky_horizon", "sky_zenith", "sky_ground"))
    up = hor + (zen - hor) * np.sqrt(np.clip(y, 0.0, 1.0))
    down = hor + (gnd - hor) * _smoothstep(0.0, 0.2, -y)
    return np.where(y >= 0.0, up, down)


def _nebula(d: np.ndarray, colours) -> np.ndarray:
    q = d * 3.0
    q = q + 0.7 * np.sin(q[..., [1, 2, 0]] * 1.7 + np.array([1.3, 4.1, 2.7]))
    q = q + 0.4 * np.sin(q[..., [2, 0, 1]] * 3.3 + np.array([5.2, 0.7, 3.3]))
    shape = 0.5 + 0.5 * np.sin(q[..., 0]) * np.sin(q[..., 1] + 0.5) * np.sin(q[..., 2] + 1.0)
    across = d @ _unit(BAND_NORMAL)
    band = np.exp(-across * across / 0.09)
    hue = (0.5 + 0.5 * np.sin((d @ np.array([2.1, -1.3, 3.7])) * 2.0))[..., None]
    a, b = (np.asarray(colours[k], np.float64) for k in ("nebula_a", "nebula_b"))
    above = _smoothstep(-0.15, 0.1, d[..., 1])
    return (a + (b - a) * hue) * (band * _smoothstep(0.3, 0.95, shape) * 0.55 * above)[..., None]


def _sun_halo(d: np.ndarray, light: np.ndarray, colours) -> np.ndarray:
    sd = np.clip(d @ light, 0.0, 1.0)
    return np.asarray(colours["sun"], np.float64) * (sd**12 * 0.12 + sd**200 * 0.5)[..., None]


def _fan(center: np.ndarray, radius: float, rings: int, segments: int):
    """A disc on the unit sphere around ``center``: vertices ``(v, 3)``, triangles ``(t, 3)``,
    and each vertex's distance from the centre in disc radii ``(v,)``."""
    c = _unit(center)
    e1 = _unit(np.cross(c, [0.0, 1.0, 0.0]) if abs(c[1]) < 0.9 else np.cross(c, [1.0, 0.0, 0.0]))
    e2 = np.cross(c, e1)
    r = np.linspace(0.0, 1.0, rings + 1)[1:]
    ang = 2 * np.pi * np.arange(segments) / segments
    rr, aa = np.meshgrid(r, ang, indexing="ij")
    ring = c + np.tan(radius * rr)[..., None] * (np.cos(aa)[..., None] * e1 + np.sin(aa)[..., None] * e2)
    verts = np.concatenate([c[None], _unit(ring.reshape(-1, 3))])
    j = np.arange(segments)
    jn = (j + 1) % segments
    tris = [np.c_[np.zeros(segments, int), 1 + j, 1 + jn]]
    for i in range(rings - 1):
        a, b = 1 + i * segments + j, 1 + i * segments + jn
        tris += [np.c_[a, a + segments, b], np.c_[b, a + segments, b + segments]]
    return verts, np.concatenate(tris), np.concatenate([[0.0], rr.ravel()])


def build_dome(colours, light_dir) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The sky's geometry for a palette and a sun direction.

    Returns
    -------
    vertices : (v, 7) float32
        Direction xyz, colour rgb (display space), point size (stars; 1 elsewhere).
    behind : (t, 3) uint32
        Dome triangles (drawn first).
    front : (u, 3) uint32
        Planet and sun triangles (drawn after the stars, over them).
    star_first : int
        Index of the first star vertex; the stars are the last :data:`N_STARS` vertices.
    """
    light = _unit(light_dir)
    n_lon, n_lat = DOME_GRID
    t = np.linspace(-1.0, 1.0, n_lat)
    lat = np.sign(t) * np.abs(t) ** 1.6 * (np.pi / 2)
    lon = 2 * np.pi * np.arange(n_lon) / n_lon
    la, lo = np.meshgrid(lat, lon, indexing="ij")
    d = np.stack([np.cos(la) * np.sin(lo), np.sin(la), np.cos(la) * np.cos(lo)], axis=-1).reshape(-1, 3)
    col = gradient(d, colours) + _nebula(d, colours) + _sun_halo(d, light, colours)
    i, j = np.meshgrid(np.arange(n_lat - 1), np.arange(n_lon), indexing="ij")
    a = (i * n_lon + j).ravel()
    b = (i * n_lon + (j + 1) % n_lon).ravel()
    behind = np.concatenate([np.c_[a, a + n_lon, b], np.c_[b, a + n_lon, b + n_lon]])
    parts_v, parts_c, front = [d], [col], []
    base = len(d)

    # The planet: a sphere seen from afar, lit by the sun, its rim catching the light.
    pv, pt, pr = _fan(np.asarray(PLANET_DIR), PLANET_RADIUS, 10, 48)
    pc = _unit(PLANET_DIR)
    off = pv - pc * (pv @ pc)[:, None]
    offn = off / np.maximum(np.linalg.norm(off, axis=1, keepdims=True), 1e-9)
    normal = offn * pr[:, None] - pc * np.sqrt(np.clip(1 - pr * pr, 0.0, 1.0))[:, None]
    lit = np.clip(normal @ light, 0.0, 1.0) * 0.85 + 0.06
    stripes = 0.88 + 0.12 * np.sin(pv[:, 1] * 70.0)
    rim = _smoothstep(0.8, 1.0, pr) * 0.35
    planet = np.asarray(colours["planet"]) * (lit * stripes + rim)[:, None] + gradient(pv, colours) * 0.3
    parts_v.append(pv)
    parts_c.append(planet)
    front.append(pt + base)
    base += len(pv)

    # The sun's disc, white-hot in the middle.
    sv, st, sr = _fan(light, SUN_RADIUS, 2, 20)
    sun = np.asarray(colours["sun"]) * (1.6 - 0.5 * sr)[:, None] + 0.25
    parts_v.append(sv)
    parts_c.append(sun)
    front.append(st + base)
    base += len(sv)

    # Stars: a fixed random sky (its own generator: rendering only, never the simulation's).
    rng = np.random.default_rng(20211)
    sd = _unit(rng.normal(size=(N_STARS, 3)))
    bright = rng.random(N_STARS) ** 3
    across = sd @ _unit(BAND_NORMAL)
    bright *= (0.45 + 0.55 * _smoothstep(-0.1, 0.2, sd[:, 1])) * (1.0 - 0.4 * np.exp(-across * across / 0.09))
    star = np.asarray(colours["star"]) * (0.25 + 0.75 * bright)[:, None]
    star = gradient(sd, colours) + star
    parts_v.append(sd)
    parts_c.append(star)
    star_first = base

    v = np.concatenate(parts_v)
    c = np.clip(np.concatenate(parts_c), 0.0, 1.0)
    size = np.ones(len(v))
    size[star_first:] = np.where(bright > 0.55, 2.0, 1.0)
    verts = np.concatenate([v, c, size[:, None]], axis=1).astype(np.float32)
    return verts, behind.astype(np.uint32), np.concatenate(front).astype(np.uint32), star_first


#: Cube-map faces in OpenGL's order (+x, -x, +y, -y, +z, -z): for each, the axes along which
#: the texel's s and t grow, and the face's axis (the GL specification's table, "Cube Map
#: Texture Selection").
CUBE_FACES = (
    ((0, 0, -1), (0, -1, 0), (1, 0, 0)),
    ((0, 0, 1), (0, -1, 0), (-1, 0, 0)),
    ((1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((1, 0, 0), (0, 0, -1), (0, -1, 0)),
    ((1, 0, 0), (0, -1, 0), (0, 0, 1)),
    ((-1, 0, 0), (0, -1, 0), (0, 0, -1)),
)
#: Cube face sizes are multiples of this many texels, at most :data:`CUBE_MAX` (a face as
#: fine as the screen at the centre of the view; see :func:`cube_face_size`).
CUBE_STEP = 64
CUBE_MAX = 1024

CUBE_VERTEX = """
#version 330
uniform mat3 u_dir_from_ndc;  // screen (x, y, 1) to a world direction (see SkyRenderer.draw)
in vec2 in_ndc;  // a corner of the screen's triangle or of a rectangle where the sky may show
noperspective out vec3 v_dir;
void main() {
    // Linear in screen space, so interpolating it per pixel is exact; without perspective
    // (every corner's w is 1), which spares llvmpipe a division per pixel: a tenth of the sky.
    v_dir = u_dir_from_ndc * vec3(in_ndc, 1.0);
    gl_Position = vec4(in_ndc, 1.0, 1.0);  // at the far plane (z = w)
}
"""

CUBE_FRAGMENT = """
#version 330
uniform samplerCube u_sky;
noperspective in vec3 v_dir;
out vec4 f_color;
void main() {
    f_color = vec4(texture(u_sky, v_dir).rgb, 1.0);
}
"""

#: One triangle covering the screen (normalized device coordinates), the sky's when it may show anywhere.
SCREEN_TRIANGLE = np.array([[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]], np.float32)


#: Views of at least this many pixels test the sky's cells finely (``SKY_ROWS`` rows); smaller
#: ones in three cells, the middle one square: there a sky pixel costs too little for the finer
#: test's 0.05-0.1 ms of the main thread to pay (at half of 1280x720 it lost 0.03-0.18 ms a frame,
#: at 1280x720 it saves 0.2-0.6 ms).
FINE_CELLS_PIXELS = 500_000


def open_sky(frame: Frame, width: int, height: int) -> np.ndarray | None:
    """Where ``frame``'s dome may show in a view ``width`` x ``height`` pixels: rectangles ``(k, 4)``
    in the view's units (:func:`~across_dimensions.game.occlusion.open_rectangles` of its
    ``sky_boxes``), or None for anywhere (no boxes, or a window wider than the frame was made for,
    whose sides were never tested)."""
    boxes = frame.sky_boxes
    if boxes is None or width > WIDEST_VIEW * height:
        return None
    # Here, not at the top: only a level's frame has boxes, and the title and menus, drawn by
    # this module too, would otherwise load the physics package first (a tenth of a second).
    from ..game.occlusion import SKY_ROWS, open_rectangles

    cam = frame.camera
    rows = SKY_ROWS if width * height >= FINE_CELLS_PIXELS else 1
    t = np.tan(np.radians(cam.fov_y_deg) / 2.0)
    return open_rectangles(np.asarray(cam.position, np.float64), cam.axes(), t, cam.far, boxes, rows)


#: Rectangles leaving the sky more than this fraction of the screen are drawn as the whole
#: screen: their edges across llvmpipe's tiles then cost more than the depth test they spare.
OPEN_ENOUGH = 0.75


def open_triangles(rects: np.ndarray | None, aspect: float) -> np.ndarray:
    """The triangles ``(3 t, 2) float32`` (normalized device coordinates) to draw the sky over:
    two per rectangle ``x0, y0, x1, y1`` of ``rects (k, 4)`` (the view's units, :func:`open_sky`:
    x spans -``aspect`` to ``aspect``)
    that reaches the screen, clipped to it; :data:`SCREEN_TRIANGLE` for None, or when they
    hold more than :data:`OPEN_ENOUGH` of the screen."""
    if rects is None:
        return SCREEN_TRIANGLE
    r = np.asarray(rects, np.float64).reshape(-1, 4) / (aspect, 1.0, aspect, 1.0)
    x0, y0 = np.maximum(r[:, 0], -1.0), np.maximum(r[:, 1], -1.0)
    x1, y1 = np.minimum(r[:, 2], 1.0), np.minimum(r[:, 3], 1.0)
    on = (x0 < x1) & (y0 < y1)
    x0, y0, x1, y1 = x0[on], y0[on], x1[on], y1[on]
    if ((x1 - x0) * (y1 - y0)).sum() > 4.0 * OPEN_ENOUGH:  # the screen is 2 by 2
        return SCREEN_TRIANGLE
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y0), (x1, y1), (x0, y1)]  # counter-clockwise
    return np.stack([np.stack(c, axis=1) for c in corners], axis=1).reshape(-1, 2).astype(np.float32)


def cube_face_size(view_proj: np.ndarray, height: int) -> int:
    """Texels per cube face so that one texel covers about one pixel at the centre of the view.

    A face spans ``tan`` -1 to 1, so it has ``size / 2`` texels per radian at its centre; the
    screen has ``height / 2 * t`` pixels per radian at its centre, where ``t`` is the
    projection's vertical scale (``1 / tan(fov_y / 2)``), the length of ``view_proj``'s second
    row's rotation part.
    """
    t = float(np.linalg.norm(np.asarray(view_proj, np.float64)[1, :3]))
    size = int(np.ceil(height * t / CUBE_STEP)) * CUBE_STEP
    return int(min(max(size, CUBE_STEP), CUBE_MAX))


def _face_view_proj(face: int) -> np.ndarray:
    """``(4, 4) float64``: the dome seen from its centre through cube face ``face`` (90 degrees).

    The eye's x and y are the face's s and t axes, so the framebuffer's rows, read from the
    bottom, are the face's texel rows in the order ``TextureCube.write`` takes them."""
    s_axis, t_axis, axis = (np.asarray(a, np.float64) for a in CUBE_FACES[face])
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = s_axis, t_axis, -axis
    near, far = 1.0, 1000.0  # the dome is drawn at a radius of 100
    proj = np.zeros((4, 4))
    proj[0, 0] = proj[1, 1] = 1.0
    proj[2, 2] = (far + near) / (near - far)
    proj[2, 3] = 2 * far * near / (near - far)
    proj[3, 2] = -1.0
    return proj @ view


class SkyRenderer:
    """Draws the sky dome into the bound framebuffer, behind what is already drawn.

    The dome's geometry (thousands of triangles and stars) is drawn once into a cube map,
    again only when the palette, the sun or the needed resolution changes; each frame is
    then one triangle covering the screen that looks the sky up by direction. On llvmpipe,
    where the main thread transforms and sets up every triangle and star before any pixel
    is shaded, that takes about half a millisecond a frame off the critical path.

    Attributes
    ----------
    builds : int
        How many times the dome was (re)drawn into the cube map: once, and again after a
        palette, sun or resolution change.
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.prog = ctx.program(vertex_shader=SKY_VERTEX, fragment_shader=SKY_FRAGMENT)
        self.cube_prog = ctx.program(vertex_shader=CUBE_VERTEX, fragment_shader=CUBE_FRAGMENT)
        self.corners = ctx.buffer(reserve=SCREEN_TRIANGLE.nbytes, dynamic=True)
        self.cube_vao = ctx.vertex_array(self.cube_prog, [(self.corners, "2f", "in_ndc")])
        self._drawn_over = b""  # the corners in the buffer
        self.cube: moderngl.TextureCube | None = None
        self._built_for = None
        self.builds = 0

    def _build(self, colours, light_dir, size: int) -> None:
        light = tuple(round(float(x), 6) for x in light_dir)
        key = (tuple(sorted((k, tuple(v)) for k, v in colours.items())), light, size)
        if key == self._built_for:
            return
        verts, behind, front, star_first = build_dome(colours, light)
        ctx = self.ctx
        bound, viewport = ctx.fbo, ctx.viewport
        vbo = ctx.buffer(verts.tobytes())
        ibo = ctx.buffer(np.concatenate([behind.ravel(), front.ravel()]).tobytes())
        vao = ctx.vertex_array(
            self.prog, [(vbo, "3f 4f", "in_pos", "in_color")], index_buffer=ibo, index_element_size=4
        )
        points = ctx.vertex_array(self.prog, [(vbo, "3f 4f", "in_pos", "in_color")])
        color = ctx.texture((size, size), 4)
        depth = ctx.depth_renderbuffer((size, size))
        fbo = ctx.framebuffer(color_attachments=[color], depth_attachment=depth)
        if self.cube is None or self.cube.size != (size, size):
            if self.cube is not None:
                self.cube.release()
            self.cube = ctx.texture_cube((size, size), 4)
            # Nearest: stars stay one or two crisp texels, and faces never blend across seams.
            self.cube.filter = (moderngl.NEAREST, moderngl.NEAREST)
        fbo.use()
        ctx.viewport = (0, 0, size, size)
        ctx.enable(moderngl.DEPTH_TEST | moderngl.PROGRAM_POINT_SIZE)
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        ctx.depth_func = "<="
        self.prog["u_eye"].value = (0.0, 0.0, 0.0)
        for face in range(6):
            ctx.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
            vp = _face_view_proj(face)
            self.prog["u_view_proj"].write(np.ascontiguousarray(vp.T, np.float32).tobytes())
            # Dome, then the stars over it, then the planet and the sun over the stars.
            vao.render(moderngl.TRIANGLES, vertices=behind.size)
            points.render(moderngl.POINTS, vertices=len(verts) - star_first, first=star_first)
            vao.render(moderngl.TRIANGLES, vertices=front.size, first=behind.size)
            self.cube.write(face, fbo.read(components=4))
        ctx.disable(moderngl.PROGRAM_POINT_SIZE)
        ctx.depth_func = "<"
        for obj in (fbo, depth, color, points, vao, ibo, vbo):
            obj.release()
        if bound is not None:
            bound.use()
        ctx.viewport = viewport
        self._built_for = key
        self.builds += 1

    def draw(self, view_proj: np.ndarray, eye: np.ndarray, light_dir, colours, set_uniform, corners=None) -> int:
        """Draw the sky where the depth buffer is still clear (depth test on, cleared to 1.0),
        over the whole screen or only over the triangles ``corners``.

        Parameters
        ----------
        view_proj : (4, 4) float64
            The scene's projection times view.
        eye : (3,) float64
            Unused: the sky is infinitely far, only the view's rotation matters.
        light_dir : (3,) float
            Unit vector towards the key light (the sun is drawn there).
        colours : dict
            The palette (:mod:`.materials`).
        set_uniform : callable
            ``set_uniform(prog, name, value)``, tolerant of names the compiler dropped.
        corners : (3 t, 2) float32, optional
            Triangles in normalized device coordinates where the sky may show
            (:func:`open_triangles` of :func:`open_sky`; elsewhere a box covers the view, and
            even a depth test there costs on llvmpipe); the whole screen by default.

        Returns
        -------
        int
            Draw calls made.
        """
        corners = SCREEN_TRIANGLE if corners is None else corners
        ctx = self.ctx
        vp = np.asarray(view_proj, np.float64)
        size = cube_face_size(vp, ctx.viewport[3])
        if self.cube is not None:
            # Never smaller than it is: a small view drawn between two big ones (the picture in
            # picture, a benchmark's two scales) must not make it rebuild every frame.
            size = max(size, self.cube.size[0])
        self._build(colours, light_dir, size)
        # A direction d has clip (x, y, w) = M d with M the rows x, y, w of view_proj's rotation
        # part (directions ignore the eye's translation); so d = M^-1 (ndc x, ndc y, 1).
        dir_from_ndc = np.linalg.inv(vp[[0, 1, 3], :3])
        set_uniform(self.cube_prog, "u_dir_from_ndc", np.ascontiguousarray(dir_from_ndc.T, np.float32).tobytes())
        self.cube.use(0)
        set_uniform(self.cube_prog, "u_sky", 0)
        ctx.depth_func = "<="
        ctx.fbo.depth_mask = False
        data = corners.tobytes()
        if data != self._drawn_over:
            if len(data) > self.corners.size:
                self.corners.orphan(len(data))
            self.corners.write(data)
            self._drawn_over = data
        self.cube_vao.render(moderngl.TRIANGLES, vertices=len(corners))
        ctx.fbo.depth_mask = True
        ctx.depth_func = "<"
        return 1

    def release(self) -> None:
        for obj in (self.cube, self.cube_vao, self.corners, self.cube_prog, self.prog):
            if obj is not None:
                obj.release()
        self.cube = None


__all__ = ["SkyRenderer", "build_dome", "gradient", "open_sky", "open_triangles", "SKY_VERTEX", "SKY_FRAGMENT"]
