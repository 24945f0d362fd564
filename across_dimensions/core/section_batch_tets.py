"""The tet-by-tet path of :func:`~.section_batch_kernels._slice_batch`: one instance's cut tets,
then their triangles, bit for bit those of :func:`~.section.cross_section`.

Each step is a loop of its own without unpredictable branches, as in the per-object slicer
(:mod:`.section_kernels`), whose arithmetic it repeats exactly:

1. :func:`_cut_tets`: the chunks of tets the slice meets (bounding boxes), then their cut
   tets compacted without a branch, from one byte per vertex saying whether it lies above the
   slice (made with the vertices' camera-space coordinates in one pass over them).
2. :func:`_tet_rows`: per cut tet its normal and its polygon's corners (only the real ones:
   three or four), the normals made unit in a loop of their own (vectorized), the corners'
   colours only for a mesh whose tets are not each of one colour (a one-coloured tet's
   corners all have its colour, exactly: ``c + s (c - c) == c``), then the rows.

The helpers are inlined into the batch kernel and take the bundles whole: numba counts
references on every call of a function that takes arrays.
"""

from __future__ import annotations

import numpy as np

from ._jit import njit
from .cases import CASE_COUNT, CASE_LOCAL_FLAT, CASE_REVERSED, CASE_TRIANGLES
from .section_kernels import U, _unit_normals, normal_transform

#: Floats per output vertex: position 3, normal 3, colour 4 (the renderer's layout).
ROW = 10


@njit(inline="always")
def _cut_tets(pool, inst, k, ws):
    """The tets of instance ``k`` its slice cuts, into ``ws.cut`` (their cases into
    ``ws.cmask``); returns their number and their triangles'.

    Chunks of tets are culled by their box. The vertices in camera space, and which side of
    the slice each lies on, are in ``ws.cam`` and ``ws.above`` already
    (:func:`~.section_batch_kernels._w_side`).
    """
    tets, clo, chi, ccenter, chalf = pool.tets, pool.clo, pool.chi, pool.ccenter, pool.chalf
    above, cut, cmask, keep = ws.above, ws.cut, ws.cmask, ws.keep
    m = inst.mesh[k]
    mv = inst.mvs[k]
    v_lo = pool.mesh_v[m, 0]
    m0, m1, m2, m3, m4 = mv[3, 0], mv[3, 1], mv[3, 2], mv[3, 3], mv[3, 4]
    a0, a1, a2, a3 = abs(m0), abs(m1), abs(m2), abs(m3)
    nkeep = 0
    for cl in range(pool.mesh_c[m, 0], pool.mesh_c[m, 1]):
        c0, c1, c2, c3 = ccenter[cl, 0], ccenter[cl, 1], ccenter[cl, 2], ccenter[cl, 3]
        h0, h1, h2, h3 = chalf[cl, 0], chalf[cl, 1], chalf[cl, 2], chalf[cl, 3]
        # The box's w reaches |w(middle)| - sum |row_j| half_j; the slack covers rounding.
        reach = a0 * h0 + a1 * h1 + a2 * h2 + a3 * h3
        size = abs(m4) + a0 * abs(c0) + a1 * abs(c1) + a2 * abs(c2) + a3 * abs(c3) + reach
        hit = abs(m0 * c0 + m1 * c1 + m2 * c2 + m3 * c3 + m4) <= reach + 1e-9 * size
        keep[nkeep] = cl
        nkeep += hit
    vl = U(v_lo)
    tf = tets.reshape(-1)
    ncut = 0
    ntri = 0
    for kc in range(nkeep):
        cl = keep[kc]
        for t in range(U(clo[cl]), U(chi[cl])):
            mask = (
                U(above[U(tf[U(4) * t]) - vl])
                | (U(above[U(tf[U(4) * t + U(1)]) - vl]) << U(1))
                | (U(above[U(tf[U(4) * t + U(2)]) - vl]) << U(2))
                | (U(above[U(tf[U(4) * t + U(3)]) - vl]) << U(3))
            )
            # Compacted without a branch: near the slice whether a tet is cut is a coin toss.
            cut[ncut] = t
            cmask[ncut] = mask
            ncut += CASE_TRIANGLES[mask] != 0
            ntri += CASE_TRIANGLES[mask]
    return ncut, ntri


@njit(inline="always")
def _tet_rows(pool, inst, k, cuts, out, o, ws):
    """The triangles of instance ``k``'s cut tets (``cuts``: :func:`_cut_tets`'s counts) into
    ``out`` from row ``o``; returns the next row. When they might not fit, nothing is written
    and the rows all cut tets need are counted (the caller grows the output). With
    ``inst.cull[k]``, tets whose polygon faces away from ``inst.eye`` are left out.

    The points, normal and winding of the per-object slicer
    (:func:`~.section_kernels._points_by_tet`, ``_unit_normals``, ``_rows``), bit for bit.
    """
    ncut, ntri = cuts
    if o + 3 * ntri > out.shape[0]:
        return o + 3 * ntri
    m = inst.mesh[k]
    ncut, npt = _corners(pool, inst, k, ncut, ws)
    if not pool.flat[m]:
        _corner_colors(pool, m, npt, ws)
    _unit_normals(ncut, ws.n64, ws.tn)  # the per-object slicer's own loop: the same bits
    return _rows(pool, inst, k, ncut, out, o, ws)


@njit(inline="always")
def _corners(pool, inst, k, ncut, ws):
    """Per cut tet ``i`` kept: its normal, not yet unit, into ``ws.n64[:, i]``, and the point
    numbers of its polygon's corners into ``ws.tj[4 i:]`` (a triangle's fourth repeats its
    third); then each point once, though several cut tets share its edge: its xyz into
    ``ws.rec[4 j:]`` (float32, one unused), its interpolation factor into ``ws.sj[j]``.
    Returns the tets kept (compacted in ``ws.cut`` and ``ws.cmask``) and the points' number.

    With ``inst.cull[k]``, a tet whose polygon faces away from ``inst.eye`` is left out
    (:func:`_faces_away`). ``ws.point`` numbers the instance's cut edges (-1 on entry and on
    return), ``ws.elist`` lists them. A point is interpolated from its edge's lower vertex
    index, as the per-object slicer does (:func:`~.section_kernels._points_by_edge`), so the
    same to the bit. Flat views and unsigned indices (``U``), as in :func:`_rows`.
    """
    cut, cmask, point, elist, tj, g = ws.cut, ws.cmask, ws.point, ws.elist, ws.tj, ws.g
    nf, ef, tf, cf = pool.tet_normals.reshape(-1), pool.tet_edges.reshape(-1), pool.tets.reshape(-1), ws.cam.reshape(-1)
    mv = inst.mvs[k]
    normal_transform(mv, inst.flips[k], g)
    g0, g1, g2, g3, g4, g5 = g[0], g[1], g[2], g[3], g[4], g[5]
    g6, g7, g8, g9, g10, g11 = g[6], g[7], g[8], g[9], g[10], g[11]
    h0, h1, h2, h3 = _w_cofactors(mv, inst.flips[k])
    cull = inst.cull[k] != 0
    ex, ey, ez = inst.eye[0], inst.eye[1], inst.eye[2]
    v_lo = U(pool.mesh_v[inst.mesh[k], 0])
    nx, ny, nz = ws.n64[0], ws.n64[1], ws.n64[2]
    npt = 0  # signed, as the point numbers it is chosen among (a signed and an unsigned make a float)
    kept = U(0)
    for idx in range(ncut):
        i = U(idx)
        t = U(cut[i])
        mask = U(cmask[i])
        t4 = U(4) * t
        n0, n1, n2, n3 = nf[t4], nf[t4 + U(1)], nf[t4 + U(2)], nf[t4 + U(3)]
        x = g0 * n0 + g1 * n1 + g2 * n2 + g3 * n3
        y = g4 * n0 + g5 * n1 + g6 * n2 + g7 * n3
        z = g8 * n0 + g9 * n1 + g10 * n2 + g11 * n3
        if cull:
            v = U(4) * (U(tf[t4]) - v_lo)
            w = h0 * n0 + h1 * n1 + h2 * n2 + h3 * n3
            if _faces_away(ex - cf[v], ey - cf[v + U(1)], ez - cf[v + U(2)], cf[v + U(3)], x, y, z, w):
                continue
        cut[kept] = t  # compacted in place: kept <= i
        cmask[kept] = mask
        nx[kept], ny[kept], nz[kept] = x, y, z
        for e in range(4):
            # Number the edge's point if it has none yet, without a branch.
            eid = U(ef[U(6) * t + U(CASE_LOCAL_FLAT[U(4) * mask + U(e)])])
            j = point[eid]
            new = j < 0
            j = npt if new else j
            point[eid] = j
            elist[npt] = eid
            npt += new
            tj[U(4) * kept + U(e)] = j
        kept += U(1)
    ends, rec, sj = pool.edge_ends.reshape(-1), ws.rec, ws.sj
    e_lo = U(pool.mesh_e[inst.mesh[k], 0])
    for jj in range(npt):
        j = U(jj)
        eid = U(elist[j])
        point[eid] = -1
        a = U(4) * U(ends[U(2) * (e_lo + eid)])
        b = U(4) * U(ends[U(2) * (e_lo + eid) + U(1)])
        s = cf[a + U(3)] / (cf[a + U(3)] - cf[b + U(3)])
        sj[j] = s
        for r in range(3):
            rec[U(4) * j + U(r)] = np.float32(cf[a + U(r)] + s * (cf[b + U(r)] - cf[a + U(r)]))
    return np.int64(kept), npt


#: A polygon is left out when the eye lies behind its plane by more than this fraction of its
#: distance from the polygon (the cosine of the angle from the plane): nearly edge-on ones are
#: kept, so the rasterizer, which culls back faces itself, decides those as it always did.
CULL_MARGIN = 1e-2


# size: scalar helper, coordinates in registers
@njit(inline="always")
def _faces_away(dx, dy, dz, vw, nx, ny, nz, nw):
    """Does a tet's section face away from the eye, clearly? ``(dx, dy, dz)`` is the eye minus
    one vertex of the tet (camera space xyz), ``vw`` that vertex's w, ``(nx, ny, nz, nw)`` the
    tet's outward 4D normal. The section's plane holds the points ``x`` of the slice (w = 0)
    with ``n . (x - v) = nw vw``, so the eye's side of it is the sign of ``n . d - nw vw``.
    Scalars in, scalars out: an inlined function taking arrays would count references."""
    side = dx * nx + dy * ny + dz * nz - nw * vw
    far = (CULL_MARGIN * CULL_MARGIN) * (nx * nx + ny * ny + nz * nz) * (dx * dx + dy * dy + dz * dz)
    return side < 0.0 and side * side > far


@njit(inline="always")
def _w_cofactors(mv, flip):
    """The w row of :func:`~.section_kernels.normal_transform`'s ``flip cof(A)``, ``A = mv[:4,
    :4]``: what turns an object-space tet normal into the w of its camera-space normal."""
    out0 = out1 = out2 = out3 = 0.0
    for j in range(4):
        c0 = 1 if j == 0 else 0
        c1 = 2 if j <= 1 else 1
        c2 = 3 if j <= 2 else 2
        minor = (
            mv[0, c0] * (mv[1, c1] * mv[2, c2] - mv[1, c2] * mv[2, c1])
            - mv[0, c1] * (mv[1, c0] * mv[2, c2] - mv[1, c2] * mv[2, c0])
            + mv[0, c2] * (mv[1, c0] * mv[2, c1] - mv[1, c1] * mv[2, c0])
        )
        value = -flip * minor if j % 2 == 0 else flip * minor  # the sign of (3 + j)
        if j == 0:
            out0 = value
        elif j == 1:
            out1 = value
        elif j == 2:
            out2 = value
        else:
            out3 = value
    return out0, out1, out2, out3


@njit(inline="always")
def _corner_colors(pool, m, npt, ws):
    """The colours of :func:`_corners`' points into ``ws.recc[4 j:]`` (rgba), for a mesh ``m``
    of many-coloured tets."""
    colors, ends, elist, sj, recc = pool.colors, pool.edge_ends, ws.elist, ws.sj, ws.recc
    e_lo, v_lo = pool.mesh_e[m, 0], pool.mesh_v[m, 0]
    for j in range(npt):
        a, b = v_lo + ends[e_lo + elist[j], 0], v_lo + ends[e_lo + elist[j], 1]
        s = sj[j]
        for r in range(4):
            recc[4 * j + r] = np.float32(colors[a, r] + s * (colors[b, r] - colors[a, r]))


@njit(inline="always")
def _rows(pool, inst, k, ncut, out, o, ws):
    """Three rows per triangle into ``out`` from row ``o``: each polygon fanned from its first
    corner, wound outward (the case's :data:`~.cases.CASE_REVERSED`); returns the next row.

    Copies only: a one-coloured tet's rows take its first vertex's colour, the alpha is
    ``inst.alpha[k]`` unless that is NaN. Flat views and unsigned indices (``U``): a row's
    ten floats are then stored with constant offsets.
    """
    cut, cmask, tj, rec, recc = ws.cut, ws.cmask, ws.tj, ws.rec, ws.recc
    tx, ty, tz = ws.tn[0], ws.tn[1], ws.tn[2]
    of, cf, tf = out.reshape(-1), pool.colors.reshape(-1), pool.tets.reshape(-1)
    flat = pool.flat[inst.mesh[k]] != 0
    reverse = CASE_REVERSED[1 if inst.flips[k] < 0.0 else 0]
    keep_alpha = np.isnan(inst.alpha[k])
    alpha = np.float32(inst.alpha[k])
    row = U(o)
    for idx in range(ncut):
        i = U(idx)
        mask = U(cmask[i])
        four = CASE_COUNT[mask] == 4
        rev = reverse[mask] != 0
        fx, fy, fz = tx[i], ty[i], tz[i]
        c0 = U(4) * U(tf[U(4) * U(cut[i])])
        cr, cg, cb, ca = cf[c0], cf[c0 + U(1)], cf[c0 + U(2)], cf[c0 + U(3)]
        ca = ca if keep_alpha else alpha
        j0, j1, j2, j3 = U(tj[U(4) * i]), U(tj[U(4) * i + U(1)]), U(tj[U(4) * i + U(2)]), U(tj[U(4) * i + U(3)])
        # Fan from corner 0: triangles (0, 1, 2) and (0, 2, 3), their last two swapped when reversed.
        for kk in range(6 if four else 3):
            j = j0
            if kk == 1 or kk == 2:
                j = j2 if rev == (kk == 1) else j1
            elif kk == 4 or kk == 5:
                j = j3 if rev == (kk == 4) else j2
            b = U(4) * j
            if not flat:
                cr, cg, cb, ca = recc[b], recc[b + U(1)], recc[b + U(2)], recc[b + U(3)]
                ca = ca if keep_alpha else alpha
            r = U(ROW) * (row + U(kk))
            of[r] = rec[b]
            of[r + U(1)] = rec[b + U(1)]
            of[r + U(2)] = rec[b + U(2)]
            of[r + U(3)] = fx
            of[r + U(4)] = fy
            of[r + U(5)] = fz
            of[r + U(6)] = cr
            of[r + U(7)] = cg
            of[r + U(8)] = cb
            of[r + U(9)] = ca
        row += U(6) if four else U(3)
    return np.int64(row)
