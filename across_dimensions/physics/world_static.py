"""The static-world methods of :class:`~.world.PhysicsWorld`: half-spaces, world boxes, solids, tet meshes.

A part of the world class, kept apart by job: it replaces the colliders of the
world's ``static`` (:class:`~.state.StaticWorld`), wakes the sleeping bodies a
change may concern and drops the kept manifolds against the static world
(through the world's ``wake``, ``_wake_all`` and ``_forget_static_manifolds``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from .body_def import vec4
from .state import DYNAMIC, StaticWorld
from .tet_mesh import tet_geometry


def empty_static() -> StaticWorld:
    """A static world without colliders."""
    return StaticWorld(
        np.zeros((0, 5)),
        np.zeros((0, 6)),
        np.zeros((0, 24)),
        np.zeros((0, 5)),
        np.zeros((0, 2), np.int64),
        np.zeros((0, 8)),
        np.zeros((0, 4, 4)),
        np.zeros((0, 5)),
        np.zeros((0, 3, 4)),
        np.zeros((0, 8)),
        np.zeros((0, 2), np.int64),
        np.zeros((0, 8)),
        np.zeros((0, 2)),
        np.zeros((0, 4, 5)),
    )


def _bounds_box(b: np.ndarray) -> np.ndarray:
    """The solid-box row ``(center, half extents, identity)`` of bounds ``(lo (4), hi (4))``."""
    return np.concatenate([0.5 * (b[:4] + b[4:]), 0.5 * (b[4:] - b[:4]), np.eye(4).ravel()])


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return a is b or np.array_equal(a, b)


class TetMeshes:
    """The tet meshes last handed to :meth:`WorldStatic.set_static_tets`, and their geometry.

    A mesh handed over again (the same array, or an equal one) keeps its
    geometry; only the meshes that changed are measured again.
    """

    def __init__(self):
        self.inputs: list[np.ndarray] = []
        self.parts: list[tuple] = []  # per mesh: (tets, planes, bary, bounds) sorted, and its sweep
        self.mesh_bounds = np.zeros((0, 8))

    def same(self, inputs: list[np.ndarray]) -> bool:
        return len(inputs) == len(self.inputs) and all(_same(a, b) for a, b in zip(inputs, self.inputs))

    def _part(self, i: int, m: np.ndarray) -> tuple:
        if i < len(self.inputs) and _same(m, self.inputs[i]):
            return self.parts[i]  # this mesh stays: its geometry too
        geo = tet_geometry(m)
        # Sorted along the mesh's longest axis: a body meets one run of them (see tet_mesh).
        b = geo[3]
        ax = int(np.argmax(b[:, 4:].max(axis=0) - b[:, :4].min(axis=0))) if len(b) else 0
        order = np.argsort(b[:, ax], kind="stable")
        geo = tuple(np.ascontiguousarray(a[order]) for a in geo)
        return geo, (ax, float((b[:, 4 + ax] - b[:, ax]).max()) if len(b) else 0.0)

    def update(self, inputs: list[np.ndarray]) -> tuple[dict, list[np.ndarray]]:
        """Take ``inputs`` as the meshes: the :class:`~.state.StaticWorld` tet fields (all but
        ``tet_motion``) and the bounds ``(8,)`` of each mesh that changed, before and after."""
        self.parts = [self._part(i, m) for i, m in enumerate(inputs)]
        parts = [p[0] for p in self.parts]
        ranges = []
        start = 0
        for geo in parts:
            ranges.append((start, start + len(geo[0])))
            start += len(geo[0])
        if parts:
            tets, planes, bary, bounds = (np.concatenate(a) for a in zip(*parts))
        else:
            tets, planes, bary, bounds = np.zeros((0, 4, 4)), np.zeros((0, 5)), np.zeros((0, 3, 4)), np.zeros((0, 8))
        empty = np.array([np.inf] * 4 + [-np.inf] * 4)
        mesh_bounds = np.array(
            [
                np.concatenate([bounds[a:b, :4].min(axis=0), bounds[a:b, 4:].max(axis=0)]) if b > a else empty
                for a, b in ranges
            ],
            dtype=np.float64,
        ).reshape(-1, 8)
        old = self.inputs
        changed = []
        for i in range(max(len(inputs), len(old))):
            if i < len(inputs) and i < len(old) and _same(inputs[i], old[i]):
                continue
            changed += [self.mesh_bounds[i]] if i < len(old) else []
            changed += [mesh_bounds[i]] if i < len(inputs) else []
        self.inputs = inputs
        self.mesh_bounds = mesh_bounds
        arrays = dict(
            tets=tets,
            tet_planes=planes,
            tet_bary=bary,
            tet_bounds=bounds,
            tet_ranges=np.array(ranges, dtype=np.int64).reshape(-1, 2),
            tet_mesh_bounds=mesh_bounds,
            tet_sweep=np.array([p[1] for p in self.parts], dtype=np.float64).reshape(-1, 2),
        )
        return arrays, changed


class WorldStatic:
    """Methods on the static world of a :class:`~.world.PhysicsWorld` (see there for its state)."""

    def _set_static(self, **fields: np.ndarray) -> None:
        """Replace fields of the static world, each as a C-ordered array.

        Numba compiles a kernel once per array layout: one Fortran-ordered field (a solid's
        planes given transposed) would compile the whole tick again, minutes on two cores,
        instead of loading the kernels shipped for C-ordered arrays.
        """
        self.static = self.static._replace(**{k: np.ascontiguousarray(v) for k, v in fields.items()})

    def add_half_space(self, normal, offset: float = 0.0) -> int:
        """Add the static solid ``{x : n . x <= offset}`` (``n`` is normalised).

        A slope is a half-space with a tilted normal; the ground is
        ``normal=(0, 1, 0, 0), offset=0``. Returns its index among half-spaces.
        """
        n = vec4(normal, "normal")
        ln = np.linalg.norm(n)
        if ln == 0:
            raise ValueError("normal must be non-zero")
        row = np.append(n / ln, float(offset) / ln)
        self._set_static(half_spaces=np.vstack([self.static.half_spaces, row[None]]))
        self._forget_static_manifolds()
        self._wake_all()
        return self.static.half_spaces.shape[0] - 1

    def set_static_boxes(self, boxes: Iterable[tuple[Sequence[float], Sequence[float]]]) -> None:
        """Replace the 3D world boxes: ``(center (3,), half_extents (3,))`` each,
        extending over all of w."""
        rows = []
        for center, half in boxes:
            c = np.asarray(center, dtype=np.float64).reshape(3)
            h = np.asarray(half, dtype=np.float64).reshape(3)
            if np.any(h <= 0):
                raise ValueError("world box half extents must be positive")
            rows.append(np.concatenate([c, h]))
        self._set_static(boxes=np.array(rows, dtype=np.float64).reshape(-1, 6))
        self._forget_static_manifolds()
        self._wake_all()

    def set_static_solids(self, solids: Iterable[tuple]) -> None:
        """Replace the 4D solid boxes: ``(center (4,), half_extents (4,), rotation (4, 4))``
        each, rotation local to world (as :meth:`body_rotation`).

        They are the level's solid objects as seen by the bodies (the game
        sets them each tick from the objects' poses). Sleeping bodies near a
        box that appeared, vanished or moved wake; nothing else changes, so
        setting the same boxes again is free and leaves the simulation as it
        was. They are not in :meth:`state_bytes`: they are derived from poses
        the game hashes itself.
        """
        rows = []
        for center, half, rot in solids:
            c = vec4(center, "center")
            h = vec4(half, "half_extents")
            if np.any(h <= 0):
                raise ValueError("solid half extents must be positive")
            r = np.asarray(rot, dtype=np.float64).reshape(4, 4)
            rows.append(np.concatenate([c, h, r.reshape(16)]))
        new = np.array(rows, dtype=np.float64).reshape(-1, 24)
        old = self.static.solids
        if new.shape == old.shape and np.array_equal(new, old):
            return
        self._set_static(solids=new)
        self._forget_static_manifolds()
        changed = [r for r in old if not any(np.array_equal(r, q) for q in new)]
        changed += [r for r in new if not any(np.array_equal(r, q) for q in old)]
        self._wake_near_solids(changed)

    def set_static_convex(self, solids: Iterable[tuple]) -> None:
        """Replace the convex solids: each ``(planes (k, 5), lo (4,), hi (4,))``, its facet
        half-spaces ``(n, offset)`` (the solid is ``{x : n . x <= offset}`` for every
        row, ``n`` pointing out of it; normalised here) and its bounds.

        Bodies meet each solid through its facet of least penetration (the
        separating-axis test over its facets), so a body resting on a face is
        exact; near an edge or a corner the contact comes up to the margin
        early. As for :meth:`set_static_solids`, setting the same solids again
        changes nothing, sleeping bodies near a changed one wake, and they are
        not in :meth:`state_bytes`.
        """
        planes, ranges, bounds = [], [], []
        start = 0
        for rows, lo, hi in solids:
            r = np.asarray(rows, dtype=np.float64).reshape(-1, 5)
            ln = np.linalg.norm(r[:, :4], axis=1)
            if len(r) < 5 or not np.all(ln > 0):
                raise ValueError("a convex solid needs at least 5 facets with non-zero normals")
            r = r / ln[:, None]
            lo, hi = vec4(lo, "lo"), vec4(hi, "hi")
            planes.append(r)
            ranges.append((start, start + len(r)))
            bounds.append(np.concatenate([lo, hi]))
            start += len(r)
        new = (
            np.concatenate(planes) if planes else np.zeros((0, 5)),
            np.array(ranges, dtype=np.int64).reshape(-1, 2),
            np.array(bounds, dtype=np.float64).reshape(-1, 8),
        )
        st = self.static
        old = (st.convex_planes, st.convex_ranges, st.convex_bounds)
        if all(a.shape == b.shape and np.array_equal(a, b) for a, b in zip(new, old)):
            return
        self._set_static(convex_planes=new[0], convex_ranges=new[1], convex_bounds=new[2])
        self._forget_static_manifolds()
        # Wake sleepers near every convex solid before and after (changes are rare: a door opens).
        self._wake_near_solids([_bounds_box(b) for b in old[2]] + [_bounds_box(b) for b in new[2]])

    def set_static_tets(self, meshes: Iterable[np.ndarray], motions: Iterable[np.ndarray] | None = None) -> None:
        """Replace the tet meshes: each the boundary tets ``(T, 4, 4)`` of one solid, in the world.

        For solids that are neither boxes nor convex (an arch, a lifted asset):
        every tet is a 3-simplex of the solid's closed boundary, its corners
        ordered so that ``core.mesh.cross4`` of the edges from corner 0 points
        out of the solid (as :class:`~across_dimensions.core.mesh.TetMesh4` keeps
        them). Bodies meet each tet exactly (see :mod:`.tet_mesh`). As for
        :meth:`set_static_solids`, handing over the same arrays again changes
        nothing, sleeping bodies near a mesh that changed wake, and the meshes are
        not in :meth:`state_bytes` (the game hashes the poses they come from).
        Arrays handed over are kept (not copied): make new ones when a mesh moves.

        Parameters
        ----------
        meshes : iterable of (T, 4, 4) array_like
        motions : iterable of (4, 5) array_like, optional
            Each mesh's velocity field ``v(x) = A x + b`` as ``[A | b]`` (m/s), for a
            mesh that moves: a body resting on it is carried along (its contacts
            see the surface's velocity) rather than pushed out after it sank in.
            ``(M_new M_old^-1 - I)[:4] / dt`` for a pose change ``M_old -> M_new``
            over a tick ``dt``. Zero (a still mesh) when not given.
        """
        inputs = [np.asarray(m, dtype=np.float64).reshape(-1, 4, 4) for m in meshes]
        if motions is None:
            motion = np.zeros((len(inputs), 4, 5))
        else:
            motion = np.array([np.asarray(v, dtype=np.float64).reshape(4, 5) for v in motions]).reshape(-1, 4, 5)
            if len(motion) != len(inputs):
                raise ValueError(f"{len(inputs)} tet meshes but {len(motion)} motions")
        if self._tets.same(inputs):
            if not np.array_equal(motion, self.static.tet_motion):
                self._set_static(tet_motion=motion)
            return
        arrays, changed = self._tets.update(inputs)
        self._set_static(**arrays, tet_motion=motion)
        # Wake sleepers near each mesh that moved, where it was and where it is now.
        self._wake_near_solids([_bounds_box(b) for b in changed if np.all(np.isfinite(b))])

    def _wake_near_solids(self, rows) -> None:
        """Wake sleeping bodies whose bounding ball meets one of the solid boxes ``rows``."""
        n = self._n
        if not rows or n == 0:
            return
        b = self.bodies
        sleeping = np.flatnonzero(b.alive[:n] & ~b.awake[:n] & (b.kind[:n] == DYNAMIC))
        for row in rows:
            ext = np.abs(row[8:].reshape(4, 4)) @ row[4:8]
            reach = b.bound[sleeping, None] + 4 * self.params["margin"][0]
            near = np.all(np.abs(b.position[sleeping] - row[:4]) <= ext + reach, axis=1)
            for j in sleeping[near]:
                self.wake(int(j))
