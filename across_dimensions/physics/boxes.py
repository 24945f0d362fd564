"""Two 4D boxes: the separating-axis test over their 56 candidate axes, and the clipping that
gives the corners of their overlap region (see :mod:`.collide` for the method).

The candidate axes are the 4 + 4 cell (3-face) normals and, for every 2-face of
one box and edge of the other, the direction orthogonal to both. The contact
points are the vertices of each box inside the other plus the points where
each box's edges leave the other box, thinned by :func:`.collide.reduce_points`.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import PLANE_I, PLANE_J
from .collide import reduce_points

#: Bit 16 a of a vertex mask word for each axis a (see :func:`_clip_into`).
_AXIS_BITS = 1 | (1 << 16) | (1 << 32) | (1 << 48)


@njit(inline="always")
def _face_of(trot, th, m, margin, lim):
    """T's slab limits ``lim`` (expanded by the margin only along ``m``) and the face of T that
    ``m`` leaves through, when there is one: ``(fk, fm, fh)``, axis, ``m . axis`` and the face's
    coordinate; ``fk`` is -1 when ``m`` leaves through no face squarely."""
    # A vertex that overhangs T's face sideways is not supported by it. Depth is
    # measured to the face of T that m leaves through, when there is one (T's
    # face plane, tilted or not); the support plane of T along m would
    # overstate the depth under a tilted face.
    fk = -1
    fm = 0.7
    fs = 0.0
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
        return fk, fs, th[fk] if fs > 0.0 else -th[fk]
    return fk, fm, 0.0


@njit(inline="always")
def _vertices(loc_c, loc_axes, oh, v):
    """O's 16 vertices in T's frame into ``v``.

    Vertex j has +oh[k] along its axis k where bit k of j is set. The sums are
    built axis by axis in that fixed order, sharing the partial sums of vertices
    that agree on the first axes (30 additions per coordinate instead of 64, the
    same rounding as summing each alone).
    """
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


@njit(inline="always")
def _edge_span(v, j, j2, lim):
    """The part ``[t0, t1]`` of the edge from vertex ``j`` to ``j2`` inside T's slabs: ``(ok, t0, t1)``."""
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
            return False, t0, t1
    return True, t0, t1


@njit(cache=True)
def _clip_into(t, o, margin, m, sup, cand, cnt, work):
    """Add the points of box O that lie inside box T (expanded by ``margin`` along ``m``).

    Points are O's vertices inside T and the points where O's edges cross T's
    boundary. Their depth is measured along ``m`` (the normal pointing out of T
    towards O): ``sup - m . p`` with ``sup`` the support of T along ``m``.
    Points are stored half-way between the two surfaces.

    Parameters
    ----------
    t : Box
        T.
    o : tuple
        O in T's frame: its centre ``(4,)``, its axes ``(4, 4)`` (column k is
        axis k) and its half extents ``(4,)``.
    m : (4,) float64
        Unit normal (world).
    sup : float
    cand : tuple
        Candidate output: points ``(M, 4)`` and depths ``(M,)``; ``cnt`` rows used.
    work : tuple
        Scratch: O's vertices ``(16, 4)``, a point and the slab limits ``(4,)``.

    Returns
    -------
    int
        New row count.
    """
    v, pl, lim = work
    face = _face_of(t.rotation, t.half, m, margin, lim)
    _vertices(o[0], o[1], o[2], v)
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
            cnt = _emit(t, v[j], m, sup, margin, cand, cnt, face)
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
            ok, t0, t1 = _edge_span(v, j, j2, lim)
            if not ok:
                continue
            if t0 > 0.0:
                for a in range(4):
                    pl[a] = v[j, a] + t0 * (v[j2, a] - v[j, a])
                cnt = _emit(t, pl, m, sup, margin, cand, cnt, face)
            if t1 < 1.0:
                for a in range(4):
                    pl[a] = v[j, a] + t1 * (v[j2, a] - v[j, a])
                cnt = _emit(t, pl, m, sup, margin, cand, cnt, face)
    return cnt


@njit(cache=True)
def _emit(t, pl, m, sup, margin, cand, cnt, face):
    """Store a candidate given in T's frame if it is within ``margin`` of touching.

    Its depth is the distance along ``m`` to T's face ``fk`` (``x_fk = fh``,
    ``fm = m . axis_fk``; ``face`` is ``(fk, fm, fh)``), or to T's support plane
    ``sup`` when ``fk < 0``.
    """
    cp, cd = cand
    fk, fm, fh = face
    tx = t.center
    trot = t.rotation
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
def _face_edge_axes(c, swap, face, h_edge, margin, best, normal):
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
    face : tuple
        The face box's half extents ``(4,)``, its rotation ``(4, 4)`` (columns
        are its axes) and the centre offset ``(4,)`` (edge box minus face box,
        or the reverse when swapped) in its frame.
    h_edge : (4,) float64
        Half extents of the edge box.
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
    h_face, r_face, d_face = face
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
def separated_along(axis, a, b, margin, wk):
    """Whether candidate axis ``axis`` of :func:`box_box` separates boxes ``a`` and ``b``
    (:class:`~.collide.Box`) by more than ``margin``.

    The same arithmetic as :func:`box_box`, so True means it would find no
    contact either (a pair's separating axis from one tick is usually still one
    the next, and this one test is far cheaper than all 56).
    """
    ha = a.half
    hb = b.half
    _relate(a.center, a.rotation, b.center, b.rotation, wk)
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


@njit(inline="always")
def _best_axis(a, b, margin, wk):
    """The separating-axis test: ``(hit, best_face, best_cross)``, ``hit`` the first candidate
    axis that separates the boxes by more than ``margin`` (-1 if none), the smallest overlaps on
    cell normals and on face-edge axes, and the contact normal (from a to b) in ``wk[6]``.

    Face normals are preferred unless an edge axis is clearly shallower: they
    are stable from step to step, which keeps warm starting effective.
    """
    ha = a.half
    hb = b.half
    c = wk[0:4]
    da = wk[4]
    db = wk[5]
    n = wk[6]
    best_face = np.inf
    for i in range(8):
        o = _face_gap(i, ha, hb, c, da, db)
        if o < -margin:
            return i, best_face, np.inf
        if o < best_face:
            best_face = o
            if i < 4:
                sg = 1.0 if da[i] >= 0.0 else -1.0
                for m in range(4):
                    n[m] = sg * a.rotation[m, i]
            else:
                sg = 1.0 if db[i - 4] >= 0.0 else -1.0
                for m in range(4):
                    n[m] = sg * b.rotation[m, i - 4]
    ncross = wk[7]
    # 2-faces of A (spanning the axes other than p, q) against edges of B, then
    # the same with the boxes' roles swapped (c read transposed).
    hit, best_cross = _face_edge_axes(c, False, (ha, a.rotation, da), hb, margin, np.inf, ncross)
    if hit >= 0:
        return 8 + hit, best_face, best_cross
    hit, best_cross = _face_edge_axes(c, True, (hb, b.rotation, db), ha, margin, best_cross, ncross)
    if hit >= 0:
        return 32 + hit, best_face, best_cross
    if best_cross + 0.002 + 0.05 * abs(best_face) < best_face:
        for m in range(4):
            n[m] = ncross[m]
    return -1, best_face, best_cross


@njit(inline="always")
def _support(n, box, sign):
    """Support of ``box`` along ``sign * n``."""
    s = 0.0
    for m in range(4):
        s += sign * n[m] * box.center[m]
    for i in range(4):
        t = 0.0
        for m in range(4):
            t += n[m] * box.rotation[m, i]
        s += box.half[i] * abs(t)
    return s


@njit(inline="always")
def _squarest(n, a, b):
    """The rotation of whichever box faces the normal ``n`` squarely (a on ties)."""
    fa = 0.0
    fb = 0.0
    for i in range(4):
        sa = 0.0
        sb = 0.0
        for m in range(4):
            sa += n[m] * a.rotation[m, i]
            sb += n[m] * b.rotation[m, i]
        fa = max(fa, abs(sa))
        fb = max(fb, abs(sb))
    return a.rotation if fa >= fb else b.rotation


@njit(cache=True)
def box_box(a, b, margin, cand, wk, out, k):
    """Contact manifold of two 4D boxes (normal from a to b).

    Parameters
    ----------
    a, b : Box
    margin : float
        Speculative distance: pairs closer than this still get contacts.
    cand : tuple
        Scratch for candidate points: ``(SCRATCH_POINTS, 4)`` and ``(SCRATCH_POINTS,)`` float64.
    wk : (SCRATCH_ROWS, 4) float64
        Scratch.
    out : Points
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
    xa, ra, ha = a
    xb, rb, hb = b
    _relate(xa, ra, xb, rb, wk)
    hit, best_face, best_cross = _best_axis(a, b, margin, wk)
    if hit >= 0:
        return -1 - hit
    c = wk[0:4]
    db = wk[5]
    n = wk[6]
    # Supports of A along n and of B along -n.
    sup_a = _support(n, a, 1.0)
    sup_b = _support(n, b, -1.0)
    # B's points inside A, depth along n.
    loc_axes = wk[8:12]
    negn = wk[12]
    for m in range(4):
        negn[m] = -n[m]
    work = (wk[16:32], wk[13], wk[14])
    cnt = _clip_into(a, (wk[4], c, hb), margin, n, sup_a, cand, 0, work)
    # A's points inside B, depth along -n.
    for i in range(4):
        for j in range(4):
            loc_axes[i, j] = c[j, i]
    for m in range(4):
        db[m] = -db[m]
    cnt = _clip_into(b, (db, loc_axes, ha), margin, negn, sup_b, cand, cnt, work)
    if cnt == 0:
        # Overlapping, yet no vertex or edge of either box is inside the other:
        # the region's corners are where 2-faces of the two boxes cross, which
        # only happens for deep overlaps (shallow contacts always have a box
        # edge through the other). One point between the centres, at the SAT
        # depth, pushes them apart along the separating axis.
        if min(best_face, best_cross) < 0.0:
            return 0
        out_p, out_n, out_d = out
        for m in range(4):
            out_p[k, m] = 0.5 * (xa[m] + xb[m])
            out_n[k, m] = n[m]
        out_d[k] = best_face if best_cross + 0.002 + 0.05 * abs(best_face) >= best_face else best_cross
        return 1
    # The region follows the faces of whichever box faces the normal squarely.
    return reduce_points(cand, cnt, n, _squarest(n, a, b), wk[32:], out, k)
