"""Many placed meshes sliced in one kernel call into one shared vertex array.

The per-object path (:func:`core.section.cross_section` once per object, one
GPU buffer per object) pays a Python call, a fresh allocation, an index buffer
and the renderer's checks for every object every frame. A :class:`SectionBatch`
instead keeps every distinct mesh once in pooled arrays (instances of the same
mesh share them) and slices all instances with one numba call that writes
straight into the renderer's interleaved vertex format::

    row = x y z | nx ny nz | r g b a        (10 float32, 40 bytes)

three rows per triangle, no index buffer. A mesh made of convex cells (a
polychoron: see :mod:`.cells`) is sliced cell by cell, each cut cell's polygon
as one fan: the section :func:`~core.section.cross_section` draws, corners
identical to the bit, in about a third of the triangles. Any other mesh is
sliced tet by tet, into triangles bit-identical to
:func:`~core.section.cross_section` of the same mesh, model and camera (same
float64 arithmetic, same case table, same vertex order). Either way a batched
frame draws what the per-object frame drew.

Whole instances are culled before any tet is touched: by their bounding sphere
against the slice (``|w distance| > radius``) and, when view planes are given,
against the 3D view frustum. Inside a surviving instance, runs of 16 tets are
culled by their boxes (:data:`CHUNK`), and each vertex is moved into camera space
once (a 120-cell's vertex belongs to ~22 tets).

A batch drawn with inner faces skipped may be given the eye: the instances it
slices anyway then leave out the polygons that clearly face away from it (the
rasterizer would skip them), about half their rows (see :meth:`SectionBatch.update`).

Instances that did not move keep their triangles: the batch re-slices only from
the first changed instance on, and moves instances that change to the back of
its order, so after a few frames the static ones form a prefix that is neither
re-sliced nor re-uploaded (:attr:`SectionBatch.changed_from`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .cells import Cells, mesh_cells
from .layout import Layout, layout_colors, layout_edges, layout_normals, mesh_clusters
from .mesh import TetMesh4
from .section_batch_kernels import BatchScratch, Instances, Pool, _instances_in_view, _slice_batch
from .section_batch_tets import ROW
from .transform import inverse

#: Updates the output must have fitted half its capacity before it shrinks.
SHRINK_AFTER = 30


def _capacity(rows: int, minimum: int) -> int:
    """Rows held for ``rows`` in use: the next power of two, at least ``minimum``."""
    return max(int(minimum), 1 << max(int(rows) - 1, 0).bit_length())


def _view_of(camera_pose) -> np.ndarray:
    """World-to-camera ``(5, 5)`` of a camera-to-world pose (None: the identity)."""
    return np.eye(5) if camera_pose is None else inverse(camera_pose)


#: Tets per chunk, the unit the tet slicer culls by: its layout's clusters (spatially
#: coherent runs of tets) cut into runs this long, each with its bounding box.
CHUNK = 16


def _chunks(layout) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A layout's clusters cut into chunks of :data:`CHUNK` tets: their first and one-past-last
    tets ``(c,) int64``, and the middle and half size ``(c, 4) float64`` of each one's box in
    object space (a tighter bound along any direction than a cluster's sphere)."""
    lo = np.concatenate([np.arange(a, b, CHUNK) for a, b in zip(layout.lo, layout.hi)]).astype(np.int64)
    hi = np.minimum(lo + CHUNK, np.repeat(layout.hi, -(-(layout.hi - layout.lo) // CHUNK)))
    corners = layout.vertices.astype(np.float64)[layout.tets]  # (m, 4, 4)
    order = np.argsort(lo, kind="stable")
    mn = np.minimum.reduceat(corners.min(axis=1), lo[order])[np.argsort(order)]
    mx = np.maximum.reduceat(corners.max(axis=1), lo[order])[np.argsort(order)]
    return lo, hi, 0.5 * (mn + mx), 0.5 * (mx - mn)


def _one_colour_tets(tets: np.ndarray, colors: np.ndarray) -> bool:
    """Is each tet ``(m, 4)`` of one colour (its vertices' ``colors (n, 4)`` equal, bit for bit)?

    Then a corner's colour interpolated along an edge is its ends' colour, exactly, unless that
    is a negative zero (``-0.0 + s * 0.0`` is ``+0.0``): a mesh with one is not of one colour."""
    c = colors.view(np.uint32)[tets]
    return bool((c == c[:, :1]).all()) and not (np.signbit(colors) & (colors == 0)).any()


class PoolPart(NamedTuple):
    """What a mesh brings to a batch's pool, in its own numbering (see :func:`pool_part`)."""

    layout: Layout
    chunks: tuple  # _chunks(layout)
    edges: tuple  # layout_edges(layout)
    colors: np.ndarray  # (n, 4) float32, in the layout's order
    flat: bool  # each tet of one colour (_one_colour_tets)
    center: np.ndarray  # (4,) float64, the middle of its box (object space)
    radius: float  # of the sphere about it holding every vertex


def pool_part(mesh: TetMesh4) -> PoolPart:
    """The arrays :class:`SectionBatch` pools for ``mesh``, made once and cached on it (a
    shot or an enemy met again by another batch, or after a pool starts again, costs a few
    copies instead of 4-7 ms of sorting), made again when its colours change. Call it ahead
    of play (a level's start) to spare the first frame that meets the mesh its making."""
    layout = mesh_clusters(mesh)
    colors = layout_colors(mesh, layout)
    key = ("batch_pool_part", id(layout))
    part = mesh._cache.get(key)
    if part is None or part[0] is not colors:
        colors32 = colors.astype(np.float32)
        v = layout.vertices.astype(np.float64)
        ctr = 0.5 * (v.min(axis=0) + v.max(axis=0))
        radius = float(np.sqrt(((v - ctr) ** 2).sum(axis=1).max()))
        flat = _one_colour_tets(layout.tets, colors32)
        made = PoolPart(layout, _chunks(layout), layout_edges(layout), colors32, flat, ctr, radius)
        layout_normals(mesh, layout)
        mesh_cells(mesh)
        part = mesh._cache[key] = (colors, made)
    return part[1]


class _Pool:
    """Every distinct mesh's slicing layout, concatenated: :attr:`arrays` is the kernels'
    :class:`~.section_batch_kernels.Pool`."""

    def __init__(self, by_cells: bool = True):
        self.by_cells = by_cells
        self.index: dict[int, int] = {}  # id(mesh) -> mesh number
        self.meshes: list[TetMesh4] = []  # keeps ids valid
        self.arrays = Pool(
            vertices=np.zeros((0, 4), np.float32),
            tets=np.zeros((0, 4), np.uint32),
            tet_normals=np.zeros((0, 4), np.float32),
            colors=np.zeros((0, 4), np.float32),
            mesh_v=np.zeros((0, 2), np.int64),
            mesh_c=np.zeros((0, 2), np.int64),
            clo=np.zeros(0, np.int64),
            chi=np.zeros(0, np.int64),
            ccenter=np.zeros((0, 4)),
            chalf=np.zeros((0, 4)),
            mesh_cells=np.zeros((0, 2), np.int64),
            cell_edge_start=np.zeros(1, np.int64),
            cell_edges=np.zeros((0, 2), np.uint32),
            cell_tet=np.zeros((0, 4), np.uint32),
            cell_center=np.zeros((0, 4)),
            cell_radius=np.zeros(0),
            tet_edges=np.zeros((0, 6), np.uint32),
            edge_ends=np.zeros((0, 2), np.uint32),
            mesh_e=np.zeros((0, 2), np.int64),
            flat=np.zeros(0, np.uint8),
        )
        self.center = np.zeros((0, 4))  # per mesh: bounding sphere (object space)
        self.radius = np.zeros(0)
        # The largest mesh's vertices, tets (or cells), and cell corners (at least a tet's 4).
        self.max_vertices, self.max_tets, self.max_corners, self.max_edges = 0, 0, 4, 0
        self.max_clusters = 1

    def add(self, mesh: TetMesh4) -> int:
        k = self.index.get(id(mesh))
        if k is not None:
            return k
        part = pool_part(mesh)
        layout = part.layout
        a = self.arrays
        v0, c0, t0 = len(a.vertices), len(a.clo), len(a.tets)
        lo, hi, center, half = part.chunks
        tet_edges, edge_lo, edge_hi = part.edges
        e0 = len(a.edge_ends)
        self.arrays = a._replace(
            vertices=np.concatenate([a.vertices, layout.vertices]),
            tets=np.concatenate([a.tets, layout.tets + np.uint32(v0)]),
            tet_normals=np.concatenate([a.tet_normals, layout_normals(mesh, layout)]),
            colors=np.concatenate([a.colors, part.colors]),
            mesh_v=np.concatenate([a.mesh_v, [[v0, v0 + len(layout.vertices)]]]),
            mesh_c=np.concatenate([a.mesh_c, [[c0, c0 + len(lo)]]]),
            clo=np.concatenate([a.clo, lo + t0]),
            chi=np.concatenate([a.chi, hi + t0]),
            ccenter=np.concatenate([a.ccenter, center]),
            chalf=np.concatenate([a.chalf, half]),
            tet_edges=np.concatenate([a.tet_edges, tet_edges]),
            edge_ends=np.concatenate([a.edge_ends, np.column_stack([edge_lo, edge_hi])]),
            mesh_e=np.concatenate([a.mesh_e, [[e0, e0 + len(edge_lo)]]]),
            flat=np.append(a.flat, np.uint8(part.flat)),
        )
        self.center = np.concatenate([self.center, part.center[None]])
        self.radius = np.append(self.radius, part.radius)
        self.max_vertices = max(self.max_vertices, len(layout.vertices))
        self.max_tets = max(self.max_tets, len(layout.tets) + 1)
        self.max_edges = max(self.max_edges, len(edge_lo))
        self.max_clusters = max(self.max_clusters, len(lo))
        self._add_cells(mesh_cells(mesh) if self.by_cells else None, layout, v0)
        k = self.index[id(mesh)] = len(self.meshes)
        self.meshes.append(mesh)
        return k

    def _add_cells(self, cells: Cells | None, layout, v0: int) -> None:
        a = self.arrays
        c0 = len(a.cell_radius)
        if cells is not None:
            # Into the pool's numbering: the layout's vertex order, offset by the mesh's first vertex.
            renumber = np.empty(len(layout.source), np.int64)
            renumber[layout.source] = np.arange(len(layout.source))
            edges = np.sort(renumber[cells.edges], axis=1) + v0
            a = a._replace(
                cell_edge_start=np.concatenate([a.cell_edge_start, cells.edge_start[1:] + len(a.cell_edges)]),
                cell_edges=np.concatenate([a.cell_edges, edges.astype(np.uint32)]),
                cell_tet=np.concatenate([a.cell_tet, (renumber[cells.tets_of] + v0).astype(np.uint32)]),
                cell_center=np.concatenate([a.cell_center, cells.centers]),
                cell_radius=np.concatenate([a.cell_radius, cells.radii]),
            )
            self.max_corners = max(self.max_corners, len(cells.edges))
        self.arrays = a._replace(mesh_cells=np.concatenate([a.mesh_cells, [[c0, len(a.cell_radius)]]]))

    def scratch(self, ws: BatchScratch | None) -> BatchScratch:
        """``ws`` if it is large enough for every mesh of the pool, else a new one."""
        if ws is not None and len(ws.above) >= self.max_vertices and len(ws.cut) >= self.max_tets:
            if len(ws.q) >= self.max_corners and len(ws.keep) >= self.max_clusters and len(ws.point) >= self.max_edges:
                return ws
        v, t, c = self.max_vertices, self.max_tets, self.max_corners
        return BatchScratch(
            cam=np.empty((v, 4)),
            cut=np.empty(t, np.int64),
            cmask=np.empty(t, np.int64),
            g=np.empty(12),
            q=np.empty((c, 3)),
            qc=np.empty((c, 4)),
            qe=np.empty(c, np.int64),
            ang=np.empty(c),
            order=np.empty(c, np.int64),
            keep=np.empty(self.max_clusters, np.int64),
            above=np.empty(v, np.uint8),
            point=np.full(self.max_edges, -1, np.int64),
            elist=np.empty(4 * t, np.int64),
            tj=np.empty(4 * t, np.int64),
            rec=np.empty(16 * t, np.float32),
            recc=np.empty(16 * t, np.float32),
            sj=np.empty(4 * t),
            n64=np.empty((3, t)),
            tn=np.empty((3, t), np.float32),
        )


class SectionBatch:
    """Slices a changing set of placed meshes into one vertex array.

    Usage, once per frame::

        batch.update(keys, meshes, models, camera_pose, planes)
        batch.vertices      # (3 * triangles, 10) float32, ready to upload
        batch.changed_from  # rows before this are the same as last frame

    ``update(..., defer=True)`` leaves the slicing itself for :meth:`finish` (the
    outputs finish it when read): a frame can do all its Python first and run its
    batches' kernels back to back, since Python right after a large kernel call runs
    with cold caches.

    Parameters
    ----------
    capacity_rows : int
        Rows the output holds at the least (it grows and shrinks with the scene).
    by_cells : bool
        Slice meshes made of convex cells cell by cell (fewer triangles, the same
        section); False slices every mesh tet by tet, exactly as
        :func:`~core.section.cross_section` does.

    Attributes
    ----------
    vertices : (k, 10) float32
        A view of the shared output, valid until the next :meth:`update`.
    changed_from : int
        First row that may differ from the previous :meth:`update`'s output.
    revision : int
        Bumped by every update that changed anything.
    culled : int
        Instances skipped by the last update: bounding sphere off the slice or out of view.
    sliced : int
        Instances re-sliced by the last update.
    """

    def __init__(self, capacity_rows: int = 3 * 1024, by_cells: bool = True):
        self._by_cells = by_cells
        self._pool = _Pool(by_cells)
        self._out = np.empty((_capacity(0, capacity_rows), ROW), np.float32)
        self._keys: list = []  # instance order (changed ones drift to the back)
        self._pos: dict | None = {}  # key -> its place in that order (None: not made yet)
        self._order = np.zeros(0, np.int64)  # that order as places in the last update's keys
        self._view_culled: set = set()
        self._last = None  # (keys, mesh numbers, visible, model-views, sliced for an eye) of the last update
        self._start = np.zeros(1, np.int64)
        self._count = np.zeros(0, np.int64)
        self._w_range = np.zeros((0, 2))
        # Of the last update: (id of each mesh, its number in the pool, its bounding sphere's centre and radius).
        self._mesh_ids: tuple = (None, None, None, None)
        self._view: tuple = (b"", None)  # (camera pose's bytes, its world-to-camera) of the last update
        self._eye = None  # the last update's eye, as bytes
        self._cut = np.zeros(0, np.int64)
        self._scratch = None  # the kernel's BatchScratch, grown with the pool
        self._min_rows = int(capacity_rows)
        self._small = 0  # updates in a row the output could have been smaller
        self._rows = 0
        self._pending: tuple | None = None  # (instances, first, w_cue) a deferred update left to slice
        self.changed_from = 0
        self.revision = 0
        self.culled = 0
        self.sliced = 0

    @property
    def vertices(self) -> np.ndarray:
        self.finish()
        return self._out[: self._rows]

    @property
    def capacity_bytes(self) -> int:
        """Bytes held by the output array."""
        return self._out.nbytes

    def instance_rows(self, key) -> tuple[int, int]:
        """``(first row, row count)`` of an instance's triangles in :attr:`vertices`."""
        self.finish()
        if self._pos is None:
            self._pos = {k: i for i, k in enumerate(self._keys)}
        i = self._pos[key]
        return int(self._start[i]), int(self._count[i])

    def instances(self) -> tuple[list, np.ndarray, np.ndarray, np.ndarray]:
        """Every instance in the output's order, as arrays: ``(keys, start (k + 1,) int64,
        count (k,) int64, w_range (k, 2) float64)``: its rows ``start[i]`` to ``start[i] + count[i]``,
        and the least and greatest camera-space w of its posed vertices (how far it reaches
        either side of the slice). Valid until the next :meth:`update`."""
        self.finish()
        return self._keys, self._start, self._count, self._w_range

    @property
    def cut_counts(self) -> np.ndarray:
        """``(k,) int64`` in :meth:`instances`' order: each instance's cut tets (or cells), the
        polygons left out for facing away from the eye included: it has a section if > 0."""
        self.finish()
        return self._cut

    @property
    def view_culled(self) -> set:
        """The keys :meth:`culled_by_view` says yes to."""
        return self._view_culled

    def culled_by_view(self, key) -> bool:
        """Was the instance skipped only because it is out of view (its sphere reaches the slice)?"""
        return key in self._view_culled

    def update(
        self, keys, meshes, models, camera_pose=None, planes=None, w_cue: bool = False, eye=None, defer: bool = False
    ) -> bool:
        """Slice every instance that changed; returns True if the output changed.

        Parameters
        ----------
        keys : sequence of hashable
            One stable identity per instance (an entity id).
        meshes : sequence of TetMesh4
        models : sequence of (5, 5) float64, or (k, 5, 5) float64
            Object-to-world transforms.
        camera_pose : (5, 5) float64, optional
            Camera-to-world; the slice is its ``w = 0`` and the output is in its
            xyz frame (identity: world ``w = 0``, world xyz).
        planes : (p, 4) float64, optional
            View planes ``(n, d)`` in the output frame, inside where
            ``n . x + d >= 0`` (any ``|n|``); instances entirely outside one are culled.
        w_cue : bool
            The alpha of each instance's rows says where the slice cuts it along its extent
            that way (0 mid-way, -1 or 1 at its ends), instead of its colours' alpha.
        eye : (3,) float64, optional
            Where the picture is seen from, in the output frame, for a batch drawn with its
            inner faces skipped (closed surfaces, wound counter-clockwise from outside): the
            polygons of a changed instance that clearly face away from it are left out, since
            the rasterizer would skip them (half the rows to write and to upload). Such an
            instance is sliced again, whole, once the eye has moved (:meth:`cut_counts` still
            says which instances have a section).
        defer : bool
            Leave the slicing for :meth:`finish` (or the first read of the outputs);
            :attr:`changed_from`, :attr:`revision` and :attr:`sliced` are already this update's.
        """
        self.finish()  # a deferred update's rows are where this one starts from
        keys = list(keys)
        n = len(keys)
        models = np.asarray(models, np.float64).reshape(n, 5, 5)
        mvs = np.ascontiguousarray(np.matmul(self._view_for(camera_pose), models))
        self._number_meshes(list(meshes))
        mesh_ids = self._mesh_ids[1]
        in_slice, visible, flips = self._visible(mvs, *self._mesh_ids[2:], planes)
        self.culled = n - int(np.count_nonzero(visible))
        self._view_culled = {keys[i] for i in np.flatnonzero(in_slice & ~visible)} if self.culled else set()
        old = self._old_order(keys)
        eye_key = None if eye is None else np.asarray(eye, np.float64).reshape(3).tobytes()
        moved, self._eye = eye_key != self._eye, eye_key
        diff, culled = self._changed(keys, mesh_ids, visible, mvs)
        cull = diff if eye is not None else np.zeros(n, bool)  # only what changed anyway
        if moved:
            diff = diff | culled  # sliced for the eye where it was: whole again
        self._last = (*self._last[:4], np.where(diff, cull, culled))
        if not diff.any() and len(old) == n and (old >= 0).all():
            self.changed_from = self._rows
            self.sliced = 0
            self._shrink_if_settled()
            return False
        # New order: unchanged instances in their old order, then the changed ones,
        # so the static ones settle into a prefix that is never touched again.
        seen_from = np.zeros(3) if eye is None else np.asarray(eye, np.float64).reshape(3)
        every = bool(diff.all())
        if every:  # everything changed (animated things): the order of keys
            first, order = 0, np.arange(n)
            inst = Instances(mesh_ids, mvs, flips, visible.view(np.uint8), np.empty(n), cull.view(np.uint8), seen_from)
        else:
            kept = old[old >= 0]
            stay = kept[~diff[kept]]
            first = int(np.argmin(np.append(old[: len(stay)] == stay, False)))
            order = np.concatenate([stay, np.flatnonzero(diff)])
            look = (np.empty(n), cull[order].view(np.uint8), seen_from)
            inst = Instances(mesh_ids[order], mvs[order], flips[order], visible[order].view(np.uint8), *look)
        self._keys = keys if every else list(map(keys.__getitem__, order.tolist()))
        self._order = order
        self._pos = None
        self.sliced = n - first
        self.revision += 1
        self.changed_from = int(self._start[first]) if first else 0
        self._pending = (inst, first, w_cue)
        if not defer:
            self.finish()
        return True

    def finish(self) -> None:
        """Slice what a deferred :meth:`update` left (nothing if none is pending)."""
        if self._pending is not None:
            inst, first, w_cue = self._pending
            self._pending = None
            self._slice(inst, first, w_cue)

    def _number_meshes(self, meshes: list) -> None:
        """The meshes' numbers in the pool and their bounding spheres into ``self._mesh_ids``,
        added to the pool if new (the same meshes as last time, most frames: nothing to do)."""
        by_id = list(map(id, meshes))
        if by_id == self._mesh_ids[0]:
            return
        if len(self._pool.meshes) > max(16, 2 * len(set(by_id))):
            # Mostly meshes no longer drawn: start the pool again (and slice everything anew),
            # so a long game spawning objects of new shapes does not grow it forever.
            self._pool = _Pool(self._by_cells)
            self._last, self._keys, self._pos = None, [], {}
            self._start = np.zeros(1, np.int64)
        ids = np.array([self._pool.add(m) for m in meshes], np.int64)
        self._mesh_ids = (by_id, ids, self._pool.center[ids], self._pool.radius[ids])

    def _view_for(self, camera_pose) -> np.ndarray:
        """:func:`_view_of` the pose, made again only when the pose changes."""
        key = None if camera_pose is None else np.asarray(camera_pose, np.float64).tobytes()
        if key != self._view[0]:
            self._view = (key, _view_of(camera_pose))
        return self._view[1]

    def _old_order(self, keys: list) -> np.ndarray:
        """The last update's order as places in ``keys``, ``(k,) int64``, -1 for keys gone."""
        if self._last is not None and self._last[0] == keys:
            return self._order  # the same keys as last time (most frames)
        where = {k: i for i, k in enumerate(keys)}
        return np.array([where.get(k, -1) for k in self._keys], np.int64)

    def _changed(self, keys: list, mesh_ids: np.ndarray, visible: np.ndarray, mvs: np.ndarray):
        """``(n,) bool`` twice, by place in ``keys``: the instances that are new, moved, or entered
        or left the view; and those whose rows were made without the polygons facing away
        from the last update's eye.

        Compared as arrays: per-key Python work is what the batch is here to avoid.
        """
        n = len(keys)
        last = self._last
        if last is not None and last[0] == keys:
            diff = (last[2] != visible) | (last[3] != mvs).reshape(n, 25).any(axis=1)
            if last[1] is not mesh_ids:  # the same meshes (most frames): the same array
                diff |= last[1] != mesh_ids
            culled = last[4]
        else:
            diff, culled = np.ones(n, bool), np.zeros(n, bool)
            if last is not None:  # other keys (a ghost layer's pick changes): match them by key
                where = {k: i for i, k in enumerate(last[0])}
                was = np.fromiter((where.get(k, -1) for k in keys), np.int64, n)
                now = np.flatnonzero(was >= 0)
                j = was[now]
                moved = (last[3][j] != mvs[now]).reshape(-1, 25).any(axis=1)
                diff[now] = (last[1][j] != mesh_ids[now]) | (last[2][j] != visible[now]) | moved
                culled[now] = last[4][j]
        self._last = (keys, mesh_ids, visible, mvs, culled)
        return diff, culled

    def _slice(self, inst: Instances, first: int, w_cue: bool) -> None:
        """Slice the instances from ``first`` on (those before keep their rows), growing the output if needed."""
        n = len(inst.mesh)
        start_row = int(self._start[first]) if first else 0
        self._scratch = self._pool.scratch(self._scratch)
        # As many instances as last time: the first ones' entries stand. (The start array is
        # checked: after the pool was started again it is one entry long, and the kernel,
        # which never checks bounds, would write past it.)
        if len(self._count) == n and len(self._start) == n + 1:
            start, count, w_range, cut = self._start, self._count, self._w_range, self._cut
        else:
            start = np.zeros(n + 1, np.int64)
            count = np.zeros(n, np.int64)
            start[: first + 1] = self._start[: first + 1]
            count[:first] = self._count[:first]
            w_range = np.empty((n, 2))
            w_range[:first] = self._w_range[:first]
            cut = np.empty(n, np.int64)
            cut[:first] = self._cut[:first]
        while True:
            out = (self._out, start, count, w_range, cut)  # a Rows, as a plain tuple like the other bundles
            pool, ws = tuple(self._pool.arrays), tuple(self._scratch)
            rows = _slice_batch(pool, tuple(inst), first, start_row, out, ws, w_cue)
            if rows <= len(self._out):
                break
            # Grow at once and slice again (rare: only when the scene grows).
            grown = np.empty((_capacity(rows, self._min_rows), ROW), np.float32)
            grown[:start_row] = self._out[:start_row]
            self._out = grown
        self._rows = int(rows)
        self._shrink_if_settled()
        self._start, self._count, self._w_range, self._cut = start, count, w_range, cut

    def _shrink_if_settled(self) -> None:
        """Hold the next power of two of the rows in use, once that has been true for a while.

        The capacity then depends on the scene, not on its history: objects
        spawned and removed for ten minutes leave the memory where it began.
        """
        want = _capacity(self._rows, self._min_rows)
        if want >= len(self._out):
            self._small = 0
            return
        self._small += 1
        if self._small >= SHRINK_AFTER:
            small = np.empty((want, ROW), np.float32)
            small[: self._rows] = self._out[: self._rows]
            self._out = small
            self._small = 0

    @staticmethod
    def _visible(
        mvs: np.ndarray, center: np.ndarray, radius: np.ndarray, planes
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Which instances' bounding spheres (``center (k, 4)``, ``radius (k,)`` in object space)
        meet the slice, and which meet both the slice and the view (two ``(k,) bool`` arrays), and
        each one's orientation, ``(k,) float64``: ``1.0`` where ``det(mv[:4, :4]) > 0``, else
        ``-1.0`` (the winding rule needs it)."""
        pl = np.zeros((0, 4)) if planes is None else np.ascontiguousarray(planes, np.float64).reshape(-1, 4)
        in_slice, visible, flips = np.empty(len(mvs), np.bool_), np.empty(len(mvs), np.bool_), np.empty(len(mvs))
        if _instances_in_view(mvs, center, radius, pl, in_slice, visible, flips):
            flips = np.where(np.linalg.det(mvs[:, :4, :4]) > 0, 1.0, -1.0)  # flat ones: the per-object slicer's call
        return in_slice, visible, flips
