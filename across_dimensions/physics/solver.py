"""Sequential-impulse contact solver (Catto's scheme) generalised to 4D.

Each contact has four rows: the normal and three tangents spanning the contact
hyperplane (a 3D space in 4D). A row along unit direction ``d`` at offsets
``rA``, ``rB`` from the body centres has the Jacobian ``(-d, -(rA ^ d), d, rB ^ d)``
on ``(vA, wA, vB, wB)``, so the relative velocity along ``d`` is
``d . (vB - vA) + (rB ^ d) . wB - (rA ^ d) . wA`` and its effective mass is
``1 / (1/mA + 1/mB + (rA^d) . IA^-1 (rA^d) + (rB^d) . IB^-1 (rB^d))``.
That relative velocity is ``d . u`` with ``u`` the velocity of b's contact
point minus a's (``v + w r`` each, see :func:`.scalars.spin_velocity`), which is how
the solver computes it: ``u`` once per contact, then one dot product per row,
and the contact's whole impulse applied to the bodies at once. For an
isotropic inertia ``i`` the angular term is ``i (|r|^2 - (r . d)^2)``.

Friction is isotropic: the three tangent impulses form one vector clamped to
the ball of radius ``mu * normal impulse`` (a Coulomb cone in 4D), which is what
turns a sliding hypersphere's slip into spin in whatever plane the slip is.
Contacts of hyperspheres also get angular-only rows: spin friction in the three
planes of the contact hyperplane and optional rolling resistance in the three
planes containing the normal (see :func:`.prepare.prepare_spins`).

The time stepping is Box2D v3's "soft step": contacts are found and prepared
once per tick (:mod:`.prepare`), then several substeps each warm start, solve with a soft
(spring-damper) push-out, move the bodies, and relax without the push-out so
the separation speed is not kept as momentum. The overlap seen by each solve is
updated from how far the bodies moved since the contacts were found, so the
substeps work without a new narrowphase. Restitution runs once at the end from
the approach speed measured when the contact was prepared.

Arrays use ``b = -1 - s`` for a contact against static world collider ``s``:
those rows have no second body.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .scalars import (
    axpy4,
    axpy6,
    dot4,
    dot6,
    load4,
    load6,
    load6r,
    point_velocity,
    push,
    row4,
    spin_change,
    store4,
    store6,
    sub4,
    wedge,
)
from .state import Softness


@njit(cache=True)
def soft_params(hertz, zeta, h):
    """Bias rate, mass scale and impulse scale of a soft contact (Box2D's b2MakeSoft).

    The push-out behaves as a damped spring of frequency ``hertz`` and damping
    ratio ``zeta`` integrated implicitly with step ``h``, so it cannot overshoot.
    """
    if hertz == 0.0:
        return 0.0, 1.0, 0.0
    omega = 2.0 * np.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@njit(cache=True)
def softness(hertz, zeta, h, max_push):
    """The :class:`~.state.Softness` of a substep of ``h`` seconds: :func:`soft_params` with the
    stiffness held to a quarter of the substep rate (stiffer is not stable), and ``max_push``."""
    bias_rate, mass_scale, impulse_scale = soft_params(min(hertz, 0.25 / h), zeta, h)
    return Softness(bias_rate, mass_scale, impulse_scale, max_push, 1.0 / h)


@njit(cache=True)
def warm_start(nc, contacts, rows_in, bodies, inertia):
    """Apply the accumulated impulses so the iterations start near the answer.

    Spin friction is not warm started: it only damps, so it restarts from zero
    each substep.

    ``inertia`` holds the bodies' inverse inertias (see :func:`.prepare.world_inertia`).
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    lam = rows_in.impulse
    rows = rows_in.direction
    anchor_a = rows_in.anchor_a
    anchor_b = rows_in.anchor_b
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_mass = bodies.inv_mass
    iso = inertia.iso
    iinv = inertia.full
    slam = rows_in.spin.impulse
    for c in range(nc):
        for k in range(6):
            slam[c, k] = 0.0
        if lam[c, 0] == 0.0 and lam[c, 1] == 0.0 and lam[c, 2] == 0.0 and lam[c, 3] == 0.0:
            continue
        a = body_a[c]
        b = body_b[c]
        p = axpy4(lam[c, 0], row4(rows, c, 0), (0.0, 0.0, 0.0, 0.0))
        for r in range(1, 4):
            p = axpy4(lam[c, r], row4(rows, c, r), p)
        push(a, load4(anchor_a, c), p, -1.0, inv_mass, iso, iinv, vel, omg)
        if b >= 0:
            push(b, load4(anchor_b, c), p, 1.0, inv_mass, iso, iinv, vel, omg)


@njit(cache=True)
def current_separation(nc, contacts, rows_in, dpos, drot):
    """Separation of each contact after the bodies moved by ``dpos``, ``drot``.

    ``s = -depth + n . ((dB + dRB rB - rB) - (dA + dRA rA - rA))``: the anchors
    ride along with their bodies; the normal stays fixed within a tick.

    Parameters
    ----------
    dpos : (N, 4) float64
        Displacement of each body since the contacts were found.
    drot : (N, 4, 4) float64
        Rotation of each body since then (``R_now @ R_then.T``).

    The result goes to ``rows_in.separation``.
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    cd = contacts.depth
    rows = rows_in.direction
    ra_ = rows_in.anchor_a
    rb_ = rows_in.anchor_b
    sep = rows_in.separation
    for c in range(nc):
        a = body_a[c]
        b = body_b[c]
        s = -cd[c]
        for m in range(4):
            move = -dpos[a, m] + ra_[c, m]
            for q in range(4):
                move -= drot[a, m, q] * ra_[c, q]
            if b >= 0:
                move += dpos[b, m] - rb_[c, m]
                for q in range(4):
                    move += drot[b, m, q] * rb_[c, q]
            s += rows[c, 0, m] * move
        sep[c] = s


# size: one hot loop, values in registers (helpers taking arrays cost a reference count per array per contact)
@njit(cache=True)
def solve(nc, contacts, rows_in, bodies, inertia, soft, use_bias, iterations):
    """Gauss-Seidel sweeps over all contacts: normal, then friction, then a ball's spin rows.

    Each contact works on the relative velocity ``u`` of its two contact
    points (b's minus a's): a row's velocity is ``d . u``. After the normal
    impulse ``u`` moves by ``K n`` times it (``normal_response``), so the
    friction rows see it without a round trip through the bodies; the bodies
    then take the contact's whole impulse at once.

    Parameters
    ----------
    nc : int
    contacts : Contacts
    rows_in : SolverRows
        Rows from :func:`.prepare.prepare`, ``separation`` from :func:`current_separation`
        (negative when overlapping); the impulses are updated.
    bodies : Bodies
        Velocities updated in place.
    inertia : Inertia
        The bodies' world-frame inverse inertias.
    soft : Softness
        The substep's push-out (see :func:`softness`).
    use_bias : bool
        True for the solve pass (soft push-out of overlap at most ``max_push``
        m/s), False for the relax pass.
    iterations : int
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    surf = contacts.surface_velocity
    sep = rows_in.separation
    lam = rows_in.impulse
    cmu = rows_in.friction
    rows = rows_in.direction
    anchor_a = rows_in.anchor_a
    anchor_b = rows_in.anchor_b
    resp = rows_in.normal_response
    rmass = rows_in.eff_mass
    maxlam = rows_in.max_normal_impulse
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_mass = bodies.inv_mass
    iso = inertia.iso
    iinv = inertia.full
    bias_rate, mass_scale, impulse_scale, max_push, inv_h = soft
    spin = rows_in.spin
    slim = spin.limits
    sbv = spin.planes
    smass = spin.eff_mass
    slam = spin.impulse
    zero4 = (0.0, 0.0, 0.0, 0.0)
    zero6 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for _ in range(iterations):
        for c in range(nc):
            a = body_a[c]
            b = body_b[c]
            ra = load4(anchor_a, c)
            va = load4(vel, a)
            wa = load6(omg, a)
            ima = inv_mass[a]
            if b >= 0:
                rb = load4(anchor_b, c)
                vb = load4(vel, b)
                wb = load6(omg, b)
                imb = inv_mass[b]
                u = sub4(point_velocity(vb, wb, rb), point_velocity(va, wa, ra))
            else:
                # The static world: still, or a moving tet mesh's surface (see Contacts).
                rb = zero4
                vb = zero4
                wb = zero6
                imb = 0.0
                u = sub4(load4(surf, c), point_velocity(va, wa, ra))
            # Normal: a speculative contact (s > 0) may close its gap this
            # substep; an overlapping one is pushed out softly (solve pass only).
            n = row4(rows, c, 0)
            vn = dot4(n, u)
            s = sep[c]
            ms = 1.0
            isc = 0.0
            if s > 0.0:
                bias = s * inv_h
            elif use_bias:
                bias = bias_rate * s
                if bias < -max_push:
                    bias = -max_push
                ms = mass_scale
                isc = impulse_scale
            else:
                bias = 0.0
            old = lam[c, 0]
            new = old - rmass[c, 0] * ms * (vn + bias) - isc * old
            if new < 0.0:
                new = 0.0
            o1 = lam[c, 1]
            o2 = lam[c, 2]
            o3 = lam[c, 3]
            if new == 0.0 and old == 0.0 and o1 == 0.0 and o2 == 0.0 and o3 == 0.0:
                # A gap that stays open: no push, so no friction either (its
                # limit is zero) and nothing to apply. In a resting pile about
                # half the contacts are such speculative ones.
                continue
            dn = new - old
            lam[c, 0] = new
            if new > maxlam[c]:
                maxlam[c] = new
            u = axpy4(dn, load4(resp, c), u)
            # Friction: one vector impulse clamped to the friction ball.
            t1 = row4(rows, c, 1)
            t2 = row4(rows, c, 2)
            t3 = row4(rows, c, 3)
            f1 = o1 - rmass[c, 1] * dot4(t1, u)
            f2 = o2 - rmass[c, 2] * dot4(t2, u)
            f3 = o3 - rmass[c, 3] * dot4(t3, u)
            limit = cmu[c] * new
            s2 = f1 * f1 + f2 * f2 + f3 * f3
            if s2 > limit * limit:
                sc = limit / np.sqrt(s2) if s2 > 0.0 else 0.0
                f1 *= sc
                f2 *= sc
                f3 *= sc
            lam[c, 1] = f1
            lam[c, 2] = f2
            lam[c, 3] = f3
            p = axpy4(dn, n, axpy4(f1 - o1, t1, axpy4(f2 - o2, t2, axpy4(f3 - o3, t3, zero4))))
            va = axpy4(-ima, p, va)
            wa = axpy6(-1.0, spin_change(a, iso, iinv, wedge(ra, p)), wa)
            if b >= 0:
                vb = axpy4(imb, p, vb)
                wb = axpy6(1.0, spin_change(b, iso, iinv, wedge(rb, p)), wb)
            # A ball's spin friction and rolling resistance: angular rows on
            # the relative spin, each group one impulse clamped to its ball.
            for g in range(2):
                if slim[c, g] == 0.0:
                    continue
                limit = slim[c, g] * new
                rel = axpy6(-1.0, wa, wb)
                q0 = 3 * g
                d1 = slam[c, q0] - smass[c, q0] * dot6(sbv, c, q0, rel)
                d2 = slam[c, q0 + 1] - smass[c, q0 + 1] * dot6(sbv, c, q0 + 1, rel)
                d3 = slam[c, q0 + 2] - smass[c, q0 + 2] * dot6(sbv, c, q0 + 2, rel)
                s2 = d1 * d1 + d2 * d2 + d3 * d3
                if s2 > limit * limit:
                    sc = limit / np.sqrt(s2) if s2 > 0.0 else 0.0
                    d1 *= sc
                    d2 *= sc
                    d3 *= sc
                q = axpy6(d1 - slam[c, q0], load6r(sbv, c, q0), zero6)
                q = axpy6(d2 - slam[c, q0 + 1], load6r(sbv, c, q0 + 1), q)
                q = axpy6(d3 - slam[c, q0 + 2], load6r(sbv, c, q0 + 2), q)
                slam[c, q0] = d1
                slam[c, q0 + 1] = d2
                slam[c, q0 + 2] = d3
                wa = axpy6(-1.0, spin_change(a, iso, iinv, q), wa)
                if b >= 0:
                    wb = axpy6(1.0, spin_change(b, iso, iinv, q), wb)
            store4(vel, a, va)
            store6(omg, a, wa)
            if b >= 0:
                store4(vel, b, vb)
                store6(omg, b, wb)


@njit(cache=True)
def restitution(nc, contacts, rows_in, bodies, inertia, threshold):
    """Bounce: drive the normal velocity to ``-e * vn0`` for contacts that were hit.

    Only contacts approaching faster than ``threshold`` and that actually pushed
    (a speculative contact that never engaged must not bounce early).
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    surf = contacts.surface_velocity
    impulse = rows_in.impulse
    ce = rows_in.restitution
    rows = rows_in.direction
    anchor_a = rows_in.anchor_a
    anchor_b = rows_in.anchor_b
    rmass = rows_in.eff_mass
    vn0 = rows_in.approach_speed
    maxlam = rows_in.max_normal_impulse
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_mass = bodies.inv_mass
    iso = inertia.iso
    iinv = inertia.full
    for c in range(nc):
        if ce[c] == 0.0 or vn0[c] > -threshold or maxlam[c] == 0.0:
            continue
        a = body_a[c]
        b = body_b[c]
        ra = load4(anchor_a, c)
        rb = load4(anchor_b, c)
        pa = point_velocity(load4(vel, a), load6(omg, a), ra)
        pb = point_velocity(load4(vel, b), load6(omg, b), rb) if b >= 0 else load4(surf, c)
        n = row4(rows, c, 0)
        vn = dot4(n, sub4(pb, pa))
        lam = -rmass[c, 0] * (vn + ce[c] * vn0[c])
        new = impulse[c, 0] + lam
        if new < 0.0:
            new = 0.0
        d = new - impulse[c, 0]
        impulse[c, 0] = new
        if d != 0.0:
            p = axpy4(d, n, (0.0, 0.0, 0.0, 0.0))
            push(a, ra, p, -1.0, inv_mass, iso, iinv, vel, omg)
            if b >= 0:
                push(b, rb, p, 1.0, inv_mass, iso, iinv, vel, omg)


@njit(cache=True)
def store(nc, contacts, rows_in, warm):
    """Keep this tick's impulses, keyed by pair, in ``warm`` for the next warm start."""
    lam = rows_in.impulse
    rows = rows_in.direction
    local_point = rows_in.local_point
    keys = contacts.key
    old_key = warm.key
    old_normal = warm.normal_impulse
    old_point = warm.local_point
    old_friction = warm.friction_impulse
    for c in range(nc):
        old_key[c] = keys[c]
        old_normal[c] = lam[c, 0]
        for m in range(4):
            old_point[c, m] = local_point[c, m]
            s = 0.0
            for r in range(3):
                s += lam[c, r + 1] * rows[c, r + 1, m]
            old_friction[c, m] = s
    warm.count[0] = nc
