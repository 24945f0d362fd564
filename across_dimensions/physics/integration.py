"""Integration: forces on the bodies' velocities, and velocities into poses, one substep at a time."""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import compound, rotate_by
from .borrow import borrowed, keep
from .collide import SPHERE
from .state import DYNAMIC, KINEMATIC, STATIC


@njit(cache=True)
def apply_forces(bodies, prm, h):
    """Gravity, optional inverse-cube attraction and damping for awake dynamic bodies
    over a substep of ``h`` seconds (``prm``: a record of ``PARAMS_DTYPE``)."""
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.angular_velocity
    mass = bodies.mass
    gravity = prm.gravity
    G = prm.inverse_cube_G
    eps2 = prm.softening * prm.softening
    lin = 1.0 / (1.0 + h * prm.linear_damping)
    ang = 1.0 / (1.0 + h * prm.angular_damping)
    acc = np.zeros((nb, 4))
    if G != 0.0:
        # Gauss's law in 4D: |F| = G m1 m2 / r^3, so a_i = G m_j d / r^4.
        for i in range(nb):
            if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
                continue
            for j in range(nb):
                if j == i or not alive[j] or mass[j] <= 0.0:
                    continue
                r2 = eps2
                for m in range(4):
                    t = pos[j, m] - pos[i, m]
                    r2 += t * t
                f = G * mass[j] / (r2 * r2)
                for m in range(4):
                    acc[i, m] += f * (pos[j, m] - pos[i, m])
    for i in range(nb):
        if not (alive[i] and kind[i] == DYNAMIC and awake[i]):
            continue
        for m in range(4):
            vel[i, m] = (vel[i, m] + h * (gravity[m] + acc[i, m])) * lin
        if ang != 1.0:
            for k in range(6):
                omg[i, k] *= ang


@njit(cache=True)
def integrate_positions(bodies, h, orthonormalise=True):
    """Move awake dynamic and kinematic bodies by one substep.

    Bodies with an isotropic inertia (hyperspheres, hypercubes) keep their
    angular velocity while free. Other boxes precess: their world angular
    momentum ``L = I_world(R) omega`` is what is conserved, so the rotation uses
    the midpoint rate recomputed from ``L`` and ``omega`` is re-derived from
    ``L`` afterwards (second order, and ``L`` is kept exactly).
    ``orthonormalise`` is passed on to :func:`.bivector.rotate_by`.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    awake = bodies.awake
    pos = bodies.position
    rot = bodies.rotation
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_inertia = bodies.inv_inertia
    # Work arrays borrowed (see .borrow): rotate_by gets them for every body.
    own = np.empty((6, 4, 4))
    wk = borrowed(own)[:5]
    rh = borrowed(own)[5]
    own6 = np.empty((9, 6))
    M = borrowed(own6)[:6]
    lw = borrowed(own6)[6]
    lb = borrowed(own6)[7]
    wh = borrowed(own6)[8]
    for i in range(nb):
        if not alive[i] or kind[i] == STATIC:
            continue
        if kind[i] == DYNAMIC and not awake[i]:
            continue
        for m in range(4):
            pos[i, m] += h * vel[i, m]
        iso = True
        for k in range(1, 6):
            if inv_inertia[i, k] != inv_inertia[i, 0]:
                iso = False
        if iso or kind[i] == KINEMATIC:
            rotate_by(omg[i], h, rot[i], wk, orthonormalise)
            continue
        compound(rot[i], M)
        for k in range(6):
            s = 0.0
            for j in range(6):
                s += M[j, k] * omg[i, j]
            lb[k] = s / inv_inertia[i, k]
        for k in range(6):
            s = 0.0
            for j in range(6):
                s += M[k, j] * lb[j]
            lw[k] = s
        for a in range(4):
            for b in range(4):
                rh[a, b] = rot[i, a, b]
        rotate_by(omg[i], 0.5 * h, rh, wk, False)
        _omega_from_l(rh, inv_inertia[i], lw, M, wh)
        rotate_by(wh, h, rot[i], wk, orthonormalise)
        _omega_from_l(rot[i], inv_inertia[i], lw, M, omg[i])
    keep(own)
    keep(own6)


@njit(cache=True)
def _omega_from_l(r, inv_i, lw, M, out):
    compound(r, M)
    tmp = np.empty(6)
    for k in range(6):
        s = 0.0
        for j in range(6):
            s += M[j, k] * lw[j]
        tmp[k] = s * inv_i[k]
    for k in range(6):
        s = 0.0
        for j in range(6):
            s += M[k, j] * tmp[j]
        out[k] = s


@njit(cache=True)
def track_motion(bodies, x0, r0, dpos, drot):
    """How far each moving body got since the contacts were found: ``dpos = x - x0``, ``drot = R R0^T``.

    A ball's rotation is left out (``drot`` stays the identity): its contact
    point stays where the normal leaves its centre however it spins, and
    rotating the anchor would make a rolling ball look lifted off the ground
    and let it sink.
    """
    alive = bodies.alive
    kind = bodies.kind
    shape = bodies.shape
    pos = bodies.position
    rot = bodies.rotation
    for i in range(bodies.count):
        if not alive[i] or kind[i] == STATIC:
            continue
        for m in range(4):
            dpos[i, m] = pos[i, m] - x0[i, m]
        if shape[i] == SPHERE:
            continue
        for m in range(4):
            for q in range(4):
                s = 0.0
                for k in range(4):
                    s += rot[i, m, k] * r0[i, q, k]
                drot[i, m, q] = s
