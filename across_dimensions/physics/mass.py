"""Mass and inertia of solid hyperspheres (4-balls) and 4D boxes.

Inertia in 4D acts on angular-velocity bivectors: the kinetic energy of a body
spinning in plane ``ij`` at rate ``w`` is ``w^2/2 * integral(x_i^2 + x_j^2) dm``.
Both shapes are symmetric under reflection of each body axis, so the operator is
diagonal in the body-frame plane basis (``xy xz yz xw yw zw``):

* 4-ball of radius ``r``: ``E[x_i^2] = r^2 / (n + 2) = r^2 / 6``, so every plane
  has ``I = m r^2 / 3``.
* box with side lengths ``s``: ``E[x_i^2] = s_i^2 / 12``, so plane ``ij`` has
  ``I = m (s_i^2 + s_j^2) / 12`` (isotropic only for a hypercube).
"""

from __future__ import annotations

import numpy as np

from .bivector import PLANE_I, PLANE_J


def hypersphere_volume(radius: float) -> float:
    """Hypervolume ``pi^2 r^4 / 2`` of a 4-ball."""
    return 0.5 * np.pi**2 * float(radius) ** 4


def box_volume(half_extents) -> float:
    """Hypervolume of a 4D box given its ``(4,)`` half extents."""
    return float(np.prod(2.0 * np.asarray(half_extents, dtype=np.float64)))


def hypersphere_inertia(mass: float, radius: float) -> np.ndarray:
    """Body-frame plane inertias of a solid 4-ball.

    Returns
    -------
    (6,) float64
        ``m r^2 / 3`` in every plane.
    """
    return np.full(6, float(mass) * float(radius) ** 2 / 3.0)


def box_inertia(mass: float, half_extents) -> np.ndarray:
    """Body-frame plane inertias of a solid 4D box.

    Parameters
    ----------
    mass : float
    half_extents : (4,) array_like

    Returns
    -------
    (6,) float64
        ``m (s_i^2 + s_j^2) / 12`` for plane ``ij`` with ``s = 2 * half_extents``.
    """
    s = 2.0 * np.asarray(half_extents, dtype=np.float64)
    return float(mass) * (s[PLANE_I] ** 2 + s[PLANE_J] ** 2) / 12.0
