"""Narrowphase: contact points between hyperspheres, 4D boxes and the static world.

Every routine writes contacts into caller-owned arrays and returns how many it
wrote. A contact is a world point ``(4,)``, a unit normal ``(4,)`` pointing from
the first shape to the second, and a depth (positive when overlapping, negative
down to ``-margin`` for speculative contacts that are about to touch, which lets
the solver stop fast bodies before they pass through each other).

Box-box (:mod:`.boxes`) uses the separating-axis test over the 56 candidate axes of two 4D
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

from typing import NamedTuple

import numpy as np

from across_dimensions.core._jit import njit

#: Most contact points kept per touching pair (a 3D overlap cell has 8 corners).
MAX_POINTS = 8
#: Scratch rows needed by :func:`box_box` for its candidate points.
SCRATCH_POINTS = 160
#: Rows of the ``(SCRATCH_ROWS, 4)`` work array the routines here use.
SCRATCH_ROWS = 36 + SCRATCH_POINTS

SPHERE = 0
BOX = 1


class Box(NamedTuple):
    """A 4D box where it is: the first argument of the box routines here and in :mod:`.boxes`.

    Attributes
    ----------
    center : (4,) float64
    rotation : (4, 4) float64
        Box to world (columns are the box's axes).
    half : (4,) float64
        Half extents.
    """

    center: np.ndarray
    rotation: np.ndarray
    half: np.ndarray


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


@njit(inline="always")
def _extreme_picks(pr, cd, cnt):
    """For each of the eight diagonals ``+-u1 +-u2 +-u3``, the candidate farthest along it
    (coordinates ``pr[:cnt]`` along ``u``), the deepest among near ties."""
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
    return picks


@njit(cache=True)
def reduce_points(cand, cnt, n, rot, wk, out, k):
    """Keep the candidates that are extreme along the diagonals of a box face.

    A face-to-face contact region is (close to) a 3D box whose edges follow the
    lateral axes of one of the boxes, so the candidates farthest along the
    eight directions ``+-u1 +-u2 +-u3`` are its corners: the support outline a
    resting box needs. Nearly tied candidates (a vertex and the point where an
    edge through it leaves the speculative margin, or two almost coincident
    corners of the two boxes) resolve to the deepest.

    Parameters
    ----------
    cand : tuple
        Candidate points ``(M, 4)`` and depths ``(M,)``; rows ``[:cnt]`` are used.
    cnt : int
    n : (4,) float64
        Shared contact normal, copied to every output row.
    rot : (4, 4) float64
        Rotation of the box whose face the region follows; its axis most
        aligned with ``n`` is dropped and the other three give ``u1, u2, u3``.
    wk : (4 + M, 4) float64
        Scratch.
    out : Points
    k : int
        First output row.

    Returns
    -------
    int
        Rows written (at most :data:`MAX_POINTS`).
    """
    if cnt == 0:
        return 0
    cp, cd = cand
    out_p, out_n, out_d = out
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
    picks = _extreme_picks(pr, cd, cnt)
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
def sphere_sphere(xa, ra, xb, rb, margin, wk, out, k):
    """One contact between two hyperspheres (normal from a to b); returns 0 or 1.

    ``wk`` is a ``(W, 4) float64`` scratch array and ``out`` the :class:`~.state.Points`
    written from row ``k``, as for all routines here.
    """
    out_p, out_n, out_d = out
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
def box_sphere(box, c, r, margin, wk, out, k):
    """One contact between a box and a hypersphere (normal from box to sphere).

    Parameters
    ----------
    box : Box
    c : (4,) float64
        Sphere centre.
    r : float
        Sphere radius.

    Returns
    -------
    int
        0 or 1.
    """
    xb, rot, h = box
    out_p, out_n, out_d = out
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


@njit(cache=True)
def sphere_halfspace(c, r, pn, off, margin, out, k):
    """Hypersphere against the solid ``{x : pn . x <= off}`` (normal into the solid)."""
    out_p, out_n, out_d = out
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
def box_halfspace(box, pn, off, margin, cand, wk, out, k):
    """Box against the solid ``{x : pn . x <= off}``: its vertices near or below the plane
    (candidates in ``cand``, as for :func:`.boxes.box_box`)."""
    x, rot, h = box
    cp, cd = cand
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
    return reduce_points(cand, cnt, negn, rot, wk[32:], out, k)
