"""The editor's handles on the selection: move, rotate and scale (ImGuizmo's, for x y z) and the
editor's own for w: the w handle (a bar beside the selection: drag it up for ana, down for kata),
the rings of the three rotations that include w (xw, yw, zw: drag around a ring to turn in its
plane) and the hyper-depth handle (the w scale) while scaling.

A drag is one undo step. Each frame of a drag redoes the whole change from where the drag began
(the model's text then), so snapping works on the total: with snapping on (G), a move puts the
first selected entry on the grid, a turn goes by angle steps and w by w steps
(:mod:`across_dimensions.world.level_group`).
"""

from __future__ import annotations

import math

import numpy as np
from imgui_bundle import imgui, imguizmo

from ...core.transform import rotation4
from ...world import level_group as group
from ...world.level_edit import model_of

OPERATIONS = ("move", "rotate", "scale")
W_RINGS = (("xw", 112, (1.0, 0.35, 0.85, 1.0)), ("yw", 128, (0.3, 0.9, 1.0, 1.0)), ("zw", 144, (1.0, 0.6, 0.2, 1.0)))
RING_LABEL_DEG = {"xw": 20.0, "yw": 45.0, "zw": 70.0}  # where on its ring each plane's name is written
RING_GRAB = 7  # pixels either side of a ring that grab it
W_BAR = (110, 60)  # the w handle: pixels right of the selection (beyond the x arrow), half its height
W_PER_PIXEL = 0.01  # w moved per pixel dragged on the w handle
DEPTH_PER_PIXEL = 0.01  # hyper-depth factor (log) per pixel dragged on its handle


def _m16(m) -> imguizmo.im_guizmo.Matrix16:
    """ImGuizmo takes OpenGL's column-major matrices: the transpose of ours, flattened."""
    return imguizmo.im_guizmo.Matrix16(list(np.asarray(m, np.float64).T.ravel()))


class Handles:
    """The handles of an :class:`~.mode.EditorView` on its model's selection."""

    def __init__(self, mode):
        self.mode = mode
        self.operation = "move"
        self.snapping = False
        self.grid, self.angle_step, self.w_step = group.GRID, group.ANGLE_STEP, group.W_STEP
        self._gizmo = None  # (text before, refs) while ImGuizmo's handle is dragged
        self._own = None  # (what, text before, refs, start mouse (2,), extra) while one of ours is
        self.screen_center = None  # the selection's pivot on screen (top-left origin), when in front

    @property
    def model(self):
        return self.mode.model

    def refs(self) -> list:
        return [r for r in self.model.selected if self.model.exists(r)]

    def steps(self) -> tuple[float, float, float]:
        return (self.grid, self.angle_step, self.w_step) if self.snapping else (0.0, 0.0, 0.0)

    # ------------------------------------------------------------ drawing
    def draw(self, width: int, height: int) -> None:
        g = imguizmo.im_guizmo
        g.begin_frame()
        refs = self.refs()
        center = group.pivot(self.model, refs) if refs else None
        self.screen_center = None
        if center is None:
            self._gizmo = None
            return
        cam = self.mode.cam.camera3()
        view, proj = cam.view_matrix(), cam.projection_matrix(width / max(height, 1))
        clip = proj @ view @ np.array([*center[:3], 1.0])
        if clip[3] > 0:
            self.screen_center = np.array([(clip[0] / clip[3] + 1) * width / 2, (1 - clip[1] / clip[3]) * height / 2])
        g.set_drawlist(imgui.get_background_draw_list())
        g.allow_axis_flip(False)  # +x +y +z always point their true way (ImGuizmo flips them to face you)
        g.set_rect(0.0, 0.0, float(width), float(height))
        start = np.eye(4)
        start[:3, 3] = center[:3]
        # During a drag ImGuizmo is given the drag's whole transform so far: some of its operations
        # add each frame's change to the matrix they are given.
        obj = _m16(self._gizmo[3] if self._gizmo is not None else start)
        grid, angle, _ = self.steps()
        op = {"move": g.OPERATION.translate, "rotate": g.OPERATION.rotate, "scale": g.OPERATION.scale}[self.operation]
        snap = {"move": grid, "rotate": angle, "scale": 0.1 if self.snapping else 0.0}[self.operation]
        snap_m = imguizmo.im_guizmo.Matrix3([snap] * 3) if snap else None
        if self._own is None and g.manipulate(_m16(view), _m16(proj), op, g.MODE.world, obj, None, snap_m):
            self._gizmo_changed(refs, center, np.asarray(obj.values, np.float64).reshape(4, 4).T)
        if not g.is_using() and self._gizmo is not None:
            self._gizmo = None
            self.model.seal()
        self._draw_own(center)

    def _gizmo_changed(self, refs, center, now) -> None:
        if self._gizmo is None:
            self._gizmo = (self.model.text(), list(refs), center.copy(), now)
        before, refs, c0, _ = self._gizmo
        self._gizmo = (before, refs, c0, now)
        self.model.restore_text(before)  # the whole drag is redone from its start
        grid, angle, w_step = self.steps()
        if self.operation == "move":
            d = now[:3, 3] - c0[:3]
            group.move(self.model, refs, [*d, 0.0], grid=grid, merge=True)
        elif self.operation == "rotate":
            r4 = np.eye(4)
            r4[:3, :3] = now[:3, :3]
            group.turn(self.model, refs, r4, c0, label="rotate", merge=True)
        else:
            f = [float(np.linalg.norm(now[:3, i])) for i in range(3)]
            group.scale(self.model, refs, [*f, 1.0], merge=True)

    def _draw_own(self, center) -> None:
        """The w handle, and the w rings (rotate) or the hyper-depth handle (scale)."""
        if self.screen_center is None:
            return
        dl = imgui.get_background_draw_list()
        sx, sy = self.screen_center
        col = imgui.color_convert_float4_to_u32
        if self.operation == "rotate":
            for plane, radius, c in W_RINGS:
                hot = self._own is not None and self._own[4] == plane
                dl.add_circle(imgui.ImVec2(sx, sy), radius, col(imgui.ImVec4(*c)), 64, 4.0 if hot else 2.0)
                a = math.radians(RING_LABEL_DEG[plane])  # each label at its own angle: they never overlap
                at = imgui.ImVec2(sx + radius * math.cos(a) + 4, sy - radius * math.sin(a) - 14)
                dl.add_text(at, col(imgui.ImVec4(*c)), plane)
            return
        bx, half = sx + W_BAR[0], W_BAR[1]
        white = col(imgui.ImVec4(0.85, 0.85, 1.0, 1.0))
        if self.operation == "scale":  # the hyper-depth: a horizontal bar under the selection
            if not self._hyper():
                return
            y = sy + W_BAR[0]
            dl.add_line(imgui.ImVec2(sx - half, y), imgui.ImVec2(sx + half, y), white, 2.0)
            dl.add_rect_filled(imgui.ImVec2(sx - 6, y - 6), imgui.ImVec2(sx + 6, y + 6), white)
            dl.add_text(imgui.ImVec2(sx + half + 6, y - 7), white, "hyper-depth (w scale)")
            return
        dl.add_line(imgui.ImVec2(bx, sy - half), imgui.ImVec2(bx, sy + half), white, 2.0)
        dl.add_circle_filled(imgui.ImVec2(bx, sy), 7.0, white)
        dl.add_text(imgui.ImVec2(bx + 10, sy - 7), white, f"w {center[3]:+.2f}")
        dl.add_text(imgui.ImVec2(bx - 12, sy - half - 16), white, "ana")
        dl.add_text(imgui.ImVec2(bx - 14, sy + half + 2), white, "kata")

    def _hyper(self) -> bool:
        """Does a selected entry have a hyper-depth (a ``scale`` with a w part: a 4D object)?"""
        return any(getattr(model_of(r).get("scale"), "n", 0) == 4 for r in self.refs())

    # ------------------------------------------------------------ our own handles' drags
    def grab(self, x: float, y: float) -> bool:
        """A press at ``(x, y)`` (pixels, top-left origin): True when it took one of our handles."""
        if self.screen_center is None:
            return False
        sx, sy = self.screen_center
        what = None
        if self.operation == "rotate":
            r = math.hypot(x - sx, y - sy)
            what = next((p for p, radius, _ in W_RINGS if abs(r - radius) <= RING_GRAB), None)
        elif self.operation == "scale":
            if self._hyper() and abs(y - (sy + W_BAR[0])) <= 8 and abs(x - sx) <= W_BAR[1]:
                what = "depth"
        elif abs(x - (sx + W_BAR[0])) <= 10 and abs(y - sy) <= W_BAR[1]:
            what = "w"
        if what is None:
            return False
        self._own = ("own", self.model.text(), self.refs(), np.array([x, y], float), what)
        return True

    def drag(self, x: float, y: float) -> None:
        """The mouse is at ``(x, y)`` while one of our handles is held."""
        if self._own is None:
            return
        _, before, refs, start, what = self._own
        self.model.restore_text(before)  # the whole drag is redone from its start
        _, angle, w_step = self.steps()
        if what == "w":
            group.move(self.model, refs, [0, 0, 0, (start[1] - y) * W_PER_PIXEL], w_step=w_step, merge=True)
        elif what == "depth":
            f = math.exp((x - start[0]) * DEPTH_PER_PIXEL)
            group.scale(self.model, refs, [1.0, 1.0, 1.0, f], step=0.1 if self.snapping else 0.0, merge=True)
        else:
            sx, sy = self.screen_center
            a0 = math.atan2(start[1] - sy, start[0] - sx)
            deg = math.degrees(math.atan2(y - sy, x - sx) - a0)
            deg = (deg + 180.0) % 360.0 - 180.0
            deg = group.snap(deg, angle)
            group.turn(self.model, refs, rotation4(what, math.radians(deg)), label=f"rotate in {what}", merge=True)

    def release(self) -> bool:
        """The mouse button went up: True when it ended a drag of ours."""
        if self._own is None:
            return False
        self._own = None
        self.model.seal()
        return True

    @property
    def busy(self) -> bool:
        """A handle is being dragged."""
        return self._own is not None or self._gizmo is not None
