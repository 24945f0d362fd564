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
against the 3D view frustum. Inside a surviving instance, clusters of tets are
culled as in the per-object slicer, and each vertex is moved into camera space
once (a 120-cell's vertex belongs to ~22 tets).

Instances that did not move keep their triangles: the batch re-slices only from
the first changed instance on, and moves instances that change to the back of
its order, so after a few frames the static ones form a prefix that is neither
re-sliced nor re-uploaded (:attr:`SectionBatch.changed_from`).
"""

from __future__ import annotations

import numpy as np

from ._jit import njit
from .cells import Cells, mesh_cells
from .mesh import TetMesh4
from .section import (
    CASE_COUNT,
    CASE_EDGES,
    CASE_REVERSED,
    _layout_colors,
    _normal_of,
    layout_normals,
    mesh_clusters,
    normal_transform,
)
from .transform import inverse

#: Floats per output vertex: position 3, normal 3, colour 4 (the renderer's layout).
ROW = 10
#: Updates the output must have fitted half its capacity before it shrinks.
SHRINK_AFTER = 30


def _capacity(rows: int, minimum: int) -> int:
    """Rows held for ``rows`` in use: the next power of two, at least ``minimum``."""
    return max(int(minimum), 1 << max(int(rows) - 1, 0).bit_length())


class _Pool:
    """Every distinct mesh's slicing layout, concatenated (global vertex indices)."""

    def __init__(self, by_cells: bool = True):
        self.by_cells = by_cells
        self.index: dict[int, int] = {}  # id(mesh) -> mesh number
        self.meshes: list[TetMesh4] = []  # keeps ids valid
        self.vertices = np.zeros((0, 4), np.float32)
        self.colors = np.zeros((0, 4), np.float32)
        self.tets = np.zeros((0, 4), np.uint32)
        self.tet_normals = np.zeros((0, 4))  # per tet: outward normal in object space
        self.clo = np.zeros(0, np.int64)  # per cluster: tet range
        self.chi = np.zeros(0, np.int64)
        self.ccenter = np.zeros((0, 4))
        self.cradius = np.zeros(0)
        self.mesh_v = np.zeros((0, 2), np.int64)  # per mesh: vertex range
        self.mesh_c = np.zeros((0, 2), np.int64)  # per mesh: cluster range
        self.center = np.zeros((0, 4))  # per mesh: bounding sphere (object space)
        self.radius = np.zeros(0)
        self.max_vertices = 0
        # Meshes sliced cell by cell (see core.cells): per mesh its cell range (empty: by tets).
        self.mesh_cells = np.zeros((0, 2), np.int64)
        self.cell_edge_start = np.zeros(1, np.int64)  # per cell: its range of cell_edges
        self.cell_edges = np.zeros((0, 2), np.uint32)  # lower vertex index first
        self.cell_tet = np.zeros((0, 4), np.uint32)  # one tet of each cell, for its normal
        self.cell_center = np.zeros((0, 4))
        self.cell_radius = np.zeros(0)

    def add(self, mesh: TetMesh4) -> int:
        k = self.index.get(id(mesh))
        if k is not None:
            return k
        layout = mesh_clusters(mesh)
        colors = _layout_colors(mesh, layout)
        v0, c0, t0 = len(self.vertices), len(self.clo), len(self.tets)
        self.vertices = np.concatenate([self.vertices, layout.vertices])
        self.colors = np.concatenate([self.colors, colors.astype(np.float32)])
        self.tets = np.concatenate([self.tets, layout.tets + np.uint32(v0)])
        self.tet_normals = np.concatenate([self.tet_normals, layout_normals(mesh, layout)])
        self.clo = np.concatenate([self.clo, layout.lo + t0])
        self.chi = np.concatenate([self.chi, layout.hi + t0])
        self.ccenter = np.concatenate([self.ccenter, layout.centers])
        self.cradius = np.concatenate([self.cradius, layout.radii])
        self.mesh_v = np.concatenate([self.mesh_v, [[v0, len(self.vertices)]]])
        self.mesh_c = np.concatenate([self.mesh_c, [[c0, len(self.clo)]]])
        v = layout.vertices.astype(np.float64)
        ctr = 0.5 * (v.min(axis=0) + v.max(axis=0))
        self.center = np.concatenate([self.center, ctr[None]])
        self.radius = np.append(self.radius, float(np.sqrt(((v - ctr) ** 2).sum(axis=1).max())))
        self.max_vertices = max(self.max_vertices, len(layout.vertices))
        self._add_cells(mesh_cells(mesh) if self.by_cells else None, layout, v0)
        k = self.index[id(mesh)] = len(self.meshes)
        self.meshes.append(mesh)
        return k

    def _add_cells(self, cells: Cells | None, layout, v0: int) -> None:
        c0 = len(self.cell_radius)
        if cells is not None:
            # Into the pool's numbering: the layout's vertex order, offset by the mesh's first vertex.
            renumber = np.empty(len(layout.source), np.int64)
            renumber[layout.source] = np.arange(len(layout.source))
            edges = np.sort(renumber[cells.edges], axis=1) + v0
            self.cell_edge_start = np.concatenate([self.cell_edge_start, cells.edge_start[1:] + len(self.cell_edges)])
            self.cell_edges = np.concatenate([self.cell_edges, edges.astype(np.uint32)])
            self.cell_tet = np.concatenate([self.cell_tet, (renumber[cells.tets_of] + v0).astype(np.uint32)])
            self.cell_center = np.concatenate([self.cell_center, cells.centers])
            self.cell_radius = np.concatenate([self.cell_radius, cells.radii])
        self.mesh_cells = np.concatenate([self.mesh_cells, [[c0, len(self.cell_radius)]]])


class SectionBatch:
    """Slices a changing set of placed meshes into one vertex array.

    Usage, once per frame::

        batch.update(keys, meshes, models, camera_pose, planes)
        batch.vertices      # (3 * triangles, 10) float32, ready to upload
        batch.changed_from  # rows before this are the same as last frame

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
        self._pos: dict = {}  # key -> its place in that order
        self._view_culled: set = set()
        self._last = None  # (keys, mesh numbers, visible, model-views) of the last update
        self._start = np.zeros(1, np.int64)
        self._count = np.zeros(0, np.int64)
        self._cam = np.empty((0, 4))  # camera-space vertices of the instance being sliced
        self._stamp = np.empty(0, np.int64)  # which instance each row of _cam belongs to
        self._tag = 0
        self._min_rows = int(capacity_rows)
        self._small = 0  # updates in a row the output could have been smaller
        self._rows = 0
        self.changed_from = 0
        self.revision = 0
        self.culled = 0
        self.sliced = 0

    @property
    def vertices(self) -> np.ndarray:
        return self._out[: self._rows]

    @property
    def capacity_bytes(self) -> int:
        """Bytes held by the output array."""
        return self._out.nbytes

    def instance_rows(self, key) -> tuple[int, int]:
        """``(first row, row count)`` of an instance's triangles in :attr:`vertices`."""
        i = self._pos[key]
        return int(self._start[i]), int(self._count[i])

    def culled_by_view(self, key) -> bool:
        """Was the instance skipped only because it is out of view (its sphere reaches the slice)?"""
        return key in self._view_culled

    def update(self, keys, meshes, models, camera_pose=None, planes=None) -> bool:
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
        """
        keys = list(keys)
        n = len(keys)
        view = np.eye(5) if camera_pose is None else inverse(camera_pose)
        models = np.asarray(models, np.float64).reshape(n, 5, 5)
        mvs = np.ascontiguousarray(np.matmul(view, models))
        meshes = list(meshes)
        if len(self._pool.meshes) > max(16, 2 * len({id(m) for m in meshes})):
            # Mostly meshes no longer drawn: start the pool again (and slice everything anew),
            # so a long game spawning objects of new shapes does not grow it forever.
            self._pool = _Pool(self._by_cells)
            self._last, self._keys, self._pos = None, [], {}
            self._start = np.zeros(1, np.int64)
        pool = self._pool
        mesh_ids = np.array([pool.add(m) for m in meshes], np.int64)
        in_slice, visible = self._visible(mvs, mesh_ids, planes)
        self._view_culled = {keys[i] for i in np.flatnonzero(in_slice & ~visible)}
        # An instance changed when it is new, moved, or entered/left the view.
        # Compared as arrays: per-key Python work is what the batch is here to avoid.
        self.culled = int(n - visible.sum())
        last = self._last
        if last is not None and last[0] == keys:
            diff = (last[1] != mesh_ids) | (last[2] != visible) | (last[3] != mvs).any(axis=(1, 2))
        else:
            diff = np.ones(n, bool)
            if last is not None:
                where = {k: i for i, k in enumerate(last[0])}
                for i, k in enumerate(keys):
                    j = where.get(k)
                    if j is not None:
                        diff[i] = last[1][j] != mesh_ids[i] or last[2][j] != visible[i] or (last[3][j] != mvs[i]).any()
        self._last = (keys, mesh_ids, visible, mvs)
        changed = {keys[i] for i in np.flatnonzero(diff)}
        inputs = set(keys)
        if not changed and len(inputs) == len(self._keys) and all(k in inputs for k in self._keys):
            self.changed_from = self._rows
            self.sliced = 0
            self._shrink_if_settled()
            return False
        # New order: unchanged instances in their old order, then the changed ones,
        # so the static ones settle into a prefix that is never touched again.
        stay = [k for k in self._keys if k in inputs and k not in changed]
        first = 0
        while first < len(stay) and self._keys[first] == stay[first]:
            first += 1
        order = stay + [k for k in keys if k in changed]
        pos = {k: i for i, k in enumerate(keys)}
        idx = np.array([pos[k] for k in order], np.int64)
        start_row = int(self._start[first]) if first else 0
        # The winding rule needs each transform's orientation.
        flips = np.where(np.linalg.det(mvs[:, :4, :4]) > 0, 1.0, -1.0)
        if len(self._stamp) < pool.max_vertices:
            self._cam = np.empty((pool.max_vertices, 4))
            self._stamp = np.full(pool.max_vertices, -1, np.int64)
        start = np.zeros(n + 1, np.int64)
        count = np.zeros(n, np.int64)
        start[: first + 1] = self._start[: first + 1]
        count[:first] = self._count[:first]
        args = (
            np.ascontiguousarray(mvs[idx]),
            np.ascontiguousarray(flips[idx]),
            visible[idx].astype(np.uint8),
        )
        while True:
            rows = _slice_batch(
                pool.vertices,
                pool.tets,
                pool.tet_normals,
                pool.colors,
                pool.mesh_v,
                pool.mesh_c,
                pool.clo,
                pool.chi,
                pool.ccenter,
                pool.cradius,
                pool.mesh_cells,
                pool.cell_edge_start,
                pool.cell_edges,
                pool.cell_tet,
                pool.cell_center,
                pool.cell_radius,
                mesh_ids[idx],
                *args,
                first,
                start_row,
                self._out,
                start,
                count,
                self._cam,
                self._stamp,
                self._tag,
                CASE_EDGES,
                CASE_COUNT,
                CASE_REVERSED,
            )
            self._tag += n + 1
            if rows <= len(self._out):
                break
            # Grow at once and slice again (rare: only when the scene grows).
            grown = np.empty((_capacity(rows, self._min_rows), ROW), np.float32)
            grown[:start_row] = self._out[:start_row]
            self._out = grown
        self._rows = int(rows)
        self._shrink_if_settled()
        self._start, self._count = start, count
        self._keys = order
        self._pos = {k: i for i, k in enumerate(order)}
        self.changed_from = start_row
        self.sliced = n - first
        self.revision += 1
        return True

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

    def _visible(self, mvs: np.ndarray, mesh_ids: np.ndarray, planes) -> tuple[np.ndarray, np.ndarray]:
        """Which instances' bounding spheres meet the slice, and which meet both the slice and the view.

        Returns two ``(k,) bool`` arrays.
        """
        pool = self._pool
        if len(mvs) == 0:
            return np.zeros(0, bool), np.zeros(0, bool)
        a = mvs[:, :4, :4]
        # Stretch bound: sqrt of a Gershgorin bound on A^T A (exact for a
        # rotation times a uniform scale, an upper bound otherwise).
        ata = np.matmul(a.transpose(0, 2, 1), a)
        stretch = np.sqrt(np.abs(ata).sum(axis=2).max(axis=1))
        c = np.einsum("kij,kj->ki", a, pool.center[mesh_ids]) + mvs[:, :4, 4]
        # Margin: vertices are float32, spheres float64.
        r = pool.radius[mesh_ids] * stretch * (1.0 + 1e-6) + 1e-6
        in_slice = np.abs(c[:, 3]) <= r
        visible = in_slice.copy()
        if planes is not None and len(planes):
            pl = np.asarray(planes, np.float64).reshape(-1, 4)
            # The slice of a 4D ball at w distance d is a 3D ball of radius sqrt(r^2 - d^2).
            r3 = np.sqrt(np.maximum(r * r - c[:, 3] ** 2, 0.0))
            dist = c[:, :3] @ pl[:, :3].T + pl[:, 3]
            visible &= (dist >= -r3[:, None] * np.linalg.norm(pl[:, :3], axis=1)).all(axis=1)
        return in_slice, visible


@njit(cache=True)
def _slice_batch(
    verts,
    tets,
    tet_normals,
    colors,
    mesh_v,
    mesh_c,
    clo,
    chi,
    ccenter,
    cradius,
    mesh_cells,
    cell_edge_start,
    cell_edges,
    cell_tet,
    cell_center,
    cell_radius,
    inst_mesh,
    mvs,
    flips,
    visible,
    first,
    start_row,
    out,
    start,
    count,
    cam,
    stamp,
    tag,
    case_edges,
    case_count,
    case_reversed,
):
    """Slice instances ``first..`` into ``out`` from row ``start_row``.

    A mesh with a cell range in ``mesh_cells`` is sliced cell by cell
    (:func:`_slice_cells`), any other tet by tet. Returns the rows needed (may
    exceed ``len(out)``: then nothing past the end was written and the caller
    grows ``out`` and calls again). ``stamp`` marks which vertices are in
    ``cam`` already: ``tag + k`` for instance ``k``, with a ``tag`` the caller
    never reuses.
    """
    # The loops below are written out rather than split into small helpers:
    # numba counts references (atomically) on every call of a helper that takes
    # arrays, even an inlined one, which made the tet loop several times slower.
    cap = out.shape[0]
    o = start_row
    q = np.empty((4, 3))
    qc = np.empty((4, 4))
    g = np.empty(12)
    p = np.empty((4, 4))
    for k in range(first, inst_mesh.shape[0]):
        start[k] = o
        m = inst_mesh[k]
        mv = mvs[k]
        if not visible[k]:
            count[k] = 0
            start[k + 1] = o
            continue
        v_lo = mesh_v[m, 0]
        flip = flips[k]
        neg = 1 if flip < 0.0 else 0  # which row of case_reversed
        normal_transform(mv, flip, g)
        g0, g1, g2, g3, g4, g5, g6, g7, g8, g9, g10, g11 = (
            g[0],
            g[1],
            g[2],
            g[3],
            g[4],
            g[5],
            g[6],
            g[7],
            g[8],
            g[9],
            g[10],
            g[11],
        )
        if mesh_cells[m, 1] > mesh_cells[m, 0]:
            o = _slice_cells(
                verts,
                colors,
                v_lo,
                mesh_v[m, 1],
                mesh_cells[m, 0],
                mesh_cells[m, 1],
                cell_edge_start,
                cell_edges,
                cell_tet,
                cell_center,
                cell_radius,
                mv,
                flip,
                out,
                o,
                cam,
            )
            count[k] = o - start[k]
            start[k + 1] = o
            continue
        w_gain = np.sqrt(mv[3, 0] ** 2 + mv[3, 1] ** 2 + mv[3, 2] ** 2 + mv[3, 3] ** 2)
        for cl in range(mesh_c[m, 0], mesh_c[m, 1]):
            cc = ccenter[cl]
            dc = mv[3, 0] * cc[0] + mv[3, 1] * cc[1] + mv[3, 2] * cc[2] + mv[3, 3] * cc[3] + mv[3, 4]
            if abs(dc) > cradius[cl] * w_gain:
                continue
            for t in range(clo[cl], chi[cl]):
                mask = 0
                for j in range(4):
                    vi = tets[t, j]
                    li = vi - v_lo
                    if stamp[li] != tag + k:
                        # Camera space once per vertex and instance (same sums as the per-object slicer).
                        stamp[li] = tag + k
                        for r in range(4):
                            cam[li, r] = (
                                mv[r, 0] * verts[vi, 0]
                                + mv[r, 1] * verts[vi, 1]
                                + mv[r, 2] * verts[vi, 2]
                                + mv[r, 3] * verts[vi, 3]
                                + mv[r, 4]
                            )
                    if cam[li, 3] > 0.0:
                        mask |= 1 << j
                if mask == 0 or mask == 15:
                    continue
                nk = case_count[mask]
                if o + 3 * (nk - 2) > cap:
                    o += 3 * (nk - 2)  # count only: the caller grows the output
                    continue
                for j in range(4):
                    li = tets[t, j] - v_lo
                    for r in range(4):
                        p[j, r] = cam[li, r]
                # The normal and winding of the per-object slicer (core.section._points_by_edge, _unit_normals, _rows).
                n0, n1, n2, n3 = tet_normals[t, 0], tet_normals[t, 1], tet_normals[t, 2], tet_normals[t, 3]
                nx = g0 * n0 + g1 * n1 + g2 * n2 + g3 * n3
                ny = g4 * n0 + g5 * n1 + g6 * n2 + g7 * n3
                nz = g8 * n0 + g9 * n1 + g10 * n2 + g11 * n3
                ln = np.sqrt(nx * nx + ny * ny + nz * nz)
                inv = 1.0 / ln if ln > 0.0 else 0.0
                nx, ny, nz = nx * inv, ny * inv, nz * inv
                for e in range(nk):
                    a = case_edges[mask, e, 0]
                    b = case_edges[mask, e, 1]
                    if tets[t, a] > tets[t, b]:
                        a, b = b, a
                    s = p[a, 3] / (p[a, 3] - p[b, 3])
                    for r in range(3):
                        q[e, r] = p[a, r] + s * (p[b, r] - p[a, r])
                    ca = tets[t, a]
                    cb = tets[t, b]
                    for r in range(4):
                        qc[e, r] = colors[ca, r] + s * (colors[cb, r] - colors[ca, r])
                reverse = case_reversed[neg, mask] != 0
                for tri in range(nk - 2):
                    for j in range(3):
                        src = 0 if j == 0 else tri + j
                        if reverse and j > 0:
                            src = tri + 3 - j
                        row = out[o]
                        row[0] = q[src, 0]
                        row[1] = q[src, 1]
                        row[2] = q[src, 2]
                        row[3] = nx
                        row[4] = ny
                        row[5] = nz
                        row[6] = qc[src, 0]
                        row[7] = qc[src, 1]
                        row[8] = qc[src, 2]
                        row[9] = qc[src, 3]
                        o += 1
        count[k] = o - start[k]
        start[k + 1] = o
    return o


@njit(cache=True)
def _slice_cells(
    verts, colors, v_lo, v_hi, c_lo, c_hi, edge_start, edges, cell_tet, center, radius, mv, flip, out, o, cam
):
    """One instance, cell by cell: each cut cell's convex polygon as a fan; returns the next row.

    The polygon's corners are the cut points of the cell's real edges,
    interpolated from the lower vertex index exactly as the tet slicer does,
    so neighbouring cells (and the tet slicer) agree on every shared point.
    They are put in order by their angle about their centroid, counter-clockwise
    seen from outside (along the cell's outward normal). Rows past ``len(out)``
    are counted, not written, as in :func:`_slice_batch`.
    """
    cap = out.shape[0]
    most = 0
    for c in range(c_lo, c_hi):
        most = max(most, edge_start[c + 1] - edge_start[c])
    q = np.empty((most, 3))
    qc = np.empty((most, 4))
    ang = np.empty(most)
    order = np.empty(most, np.int64)
    p = np.empty((4, 4))
    # Every vertex into camera space: a cell mesh has few vertices for its
    # tets (a 120-cell: 600 for 3,240), and most of them are on cut cells.
    for vi in range(v_lo, v_hi):
        li = vi - v_lo
        for r in range(4):
            cam[li, r] = (
                mv[r, 0] * verts[vi, 0]
                + mv[r, 1] * verts[vi, 1]
                + mv[r, 2] * verts[vi, 2]
                + mv[r, 3] * verts[vi, 3]
                + mv[r, 4]
            )
    w_gain = np.sqrt(mv[3, 0] ** 2 + mv[3, 1] ** 2 + mv[3, 2] ** 2 + mv[3, 3] ** 2)
    for c in range(c_lo, c_hi):
        cc = center[c]
        dc = mv[3, 0] * cc[0] + mv[3, 1] * cc[1] + mv[3, 2] * cc[2] + mv[3, 3] * cc[3] + mv[3, 4]
        if abs(dc) > radius[c] * w_gain:
            continue
        k = 0
        for e in range(edge_start[c], edge_start[c + 1]):
            va = edges[e, 0]
            vb = edges[e, 1]
            la = va - v_lo
            lb = vb - v_lo
            wa = cam[la, 3]
            wb = cam[lb, 3]
            if (wa > 0.0) == (wb > 0.0):
                continue
            s = wa / (wa - wb)
            for r in range(3):
                q[k, r] = cam[la, r] + s * (cam[lb, r] - cam[la, r])
            for r in range(4):
                qc[k, r] = colors[va, r] + s * (colors[vb, r] - colors[va, r])
            k += 1
        if k < 3:
            continue
        if o + 3 * (k - 2) > cap:
            o += 3 * (k - 2)
            continue
        for j in range(4):
            li = cell_tet[c, j] - v_lo
            for r in range(4):
                p[j, r] = cam[li, r]
        nx, ny, nz = _normal_of(
            p[1, 0] - p[0, 0], p[1, 1] - p[0, 1], p[1, 2] - p[0, 2], p[1, 3] - p[0, 3],
            p[2, 0] - p[0, 0], p[2, 1] - p[0, 1], p[2, 2] - p[0, 2], p[2, 3] - p[0, 3],
            p[3, 0] - p[0, 0], p[3, 1] - p[0, 1], p[3, 2] - p[0, 2], p[3, 3] - p[0, 3],
            flip,
        )  # fmt: skip
        # Angles in the polygon's plane about the centroid, in the basis (u, n x u).
        mx = my = mz = 0.0
        for i in range(k):
            mx += q[i, 0]
            my += q[i, 1]
            mz += q[i, 2]
        mx /= k
        my /= k
        mz /= k
        ux, uy, uz = q[0, 0] - mx, q[0, 1] - my, q[0, 2] - mz
        vx = ny * uz - nz * uy
        vy = nz * ux - nx * uz
        vz = nx * uy - ny * ux
        for i in range(k):
            dx, dy, dz = q[i, 0] - mx, q[i, 1] - my, q[i, 2] - mz
            ang[i] = _pseudo_angle(dx * ux + dy * uy + dz * uz, dx * vx + dy * vy + dz * vz)
            j = i  # insertion sort: a polygon has a handful of corners
            while j > 0 and ang[order[j - 1]] > ang[i]:
                order[j] = order[j - 1]
                j -= 1
            order[j] = i
        for i in range(3 * (k - 2)):
            src = order[0] if i % 3 == 0 else order[i // 3 + i % 3]
            row = out[o]
            row[0] = q[src, 0]
            row[1] = q[src, 1]
            row[2] = q[src, 2]
            row[3] = nx
            row[4] = ny
            row[5] = nz
            row[6] = qc[src, 0]
            row[7] = qc[src, 1]
            row[8] = qc[src, 2]
            row[9] = qc[src, 3]
            o += 1
    return o


@njit(inline="always")
def _pseudo_angle(x, y):
    """A value in ``[0, 4)`` increasing with the angle of ``(x, y)`` (no trigonometry)."""
    d = abs(x) + abs(y)
    if d == 0.0:
        return 0.0
    t = y / d
    if x >= 0.0:
        return t if y >= 0.0 else 4.0 + t
    return 2.0 - t
