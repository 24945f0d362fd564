"""Rigid bodies against the boundary of a non-convex 4D solid: its outward tets (a "tet mesh").

A solid 4D object that is neither a box nor convex (an arch, a lifted asset) is
met by the bodies as the tets of its boundary, in world space. Each tet is a
3-simplex lying in a hyperplane of R^4; the mesh is closed and every tet is
oriented so that ``core.mesh.cross4`` of its edges points out of the solid
(CONVENTIONS.md), which is what tells a body on top of a face from a body
inside the solid under it.

Contacts (normal from the body to the mesh, depth positive when overlapping,
negative down to ``-margin`` for speculative contacts), as the other static
shapes of :mod:`.collide`:

* **hypersphere**: the closest point of each nearby tet. With the centre in
  front of the tet's hyperplane the normal runs from the centre to that
  point; with the centre behind it (already inside, at most
  :data:`MAX_DEPTH` deep) only a tet whose face region holds the centre counts,
  and the normal is the tet's inward normal;
* **box**, vertex-face both ways, as mesh colliders of 3D engines do:
  (1) box corners near or below a tet's hyperplane whose projection falls inside
  the tet (depth: the distance below; normal: the tet's inward normal);
  (2) tet vertices and (3) the points where tet edges cross the box (the box
  grown by the margin along the tet's normal only) with depth the distance the
  box must move along the tet's outward normal to leave that point. A box on a
  bar narrower than itself is thus held by the bar's edges, a box on a pillar's
  top by its corners.

Depths are taken only within :data:`MAX_DEPTH` (plus the body's speculative
margin) behind a face: a corner in an arch's doorway is below the plane of
the lintel's top, and must not be pushed up through the lintel; a body that
got deeper into a thin wall than that is not pushed out through its far side.

Candidates that repeat (a point on an edge shared by several tets) are merged,
and at most :data:`~.collide.MAX_POINTS` are kept by farthest-point sampling
from the deepest, so a resting box keeps the outline of its support.

Each mesh's tets are sorted by their low bound along the mesh's longest axis, and
each tet carries its bounds: a body finds the run of tets that can reach it by a
binary search, and tests only those whose bounds meet its own (grown by its margin).
Built by :func:`tet_geometry` from world tets ``(T, 4, 4)``; see :meth:`~.world.PhysicsWorld.set_static_tets`.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .collide import MAX_POINTS, most_aligned_axis, written_before

#: Metres behind a tet's face that a body may be and still be pushed out through that
#: face. Bodies never get that deep at rest (the speculative margin stops them first), so
#: this only decides what happens after a deep overlap; it must stay under half the
#: thinnest wall or lintel of a level's objects (0.2 m and more), else a corner in an
#: arch's doorway would be pushed up through the lintel above it.
MAX_DEPTH = 0.1
#: Candidate contact rows the scratch holds per pair before thinning (a box on a
#: fine mesh touches a few dozen tets; beyond this the shallowest are replaced).
CANDIDATES = 256
#: Barycentric slack when asking whether a projected point lies in a tet: points on a
#: shared edge belong to both tets (the duplicate is merged), none falls between.
_BARY_TOL = 1e-9
#: Candidates closer than this (metres) with normals closer than _SAME_NORMAL are one.
_SAME_POINT = 1e-7
_SAME_NORMAL = 1.0 - 1e-9
#: Sphere candidates whose normals agree to this are one contact (the deepest): a ball
#: on a face made of several coplanar tets touches it once.
_SPHERE_SAME_NORMAL = 1.0 - 1e-6
#: Cosine of the largest angle between a tet's normal and the box face a point of the
#: tet leaves the box through, for that point to be a contact of the tet (45 degrees).
_FACE_ALIGN = 0.7071
#: Tets whose normal (the cross product of three edges) is shorter than this, relative
#: to the cube of their longest edge, are slivers with no reliable hyperplane; skipped.
_DEGENERATE = 1e-12


def tet_geometry(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Hyperplanes, barycentric maps and bounds of world tets (degenerate ones dropped).

    Parameters
    ----------
    tets : (T, 4, 4) float64
        Corners of each boundary tet, oriented outward (``cross4`` of edges 1-0,
        2-0, 3-0 points out of the solid).

    Returns
    -------
    tets : (T', 4, 4) float64
        The tets kept.
    planes : (T', 5) float64
        ``(n, offset)``: unit outward normal, ``n . x = offset`` on the tet.
    bary : (T', 3, 4) float64
        ``lambda_1..3 = bary @ (p - corner_0)`` for a point ``p`` in the tet's
        hyperplane (``lambda_0 = 1 - sum``).
    bounds : (T', 8) float64
        ``(lo (4), hi (4))`` of each tet.
    """
    t = np.ascontiguousarray(np.asarray(tets, dtype=np.float64).reshape(-1, 4, 4))
    planes = np.empty((len(t), 5))
    bary = np.empty((len(t), 3, 4))
    bounds = np.empty((len(t), 8))
    keep = np.empty(len(t), dtype=np.bool_)
    _geometry(t, planes, bary, bounds, keep)
    if keep.all():
        return t, planes, bary, bounds
    return t[keep], planes[keep], bary[keep], bounds[keep]


@njit(cache=True)
def _geometry(t, planes, bary, bounds, keep):
    """:func:`tet_geometry` in place, for every tet (``keep`` False for slivers)."""
    e = np.empty((3, 4))
    g = np.empty((3, 3))
    for i in range(t.shape[0]):
        size2 = 0.0
        for r in range(3):
            s = 0.0
            for m in range(4):
                e[r, m] = t[i, r + 1, m] - t[i, 0, m]
                s += e[r, m] * e[r, m]
            size2 = max(size2, s)
        # cross4 (core.mesh): cofactors of det[e0, e1, e2, x] along the last row.
        ln2 = 0.0
        for c in range(4):
            a0 = 0 if c > 0 else 1
            a1 = 1 if c > 1 else 2
            a2 = 2 if c > 2 else 3
            d = (
                e[0, a0] * (e[1, a1] * e[2, a2] - e[1, a2] * e[2, a1])
                - e[0, a1] * (e[1, a0] * e[2, a2] - e[1, a2] * e[2, a0])
                + e[0, a2] * (e[1, a0] * e[2, a1] - e[1, a1] * e[2, a0])
            )
            planes[i, c] = -d if c % 2 == 0 else d
            ln2 += d * d
        ln = np.sqrt(ln2)
        keep[i] = ln > _DEGENERATE * size2 * np.sqrt(size2)
        for m in range(4):
            bounds[i, m] = min(t[i, 0, m], t[i, 1, m], t[i, 2, m], t[i, 3, m])
            bounds[i, 4 + m] = max(t[i, 0, m], t[i, 1, m], t[i, 2, m], t[i, 3, m])
        if not keep[i]:
            continue
        off = 0.0
        for m in range(4):
            planes[i, m] /= ln
            off += planes[i, m] * t[i, 0, m]
        planes[i, 4] = off
        # bary = Gram^-1 E (Gram = E E^T, symmetric 3x3, inverted by its cofactors).
        for r in range(3):
            for q in range(3):
                s = 0.0
                for m in range(4):
                    s += e[r, m] * e[q, m]
                g[r, q] = s
        c00 = g[1, 1] * g[2, 2] - g[1, 2] * g[2, 1]
        c01 = g[1, 2] * g[2, 0] - g[1, 0] * g[2, 2]
        c02 = g[1, 0] * g[2, 1] - g[1, 1] * g[2, 0]
        det = g[0, 0] * c00 + g[0, 1] * c01 + g[0, 2] * c02
        inv00 = c00 / det
        inv01 = (g[0, 2] * g[2, 1] - g[0, 1] * g[2, 2]) / det
        inv02 = (g[0, 1] * g[1, 2] - g[0, 2] * g[1, 1]) / det
        inv11 = (g[0, 0] * g[2, 2] - g[0, 2] * g[2, 0]) / det
        inv12 = (g[0, 2] * g[1, 0] - g[0, 0] * g[1, 2]) / det
        inv22 = (g[0, 0] * g[1, 1] - g[0, 1] * g[1, 0]) / det
        inv10 = c01 / det
        inv20 = c02 / det
        inv21 = (g[0, 1] * g[2, 0] - g[0, 0] * g[2, 1]) / det
        for m in range(4):
            bary[i, 0, m] = inv00 * e[0, m] + inv01 * e[1, m] + inv02 * e[2, m]
            bary[i, 1, m] = inv10 * e[0, m] + inv11 * e[1, m] + inv12 * e[2, m]
            bary[i, 2, m] = inv20 * e[0, m] + inv21 * e[1, m] + inv22 * e[2, m]


@njit(cache=True)
def _project_inside(tets, bary, t, q):
    """Whether ``q`` (in tet ``t``'s hyperplane) lies in the tet."""
    s = 0.0
    for a in range(3):
        lam = 0.0
        for m in range(4):
            lam += bary[t, a, m] * (q[m] - tets[t, 0, m])
        if lam < -_BARY_TOL:
            return False
        s += lam
    return s <= 1.0 + _BARY_TOL


@njit(cache=True)
def _closest_on_triangle(p, a, b, c, out):
    """Closest point of triangle ``abc`` to ``p`` in R^4 (Ericson's regions, dot products only)."""
    ab = np.empty(4)
    ac = np.empty(4)
    ap = np.empty(4)
    for m in range(4):
        ab[m] = b[m] - a[m]
        ac[m] = c[m] - a[m]
        ap[m] = p[m] - a[m]
    d1 = 0.0
    d2 = 0.0
    for m in range(4):
        d1 += ab[m] * ap[m]
        d2 += ac[m] * ap[m]
    if d1 <= 0.0 and d2 <= 0.0:
        out[:] = a
        return
    d3 = 0.0
    d4 = 0.0
    for m in range(4):
        bp = p[m] - b[m]
        d3 += ab[m] * bp
        d4 += ac[m] * bp
    if d3 >= 0.0 and d4 <= d3:
        out[:] = b
        return
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        v = d1 / (d1 - d3)
        for m in range(4):
            out[m] = a[m] + v * ab[m]
        return
    d5 = 0.0
    d6 = 0.0
    for m in range(4):
        cp = p[m] - c[m]
        d5 += ab[m] * cp
        d6 += ac[m] * cp
    if d6 >= 0.0 and d5 <= d6:
        out[:] = c
        return
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        w = d2 / (d2 - d6)
        for m in range(4):
            out[m] = a[m] + w * ac[m]
        return
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        for m in range(4):
            out[m] = b[m] + w * (c[m] - b[m])
        return
    den = 1.0 / (va + vb + vc)
    v = vb * den
    w = vc * den
    for m in range(4):
        out[m] = a[m] + ab[m] * v + ac[m] * w


@njit(cache=True)
def _closest_on_boundary(p, tets, t, out, tmp):
    """Closest point to ``p`` on the four triangles of tet ``t``; returns its squared distance."""
    best = np.inf
    for f in range(4):
        i0 = (f + 1) % 4
        i1 = (f + 2) % 4
        i2 = (f + 3) % 4
        _closest_on_triangle(p, tets[t, i0], tets[t, i1], tets[t, i2], tmp)
        d2 = 0.0
        for m in range(4):
            e = tmp[m] - p[m]
            d2 += e * e
        if d2 < best:
            best = d2
            out[:] = tmp
    return best


@njit(cache=True)
def _add(cp, cn, cd, cnt, p, n, depth, same_normal, same_point2):
    """Add a candidate unless one with the same normal (and point) is there; keep the deeper.

    ``same_point2 < 0`` merges on the normal alone. When the buffer is full the
    shallowest candidate gives way to a deeper one. Returns the new count.
    """
    for c in range(cnt):
        dn = 0.0
        for m in range(4):
            dn += cn[c, m] * n[m]
        if dn < same_normal:
            continue
        if same_point2 >= 0.0:
            d2 = 0.0
            for m in range(4):
                e = cp[c, m] - p[m]
                d2 += e * e
            if d2 > same_point2:
                continue
        if depth > cd[c]:
            for m in range(4):
                cp[c, m] = p[m]
                cn[c, m] = n[m]
            cd[c] = depth
        return cnt
    k = cnt
    if cnt >= cp.shape[0]:
        k = 0
        for c in range(1, cnt):
            if cd[c] < cd[k]:
                k = c
        if cd[k] >= depth:
            return cnt
    for m in range(4):
        cp[k, m] = p[m]
        cn[k, m] = n[m]
    cd[k] = depth
    return cnt if cnt >= cp.shape[0] else cnt + 1


@njit(cache=True)
def _emit_thinned(cp, cn, cd, cnt, out_p, out_n, out_d, k):
    """Write at most MAX_POINTS candidates: the deepest, then each time the one farthest from
    those kept (first in order on ties). Returns how many were written."""
    if cnt <= MAX_POINTS:
        for c in range(cnt):
            for m in range(4):
                out_p[k + c, m] = cp[c, m]
                out_n[k + c, m] = cn[c, m]
            out_d[k + c] = cd[c]
        return cnt
    far = np.full(cnt, np.inf)
    pick = 0
    for c in range(1, cnt):
        if cd[c] > cd[pick]:
            pick = c
    for j in range(MAX_POINTS):
        for m in range(4):
            out_p[k + j, m] = cp[pick, m]
            out_n[k + j, m] = cn[pick, m]
        out_d[k + j] = cd[pick]
        far[pick] = -1.0
        nxt = -1
        best = -1.0
        for c in range(cnt):
            if far[c] < 0.0:
                continue
            d2 = 0.0
            for m in range(4):
                e = cp[c, m] - cp[pick, m]
                d2 += e * e
            if d2 < far[c]:
                far[c] = d2
            if far[c] > best:
                best = far[c]
                nxt = c
        if nxt < 0:
            return j + 1
        pick = nxt
    return MAX_POINTS


@njit(cache=True)
def _emit_box(cp, cn, cd, cnt, rot, out_p, out_n, out_d, k):
    """Thin a box's candidates to MAX_POINTS.

    Those sharing the deepest candidate's normal (a box on a face) come first: the
    ones extreme along the eight diagonals of the box's face across that normal (plus
    their depth), the corners of the support region (as :func:`.collide.reduce_points`
    does for two boxes). Free rows then go to the others (a wall beside it) by farthest-point
    sampling.
    """
    if cnt <= MAX_POINTS:
        return _emit_thinned(cp, cn, cd, cnt, out_p, out_n, out_d, k)
    top = 0
    for c in range(1, cnt):
        if cd[c] > cd[top]:
            top = c
    n0 = cn[top].copy()
    drop = most_aligned_axis(rot, n0)
    group = np.zeros(cnt, dtype=np.bool_)
    for c in range(cnt):
        dn = 0.0
        for m in range(4):
            dn += cn[c, m] * n0[m]
        group[c] = dn >= _SPHERE_SAME_NORMAL
    written = 0
    for sgn in range(8):
        far = -np.inf
        pick = -1
        for c in range(cnt):
            if not group[c]:
                continue
            s = 0.0
            j = 0
            for a in range(4):
                if a == drop:
                    continue
                sg = 1.0 if (sgn >> j) & 1 else -1.0
                j += 1
                for m in range(4):
                    s += sg * rot[m, a] * cp[c, m]
            # Depth counts as much as reach: a corner a little in beats the speculative
            # point above it where a box edge leaves the margin (a hair farther out
            # when the box is turned), which would leave that corner unsupported.
            s += cd[c]
            if s > far:
                far = s
                pick = c
        if written_before(out_p, k, written, cp, pick):
            continue
        for m in range(4):
            out_p[k + written, m] = cp[pick, m]
            out_n[k + written, m] = cn[pick, m]
        out_d[k + written] = cd[pick]
        written += 1
    # The rest by farthest-point sampling from what is kept.
    dist = np.full(cnt, np.inf)
    while written < MAX_POINTS:
        nxt = -1
        best = -1.0
        for c in range(cnt):
            if group[c]:
                continue
            d2 = dist[c]
            for q in range(written):
                e2 = 0.0
                for m in range(4):
                    e = cp[c, m] - out_p[k + q, m]
                    e2 += e * e
                if e2 < d2:
                    d2 = e2
            dist[c] = d2
            if d2 > best:
                best = d2
                nxt = c
        if nxt < 0 or best <= 0.0:
            break
        group[nxt] = True
        for m in range(4):
            out_p[k + written, m] = cp[nxt, m]
            out_n[k + written, m] = cn[nxt, m]
        out_d[k + written] = cd[nxt]
        written += 1
    return written


@njit(cache=True)
def _first(bounds, t0, t1, ax, v):
    """First tet of ``t0:t1`` (sorted by their low bound along ``ax``) whose low bound is
    at least ``v``: a body reaching down to ``v + ext`` meets no tet before it, as no tet
    is longer than ``ext`` along that axis."""
    a = t0
    b = t1
    while a < b:
        m = (a + b) // 2
        if bounds[m, ax] < v:
            a = m + 1
        else:
            b = m
    return a


@njit(cache=True)
def _overlaps(bounds, t, lo, hi):
    for m in range(4):
        if bounds[t, m] > hi[m] or bounds[t, 4 + m] < lo[m]:
            return False
    return True


@njit(cache=True)
def sphere_tets(c, r, tets, planes, bary, bounds, t0, t1, ax, ext, margin, cp, cn, cd, out_p, out_n, out_d, k):
    """Contacts of a hypersphere with tets ``t0:t1`` of a tet mesh (normal from the sphere).

    Parameters
    ----------
    c : (4,) float64
        Centre.
    r : float
        Radius.
    tets, planes, bary, bounds : arrays of :func:`tet_geometry`
    t0, t1 : int
        The mesh's tets, sorted by their low bound along axis ``ax``.
    ax : int
    ext : float
        The mesh's longest tet along ``ax``: the tets a body can meet are a run of them.
    margin : float
        Speculative distance.
    cp, cn, cd : (CANDIDATES, 4), (CANDIDATES, 4), (CANDIDATES,) float64
        Candidate scratch.
    out_p, out_n, out_d, k
        Contact output from row ``k``.

    Returns
    -------
    int
        Contacts written (at most ``MAX_POINTS``).
    """
    lo = np.empty(4)
    hi = np.empty(4)
    for m in range(4):
        lo[m] = c[m] - r - margin
        hi[m] = c[m] + r + margin
    q = np.empty(4)
    cl = np.empty(4)
    tmp = np.empty(4)
    nrm = np.empty(4)
    pt = np.empty(4)
    cnt = 0
    nface = 0
    # Two sweeps: face regions first (the centre's projection in the tet), then the
    # tets' edges and corners. A flat face made of several tets has inner edges that
    # are no feature: an edge point on (or behind) the plane of a face contact is
    # covered by it, and left out, else its tilted normal would set a resting ball rolling.
    for sweep in range(2):
        for t in range(_first(bounds, t0, t1, ax, lo[ax] - ext), t1):
            if bounds[t, ax] > hi[ax]:
                break
            if not _overlaps(bounds, t, lo, hi):
                continue
            s = -planes[t, 4]
            for m in range(4):
                s += planes[t, m] * c[m]
            if s > r + margin or s < -(MAX_DEPTH + margin):
                continue
            for m in range(4):
                q[m] = c[m] - s * planes[t, m]
            inside = _project_inside(tets, bary, t, q)
            if inside != (sweep == 0):
                continue
            if inside:
                # In front: the face is nearest. Behind (the centre already in): out along
                # the face's normal, never through an edge (that would point inwards).
                depth = r - s
                for m in range(4):
                    nrm[m] = -planes[t, m]
            else:
                if s < 0.0:
                    continue
                d = np.sqrt(_closest_on_boundary(c, tets, t, cl, tmp))
                if d > r + margin or d <= 1e-12:
                    continue
                covered = False
                for f in range(nface):
                    # cl on or behind face contact f's plane (normal -cn[f], through its point)?
                    e = 0.0
                    for m in range(4):
                        e += cn[f, m] * (cl[m] - c[m] - cn[f, m] * (r - cd[f]))
                    if e >= -_SAME_POINT:
                        covered = True
                        break
                if covered:
                    continue
                for m in range(4):
                    nrm[m] = (cl[m] - c[m]) / d
                depth = r - d
            for m in range(4):
                pt[m] = c[m] + nrm[m] * (r - 0.5 * depth)
            cnt = _add(cp, cn, cd, cnt, pt, nrm, depth, _SPHERE_SAME_NORMAL, -1.0)
        if sweep == 0:
            nface = cnt
    return _emit_thinned(cp, cn, cd, cnt, out_p, out_n, out_d, k)


@njit(cache=True)
def _keep_least_deep(cp, cn, cd, cnt, tets, planes, bary, bounds, t0, t1, ax, ext, lo, hi, margin, deep, raw):
    """Drop each of the box's points that another tet sees less deep (or outside).

    A point of the box a little inside the solid near a convex edge is behind both
    faces of the edge; only the shallower tells how it came in (a box resting on a
    lintel's top near its end is not inside the end face). Within the margin of each
    other both stay: a point on the rim is on both faces. Returns the new count.
    """
    keep = 0
    for c in range(cnt):
        for m in range(4):
            raw[m] = cp[c, m] + 0.5 * cd[c] * cn[c, m]
        drop = False
        for t in range(_first(bounds, t0, t1, ax, lo[ax] - ext), t1):
            if bounds[t, ax] > hi[ax]:
                break
            if not _overlaps(bounds, t, lo, hi):
                continue
            s = -planes[t, 4]
            for m in range(4):
                s += planes[t, m] * raw[m]
            if s > margin or s < -deep or -s >= cd[c] - margin:
                continue
            if _project_inside(tets, bary, t, raw):
                drop = True
                break
        if not drop:
            if keep != c:
                for m in range(4):
                    cp[keep, m] = cp[c, m]
                    cn[keep, m] = cn[c, m]
                cd[keep] = cd[c]
            keep += 1
    return keep


@njit(cache=True)
def _surface_point(p, x, rot, h, un, depth_lo, margin, nrm, cp, cn, cd, cnt, ql, pt):
    """Add a point ``p`` of a tet (outward normal ``un``) that lies in the box (grown by the
    margin along ``un``) as a candidate.

    The box meets the tet with its face most turned towards it (the face whose axis is
    most aligned with ``un``); the depth is how far the box must move along ``un`` for
    that face to pass ``p`` (a gap when negative). Kept when ``-margin <= depth <=
    depth_lo``. A rim of the solid inside a tilted box is met by the box's bottom face
    through the top tet; through the end tet the box's far side face would have to
    pass it, much deeper, and that one is dropped.
    """
    best = -1.0
    ua = 0.0
    qa = 0.0
    for a in range(4):
        q = 0.0
        u = 0.0
        for m in range(4):
            q += rot[m, a] * (p[m] - x[m])
            u += rot[m, a] * un[m]
        ql[a] = q
        if abs(u) > best:
            best = abs(u)
            ua = u
            qa = q
            ax = a
    # The face at -sign(u) h along that axis faces the tet; p is g in front of it.
    g = h[ax] + qa if ua > 0.0 else h[ax] - qa
    depth = g / best
    if depth < -margin or depth > depth_lo:
        return cnt
    for m in range(4):
        pt[m] = p[m] - 0.5 * depth * un[m]
    return _add(cp, cn, cd, cnt, pt, nrm, depth, _SAME_NORMAL, _SAME_POINT * _SAME_POINT)


@njit(cache=True)
def box_tets(x, rot, h, tets, planes, bary, bounds, t0, t1, ax, ext, margin, cp, cn, cd, out_p, out_n, out_d, k):
    """Contacts of a 4D box with tets ``t0:t1`` of a tet mesh (normal from the box).

    Parameters
    ----------
    x : (4,) float64
        Box centre.
    rot : (4, 4) float64
        Box rotation (columns are its axes).
    h : (4,) float64
        Half extents.
    tets, planes, bary, bounds, t0, t1, ax, ext, margin, cp, cn, cd, out_p, out_n, out_d, k
        As :func:`sphere_tets`.

    Returns
    -------
    int
        Contacts written (at most ``MAX_POINTS``).
    """
    v = np.empty((16, 4))
    lo = np.empty(4)
    hi = np.empty(4)
    for m in range(4):
        e = 0.0
        for a in range(4):
            e += abs(rot[m, a]) * h[a]
        lo[m] = x[m] - e - margin
        hi[m] = x[m] + e + margin
    for j in range(16):
        for m in range(4):
            s = x[m]
            for a in range(4):
                if (j >> a) & 1:
                    s += h[a] * rot[m, a]
                else:
                    s -= h[a] * rot[m, a]
            v[j, m] = s
    un = np.empty(4)
    nrm = np.empty(4)
    q = np.empty(4)
    pt = np.empty(4)
    ql = np.empty(4)
    lim = np.empty(4)
    vl = np.empty((4, 4))
    fv = np.empty((16, 6))
    deep = MAX_DEPTH + margin
    cnt = 0
    # Two sweeps over the tets: the box's points (1), then the tets' points (2, 3).
    for sweep in range(2):
        if sweep == 1:
            cnt = _keep_least_deep(
                cp, cn, cd, cnt, tets, planes, bary, bounds, t0, t1, ax, ext, lo, hi, margin, deep, q
            )
        for t in range(_first(bounds, t0, t1, ax, lo[ax] - ext), t1):
            if bounds[t, ax] > hi[ax]:
                break
            if not _overlaps(bounds, t, lo, hi):
                continue
            for m in range(4):
                un[m] = planes[t, m]
                nrm[m] = -planes[t, m]
            # The box's extent along the tet's normal: all of it beyond the margin in
            # front, or deeper than the window behind, and this tet has nothing to say.
            sc = -planes[t, 4]
            ext = 0.0
            for m in range(4):
                sc += un[m] * x[m]
            for a in range(4):
                u = 0.0
                for m in range(4):
                    u += un[m] * rot[m, a]
                lim[a] = u
                ext += h[a] * abs(u)
            if sc - ext > margin or sc + ext < -deep:
                continue
            if sweep == 0:
                # (1) The box's corners and edges over the tet, near or below its face: each
                # edge clipped to the prism of points whose projection falls in the tet and
                # that lie within [-deep, margin] of its face (the barycentric coordinates and
                # the distance are affine along an edge). Its ends are contact points.
                for j in range(16):
                    s = -planes[t, 4]
                    for m in range(4):
                        s += un[m] * v[j, m]
                    fv[j, 0] = margin - s
                    fv[j, 1] = s + deep
                    l0 = 1.0
                    for a in range(3):
                        lam = 0.0
                        for m in range(4):
                            lam += bary[t, a, m] * (v[j, m] - tets[t, 0, m])
                        fv[j, 3 + a] = lam + _BARY_TOL
                        l0 -= lam
                    fv[j, 2] = l0 + _BARY_TOL
                for j in range(16):
                    for kk in range(4):
                        if (j >> kk) & 1:
                            continue
                        j2 = j | (1 << kk)
                        e0 = 0.0
                        e1 = 1.0
                        ok = True
                        for f in range(6):
                            f0 = fv[j, f]
                            f1 = fv[j2, f]
                            if f0 < 0.0 and f1 < 0.0:
                                ok = False
                                break
                            if f0 < 0.0:
                                tc = f0 / (f0 - f1)
                                if tc > e0:
                                    e0 = tc
                            elif f1 < 0.0:
                                tc = f0 / (f0 - f1)
                                if tc < e1:
                                    e1 = tc
                        if not ok or e0 > e1:
                            continue
                        for tt in (e0, e1):
                            s = -planes[t, 4]
                            for m in range(4):
                                q[m] = v[j, m] + tt * (v[j2, m] - v[j, m])
                                s += un[m] * q[m]
                            # The point lies on three or four of the box's faces; one of them
                            # must face the tet. A box edge just inside a lintel's rim faces
                            # its top with its bottom face, and none faces the lintel's end.
                            align = 0.0
                            for a in range(4):
                                qa = 0.0
                                for m in range(4):
                                    qa += rot[m, a] * (q[m] - x[m])
                                if abs(qa) >= h[a] - 1e-7 * (1.0 + h[a]):
                                    f = -lim[a] if qa > 0.0 else lim[a]
                                    if f > align:
                                        align = f
                            if align >= _FACE_ALIGN:
                                for m in range(4):
                                    pt[m] = q[m] - 0.5 * s * un[m]
                                cnt = _add(cp, cn, cd, cnt, pt, nrm, -s, _SAME_NORMAL, _SAME_POINT * _SAME_POINT)
                            if e1 == e0:
                                break
                continue
            # (2) and (3): the tet's corners and edge crossings inside the box grown by the
            # margin along the normal only (a point beside the box does not hold it up).
            for a in range(4):
                lim[a] = h[a] + margin * abs(lim[a]) + 1e-9
            for i in range(4):
                for a in range(4):
                    s = 0.0
                    for m in range(4):
                        s += rot[m, a] * (tets[t, i, m] - x[m])
                    vl[i, a] = s
            for i in range(4):
                ok = True
                for a in range(4):
                    if abs(vl[i, a]) > lim[a]:
                        ok = False
                        break
                if ok:
                    cnt = _surface_point(tets[t, i], x, rot, h, un, deep, margin, nrm, cp, cn, cd, cnt, ql, pt)
            for i in range(3):
                for j in range(i + 1, 4):
                    e0 = 0.0
                    e1 = 1.0
                    ok = True
                    for a in range(4):
                        p0 = vl[i, a]
                        dp = vl[j, a] - p0
                        if abs(dp) < 1e-14:
                            if abs(p0) > lim[a]:
                                ok = False
                                break
                            continue
                        ta = (-lim[a] - p0) / dp
                        tb = (lim[a] - p0) / dp
                        if ta > tb:
                            ta, tb = tb, ta
                        if ta > e0:
                            e0 = ta
                        if tb < e1:
                            e1 = tb
                        if e0 > e1:
                            ok = False
                            break
                    if not ok:
                        continue
                    for tt in (e0, e1):
                        if 0.0 < tt < 1.0:
                            for m in range(4):
                                q[m] = tets[t, i, m] + tt * (tets[t, j, m] - tets[t, i, m])
                            cnt = _surface_point(q, x, rot, h, un, deep, margin, nrm, cp, cn, cd, cnt, ql, pt)
    return _emit_box(cp, cn, cd, cnt, rot, out_p, out_n, out_d, k)


@njit(cache=True)
def ray_tets(o, d, tets, planes, bary, t0, t1, best_t):
    """First front-facing tet of ``t0:t1`` hit by the ray ``o + t d`` before ``best_t``.

    Returns
    -------
    t : float
        Distance (``best_t`` when nothing nearer is hit).
    tet : int
        The tet hit, or -1.
    """
    q = np.empty(4)
    hit = -1
    for t in range(t0, t1):
        dn = 0.0
        on = -planes[t, 4]
        for m in range(4):
            dn += planes[t, m] * d[m]
            on += planes[t, m] * o[m]
        # Only faces seen from outside: a ray from inside the solid passes out of it.
        if dn >= 0.0 or on < 0.0:
            continue
        tt = -on / dn
        if tt >= best_t:
            continue
        for m in range(4):
            q[m] = o[m] + tt * d[m]
        if _project_inside(tets, bary, t, q):
            best_t = tt
            hit = t
    return best_t, hit
