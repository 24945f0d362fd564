"""The numba kernels of :class:`~.section_batch.SectionBatch`, and the bundles of arrays they take.

:func:`_slice_batch` slices instance after instance into the shared rows
(:class:`Rows`), reading the pooled meshes (:class:`Pool`), the instances
(:class:`Instances`) and reusing :class:`BatchScratch`. An instance is sliced
in two passes, each a loop without calls: which tets (or cells) are cut, then
their triangles. The per-instance helpers take the bundles whole and are
inlined; nothing is called per tet or per cell but scalar helpers (numba counts
references on every call of a function that takes arrays).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import njit
from .section_batch_tets import _cut_tets, _faces_away, _tet_rows
from .section_kernels import U, _orientation


class Pool(NamedTuple):
    """Every distinct mesh's slicing layout, concatenated (global vertex and tet numbers).

    Attributes
    ----------
    vertices : (n, 4) float32
    tets : (m, 4) uint32
    tet_normals : (m, 4) float32
        Per tet: its outward normal in object space.
    colors : (n, 4) float32
    mesh_v, mesh_c : (meshes, 2) int64
        Per mesh: its vertex range, its chunk range.
    clo, chi : (c,) int64
        Per chunk (a run of tets of one of its layout's clusters, see ``section_batch._chunks``):
        its tet range.
    ccenter, chalf : (c, 4) float64
        Per chunk: the middle and half size of its box (object space).
    mesh_cells : (meshes, 2) int64
        Per mesh sliced cell by cell (see :mod:`.cells`): its cell range (empty: by tets).
    cell_edge_start : (cells + 1,) int64
        Per cell: its range of ``cell_edges``.
    cell_edges : (e, 2) uint32
        Lower vertex index first.
    cell_tet : (cells, 4) uint32
        One tet of each cell, for its normal.
    cell_center : (cells, 4) float64
    cell_radius : (cells,) float64
    tet_edges : (m, 6) uint32
        Per tet: its edges' numbers in its mesh, in :data:`~.cases.TET_EDGE_PAIRS` order.
    edge_ends : (e, 2) uint32
        Per edge: its vertices' numbers in its mesh, lower first (:func:`~.layout.layout_edges`).
    mesh_e : (meshes, 2) int64
        Per mesh: its edge range.
    flat : (meshes,) uint8
        Per mesh: 1 when each of its tets is of one colour (its four vertices' colours equal).
    """

    vertices: np.ndarray
    tets: np.ndarray
    tet_normals: np.ndarray
    colors: np.ndarray
    mesh_v: np.ndarray
    mesh_c: np.ndarray
    clo: np.ndarray
    chi: np.ndarray
    ccenter: np.ndarray
    chalf: np.ndarray
    mesh_cells: np.ndarray
    cell_edge_start: np.ndarray
    cell_edges: np.ndarray
    cell_tet: np.ndarray
    cell_center: np.ndarray
    cell_radius: np.ndarray
    tet_edges: np.ndarray
    edge_ends: np.ndarray
    mesh_e: np.ndarray
    flat: np.ndarray


class Instances(NamedTuple):
    """The instances to slice, in the batch's order.

    Attributes
    ----------
    mesh : (k,) int64
        Each one's mesh in the :class:`Pool`.
    mvs : (k, 5, 5) float64
        Model-view transforms.
    flips : (k,) float64
        ``1.0`` where ``det(mv[:4, :4]) > 0``, else ``-1.0``.
    visible : (k,) uint8
        0 for an instance culled whole.
    alpha : (k,) float64
        What its rows' alpha is: NaN for its colours' own, else this value (see :func:`_w_side`).
    cull : (k,) uint8
        1: leave out the polygons that face away from ``eye``.
    eye : (3,) float64
        Where the picture is seen from, in the output's frame.
    """

    mesh: np.ndarray
    mvs: np.ndarray
    flips: np.ndarray
    visible: np.ndarray
    alpha: np.ndarray
    cull: np.ndarray
    eye: np.ndarray


class Rows(NamedTuple):
    """The shared output.

    Attributes
    ----------
    out : (r, 10) float32
        Three rows per triangle (:data:`~.section_batch_tets.ROW`).
    start : (k + 1,) int64
        Instance ``i``'s first row; ``start[k]`` is one past the last.
    count : (k,) int64
        Instance ``i``'s rows.
    w_range : (k, 2) float64
        Instance ``i``'s least and greatest camera-space w.
    cut : (k,) int64
        Instance ``i``'s cut tets (or cells), polygons facing away included: has it a section?
    """

    out: np.ndarray
    start: np.ndarray
    count: np.ndarray
    w_range: np.ndarray
    cut: np.ndarray


class BatchScratch(NamedTuple):
    """Arrays reused instance after instance, sized for the pool's largest mesh.

    Attributes
    ----------
    cam : (v, 4) float64
        Camera-space vertices of the instance being sliced.
    cut : (t,) int64
        The cut tets (or cells) of the instance.
    cmask : (t,) int64
        Their cases (or the start of their corners in ``q``).
    g : (12,) float64
        The normals' transform (:func:`~.section_kernels.normal_transform`).
    q : (p, 3) float64
    qc : (p, 4) float64
        Polygon corners and their colours.
    qe : (p,) int64
        Per corner: the cell edge it lies on.
    ang : (p,) float64
    order : (p,) int64
        A cell polygon's corners' angles and their order.
    keep : (c,) int64
        The chunks of the instance its slice meets.
    above : (v,) uint8
        Per vertex of the instance: camera-space w > 0.
    point : (e,) int64
        Per edge of the mesh: its point's number (-1 between instances).
    elist : (4 t,) int64
        Per point: its edge.
    tj : (4 t,) int64
        Per cut tet: its polygon's point numbers.
    rec : (16 t,) float32
    recc : (16 t,) float32
        Per point ``j``, from ``4 j``: xyz and one unused; its colour.
    sj : (4 t,) float64
        Per point: how far along its edge.
    n64 : (3, t) float64
    tn : (3, t) float32
        Per cut tet: its normal, then made unit.
    """

    cam: np.ndarray
    cut: np.ndarray
    cmask: np.ndarray
    g: np.ndarray
    q: np.ndarray
    qc: np.ndarray
    qe: np.ndarray
    ang: np.ndarray
    order: np.ndarray
    keep: np.ndarray
    above: np.ndarray
    point: np.ndarray
    elist: np.ndarray
    tj: np.ndarray
    rec: np.ndarray
    recc: np.ndarray
    sj: np.ndarray
    n64: np.ndarray
    tn: np.ndarray


@njit(cache=True)
def _slice_batch(pool, inst, first, start_row, rows, ws, w_cue):
    """Slice instances ``first..`` into ``rows`` from row ``start_row``; returns the rows needed.
    Each one's reach along w goes into ``rows.w_range``, with ``w_cue`` its rows' alpha too
    (:func:`_w_side`).

    A mesh with a cell range in ``pool.mesh_cells`` is sliced cell by cell, any
    other tet by tet. The rows needed may exceed ``len(rows.out)``: then nothing
    past the end was written and the caller grows the output and calls again.

    The bundles come as plain tuples and are named again here: numba's dispatcher types a plain
    tuple of arrays in C, a named tuple in Python (about 10 us a call).
    """
    pool, inst, rows, ws = Pool(*pool), Instances(*inst), Rows(*rows), BatchScratch(*ws)
    start, count, mesh_cells = rows.start, rows.count, pool.mesh_cells
    o = start_row
    for k in range(first, inst.mesh.shape[0]):
        start[k] = o
        m = inst.mesh[k]
        _w_side(pool, inst, k, ws, rows.w_range, w_cue)
        if inst.visible[k]:
            if mesh_cells[m, 1] > mesh_cells[m, 0]:
                ncut = _cut_cells(pool, inst, k, ws)
                rows.cut[k] = ncut
                o = _cell_rows(pool, inst, k, ncut, rows.out, o, ws)
            else:
                cuts = _cut_tets(pool, inst, k, ws)
                rows.cut[k] = cuts[0]
                o = _tet_rows(pool, inst, k, cuts, rows.out, o, ws)
        else:
            rows.cut[k] = 0
        count[k] = o - start[k]
        start[k + 1] = o
    return o


@njit(cache=True)
def _instances_in_view(mvs, center, radius, planes, in_slice, visible, flips):
    """Which instances' bounding spheres meet the slice (``in_slice (k,) bool``), and which meet
    both the slice and every view plane (``visible``); each one's orientation into ``flips``
    (:func:`_orientation`). Returns how many orientations were too close to call (then the
    caller takes ``np.linalg.det``'s, as the per-object slicer does).

    Instance ``k`` is the sphere ``center[k] (4,)``, ``radius[k]`` of its mesh moved by
    ``mvs[k] (5, 5)``; ``planes (p, 4)`` are ``(n, d)``, inside where ``n . x + d >= 0``. The
    radius grows by a bound on the stretch of ``A = mvs[k][:4, :4]``: the square root of a
    Gershgorin bound on ``A^T A`` (exact for a rotation times a uniform scale, an upper bound
    otherwise), and by a margin (vertices are float32, spheres float64). The slice of a 4D ball
    at w distance ``d`` is a 3D ball of radius ``sqrt(r^2 - d^2)``: that is tested against the planes.
    """
    unsure = 0
    for k in range(mvs.shape[0]):
        a = mvs[k]
        g = 0.0
        for i in range(4):
            row = 0.0
            for j in range(4):
                row += abs(a[0, i] * a[0, j] + a[1, i] * a[1, j] + a[2, i] * a[2, j] + a[3, i] * a[3, j])
            g = max(g, row)
        r = radius[k] * np.sqrt(g) * (1.0 + 1e-6) + 1e-6
        x0, x1, x2, x3 = center[k, 0], center[k, 1], center[k, 2], center[k, 3]
        cx = a[0, 0] * x0 + a[0, 1] * x1 + a[0, 2] * x2 + a[0, 3] * x3 + a[0, 4]
        cy = a[1, 0] * x0 + a[1, 1] * x1 + a[1, 2] * x2 + a[1, 3] * x3 + a[1, 4]
        cz = a[2, 0] * x0 + a[2, 1] * x1 + a[2, 2] * x2 + a[2, 3] * x3 + a[2, 4]
        cw = a[3, 0] * x0 + a[3, 1] * x1 + a[3, 2] * x2 + a[3, 3] * x3 + a[3, 4]
        seen = abs(cw) <= r
        in_slice[k] = seen
        r3 = np.sqrt(max(r * r - cw * cw, 0.0))
        for p in range(planes.shape[0]):
            if not seen:
                break
            n = np.sqrt(planes[p, 0] ** 2 + planes[p, 1] ** 2 + planes[p, 2] ** 2)
            seen = planes[p, 0] * cx + planes[p, 1] * cy + planes[p, 2] * cz + planes[p, 3] >= -r3 * n
        visible[k] = seen
        flips[k] = _orientation(a)
        unsure += flips[k] == 0.0
    return unsure


@njit(inline="always")
def _w_side(pool, inst, k, ws, w_range, w_cue):
    """Instance ``k``'s least and greatest camera-space w of its vertices into ``w_range[k]``
    (``(k, 2) float64``): how far the posed mesh reaches either side of the slice. For an
    instance not culled whole, also its vertices in camera space (``ws.cam``, the per-object
    slicer's sums) and whether each lies above the slice (``ws.above``): one pass for all.

    With ``w_cue``, also where the slice cuts it along that extent into ``inst.alpha[k]``, the
    alpha of its rows: 0 mid-way, -1 or 1 at its ends (the renderer's w cue, as
    :func:`~across_dimensions.game.entity_sections.w_offset` gives it); else NaN (its colours' own).
    """
    verts, cam, above = pool.vertices, ws.cam, ws.above
    m = inst.mesh[k]
    mv = inst.mvs[k]
    v_lo = pool.mesh_v[m, 0]
    a00, a01, a02, a03, a04 = mv[0, 0], mv[0, 1], mv[0, 2], mv[0, 3], mv[0, 4]
    a10, a11, a12, a13, a14 = mv[1, 0], mv[1, 1], mv[1, 2], mv[1, 3], mv[1, 4]
    a20, a21, a22, a23, a24 = mv[2, 0], mv[2, 1], mv[2, 2], mv[2, 3], mv[2, 4]
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    lo, hi = np.inf, -np.inf
    if inst.visible[k]:
        # Flat views and unsigned indices, the extent along w in a loop of its own: the
        # compiler then moves the vertices as vectors (a min/max reduction keeps a loop scalar).
        vf, cf = verts.reshape(-1), cam.reshape(-1)
        vb = U(4) * U(v_lo)
        for i in range(U(pool.mesh_v[m, 1] - v_lo)):
            j = vb + U(4) * i
            x, y, z, u = vf[j], vf[j + U(1)], vf[j + U(2)], vf[j + U(3)]
            cf[U(4) * i] = a00 * x + a01 * y + a02 * z + a03 * u + a04
            cf[U(4) * i + U(1)] = a10 * x + a11 * y + a12 * z + a13 * u + a14
            cf[U(4) * i + U(2)] = a20 * x + a21 * y + a22 * z + a23 * u + a24
            cf[U(4) * i + U(3)] = m0 * x + m1 * y + m2 * z + m3 * u + m4
        for i in range(U(pool.mesh_v[m, 1] - v_lo)):
            w = cf[U(4) * i + U(3)]
            above[i] = w > 0.0
            lo = min(lo, w)
            hi = max(hi, w)
    else:
        for vi in range(v_lo, pool.mesh_v[m, 1]):
            w = m0 * verts[vi, 0] + m1 * verts[vi, 1] + m2 * verts[vi, 2] + m3 * verts[vi, 3] + m4
            lo = min(lo, w)
            hi = max(hi, w)
    w_range[k, 0] = lo
    w_range[k, 1] = hi
    half = 0.5 * (hi - lo)
    inst.alpha[k] = (0.5 * (lo + hi) / half if half > 0.0 else 0.0) if w_cue else np.nan


@njit(inline="always")
def _cut_cells(pool, inst, k, ws):
    """The corners of the polygons instance ``k``'s slice cuts from its cells; returns
    the number of polygons.

    Polygon ``i`` is cell ``ws.cut[i]``, its corners rows ``ws.cmask[i]`` to
    ``ws.cmask[i + 1]`` of ``ws.q`` (colours in ``ws.qc``): the cut points of the
    cell's real edges, interpolated from the lower vertex index exactly as the
    tet slicer does, so neighbouring cells (and the tet slicer) agree on every
    shared point. Cells cut in fewer than three points are left out.

    A cell's cut edges are listed first (``ws.qe``), from which side of the slice each
    vertex lies (``ws.above``), compacted without a branch: a cell has some thirty
    edges, a handful of them cut, and whether one is cut is a coin toss to the branch
    predictor. Then only those are interpolated. Flat views and unsigned indices, as in
    the tet slicer (:func:`~.section_batch_tets._rows`).
    """
    center, radius, above = pool.cell_center, pool.cell_radius, ws.above
    cut, first, qe, edge_start = ws.cut, ws.cmask, ws.qe, pool.cell_edge_start
    ef, colf, cf = pool.cell_edges.reshape(-1), pool.colors.reshape(-1), ws.cam.reshape(-1)
    qf, qcf = ws.q.reshape(-1), ws.qc.reshape(-1)
    m = inst.mesh[k]
    mv = inst.mvs[k]
    v_lo = U(pool.mesh_v[m, 0])
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    w_gain = np.sqrt(m0**2 + m1**2 + m2**2 + m3**2)
    npoly = 0
    first[0] = 0
    n = 0
    for c in range(pool.mesh_cells[m, 0], pool.mesh_cells[m, 1]):
        dc = m0 * center[c, 0] + m1 * center[c, 1] + m2 * center[c, 2] + m3 * center[c, 3] + m4
        if abs(dc) > radius[c] * w_gain:
            continue
        n0 = n
        for e in range(U(edge_start[c]), U(edge_start[c + 1])):
            qe[n] = e
            n += above[U(ef[U(2) * e]) - v_lo] != above[U(ef[U(2) * e + U(1)]) - v_lo]
        if n - n0 < 3:
            n = n0
            continue
        for jj in range(n0, n):
            j = U(jj)
            e = U(qe[j])
            va, vb = U(ef[U(2) * e]), U(ef[U(2) * e + U(1)])
            a, b = U(4) * (va - v_lo), U(4) * (vb - v_lo)
            s = cf[a + U(3)] / (cf[a + U(3)] - cf[b + U(3)])
            for r in range(3):
                qf[U(3) * j + U(r)] = cf[a + U(r)] + s * (cf[b + U(r)] - cf[a + U(r)])
            ca, cb = U(4) * va, U(4) * vb
            for r in range(4):
                qcf[U(4) * j + U(r)] = colf[ca + U(r)] + s * (colf[cb + U(r)] - colf[ca + U(r)])
        cut[npoly] = c
        npoly += 1
        first[npoly] = n
    return npoly


@njit(inline="always")
def _cell_rows(pool, inst, k, npoly, out, o, ws):
    """The polygons of :func:`_cut_cells` into ``out`` from row ``o``, each as a fan;
    returns the next row (rows past ``len(out)`` are counted, not written).

    A polygon's corners are put in order by their angle about their centroid,
    counter-clockwise seen from outside (along the cell's outward normal). With
    ``inst.cull[k]``, a polygon that faces away from ``inst.eye`` is left out, as the
    tet slicer does (:func:`~.section_batch_tets._faces_away`): a convex section's far
    half, which the rasterizer would set up only to cull it.
    """
    cell_tet, cut, first, q, qc, ang, order, cam = (
        pool.cell_tet,
        ws.cut,
        ws.cmask,
        ws.q,
        ws.qc,
        ws.ang,
        ws.order,
        ws.cam,
    )
    cap = out.shape[0]
    flip = inst.flips[k]
    alpha = inst.alpha[k]
    keep_alpha = np.isnan(alpha)
    v_lo = pool.mesh_v[inst.mesh[k], 0]
    cull = inst.cull[k] != 0
    ex, ey, ez = inst.eye[0], inst.eye[1], inst.eye[2]
    for i in range(npoly):
        c = cut[i]
        f0 = first[i]
        n = first[i + 1] - f0
        a, b, d, e = cell_tet[c, 0] - v_lo, cell_tet[c, 1] - v_lo, cell_tet[c, 2] - v_lo, cell_tet[c, 3] - v_lo
        nx, ny, nz = _normal_of(
            cam[b, 0] - cam[a, 0], cam[b, 1] - cam[a, 1], cam[b, 2] - cam[a, 2], cam[b, 3] - cam[a, 3],
            cam[d, 0] - cam[a, 0], cam[d, 1] - cam[a, 1], cam[d, 2] - cam[a, 2], cam[d, 3] - cam[a, 3],
            cam[e, 0] - cam[a, 0], cam[e, 1] - cam[a, 1], cam[e, 2] - cam[a, 2], cam[e, 3] - cam[a, 3],
            flip,
        )  # fmt: skip
        # The polygon lies in the slice (w = 0): its plane holds its corners, so one tells the eye's side.
        if cull and _faces_away(ex - q[f0, 0], ey - q[f0, 1], ez - q[f0, 2], 0.0, nx, ny, nz, 0.0):
            continue
        if o + 3 * (n - 2) > cap:
            o += 3 * (n - 2)
            continue
        # Angles in the polygon's plane about the centroid, in the basis (u, n x u).
        mx = my = mz = 0.0
        for j in range(f0, f0 + n):
            mx += q[j, 0]
            my += q[j, 1]
            mz += q[j, 2]
        mx /= n
        my /= n
        mz /= n
        ux, uy, uz = q[f0, 0] - mx, q[f0, 1] - my, q[f0, 2] - mz
        vx = ny * uz - nz * uy
        vy = nz * ux - nx * uz
        vz = nx * uy - ny * ux
        for j in range(n):
            dx, dy, dz = q[f0 + j, 0] - mx, q[f0 + j, 1] - my, q[f0 + j, 2] - mz
            ang[j] = _pseudo_angle(dx * ux + dy * uy + dz * uz, dx * vx + dy * vy + dz * vz)
            h = j  # insertion sort: a polygon has a handful of corners
            while h > 0 and ang[order[h - 1]] > ang[j]:
                order[h] = order[h - 1]
                h -= 1
            order[h] = j
        for j in range(3 * (n - 2)):
            src = f0 + (order[0] if j % 3 == 0 else order[j // 3 + j % 3])
            out[o, 0] = q[src, 0]
            out[o, 1] = q[src, 1]
            out[o, 2] = q[src, 2]
            out[o, 3] = nx
            out[o, 4] = ny
            out[o, 5] = nz
            out[o, 6] = qc[src, 0]
            out[o, 7] = qc[src, 1]
            out[o, 8] = qc[src, 2]
            out[o, 9] = qc[src, 3] if keep_alpha else alpha
            o += 1
    return o


# size: scalar helper, coordinates in registers
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
