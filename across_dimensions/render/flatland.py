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
from .hud import _QuadList, hud_quads
from .renderer import Renderer

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
FLOATS = 9  # per vertex: x, y | r, g, b, a | across (glow) or radius (rings) | kind | cue

_VS = """
#version 330
uniform vec2 u_center;
uniform vec2 u_half;
in vec2 in_pos;
in vec4 in_color;
in float in_across;
in float in_kind;
in float in_cue;
out vec4 v_color;
out vec2 v_world;
out float v_across;
out float v_kind;
out float v_cue;
void main() {
    v_color = in_color; v_world = in_pos; v_across = in_across; v_kind = in_kind; v_cue = in_cue;
    gl_Position = vec4((in_pos - u_center) / u_half, 0.0, 1.0);
}
"""

_FS = """
#version 330
uniform float u_alpha;
uniform vec3 u_ana;
uniform vec3 u_kata;
in vec4 v_color;
in vec2 v_world;
in float v_across;
in float v_kind;
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
void main() {
    vec3 c = v_color.rgb;
    float a = v_color.a;
    if (v_kind < 0.5) {                      // a panel: seams every metre
        vec2 g = abs(fract(v_world + 0.5) - 0.5);
        c *= 1.0 - 0.3 * (1.0 - smoothstep(0.0, 0.025, min(g.x, g.y)));
        if (v_cue > -1.5) c = cue_bands(c, v_world.x + v_world.y, v_cue);
    } else if (v_kind < 1.5) {               // a glow across a line: added on top
        float t = 1.0 - abs(v_across);
        a *= t * t;
    } else if (v_kind < 2.5) {               // flat colour
    } else {                                 // a ball's circle: rings by radius
        c = cue_bands(c, v_across * 2.0, v_cue);
        c *= 0.75 + 0.25 * (1.0 - v_across * v_across);
    }
    f_color = vec4(c, a * u_alpha);
}
"""

_BG_VS = """
#version 330
in vec2 in_pos;
out vec2 v_ndc;
void main() { v_ndc = in_pos; gl_Position = vec4(in_pos, 0.0, 1.0); }
"""

_BG_FS = """
#version 330
uniform vec2 u_center;
uniform vec2 u_half;
uniform vec3 u_zenith;
uniform vec3 u_horizon;
uniform vec3 u_line;
uniform float u_alpha;
in vec2 v_ndc;
out vec4 f_color;
void main() {
    vec2 w = u_center + v_ndc * u_half;
    vec3 c = mix(u_horizon, u_zenith, smoothstep(-0.6, 1.0, v_ndc.y));
    vec2 g = abs(fract(w + 0.5) - 0.5);
    float fine = 1.0 - smoothstep(0.0, 0.02, min(g.x, g.y));
    vec2 g5 = abs(fract(w / 5.0 + 0.5) - 0.5) * 5.0;
    float major = 1.0 - smoothstep(0.0, 0.03, min(g5.x, g5.y));
    c += u_line * (0.05 * fine + 0.12 * major);
    vec2 cell = floor(w * 1.7);
    float h = fract(sin(dot(cell, vec2(12.9898, 78.233))) * 43758.5453);
    float star = step(0.985, h) * (1.0 - smoothstep(0.0, 0.06, length(fract(w * 1.7) - 0.5)));
    c += vec3(star) * 0.6;
    f_color = vec4(c, u_alpha);
}
"""


class _Mesh:
    """Vertices of one frame, as rows of :data:`FLOATS`."""

    def __init__(self):
        self.rows: list[np.ndarray] = []

    def fan(self, points, color, kind: float, cue: float | None = None, across=None) -> None:
        """A convex polygon ``(k, 2)`` as triangles from its first corner."""
        p = np.asarray(points, np.float64)
        if len(p) < 3:
            return
        a = np.zeros(len(p)) if across is None else np.asarray(across, np.float64)
        idx = np.array([(0, i, i + 1) for i in range(1, len(p) - 1)]).ravel()
        self._add(p[idx], color, a[idx], kind, -2.0 if cue is None else cue)

    def glow(self, points, color, width: float, closed: bool = True) -> None:
        """A glowing line ``width`` world units either side of the polyline ``points (k, 2)``."""
        p = np.asarray(points, np.float64)
        q = np.roll(p, -1, axis=0) if closed else p[1:]
        p = p if closed else p[:-1]
        d = q - p
        n = np.c_[-d[:, 1], d[:, 0]] / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)[:, None] * width
        quads = np.stack([p - n, q - n, q + n, p - n, q + n, p + n], axis=1).reshape(-1, 2)
        across = np.tile([-1.0, -1.0, 1.0, -1.0, 1.0, 1.0], len(p))
        self._add(quads, color, across, 1.0, -2.0)

    def _add(self, xy, color, across, kind, cue) -> None:
        rows = np.empty((len(xy), FLOATS), np.float32)
        rows[:, 0:2] = xy
        rows[:, 2:6] = color
        rows[:, 6] = across
        rows[:, 7] = kind
        rows[:, 8] = cue
        self.rows.append(rows)

    def array(self) -> np.ndarray:
        return np.concatenate(self.rows) if self.rows else np.zeros((0, FLOATS), np.float32)


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
        self.program = ctx.program(vertex_shader=_VS, fragment_shader=_FS)
        self.bg = ctx.program(vertex_shader=_BG_VS, fragment_shader=_BG_FS)
        tri = np.array([[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]], np.float32)
        self._bg_vbo = ctx.buffer(tri.tobytes())
        self._bg_vao = ctx.vertex_array(self.bg, [(self._bg_vbo, "2f", "in_pos")])
        self._vbo = ctx.buffer(reserve=4096 * FLOATS * 4, dynamic=True)
        self._vao = self._make_vao()
        self._meshes3: dict[str, TriMesh3] = {}
        self.last_quads = np.zeros((0, 12), np.float32)

    def _make_vao(self) -> moderngl.VertexArray:
        return self.ctx.vertex_array(
            self.program, [(self._vbo, "2f 4f 1f 1f 1f", "in_pos", "in_color", "in_across", "in_kind", "in_cue")]
        )

    @property
    def palette(self) -> dict:
        return self.renderer.palette

    # ---------------------------------------------------------------- a frame
    def draw(self, frame: FlatFrame, viewport: tuple[int, int, int, int]) -> None:
        """Draw ``frame`` into ``viewport`` (``(x, y, w, h)``, GL convention) of the bound framebuffer."""
        viewport = tuple(int(v) for v in viewport)
        fade = 1.0 - min(1.0, frame.reveal / FADE) if frame.reveal > 0.0 else 1.0
        if frame.reveal > 0.0:
            self._draw_3d(frame, viewport)
        if fade > 0.0:
            self._draw_flat(frame, viewport, fade)
        hud = Hud(crosshair=False, w_min=0.0, w_max=0.0, hint=frame.hint, hint_label=frame.hint_label)
        hud.message = frame.line if frame.reveal >= 0.35 else frame.message
        quads = hud_quads(hud, viewport[2], viewport[3])
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
        ctx = self.ctx
        ctx.viewport = viewport
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        center, half, per_px = self._view(frame, viewport)
        pal = self.palette
        for name, value in (("u_center", center), ("u_half", half), ("u_alpha", alpha)):
            self.bg[name].value = value
        for name, key in (("u_zenith", "sky_zenith"), ("u_horizon", "sky_horizon"), ("u_line", "floor_line")):
            self.bg[name].value = tuple(pal[key])
        self._bg_vao.render(moderngl.TRIANGLES)
        panels, glows = self._geometry(frame, per_px)
        prog = self.program
        prog["u_center"].value, prog["u_half"].value = center, half
        prog["u_alpha"].value = alpha
        prog["u_ana"].value, prog["u_kata"].value = tuple(pal["ana"]), tuple(pal["kata"])
        self._render(panels)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE
        self._render(glows)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        ctx.disable(moderngl.BLEND)

    def _render(self, rows: np.ndarray) -> None:
        if not len(rows):
            return
        data = rows.astype(np.float32).tobytes()
        if len(data) > self._vbo.size:
            self._vbo.orphan(len(data) * 2)
            self._vao = self._make_vao()
        self._vbo.write(data)
        self._vao.render(moderngl.TRIANGLES, vertices=len(rows))

    def _geometry(self, frame: FlatFrame, per_px: float) -> tuple[np.ndarray, np.ndarray]:
        """The panels and the glows of a frame, as vertex rows."""
        panels, glows = _Mesh(), _Mesh()
        trim = tuple(self.palette["trim"]) + (1.0,)
        width = TRIM_PX * per_px
        (gx, gy), (sx, sy) = frame.goal
        lo, hi = (gx - sx / 2, gy - sy / 2), (gx + sx / 2, gy + sy / 2)
        beam = np.array([lo, (hi[0], lo[1]), hi, (lo[0], hi[1])])
        panels.fan(beam, GOAL[:3] + (0.22,), 2.0)
        glows.glow(np.array([(lo[0], lo[1]), (hi[0], lo[1])]), GOAL, 2 * width, closed=False)
        for piece in frame.pieces:
            panels.fan(piece.points, _shade(piece.color, PANEL_SHADE), 0.0, piece.cue)
        for outline in frame.outlines:
            glows.glow(outline.points, _mix(trim, outline.color, 0.45), width)
        pulse = 0.75 + 0.25 * math.sin(frame.time * 4.0)
        for c in frame.circles:
            ring = _circle(c.center, c.radius)
            if c.kind == "item":
                panels.fan(ring, _shade(c.color, pulse), 2.0)
                glows.glow(ring, ITEM_GLOW, 2.5 * width)
            else:
                across = np.r_[0.0, np.ones(len(ring))]
                panels.fan(np.r_[[c.center], ring, ring[:1]], _shade(c.color, 0.8), 3.0, c.side, np.r_[across, 1.0])
                glows.glow(ring, _mix(c.color, (1.0, 1.0, 1.0, 1.0), 0.3), width)
        self._being(frame, panels, glows, width)
        return panels.array(), glows.array()

    def _being(self, frame: FlatFrame, panels: _Mesh, glows: _Mesh, width: float) -> None:
        (x, y), (w, h), f = frame.being, frame.being_size, frame.facing
        c = 0.12  # chamfer, metres
        body = np.array(
            [(x - w / 2 + c, y), (x + w / 2 - c, y), (x + w / 2, y + c), (x + w / 2, y + h - c)]
            + [(x + w / 2 - c, y + h), (x - w / 2 + c, y + h), (x - w / 2, y + h - c), (x - w / 2, y + c)]
        )
        color = BLOCKED if frame.z_blocked else BEING
        panels.fan(body, color, 2.0)
        glows.glow(body, color, width)
        ex, ey, r = x + f * w * 0.22, y + h * 0.82, 0.07
        panels.fan(_circle((ex, ey), r, 12), EYE, 2.0)

    # ---------------------------------------------------------------- the z bar
    def _bar_quads(self, frame: FlatFrame, width: int, height: int, alpha: float) -> np.ndarray:
        """The z bar beside the view: ``(n, 12) float32`` HUD quads."""
        q = _QuadList()
        s = max(1, height // 300)
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
            scene.drawables.append(Drawable(f"flat3:{s.key}", 0, self._mesh3(s.key, s.solid, s.color)))
        for b in frame.balls3:
            solid = sphere_solid(b.center, b.radius, 3)
            scene.drawables.append(Drawable(f"flat3:{b.key}", self._revision(b.center), _trimesh(solid, b.color)))
        scene.drawables += self._plane(frame, lo, hi)
        self.renderer.draw(scene, viewport, hud=False, view="flatland")

    def _mesh3(self, key: str, solid: Solid3, color) -> TriMesh3:
        if key not in self._meshes3:
            self._meshes3[key] = _trimesh(solid, color)
        return self._meshes3[key]

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
        for obj in (self._vao, self._vbo, self._bg_vao, self._bg_vbo, self.program, self.bg):
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
