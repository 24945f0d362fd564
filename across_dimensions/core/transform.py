"""4D affine transforms as 5x5 homogeneous matrices.

Conventions (axes, handedness, units, plane names) are in ``CONVENTIONS.md`` at
the repository's top level; what matters most here:

* Points are row arrays ``(..., 4)`` batched over leading axes.
* Matrices act on column vectors: ``p' = M @ [p, 1]``. :func:`apply` does this for
  row arrays, so ``apply(a @ b, p) == apply(a, apply(b, p))``.
* Rotation planes are named ``xy xz yz xw yw zw`` (the paper's t, u, v are xw, yw,
  zw). A rotation in plane ``ij`` by a positive angle turns axis i towards axis j.
* A pose's six angles compose in the fixed order of :data:`ANGLE_ORDER`::

      R = R_xw @ R_xz @ R_xy @ R_yw @ R_yz @ R_zw

  which is the order in which :func:`rotation_to_angles` peels them off again, so
  every rotation has angles and the round trip is exact.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ._jit import njit

AXES = "xyzw"
PLANES = ("xy", "xz", "yz", "xw", "yw", "zw")
#: First and second axis of each plane, in PLANES order (for compiled code).
PLANE_I = np.array([0, 0, 1, 0, 1, 2], dtype=np.int64)
PLANE_J = np.array([1, 2, 2, 3, 3, 3], dtype=np.int64)
#: Order in which pose angles compose (leftmost applied last to points).
ANGLE_ORDER = ("xw", "xz", "xy", "yw", "yz", "zw")


def _plane_axes(plane: str) -> tuple[int, int]:
    if plane not in PLANES:
        # Accept "wx" for "xw" etc. with the angle's sign left to the caller.
        raise ValueError(f"unknown rotation plane {plane!r}; expected one of {', '.join(PLANES)}")
    return AXES.index(plane[0]), AXES.index(plane[1])


def rotation4(plane: str, angle: float) -> np.ndarray:
    """4x4 rotation in one coordinate plane.

    Parameters
    ----------
    plane : str
        One of ``xy xz yz xw yw zw``.
    angle : float
        Radians; positive turns the plane's first axis towards its second.

    Returns
    -------
    (4, 4) float64
    """
    i, j = _plane_axes(plane)
    c, s = np.cos(angle), np.sin(angle)
    r = np.eye(4)
    r[i, i] = c
    r[j, j] = c
    r[i, j] = -s
    r[j, i] = s
    return r


def identity() -> np.ndarray:
    """The 5x5 identity transform, ``(5, 5) float64``."""
    return np.eye(5)


def translation(offset) -> np.ndarray:
    """5x5 translation by ``offset`` ``(4,)``."""
    m = np.eye(5)
    m[:4, 4] = np.asarray(offset, dtype=np.float64).reshape(4)
    return m


def scaling(factors) -> np.ndarray:
    """5x5 scale; ``factors`` is a scalar or ``(4,)``. Scaling w is hyper-depth."""
    f = np.broadcast_to(np.asarray(factors, dtype=np.float64), (4,))
    return np.diag(np.append(f, 1.0))


def rotation(plane: str, angle: float) -> np.ndarray:
    """5x5 rotation in one plane (see :func:`rotation4`)."""
    m = np.eye(5)
    m[:4, :4] = rotation4(plane, angle)
    return m


def angles_to_rotation(angles: Mapping[str, float] | None = None, **kw: float) -> np.ndarray:
    """Compose a 4x4 rotation from up to six plane angles (radians).

    Parameters
    ----------
    angles : mapping of plane name to angle, optional
        Missing planes are zero. Keyword arguments (``xw=0.3``) add to it.

    Returns
    -------
    (4, 4) float64
        ``R_xw @ R_xz @ R_xy @ R_yw @ R_yz @ R_zw``.
    """
    a = dict(angles or {})
    a.update(kw)
    for k in a:
        _plane_axes(k)
    r = np.eye(4)
    for plane in ANGLE_ORDER:
        if a.get(plane, 0.0):
            r = r @ rotation4(plane, a[plane])
    return r


def rotation_to_angles(r) -> dict[str, float]:
    """Six plane angles of a rotation, inverse of :func:`angles_to_rotation`.

    Givens eliminations zero the sub-diagonal column by column; the rotation that
    cleared each entry is one factor of the product, so
    ``angles_to_rotation(rotation_to_angles(r))`` equals ``r`` to rounding.

    Parameters
    ----------
    r : (4, 4) array_like
        A proper rotation (determinant +1).

    Returns
    -------
    dict of str to float
    """
    m = np.array(r, dtype=np.float64)
    out: dict[str, float] = {}
    # (pivot row, row to clear, column); the plane is (pivot, cleared).
    for i, j, k in ((0, 3, 0), (0, 2, 0), (0, 1, 0), (1, 3, 1), (1, 2, 1), (2, 3, 2)):
        theta = np.arctan2(m[j, k], m[i, k])
        # Left-multiplying by R_ij(-theta) zeroes m[j, k] and leaves m[i, k] >= 0.
        g = np.eye(4)
        c, s = np.cos(theta), np.sin(theta)
        g[i, i] = c
        g[j, j] = c
        g[i, j] = s
        g[j, i] = -s
        m = g @ m
        out[AXES[i] + AXES[j]] = float(theta)
    return {p: out[p] for p in PLANES}


def pose(position=(0.0, 0.0, 0.0, 0.0), angles: Mapping[str, float] | None = None, scale=1.0) -> np.ndarray:
    """Build ``T @ R @ S``: scale, then rotate, then translate.

    Parameters
    ----------
    position : (4,) array_like
    angles : mapping of plane name to radians, optional
    scale : float or (4,) array_like
        Per-axis scale in the object's own frame; ``scale[3]`` is hyper-depth.

    Returns
    -------
    (5, 5) float64
    """
    m = scaling(scale)
    m[:4, :4] = angles_to_rotation(angles) @ m[:4, :4]
    m[:4, 4] = np.asarray(position, dtype=np.float64).reshape(4)
    return m


def decompose(m) -> tuple[np.ndarray, dict[str, float], np.ndarray]:
    """Split a transform made by :func:`pose` back into position, angles and scale.

    Only valid for ``T @ R @ S`` with positive scales (no shear).

    Returns
    -------
    position : (4,) float64
    angles : dict of str to float
    scale : (4,) float64
    """
    m = np.asarray(m, dtype=np.float64)
    linear = m[:4, :4]
    scale = np.linalg.norm(linear, axis=0)
    rot = linear / scale
    return m[:4, 4].copy(), rotation_to_angles(rot), scale


def compose(*transforms) -> np.ndarray:
    """Product ``transforms[0] @ transforms[1] @ ...``: the last one acts first."""
    out = np.eye(5)
    for t in transforms:
        out = out @ np.asarray(t, dtype=np.float64)
    return out


def inverse(m) -> np.ndarray:
    """Inverse of an affine 5x5 transform (exact for the linear part's inverse)."""
    m = np.asarray(m, dtype=np.float64)
    out = np.eye(5)
    if m[:4, :4].tobytes() == _EYE4_BYTES:
        # A pure translation (a plain slice's pose, every frame): the bits of the general path
        # below, whose (-I) @ t is 0.0 - t_i (the other terms add zeros to +0.0: a zero comes
        # out +0.0), without a LAPACK call, which after a large section costs tens of
        # microseconds with the caches cold.
        out[:4, 4] = 0.0 - m[:4, 4]
        return out
    inv = np.linalg.inv(m[:4, :4])
    out[:4, :4] = inv
    out[:4, 4] = -inv @ m[:4, 4]
    return out


_EYE4_BYTES = np.eye(4).tobytes()


def rigid_inverse(m) -> np.ndarray:
    """Inverse of a rotation plus translation, using the transpose (no scale allowed)."""
    m = np.asarray(m, dtype=np.float64)
    out = np.eye(5)
    out[:4, :4] = m[:4, :4].T
    out[:4, 4] = -m[:4, :4].T @ m[:4, 4]
    return out


def apply(m, points) -> np.ndarray:
    """Transform points.

    Parameters
    ----------
    m : (5, 5) array_like
    points : (..., 4) array_like

    Returns
    -------
    (..., 4) float64
    """
    m = np.asarray(m, dtype=np.float64)
    p = np.asarray(points, dtype=np.float64)
    return p @ m[:4, :4].T + m[:4, 4]


def apply_vectors(m, vectors) -> np.ndarray:
    """Transform directions (no translation): ``(..., 4) -> (..., 4) float64``."""
    m = np.asarray(m, dtype=np.float64)
    return np.asarray(vectors, dtype=np.float64) @ m[:4, :4].T


def orthonormalize(r) -> np.ndarray:
    """Nearest proper rotation to ``r`` (polar decomposition by SVD).

    Parameters
    ----------
    r : (..., 4, 4) array_like

    Returns
    -------
    (..., 4, 4) float64
        ``U @ Vt`` with the sign fixed so the determinant is +1.
    """
    u, _, vt = np.linalg.svd(np.asarray(r, dtype=np.float64))
    d = np.sign(np.linalg.det(u @ vt))
    u[..., :, 3] *= d[..., None]
    return u @ vt


def orthonormality_error(r) -> float:
    """``max |R^T R - I|`` over all entries: 0 for an exact rotation."""
    r = np.asarray(r, dtype=np.float64)
    return float(np.max(np.abs(np.swapaxes(r, -1, -2) @ r - np.eye(4))))


def bivector_rotation(omega, dt: float = 1.0) -> np.ndarray:
    """Rotation generated by an angular velocity bivector over a time step.

    Parameters
    ----------
    omega : (6,) array_like
        Rates in the planes of :data:`PLANES` order, radians per unit time.
    dt : float

    Returns
    -------
    (4, 4) float64
        ``expm(dt * A)`` where A is the skew matrix of ``omega``, computed by
        :func:`expm_skew`: the one implementation, which the physics runs compiled.
    """
    w = np.asarray(omega, dtype=np.float64).reshape(6)
    out = np.empty((4, 4))
    # The same source run as plain Python: no compile wait for a one-off call.
    expm_skew.py_func(w, float(dt), out, np.empty((3, 4, 4)))
    return out


@njit(cache=True)
def expm_skew(w, h, out, wk):
    """Rotation ``expm(h * skew(w))`` by scaling and squaring a Taylor series.

    A 4x4 skew matrix satisfies ``A^4 = -p A^2 - q I`` (Cayley-Hamilton, with
    ``p`` the squared norm of the bivector and ``q`` its squared Pfaffian), so
    every power of ``A`` is a combination of ``I, A, A^2, A^3``: the series is
    summed on those four coefficients, in scalars, and only ``A^2`` and ``A^3``
    are matrix products (this runs for every moving body every substep).

    Parameters
    ----------
    w : (6,) float64
    h : float
    out : (4, 4) float64
        Overwritten with a rotation (orthogonal to rounding).
    wk : (3, 4, 4) float64
        Scratch (so that nothing is allocated).
    """
    a = wk[0]
    a2 = wk[1]
    a3 = wk[2]
    for i in range(4):
        for j in range(4):
            a[i, j] = 0.0
    for k in range(6):
        i = PLANE_I[k]
        j = PLANE_J[k]
        a[j, i] = w[k] * h
        a[i, j] = -w[k] * h
    norm = 0.0
    for i in range(4):
        s = 0.0
        for j in range(4):
            s += abs(a[i, j])
        norm = max(norm, s)
    # Halve until the series converges fast and without cancellation (|A| <= 1/4).
    squarings = 0
    while norm > 0.25:
        norm *= 0.5
        squarings += 1
    scale = 1.0 / (2.0**squarings)
    p = 0.0
    for k in range(6):
        t = w[k] * h * scale
        p += t * t
    # Planes xy, xz, yz, xw, yw, zw: the Pfaffian is a01 a23 - a02 a13 + a03 a12.
    pf = (w[0] * w[5] - w[1] * w[4] + w[3] * w[2]) * (h * scale) * (h * scale)
    q = pf * pf
    for i in range(4):
        for j in range(4):
            a[i, j] *= scale
    c0, c1, c2, c3 = _series_on_powers(p, q, norm)
    for i in range(4):
        for j in range(4):
            s = 0.0
            for k in range(4):
                s += a[i, k] * a[k, j]
            a2[i, j] = s
    for i in range(4):
        for j in range(4):
            s = 0.0
            for k in range(4):
                s += a[i, k] * a2[k, j]
            a3[i, j] = s
    for i in range(4):
        for j in range(4):
            out[i, j] = c1 * a[i, j] + c2 * a2[i, j] + c3 * a3[i, j]
        out[i, i] += c0
    for _ in range(squarings):
        for i in range(4):
            for j in range(4):
                s = 0.0
                for k in range(4):
                    s += out[i, k] * out[k, j]
                a2[i, j] = s
        for i in range(4):
            for j in range(4):
                out[i, j] = a2[i, j]


@njit(cache=True)
def _series_on_powers(p, q, norm):
    """``expm(A)`` as ``c0 I + c1 A + c2 A^2 + c3 A^3`` for a 4x4 skew ``A`` with
    ``A^4 = -p A^2 - q I`` and norm at most ``norm``: returns ``c0, c1, c2, c3``.

    Scalars in, scalars out (see :func:`expm_skew`).
    """
    # Coefficients of A^n / n! on I, A, A^2, A^3, and their running sums.
    t0, t1, t2, t3 = 1.0, 0.0, 0.0, 0.0
    c0, c1, c2, c3 = 1.0, 0.0, 0.0, 0.0
    bound = 1.0
    for n in range(1, 30):
        inv_n = 1.0 / n
        t0, t1, t2, t3 = -t3 * q * inv_n, t0 * inv_n, (t1 - t3 * p) * inv_n, t2 * inv_n
        c0 += t0
        c1 += t1
        c2 += t2
        c3 += t3
        # |A^n / n!| <= |A|^n / n!: stop once that is below rounding.
        bound *= norm * inv_n
        if bound < 1e-18:
            break
    return c0, c1, c2, c3


def skew(omega) -> np.ndarray:
    """Skew-symmetric 4x4 matrix of a bivector ``(6,)`` in :data:`PLANES` order.

    Entry ``[j, i] = omega_ij`` so that ``expm(skew(e_ij * t)) == rotation4(ij, t)``.
    """
    omega = np.asarray(omega, dtype=np.float64)
    a = np.zeros(omega.shape[:-1] + (4, 4))
    for k, plane in enumerate(PLANES):
        i, j = _plane_axes(plane)
        a[..., j, i] = omega[..., k]
        a[..., i, j] = -omega[..., k]
    return a


def unskew(a) -> np.ndarray:
    """Bivector ``(6,)`` of a skew-symmetric 4x4 matrix (inverse of :func:`skew`)."""
    a = np.asarray(a, dtype=np.float64)
    out = np.empty(a.shape[:-2] + (6,))
    for k, plane in enumerate(PLANES):
        i, j = _plane_axes(plane)
        out[..., k] = 0.5 * (a[..., j, i] - a[..., i, j])
    return out


def parse_axis_assignments(items, kind: str) -> dict[str, float]:
    """Parse ``["xw=30", "w=0.3"]`` style command-line assignments.

    Parameters
    ----------
    items : iterable of str
    kind : {"plane", "axis"}

    Returns
    -------
    dict of str to float
        Values as given (degrees stay degrees).

    Raises
    ------
    ValueError
        With a one-line message naming the offending item.
    """
    names = PLANES if kind == "plane" else tuple(AXES)
    out: dict[str, float] = {}
    for item in items:
        key, sep, value = item.partition("=")
        key = key.strip().lower()
        if not sep or key not in names:
            raise ValueError(f"{item!r}: expected NAME=NUMBER with NAME one of {', '.join(names)}")
        try:
            out[key] = out.get(key, 0.0) + float(value)
        except ValueError:
            raise ValueError(f"{item!r}: {value!r} is not a number") from None
    return out
