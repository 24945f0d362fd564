"""Candidate contacts against a tet mesh: merged as they are found, thinned to
:data:`~.collide.MAX_POINTS` when written (see :mod:`.tet_mesh`).

Candidates are a :class:`~.state.Points` of :data:`.tet_mesh.CANDIDATES` rows
(the scratch's ``tet_points``, ``tet_normals``, ``tet_depths``).
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .collide import MAX_POINTS, most_aligned_axis, written_before

#: Sphere candidates whose normals agree to this are one contact (the deepest): a ball
#: on a face made of several coplanar tets touches it once.
SPHERE_SAME_NORMAL = 1.0 - 1e-6


@njit(cache=True)
def add_candidate(cand, cnt, p, n, depth, same_normal, same_point2):
    """Add a candidate unless one with the same normal (and point) is there; keep the deeper.

    ``same_point2 < 0`` merges on the normal alone. When the buffer is full the
    shallowest candidate gives way to a deeper one. ``cand`` is the candidates'
    :class:`~.state.Points` (``cnt`` rows used). Returns the new count.
    """
    cp, cn, cd = cand
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
def emit_thinned(cand, cnt, out, k):
    """Write at most MAX_POINTS candidates: the deepest, then each time the one farthest from
    those kept (first in order on ties). Returns how many were written."""
    cp, cn, cd = cand
    out_p, out_n, out_d = out
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
def _face_corners(cand, cnt, rot, group, out, k):
    """Write the candidates of ``group`` extreme along the eight diagonals of the box's face
    across their normal (plus their depth): the corners of the support region. Returns how many."""
    cp, cn, cd = cand
    out_p, out_n, out_d = out
    top = 0
    for c in range(1, cnt):
        if cd[c] > cd[top]:
            top = c
    n0 = cn[top].copy()
    drop = most_aligned_axis(rot, n0)
    for c in range(cnt):
        dn = 0.0
        for m in range(4):
            dn += cn[c, m] * n0[m]
        group[c] = dn >= SPHERE_SAME_NORMAL
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
    return written


@njit(cache=True)
def emit_box(cand, cnt, rot, out, k):
    """Thin a box's candidates to MAX_POINTS.

    Those sharing the deepest candidate's normal (a box on a face) come first: the
    ones extreme along the eight diagonals of the box's face across that normal (plus
    their depth), the corners of the support region (as :func:`.collide.reduce_points`
    does for two boxes). Free rows then go to the others (a wall beside it) by farthest-point
    sampling.
    """
    if cnt <= MAX_POINTS:
        return emit_thinned(cand, cnt, out, k)
    cp, cn, cd = cand
    out_p, out_n, out_d = out
    group = np.zeros(cnt, dtype=np.bool_)
    written = _face_corners(cand, cnt, rot, group, out, k)
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
