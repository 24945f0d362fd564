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
The contacts are found in :mod:`.tet_contacts` (their candidates merged and thinned
in :mod:`.tet_candidates`); this module holds the geometry and the ray test.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

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
BARY_TOL = 1e-9
#: Candidates closer than this (metres) with normals closer than SAME_NORMAL are one.
SAME_POINT = 1e-7
SAME_NORMAL = 1.0 - 1e-9
#: Cosine of the largest angle between a tet's normal and the box face a point of the
#: tet leaves the box through, for that point to be a contact of the tet (45 degrees).
FACE_ALIGN = 0.7071
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
def project_inside(tets, bary, t, q):
    """Whether ``q`` (in tet ``t``'s hyperplane) lies in the tet."""
    s = 0.0
    for a in range(3):
        lam = 0.0
        for m in range(4):
            lam += bary[t, a, m] * (q[m] - tets[t, 0, m])
        if lam < -BARY_TOL:
            return False
        s += lam
    return s <= 1.0 + BARY_TOL


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
def closest_on_boundary(p, tets, t, out, tmp):
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
def first_tet(bounds, t0, t1, ax, v):
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
def overlaps(bounds, t, lo, hi):
    for m in range(4):
        if bounds[t, m] > hi[m] or bounds[t, 4 + m] < lo[m]:
            return False
    return True


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
        if project_inside(tets, bary, t, q):
            best_t = tt
            hit = t
    return best_t, hit
