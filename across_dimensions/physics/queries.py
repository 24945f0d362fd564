"""Ray casts and pushing an upright box out of the bodies (compiled kernels).

The box push-out serves anything that lives in a 3D slice ``w = w0`` and only
moves in x, y, z, such as the player (see :mod:`across_dimensions.game.player_bodies`):
its collider is an axis-aligned 4D box, thin in w, and anything whose 4D shape
misses that slab is invisible to it and does not block it.

The push-out is the shortest move *in xyz* that separates the box from a
body. For two convex shapes whose Minkowski difference ``D`` contains the
origin, that move is the distance from the origin to the boundary of the 3D
section of ``D`` at ``w = 0``. Every facet of that section lies on a facet of
``D`` with normal ``u`` and overlap ``o``, at xyz distance ``o / |u_xyz|``; the
box-box separating axes include every facet normal of ``D``, so the minimum of
``o / |u_xyz|`` over them is the exact answer.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import PLANE_I, PLANE_J
from .collide import SPHERE
from .tet_mesh import ray_tets


@njit(cache=True)
def _slab_hit(o, d, lo, hi, ndim):
    """Entry distance and axis of a ray into the box ``[lo, hi]`` over the first
    ``ndim`` coordinates; ``(-1, -1, 0)`` on a miss or when starting inside."""
    tmin = -np.inf
    tmax = np.inf
    ax = -1
    sg = 0.0
    for a in range(ndim):
        if abs(d[a]) < 1e-300:
            if o[a] < lo[a] or o[a] > hi[a]:
                return -1.0, -1, 0.0
            continue
        t1 = (lo[a] - o[a]) / d[a]
        t2 = (hi[a] - o[a]) / d[a]
        s = -1.0
        if t1 > t2:
            t1, t2 = t2, t1
            s = 1.0
        if t1 > tmin:
            tmin = t1
            ax = a
            sg = s
        if t2 < tmax:
            tmax = t2
        if tmin > tmax:
            return -1.0, -1, 0.0
    if tmin < 0.0 or ax < 0:
        return -1.0, -1, 0.0
    return tmin, ax, sg


@njit(cache=True)
def _ray_bodies(bodies, o, d, best_t, normal):
    """Nearest body hit before ``best_t``: ``(body or -(2**62), t)``."""
    alive = bodies.alive
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    best = -(1 << 62)
    ol = np.empty(4)
    dl = np.empty(4)
    lo = np.empty(4)
    hi = np.empty(4)
    for i in range(bodies.count):
        if not alive[i]:
            continue
        if shape[i] == SPHERE:
            r = half[i, 0]
            b = 0.0
            cc = -r * r
            for m in range(4):
                t = o[m] - pos[i, m]
                b += t * d[m]
                cc += t * t
            disc = b * b - cc
            if cc <= 0.0 or disc < 0.0:
                continue
            t = -b - np.sqrt(disc)
            if 0.0 <= t < best_t:
                best_t = t
                best = i
                for m in range(4):
                    normal[m] = (o[m] + t * d[m] - pos[i, m]) / r
        else:
            for a in range(4):
                s = 0.0
                u = 0.0
                for m in range(4):
                    s += rot[i, m, a] * (o[m] - pos[i, m])
                    u += rot[i, m, a] * d[m]
                ol[a] = s
                dl[a] = u
                lo[a] = -half[i, a]
                hi[a] = half[i, a]
            t, ax, sg = _slab_hit(ol, dl, lo, hi, 4)
            if ax >= 0 and t < best_t:
                best_t = t
                best = i
                for m in range(4):
                    normal[m] = sg * rot[i, m, ax]
    return best, best_t


@njit(cache=True)
def _ray_half_spaces_and_boxes(static, o, d, best, best_t, normal):
    """Nearer hits of the half-spaces and 3D world boxes: ``(hit, t)``."""
    hs = static.half_spaces
    wb = static.boxes
    nh = hs.shape[0]
    lo = np.empty(4)
    hi = np.empty(4)
    for s in range(nh):
        dn = 0.0
        on = -hs[s, 4]
        for m in range(4):
            dn += hs[s, m] * d[m]
            on += hs[s, m] * o[m]
        if dn >= 0.0 or on < 0.0:
            continue
        t = -on / dn
        if t < best_t:
            best_t = t
            best = -1 - s
            for m in range(4):
                normal[m] = hs[s, m]
    for s in range(wb.shape[0]):
        for a in range(3):
            lo[a] = wb[s, a] - wb[s, 3 + a]
            hi[a] = wb[s, a] + wb[s, 3 + a]
        t, ax, sg = _slab_hit(o, d, lo, hi, 3)
        if ax >= 0 and t < best_t:
            best_t = t
            best = -1 - nh - s
            for m in range(4):
                normal[m] = 0.0
            normal[ax] = sg
    return best, best_t


@njit(cache=True)
def _ray_solids(static, o, d, best, best_t, normal):
    """Nearer hits of the level's solid boxes and convex solids: ``(hit, t)``.

    A convex solid clips the ray by every facet (Cyrus-Beck); the ray enters
    where the last facet it crosses from outside lets it in.
    """
    so = static.solids
    cpl = static.convex_planes
    cr = static.convex_ranges
    first = static.half_spaces.shape[0] + static.boxes.shape[0]
    ol = np.empty(4)
    dl = np.empty(4)
    lo = np.empty(4)
    hi = np.empty(4)
    for s in range(so.shape[0]):
        for a in range(4):
            u = 0.0
            v = 0.0
            for m in range(4):
                u += so[s, 8 + 4 * m + a] * (o[m] - so[s, m])
                v += so[s, 8 + 4 * m + a] * d[m]
            ol[a] = u
            dl[a] = v
            lo[a] = -so[s, 4 + a]
            hi[a] = so[s, 4 + a]
        t, ax, sg = _slab_hit(ol, dl, lo, hi, 4)
        if ax >= 0 and t < best_t:
            best_t = t
            best = -1 - first - s
            for m in range(4):
                normal[m] = sg * so[s, 8 + 4 * m + ax]
    for q in range(cr.shape[0]):
        t_in = -np.inf
        t_out = np.inf
        f_in = -1
        for f in range(cr[q, 0], cr[q, 1]):
            dn = 0.0
            on = -cpl[f, 4]
            for m in range(4):
                dn += cpl[f, m] * d[m]
                on += cpl[f, m] * o[m]
            if dn == 0.0:
                if on > 0.0:
                    t_in = np.inf
                    break
                continue
            t = -on / dn
            if dn < 0.0:
                if t > t_in:
                    t_in = t
                    f_in = f
            elif t < t_out:
                t_out = t
        if f_in >= 0 and 0.0 <= t_in <= t_out and t_in < best_t:
            best_t = t_in
            best = -1 - first - so.shape[0] - q
            for m in range(4):
                normal[m] = cpl[f_in, m]
    return best, best_t


@njit(cache=True)
def _ray_tet_meshes(static, o, d, best, best_t, normal):
    """Nearer hits of the tet meshes: the nearest outward face hit, within meshes whose bounds
    the ray meets: ``(hit, t)``."""
    tr = static.tet_ranges
    tmb = static.tet_mesh_bounds
    first = static.half_spaces.shape[0] + static.boxes.shape[0] + static.solids.shape[0]
    first += static.convex_ranges.shape[0]
    lo = np.empty(4)
    hi = np.empty(4)
    for q in range(tr.shape[0]):
        for a in range(4):
            lo[a] = tmb[q, a]
            hi[a] = tmb[q, 4 + a]
        inside = True
        for a in range(4):
            if o[a] < lo[a] or o[a] > hi[a]:
                inside = False
        if not inside:
            t, ax, sg = _slab_hit(o, d, lo, hi, 4)
            if ax < 0 or t >= best_t:
                continue
        t, hit = ray_tets(o, d, static.tets, static.tet_planes, static.tet_bary, tr[q, 0], tr[q, 1], best_t)
        if hit >= 0:
            best_t = t
            best = -1 - first - q
            for m in range(4):
                normal[m] = static.tet_planes[hit, m]
    return best, best_t


@njit(cache=True)
def raycast_kernel(bodies, static, o, d, max_t, use_world, normal):
    """Nearest hit of the ray ``o + t d`` (``d`` unit, ``0 <= t <= max_t``).

    Shapes that contain the origin are skipped, so a shot fired from inside a
    body (the shooter) passes out of it.

    Returns
    -------
    hit : int
        Body index, ``-1 - s`` for static world collider ``s``, or ``-(2**62)``
        for no hit.
    t : float
    normal : (4,) float64
        Written with the outward surface normal at the hit.
    """
    best, best_t = _ray_bodies(bodies, o, d, max_t, normal)
    if use_world:
        best, best_t = _ray_half_spaces_and_boxes(static, o, d, best, best_t, normal)
        best, best_t = _ray_solids(static, o, d, best, best_t, normal)
        best, best_t = _ray_tet_meshes(static, o, d, best, best_t, normal)
    return best, best_t


@njit(cache=True)
def _box_out_of_box(pc, ph, x, rot, h, out):
    """Shortest xyz move of the player box (centre ``pc``, half ``ph``, axis
    aligned) out of the box body; returns False when they do not overlap."""
    d = np.empty(4)
    for m in range(4):
        d[m] = x[m] - pc[m]
    best = np.inf
    u = np.empty(4)
    # Player's own face normals are the coordinate axes; w cannot be resolved
    # by an xyz move, but it still must overlap.
    for a in range(4):
        rr = ph[a]
        for k in range(4):
            rr += h[k] * abs(rot[a, k])
        o = rr - abs(d[a])
        if o <= 0.0:
            return False
        if a < 3 and o < best:
            best = o
            for m in range(3):
                out[m] = 0.0
            out[a] = -o if d[a] > 0.0 else o
    cand = np.empty((56, 4))
    nc = 0
    for k in range(4):
        for m in range(4):
            cand[nc, m] = rot[m, k]
        nc += 1
    # Player 2-face (axes other than p, q) x body edge k, and body 2-face x
    # player edge: the normal lies in the (p, q) plane of the respective frame.
    for pq in range(6):
        p = PLANE_I[pq]
        q = PLANE_J[pq]
        for k in range(4):
            for m in range(4):
                cand[nc, m] = 0.0
            cand[nc, p] = rot[q, k]
            cand[nc, q] = -rot[p, k]
            nc += 1
            for m in range(4):
                cand[nc, m] = rot[m, p] * rot[k, q] - rot[m, q] * rot[k, p]
            nc += 1
    for c in range(nc):
        ln = 0.0
        for m in range(4):
            u[m] = cand[c, m]
            ln += u[m] * u[m]
        if ln < 1e-8:
            continue
        ln = np.sqrt(ln)
        for m in range(4):
            u[m] /= ln
        rr = 0.0
        dist = 0.0
        for m in range(4):
            rr += ph[m] * abs(u[m])
            dist += u[m] * d[m]
        for k in range(4):
            t = 0.0
            for m in range(4):
                t += rot[m, k] * u[m]
            rr += h[k] * abs(t)
        o = rr - abs(dist)
        if o <= 0.0:
            return False
        l3 = np.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
        if l3 < 1e-6:
            continue
        move = o / l3
        if move < best:
            best = move
            sg = -1.0 if dist > 0.0 else 1.0
            for m in range(3):
                out[m] = sg * move * u[m] / l3
    return best < np.inf


@njit(cache=True)
def _box_out_of_sphere(pc, ph, c, r, out):
    """Shortest xyz move of the player box out of a hypersphere."""
    dw = abs(c[3] - pc[3]) - ph[3]
    if dw < 0.0:
        dw = 0.0
    if dw >= r:
        return False
    # The sphere's widest section inside the player's w slab.
    r3 = np.sqrt(r * r - dw * dw)
    q = np.empty(3)
    inside = True
    for a in range(3):
        v = c[a]
        if v > pc[a] + ph[a]:
            v = pc[a] + ph[a]
            inside = False
        elif v < pc[a] - ph[a]:
            v = pc[a] - ph[a]
            inside = False
        q[a] = v
    if not inside:
        d2 = 0.0
        for a in range(3):
            d2 += (c[a] - q[a]) ** 2
        if d2 >= r3 * r3:
            return False
        dist = np.sqrt(d2)
        for a in range(3):
            out[a] = -(c[a] - q[a]) / dist * (r3 - dist)
        return True
    ax = 0
    gap = np.inf
    for a in range(3):
        g = ph[a] - abs(c[a] - pc[a])
        if g < gap:
            gap = g
            ax = a
    for a in range(3):
        out[a] = 0.0
    out[ax] = -(gap + r3) if c[ax] >= pc[ax] else gap + r3
    return True


@njit(cache=True)
def box_push_out_kernel(bodies, center, half, passes, touched):
    """Push an upright 4D box out of every body it overlaps.

    Parameters
    ----------
    bodies : Bodies
    center, half : (4,) float64
        The box: axis-aligned, moved only in x, y and z (its w is fixed).
    passes : int
        Gauss-Seidel passes over the bodies (corners between two bodies need
        more than one).
    touched : (N,) bool
        Output: bodies the box overlapped.

    Returns
    -------
    (3,) float64
        Total xyz correction.
    """
    nb = bodies.count
    alive = bodies.alive
    shape = bodies.shape
    pos = bodies.position
    rot = bodies.rotation
    half_extents = bodies.half_extents
    pc = np.empty(4)
    ph = np.empty(4)
    for m in range(4):
        pc[m] = center[m]
        ph[m] = half[m]
    total = np.zeros(3)
    out = np.zeros(3)
    for i in range(nb):
        touched[i] = False
    for _ in range(passes):
        moved = False
        for i in range(nb):
            if not alive[i]:
                continue
            if shape[i] == SPHERE:
                hit = _box_out_of_sphere(pc, ph, pos[i], half_extents[i, 0], out)
            else:
                hit = _box_out_of_box(pc, ph, pos[i], rot[i], half_extents[i], out)
            if hit:
                touched[i] = True
                moved = True
                for a in range(3):
                    pc[a] += out[a]
                    total[a] += out[a]
        if not moved:
            break
    return total
