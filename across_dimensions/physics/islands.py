"""Islands: which sleeping bodies a moving one wakes, and which groups fall asleep.

An island is a group of dynamic bodies whose (margin-expanded) bounding boxes
overlap, joined by union-find over the broadphase pairs with the smallest body
index as root, so island ids do not depend on the order pairs are found in.
A sleeping body keeps its island's root as ``Bodies.island``: a touch wakes the
whole island at once (:func:`wake_touched`), and an island sleeps only when all
its bodies have been calm for ``sleep_time`` (:func:`update_sleep`).
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .state import DYNAMIC, KINEMATIC


@njit(cache=True)
def moving(i, kind, awake, vel, omg):
    """Whether body ``i`` can disturb others: awake dynamic or moving kinematic."""
    if kind[i] == DYNAMIC:
        return awake[i]
    if kind[i] == KINEMATIC:
        for m in range(4):
            if vel[i, m] != 0.0:
                return True
        for k in range(6):
            if omg[i, k] != 0.0:
                return True
    return False


@njit(cache=True)
def _wake_island(j, bodies):
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    timer = bodies.sleep_timer
    island = bodies.island
    isl = island[j]
    for i in range(nb):
        if alive[i] and kind[i] == DYNAMIC and not awake[i] and island[i] == isl:
            awake[i] = True
            timer[i] = 0.0


@njit(cache=True)
def wake_touched(bodies, cand, nc):
    """Wake the sleeping islands that a moving body's bounds overlap, until nothing changes.

    Parameters
    ----------
    bodies : Bodies
        ``awake`` and ``sleep_timer`` updated in place.
    cand : (P, 2) int64
        Body pairs ``(min, max)`` whose bounds overlap (the first ``nc``).
    nc : int
    """
    kind = bodies.kind
    awake = bodies.awake
    vel = bodies.velocity
    omg = bodies.angular_velocity
    changed = True
    while changed:
        changed = False
        for p in range(nc):
            i = cand[p, 0]
            j = cand[p, 1]
            if kind[j] == DYNAMIC and not awake[j] and moving(i, kind, awake, vel, omg):
                _wake_island(j, bodies)
                changed = True
            elif kind[i] == DYNAMIC and not awake[i] and moving(j, kind, awake, vel, omg):
                _wake_island(i, bodies)
                changed = True


@njit(cache=True)
def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(cache=True)
def _join(bodies, npairs, pairs, parent, stir):
    """Union-find over the body pairs into ``parent``; ``stir`` marks bodies a moving kinematic one touches."""
    kind = bodies.kind
    awake = bodies.awake
    vel = bodies.velocity
    omg = bodies.angular_velocity
    for c in range(npairs):
        a = pairs[c, 0]
        b = pairs[c, 1]
        if b < 0:
            continue
        if kind[a] == DYNAMIC and kind[b] == DYNAMIC:
            ra = _find(parent, a)
            rb = _find(parent, b)
            if ra != rb:
                # Smaller index as root keeps island ids independent of order.
                if ra < rb:
                    parent[rb] = ra
                else:
                    parent[ra] = rb
        elif kind[a] == KINEMATIC and moving(a, kind, awake, vel, omg):
            stir[b] = True
        elif kind[b] == KINEMATIC and moving(b, kind, awake, vel, omg):
            stir[a] = True


@njit(cache=True)
def update_sleep(bodies, npairs, pairs, prm):
    """Islands by union-find over the broadphase pairs; whole islands sleep.

    A body is calm when its speed and spin stay under the thresholds; an island
    sleeps once all its bodies have been calm for ``sleep_time``. Sleeping
    bodies keep the island id so a touch wakes all of them together.

    Islands join bodies whose (margin-expanded) boxes overlap, the same test
    that wakes sleepers: joining only bodies in actual contact would let two
    neighbours fall asleep at different times and wake each other forever.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    vel = bodies.velocity
    omg = bodies.angular_velocity
    timer = bodies.sleep_timer
    island = bodies.island
    h = prm.tick_dt
    parent = np.arange(nb)
    stir = np.zeros(nb, dtype=np.bool_)
    _join(bodies, npairs, pairs, parent, stir)
    lin2 = prm.sleep_linear**2
    ang2 = prm.sleep_angular**2
    mint = np.full(nb, np.inf)
    for i in range(nb):
        if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
            continue
        v2 = 0.0
        for m in range(4):
            v2 += vel[i, m] * vel[i, m]
        w2 = 0.0
        for k in range(6):
            w2 += omg[i, k] * omg[i, k]
        if v2 < lin2 and w2 < ang2 and not stir[i]:
            timer[i] += h
        else:
            timer[i] = 0.0
        r = _find(parent, i)
        if timer[i] < mint[r]:
            mint[r] = timer[i]
    if prm.allow_sleep == 0.0:
        return
    for i in range(nb):
        if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
            continue
        r = _find(parent, i)
        if mint[r] >= prm.sleep_time:
            awake[i] = False
            island[i] = r
            for m in range(4):
                vel[i, m] = 0.0
            for k in range(6):
                omg[i, k] = 0.0
