"""Contacts of a hypersphere or a 4D box with a tet mesh (the method is in :mod:`.tet_mesh`).

Both routines take the mesh as ``mesh = (tets, planes, bary, bounds)`` (the arrays
of :func:`.tet_mesh.tet_geometry`, for all meshes) and ``run = (t0, t1, ax, ext)``:
the mesh's tets ``t0:t1``, sorted by their low bound along axis ``ax``, and its
longest tet along that axis. Candidates go to ``cand``
(:mod:`.tet_candidates`), the thinned contacts to ``out`` from row ``k``.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .tet_candidates import SPHERE_SAME_NORMAL, add_candidate, emit_box, emit_thinned
from .tet_mesh import (
    BARY_TOL,
    FACE_ALIGN,
    MAX_DEPTH,
    SAME_NORMAL,
    SAME_POINT,
    closest_on_boundary,
    first_tet,
    overlaps,
    project_inside,
)


@njit(cache=True)
def _edge_candidate(ball, s, t, tets, margin, cand, nface, work):
    """The ball ``(centre, radius)`` against tet ``t`` away from its face region: whether it
    has a candidate there (not covered by a face contact among the first ``nface``
    candidates), and its depth; the normal goes to ``work[2]`` (``work``: three ``(4,)``)."""
    c, r = ball
    cl, tmp, nrm = work
    cp, cn, cd = cand
    if s < 0.0:
        return False, 0.0
    d = np.sqrt(closest_on_boundary(c, tets, t, cl, tmp))
    if d > r + margin or d <= 1e-12:
        return False, 0.0
    for f in range(nface):
        # cl on or behind face contact f's plane (normal -cn[f], through its point)?
        e = 0.0
        for m in range(4):
            e += cn[f, m] * (cl[m] - c[m] - cn[f, m] * (r - cd[f]))
        if e >= -SAME_POINT:
            return False, 0.0
    for m in range(4):
        nrm[m] = (cl[m] - c[m]) / d
    return True, r - d


@njit(cache=True)
def sphere_tets(c, r, mesh, run, margin, cand, out, k):
    """Contacts of a hypersphere (centre ``c`` ``(4,)``, radius ``r``) with a tet mesh (normal
    from the sphere); at most ``MAX_POINTS`` are written. ``margin`` is the speculative distance.

    Two sweeps: face regions first (the centre's projection in the tet), then the
    tets' edges and corners. A flat face made of several tets has inner edges that
    are no feature: an edge point on (or behind) the plane of a face contact is
    covered by it, and left out, else its tilted normal would set a resting ball rolling.
    """
    tets, planes, bary, bounds = mesh
    t0, t1, ax, ext = run
    lo = np.empty(4)
    hi = np.empty(4)
    for m in range(4):
        lo[m] = c[m] - r - margin
        hi[m] = c[m] + r + margin
    q = np.empty(4)
    work = (np.empty(4), np.empty(4), np.empty(4))
    nrm = work[2]
    pt = np.empty(4)
    cnt = 0
    nface = 0
    for sweep in range(2):
        for t in range(first_tet(bounds, t0, t1, ax, lo[ax] - ext), t1):
            if bounds[t, ax] > hi[ax]:
                break
            if not overlaps(bounds, t, lo, hi):
                continue
            s = -planes[t, 4]
            for m in range(4):
                s += planes[t, m] * c[m]
            if s > r + margin or s < -(MAX_DEPTH + margin):
                continue
            for m in range(4):
                q[m] = c[m] - s * planes[t, m]
            inside = project_inside(tets, bary, t, q)
            if inside != (sweep == 0):
                continue
            if inside:
                # In front: the face is nearest. Behind (the centre already in): out along
                # the face's normal, never through an edge (that would point inwards).
                depth = r - s
                for m in range(4):
                    nrm[m] = -planes[t, m]
            else:
                ok, depth = _edge_candidate((c, r), s, t, tets, margin, cand, nface, work)
                if not ok:
                    continue
            for m in range(4):
                pt[m] = c[m] + nrm[m] * (r - 0.5 * depth)
            cnt = add_candidate(cand, cnt, pt, nrm, depth, SPHERE_SAME_NORMAL, -1.0)
        if sweep == 0:
            nface = cnt
    return emit_thinned(cand, cnt, out, k)


@njit(cache=True)
def _keep_least_deep(cand, cnt, mesh, run, reach, margin, deep, raw):
    """Drop each of the box's points that another tet sees less deep (or outside).

    A point of the box a little inside the solid near a convex edge is behind both
    faces of the edge; only the shallower tells how it came in (a box resting on a
    lintel's top near its end is not inside the end face). Within the margin of each
    other both stay: a point on the rim is on both faces. ``reach`` is the box's
    bounds ``(lo, hi)``, ``raw`` work ``(4,)``. Returns the new count.
    """
    cp, cn, cd = cand
    tets, planes, bary, bounds = mesh
    t0, t1, ax, ext = run
    lo, hi = reach
    keep = 0
    for c in range(cnt):
        for m in range(4):
            raw[m] = cp[c, m] + 0.5 * cd[c] * cn[c, m]
        drop = False
        for t in range(first_tet(bounds, t0, t1, ax, lo[ax] - ext), t1):
            if bounds[t, ax] > hi[ax]:
                break
            if not overlaps(bounds, t, lo, hi):
                continue
            s = -planes[t, 4]
            for m in range(4):
                s += planes[t, m] * raw[m]
            if s > margin or s < -deep or -s >= cd[c] - margin:
                continue
            if project_inside(tets, bary, t, raw):
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
def _surface_point(p, box, normals, depth_lo, margin, cand, cnt, work):
    """Add a point ``p`` of a tet that lies in the box (grown by the margin along the tet's
    outward normal) as a candidate.

    ``normals`` is the tet's outward and inward unit normals; ``work`` two ``(4,)``.
    The box meets the tet with its face most turned towards it (the face whose axis is
    most aligned with the normal); the depth is how far the box must move along it for
    that face to pass ``p`` (a gap when negative). Kept when ``-margin <= depth <=
    depth_lo``. A rim of the solid inside a tilted box is met by the box's bottom face
    through the top tet; through the end tet the box's far side face would have to
    pass it, much deeper, and that one is dropped.
    """
    x, rot, h = box
    un, nrm = normals
    ql, pt = work
    best = -1.0
    ua = 0.0
    qa = 0.0
    ax = 0
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
    return add_candidate(cand, cnt, pt, nrm, depth, SAME_NORMAL, SAME_POINT * SAME_POINT)


@njit(inline="always")
def _facing(t, box, planes, margin, deep, normals, lim):
    """Tet ``t``'s outward and inward normals into ``normals``, the box's axes along the normal
    into ``lim``: ``(near, ext)``, whether the box reaches within ``[-deep, margin]`` of the tet's
    hyperplane, and its extent along the normal."""
    x, rot, h = box
    un, nrm = normals
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
    return not (sc - ext > margin or sc + ext < -deep), ext


@njit(inline="always")
def _corner_values(t, v, mesh, un, margin, deep, fv):
    """For each box corner: how far it is inside each of the six limits of tet ``t``'s prism
    (the two of its distance to the face, the four barycentric ones), into ``fv`` ``(16, 6)``."""
    tets, planes, bary, _ = mesh
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
            fv[j, 3 + a] = lam + BARY_TOL
            l0 -= lam
        fv[j, 2] = l0 + BARY_TOL


@njit(inline="always")
def _prism_span(fv, j, j2):
    """The part ``[e0, e1]`` of the box edge from corner ``j`` to ``j2`` inside the prism
    (the limits are affine along an edge): ``(ok, e0, e1)``."""
    e0 = 0.0
    e1 = 1.0
    for f in range(6):
        f0 = fv[j, f]
        f1 = fv[j2, f]
        if f0 < 0.0 and f1 < 0.0:
            return False, e0, e1
        if f0 < 0.0:
            tc = f0 / (f0 - f1)
            if tc > e0:
                e0 = tc
        elif f1 < 0.0:
            tc = f0 / (f0 - f1)
            if tc < e1:
                e1 = tc
    return e0 <= e1, e0, e1


@njit(inline="always")
def _facing_face(q, box, lim):
    """How squarely the box faces the tet at its surface point ``q``: the largest ``-lim[a]``
    (``lim`` the box's axes along the tet's outward normal) over the faces ``q`` lies on."""
    x, rot, h = box
    align = 0.0
    for a in range(4):
        qa = 0.0
        for m in range(4):
            qa += rot[m, a] * (q[m] - x[m])
        if abs(qa) >= h[a] - 1e-7 * (1.0 + h[a]):
            f = -lim[a] if qa > 0.0 else lim[a]
            if f > align:
                align = f
    return align


@njit(cache=True)
def _box_corners(box, mesh, run, margin, cand, work):
    """(1) The box's corners and edges over each tet, near or below its face: each edge clipped
    to the prism of points whose projection falls in the tet and that lie within
    ``[-deep, margin]`` of its face. Its ends are contact points. Returns ``(count, ext)``,
    ``ext`` the box's extent along the last tet's normal met (``run``'s own when none)."""
    v, un, nrm, q, pt, ql, lim, vl, fv, reach = work
    tets, planes, bary, bounds = mesh
    t0, t1, ax, ext = run
    lo, hi = reach
    deep = MAX_DEPTH + margin
    cnt = 0
    for t in range(first_tet(bounds, t0, t1, ax, lo[ax] - ext), t1):
        if bounds[t, ax] > hi[ax]:
            break
        if not overlaps(bounds, t, lo, hi):
            continue
        near, ext = _facing(t, box, planes, margin, deep, (un, nrm), lim)
        if not near:
            continue
        _corner_values(t, v, mesh, un, margin, deep, fv)
        for j in range(16):
            for kk in range(4):
                if (j >> kk) & 1:
                    continue
                j2 = j | (1 << kk)
                ok, e0, e1 = _prism_span(fv, j, j2)
                if not ok:
                    continue
                for tt in (e0, e1):
                    s = -planes[t, 4]
                    for m in range(4):
                        q[m] = v[j, m] + tt * (v[j2, m] - v[j, m])
                        s += un[m] * q[m]
                    # The point lies on three or four of the box's faces; one of them
                    # must face the tet. A box edge just inside a lintel's rim faces
                    # its top with its bottom face, and none faces the lintel's end.
                    if _facing_face(q, box, lim) >= FACE_ALIGN:
                        for m in range(4):
                            pt[m] = q[m] - 0.5 * s * un[m]
                        cnt = add_candidate(cand, cnt, pt, nrm, -s, SAME_NORMAL, SAME_POINT * SAME_POINT)
                    if e1 == e0:
                        break
    return cnt, ext


@njit(inline="always")
def _tet_edge_span(vl, i, j, lim):
    """The part ``[e0, e1]`` of the tet edge from corner ``i`` to ``j`` (box frame ``vl``) inside
    the box's slabs ``lim``: ``(ok, e0, e1)``."""
    e0 = 0.0
    e1 = 1.0
    for a in range(4):
        p0 = vl[i, a]
        dp = vl[j, a] - p0
        if abs(dp) < 1e-14:
            if abs(p0) > lim[a]:
                return False, e0, e1
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
            return False, e0, e1
    return True, e0, e1


@njit(cache=True)
def _tet_corners(box, mesh, run, margin, cand, cnt, work):
    """(2) and (3): each tet's corners and edge crossings inside the box grown by the margin
    along the tet's normal only (a point beside the box does not hold it up). Returns the count."""
    v, un, nrm, q, pt, ql, lim, vl, fv, reach = work
    x, rot, h = box
    tets, planes, bary, bounds = mesh
    t0, t1, ax, ext = run
    lo, hi = reach
    deep = MAX_DEPTH + margin
    for t in range(first_tet(bounds, t0, t1, ax, lo[ax] - ext), t1):
        if bounds[t, ax] > hi[ax]:
            break
        if not overlaps(bounds, t, lo, hi):
            continue
        near, _ = _facing(t, box, planes, margin, deep, (un, nrm), lim)
        if not near:
            continue
        for a in range(4):
            lim[a] = h[a] + margin * abs(lim[a]) + 1e-9
        for i in range(4):
            for a in range(4):
                s = 0.0
                for m in range(4):
                    s += rot[m, a] * (tets[t, i, m] - x[m])
                vl[i, a] = s
        for i in range(4):
            inside = True
            for a in range(4):
                if abs(vl[i, a]) > lim[a]:
                    inside = False
                    break
            if inside:
                cnt = _surface_point(tets[t, i], box, (un, nrm), deep, margin, cand, cnt, (ql, pt))
        for i in range(3):
            for j in range(i + 1, 4):
                ok, e0, e1 = _tet_edge_span(vl, i, j, lim)
                if not ok:
                    continue
                for tt in (e0, e1):
                    if 0.0 < tt < 1.0:
                        for m in range(4):
                            q[m] = tets[t, i, m] + tt * (tets[t, j, m] - tets[t, i, m])
                        cnt = _surface_point(q, box, (un, nrm), deep, margin, cand, cnt, (ql, pt))
    return cnt


@njit(cache=True)
def box_tets(box, mesh, run, margin, cand, out, k):
    """Contacts of a 4D box (:class:`~.collide.Box`) with a tet mesh (normal from the box); at
    most ``MAX_POINTS`` are written. Two sweeps over the tets: the box's points (1), then the
    tets' points (2, 3), after dropping the box's points another tet sees less deep."""
    x, rot, h = box
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
    small = np.empty((7, 4))
    work = (
        v,
        small[0],
        small[1],
        small[2],
        small[3],
        small[4],
        small[5],
        np.empty((4, 4)),
        np.empty((16, 6)),
        (lo, hi),
    )
    cnt, ext = _box_corners(box, mesh, run, margin, cand, work)
    # (The sweep over the tets' points starts from the box's extent along the last
    # tet's normal, as it always has: the run's longest tet is not used there.)
    run = (run[0], run[1], run[2], ext)
    cnt = _keep_least_deep(cand, cnt, mesh, run, (lo, hi), margin, MAX_DEPTH + margin, small[2])
    cnt = _tet_corners(box, mesh, run, margin, cand, cnt, work)
    return emit_box(cand, cnt, rot, out, k)
