"""Many poses at once: :func:`core.transform.pose` over arrays, bit for bit.

The game poses every spinning object, crystal and enemy every tick and every frame; one
:func:`~core.transform.pose` call each costs a dozen small numpy calls, which for a few
hundred entities is most of a frame. :func:`poses` builds them all in one pass with the
same float64 operations in the same order (the same ``cos``, ``sin``, the same 4x4 and 5x5
products, a plane left out where its angle is zero), so a pose made here equals the one
:func:`~core.transform.pose` makes to the last bit: the simulation's state, and so its
hash, does not depend on which path made it.
"""

from __future__ import annotations

import numpy as np

from ..core.transform import ANGLE_ORDER, PLANES

#: Column of each plane of :data:`~core.transform.PLANES` in an angles array, in composing order.
_ORDER = [(PLANES.index(p), *(("xyzw".index(p[0]), "xyzw".index(p[1])))) for p in ANGLE_ORDER]


def angle_rows(angles: list[dict]) -> np.ndarray:
    """``(n, 6) float64`` in :data:`~core.transform.PLANES` order from ``n`` mappings of plane to
    angle (radians or degrees; a plane left out is zero, which composes the same: no turn)."""
    out = np.zeros((len(angles), len(PLANES)))
    for i, a in enumerate(angles):
        for p, v in a.items():
            out[i, PLANES.index(p)] = v
    return out


def rotations(angles: np.ndarray) -> np.ndarray:
    """``(n, 4, 4) float64``: each row of ``angles (n, 6)`` composed as
    :func:`~core.transform.angles_to_rotation` composes it."""
    n = len(angles)
    r = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
    for col, i, j in _ORDER:
        a = angles[:, col]
        on = np.flatnonzero(a)
        if not len(on):
            continue
        c, s = np.cos(a[on]), np.sin(a[on])
        g = np.broadcast_to(np.eye(4), (len(on), 4, 4)).copy()
        g[:, i, i] = c
        g[:, j, j] = c
        g[:, i, j] = -s
        g[:, j, i] = s
        if len(on) == n:  # every row turns in this plane (things spinning alike): no gather, no scatter
            r = r @ g
        else:
            r[on] = r[on] @ g
    return r


def scalings(factors: np.ndarray) -> np.ndarray:
    """``(n, 5, 5) float64`` diagonal scales from ``factors (n, 4)``."""
    m = np.zeros((len(factors), 5, 5))
    idx = np.arange(4)
    m[:, idx, idx] = factors
    m[:, 4, 4] = 1.0
    return m


def translations(offsets: np.ndarray) -> np.ndarray:
    """``(n, 5, 5) float64`` translations by ``offsets (n, 4)``."""
    m = np.broadcast_to(np.eye(5), (len(offsets), 5, 5)).copy()
    m[:, :4, 4] = offsets
    return m


def poses(positions: np.ndarray, angles: np.ndarray, scales: np.ndarray) -> np.ndarray:
    """``(n, 5, 5) float64`` ``T @ R @ S`` for each row, as :func:`~core.transform.pose` makes it.

    Parameters
    ----------
    positions : (n, 4) float64
    angles : (n, 6) float64
        Radians, in :data:`~core.transform.PLANES` order (see :func:`angle_rows`).
    scales : (n, 4) float64
    """
    m = scalings(scales)
    m[:, :4, :4] = rotations(angles) @ m[:, :4, :4]
    m[:, :4, 4] = positions
    return m


__all__ = ["angle_rows", "poses", "rotations", "scalings", "translations"]
