"""Cross-section: slice a tetrahedral 4D mesh by a hyperplane into 3D triangles.

The hyperplane is the ``w = 0`` hyperplane of a 4D camera given by its pose
(camera-to-world 5x5 transform); the output lives in the camera's own xyz frame.

Case table
----------
Each tet's four vertices are classified by the sign of their camera-space w
(``d > 0`` is "above"; ``d == 0`` counts as below, a consistent tie-break that
keeps sections closed). Bit ``i`` of the case index is set when vertex ``i`` is
above, giving 16 cases:

====================  ====================  ===============================
cases                 vertices above        cut edges, in cycle order
====================  ====================  ===============================
0, 15                 none / all            nothing
1, 2, 4, 8            one: ``a``            ``ab ac ad`` -> one triangle
14, 13, 11, 7         three (one below b)   ``ba bc bd`` -> one triangle
3, 5, 6, 9, 10, 12    two: ``a0 a1``        ``a0b0 a0b1 a1b1 a1b0`` -> a quad
====================  ====================  ===============================

The table fixes which edges form the polygon and their cyclic order. The
section's outward normal is the xyz part of the tet's outward 4D normal
(``cross4`` of its edges, times the sign of the model-view's determinant), and
the polygon's winding against it depends on the case alone
(:data:`CASE_REVERSED`), so triangles come out counter-clockwise seen from
outside whatever the tet's vertex order, with no geometry per tet to decide it.
The kernel turns each tet's object-space normal (:func:`layout_normals`) by the
model-view's cofactor matrix (:func:`normal_transform`).

Two implementations share these rules: :func:`cross_section` (numba, clustered,
single-threaded) and :func:`cross_section_reference` (plain Python/numpy, the
oracle the tests compare against).
"""

from __future__ import annotations

import sys
import threading
from typing import NamedTuple

import numpy as np

from ._jit import njit
from .mesh import TetMesh4, TriMesh3, cross4
from .transform import inverse


def _build_case_table() -> tuple[np.ndarray, np.ndarray]:
    edges = np.zeros((16, 4, 2), dtype=np.int64)
    count = np.zeros(16, dtype=np.int64)
    for mask in range(16):
        above = [i for i in range(4) if mask >> i & 1]
        below = [i for i in range(4) if not mask >> i & 1]
        if len(above) == 1:
            cyc = [(above[0], b) for b in below]
        elif len(below) == 1:
            cyc = [(below[0], a) for a in above]
        elif len(above) == 2:
            a0, a1 = above
            b0, b1 = below
            cyc = [(a0, b0), (a0, b1), (a1, b1), (a1, b0)]
        else:
            cyc = []
        count[mask] = len(cyc)
        for k, e in enumerate(cyc):
            edges[mask, k] = e
    return edges, count


CASE_EDGES, CASE_COUNT = _build_case_table()
# The same table with a triangle's unused fourth edge repeating its third, so a
# kernel can always compute four points (the fourth then equals the third).
CASE_EDGES_PADDED = CASE_EDGES.copy()
CASE_EDGES_PADDED[CASE_COUNT == 3, 3] = CASE_EDGES[CASE_COUNT == 3, 2]
#: A tet's six edges as vertex pairs (lower local index first); ``CASE_LOCAL_EDGES[mask, e]``
#: is which of them ``CASE_EDGES_PADDED[mask, e]`` is.
TET_EDGE_PAIRS = np.array([(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)], np.int64)
CASE_LOCAL_EDGES = np.array(
    [
        [[tuple(p) for p in TET_EDGE_PAIRS.tolist()].index(tuple(sorted(e))) if e[0] != e[1] else 0 for e in row]
        for row in CASE_EDGES_PADDED.tolist()
    ],
    np.int64,
)

#: ``CASE_LOCAL_EDGES`` flat, as bytes (``[4 * mask + e]``): the kernels' copy.
CASE_LOCAL_FLAT = CASE_LOCAL_EDGES.astype(np.uint8).reshape(-1)
#: Unsigned index type of the kernels' inner loops.
U = np.uint64


def _build_case_reversed() -> np.ndarray:
    """Whether each case's polygon, in table order, is clockwise seen from outside.

    The outward normal is ``cross4`` of the tet's edges (times the sign of the
    model-view's determinant) and the polygon's corners lie on the same edges,
    so the two turn together: for a tet that is not flat, the polygon's winding
    against the normal depends on the case alone (any non-flat tet can be
    deformed into any other of its case without flattening it or its section).
    Read off one tet here; ``tests/test_section_kernels.py`` checks random ones.

    Returns
    -------
    (2, 16) uint8
        Row 0 for a model-view of positive determinant, row 1 (the opposite) for
        a mirroring one; 0 for the cases that cut nothing.
    """
    rev = np.zeros(16, np.uint8)
    for mask in range(1, 15):
        w = np.array([1.0 if mask >> i & 1 else -1.0 for i in range(4)]) * (1.0 + 0.1 * np.arange(4))
        p = np.column_stack([np.vstack([np.zeros(3), np.eye(3)]), w])
        pts = []
        for a, b in CASE_EDGES[mask, : CASE_COUNT[mask]]:
            s = p[a, 3] / (p[a, 3] - p[b, 3])
            pts.append(p[a, :3] + s * (p[b, :3] - p[a, :3]))
        normal = cross4(p[1] - p[0], p[2] - p[0], p[3] - p[0])[:3]
        if len(pts) == 4:
            poly = np.cross(pts[2] - pts[0], pts[3] - pts[1])
        else:
            poly = np.cross(pts[1] - pts[0], pts[2] - pts[0])
        rev[mask] = poly @ normal < 0
    return np.stack([rev, np.where(CASE_COUNT > 0, 1 - rev, 0).astype(np.uint8)])


#: ``CASE_REVERSED[det < 0, mask]``: a case's polygon is wound the other way round (see
#: :func:`_build_case_reversed`).
CASE_REVERSED = _build_case_reversed()


def _model_view(mesh_model, camera_pose) -> np.ndarray:
    """Object-to-camera 5x5 transform."""
    view = np.eye(5) if camera_pose is None else inverse(camera_pose)
    model = np.eye(5) if mesh_model is None else np.asarray(mesh_model, dtype=np.float64)
    return view @ model


def cross_section(mesh: TetMesh4, camera_pose=None, model=None, cull: bool = True) -> TriMesh3:
    """Slice ``mesh`` by the camera's ``w = 0`` hyperplane.

    Parameters
    ----------
    mesh : TetMesh4
    camera_pose : (5, 5) array_like, optional
        Camera-to-world transform; identity slices at world ``w = 0`` and keeps
        world xyz.
    model : (5, 5) array_like, optional
        Object-to-world transform of the mesh.
    cull : bool
        Skip clusters of tets whose bounding sphere the hyperplane misses
        (False scans every tet, for benchmarks).

    Returns
    -------
    TriMesh3
        Unwelded triangles (three vertices each) with flat outward normals and
        interpolated colours, in the camera's xyz frame. Empty when nothing is cut.
        Its ``faces`` are ``arange(3 * triangles)``: a read-only view shared by
        every section (they are the same numbers every time).
    """
    mv = _model_view(model, camera_pose)
    layout = mesh_clusters(mesh)
    colors = _layout_colors(mesh, layout)
    a = mv[:4, :4]
    # Bound on how far a unit object-space step moves camera-space w.
    w_gain = float(np.linalg.norm(a[3]))
    flip = 1.0 if np.linalg.det(a) > 0 else -1.0
    ws = _workspace(mesh, layout)
    with ws.lock:
        ncut, ntri = _find_cut(
            layout.vertices, layout.tets, mv, layout.lo, layout.hi, layout.centers, layout.radii, w_gain, cull,
            CASE_TRIANGLES, ws.keep, ws.above, ws.cut, ws.cmask,
        )  # fmt: skip
        if ntri == 0:
            return TriMesh3.empty()
        out = ws.output_block(30 * ntri)  # the three outputs in one block
        ov, on, oc = out[: 9 * ntri], out[9 * ntri : 18 * ntri], out[18 * ntri : 30 * ntri]
        by_edge = EDGE_TABLE_FRACTION * ncut > len(layout.tets)
        if by_edge and ws.edges is None:
            ws.set_edges(layout_edges(layout))
        if ws.tn.shape[1] < ncut:
            ws.grow_tets(ncut)
        edges = ws.edges if by_edge else _NO_EDGES
        _emit(
            layout.vertices, layout.tets, colors, mv, layout_normals(mesh, layout).reshape(-1),
            flip, ws.g, ws.cut[:ncut], ws.cmask, by_edge,
            EVERY_VERTEX_FRACTION * ncut > len(layout.vertices), ws.cam, ws.vmark, ws.vlist,
            CASE_EDGES_PADDED, CASE_COUNT, CASE_REVERSED[int(flip < 0)], CASE_LOCAL_FLAT, *edges,
            ws.point, ws.elist, ws.rec, ws.tj, ws.n64, ws.tn, ov, on, oc,
        )  # fmt: skip
    return TriMesh3(ov.reshape(-1, 3), _faces(ntri), on.reshape(-1, 3), oc.reshape(-1, 4))


#: Move every vertex into camera space (one vectorized loop) when the cut tets are
#: more than the vertices over this (a cut tet has four), else only the cut tets' vertices.
EVERY_VERTEX_FRACTION = 4
#: Use a mesh's edge table (built on first need) once a section cuts more than one
#: tet in this many: it has about as many edges as the mesh has tets.
EDGE_TABLE_FRACTION = 16
_NO_EDGES = (np.zeros((0, 6), np.uint32), np.zeros(0, np.uint32), np.zeros(0, np.uint32))


class _Workspace:
    """Scratch arrays for the sections of one layout, reused call after call.

    Fresh scratch arrays cost more than the slicing itself: the first write to
    each new page of memory is a page fault (about a microsecond per 4 KiB),
    and a dense section touches thousands of pages of scratch. Sections of one
    mesh from several threads take turns (``lock``).
    """

    def __init__(self, layout: Layout):
        n, m = len(layout.vertices), len(layout.tets)
        self.lock = threading.Lock()
        self.keep = np.empty(len(layout.lo), np.int64)  # clusters the hyperplane meets
        self.above = np.empty(n, np.uint8)  # per vertex: camera-space w > 0
        self.cut = np.empty(m, np.uint32)  # the cut tets (pages touched only as far as used)
        self.cmask = np.empty(m, np.uint8)  # and their cases
        self.g = np.empty(12)  # the normals' transform (normal_transform)
        self.cam = np.empty(4 * n)  # camera-space vertices, flat
        self.vmark = np.zeros(n, np.uint8)  # per vertex: used by a cut tet (0 between calls)
        self.edges = None  # layout_edges(layout), once a dense section needs it
        self.point = np.zeros(0, np.int32)  # per edge: its point number, -1 between calls
        self.tn = np.empty((3, 0), np.float32)
        self.grow_tets(0)
        self.blocks: list[np.ndarray] = []  # output blocks of earlier sections

    def output_block(self, size: int) -> np.ndarray:
        """A float32 array of at least ``size`` for a section's outputs.

        The outputs of an earlier section are reused once nothing outside holds
        them (their reference count is the pool's own): a game drops last
        frame's section, a benchmark each run's, and both then write into memory
        that is already mapped. A new block has room to spare, so a section
        that grows a little still fits next time.
        """
        for b in self.blocks:
            if size <= len(b) <= 2 * size + 4096 and sys.getrefcount(b) <= _FREE_REFS:
                return b
        b = np.empty(size + size // 4 + 1024, np.float32)
        if len(self.blocks) >= OUTPUT_BLOCKS:
            self.blocks.pop(0)  # the oldest: whoever holds it keeps it alive
        self.blocks.append(b)
        return b

    def set_edges(self, edges) -> None:
        self.edges = edges
        self.point = np.full(len(edges[1]), -1, np.int32)

    def grow_tets(self, count: int) -> None:
        """Room for ``count`` cut tets (and four times as many section points)."""
        count = max(count, self.tn.shape[1] * 5 // 4)  # grow by a quarter at least
        self.n64 = np.empty((3, count))  # per cut tet: its outward normal, not yet unit
        self.tn = np.empty((3, count), np.float32)  # and unit
        self.tj = np.empty(5 * count, np.int32)  # and its polygon's point numbers, then its case
        self.elist = np.empty(4 * count, np.uint32)  # per point: its edge (the edge path)
        self.vlist = np.empty(4 * count, np.uint32)  # the vertices of the cut tets
        self.rec = np.empty(32 * count, np.float32)  # per point: xyz, rgba and one unused


def _refs_when_free() -> int:
    """``sys.getrefcount`` of a block in :meth:`_Workspace.output_block`'s loop that nothing else holds."""
    blocks = [np.empty(0, np.float32)]
    for b in blocks:
        return sys.getrefcount(b)


_FREE_REFS = _refs_when_free()
#: Output blocks kept per mesh: the section on screen, the one being made, and spares.
OUTPUT_BLOCKS = 4


def _workspace(mesh: TetMesh4, layout: Layout) -> _Workspace:
    key = ("section_workspace", id(layout))
    ws = mesh._cache.get(key)
    if ws is None:
        ws = mesh._cache[key] = _Workspace(layout)
    return ws


def layout_edges(layout) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The edges of a layout's tets, each once.

    Returns
    -------
    tet_edges : (m, 6) uint32
        Edge number of each tet's edges, in :data:`TET_EDGE_PAIRS` order.
    edge_lo, edge_hi : (e,) uint32
        Each edge's vertices, lower index first (the end a section point is
        interpolated from, see :func:`_emit_by_tet`).
    """
    tets = layout.tets.astype(np.int64)
    a, b = tets[:, TET_EDGE_PAIRS[:, 0]], tets[:, TET_EDGE_PAIRS[:, 1]]
    n = max(len(layout.vertices), 1)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    uniq, inverse = np.unique(key.ravel(), return_inverse=True)
    return (
        np.ascontiguousarray(inverse.reshape(-1, 6).astype(np.uint32)),
        (uniq // n).astype(np.uint32),
        (uniq % n).astype(np.uint32),
    )


_FACES = [np.zeros((0, 3), np.uint32)]


def _faces(ntri: int) -> np.ndarray:
    """``arange(3 * ntri).reshape(-1, 3)`` as a read-only view of one shared, growing array.

    An unwelded section's faces are always these numbers; writing them afresh
    for every section is a sizeable part of slicing a small mesh.
    """
    faces = _FACES[0]
    if len(faces) < ntri:
        faces = np.arange(3 * max(ntri, 2 * len(faces)), dtype=np.uint32).reshape(-1, 3)
        faces.flags.writeable = False
        _FACES[0] = faces
    return faces[:ntri]


CLUSTER_SIZE = 64


class Layout(NamedTuple):
    """A mesh rearranged for slicing (see :func:`mesh_clusters`)."""

    vertices: np.ndarray  # (n', 4) float32, in order of first use by the sorted tets
    tets: np.ndarray  # (m, 4) uint32, sorted into clusters, indexing ``vertices``
    source: np.ndarray  # (n',) int64, the original index of each vertex
    lo: np.ndarray  # (c,) int64, first tet of each cluster
    hi: np.ndarray  # (c,) int64, one past its last tet
    centers: np.ndarray  # (c, 4) float64, bounding sphere centres
    radii: np.ndarray  # (c,) float64


def mesh_clusters(mesh: TetMesh4, size: int = CLUSTER_SIZE) -> Layout:
    """Tets sorted into spatially coherent clusters with bounding spheres.

    Cached on the mesh. Sorting by a 4D Morton code of tet centroids makes each
    run of ``size`` tets compact, so a hyperplane far from a cluster's sphere
    skips all of its tets without touching them. Vertices are renumbered in the
    order the sorted tets first use them, so a cluster's vertices sit together
    in memory: the gathers of a scan hit the cache instead of main memory.
    """
    key = ("clusters", size)
    if key not in mesh._cache:
        v = mesh.vertices.astype(np.float64)
        cent = v[mesh.tets].mean(axis=1)
        lo_b, hi_b = cent.min(axis=0), cent.max(axis=0)
        q = ((cent - lo_b) / np.maximum(hi_b - lo_b, 1e-12) * 255).astype(np.uint64)
        code = np.zeros(len(cent), np.uint64)
        for bit in range(8):
            for axis in range(4):
                code |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(4 * bit + axis)
        sorted_tets = mesh.tets[np.argsort(code, kind="stable")]
        used, first = np.unique(sorted_tets.ravel(), return_index=True)
        source = used[np.argsort(first, kind="stable")]
        renumber = np.empty(len(mesh.vertices), np.int64)
        renumber[source] = np.arange(len(source))
        tets = np.ascontiguousarray(renumber[sorted_tets].astype(np.uint32))
        vertices = np.ascontiguousarray(mesh.vertices[source])
        starts = np.arange(0, len(tets), size, dtype=np.int64)
        ends = np.minimum(starts + size, len(tets))
        centers, radii = _cluster_spheres(vertices.astype(np.float64), tets, starts, ends)
        mesh._cache[key] = Layout(vertices, tets, source, starts, ends, centers, radii)
    return mesh._cache[key]


def layout_normals(mesh: TetMesh4, layout: Layout) -> np.ndarray:
    """Outward normals ``(m, 4) float64`` of the layout's tets in object space (cached)."""
    key = ("layout_normals", id(layout))  # layouts live as long as the mesh (its cache)
    if key not in mesh._cache:
        p = layout.vertices.astype(np.float64)[layout.tets]
        mesh._cache[key] = np.ascontiguousarray(cross4(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
    return mesh._cache[key]


@njit(cache=True)
def normal_transform(mv, flip, g):
    """What turns object-space tet normals into camera-space section normals, into ``g``.

    ``cross4(A u, A v, A t) = cof(A) cross4(u, v, t)``, with ``cof(A)`` the
    cofactor matrix of ``A = mv[:4, :4]`` (``det(A) inv(A).T``, defined for a
    singular ``A`` too). So a tet's camera-space normal, outward (times
    ``flip``, the sign of ``det(A)``: -1 for a singular one, as the winding
    rule takes it), is ``flip cof(A)`` of its object-space normal, up to a
    positive factor that normalizing removes.

    Parameters
    ----------
    mv : (5, 5) float64
        Model-view transform.
    flip : float
        ``1.0`` if ``det(mv[:4, :4]) > 0`` else ``-1.0``.
    g : (12,) float64
        Out: the xyz rows of ``flip cof(A)``, flat.
    """
    for i in range(3):
        r0 = 1 if i == 0 else 0
        r1 = 2 if i <= 1 else 1
        for j in range(4):
            c0 = 1 if j == 0 else 0
            c1 = 2 if j <= 1 else 1
            c2 = 3 if j <= 2 else 2
            minor = (
                mv[r0, c0] * (mv[r1, c1] * mv[3, c2] - mv[r1, c2] * mv[3, c1])
                - mv[r0, c1] * (mv[r1, c0] * mv[3, c2] - mv[r1, c2] * mv[3, c0])
                + mv[r0, c2] * (mv[r1, c0] * mv[3, c1] - mv[r1, c1] * mv[3, c0])
            )
            g[4 * i + j] = flip * minor if (i + j) % 2 == 0 else -flip * minor


def _layout_colors(mesh: TetMesh4, layout: Layout) -> np.ndarray:
    """The mesh's vertex colours in the layout's order (cached with the colours)."""
    key = ("layout_colors", len(layout.source))
    colors = mesh.vertex_colors()
    entry = mesh._cache.get(key)
    if entry is None or entry[0] is not colors:
        entry = (colors, np.ascontiguousarray(colors[layout.source]))
        mesh._cache[key] = entry
    return entry[1]


@njit(cache=True)
def _cluster_spheres(v, tets, starts, ends):
    nc = len(starts)
    centers = np.zeros((nc, 4))
    radii = np.zeros(nc)
    for c in range(nc):
        lo = np.full(4, np.inf)
        hi = np.full(4, -np.inf)
        for t in range(starts[c], ends[c]):
            for k in range(4):
                for a in range(4):
                    x = v[tets[t, k], a]
                    lo[a] = min(lo[a], x)
                    hi[a] = max(hi[a], x)
        ctr = 0.5 * (lo + hi)
        r2 = 0.0
        for t in range(starts[c], ends[c]):
            for k in range(4):
                s = 0.0
                for a in range(4):
                    d = v[tets[t, k], a] - ctr[a]
                    s += d * d
                r2 = max(r2, s)
        centers[c] = ctr
        radii[c] = np.sqrt(r2)
    return centers, radii


@njit(inline="always")
def _normal_of(ux, uy, uz, uw, vx, vy, vz, vw, tx, ty, tz, tw, flip):
    """Unit normal of a section of the tet with camera-space edge vectors ``u v t``:
    the xyz part of ``cross4(u, v, t)`` times ``flip`` (+-1), normalized; zero stays zero.
    Scalars in, scalars out: an inlined function taking arrays would count references on
    every call."""
    nx = -(uy * (vz * tw - vw * tz) - uz * (vy * tw - vw * ty) + uw * (vy * tz - vz * ty))
    ny = ux * (vz * tw - vw * tz) - uz * (vx * tw - vw * tx) + uw * (vx * tz - vz * tx)
    nz = -(ux * (vy * tw - vw * ty) - uy * (vx * tw - vw * tx) + uw * (vx * ty - vy * tx))
    nx *= flip
    ny *= flip
    nz *= flip
    ln = np.sqrt(nx * nx + ny * ny + nz * nz)
    if ln > 0.0:
        nx /= ln
        ny /= ln
        nz /= ln
    return nx, ny, nz


#: Triangles a tet makes, by case (0 when it is not cut).
CASE_TRIANGLES = np.where(CASE_COUNT > 0, CASE_COUNT - 2, 0).astype(np.int64)


@njit(cache=True)
def _find_cut(v, tets, mv, lo, hi, centers, radii, w_gain, cull, case_triangles, keep, above, cut, cmask):
    """The tets the hyperplane cuts, into ``cut`` (their cases into ``cmask``); returns their
    number and their triangles'.

    Arrays are read through flat views: their constant strides let the
    compiler vectorize the per-vertex loop. ``keep``, ``above`` and ``cut`` are
    scratch (see :class:`_Workspace`).
    """
    vf = v.reshape(-1)
    tf = tets.reshape(-1)
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    n = v.shape[0]
    # Clusters whose bounding sphere the hyperplane meets (all without culling).
    nkeep = 0
    visit = 0
    for c in range(lo.shape[0]):
        dc = m0 * centers[c, 0] + m1 * centers[c, 1] + m2 * centers[c, 2] + m3 * centers[c, 3] + m4
        hit = (not cull) or abs(dc) <= radii[c] * w_gain
        keep[nkeep] = c
        nkeep += hit
        visit += (hi[c] - lo[c]) * hit
    # One byte per vertex: is it above? Every vertex at once when the visited
    # tets hold about as many vertex slots as there are vertices; else only
    # the vertices they use.
    if 4 * visit < n:
        above[:] = 2  # not computed yet
        for kc in range(nkeep):
            c = keep[kc]
            for j in range(4 * lo[c], 4 * hi[c]):
                i = tf[j]
                if above[i] == 2:
                    above[i] = (
                        m0 * vf[4 * i] + m1 * vf[4 * i + 1] + m2 * vf[4 * i + 2] + m3 * vf[4 * i + 3] + m4
                    ) > 0.0
    else:
        for i in range(n):
            above[i] = (m0 * vf[4 * i] + m1 * vf[4 * i + 1] + m2 * vf[4 * i + 2] + m3 * vf[4 * i + 3] + m4) > 0.0
    # Per cluster, first whether any tet is cut (a branch-free sum: a tet is
    # cut when 1 to 3 of its vertices are above; skipped after a cluster with
    # cut tets, as its neighbour likely has some too), then, only if so, the
    # cut ones compacted without a branch: far from the hyperplane a scan is
    # one predictable branch per cluster, and near it which tets are cut is a
    # coin toss. Unsigned indices spare the negative-index checks.
    ncut = U(0)
    ntri = 0
    last = U(0)  # cut tets in the previous cluster: if any, this one likely has some too
    for kc in range(nkeep):
        c = keep[kc]
        t0, t1 = np.uint64(lo[c]), np.uint64(hi[c])
        if last == 0:
            some = 0
            for t in range(t0, t1):
                some |= above[tf[4 * t]] + above[tf[4 * t + 1]] + above[tf[4 * t + 2]] + above[tf[4 * t + 3]] & 3
            if some == 0:
                continue
        before = ncut
        for t in range(t0, t1):
            mask = (
                U(above[tf[4 * t]])
                | (U(above[tf[4 * t + 1]]) << U(1))
                | (U(above[tf[4 * t + 2]]) << U(2))
                | (U(above[tf[4 * t + 3]]) << U(3))
            )
            k = case_triangles[mask]
            cut[ncut] = t
            cmask[ncut] = mask
            ncut += U(k != 0)
            ntri += k
        last = ncut - before
    return ncut, ntri


@njit(cache=True)
def _emit(
    v, tets, colors, mv, nobj, flip, g, cut, cmask, by_edge, every_vertex, cam, vmark, vlist, case_edges, case_count,
    reverse, case_local, tet_edges, edge_lo, edge_hi, point, elist, rec, tj, n64, tn, ov, on, oc,
):  # fmt: skip
    """Triangles of the cut tets into the flat outputs ``ov``, ``on`` (3 per row), ``oc`` (4 per row).

    Each vertex the cut tets use is moved into camera space once, into
    ``cam`` (a vertex belongs to ~20 tets): with ``every_vertex`` (the cut tets
    use most of them) all in one vectorized loop, else only theirs (``vmark``: per
    vertex, 0 on entry and on return; ``vlist``: those vertices). With
    ``by_edge`` each cut edge's point is computed once, though ~5 cut tets
    share it. Every camera-space coordinate and every section point is the
    same float64 expression whichever path computes it, so the output depends
    neither on the path nor on culling, and equals the batched slicer's
    (:mod:`.section_batch`).

    Loops without unpredictable branches (a mispredicted branch costs more
    than the arithmetic it skips): the vertices, the tets' normals and points,
    the points' positions and colours, the rows. The loops call no function
    taking arrays: numba would count references on each call, with atomic
    operations. Each tet's case comes from :func:`_find_cut` (``cmask``), its
    normal from its object-space normal ``nobj`` and ``g`` (scratch for
    :func:`normal_transform`), its winding from ``reverse``
    (:data:`CASE_REVERSED`, the row for the model-view's orientation). The
    other arrays are scratch (:class:`_Workspace`).
    """
    vf = v.reshape(-1)
    tf = tets.reshape(-1)
    a00, a01, a02, a03, a04 = mv[0, 0], mv[0, 1], mv[0, 2], mv[0, 3], mv[0, 4]
    a10, a11, a12, a13, a14 = mv[1, 0], mv[1, 1], mv[1, 2], mv[1, 3], mv[1, 4]
    a20, a21, a22, a23, a24 = mv[2, 0], mv[2, 1], mv[2, 2], mv[2, 3], mv[2, 4]
    a30, a31, a32, a33, a34 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    if every_vertex:
        for i in range(v.shape[0]):
            x, y, z, w = vf[4 * i], vf[4 * i + 1], vf[4 * i + 2], vf[4 * i + 3]
            cam[4 * i] = a00 * x + a01 * y + a02 * z + a03 * w + a04
            cam[4 * i + 1] = a10 * x + a11 * y + a12 * z + a13 * w + a14
            cam[4 * i + 2] = a20 * x + a21 * y + a22 * z + a23 * w + a24
            cam[4 * i + 3] = a30 * x + a31 * y + a32 * z + a33 * w + a34
    else:
        nv = 0
        for idx in range(cut.shape[0]):
            t = cut[idx]
            for k in range(4):
                i = tf[4 * t + k]
                vlist[nv] = i
                nv += vmark[i] == 0
                vmark[i] = 1
        for j in range(nv):
            i = vlist[j]
            vmark[i] = 0
            x, y, z, w = vf[4 * i], vf[4 * i + 1], vf[4 * i + 2], vf[4 * i + 3]
            cam[4 * i] = a00 * x + a01 * y + a02 * z + a03 * w + a04
            cam[4 * i + 1] = a10 * x + a11 * y + a12 * z + a13 * w + a14
            cam[4 * i + 2] = a20 * x + a21 * y + a22 * z + a23 * w + a24
            cam[4 * i + 3] = a30 * x + a31 * y + a32 * z + a33 * w + a34
    normal_transform(mv, flip, g)
    if by_edge:
        _points_by_edge(
            colors, cam, nobj, g, cut, cmask, case_local, tet_edges, edge_lo, edge_hi, point, elist, rec, tj, n64
        )
    else:
        _points_by_tet(tets, colors, cam, nobj, g, cut, cmask, case_edges, rec, tj, n64)
    _unit_normals(cut.shape[0], n64, tn)
    _rows(cut.shape[0], case_count, reverse, rec, tj, tn, ov, on, oc)


@njit(cache=True)
def _unit_normals(ncut, n64, tn):
    """Per cut tet ``i``: its section's normal ``n64[:, i]`` made unit, float32, into ``tn[:, i]``.

    A loop of its own, over one component per row: it is vectorized (a square
    root and a division per tet, one at a time, cost more than all the rest of
    a tet's normal). The batched slicer uses the same expressions, bit for bit.
    """
    nx, ny, nz = n64[0], n64[1], n64[2]
    tx, ty, tz = tn[0], tn[1], tn[2]
    for idx in range(ncut):
        x, y, z = nx[idx], ny[idx], nz[idx]
        ln = np.sqrt(x * x + y * y + z * z)
        inv = 1.0 / ln if ln > 0.0 else 0.0  # a degenerate tet: zero stays zero
        tx[idx] = np.float32(x * inv)
        ty[idx] = np.float32(y * inv)
        tz[idx] = np.float32(z * inv)


@njit(cache=True)
def _points_by_tet(tets, colors, cam, nobj, g, cut, cmask, case_edges, rec, tj, n64):
    """Per cut tet ``i``: its case into ``tj[5 i + 4]``, its polygon's points into
    records ``4 i ... 4 i + 3`` of ``rec`` (numbered in ``tj[5 i:]``) and its normal into
    ``n64[:, i]`` (not yet unit, see :func:`_unit_normals`).

    A record is eight float32: the point's camera-space xyz, its colour, one
    unused. The normal is the tet's object-space normal ``nobj``
    (:func:`layout_normals`, flat) turned by ``g`` (:func:`normal_transform`):
    four loads where the normal of its camera-space corners needs sixteen;
    in this loop, whose other loads wait on memory, it costs little.
    """
    tf = tets.reshape(-1)
    cf = colors.reshape(-1)
    g0, g1, g2, g3, g4, g5 = g[0], g[1], g[2], g[3], g[4], g[5]
    g6, g7, g8, g9, g10, g11 = g[6], g[7], g[8], g[9], g[10], g[11]
    nx, ny, nz = n64[0], n64[1], n64[2]
    for idx in range(cut.shape[0]):
        t = np.uint64(cut[idx])
        mask = cmask[idx]
        n0, n1, n2, n3 = nobj[4 * t], nobj[4 * t + 1], nobj[4 * t + 2], nobj[4 * t + 3]
        nx[idx] = g0 * n0 + g1 * n1 + g2 * n2 + g3 * n3
        ny[idx] = g4 * n0 + g5 * n1 + g6 * n2 + g7 * n3
        nz[idx] = g8 * n0 + g9 * n1 + g10 * n2 + g11 * n3
        tj[5 * idx + 4] = mask
        for e in range(4):
            ia = tf[4 * t + case_edges[mask, e, 0]]
            ib = tf[4 * t + case_edges[mask, e, 1]]
            # Interpolate from the lower vertex index, so the tets sharing this
            # edge compute bit-identical points (a select: the order is a coin toss).
            ca = 4 * min(ia, ib)
            cb = 4 * max(ia, ib)
            s = cam[ca + 3] / (cam[ca + 3] - cam[cb + 3])
            j = 4 * idx + e
            for r in range(3):
                rec[8 * j + r] = np.float32(cam[ca + r] + s * (cam[cb + r] - cam[ca + r]))
            for r in range(4):
                rec[8 * j + 3 + r] = np.float32(cf[ca + r] + s * (cf[cb + r] - cf[ca + r]))
            tj[5 * idx + e] = j


@njit(cache=True)
def _points_by_edge(
    colors, cam, nobj, g, cut, cmask, case_local, tet_edges, edge_lo, edge_hi, point, elist, rec, tj, n64
):
    """:func:`_points_by_tet` computing each cut edge's point once.

    ``case_local``: :data:`CASE_LOCAL_FLAT`; ``point``: per edge, its point
    number (-1 on entry and on return); ``elist``: per point, its edge.
    Indices are unsigned (``U``): numba then skips the negative-index fix-up,
    a sizeable part of these short loops.
    """
    cf = colors.reshape(-1)
    ef = tet_edges.reshape(-1)
    g0, g1, g2, g3, g4, g5 = g[0], g[1], g[2], g[3], g[4], g[5]
    g6, g7, g8, g9, g10, g11 = g[6], g[7], g[8], g[9], g[10], g[11]
    nx, ny, nz = n64[0], n64[1], n64[2]
    npt = 0
    for idx in range(cut.shape[0]):
        i = U(idx)
        t = U(cut[i])
        mask = U(cmask[i])
        tn4 = U(4) * t
        n0, n1, n2, n3 = nobj[tn4], nobj[tn4 + U(1)], nobj[tn4 + U(2)], nobj[tn4 + U(3)]
        nx[i] = g0 * n0 + g1 * n1 + g2 * n2 + g3 * n3
        ny[i] = g4 * n0 + g5 * n1 + g6 * n2 + g7 * n3
        nz[i] = g8 * n0 + g9 * n1 + g10 * n2 + g11 * n3
        tj[U(5) * i + U(4)] = mask
        for e in range(4):
            # Number the edge's point if it has none yet, without a branch.
            eid = U(ef[U(6) * t + case_local[U(4) * mask + U(e)]])
            j = point[eid]
            new = j < 0
            j = npt if new else j
            point[eid] = j
            elist[npt] = eid
            npt += new
            tj[U(5) * i + U(e)] = j
    for k in range(npt):
        j = U(k)
        eid = U(elist[j])
        point[eid] = -1
        ca = U(4) * U(edge_lo[eid])
        cb = U(4) * U(edge_hi[eid])
        s = cam[ca + U(3)] / (cam[ca + U(3)] - cam[cb + U(3)])
        for r in range(3):
            rec[U(8) * j + U(r)] = np.float32(cam[ca + U(r)] + s * (cam[cb + U(r)] - cam[ca + U(r)]))
        for r in range(4):
            rec[U(8) * j + U(3 + r)] = np.float32(cf[ca + U(r)] + s * (cf[cb + U(r)] - cf[ca + U(r)]))


@njit(cache=True)
def _rows(ncut, case_count, reverse, rec, tj, tn, ov, on, oc):
    """Three rows per triangle: the polygon of each tet fanned from its first point, wound outward.

    The winding is the case's (``reverse``, see :data:`CASE_REVERSED`): copies
    only, no geometry. Unsigned indices (see :func:`_points_by_edge`).
    """
    tx, ty, tz = tn[0], tn[1], tn[2]
    o = U(0)
    for idx in range(ncut):
        i = U(idx)
        j0, j1, j2, j3 = U(tj[U(5) * i]), U(tj[U(5) * i + U(1)]), U(tj[U(5) * i + U(2)]), U(tj[U(5) * i + U(3)])
        mask = U(tj[U(5) * i + U(4)])
        four = case_count[mask] == 4
        rev = reverse[mask] != 0
        fx, fy, fz = tx[i], ty[i], tz[i]
        # Fan from point 0: triangles (0, 1, 2) and (0, 2, 3), their last two swapped when reversed.
        for k in range(6 if four else 3):
            j = j0
            if k == 1 or k == 2:
                j = j2 if rev == (k == 1) else j1
            elif k == 4 or k == 5:
                j = j3 if rev == (k == 4) else j2
            # All loads, then all stores: lets the compiler move each row's
            # floats as vectors (it cannot tell the arrays apart).
            b = U(8) * j
            x, y, z = rec[b], rec[b + U(1)], rec[b + U(2)]
            cr, cg, cb, ca = rec[b + U(3)], rec[b + U(4)], rec[b + U(5)], rec[b + U(6)]
            r = o + U(k)
            ov[U(3) * r] = x
            ov[U(3) * r + U(1)] = y
            ov[U(3) * r + U(2)] = z
            on[U(3) * r] = fx
            on[U(3) * r + U(1)] = fy
            on[U(3) * r + U(2)] = fz
            oc[U(4) * r] = cr
            oc[U(4) * r + U(1)] = cg
            oc[U(4) * r + U(2)] = cb
            oc[U(4) * r + U(3)] = ca
        o += U(6) if four else U(3)


def cross_section_reference(mesh: TetMesh4, camera_pose=None, model=None) -> TriMesh3:
    """Plain-Python cross-section: the oracle for :func:`cross_section`.

    Same contract, written for clarity: one tet at a time, no clusters, numpy
    vector maths. Slow; use it in tests on small meshes.
    """
    mv = _model_view(model, camera_pose)
    flip = 1.0 if np.linalg.det(mv[:4, :4]) > 0 else -1.0
    cam = mesh.vertices.astype(np.float64) @ mv[:4, :4].T + mv[:4, 4]
    colors = mesh.vertex_colors()
    verts, norms, cols = [], [], []
    for tet in mesh.tets:
        p = cam[tet]
        above = [i for i in range(4) if p[i, 3] > 0]
        below = [i for i in range(4) if p[i, 3] <= 0]
        if not above or not below:
            continue
        if len(above) == 2:
            cycle = [(above[0], below[0]), (above[0], below[1]), (above[1], below[1]), (above[1], below[0])]
        elif len(above) == 1:
            cycle = [(above[0], b) for b in below]
        else:
            cycle = [(below[0], a) for a in above]
        pts, cs = [], []
        for a, b in cycle:
            if tet[a] > tet[b]:
                a, b = b, a
            s = p[a, 3] / (p[a, 3] - p[b, 3])
            pts.append(p[a, :3] + s * (p[b, :3] - p[a, :3]))
            cs.append(colors[tet[a]] + s * (colors[tet[b]] - colors[tet[a]]))
        normal = flip * cross4(p[1] - p[0], p[2] - p[0], p[3] - p[0])[:3]
        normal = normal / (np.linalg.norm(normal) or 1.0)
        if len(pts) == 4:
            poly_n = np.cross(pts[2] - pts[0], pts[3] - pts[1])
        else:
            poly_n = np.cross(pts[1] - pts[0], pts[2] - pts[0])
        if poly_n @ normal < 0:
            pts = [pts[0]] + pts[1:][::-1]
            cs = [cs[0]] + cs[1:][::-1]
        for i in range(1, len(pts) - 1):
            for j in (0, i, i + 1):
                verts.append(pts[j])
                cols.append(cs[j])
                norms.append(normal)
    if not verts:
        return TriMesh3.empty()
    v = np.array(verts, np.float32)
    return TriMesh3(
        v, np.arange(len(v), dtype=np.uint32).reshape(-1, 3), np.array(norms, np.float32), np.array(cols, np.float32)
    )
