"""Contact events: one record per touching pair per tick.

Each substep's contacts are grouped into manifolds (same pair key) and merged
into the tick's list in key order: impulses add up over the substeps, the point
and normal come from the latest substep that saw the pair. Whether a touch is
new (``began``) is decided against the previous tick's keys by the world.
"""

from __future__ import annotations

from typing import NamedTuple, Union

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
    b: Union[int, str]
    point: np.ndarray
    normal: np.ndarray
    impulse: float
    began: bool


@njit(cache=True)
def manifold_events(nc, ci, cp, cn, cd, clam, touch_tol):
    """Summarise this substep's contacts per pair; pairs not yet touching are dropped.

    Returns
    -------
    keys : (E,) int64
    ab : (E, 2) int64
    pts, nrm : (E, 4) float64
    imp : (E,) float64
    """
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
        while e < nc and ci[e, 2] == ci[c, 2]:
            deepest = max(deepest, cd[e])
            tot += clam[e, 0]
            e += 1
        if deepest >= -touch_tol or tot > 0.0:
            for q in range(c, e):
                # Weight by impulse; a resting-free touch falls back to the mean.
                wgt = clam[q, 0] / tot if tot > 0.0 else 1.0 / (e - c)
                for m in range(4):
                    pts[ne, m] += wgt * cp[q, m]
            keys[ne] = ci[c, 2]
            ab[ne, 0] = ci[c, 0]
            ab[ne, 1] = ci[c, 1]
            for m in range(4):
                nrm[ne, m] = cn[c, m]
            imp[ne] = tot
            ne += 1
        c = e
    return keys[:ne].copy(), ab[:ne].copy(), pts[:ne].copy(), nrm[:ne].copy(), imp[:ne].copy()


@njit(cache=True)
def merge_events(k1, ab1, p1, n1, i1, k2, ab2, p2, n2, i2):
    """Merge two key-sorted event lists; on equal keys add impulses, keep the later pose."""
    n = k1.shape[0] + k2.shape[0]
    k = np.empty(n, dtype=np.int64)
    ab = np.empty((n, 2), dtype=np.int64)
    p = np.empty((n, 4))
    nr = np.empty((n, 4))
    im = np.empty(n)
    i = 0
    j = 0
    o = 0
    while i < k1.shape[0] or j < k2.shape[0]:
        if j >= k2.shape[0] or (i < k1.shape[0] and k1[i] < k2[j]):
            k[o] = k1[i]
            ab[o] = ab1[i]
            p[o] = p1[i]
            nr[o] = n1[i]
            im[o] = i1[i]
            i += 1
        elif i >= k1.shape[0] or k2[j] < k1[i]:
            k[o] = k2[j]
            ab[o] = ab2[j]
            p[o] = p2[j]
            nr[o] = n2[j]
            im[o] = i2[j]
            j += 1
        else:
            k[o] = k2[j]
            ab[o] = ab2[j]
            p[o] = p2[j]
            nr[o] = n2[j]
            im[o] = i1[i] + i2[j]
            i += 1
            j += 1
        o += 1
    return k[:o].copy(), ab[:o].copy(), p[:o].copy(), nr[:o].copy(), im[:o].copy()
