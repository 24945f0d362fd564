"""Contact events: one record per touching pair per tick.

A tick's contacts are grouped into manifolds (same pair key, in key order); the
impulse is the total normal impulse of the manifold over the tick's substeps.
Whether a touch is new (``began``) is decided against the previous tick's keys
by the world.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from across_dimensions.core._jit import njit


class ContactEvent(NamedTuple):
    """A touch between two bodies, or a body and the static world, in one tick.

    Attributes
    ----------
    a : int
        Body id.
    b : int or str
        Other body id, or ``"world"`` for the ground, half-spaces and world boxes.
    point : (4,) float64
        Impulse-weighted contact point (world coordinates).
    normal : (4,) float64
        Unit normal from ``a`` towards ``b``.
    impulse : float
        Total normal impulse over the tick (N s); 0 for a touch without push.
    began : bool
        True when the pair did not touch in the previous tick.
    """

    a: int
    b: int | str
    point: np.ndarray
    normal: np.ndarray
    impulse: float
    began: bool


@njit(cache=True)
def manifold_events(nc, contacts, touch_tol):
    """Summarise the tick's contacts per pair; pairs not yet touching are dropped.

    Returns
    -------
    keys : (E,) int64
    ab : (E, 2) int64
    pts, nrm : (E, 4) float64
    imp : (E,) float64
    """
    key = contacts.key
    cp = contacts.point
    cd = contacts.depth
    imp_pt = contacts.normal_impulse
    body_a = contacts.body_a
    body_b = contacts.body_b
    normal = contacts.normal
    keys = np.empty(nc, dtype=np.int64)
    ab = np.empty((nc, 2), dtype=np.int64)
    pts = np.zeros((nc, 4))
    nrm = np.empty((nc, 4))
    imp = np.zeros(nc)
    ne = 0
    c = 0
    while c < nc:
        e = c
        deepest = -np.inf
        tot = 0.0
        for m in range(4):
            pts[ne, m] = 0.0
        while e < nc and key[e] == key[c]:
            deepest = max(deepest, cd[e])
            tot += imp_pt[e]
            e += 1
        if deepest >= -touch_tol or tot > 0.0:
            for q in range(c, e):
                # Weight by impulse; a resting-free touch falls back to the mean.
                wgt = imp_pt[q] / tot if tot > 0.0 else 1.0 / (e - c)
                for m in range(4):
                    pts[ne, m] += wgt * cp[q, m]
            keys[ne] = key[c]
            ab[ne, 0] = body_a[c]
            ab[ne, 1] = body_b[c]
            for m in range(4):
                nrm[ne, m] = normal[c, m]
            imp[ne] = tot
            ne += 1
        c = e
    return keys[:ne].copy(), ab[:ne].copy(), pts[:ne].copy(), nrm[:ne].copy(), imp[:ne].copy()


@njit(cache=True)
def touching_keys(nc, contacts, touch_tol, out):
    """Write the keys of the pairs that touch this tick into ``out``; return the count.

    This is all the bookkeeping a tick needs for ``began`` flags; the full
    events are only built (by :func:`manifold_events`) when someone reads them.
    """
    key = contacts.key
    cd = contacts.depth
    imp_pt = contacts.normal_impulse
    n = 0
    c = 0
    while c < nc:
        e = c
        deepest = -np.inf
        tot = 0.0
        while e < nc and key[e] == key[c]:
            deepest = max(deepest, cd[e])
            tot += imp_pt[e]
            e += 1
        if deepest >= -touch_tol or tot > 0.0:
            out[n] = key[c]
            n += 1
        c = e
    return n
