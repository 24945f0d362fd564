"""The projection stage: the rig and the 4D things in, the frame's meshes out.

:func:`project` is the one place where 4D content (entities with a mesh and the
extended worlds) becomes 3D meshes for a frame, in whichever way the camera rig
says:

- synced: the cross-section by the rig's slice (:meth:`.camera.CameraRig.slice_of`)
  at the player's offset, through ``game.sections`` (keys ``draw:<id>`` and
  ``world:<i>``, as the radar and the collision code expect);
- frustum and returning: :func:`~..core.frustum.frustum_project` from the rig's
  4D camera, placed in slice space by the rig's placement.

Each item is cached on the 4D pose it was made for and its own model matrix,
so an item is re-projected only when one of them changed: a still camera over
a still scene costs a comparison per item and frame. The picture-in-picture
asks for the other projection under its own keys (``other=True``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..core.frustum import frustum_project
from ..core.mesh import TetMesh4
from .camera import FRUSTUM_NEAR, CameraRig
from .entity_models import INDICATOR_KINDS
from .entity_sections import w_offset
from .frame import Drawable

#: How far beyond the slice (metres along the 4D camera's view) frustum projection
#: still draws: farther things are a few pixels and would cost as much as near ones.
FRUSTUM_REACH = 12.0


@dataclass
class Item:
    """One 4D thing to project: a drawable key, its mesh, its centre and reach, and where it is.

    ``place`` gives the object-to-world ``(5, 5)`` model when called; it is called only
    for items that survive culling (a level's many far-off entities cost no pose).
    """

    key: str
    mesh: TetMesh4
    place: Callable[[], np.ndarray]
    center: np.ndarray
    radius: float
    style: str = "solid"
    entity: int = -1

    @property
    def model(self) -> np.ndarray:
        return self.place()


class FrustumCache:
    """Frustum projections kept per key with the pose and model they were made for."""

    def __init__(self):
        self._entries: dict[str, tuple] = {}
        self.computed = 0

    def project(self, key: str, mesh: TetMesh4, model: np.ndarray, pose: np.ndarray, fov_deg: float):
        """The frustum projection of ``mesh`` placed by ``model`` from the camera at ``pose``,
        and its revision (bumped whenever it is recomputed)."""
        entry = self._entries.get(key)
        if entry is not None and np.array_equal(entry[0], pose) and np.array_equal(entry[1], model):
            return entry[2], entry[3]
        tri = frustum_project(mesh, pose, fov_deg=fov_deg, near=FRUSTUM_NEAR, model=model)
        rev = 0 if entry is None else entry[3] + 1
        self._entries[key] = (np.array(pose, copy=True), np.array(model, copy=True), tri, rev)
        self.computed += 1
        return tri, rev

    def keep(self, prefix: str, keys: set) -> None:
        """Drop every entry whose key starts with ``prefix`` and is not in ``keys``."""
        for k in [k for k in self._entries if k.startswith(prefix) and k not in keys]:
            del self._entries[k]


def world_items(game) -> list[Item]:
    """The extended worlds as items (they span the level: never culled)."""
    return [Item(f"world:{i}", w.mesh, _identity, np.zeros(4), np.inf) for i, w in enumerate(game.scene.worlds)]


def items(game, alpha: float | None) -> list[Item]:
    """Everything 4D in ``game`` to draw: extended worlds, then entities with a mesh in spawn order."""
    out = world_items(game)
    table = game.entity_table()
    for e, c in zip(table.entities, table.centers):
        if e.mesh is None or e.kind in INDICATOR_KINDS:
            continue
        out.append(Item(f"entity:{e.id}", e.mesh, partial(e.model, game, alpha), c, e.radius, e.style, e.id))
    return out


def _identity() -> np.ndarray:
    return np.eye(5)


def reaching(rig: CameraRig, things: list[Item], s: float) -> list[Item]:
    """The items the rig's slice at offset ``s`` may cut: entities whose bounding sphere
    reaches it (worlds always)."""
    centers = np.array([it.center for it in things], dtype=np.float64).reshape(-1, 4)
    offsets = np.abs(rig.to_slice(centers)[:, 3] - s)
    return [it for it, off in zip(things, offsets) if it.entity < 0 or off <= it.radius]


def cross_sections(game, rig: CameraRig, things: list[Item], s: float, prefix: str = "") -> list[Drawable]:
    """Synced: each item's section by the rig's slice at offset ``s``, with its w cue (where
    the slice cuts it along the slice's normal, see :func:`.entity_sections.w_offset`)."""
    where = rig.slice_of(s)
    pose = rig.slice_pose(s)
    shown = reaching(rig, things, s)
    if any(it.entity >= 0 for it in things):  # entities asked for: the rest left the slice
        game.sections.keep(f"{prefix}draw:", {f"{prefix}draw:{it.entity}" for it in shown if it.entity >= 0})
    out = []
    for it in shown:
        cache_key = f"{prefix}draw:{it.entity}" if it.entity >= 0 else prefix + it.key
        model = it.model
        tri, rev = game.sections.section(cache_key, it.mesh, model, where)
        cue = w_offset(it.mesh, model, pose)
        out.append(Drawable(prefix + it.key, rev, tri, style=it.style, w_offset=cue, outside_only=True))
    return out


def frustum_views(
    cache: FrustumCache,
    rig: CameraRig,
    things: list[Item],
    pose: np.ndarray,
    place: np.ndarray,
    prefix: str = "frustum:",
    fade: float = 1.0,
) -> list[Drawable]:
    """Detached: each item through the 4D camera at ``pose``, placed in slice space by ``place``;
    with ``fade < 1``, as ghosts of that opacity (over the cross-section, at the end of a return)."""
    focal = rig.focal
    keep, out = set(), []
    view = pose[:4, 3]  # the camera's w axis: where it looks
    for it in things:
        if np.isfinite(it.radius):
            depth = float(np.dot(it.center - pose[:4, 4], view))
            if depth + it.radius < FRUSTUM_NEAR or depth - it.radius > focal + FRUSTUM_REACH:
                continue  # wholly behind the camera, or too far along its view to matter
        key = prefix + it.key
        keep.add(key)
        tri, rev = cache.project(key, it.mesh, it.model, pose, rig.fov_deg)
        if fade < 1.0:
            out.append(Drawable(key, rev, tri, model=place, style="ghost", opacity=fade))
        else:
            # w_offset 0: drawn as 4D matter, like its cross-section, without the w cue's bands
            # (a frustum image shows the whole thing, not where a slice cuts it).
            out.append(Drawable(key, rev, tri, model=place, style=it.style, w_offset=0.0))
    cache.keep(prefix, keep)
    return out


def project(game, rig: CameraRig, things: list[Item], eye: np.ndarray, other: bool = False) -> list[Drawable]:
    """The frame's meshes of ``things`` as the rig shows them from ``eye (4,)`` (the frame's
    4D eye, :attr:`.frame.Camera3.eye4`); with ``other``, the projection the rig is *not* in
    (the picture-in-picture): frustum from the synced 4D camera while synced, the
    cross-section while detached."""
    xyz, s = eye[:3], float(eye[3])
    if rig.detached == other:  # synced now, or the inset of a detached view
        return cross_sections(game, rig, things, s, prefix="pip:" if other else "")
    if rig.cache is None:
        rig.cache = FrustumCache()
    if other:  # synced: what the switch would show, from the 4D camera in sync with the eye
        pose, place = rig.frustum_pose(xyz, s)
        return frustum_views(rig.cache, rig, things, pose, place, prefix="pip-frustum:")
    total = max(1, round(game.level.camera.return_time / game.dt))
    pose, place = rig.frustum_pose(xyz, s, total)
    fade = rig.return_fade(total)
    if fade >= 1.0:
        return frustum_views(rig.cache, rig, things, pose, place)
    # The end of a return: the camera is back in sync; the cross-section comes in under the
    # fading frustum view (what lies in the slice is the same in both).
    under = cross_sections(game, rig, things, s)
    return under + frustum_views(rig.cache, rig, things, pose, place, fade=fade)


__all__ = [
    "FrustumCache",
    "INDICATOR_KINDS",
    "Item",
    "cross_sections",
    "frustum_views",
    "items",
    "project",
    "reaching",
    "world_items",
]
