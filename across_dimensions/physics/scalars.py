"""Scalar helpers of the contact solver's hot loops (:mod:`.prepare`, :mod:`.solver`).

Vectors travel as tuples (4 floats for a velocity or point, 6 for a bivector),
which the compiler keeps in registers: small work arrays would go through
memory, and a helper taking arrays would cost a reference-count call each time
it runs. Every helper is inlined into its caller.
"""

from __future__ import annotations

from across_dimensions.core._jit import njit


@njit(inline="always")
def load4(x, i):
    return x[i, 0], x[i, 1], x[i, 2], x[i, 3]


@njit(inline="always")
def load6(x, i):
    return x[i, 0], x[i, 1], x[i, 2], x[i, 3], x[i, 4], x[i, 5]


@njit(inline="always")
def store4(x, i, v):
    x[i, 0] = v[0]
    x[i, 1] = v[1]
    x[i, 2] = v[2]
    x[i, 3] = v[3]


@njit(inline="always")
def store6(x, i, v):
    x[i, 0] = v[0]
    x[i, 1] = v[1]
    x[i, 2] = v[2]
    x[i, 3] = v[3]
    x[i, 4] = v[4]
    x[i, 5] = v[5]


@njit(inline="always")
def row4(rows, c, r):
    return rows[c, r, 0], rows[c, r, 1], rows[c, r, 2], rows[c, r, 3]


@njit(inline="always")
def dot4(x, y):
    # Summed in pairs: two short dependency chains instead of one long one.
    return (x[0] * y[0] + x[1] * y[1]) + (x[2] * y[2] + x[3] * y[3])


@njit(inline="always")
def add4(x, y):
    return x[0] + y[0], x[1] + y[1], x[2] + y[2], x[3] + y[3]


@njit(inline="always")
def sub4(x, y):
    return x[0] - y[0], x[1] - y[1], x[2] - y[2], x[3] - y[3]


@njit(inline="always")
def axpy4(s, x, y):
    """``s x + y``."""
    return s * x[0] + y[0], s * x[1] + y[1], s * x[2] + y[2], s * x[3] + y[3]


@njit(inline="always")
def axpy6(s, x, y):
    """``s x + y``."""
    return s * x[0] + y[0], s * x[1] + y[1], s * x[2] + y[2], s * x[3] + y[3], s * x[4] + y[4], s * x[5] + y[5]


# size: scalar helper, coordinates in registers
@njit(inline="always")
def spin_velocity(w0, w1, w2, w3, w4, w5, r0, r1, r2, r3):
    """Velocity of the point at offset ``r`` of a body spinning at bivector ``w``
    (:func:`.bivector.spin_velocity` on scalars).

    It is the vector ``u`` with ``d . u = (r ^ d) . w`` for every ``d`` (the
    angular part of a row's relative velocity), planes ordered xy, xz, yz, xw,
    yw, zw as in :mod:`.bivector`.
    """
    return (
        -w0 * r1 - w1 * r2 - w3 * r3,
        w0 * r0 - w2 * r2 - w4 * r3,
        w1 * r0 + w2 * r1 - w5 * r3,
        w3 * r0 + w4 * r1 + w5 * r2,
    )


@njit(inline="always")
def point_velocity(v, w, r):
    """Velocity of the point at offset ``r`` of a body moving at ``v`` and spinning at ``w``."""
    s = spin_velocity(w[0], w[1], w[2], w[3], w[4], w[5], r[0], r[1], r[2], r[3])
    return v[0] + s[0], v[1] + s[1], v[2] + s[2], v[3] + s[3]


@njit(inline="always")
def wedge(r, p):
    """The bivector ``r ^ p``."""
    return (
        r[0] * p[1] - r[1] * p[0],
        r[0] * p[2] - r[2] * p[0],
        r[1] * p[2] - r[2] * p[1],
        r[0] * p[3] - r[3] * p[0],
        r[1] * p[3] - r[3] * p[1],
        r[2] * p[3] - r[3] * p[2],
    )


@njit(inline="always")
def wedge_into(r, rows, k, out):
    """``out = r ^ rows[k]`` (arrays: the anisotropic path of :func:`prepare`)."""
    out[0] = r[0] * rows[k, 1] - r[1] * rows[k, 0]
    out[1] = r[0] * rows[k, 2] - r[2] * rows[k, 0]
    out[2] = r[1] * rows[k, 2] - r[2] * rows[k, 1]
    out[3] = r[0] * rows[k, 3] - r[3] * rows[k, 0]
    out[4] = r[1] * rows[k, 3] - r[3] * rows[k, 1]
    out[5] = r[2] * rows[k, 3] - r[3] * rows[k, 2]


@njit(inline="always")
def mat6_row(m, i, k, w):
    return (
        (m[i, k, 0] * w[0] + m[i, k, 1] * w[1])
        + (m[i, k, 2] * w[2] + m[i, k, 3] * w[3])
        + (m[i, k, 4] * w[4] + m[i, k, 5] * w[5])
    )


@njit(inline="always")
def spin_change(i, iso, iinv, q):
    """``I^-1 q``: the spin that angular impulse ``q`` (a bivector) gives body ``i``."""
    f = iso[i]
    if f >= 0.0:
        return f * q[0], f * q[1], f * q[2], f * q[3], f * q[4], f * q[5]
    return (
        mat6_row(iinv, i, 0, q),
        mat6_row(iinv, i, 1, q),
        mat6_row(iinv, i, 2, q),
        mat6_row(iinv, i, 3, q),
        mat6_row(iinv, i, 4, q),
        mat6_row(iinv, i, 5, q),
    )


@njit(inline="always")
def load6r(x, c, r):
    return x[c, r, 0], x[c, r, 1], x[c, r, 2], x[c, r, 3], x[c, r, 4], x[c, r, 5]


@njit(inline="always")
def dot6(x, c, r, w):
    return (
        (x[c, r, 0] * w[0] + x[c, r, 1] * w[1])
        + (x[c, r, 2] * w[2] + x[c, r, 3] * w[3])
        + (x[c, r, 4] * w[4] + x[c, r, 5] * w[5])
    )


# size: scalar helper inlined into the hot loops, arrays one by one (a tuple costs a reference count each)
@njit(inline="always")
def push(i, r, p, sign, inv_mass, iso, iinv, vel, omg):
    """Apply impulse ``sign * p`` at offset ``r`` of body ``i`` (in place)."""
    v = axpy4(sign * inv_mass[i], p, load4(vel, i))
    w = axpy6(sign, spin_change(i, iso, iinv, wedge(r, p)), load6(omg, i))
    store4(vel, i, v)
    store6(omg, i, w)
