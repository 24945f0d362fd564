"""Drawing the Flatland prologue: the flat being's side view, the z bar, and the turn to the 3D world.

:class:`FlatRenderer` draws a :class:`~across_dimensions.game.flatland.view.FlatFrame` in the game's
sci-fi look, from the same palette as the 4D scene (:mod:`.materials`):

* the background: the sky's gradient, with a faint metre grid in the plane and a few stars;
* sections as dark panels with seams and a glowing trim along their edges; a solid that ends along
  z within the level's range is banded in the ana or kata colour, denser towards its ends (the w
  cue of the 4D game, one dimension down), and a ball's circle is ringed the same way;
* the being (yellow, an eye on the side it walks to), crates, the key, the goal's beam;
* the z bar, the one-axis radar, with the HUD's quads: the level's z range as a track, the being's
  plane as a bright line on it, a pin for each thing of interest at its own z (above the line is
  +z), its name and which way it lies; the hint panel and messages are the HUD's own;
* once the level is complete, the 3D world the being lived in, drawn by the 4D game's own
  :class:`~.renderer.Renderer` as the camera turns from straight on to above and aside, with the
  plane as a glowing sheet and the sections in it, and the closing line.

All geometry is built with numpy each frame (a few hundred triangles) and drawn in two calls:
panels, then glows added on top.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ..core.flat_section import Solid3
from ..core.flat_solids import box_solid, prism_solid, sphere_solid
from ..core.mesh import TriMesh3
from ..game.flatland.view import FlatFrame
from ..game.frame import Camera3, Drawable, Frame, Hud
from .font import GLYPH_H, text_width
from .hud import hud_quads
from .quads import QuadList
from .renderer import Renderer
from .text_layout import scaled

BEING = (0.98, 0.92, 0.35, 1.0)
EYE = (0.05, 0.05, 0.1, 1.0)
ITEM_GLOW = (0.45, 1.0, 0.9, 1.0)
GOAL = (0.55, 1.0, 0.45, 1.0)
BLOCKED = (1.0, 0.3, 0.25, 1.0)
BAR_TRACK = (0.55, 0.85, 1.0, 0.18)
BAR_TEXT = (0.75, 0.92, 1.0, 1.0)
PLANE_LINE = (1.0, 0.95, 0.55, 1.0)
#: Trim width in pixels, and how far a panel's colour is darkened.
TRIM_PX = 3.0
PANEL_SHADE = 0.45
#: Seconds over which the flat view fades into the 3D one as the view starts to turn.
FADE = 0.2
#: Field of view of the turn to 3D, degrees.
REVEAL_FOV = 50.0
FLOATS = 8  # per vertex: x, y | r, g, b, a | across (glows) or radius (rings) | cue
#: The layers of a frame in drawing order, each one draw call with its own fragment shader (one
#: shader with a branch per kind cost llvmpipe 15 ms for the backdrop alone: it shades every branch).
LAYERS = ("sky", "back", "panel", "ring", "front", "glow")
#: Layers drawn without blending while the view is not fading: llvmpipe blends on the CPU.
OPAQUE = ("panel", "ring")

_VS = """
#version 330
uniform vec2 u_center;
uniform vec2 u_half;
in vec2 in_pos;
in vec4 in_color;
in float in_across;
in float in_cue;
out vec4 v_color;
out vec2 v_world;
out float v_across;
out float v_cue;
void main() {
    v_color = in_color; v_world = in_pos; v_across = in_across; v_cue = in_cue;
    gl_Position = vec4((in_pos - u_center) / u_half, 0.0, 1.0);
}
"""

_HEAD = """
#version 330
uniform float u_alpha;
uniform vec3 u_ana;
uniform vec3 u_kata;
in vec4 v_color;
in vec2 v_world;
in float v_across;
in float v_cue;
out vec4 f_color;
vec3 cue_bands(vec3 base, float coord, float cue) {
    // Bands that tighten towards the ends of a thing's z extent; ana (+z of the plane) warm,
    // kata cool, as the 4D game tints what lies ana or kata of the slice.
    vec3 tint = cue < 0.0 ? u_ana : u_kata;
    float k = abs(cue);
    float band = smoothstep(0.35, 0.5, abs(fract(coord * (1.5 + 6.0 * k)) - 0.5));
    return mix(base, tint, (0.25 + 0.5 * k) * band);
}
"""

_FS = {
    "flat": _HEAD + "void main() { f_color = vec4(v_color.rgb, v_color.a * u_alpha); }",
    # a panel: seams every metre, and the z cue's bands on what ends along z
    "panel": _HEAD
    + """
void main() {
    vec2 g = abs(fract(v_world + 0.5) - 0.5);
    vec3 c = v_color.rgb * (1.0 - 0.3 * (1.0 - smoothstep(0.0, 0.025, min(g.x, g.y))));
    if (v_cue > -1.5) c = cue_bands(c, v_world.x + v_world.y, v_cue);
    f_color = vec4(c, v_color.a * u_alpha);
}
""",
    # a ball's circle: rings by radius (v_across), banded by where the plane cuts it
    "ring": _HEAD
    + """
void main() {
    vec3 c = cue_bands(v_color.rgb, v_across * 2.0, v_cue) * (0.75 + 0.25 * (1.0 - v_across * v_across));
    f_color = vec4(c, v_color.a * u_alpha);
}
""",
    # a glow across a line (v_across from -1 to 1), added on top
    "glow": _HEAD
    + "void main() { float t = 1.0 - abs(v_across); f_color = vec4(v_color.rgb, v_color.a * t * t * u_alpha); }",
}
_SHADER_OF = {"sky": "flat", "back": "flat", "panel": "panel", "ring": "ring", "front": "flat", "glow": "glow"}


class _Mesh:
    """Vertices of one frame by layer, as rows of :data:`FLOATS`."""

    def __init__(self):
        self.rows: dict[str, list[np.ndarray]] = {layer: [] for layer in LAYERS}

    def fan(self, layer: str, points, color, cue: float | None = None, across=None) -> None:
        """A convex polygon ``(k, 2)`` as triangles from its first corner."""
        p = np.asarray(points, np.float64)
        if len(p) < 3:
            return
        a = np.zeros(len(p)) if across is None else np.asarray(across, np.float64)
        idx = np.array([(0, i, i + 1) for i in range(1, len(p) - 1)]).ravel()
        self.add(layer, p[idx], color, a[idx], -2.0 if cue is None else cue)

    def glow(self, points, color, width: float, closed: bool = True) -> None:
        """A glowing line ``width`` world units either side of the polyline ``points (k, 2)``."""
        p = np.asarray(points, np.float64)
        q = np.roll(p, -1, axis=0) if closed else p[1:]
        p = p if closed else p[:-1]
        d = q - p
        n = np.c_[-d[:, 1], d[:, 0]] / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None] * width
        quads = np.stack([p - n, q - n, q + n, p - n, q + n, p + n], axis=1).reshape(-1, 2)
        self.add("glow", quads, color, np.tile([-1.0, -1.0, 1.0, -1.0, 1.0, 1.0], len(p)), -2.0)

    def add(self, layer: str, xy, color, across, cue) -> None:
        """Vertices ``xy (n, 2)`` with one colour or one per vertex ``(n, 4)``."""
        rows = np.empty((len(xy), FLOATS), np.float32)
        rows[:, 0:2] = xy
        rows[:, 2:6] = color
        rows[:, 6] = across
        rows[:, 7] = cue
        self.rows[layer].append(rows)

    def array(self, layer: str) -> np.ndarray:
        rows = self.rows[layer]
        return np.concatenate(rows) if rows else np.zeros((0, FLOATS), np.float32)


def _circle(center, radius: float, n: int = 48) -> np.ndarray:
    t = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.c_[center[0] + radius * np.cos(t), center[1] + radius * np.sin(t)]


def _shade(color, k: float) -> tuple:
    return (color[0] * k, color[1] * k, color[2] * k, color[3])


def _mix(a, b, t: float) -> tuple:
    return tuple(float(x + (y - x) * t) for x, y in zip(a, b))


class FlatRenderer:
    """Draws prologue frames.

    Parameters
    ----------
    ctx : moderngl.Context
    renderer : Renderer, optional
        The 4D game's renderer, for the turn to 3D and the HUD; one is made when not given.
    """

    def __init__(self, ctx: moderngl.Context, renderer: Renderer | None = None):
        self.ctx = ctx
        self.renderer = renderer if renderer is not None else Renderer(ctx)
        self._own_renderer = renderer is None
        self.programs = {name: ctx.program(vertex_shader=_VS, fragment_shader=fs) for name, fs in _FS.items()}
        self._vbo = ctx.buffer(reserve=4096 * FLOATS * 4, dynamic=True)
        self._vaos = self._make_vaos()
        self._meshes3: dict[str, tuple[int, TriMesh3]] = {}
        self.last_quads = np.zeros((0, 12), np.float32)

    def _make_vaos(self) -> dict[str, moderngl.VertexArray]:
        layout = [(self._vbo, "2f 4f 1f 1f", "in_pos", "in_color", "in_across", "in_cue")]
        # skip_errors: the flat shader leaves out the attributes it does not read
        return {name: self.ctx.vertex_array(prog, layout, skip_errors=True) for name, prog in self.programs.items()}

    @property
    def palette(self) -> dict:
        return self.renderer.palette

    # ---------------------------------------------------------------- a frame
    def draw(self, frame: FlatFrame, viewport: tuple[int, int, int, int], hud: bool = True) -> None:
        """Draw ``frame`` into ``viewport`` (``(x, y, w, h)``, GL convention) of the bound framebuffer;
        with ``hud`` also the z bar, the hint and the messages (a menu over the paused level has none)."""
        viewport = tuple(int(v) for v in viewport)
        fade = 1.0 - min(1.0, frame.reveal / FADE) if frame.reveal > 0.0 else 1.0
        if frame.reveal > 0.0:
            self._draw_3d(frame, viewport)
        if fade > 0.0:
            self._draw_flat(frame, viewport, fade)
        if not hud:
            self.last_quads = np.zeros((0, 12), np.float32)
            return
        panel = Hud(crosshair=False, w_min=0.0, w_max=0.0, hint=frame.hint, hint_label=frame.hint_label)
        panel.message = frame.line if frame.reveal >= 0.35 else frame.message
        quads = hud_quads(panel, viewport[2], viewport[3])
        if fade > 0.0:
            quads = np.concatenate([self._bar_quads(frame, viewport[2], viewport[3], fade), quads])
        self.last_quads = quads
        self.renderer.hud.draw_quads(quads, viewport)

    def _view(self, frame: FlatFrame, viewport) -> tuple[tuple[float, float], tuple[float, float], float]:
        """Centre and half extents of the view in metres, and metres per pixel."""
        _, _, w, h = viewport
        half_h = frame.half_height
        return frame.center, (half_h * w / h, half_h), 2.0 * half_h / h

    def _draw_flat(self, frame: FlatFrame, viewport, alpha: float) -> None:
        """The side view, one draw call a layer; only the glows blend (additively) unless the view fades."""
        ctx = self.ctx
        ctx.viewport = viewport
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        center, half, per_px = self._view(frame, viewport)
        pal = self.palette
        mesh = self._geometry(frame, center, half, per_px)
        for prog in self.programs.values():
            for name, value in (("u_center", center), ("u_half", half), ("u_alpha", alpha)):
                prog[name].value = value
            for name in ("u_ana", "u_kata"):
                u = prog.get(name, None)  # only the shaders that band use them
                if u is not None:
                    u.value = tuple(pal[name[2:]])
        for layer in LAYERS:
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = (
                (moderngl.SRC_ALPHA, moderngl.ONE)
                if layer == "glow"
                else (
                    moderngl.SRC_ALPHA,
                    moderngl.ONE_MINUS_SRC_ALPHA,
                )
            )
            self._render(layer, mesh.array(layer))
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        ctx.disable(moderngl.BLEND)

    def _render(self, layer: str, rows: np.ndarray) -> None:
        if not len(rows):
            return
        data = rows.astype(np.float32).tobytes()
        if len(data) > self._vbo.size:
            self._vbo.orphan(len(data) * 2)
            self._vaos = self._make_vaos()
        self._vbo.write(data)
        self._vaos[_SHADER_OF[layer]].render(moderngl.TRIANGLES, vertices=len(rows))

    def _geometry(self, frame: FlatFrame, center, half, per_px: float) -> _Mesh:
        """Everything the side view draws, by layer."""
        mesh = _Mesh()
        self._backdrop(mesh, center, half, per_px)
        trim = tuple(self.palette["trim"]) + (1.0,)
        width = TRIM_PX * per_px
        (gx, gy), (sx, sy) = frame.goal
        lo, hi = (gx - sx / 2, gy - sy / 2), (gx + sx / 2, gy + sy / 2)
        mesh.fan("front", np.array([lo, (hi[0], lo[1]), hi, (lo[0], hi[1])]), GOAL[:3] + (0.22,))
        mesh.glow(np.array([(lo[0], lo[1]), (hi[0], lo[1])]), GOAL, 2 * width, closed=False)
        for piece in frame.pieces:
            mesh.fan("panel", piece.points, _shade(piece.color, PANEL_SHADE), piece.cue)
        for outline in frame.outlines:
            mesh.glow(outline.points, _mix(trim, outline.color, 0.45), width)
        pulse = 0.75 + 0.25 * math.sin(frame.time * 4.0)
        for c in frame.circles:
            ring = _circle(c.center, c.radius)
            if c.kind == "item":
                mesh.fan("front", ring, _shade(c.color, pulse))
                mesh.glow(ring, ITEM_GLOW, 2.5 * width)
            else:
                across = np.r_[0.0, np.ones(len(ring)), 1.0]
                mesh.fan("ring", np.r_[[c.center], ring, ring[:1]], _shade(c.color, 0.8), c.side, across)
                mesh.glow(ring, _mix(c.color, (1.0, 1.0, 1.0, 1.0), 0.3), width)
        self._being(frame, mesh, width)
        return mesh

    def _backdrop(self, mesh: _Mesh, center, half, per_px: float) -> None:
        """The sky's gradient (drawn only while the view fades; a clear of its middle otherwise), a
        metre grid in the plane (every fifth line brighter) and a few stars fixed in the plane."""
        pal = self.palette
        (cx, cy), (hx, hy) = center, half
        lo, hi = (cx - hx, cy - hy), (cx + hx, cy + hy)
        horizon, zenith = tuple(pal["sky_horizon"]) + (1.0,), tuple(pal["sky_zenith"]) + (1.0,)
        corners = np.array([lo, (hi[0], lo[1]), hi, lo, hi, (lo[0], hi[1])])
        mesh.add("sky", corners, np.array([horizon, horizon, zenith, horizon, zenith, zenith]), 0.0, -2.0)
        line = tuple(pal["floor_line"])
        for axis in (0, 1):
            for k in range(int(math.floor(lo[axis])), int(math.ceil(hi[axis])) + 1):
                w = per_px * (1.0 if k % 5 else 1.5)
                rect = [(k - w, lo[1]), (k + w, lo[1]), (k + w, hi[1]), (k - w, hi[1])]
                if axis:
                    rect = [(lo[0], k - w), (hi[0], k - w), (hi[0], k + w), (lo[0], k + w)]
                mesh.fan("back", rect, line + (0.12 if k % 5 == 0 else 0.05,))
        cells = np.stack(np.meshgrid(np.arange(lo[0] // 2, hi[0] // 2 + 1), np.arange(lo[1] // 2, hi[1] // 2 + 1)), -1)
        cells = cells.reshape(-1, 2)
        noise = np.modf(np.sin(cells @ (12.9898, 78.233)) * 43758.5453)[0] % 1.0  # the same stars at the same place
        r = 1.2 * per_px
        for x, y in 2.0 * cells[noise > 0.93] + 2.0 * noise[noise > 0.93, None]:
            mesh.fan("back", [(x - r, y - r), (x + r, y - r), (x + r, y + r), (x - r, y + r)], (0.9, 0.93, 1.0, 0.55))

    def _being(self, frame: FlatFrame, mesh: _Mesh, width: float) -> None:
        (x, y), (w, h), f = frame.being, frame.being_size, frame.facing
        c = 0.12  # chamfer, metres
        body = np.array(
            [(x - w / 2 + c, y), (x + w / 2 - c, y), (x + w / 2, y + c), (x + w / 2, y + h - c)]
            + [(x + w / 2 - c, y + h), (x - w / 2 + c, y + h), (x - w / 2, y + h - c), (x - w / 2, y + c)]
        )
        color = BLOCKED if frame.z_blocked else BEING
        mesh.fan("front", body, color)
        mesh.glow(body, color, width)
        mesh.fan("front", _circle((x + f * w * 0.22, y + h * 0.82), 0.07, 12), EYE)

    # ---------------------------------------------------------------- the z bar
    def _bar_quads(self, frame: FlatFrame, width: int, height: int, alpha: float) -> np.ndarray:
        """The z bar beside the view: ``(n, 12) float32`` HUD quads."""
        q = QuadList()
        s = scaled(max(1, height // 300))
        bar_w = max(6, width // 110)
        x0 = width - max(4, width // 64) - bar_w
        y0, y1 = int(height * 0.22), int(height * 0.8)
        lo, hi = frame.z_range
        span = max(hi - lo, 1e-9)

        def y_of(z: float) -> int:
            return int(round(y0 + (hi - min(max(z, lo), hi)) / span * (y1 - y0)))

        def a(color, k=1.0):
            return color[:3] + (color[3] * alpha * k,)

        q.rect(x0, y0, bar_w, y1 - y0, a(BAR_TRACK))
        for z in (lo, 0.0, hi) if lo <= 0.0 <= hi else (lo, hi):
            q.rect(x0 - 2 * s, y_of(z), bar_w + 4 * s, s, a(BAR_TEXT, 0.6))
        line = BLOCKED if frame.z_blocked else PLANE_LINE
        title = f"z {frame.z:+.2f}"
        q.text(title, x0 + bar_w - text_width(title, s), y0 - (GLYPH_H + 16) * s, s, a(line))
        q.text("+z", x0 + bar_w - text_width("+z", s), y0 - (GLYPH_H + 5) * s, s, a(BAR_TEXT, 0.8))
        q.text("-z", x0 + bar_w - text_width("-z", s), y1 + 5 * s, s, a(BAR_TEXT, 0.8))
        for pin in frame.pins:
            py = y_of(pin.z)
            size = (5 if pin.in_plane else 3) * s
            for i in range(-size, size + 1):  # a diamond
                half = size - abs(i)
                q.rect(x0 + bar_w // 2 - half, py + i, 2 * half + 1, 1, a(pin.color))
            way = "here" if abs(pin.dx) < 1.0 else f"{'>' if pin.dx > 0 else '<'} {abs(pin.dx):.0f} m"
            label = f"{pin.key} {way}"
            q.text(label, x0 - 8 * s - text_width(label, s), py - GLYPH_H * s // 2, s, a(pin.color))
        py = y_of(frame.z)
        q.rect(x0 - 6 * s, py - s, bar_w + 12 * s, 2 * s + 1, a(line))
        return q.array()

    # ---------------------------------------------------------------- the turn to 3D
    def _draw_3d(self, frame: FlatFrame, viewport) -> None:
        """The 3D world, the camera turning from the flat view (straight on, at the being) to one
        from above and aside that takes in the whole level."""
        t = frame.reveal
        e = t * t * (3.0 - 2.0 * t)  # smoothstep: the turn starts and ends gently
        lo, hi = _bounds(frame)
        start = np.array([*frame.center, frame.z])
        end = (lo + hi) / 2.0
        pivot = start + e * (end - start)
        aspect = viewport[2] / max(1, viewport[3])
        near = frame.half_height / math.tan(math.radians(REVEAL_FOV) / 2.0)
        far = 0.6 * (hi[0] - lo[0]) / aspect / math.tan(math.radians(REVEAL_FOV) / 2.0)
        distance = near + e * (max(far, near) - near)
        yaw, pitch = math.radians(28.0) * e, -math.radians(36.0) * e
        cam = Camera3(np.zeros(3), yaw, pitch, fov_y_deg=REVEAL_FOV, far=4.0 * distance + 100.0)
        cam.position = pivot - distance * cam.forward()
        scene = Frame(cam, hud=Hud(crosshair=False, w_min=0.0, w_max=0.0), sky="dome", time=frame.time)
        for s in frame.solids3:
            scene.drawables.append(Drawable(f"flat3:{s.key}", *self._mesh3(s.key, s.solid, s.color)))
        for b in frame.balls3:
            solid = sphere_solid(b.center, b.radius, 3)
            scene.drawables.append(Drawable(f"flat3:{b.key}", self._revision(b.center), _trimesh(solid, b.color)))
        scene.drawables += self._plane(frame, lo, hi)
        self.renderer.draw(scene, viewport, hud=False, view="flatland")

    def _mesh3(self, key: str, solid: Solid3, color) -> tuple[int, TriMesh3]:
        """``(revision, mesh)`` of a solid, built again only when it moved (a crate)."""
        revision = self._revision(solid.vertices)
        kept = self._meshes3.get(key)
        if kept is None or kept[0] != revision:
            kept = self._meshes3[key] = (revision, _trimesh(solid, color))
        return kept

    @staticmethod
    def _revision(position) -> int:
        return hash(np.asarray(position, np.float64).tobytes()) & 0x7FFFFFFF

    def _plane(self, frame: FlatFrame, lo: np.ndarray, hi: np.ndarray) -> list[Drawable]:
        """The being's plane as a sheet across the level, the sections in it glowing, the being on it."""
        z = frame.z
        mid, size = (lo + hi) / 2.0, hi - lo
        sheet = box_solid((mid[0], mid[1], z), (size[0] + 4.0, size[1] + 4.0, 0.01))
        key = self._revision((z, *lo, *hi))
        out = [Drawable("flat3:plane", key, _trimesh(sheet, (0.35, 0.75, 1.0, 0.9)), style="ghost")]
        cuts = [prism_solid(p.points, z - 0.03, z + 0.03) for p in frame.pieces]
        (x, y), (w, h) = frame.being, frame.being_size
        cuts.append(box_solid((x, y + h / 2, z), (w, h, 0.08)))
        for i, cut in enumerate(cuts):
            color = BEING if i == len(cuts) - 1 else (0.55, 0.95, 1.0, 1.0)
            out.append(Drawable(f"flat3:cut{i}", self._revision(cut.vertices), _trimesh(cut, color), style="glow"))
        return out

    def release(self) -> None:
        for obj in (*self._vaos.values(), self._vbo, *self.programs.values()):
            obj.release()
        if self._own_renderer:
            self.renderer.release()


def _bounds(frame: FlatFrame) -> tuple[np.ndarray, np.ndarray]:
    """Corners ``(3,), (3,)`` of the box holding the 3D world's solids and balls."""
    pts = [s.solid.vertices for s in frame.solids3] + [
        np.array([b.center - b.radius, b.center + b.radius]) for b in frame.balls3
    ]
    allp = np.concatenate(pts) if pts else np.array([[*frame.center, frame.z]])
    return allp.min(axis=0), allp.max(axis=0)


def _trimesh(solid: Solid3, color) -> TriMesh3:
    """A solid as a flat-shaded triangle mesh (each triangle its own three vertices)."""
    tri = solid.triangles.astype(np.int64)
    v = solid.vertices[tri].reshape(-1, 3)
    n = np.cross(v[1::3] - v[0::3], v[2::3] - v[0::3])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    rgba = np.broadcast_to(np.asarray(tuple(color)[:3] + (tuple(color) + (1.0,))[3:4], np.float32), (len(v), 4))
    return TriMesh3(
        v.astype(np.float32),
        np.arange(len(v), dtype=np.uint32).reshape(-1, 3),
        np.repeat(n, 3, axis=0).astype(np.float32),
        np.ascontiguousarray(rgba),
    )


__all__ = ["FlatRenderer"]
