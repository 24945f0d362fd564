"""The numba kernels of :func:`~.section.cross_section`, and the bundle of arrays they take.

A section is two kernel calls: :func:`_find_cut` finds the cut tets and counts
their triangles, the caller sizes the output, and :func:`_emit` writes the
triangles. Both take one bundle, :class:`Slicer` (a named tuple of arrays: what
they read of the mesh and the scratch arrays they reuse), and nothing else but
scalars and the output. They take it as a plain tuple (``tuple(slicer)``) and
name its fields again inside: numba's dispatcher types a plain tuple of arrays
in C but a named tuple in Python, which costs about 2 us a call where a small
mesh's whole section costs 20. The case tables (:mod:`.cases`) are read as
compile-time constants.

Each kernel unpacks the bundle into locals before its loops: reading a bundle's
field inside a loop costs a reference-count update per iteration. The helpers
it calls run once per section, never per tet (numba counts references,
atomically, on every call of a function that takes arrays), and are inlined:
a call passing the whole bundle costs about a tenth of a microsecond.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import njit
from .cases import CASE_COUNT, CASE_EDGES_PADDED, CASE_LOCAL_FLAT, CASE_REVERSED, CASE_TRIANGLES

#: How :func:`_emit` makes the section points: per cut tet, or once per cut edge, numbered
#: as the cut tets meet them or by a pass over the edge table (see :func:`_points_by_edge`).
POINTS_BY_TET, POINTS_BY_EDGE, POINTS_BY_EDGE_SCAN = 0, 1, 2

#: Unsigned index type of the kernels' inner loops: numba then skips the
#: negative-index fix-up, a sizeable part of short loops.
U = np.uint64


class Slicer(NamedTuple):
    """Everything the kernels read and write for the sections of one mesh.

    First what they read of the mesh: its slicing layout
    (:func:`~.layout.mesh_clusters`) and more; then scratch arrays reused
    section after section (see :class:`~.section._Workspace`). For a mesh of
    ``n`` vertices, ``m`` tets in ``c`` clusters and ``e`` edges, with room for
    ``k`` cut tets:

    Attributes
    ----------
    vertices : (n, 4) float32
    tets : (m, 4) uint32
        In clusters, indexing ``vertices``.
    colors : (n, 4) float32
    normals : (4 m,) float32
        Each tet's outward normal in object space (:func:`~.layout.layout_normals`), flat.
    lo, hi : (c,) int64
        Each cluster's tets.
    centers : (c, 4) float64
    radii : (c,) float64
        Each cluster's bounding sphere.
    tet_edges : (m, 6) uint32
    edge_lo, edge_hi : (e,) uint32
        The edge table (:func:`~.layout.layout_edges`), or empty arrays before a
        dense section needs it.
    keep : (c,) int64
        Scratch: the clusters the hyperplane meets.
    above : (n,) uint8
        Per vertex: camera-space w > 0.
    cut : (m,) uint32
        The cut tets (pages touched only as far as used).
    cmask : (m,) uint8
        And their cases.
    g : (12,) float64
        The normals' transform (:func:`normal_transform`).
    cam : (4 n,) float64
        Camera-space vertices, flat.
    vmark : (n,) uint8
        Per vertex: used by a cut tet (0 between calls).
    vlist : (4 k,) uint32
        The vertices of the cut tets.
    point : (e,) int32
        Per edge: its point number, -1 between calls.
    elist : (4 k + 1,) uint32
        Per point: its edge (the edge path).
    rec : (32 k,) float32
        Per point: xyz, rgba and one unused.
    tj : (5 k,) int32
        Per cut tet: its polygon's point numbers, then its case.
    n64 : (3, k) float64
        Per cut tet: its outward normal, not yet unit.
    tn : (3, k) float32
        And unit.
    """

    vertices: np.ndarray
    tets: np.ndarray
    colors: np.ndarray
    normals: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    centers: np.ndarray
    radii: np.ndarray
    tet_edges: np.ndarray
    edge_lo: np.ndarray
    edge_hi: np.ndarray
    keep: np.ndarray
    above: np.ndarray
    cut: np.ndarray
    cmask: np.ndarray
    g: np.ndarray
    cam: np.ndarray
    vmark: np.ndarray
    vlist: np.ndarray
    point: np.ndarray
    elist: np.ndarray
    rec: np.ndarray
    tj: np.ndarray
    n64: np.ndarray
    tn: np.ndarray


@njit(inline="always")
def _orientation(a):
    """``1.0`` where ``det(a[:4, :4]) > 0``, ``-1.0`` where it is < 0, ``0.0`` where it is too
    close to zero to tell whatever the arithmetic (under 1e-9 of Hadamard's bound, the product
    of the rows' lengths): a cofactor expansion, without the LU solve of ``np.linalg.det``."""
    s01 = a[2, 0] * a[3, 1] - a[2, 1] * a[3, 0]
    s02 = a[2, 0] * a[3, 2] - a[2, 2] * a[3, 0]
    s03 = a[2, 0] * a[3, 3] - a[2, 3] * a[3, 0]
    s12 = a[2, 1] * a[3, 2] - a[2, 2] * a[3, 1]
    s13 = a[2, 1] * a[3, 3] - a[2, 3] * a[3, 1]
    s23 = a[2, 2] * a[3, 3] - a[2, 3] * a[3, 2]
    c0 = a[1, 1] * s23 - a[1, 2] * s13 + a[1, 3] * s12
    c1 = a[1, 0] * s23 - a[1, 2] * s03 + a[1, 3] * s02
    c2 = a[1, 0] * s13 - a[1, 1] * s03 + a[1, 3] * s01
    c3 = a[1, 0] * s12 - a[1, 1] * s02 + a[1, 2] * s01
    det = a[0, 0] * c0 - a[0, 1] * c1 + a[0, 2] * c2 - a[0, 3] * c3
    bound = 1.0
    for i in range(4):
        bound *= np.sqrt(a[i, 0] ** 2 + a[i, 1] ** 2 + a[i, 2] ** 2 + a[i, 3] ** 2)
    if abs(det) <= 1e-9 * bound:
        return 0.0
    return 1.0 if det > 0.0 else -1.0


@njit(cache=True)
def orientation(mv):
    """:func:`_orientation` of ``mv (5, 5)``'s linear part, callable from Python: the sign of
    its determinant, or ``0.0`` when too close to zero to tell (then ask ``np.linalg.det``).
    A compiled call: after a large section, with the caches cold, LAPACK's costs tens of
    microseconds."""
    return _orientation(mv)


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


@njit(cache=True)
def _find_cut(slicer, mv, w_gain, cull):
    """The tets the hyperplane cuts, into ``s.cut`` (their cases into ``s.cmask``); returns
    their number and their triangles'.

    ``slicer`` is a :class:`Slicer` as a plain tuple (see the module docstring), ``s``
    below. First the clusters whose bounding sphere the hyperplane meets (all without
    ``cull``; ``w_gain`` bounds how far a unit object-space step moves camera-space
    w), then one byte per vertex (:func:`_classify`), then the cut tets of those
    clusters (:func:`_compact`).
    """
    s = Slicer(*slicer)
    lo, hi, centers, radii, keep = s.lo, s.hi, s.centers, s.radii, s.keep
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    nkeep = 0
    visit = 0
    for c in range(lo.shape[0]):
        dc = m0 * centers[c, 0] + m1 * centers[c, 1] + m2 * centers[c, 2] + m3 * centers[c, 3] + m4
        hit = (not cull) or abs(dc) <= radii[c] * w_gain
        keep[nkeep] = c
        nkeep += hit
        visit += (hi[c] - lo[c]) * hit
    _classify(s, mv, nkeep, visit)
    return _compact(s, nkeep)


@njit(inline="always")
def _classify(s, mv, nkeep, visit):
    """One byte per vertex into ``s.above``: is it above the hyperplane?

    Every vertex at once when the ``visit`` tets of the kept clusters hold
    about as many vertex slots as there are vertices; else only the vertices
    they use (2 marks the others). Arrays are read through flat views: their
    constant strides let the compiler vectorize the per-vertex loop.
    """
    vf = s.vertices.reshape(-1)
    tf = s.tets.reshape(-1)
    lo, hi, keep, above = s.lo, s.hi, s.keep, s.above
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    n = s.vertices.shape[0]
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


@njit(inline="always")
def _compact(s, nkeep):
    """The cut tets of the kept clusters into ``s.cut`` and ``s.cmask``; returns
    their number and their triangles'.

    Per cluster, first whether any tet is cut (a branch-free sum: a tet is cut
    when 1 to 3 of its vertices are above; skipped after a cluster with cut
    tets, as its neighbour likely has some too), then, only if so, the cut ones
    compacted without a branch: far from the hyperplane a scan is one
    predictable branch per cluster, and near it which tets are cut is a coin
    toss. Unsigned indices spare the negative-index checks.
    """
    tf = s.tets.reshape(-1)
    lo, hi, keep, above, cut, cmask = s.lo, s.hi, s.keep, s.above, s.cut, s.cmask
    ncut = U(0)
    ntri = 0
    last = U(0)  # cut tets in the previous cluster
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
            k = CASE_TRIANGLES[mask]
            cut[ncut] = t
            cmask[ncut] = mask
            ncut += U(k != 0)
            ntri += k
        last = ncut - before
    return ncut, ntri


@njit(cache=True)
def _emit(slicer, mv, flip, ncut, ntri, points, every_vertex, out):
    """The ``ntri`` triangles of the ``ncut`` cut tets (:func:`_find_cut`) into ``out``.

    Each vertex the cut tets use is moved into camera space once
    (:func:`_camera_space`; all of them with ``every_vertex``). ``points`` says how the
    section points are made: :data:`POINTS_BY_TET`, or once per cut edge though ~5 cut tets
    share it (the edge table is then in ``s``), numbered as the tets meet them
    (:data:`POINTS_BY_EDGE`) or by a pass over the whole edge table
    (:data:`POINTS_BY_EDGE_SCAN`; see :func:`_points_by_edge`). Every camera-space
    coordinate and every section point is the same float64 expression whichever path
    computes it, so the output depends neither on the path nor on culling, and equals the
    batched slicer's (:mod:`.section_batch`).

    Loops without unpredictable branches (a mispredicted branch costs more
    than the arithmetic it skips): the vertices, the tets' normals and points,
    the points' positions and colours, the rows. Each tet's case comes from
    ``s.cmask``, its normal from its object-space normal and
    :func:`normal_transform`, its winding from :data:`~.cases.CASE_REVERSED`
    (the row for the model-view's orientation, ``flip``).

    Parameters
    ----------
    slicer : tuple
        A :class:`Slicer` as a plain tuple (see the module docstring), ``s`` below.
    out : (30 ntri,) float32
        Out: the vertices (9 floats per triangle), then the normals (9), then the colours (12).
    """
    s = Slicer(*slicer)
    _camera_space(s, mv, ncut, every_vertex)
    normal_transform(mv, flip, s.g)
    if points == POINTS_BY_TET:
        _points_by_tet(s, ncut)
    else:
        _points_by_edge(s, ncut, points == POINTS_BY_EDGE_SCAN)
    _unit_normals(ncut, s.n64, s.tn)
    _rows(s, ncut, 1 if flip < 0.0 else 0, out[: 9 * ntri], out[9 * ntri : 18 * ntri], out[18 * ntri : 30 * ntri])


@njit(inline="always")
def _camera_space(s, mv, ncut, every_vertex):
    """The vertices of the ``ncut`` cut tets in camera space, into ``s.cam``.

    With ``every_vertex`` (the cut tets use most of them) all in one vectorized
    loop, else only theirs (``s.vmark``: per
    vertex, 0 on entry and on return; ``s.vlist``: those vertices).
    """
    vf = s.vertices.reshape(-1)
    tf = s.tets.reshape(-1)
    cut, cam, vmark, vlist = s.cut, s.cam, s.vmark, s.vlist
    a00, a01, a02, a03, a04 = mv[0, 0], mv[0, 1], mv[0, 2], mv[0, 3], mv[0, 4]
    a10, a11, a12, a13, a14 = mv[1, 0], mv[1, 1], mv[1, 2], mv[1, 3], mv[1, 4]
    a20, a21, a22, a23, a24 = mv[2, 0], mv[2, 1], mv[2, 2], mv[2, 3], mv[2, 4]
    a30, a31, a32, a33, a34 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    if every_vertex:
        for i in range(s.vertices.shape[0]):
            x, y, z, w = vf[4 * i], vf[4 * i + 1], vf[4 * i + 2], vf[4 * i + 3]
            cam[4 * i] = a00 * x + a01 * y + a02 * z + a03 * w + a04
            cam[4 * i + 1] = a10 * x + a11 * y + a12 * z + a13 * w + a14
            cam[4 * i + 2] = a20 * x + a21 * y + a22 * z + a23 * w + a24
            cam[4 * i + 3] = a30 * x + a31 * y + a32 * z + a33 * w + a34
        return
    nv = 0
    for idx in range(ncut):
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


@njit(inline="always")
def _unit_normals(ncut, n64, tn):
    """Per cut tet ``i``: its section's normal ``n64[:, i]`` made unit, float32, into ``tn[:, i]``.

    A loop of its own, over one component per row, in float32: vectorized four
    tets at a time even for the baseline CPU, where float64's square root and
    division stay scalar and cost more than all the rest of a tet's normal.
    The result is a float32 normal either way (to within 2 ulp of the float64
    one); float32 holds the squared length of any normal of a model scaled by
    1e-6 to 1e6. The batched slicer calls this loop too: the same bits.
    """
    nx, ny, nz = n64[0], n64[1], n64[2]
    tx, ty, tz = tn[0], tn[1], tn[2]
    zero = np.float32(0.0)
    for idx in range(ncut):
        x, y, z = np.float32(nx[idx]), np.float32(ny[idx]), np.float32(nz[idx])
        ln = np.sqrt(x * x + y * y + z * z)
        inv = np.float32(1.0) / ln if ln > zero else zero  # a degenerate tet: zero stays zero
        tx[idx] = x * inv
        ty[idx] = y * inv
        tz[idx] = z * inv


@njit(inline="always")
def _points_by_tet(s, ncut):
    """Per cut tet ``i``: its case into ``tj[5 i + 4]``, its polygon's points into
    records ``4 i ... 4 i + 3`` of ``rec`` (numbered in ``tj[5 i:]``) and its normal into
    ``n64[:, i]`` (not yet unit, see :func:`_unit_normals`); all in ``s``.

    A record is eight float32: the point's camera-space xyz, its colour, one
    unused. The normal is the tet's object-space normal turned by ``s.g``
    (:func:`normal_transform`): four loads where the normal of its
    camera-space corners needs sixteen; in this loop, whose other loads wait
    on memory, it costs little.
    """
    tf = s.tets.reshape(-1)
    cf = s.colors.reshape(-1)
    nobj, cut, cmask, cam, rec, tj, g = s.normals, s.cut, s.cmask, s.cam, s.rec, s.tj, s.g
    g0, g1, g2, g3, g4, g5 = g[0], g[1], g[2], g[3], g[4], g[5]
    g6, g7, g8, g9, g10, g11 = g[6], g[7], g[8], g[9], g[10], g[11]
    nx, ny, nz = s.n64[0], s.n64[1], s.n64[2]
    for idx in range(ncut):
        t = np.uint64(cut[idx])
        mask = cmask[idx]
        n0, n1, n2, n3 = nobj[4 * t], nobj[4 * t + 1], nobj[4 * t + 2], nobj[4 * t + 3]
        nx[idx] = g0 * n0 + g1 * n1 + g2 * n2 + g3 * n3
        ny[idx] = g4 * n0 + g5 * n1 + g6 * n2 + g7 * n3
        nz[idx] = g8 * n0 + g9 * n1 + g10 * n2 + g11 * n3
        tj[5 * idx + 4] = mask
        for e in range(4):
            ia = tf[4 * t + CASE_EDGES_PADDED[mask, e, 0]]
            ib = tf[4 * t + CASE_EDGES_PADDED[mask, e, 1]]
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


@njit(inline="always")
def _points_by_edge(s, ncut, scan_edges):
    """:func:`_points_by_tet` computing each cut edge's point once.

    ``s.point``: per edge, its point number (-1 on entry and on return);
    ``s.elist``: per point, its edge. Unsigned indices (``U``).

    The cut tets number their edges' points as they meet them, each point
    waiting on the count of the ones before. With ``scan_edges`` (a section
    cutting much of the mesh) one pass over the edge table numbers every cut
    edge first, in edge order, without that chain and without a branch; the
    tets then only look their points up. The points' values, and so the
    output, are the same either way.
    """
    cf = s.colors.reshape(-1)
    ef = s.tet_edges.reshape(-1)
    nobj, edge_lo, edge_hi, above = s.normals, s.edge_lo, s.edge_hi, s.above
    cut, cmask, cam, point, elist, rec, tj, g = s.cut, s.cmask, s.cam, s.point, s.elist, s.rec, s.tj, s.g
    g0, g1, g2, g3, g4, g5 = g[0], g[1], g[2], g[3], g[4], g[5]
    g6, g7, g8, g9, g10, g11 = g[6], g[7], g[8], g[9], g[10], g[11]
    nx, ny, nz = s.n64[0], s.n64[1], s.n64[2]
    npt = 0
    if scan_edges:
        for k in range(edge_lo.shape[0]):
            crossed = above[edge_lo[k]] != above[edge_hi[k]]
            point[k] = npt if crossed else -1
            elist[npt] = k
            npt += crossed
    for idx in range(ncut):
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
            eid = U(ef[U(6) * t + CASE_LOCAL_FLAT[U(4) * mask + U(e)]])
            j = point[eid]
            if not scan_edges:
                # Number the edge's point if it has none yet, without a branch.
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


@njit(inline="always")
def _rows(s, ncut, neg, ov, on, oc):
    """Three rows per triangle into ``ov`` (xyz), ``on`` (normal) and ``oc`` (rgba): the
    polygon of each tet fanned from its first point, wound outward.

    The winding is the case's (:data:`~.cases.CASE_REVERSED`, row ``neg``):
    copies only, no geometry. Unsigned indices (``U``).
    """
    rec, tj = s.rec, s.tj
    tx, ty, tz = s.tn[0], s.tn[1], s.tn[2]
    reverse = CASE_REVERSED[neg]
    o = U(0)
    for idx in range(ncut):
        i = U(idx)
        j0, j1, j2, j3 = U(tj[U(5) * i]), U(tj[U(5) * i + U(1)]), U(tj[U(5) * i + U(2)]), U(tj[U(5) * i + U(3)])
        mask = U(tj[U(5) * i + U(4)])
        four = CASE_COUNT[mask] == 4
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
