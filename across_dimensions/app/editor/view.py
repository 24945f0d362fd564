"""What the editor shows, as game frames: no window, no GUI, testable headless.

The editor views the level through a *preview game*: a :class:`~across_dimensions.game.sim.Game`
built from the edited level and never stepped. Its player is only a camera
holder: the editor puts it at the editor's camera and at the w scrubber's
slice, so every system's ``draw`` (sections, scenery, radar) shows the level
exactly as play would, and the game being played (if any) is not touched.
Simulated time is set directly (``game.tick``) to preview spin.

Also here: clicking in the view (a ray against every entry's bounds at the
slice), the selected entry's outline, the strip of previews of its section at
several w, and the frustum projection of the 4D entities.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...core.frustum import focal_length, frustum_project
from ...core.mesh import TriMesh3
from ...core.transform import translation
from ...game.frame import Camera3, Drawable, Frame, Hud
from ...game.player import EYE_HEIGHT, MAX_PITCH
from ...world.geometry import box_trimesh
from ...world.scene import SectionCache

#: Field of view of the 4D camera in frustum view: a point at the slice's w keeps its
#: size (it is ``focal_length`` in front of the camera); ana (+w) shrinks, kata grows.
FRUSTUM_FOV_DEG = 60.0
#: Entities farther than this along w from the slice are left out of the frustum view
#: (behind the 4D camera or too small to see; it also bounds the per-frame cost).
FRUSTUM_W_REACH = 4.0
SELECT_COLOR = (1.0, 0.85, 0.1, 1.0)
SPAWN_SIZE = (0.6, 1.75, 0.6)  # the walker's bounds, to show and pick the spawn point
SPAWN_RISE = 1.0  # the editor starts this far above the player's eye at the spawn: a designer's overview
OUTLINE_GROW = 1.02  # the outline sits just outside the box so it is not hidden in it
PITCH_LIMIT = 1.5  # radians: the editor camera stops short of straight up or down


@dataclass
class EditorCamera:
    """The editor's free camera: an eye ``position (3,) float64``, yaw and pitch (radians), and the slice's w."""

    position: np.ndarray = field(default_factory=lambda: np.array([0.0, 3.0, -8.0]))
    yaw: float = 0.0
    pitch: float = -0.2
    w: float = 0.0
    fov_deg: float = 75.0

    def camera3(self) -> Camera3:
        return Camera3(self.position.copy(), self.yaw, self.pitch, fov_y_deg=self.fov_deg)

    def fly(self, forward: float, right: float, up: float, distance: float) -> None:
        """Move along the view direction, its right and world up by ``distance`` metres times each axis."""
        cam = self.camera3()
        f = cam.forward()
        r = np.array([np.cos(self.yaw), 0.0, -np.sin(self.yaw)])
        self.position = self.position + distance * (forward * f + right * r + up * np.array([0.0, 1.0, 0.0]))

    def look(self, dyaw: float, dpitch: float) -> None:
        self.yaw += dyaw
        self.pitch = float(np.clip(self.pitch + dpitch, -PITCH_LIMIT, PITCH_LIMIT))

    @classmethod
    def at_spawn(cls, level) -> EditorCamera:
        """A little above the player's eye at the spawn point, looking along the spawn's yaw."""
        eye = level.spawn[:3] + np.array([0.0, EYE_HEIGHT + SPAWN_RISE, 0.0])
        return cls(eye, float(np.radians(level.spawn_yaw_deg)), -0.15, float(level.spawn[3]))


def place(game, cam: EditorCamera) -> None:
    """Put the preview game's player at the editor camera and slice (the frame is drawn from there)."""
    p = game.player
    p.position = np.array([cam.position[0], cam.position[1] - EYE_HEIGHT, cam.position[2], cam.w])
    p.yaw, p.pitch = float(cam.yaw), float(cam.pitch)
    game.reset_interpolation()  # no tick in between: draw exactly at the camera


def game_at(level, cam: EditorCamera | None = None, seed: int = 0):
    """A new game of ``level``; with ``cam``, its player starts at the camera's place, heading and w
    (w kept inside the level's range) instead of the spawn: "play from here"."""
    from ...game.sim import Game

    game = Game(level, seed=seed)
    if cam is not None:
        lo, hi = level.w_range
        p = game.player
        c = cam.position
        p.position = np.array([c[0], c[1] - EYE_HEIGHT, c[2], float(np.clip(cam.w, lo, hi))])
        p.yaw, p.pitch = float(cam.yaw), float(np.clip(cam.pitch, -MAX_PITCH, MAX_PITCH))
        game.reset_interpolation()  # no interpolation from the spawn
    return game


def entity_of(game, ref):
    """The preview game's entity for an entry (``("object", i)``, ``("crystal", i)``, ...), or None."""
    if len(ref) != 2:
        return None
    kind, i = ref
    if kind == "object":
        found = [e for e in game.entities if e.kind in ("object", "body")]
    else:
        found = game.entities.of_kind(kind)
    return found[i] if i < len(found) else None


def entry_box(level, ref) -> tuple[np.ndarray, np.ndarray] | None:
    """Axis-aligned bounds ``(lo, hi)`` of a 3D entry (box, goal, spawn, a world's box), or None."""
    if ref[0] == "box" and len(ref) == 2 and ref[1] < len(level.boxes):
        b = level.boxes[ref[1]]
    elif ref[0] == "world" and len(ref) == 4 and ref[2] == "box":
        boxes = level.worlds[ref[1]].boxes if ref[1] < len(level.worlds) else []
        if ref[3] >= len(boxes):
            return None
        b = boxes[ref[3]]
    elif ref == ("goal",):
        b = level.goal
    elif ref == ("spawn",):
        c = level.spawn[:3] + np.array([0.0, SPAWN_SIZE[1] / 2, 0.0])
        return c - np.array(SPAWN_SIZE) / 2, c + np.array(SPAWN_SIZE) / 2
    else:
        return None
    return b.center - b.size / 2, b.center + b.size / 2


def editor_frame(game, cam: EditorCamera, selected=None, frustum: bool = False, time: float = 0.0) -> Frame:
    """The level seen from the editor camera at its slice.

    Parameters
    ----------
    game : Game
        The preview game (see the module docstring); its player is moved to ``cam``.
    selected : tuple, optional
        The selected entry's reference; it is outlined.
    frustum : bool
        Draw the 4D entities by frustum projection from ``FRUSTUM_FOV_DEG`` instead of their sections.
    time : float
        Simulated seconds, for the spin of 4D objects.
    """
    game.tick = int(round(time / game.dt))
    place(game, cam)
    frame = game.frame(alpha=1.0, fov_y_deg=cam.fov_deg)
    frame.hud.message = ""
    if frustum:
        frame.drawables = [d for d in frame.drawables if not d.key.startswith("entity:")]
        frame.batches = [b for b in frame.batches if not b.key.startswith("entities:")]
        frame.sky_boxes = None  # a door's box no longer drawn where it stood must not hide the sky
        frame.drawables.extend(frustum_drawables(game, cam.w))
    if selected is not None:
        frame.drawables.extend(outline(game, selected, cam.w))
    return frame


_revision = [0]


def _next_revision() -> int:
    """A new revision for meshes made anew each frame (the renderer uploads a mesh when it changes)."""
    _revision[0] += 1
    return _revision[0]


def _tinted(tri: TriMesh3) -> TriMesh3:
    """``tri`` in the selection colour."""
    colors = np.tile(np.asarray(SELECT_COLOR, np.float32), (len(tri.vertices), 1))
    return TriMesh3(tri.vertices, tri.faces, tri.normals, colors, tri.depth)


def frustum_drawables(game, w: float) -> list[Drawable]:
    """Each 4D entity near the slice, projected by a 4D camera looking along +w from ``focal_length`` before
    the slice at the entity's own xyz (so its section at the slice keeps its size and place)."""
    f = focal_length(FRUSTUM_FOV_DEG)
    rev = _next_revision()  # projected anew every frame
    out = []
    for e in game.entities:
        if e.mesh is None:
            continue
        model = e.model(game, 1.0)
        c = model[:4, 4]
        if abs(c[3] - w) > FRUSTUM_W_REACH + e.radius:
            continue
        tri = frustum_project(e.mesh, translation((c[0], c[1], c[2], w - f)), FRUSTUM_FOV_DEG, model=model)
        place_xyz = np.eye(4)
        place_xyz[:3, 3] = c[:3]
        out.append(Drawable(f"frustum:{e.id}", rev, tri, place_xyz, style="ghost"))
    return out


def outline(game, ref, w: float) -> list[Drawable]:
    """The selected entry drawn as a yellow wireframe: its bounds, or its section at ``w``."""
    level = game.level
    box = entry_box(level, ref)
    if box is not None and ref[0] == "world" and ref[1] < len(game.scene.worlds):
        parts = game.scene.worlds[ref[1]].boxes_at(w)  # as sliced at w (the full box where it is absent)
        if ref[3] < len(parts) and not np.isnan(parts[ref[3]]).any():
            box = parts[ref[3]]
    if box is not None:
        lo, hi = box
        mesh = box_trimesh((lo + hi) / 2, (hi - lo) * OUTLINE_GROW, SELECT_COLOR)
        return [Drawable("editor:outline", _next_revision(), mesh, style="wire")]
    e = entity_of(game, ref)
    if e is None and ref[0] == "world" and len(ref) == 2 and ref[1] < len(game.scene.worlds):
        tri, _ = game.sections.section("editor:world", game.scene.worlds[ref[1]].mesh, np.eye(5), w)
        return [Drawable("editor:outline", _next_revision(), _tinted(tri), style="wire")]
    if e is None:
        return []
    tri, _ = game.sections.section("editor:sel", e.mesh, e.model(game, 1.0), w)
    return [Drawable("editor:outline", _next_revision(), _tinted(tri), style="wire")]


# ------------------------------------------------------------------ picking
def ray(cam: EditorCamera, x: float, y: float, aspect: float) -> tuple[np.ndarray, np.ndarray]:
    """World ray ``(origin (3,), unit direction (3,))`` through the view at normalized ``x, y`` in [-1, 1]."""
    c3 = cam.camera3()
    inv = np.linalg.inv(c3.projection_matrix(aspect) @ c3.view_matrix())
    near = inv @ np.array([x, y, -1.0, 1.0])
    far = inv @ np.array([x, y, 1.0, 1.0])
    a, b = near[:3] / near[3], far[:3] / far[3]
    d = b - a
    return a, d / np.linalg.norm(d)


def _hit_box(o, d, lo, hi) -> float | None:
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (lo - o) / d, (hi - o) / d
    t1, t2 = np.nan_to_num(np.minimum(t1, t2), nan=-np.inf), np.nan_to_num(np.maximum(t1, t2), nan=np.inf)
    tin, tout = float(np.max(t1)), float(np.min(t2))
    if tin > tout or tout < 0:
        return None
    return max(tin, 0.0)


def _hit_sphere(o, d, c, r) -> float | None:
    oc = o - c
    b = float(oc @ d)
    disc = b * b - float(oc @ oc) + r * r
    if disc < 0:
        return None
    t = -b - np.sqrt(disc)
    return t if t >= 0 else (-b + np.sqrt(disc) if -b + np.sqrt(disc) >= 0 else None)


def pick(game, cam: EditorCamera, x: float, y: float, aspect: float, refs) -> tuple | None:
    """The entry under the view point ``x, y`` (normalized, y up): the nearest one the ray meets at the slice.

    4D entities are hit as the sphere of their section's reach at the slice; boxes by their bounds
    (a world's boxes only where the world is present).
    """
    o, d = ray(cam, x, y, aspect)
    level, w = game.level, cam.w
    best, best_t = None, np.inf
    for ref in refs:
        t = None
        box = entry_box(level, ref)
        if box is not None:
            if ref[0] == "world":  # a world's box as sliced at w: shrunk by the profile, or absent
                parts = game.scene.worlds[ref[1]].boxes_at(w) if ref[1] < len(game.scene.worlds) else []
                if ref[3] >= len(parts) or np.isnan(parts[ref[3]]).any():
                    continue
                box = parts[ref[3]]
            t = _hit_box(o, d, *box)
        else:
            e = entity_of(game, ref)
            if e is None or e.mesh is None:
                continue
            c = e.center(game)
            dw = abs(float(c[3]) - w)
            if dw >= e.radius:
                continue
            t = _hit_sphere(o, d, c[:3], np.sqrt(e.radius**2 - dw**2))
        # Boxes that contain the camera (the floor under it, a wall it is in) are hit at t = 0 and
        # would hide everything; the entry hit farther out but entered is the one meant.
        if t is not None and 0 < t < best_t:
            best, best_t = ref, t
    return best


# ------------------------------------------------------------------ previews
def preview_frames(game, ref, w: float, offsets, cache: SectionCache, time: float = 0.0) -> list[tuple[float, Frame]]:
    """The selected 4D entry alone, sliced at ``w + offset`` for each offset, seen from a fixed 3/4 view.

    Returns one ``(w, Frame)`` per offset; an empty list when ``ref`` is not a 4D entry (boxes are the
    same at every w). ``cache`` keeps the slices between frames.
    """
    e = entity_of(game, ref)
    game.tick = int(round(time / game.dt))
    if e is not None and e.mesh is not None:
        mesh, model, r = e.mesh, e.model(game, 1.0), max(e.radius, 0.1)
        center = model[:3, 4]
    elif ref[0] == "world" and ref[1] < len(game.scene.worlds):
        world = game.scene.worlds[ref[1]]
        mesh, model = world.mesh, np.eye(5)
        lo, hi = world.centers.min(0) - world.halves.max(), world.centers.max(0) + world.halves.max()
        center, r = (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2)
    else:
        return []
    yaw, pitch = 0.6, -0.45
    cam3 = Camera3(np.zeros(3), yaw, pitch, fov_y_deg=50.0)
    eye = center - 2.6 * r * cam3.forward()
    out = []
    for k, dw in enumerate(offsets):
        key = f"preview:{'/'.join(map(str, ref))}:{k}"  # one cache entry per entry: another mesh, another key
        tri, rev = cache.section(key, mesh, model, w + dw)
        frame = Frame(Camera3(eye, yaw, pitch, fov_y_deg=50.0, w=w + dw), hud=Hud(w=w + dw))
        frame.drawables.append(Drawable(key, rev, tri, style=e.style if e is not None else "solid"))
        out.append((w + dw, frame))
    return out
