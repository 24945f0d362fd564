"""The physics debug overlay: a drawer that turns what the physics reports into GL lines.

:class:`LineDrawer` implements the physics' drawer interface
(:class:`~across_dimensions.physics.debug_draw.DebugDrawer`) with plain numpy
line lists, so it is usable and testable without a GPU. :class:`DebugOverlay`
draws those lines over a rendered frame, without depth test (what collides
stays visible behind walls, as in Box2D's testbed). The window calls
:meth:`DebugOverlay.draw_game` after the frame when the overlay is on.

Spheres are drawn as three great circles; box sections as their edges;
contacts as a small cross and a normal; axis-aligned boxes as their 12 edges.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..game.frame import Camera3
from ..game.player_bodies import debug_draw_game
from .shaders import FLAT_FRAGMENT, FLAT_VERTEX

#: Length (m) of a drawn contact normal, and half size of the contact cross.
NORMAL_LENGTH = 0.3
CONTACT_SIZE = 0.04

# The 12 edges of a box as pairs of corner indices (bit k of a corner = + along axis k).
_BOX_EDGES = np.array([(c, c | (1 << k)) for k in range(3) for c in range(8) if not c & (1 << k)])
_BOX_SIGNS = np.array([[1.0 if (c >> k) & 1 else -1.0 for k in range(3)] for c in range(8)])


class LineDrawer:
    """A debug drawer that collects coloured line segments.

    Parameters
    ----------
    circle_segments : int
        Segments per great circle of a sphere.
    """

    def __init__(self, circle_segments: int = 24):
        t = np.linspace(0.0, 2.0 * np.pi, circle_segments + 1)
        self._circle = np.stack([np.cos(t), np.sin(t)], axis=1)  # (n + 1, 2)
        self.clear()

    def clear(self) -> None:
        """Forget the collected lines (call once per frame)."""
        self._points: list[np.ndarray] = []
        self._colors: list[np.ndarray] = []

    def _add(self, segments: np.ndarray, color) -> None:
        seg = np.asarray(segments, dtype=np.float32).reshape(-1, 3)
        self._points.append(seg)
        self._colors.append(np.broadcast_to(np.asarray(color, np.float32), (seg.shape[0], 4)))

    # The drawer interface -------------------------------------------------
    def draw_sphere(self, body_id: int, center, radius: float, color) -> None:
        c = self._circle * float(radius)
        zero = np.zeros(c.shape[0])
        for ring in (
            np.stack([c[:, 0], c[:, 1], zero], 1),
            np.stack([c[:, 0], zero, c[:, 1]], 1),
            np.stack([zero, c[:, 0], c[:, 1]], 1),
        ):
            ring = ring + np.asarray(center, np.float64)
            self._add(np.stack([ring[:-1], ring[1:]], axis=1), color)

    def draw_section(self, body_id: int, edges, color) -> None:
        self._add(edges, color)

    def draw_contact(self, point, normal, color) -> None:
        p = np.asarray(point, np.float64)
        n = np.asarray(normal, np.float64)
        eye = np.eye(3) * CONTACT_SIZE
        cross = np.stack([p - eye, p + eye], axis=1)  # (3, 2, 3)
        self._add(cross, color)
        self._add([p, p + NORMAL_LENGTH * n], color)

    def draw_box(self, center, half_extents, color) -> None:
        corners = np.asarray(center, np.float64) + _BOX_SIGNS * np.asarray(half_extents, np.float64)
        self._add(corners[_BOX_EDGES], color)

    # Results ----------------------------------------------------------------
    def lines(self) -> tuple[np.ndarray, np.ndarray]:
        """Segment end points ``(2k, 3) float32`` and their colours ``(2k, 4) float32``."""
        if not self._points:
            return np.zeros((0, 3), np.float32), np.zeros((0, 4), np.float32)
        return np.concatenate(self._points), np.concatenate(self._colors).astype(np.float32)


class DebugOverlay:
    """Draws a :class:`LineDrawer`'s lines over the current framebuffer.

    Parameters
    ----------
    ctx : moderngl.Context
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.program = ctx.program(vertex_shader=FLAT_VERTEX, fragment_shader=FLAT_FRAGMENT)
        self.drawer = LineDrawer()
        self._vbo: moderngl.Buffer | None = None
        self._vao: moderngl.VertexArray | None = None
        self.lines_drawn = 0

    def draw(self, drawer: LineDrawer, camera: Camera3, viewport: tuple[int, int, int, int]) -> int:
        """Draw ``drawer``'s lines seen by ``camera`` into ``viewport`` of the bound framebuffer.

        Returns
        -------
        int
            Line segments drawn.
        """
        pts, cols = drawer.lines()
        self.lines_drawn = pts.shape[0] // 2
        _, _, w, h = viewport
        if self.lines_drawn == 0 or w <= 0 or h <= 0:
            return 0
        data = np.concatenate([pts, cols], axis=1).astype(np.float32).tobytes()
        if self._vbo is None or self._vbo.size < len(data):
            self._release_buffers()
            self._vbo = self.ctx.buffer(reserve=max(len(data), 4096))
            self._vao = self.ctx.vertex_array(self.program, [(self._vbo, "3f 4f", "in_pos", "in_color")])
        self._vbo.write(data)
        view_proj = camera.projection_matrix(w / h) @ camera.view_matrix()
        # GLSL matrices are column-major.
        self.program["u_view_proj"].write(np.ascontiguousarray(view_proj.T, np.float32).tobytes())
        ctx = self.ctx
        ctx.viewport = tuple(int(v) for v in viewport)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
        self._vao.render(moderngl.LINES, vertices=pts.shape[0])
        ctx.disable(moderngl.BLEND)
        return self.lines_drawn

    def draw_game(self, game, camera: Camera3, viewport: tuple[int, int, int, int], options=None) -> int:
        """The hook the window calls: the physics of ``game`` in the frame's slice (``camera.w``), and
        the player's box.

        Parameters
        ----------
        game : across_dimensions.game.sim.Game
            Read only.
        camera : Camera3
            The frame's camera (``frame.camera``).
        viewport : (x, y, w, h) ints
        options : DebugDrawOptions, optional
        """
        self.drawer.clear()
        debug_draw_game(game, self.drawer, options, w=camera.w)
        return self.draw(self.drawer, camera, viewport)

    def _release_buffers(self) -> None:
        for obj in (self._vao, self._vbo):
            if obj is not None:
                obj.release()
        self._vao = self._vbo = None

    def release(self) -> None:
        self._release_buffers()
        self.program.release()
