"""Numba kernels for 4D rotational kinematics on bivectors.

Bivectors are ``(6,) float64`` in the plane order of
:data:`across_dimensions.core.transform.PLANES` (``xy xz yz xw yw zw``) and map
to skew matrices exactly as :func:`~across_dimensions.core.transform.skew` does
(entry ``[j, i] = omega_ij``), so a body spinning with ``omega`` moves its points
with velocity ``v = skew(omega) @ r`` and turns by
:func:`~across_dimensions.core.transform.bivector_rotation`.

The duality that the solver relies on: for a force ``f`` at offset ``r`` the
torque bivector is ``r ^ f`` (:func:`wedge`) and its power is
``dot(omega, r ^ f) == dot(skew(omega) @ r, f)``. Inertia is a symmetric
operator on bivectors; boxes and balls are diagonal in their body frame, and a
rotation ``R`` acts on bivectors through its second compound matrix
(:func:`compound`), which is orthogonal.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit
from across_dimensions.core.transform import PLANE_I, PLANE_J, expm_skew

__all__ = [
    "PLANE_I",
    "PLANE_J",
    "compound",
    "expm_skew",
    "gram_schmidt",
    "mat6_vec",
    "rotate_by",
    "spin_velocity",
    "tangent_basis",
    "tangent_frame",
    "wedge",
    "world_inverse_inertia",
]


@njit(cache=True)
def wedge(r, p, out):
    """Write the bivector ``r ^ p`` (components ``r_i p_j - r_j p_i``).

    Parameters
    ----------
    r, p : (4,) float64
    out : (6,) float64
        Overwritten.
    """
    out[0] = r[0] * p[1] - r[1] * p[0]
    out[1] = r[0] * p[2] - r[2] * p[0]
    out[2] = r[1] * p[2] - r[2] * p[1]
    out[3] = r[0] * p[3] - r[3] * p[0]
    out[4] = r[1] * p[3] - r[3] * p[1]
    out[5] = r[2] * p[3] - r[3] * p[2]


@njit(cache=True)
def spin_velocity(w, r, out):
    """Write ``skew(w) @ r``: the velocity of offset ``r`` on a body spinning at ``w``.

    Parameters
    ----------
    w : (6,) float64
    r : (4,) float64
    out : (4,) float64
        Overwritten.
    """
    out[0] = -w[0] * r[1] - w[1] * r[2] - w[3] * r[3]
    out[1] = w[0] * r[0] - w[2] * r[2] - w[4] * r[3]
    out[2] = w[1] * r[0] + w[2] * r[1] - w[5] * r[3]
    out[3] = w[3] * r[0] + w[4] * r[1] + w[5] * r[2]


@njit(cache=True)
def compound(rot, out):
    """Second compound matrix: how ``rot`` acts on bivectors.

    ``out @ (a ^ b) == (rot @ a) ^ (rot @ b)``; for a rotation it is orthogonal.

    Parameters
    ----------
    rot : (4, 4) float64
    out : (6, 6) float64
        Overwritten.
    """
    for k in range(6):
        i = PLANE_I[k]
        j = PLANE_J[k]
        for m in range(6):
            a = PLANE_I[m]
            b = PLANE_J[m]
            out[k, m] = rot[i, a] * rot[j, b] - rot[i, b] * rot[j, a]


@njit(cache=True)
def world_inverse_inertia(rot, inv_inertia_body, out):
    """World-frame inverse inertia ``M diag(I_body^-1) M^T`` with ``M = compound(rot)``.

    Parameters
    ----------
    rot : (4, 4) float64
    inv_inertia_body : (6,) float64
        Diagonal of the inverse inertia in the body frame (zero for infinite).
    out : (6, 6) float64
        Overwritten.
    """
    iso = True
    for k in range(1, 6):
        if inv_inertia_body[k] != inv_inertia_body[0]:
            iso = False
    if iso:
        # Balls and hypercubes: the operator is a multiple of the identity and
        # commutes with every rotation, so skip the compound matrix (and its
        # rounding) altogether.
        for k in range(6):
            for m in range(6):
                out[k, m] = 0.0
            out[k, k] = inv_inertia_body[0]
        return
    c = np.empty((6, 6))
    compound(rot, c)
    for k in range(6):
        for m in range(6):
            s = 0.0
            for j in range(6):
                s += c[k, j] * inv_inertia_body[j] * c[m, j]
            out[k, m] = s


@njit(cache=True)
def mat6_vec(m, v, out):
    """``out = m @ v`` for ``(6, 6)`` and ``(6,)`` float64."""
    for k in range(6):
        s = 0.0
        for j in range(6):
            s += m[k, j] * v[j]
        out[k] = s


@njit(cache=True)
def rotate_by(w, h, rot, wk, orthonormalise=True):
    """Advance ``rot`` in place to ``expm(h * skew(w)) @ rot``, re-orthonormalised.

    The update is in the world frame because ``w`` is a world-frame angular
    velocity. Modified Gram-Schmidt on the columns removes the slow drift of
    repeated products so that ``rot`` stays a rotation for hours of play.

    Parameters
    ----------
    w : (6,) float64
    h : float
    rot : (4, 4) float64
        Updated in place.
    wk : (5, 4, 4) float64
        Scratch.
    orthonormalise : bool
        False skips the Gram-Schmidt step (it costs as much as the rest): the
        product of two rotations drifts from one by rounding only, so once a
        tick is enough.
    """
    e = wk[3]
    tmp = wk[4]
    expm_skew(w, h, e, wk)
    for i in range(4):
        for j in range(4):
            s = 0.0
            for k in range(4):
                s += e[i, k] * rot[k, j]
            tmp[i, j] = s
    if orthonormalise:
        gram_schmidt(tmp)
    for i in range(4):
        for j in range(4):
            rot[i, j] = tmp[i, j]


@njit(cache=True)
def gram_schmidt(m):
    """Orthonormalise the columns of a ``(4, 4)`` float64 matrix in place."""
    for j in range(4):
        for k in range(j):
            d = 0.0
            for i in range(4):
                d += m[i, j] * m[i, k]
            for i in range(4):
                m[i, j] -= d * m[i, k]
        n = 0.0
        for i in range(4):
            n += m[i, j] * m[i, j]
        n = 1.0 / np.sqrt(n)
        for i in range(4):
            m[i, j] *= n


@njit(cache=True)
def tangent_basis(n, out):
    """Three unit vectors completing the unit normal ``n`` to an orthonormal frame.

    Gram-Schmidt of the coordinate axes least aligned with ``n`` (a fixed,
    deterministic choice: friction is isotropic so any basis gives the same
    physics).

    Parameters
    ----------
    n : (4,) float64
        Unit vector.
    out : (3, 4) float64
        Overwritten.
    """
    # The three axes with the smallest |n_k| (ties to the lower index), without
    # allocating: this runs for every contact every tick.
    big = 0
    for k in range(1, 4):
        if abs(n[k]) > abs(n[big]):
            big = k
    order = (0, 1, 2) if big == 3 else ((0, 1, 3) if big == 2 else ((0, 2, 3) if big == 1 else (1, 2, 3)))
    for t in range(3):
        ax = order[t]
        for i in range(4):
            out[t, i] = -n[ax] * n[i]
        out[t, ax] += 1.0
        for s in range(t):
            d = 0.0
            for i in range(4):
                d += out[t, i] * out[s, i]
            for i in range(4):
                out[t, i] -= d * out[s, i]
        q = 0.0
        for i in range(4):
            q += out[t, i] * out[t, i]
        q = 1.0 / np.sqrt(q)
        for i in range(4):
            out[t, i] *= q


@njit(inline="always")
def tangent_frame(f):
    """Complete row 0 of ``f`` (a unit normal) with rows 1-3 as :func:`tangent_basis` does.

    The same arithmetic on one ``(4, 4)`` float64 array read by index: the
    solver calls this for every contact, and the row views ``f[0]``, ``f[1:]``
    would each cost an atomic reference-count update.
    """
    big = 0
    for k in range(1, 4):
        if abs(f[0, k]) > abs(f[0, big]):
            big = k
    for t in range(3):
        # The three axes with the smallest |n_k| (ties to the lower index).
        ax = t if t < big else t + 1
        for i in range(4):
            f[t + 1, i] = -f[0, ax] * f[0, i]
        f[t + 1, ax] += 1.0
        for s in range(t):
            d = 0.0
            for i in range(4):
                d += f[t + 1, i] * f[s + 1, i]
            for i in range(4):
                f[t + 1, i] -= d * f[s + 1, i]
        q = 0.0
        for i in range(4):
            q += f[t + 1, i] * f[t + 1, i]
        q = 1.0 / np.sqrt(q)
        for i in range(4):
            f[t + 1, i] *= q
