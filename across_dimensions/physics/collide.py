"""Narrowphase: contact points between hyperspheres, 4D boxes and the static world.

Every routine writes contacts into caller-owned arrays and returns how many it
wrote. A contact is a world point ``(4,)``, a unit normal ``(4,)`` pointing from
the first shape to the second, and a depth (positive when overlapping, negative
down to ``-margin`` for speculative contacts that are about to touch, which lets
the solver stop fast bodies before they pass through each other).

Box-box uses the separating-axis test over the 56 candidate axes of two 4D
boxes: the 4 + 4 cell (3-face) normals and, for every 2-face of one box and edge
of the other, the direction orthogonal to both (the 4D analogue of the 3D
edge-edge cross products). The contact points are the corners of the overlap
region: vertices of each box inside the other plus the points where each box's
edges leave the other box. A face-to-face contact of two stacked boxes thus gets
the corners of the 3D overlap cell, which is what makes stacks rest.
Candidates are thinned to at most :data:`MAX_POINTS` by farthest-point sampling
so the manifold keeps its outline.

The 3D world (ground and boxes that extend along all of ``w``) reuses the same
routines: a world box becomes a 4D box whose ``w`` extent comfortably covers the
body it is tested against, so its ``w`` faces never win the separating axis.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import PLANE_I, PLANE_J

#: Most contact points kept per touching pair (a 3D overlap cell has 8 corners).
MAX_POINTS = 8
#: Scratch rows needed by :func:`box_box` for its candidate points.
SCRATCH_POINTS = 160
#: Rows of the ``(SCRATCH_ROWS, 4)`` work array the routines here use.
SCRATCH_ROWS = 36 + SCRATCH_POINTS

SPHERE = 0
BOX = 1


@njit(inline="always")
def written_before(out_p, k, written, cp, pick) -> bool:
    """Is candidate ``cp[pick]`` already among the contact points ``out_p[k : k + written]``?"""
    for q in range(written):
        same = True
        for b in range(4):
            if out_p[k + q, b] != cp[pick, b]:
                same = False
                break
        if same:
            return True
    return False


@njit(inline="always")
def most_aligned_axis(rot, n) -> int:
    """The column of ``rot`` ``(4, 4)`` most aligned with ``n`` ``(4,)`` (largest ``|rot[:, a] . n|``;
    the first on ties): the box axis a contact region's face is normal to."""
    drop = 0
    big = -1.0
    for a in range(4):
        s = 0.0
        for b in range(4):
            s += rot[b, a] * n[b]
        if abs(s) > big:
            big = abs(s)
            drop = a
    return drop


@njit(cache=True)
def reduce_points(cp, cd, cnt, n, rot, wk, out_p, out_n, out_d, k):
    """Keep the candidates that are extreme along the diagonals of a box face.

    A face-to-face contact region is (close to) a 3D box whose edges follow the
    lateral axes of one of the boxes, so the candidates farthest along the
    eight directions ``+-u1 +-u2 +-u3`` are its corners: the support outline a
    resting box needs. Nearly tied candidates (a vertex and the point where an
    edge through it leaves the speculative margin, or two almost coincident
    corners of the two boxes) resolve to the deepest.

    Parameters
    ----------
    cp : (M, 4) float64
        Candidate points; rows ``[:cnt]`` are used.
    cd : (M,) float64
        Candidate depths.
    cnt : int
    n : (4,) float64
        Shared contact normal, copied to every output row.
    rot : (4, 4) float64
        Rotation of the box whose face the region follows; its axis most
        aligned with ``n`` is dropped and the other three give ``u1, u2, u3``.
    wk : (4 + M, 4) float64
        Scratch.
    out_p, out_n : (C, 4) float64
    out_d : (C,) float64
    k : int
        First output row.

    Returns
    -------
    int
        Rows written (at most :data:`MAX_POINTS`).
    """
    if cnt == 0:
        return 0
    drop = most_aligned_axis(rot, n)
    u = wk[0:3]
    j = 0
    for a in range(4):
        if a == drop:
            continue
        for b in range(4):
            u[j, b] = rot[b, a]
        j += 1
    # Coordinates along u1..u3 once; each diagonal is then a sum of signs.
    pr = wk[4 : 4 + cnt]
    for i in range(cnt):
        for q in range(3):
            s = 0.0
            for b in range(4):
                s += cp[i, b] * u[q, b]
            pr[i, q] = s
    # The eight scans in one pass over the candidates (each scan keeps its own
    # farthest value and pick, so the picks are those of eight separate scans).
    far = np.full(8, -np.inf)
    picks = np.full(8, -1, dtype=np.int64)
    for i in range(cnt):
        p0 = pr[i, 0]
        p1 = pr[i, 1]
        p2 = pr[i, 2]
        for sgn in range(8):
            s0 = 1.0 if sgn & 1 else -1.0
            s1 = 1.0 if sgn & 2 else -1.0
            s2 = 1.0 if sgn & 4 else -1.0
            s = s0 * p0 + s1 * p1 + s2 * p2
            f = far[sgn]
            if s > f + 1e-4:
                far[sgn] = s
                picks[sgn] = i
            elif s >= f - 1e-4:
                if cd[i] > cd[picks[sgn]]:
                    picks[sgn] = i
                if s > f:
                    far[sgn] = s
    written = 0
    for sgn in range(8):
        pick = picks[sgn]
        if written_before(out_p, k, written, cp, pick):
            continue
        for b in range(4):
            out_p[k + written, b] = cp[pick, b]
            out_n[k + written, b] = n[b]
        out_d[k + written] = cd[pick]
        written += 1
    return written


@njit(cache=True)
def sphere_sphere(xa, ra, xb, rb, margin, wk, out_p, out_n, out_d, k):
    """One contact between two hyperspheres (normal from a to b); returns 0 or 1.

    ``wk`` is a ``(W, 4) float64`` scratch array, as for all routines here.
    """
    d = wk[0]
    dist2 = 0.0
    for a in range(4):
        d[a] = xb[a] - xa[a]
        dist2 += d[a] * d[a]
    reach = ra + rb + margin
    if dist2 > reach * reach:
        return 0
    dist = np.sqrt(dist2)
    if dist > 1e-12:
        for a in range(4):
            d[a] /= dist
    else:
        # Coincident centres: any direction separates them; pick up.
        for a in range(4):
            d[a] = 0.0
        d[1] = 1.0
    depth = ra + rb - dist
    for a in range(4):
        out_n[k, a] = d[a]
        out_p[k, a] = xa[a] + d[a] * (ra - 0.5 * depth)
    out_d[k] = depth
    return 1


@njit(cache=True)
def box_sphere(xb, rot, h, c, r, margin, wk, out_p, out_n, out_d, k):
    """One contact between a box and a hypersphere (normal from box to sphere).

    Parameters
    ----------
    xb : (4,) float64
        Box centre.
    rot : (4, 4) float64
        Box rotation (columns are its axes).
    h : (4,) float64
        Half extents.
    c : (4,) float64
        Sphere centre.
    r : float
        Sphere radius.

    Returns
    -------
    int
        0 or 1.
    """
    q = wk[0]
    for a in range(4):
        s = 0.0
        for m in range(4):
            s += rot[m, a] * (c[m] - xb[m])
        q[a] = s
    cl = wk[1]
    inside = True
    for a in range(4):
        v = q[a]
        if v > h[a]:
            v = h[a]
            inside = False
        elif v < -h[a]:
            v = -h[a]
            inside = False
        cl[a] = v
    nl = wk[2]
    for a in range(4):
        nl[a] = 0.0
    if not inside:
        dist2 = 0.0
        for a in range(4):
            nl[a] = q[a] - cl[a]
            dist2 += nl[a] * nl[a]
        if dist2 > (r + margin) * (r + margin):
            return 0
        dist = np.sqrt(dist2)
        for a in range(4):
            nl[a] /= dist
        depth = r - dist
    else:
        # Centre inside the box: leave through the nearest face.
        ax = 0
        gap = h[0] - abs(q[0])
        for a in range(1, 4):
            g = h[a] - abs(q[a])
            if g < gap:
                gap = g
                ax = a
        sg = 1.0 if q[ax] >= 0.0 else -1.0
        nl[ax] = sg
        cl[ax] = sg * h[ax]
        depth = r + gap
    for a in range(4):
        s = 0.0
        t = 0.0
        for m in range(4):
            s += rot[a, m] * nl[m]
            t += rot[a, m] * cl[m]
        out_n[k, a] = s
        out_p[k, a] = xb[a] + t - 0.5 * depth * s
    out_d[k] = depth
    return 1


#: Bit 16 a of a vertex mask word for each axis a (see :func:`_clip_into`).
_AXIS_BITS = 1 | (1 << 16) | (1 << 32) | (1 << 48)


@njit(cache=True)
def _clip_into(tx, trot, th, loc_c, loc_axes, oh, margin, m, sup, cp, cd, cnt, v, pl, lim):
    """Add the points of box O that lie inside box T (expanded by ``margin`` along ``m``).

    Points are O's vertices inside T and the points where O's edges cross T's
    boundary. Their depth is measured along ``m`` (the normal pointing out of T
    towards O): ``sup - m . p`` with ``sup`` the support of T along ``m``.
    Points are stored half-way between the two surfaces.

    Parameters
    ----------
    tx, trot, th : (4,), (4, 4), (4,) float64
        T's centre, rotation and half extents.
    loc_c : (4,) float64
        O's centre in T's frame.
    loc_axes : (4, 4) float64
        Column k is O's axis k in T's frame.
    oh : (4,) float64
        O's half extents.
    m : (4,) float64
        Unit normal (world).
    sup : float
    cp, cd : (M, 4), (M,) float64
        Candidate output.
    cnt : int
        Rows already used.
    v : (16, 4) float64
        Scratch for O's vertices.
    pl, lim : (4,) float64
        Scratch.

    Returns
    -------
    int
        New row count.
    """
    # T expanded by the margin only along the normal: a vertex that overhangs
    # T's face sideways is not supported by it.
    # Depth is measured to the face of T that m leaves through, when there is
    # one (T's face plane, tilted or not); the support plane of T along m
    # would overstate the depth under a tilted face.
    fk = -1
    fm = 0.7
    for a in range(4):
        s = 0.0
        for b in range(4):
            s += trot[b, a] * m[b]
        lim[a] = th[a] + margin * abs(s) + 1e-6
        if abs(s) > fm:
            fm = abs(s)
            fk = a
            fs = s
    if fk >= 0:
        fm = fs
        fh = th[fk] if fs > 0.0 else -th[fk]
    else:
        fh = 0.0
    # O's vertices: vertex j has +oh[k] along its axis k where bit k of j is
    # set. The sums are built axis by axis in that fixed order, sharing the
    # partial sums of vertices that agree on the first axes (30 additions per
    # coordinate instead of 64, the same rounding as summing each alone).
    for a in range(4):
        c = loc_c[a]
        p = oh[0] * loc_axes[a, 0]
        v[0, a] = c - p
        v[1, a] = c + p
        for kk in range(1, 4):
            p = oh[kk] * loc_axes[a, kk]
            half = 1 << kk
            for j in range(half):
                v[j + half, a] = v[j, a] + p
                v[j, a] = v[j, a] - p
    # Where each vertex lies against T's slab along each axis: bit 16 a + j of
    # ``above`` (``below``) is set when vertex j is beyond +lim[a] (-lim[a]).
    above = 0
    below = 0
    for j in range(16):
        for a in range(4):
            # Without a branch: which side of a face a vertex lies is a coin
            # toss to the processor, and the mispredictions cost as much as
            # the rest of the clipping.
            above |= np.int64(v[j, a] > lim[a]) << (16 * a + j)
            below |= np.int64(v[j, a] < -lim[a]) << (16 * a + j)
    outside = above | below
    for j in range(16):
        if (outside >> j) & _AXIS_BITS == 0:
            cnt = _emit(tx, trot, v[j], m, sup, margin, cp, cd, cnt, fk, fm, fh)
    for j in range(16):
        in_j = (outside >> j) & _AXIS_BITS == 0
        for kk in range(4):
            if (j >> kk) & 1:
                continue
            j2 = j | (1 << kk)
            if in_j and (outside >> j2) & _AXIS_BITS == 0:
                continue
            # Most edges miss T entirely: both ends beyond the same face.
            if (above >> j) & (above >> j2) & _AXIS_BITS or (below >> j) & (below >> j2) & _AXIS_BITS:
                continue
            ok = True
            t0 = 0.0
            t1 = 1.0
            for a in range(4):
                p0 = v[j, a]
                dp = v[j2, a] - p0
                if abs(dp) < 1e-14:
                    continue
                inv = 1.0 / dp
                ta = (-lim[a] - p0) * inv
                tb = (lim[a] - p0) * inv
                if ta > tb:
                    ta, tb = tb, ta
                if ta > t0:
                    t0 = ta
                if tb < t1:
                    t1 = tb
                if t0 > t1:
                    ok = False
                    break
            if not ok:
                continue
            if t0 > 0.0:
                for a in range(4):
                    pl[a] = v[j, a] + t0 * (v[j2, a] - v[j, a])
                cnt = _emit(tx, trot, pl, m, sup, margin, cp, cd, cnt, fk, fm, fh)
            if t1 < 1.0:
                for a in range(4):
                    pl[a] = v[j, a] + t1 * (v[j2, a] - v[j, a])
                cnt = _emit(tx, trot, pl, m, sup, margin, cp, cd, cnt, fk, fm, fh)
    return cnt


@njit(cache=True)
def _emit(tx, trot, pl, m, sup, margin, cp, cd, cnt, fk, fm, fh):
    """Store a candidate given in T's frame if it is within ``margin`` of touching.

    Its depth is the distance along ``m`` to T's face ``fk`` (``x_fk = fh``,
    ``fm = m . axis_fk``), or to T's support plane ``sup`` when ``fk < 0``.
    """
    if cnt >= cp.shape[0]:
        return cnt
    dot = 0.0
    for a in range(4):
        s = tx[a]
        for b in range(4):
            s += trot[a, b] * pl[b]
        cp[cnt, a] = s
        dot += m[a] * s
    if fk >= 0:
        depth = (fh - pl[fk]) / fm
    else:
        depth = sup - dot
    if depth < -margin:
        return cnt
    for a in range(4):
        cp[cnt, a] += 0.5 * depth * m[a]
    cd[cnt] = depth
    return cnt + 1


@njit(inline="always")
def _edge_axis(c, swap, pq, kk):
    """The unit axis (``u``, ``w`` in the face box's ``(p, q)`` plane) of 2-face ``pq`` against edge ``kk``,
    or ``(0, 0)`` when the two are parallel (no axis)."""
    p = PLANE_I[pq]
    q = PLANE_J[pq]
    if swap:
        u = c[kk, q]
        w = -c[kk, p]
    else:
        u = c[q, kk]
        w = -c[p, kk]
    ln2 = u * u + w * w
    if ln2 < 1e-6:
        return 0.0, 0.0
    inv = 1.0 / np.sqrt(ln2)
    return u * inv, w * inv


@njit(inline="always")
def _edge_gap(c, swap, h_face, h_edge, d_face, pq, u, w):
    """Overlap of the two boxes along the axis ``u, w`` of :func:`_edge_axis` (negative: apart)."""
    p = PLANE_I[pq]
    q = PLANE_J[pq]
    rr = h_face[p] * abs(u) + h_face[q] * abs(w)
    for m in range(4):
        if swap:
            rr += h_edge[m] * abs(u * c[m, p] + w * c[m, q])
        else:
            rr += h_edge[m] * abs(u * c[p, m] + w * c[q, m])
    return rr - abs(u * d_face[p] + w * d_face[q])


@njit(inline="always")
def _face_gap(i, ha, hb, c, da, db):
    """Overlap along cell normal ``i`` (0-3: A's axes, 4-7: B's), negative when apart."""
    if i < 4:
        rr = 0.0
        for kk in range(4):
            rr += hb[kk] * abs(c[i, kk])
        return ha[i] + rr - abs(da[i])
    kk = i - 4
    rr = 0.0
    for j in range(4):
        rr += ha[j] * abs(c[j, kk])
    return hb[kk] + rr - abs(db[kk])


@njit(cache=True)
def _face_edge_axes(c, swap, h_face, h_edge, d_face, r_face, margin, best, normal):
    """Separating axes of the 2-faces of one box against the edges of the other.

    The 2-face of the face box spanning the axes other than ``p, q`` and the
    edge of the other box along its axis ``k`` have one axis orthogonal to both;
    it lies in the face box's ``(p, q)`` plane. Axis ``4 pq + k`` is the one of
    plane ``pq`` (in :data:`PLANE_I`, :data:`PLANE_J` order) and edge ``k``.

    Parameters
    ----------
    c : (4, 4) float64
        ``c[i, j] = A_i . B_j``, the axes of box A against those of box B.
    swap : bool
        False when the face box is A, True when it is B (``c`` is then read
        transposed).
    h_face, h_edge : (4,) float64
        Half extents of the face box and the edge box.
    d_face : (4,) float64
        Centre offset (edge box minus face box, or the reverse when swapped)
        in the face box's frame.
    r_face : (4, 4) float64
        Face box rotation (columns are its axes).
    margin : float
    best : float
        Smallest overlap found so far on such axes.
    normal : (4,) float64
        Overwritten with the axis of a new smallest overlap, pointing along ``d_face``.

    Returns
    -------
    separating : int
        The first axis that separates the boxes by more than ``margin``, or -1.
    best : float
    """
    for pq in range(6):
        p = PLANE_I[pq]
        q = PLANE_J[pq]
        for kk in range(4):
            u, w = _edge_axis(c, swap, pq, kk)
            if u == 0.0 and w == 0.0:
                continue
            o = _edge_gap(c, swap, h_face, h_edge, d_face, pq, u, w)
            if o < -margin:
                return 4 * pq + kk, best
            if o < best:
                best = o
                dist = u * d_face[p] + w * d_face[q]
                sg = 1.0 if dist >= 0.0 else -1.0
                for m in range(4):
                    normal[m] = sg * (r_face[m, p] * u + r_face[m, q] * w)
    return -1, best


@njit(cache=True)
def _relate(xa, ra, xb, rb, wk):
    """``c = R_a^T R_b`` into ``wk[0:4]``, the centre offset in A's and B's frames into ``wk[4]``, ``wk[5]``."""
    c = wk[0:4]
    for i in range(4):
        for j in range(4):
            s = 0.0
            for m in range(4):
                s += ra[m, i] * rb[m, j]
            c[i, j] = s
    da = wk[4]
    db = wk[5]
    for i in range(4):
        s = 0.0
        t = 0.0
        for m in range(4):
            dm = xb[m] - xa[m]
            s += ra[m, i] * dm
            t += rb[m, i] * dm
        da[i] = s
        db[i] = t


@njit(cache=True)
def separated_along(axis, xa, ra, ha, xb, rb, hb, margin, wk):
    """Whether candidate axis ``axis`` of :func:`box_box` separates the boxes by more than ``margin``.

    The same arithmetic as :func:`box_box`, so True means it would find no
    contact either (a pair's separating axis from one tick is usually still one
    the next, and this one test is far cheaper than all 56).
    """
    _relate(xa, ra, xb, rb, wk)
    c = wk[0:4]
    da = wk[4]
    db = wk[5]
    if axis < 8:
        return _face_gap(axis, ha, hb, c, da, db) < -margin
    swap = axis >= 32
    e = axis - (32 if swap else 8)
    pq = e >> 2
    u, w = _edge_axis(c, swap, pq, e & 3)
    if u == 0.0 and w == 0.0:
        return False
    if swap:
        return _edge_gap(c, True, hb, ha, db, pq, u, w) < -margin
    return _edge_gap(c, False, ha, hb, da, pq, u, w) < -margin


@njit(cache=True)
def box_box(xa, ra, ha, xb, rb, hb, margin, cp, cd, wk, out_p, out_n, out_d, k):
    """Contact manifold of two 4D boxes (normal from a to b).

    Parameters
    ----------
    xa, xb : (4,) float64
        Centres.
    ra, rb : (4, 4) float64
        Rotations (columns are the box axes in world coordinates).
    ha, hb : (4,) float64
        Half extents.
    margin : float
        Speculative distance: pairs closer than this still get contacts.
    cp, cd : (SCRATCH_POINTS, 4), (SCRATCH_POINTS,) float64
        Scratch for candidate points.
    wk : (SCRATCH_ROWS, 4) float64
        Scratch.
    out_p, out_n : (C, 4) float64
    out_d : (C,) float64
    k : int
        First output row.

    Returns
    -------
    int
        Number of contacts written (0 when apart by no more than ``margin``
        but not touching), or ``-1 - axis`` when candidate axis ``axis``
        separates the boxes by more than ``margin``: 0-3 A's cell normals, 4-7
        B's, 8-31 A's 2-faces against B's edges, 32-55 the reverse (see
        :func:`separated_along`).
    """
    _relate(xa, ra, xb, rb, wk)
    c = wk[0:4]
    da = wk[4]
    db = wk[5]
    n = wk[6]
    best_face = np.inf
    for i in range(8):
        o = _face_gap(i, ha, hb, c, da, db)
        if o < -margin:
            return -1 - i
        if o < best_face:
            best_face = o
            if i < 4:
                sg = 1.0 if da[i] >= 0.0 else -1.0
                for m in range(4):
                    n[m] = sg * ra[m, i]
            else:
                sg = 1.0 if db[i - 4] >= 0.0 else -1.0
                for m in range(4):
                    n[m] = sg * rb[m, i - 4]
    ncross = wk[7]
    # 2-faces of A (spanning the axes other than p, q) against edges of B, then
    # the same with the boxes' roles swapped (c read transposed).
    hit, best_cross = _face_edge_axes(c, False, ha, hb, da, ra, margin, np.inf, ncross)
    if hit >= 0:
        return -9 - hit
    hit, best_cross = _face_edge_axes(c, True, hb, ha, db, rb, margin, best_cross, ncross)
    if hit >= 0:
        return -33 - hit
    # Prefer face normals unless an edge axis is clearly shallower: face normals
    # are stable from step to step, which keeps warm starting effective.
    if best_cross + 0.002 + 0.05 * abs(best_face) < best_face:
        for m in range(4):
            n[m] = ncross[m]
    # Supports of A along n and of B along -n.
    sup_a = 0.0
    sup_b = 0.0
    for m in range(4):
        sup_a += n[m] * xa[m]
        sup_b -= n[m] * xb[m]
    for i in range(4):
        sa = 0.0
        sb = 0.0
        for m in range(4):
            sa += n[m] * ra[m, i]
            sb += n[m] * rb[m, i]
        sup_a += ha[i] * abs(sa)
        sup_b += hb[i] * abs(sb)
    cnt = 0
    # B's points inside A, depth along n.
    loc_axes = wk[8:12]
    negn = wk[12]
    for m in range(4):
        negn[m] = -n[m]
    v = wk[16:32]
    pl = wk[13]
    cnt = _clip_into(xa, ra, ha, da, c, hb, margin, n, sup_a, cp, cd, cnt, v, pl, wk[14])
    # A's points inside B, depth along -n.
    for i in range(4):
        for j in range(4):
            loc_axes[i, j] = c[j, i]
    for m in range(4):
        db[m] = -db[m]
    cnt = _clip_into(xb, rb, hb, db, loc_axes, ha, margin, negn, sup_b, cp, cd, cnt, v, pl, wk[14])
    if cnt == 0:
        # Overlapping, yet no vertex or edge of either box is inside the other:
        # the region's corners are where 2-faces of the two boxes cross, which
        # only happens for deep overlaps (shallow contacts always have a box
        # edge through the other). One point between the centres, at the SAT
        # depth, pushes them apart along the separating axis.
        best = min(best_face, best_cross)
        if best < 0.0:
            return 0
        for m in range(4):
            out_p[k, m] = 0.5 * (xa[m] + xb[m])
            out_n[k, m] = n[m]
        out_d[k] = best_face if best_cross + 0.002 + 0.05 * abs(best_face) >= best_face else best_cross
        return 1
    # The region follows the faces of whichever box faces the normal squarely.
    fa = 0.0
    fb = 0.0
    for i in range(4):
        sa = 0.0
        sb = 0.0
        for m in range(4):
            sa += n[m] * ra[m, i]
            sb += n[m] * rb[m, i]
        fa = max(fa, abs(sa))
        fb = max(fb, abs(sb))
    return reduce_points(cp, cd, cnt, n, ra if fa >= fb else rb, wk[32:], out_p, out_n, out_d, k)


@njit(cache=True)
def sphere_halfspace(c, r, pn, off, margin, out_p, out_n, out_d, k):
    """Hypersphere against the solid ``{x : pn . x <= off}`` (normal into the solid)."""
    dist = -off
    for a in range(4):
        dist += pn[a] * c[a]
    dist -= r
    if dist > margin:
        return 0
    depth = -dist
    for a in range(4):
        out_n[k, a] = -pn[a]
        out_p[k, a] = c[a] - pn[a] * (r - 0.5 * depth)
    out_d[k] = depth
    return 1


@njit(cache=True)
def box_halfspace(x, rot, h, pn, off, margin, cp, cd, wk, out_p, out_n, out_d, k):
    """Box against the solid ``{x : pn . x <= off}``: its vertices near or below the plane."""
    cnt = 0
    v = wk[0]
    negn = wk[1]
    for j in range(16):
        dist = -off
        for a in range(4):
            s = x[a]
            for kk in range(4):
                if (j >> kk) & 1:
                    s += h[kk] * rot[a, kk]
                else:
                    s -= h[kk] * rot[a, kk]
            v[a] = s
            dist += pn[a] * s
        if dist > margin:
            continue
        depth = -dist
        for a in range(4):
            cp[cnt, a] = v[a] + 0.5 * depth * pn[a]
        cd[cnt] = depth
        cnt += 1
    for a in range(4):
        negn[a] = -pn[a]
    return reduce_points(cp, cd, cnt, negn, rot, wk[32:], out_p, out_n, out_d, k)
