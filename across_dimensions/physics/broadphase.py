"""Broadphase: the pairs of a tick that need a narrowphase test.

Bounding boxes grown by each body's speculative margin, then a sort-and-sweep
along the axis the bodies spread most along (bodies against bodies), plus a
direct test against the few static world colliders (half-spaces, world boxes,
and the level's solid objects as 4D boxes, convex solids or tet meshes).
Sleeping islands that a moving body's bounds overlap are woken here
(:func:`.islands.wake_touched`), so the pairs found are those of awake bodies.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .collide import SPHERE
from .islands import wake_touched
from .sorting import argsort_stable
from .state import DYNAMIC


@njit(cache=True)
def _support(i, shape, half, rot, d):
    """Half-width of body ``i`` along unit direction ``d``."""
    if shape[i] == SPHERE:
        return half[i, 0]
    s = 0.0
    for k in range(4):
        t = 0.0
        for m in range(4):
            t += rot[i, m, k] * d[m]
        s += half[i, k] * abs(t)
    return s


@njit(cache=True)
def _sweep(order, slo, shi, sdyn, ax, cand):
    """Pairs of sorted bounds that overlap on all four axes, at least one body dynamic.

    Parameters
    ----------
    order : (N,) int64
        Body of each sorted slot.
    slo, shi : (4, na) float64
        Bounds of the alive bodies in sweep order (sorted by ``slo[ax]``).
    sdyn : (na,) bool
        Whether each is dynamic.
    ax : int
        Sweep axis.
    cand : (P, 2) int64
        Output: ``(min, max)`` body pairs.

    Returns
    -------
    int
        Pairs written, or -1 if ``cand`` is too small.
    """
    na = slo.shape[1]
    sweep_lo = slo[ax]
    hits = np.empty(na, dtype=np.int64)
    nc = 0
    for oi in range(na):
        i = order[oi]
        top = shi[ax, oi]
        l0 = slo[0, oi]
        l1 = slo[1, oi]
        l2 = slo[2, oi]
        l3 = slo[3, oi]
        h0 = shi[0, oi]
        h1 = shi[1, oi]
        h2 = shi[2, oi]
        h3 = shi[3, oi]
        # Without a branch on the overlap (``|`` does not short-circuit, and
        # every slot is written, kept or not): about one candidate in fifteen
        # overlaps, and a branch that unpredictable made this loop four times
        # slower.
        nh = 0
        for oj in range(oi + 1, na):
            if sweep_lo[oj] > top:
                break
            apart = (slo[0, oj] > h0) | (l0 > shi[0, oj]) | (slo[1, oj] > h1) | (l1 > shi[1, oj])
            apart |= (slo[2, oj] > h2) | (l2 > shi[2, oj]) | (slo[3, oj] > h3) | (l3 > shi[3, oj])
            hits[nh] = oj
            nh += 0 if apart else 1
        dyn = sdyn[oi]
        for q in range(nh):
            oj = hits[q]
            if not (dyn or sdyn[oj]):
                continue
            if nc == cand.shape[0]:
                return -1
            j = order[oj]
            cand[nc, 0] = min(i, j)
            cand[nc, 1] = max(i, j)
            nc += 1
    return nc


@njit(cache=True)
def _bounds(bodies, h, base_margin, lo, hi, marg):
    """Each alive body's margin ``base + h * (speed)`` into ``marg`` and its grown bounds into ``lo``, ``hi``."""
    alive = bodies.alive
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    vel = bodies.velocity
    omg = bodies.angular_velocity
    ext = np.empty(4)
    for i in range(bodies.count):
        if not alive[i]:
            continue
        sp = 0.0
        for m in range(4):
            sp += vel[i, m] * vel[i, m]
        w2 = 0.0
        for k in range(6):
            w2 += omg[i, k] * omg[i, k]
        if shape[i] == SPHERE:
            for m in range(4):
                ext[m] = half[i, 0]
            rad = half[i, 0]
        else:
            rad = 0.0
            for m in range(4):
                e = 0.0
                for k in range(4):
                    e += abs(rot[i, m, k]) * half[i, k]
                ext[m] = e
                rad += half[i, m] * half[i, m]
            rad = np.sqrt(rad)
        marg[i] = base_margin + h * (np.sqrt(sp) + np.sqrt(w2) * rad)
        for m in range(4):
            lo[i, m] = pos[i, m] - ext[m] - marg[i]
            hi[i, m] = pos[i, m] + ext[m] + marg[i]


@njit(cache=True)
def _sweep_axis(bodies):
    """The axis the alive bodies spread most along (the first on ties).

    A pile is taller than it is wide: fewer bodies overlap each other's
    interval along its longest axis. The pairs found are the same whatever the
    axis (their order does not matter: the narrowphase sorts them by key,
    islands take the smallest index as root).
    """
    nb = bodies.count
    alive = bodies.alive
    pos = bodies.position
    ax = 0
    best = -1.0
    for m in range(4):
        a_lo = np.inf
        a_hi = -np.inf
        for i in range(nb):
            if alive[i]:
                a_lo = min(a_lo, pos[i, m])
                a_hi = max(a_hi, pos[i, m])
        if a_hi - a_lo > best:
            best = a_hi - a_lo
            ax = m
    return ax


@njit(cache=True)
def _overlapping(bodies, lo, hi):
    """Body pairs ``(min, max)`` whose bounds overlap, at least one dynamic: ``(pairs (P, 2), count)``."""
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    ax = _sweep_axis(bodies)
    key = np.empty(nb)
    for i in range(nb):
        key[i] = lo[i, ax] if alive[i] else np.inf
    order = argsort_stable(key)
    # The bounds of the alive bodies (sorted first: the others have an infinite
    # key) copied in sweep order, one array per axis: the sweep then reads
    # memory in order instead of jumping between bodies (about 200 bodies share
    # an interval in a pile of 1000, so this loop is the broadphase's cost).
    na = 0
    while na < nb and alive[order[na]]:
        na += 1
    slo = np.empty((4, na))
    shi = np.empty((4, na))
    sdyn = np.empty(na, dtype=np.bool_)
    for o in range(na):
        i = order[o]
        for m in range(4):
            slo[m, o] = lo[i, m]
            shi[m, o] = hi[i, m]
        sdyn[o] = kind[i] == DYNAMIC
    # A pile has about ten neighbours per body; grown below when that is not enough.
    cand = np.empty((max(64, 16 * nb), 2), dtype=np.int64)
    nc = _sweep(order, slo, shi, sdyn, ax, cand)
    while nc < 0:
        # A buffer that grows inside the sweep would be reference-counted on
        # every step of it: grow it here and sweep again (rare).
        cand = np.empty((2 * cand.shape[0], 2), dtype=np.int64)
        nc = _sweep(order, slo, shi, sdyn, ax, cand)
    return cand, nc


@njit(inline="always")
def _add(pairs, n, i, b):
    """Append pair ``(i, b)`` when it fits; the count grows either way."""
    if n < pairs.shape[0]:
        pairs[n, 0] = i
        pairs[n, 1] = b
    return n + 1


@njit(inline="always")
def _meets(lo, hi, i, blo, bhi, s, dims):
    """Whether body ``i``'s bounds meet box ``s`` of ``[blo, bhi]`` on the first ``dims`` axes."""
    for m in range(dims):
        if lo[i, m] > bhi[s, m] or hi[i, m] < blo[s, m]:
            return False
    return True


@njit(cache=True)
def _static_pairs(bodies, static, lo, hi, marg, act, pairs, n):
    """Append the (body, static collider) pairs of the active bodies; returns the new count."""
    shape = bodies.shape
    half = bodies.half_extents
    pos = bodies.position
    rot = bodies.rotation
    hs = static.half_spaces
    wb = static.boxes
    so = static.solids
    cb = static.convex_bounds
    tb = static.tet_mesh_bounds
    nh = hs.shape[0]
    nw = wb.shape[0]
    ns = so.shape[0]
    nq = cb.shape[0]
    # Every box collider's bounds, in the order of the static colliders after
    # the half-spaces: world boxes (x, y, z only), solids, convex solids, tet meshes.
    nbox = nw + ns + nq + tb.shape[0]
    blo = np.empty((nbox, 4))
    bhi = np.empty((nbox, 4))
    for s in range(nw):
        for m in range(3):
            blo[s, m] = wb[s, m] - wb[s, 3 + m]
            bhi[s, m] = wb[s, m] + wb[s, 3 + m]
    for s in range(ns):
        # The solids' own bounds along each axis (they do not move within a tick).
        for m in range(4):
            e = 0.0
            for k in range(4):
                e += abs(so[s, 8 + 4 * m + k]) * so[s, 4 + k]
            blo[nw + s, m] = so[s, m] - e
            bhi[nw + s, m] = so[s, m] + e
    for q in range(nq):
        for m in range(4):
            blo[nw + ns + q, m] = cb[q, m]
            bhi[nw + ns + q, m] = cb[q, 4 + m]
    for q in range(tb.shape[0]):
        for m in range(4):
            blo[nw + ns + nq + q, m] = tb[q, m]
            bhi[nw + ns + nq + q, m] = tb[q, 4 + m]
    d = np.empty(4)
    for i in range(bodies.count):
        if not act[i]:
            continue
        for s in range(nh):
            for m in range(4):
                d[m] = hs[s, m]
            dist = -hs[s, 4]
            for m in range(4):
                dist += d[m] * pos[i, m]
            if dist - _support(i, shape, half, rot, d) <= marg[i]:
                n = _add(pairs, n, i, -1 - s)
        for s in range(nbox):
            if _meets(lo, hi, i, blo, bhi, s, 3 if s < nw else 4):
                n = _add(pairs, n, i, -1 - nh - s)
    return n


@njit(cache=True)
def find_pairs(bodies, static, h, base_margin, pairs, marg):
    """Broadphase: candidate pairs that need a narrowphase test.

    Parameters
    ----------
    bodies : Bodies
        Sleeping islands touched by moving bodies are woken.
    static : StaticWorld
    h : float
        Tick length: the margin covers the motion of one tick.
    base_margin : float
    pairs : (P, 2) int64
        Output: body a and body b (``b >= 0``) or ``-1 - s`` for static world
        collider ``s`` (half-spaces first, then world boxes, solid boxes, convex solids,
        tet meshes).
    marg : (N,) float64
        Output: per-body speculative margin ``base + h * (speed)``.

    Returns
    -------
    int
        Number of pairs, or ``-(needed)`` if ``pairs`` is too small.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    lo = np.empty((nb, 4))
    hi = np.empty((nb, 4))
    _bounds(bodies, h, base_margin, lo, hi, marg)
    # Overlapping pairs with at least one dynamic body; sleeping islands
    # touched by moving bodies wake, then the pairs with an awake body stay.
    cand, nc = _overlapping(bodies, lo, hi)
    wake_touched(bodies, cand, nc)
    act = np.zeros(nb, dtype=np.bool_)
    for i in range(nb):
        act[i] = alive[i] and kind[i] == DYNAMIC and awake[i]
    n = 0
    for p in range(nc):
        i = cand[p, 0]
        j = cand[p, 1]
        if act[i] or act[j]:
            n = _add(pairs, n, i, j)
    n = _static_pairs(bodies, static, lo, hi, marg, act, pairs, n)
    if n > pairs.shape[0]:
        return -n
    return n
