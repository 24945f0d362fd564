"""Sequential-impulse contact solver (Catto's scheme) generalised to 4D.

Each contact has four rows: the normal and three tangents spanning the contact
hyperplane (a 3D space in 4D). A row along unit direction ``d`` at offsets
``rA``, ``rB`` from the body centres has the Jacobian ``(-d, -(rA ^ d), d, rB ^ d)``
on ``(vA, wA, vB, wB)``, so the relative velocity along ``d`` is
``d . (vB - vA) + (rB ^ d) . wB - (rA ^ d) . wA`` and its effective mass is
``1 / (1/mA + 1/mB + (rA^d) . IA^-1 (rA^d) + (rB^d) . IB^-1 (rB^d))``.
That relative velocity is ``d . u`` with ``u`` the velocity of b's contact
point minus a's (``v + w r`` each, see :func:`_spin_velocity`), which is how
the solver computes it: ``u`` once per contact, then one dot product per row,
and the contact's whole impulse applied to the bodies at once. For an
isotropic inertia ``i`` the angular term is ``i (|r|^2 - (r . d)^2)``.

Friction is isotropic: the three tangent impulses form one vector clamped to
the ball of radius ``mu * normal impulse`` (a Coulomb cone in 4D), which is what
turns a sliding hypersphere's slip into spin in whatever plane the slip is.
Contacts of hyperspheres also get angular-only rows: spin friction in the three
planes of the contact hyperplane and optional rolling resistance in the three
planes containing the normal (see :func:`_prepare_spins`).

The time stepping is Box2D v3's "soft step": contacts are found and prepared
once per tick, then several substeps each warm start, solve with a soft
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

from .bivector import PLANE_I, PLANE_J, tangent_frame
from .borrow import borrowed, keep


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
def prepare(nc, contacts, bodies, iinv, iso, prm, warm, rows_out):
    """Build the solver rows of every contact and warm start them from the last tick.

    Parameters
    ----------
    nc : int
        Number of contacts (sorted by pair key).
    contacts : Contacts
    bodies : Bodies
    iinv : (N, 6, 6) float64
        World-frame inverse inertias (zero for non-dynamic bodies).
    iso : (N,) float64
        The scalar inverse inertia where ``iinv`` is a multiple of the
        identity, else -1.
    prm : record of PARAMS_DTYPE
        Uses ``world_friction``, ``world_restitution`` (material of static
        world colliders), ``spin_friction`` and ``rolling_resistance``.
    warm : WarmStart
        Last tick's contacts: keys (sorted), points in body a's frame, normal
        impulses, friction impulse vectors. An old contact counts as the same
        contact within a tenth of body a's bounding radius.
    rows_out : SolverRows
        Output: every field but ``separation`` (see :class:`SolverRows`);
        impulses warm-started; friction of the pair is the geometric mean,
        restitution the max.
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    surf = contacts.surface_velocity
    point = contacts.point
    normal = contacts.normal
    pos = bodies.position
    rot = bodies.rotation
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_mass = bodies.inv_mass
    bound = bodies.bound
    mu = bodies.friction
    rest = bodies.restitution
    shape = bodies.shape
    keys = contacts.key
    world_mu = prm.world_friction
    world_e = prm.world_restitution
    spin_radius = prm.spin_friction
    rolling = prm.rolling_resistance
    spin = rows_out.spin
    old_key = warm.key
    old_point = warm.local_point
    old_normal = warm.normal_impulse
    old_friction = warm.friction_impulse
    old_count = warm.count[0]
    rows = rows_out.direction
    ra_ = rows_out.anchor_a
    rb_ = rows_out.anchor_b
    resp = rows_out.normal_response
    rmass = rows_out.eff_mass
    lam = rows_out.impulse
    cmu = rows_out.friction
    ce = rows_out.restitution
    vn0 = rows_out.approach_speed
    maxlam = rows_out.max_normal_impulse
    cloc = rows_out.local_point
    # Small work arrays, borrowed (see .borrow): the helpers inlined below
    # would otherwise count references to them for every row.
    own = np.empty((8, 6))
    work = borrowed(own)
    ra = work[0, :4]
    rb = work[1, :4]
    wa = work[2]
    wb = work[3]
    tb = work[4:8, :4]
    olo = 0
    for c in range(nc):
        a = body_a[c]
        b = body_b[c]
        for m in range(4):
            ra[m] = point[c, m] - pos[a, m]
            ra_[c, m] = ra[m]
            tb[0, m] = normal[c, m]
        if b >= 0:
            for m in range(4):
                rb[m] = point[c, m] - pos[b, m]
                rb_[c, m] = rb[m]
            cmu[c] = np.sqrt(mu[a] * mu[b])
            ce[c] = max(rest[a], rest[b])
            imb = inv_mass[b]
        else:
            for m in range(4):
                rb[m] = 0.0
                rb_[c, m] = 0.0
            cmu[c] = np.sqrt(mu[a] * world_mu)
            ce[c] = max(rest[a], world_e)
            imb = 0.0
        # No views (tb[r], iinv[a]) in this loop: each would cost an atomic
        # reference-count update, which made up most of its time.
        tangent_frame(tb)
        for r in range(4):
            for m in range(4):
                rows[c, r, m] = tb[r, m]
            # The row's inverse effective mass: 1/mA + 1/mB + (r ^ d) . I^-1 (r ^ d)
            # for each body, which for an isotropic inertia i is
            # i (|r|^2 - (r . d)^2).
            kk = inv_mass[a] + imb
            if iso[a] >= 0.0:
                rd = 0.0
                rr = 0.0
                for m in range(4):
                    rd += ra[m] * tb[r, m]
                    rr += ra[m] * ra[m]
                kk += iso[a] * (rr - rd * rd)
            else:
                _wedge_into(ra, tb, r, wa)
                for k in range(6):
                    t = 0.0
                    for j in range(6):
                        t += iinv[a, k, j] * wa[j]
                    kk += wa[k] * t
            if b >= 0:
                if iso[b] >= 0.0:
                    rd = 0.0
                    rr = 0.0
                    for m in range(4):
                        rd += rb[m] * tb[r, m]
                        rr += rb[m] * rb[m]
                    kk += iso[b] * (rr - rd * rd)
                else:
                    _wedge_into(rb, tb, r, wb)
                    for k in range(6):
                        t = 0.0
                        for j in range(6):
                            t += iinv[b, k, j] * wb[j]
                        kk += wb[k] * t
            rmass[c, r] = 1.0 / kk if kk > 0.0 else 0.0
        # K n: the change of the contact points' relative velocity per unit
        # normal impulse, so the solver can update that velocity after the
        # normal row without touching the bodies.
        n = (tb[0, 0], tb[0, 1], tb[0, 2], tb[0, 3])
        pa = (ra[0], ra[1], ra[2], ra[3])
        pb = (rb[0], rb[1], rb[2], rb[3])
        ka = _spin_change(a, iso, iinv, _wedge(pa, n))
        kn = _axpy4(inv_mass[a] + imb, n, _point_velocity((0.0, 0.0, 0.0, 0.0), ka, pa))
        if b >= 0:
            kb = _spin_change(b, iso, iinv, _wedge(pb, n))
            kn = _point_velocity(kn, kb, pb)
        _store4(resp, c, kn)
        # The approach speed, for restitution.
        u = _point_velocity(_load4(vel, b), _load6(omg, b), pb) if b >= 0 else _load4(surf, c)
        vn = _dot4(n, _sub4(u, _point_velocity(_load4(vel, a), _load6(omg, a), pa)))
        vn0[c] = vn
        maxlam[c] = 0.0
        # The contact point in a's frame: the same material point next tick.
        for m in range(4):
            s = 0.0
            for q in range(4):
                s += rot[a, q, m] * ra[q]
            cloc[c, m] = s
        for r in range(4):
            lam[c, r] = 0.0
        # Warm start from the nearest old contact of the same pair. Both
        # lists are sorted by key, so the search position only moves forward.
        key = keys[c]
        while olo < old_count and old_key[olo] < key:
            olo += 1
        lo = olo
        tol = 0.1 * bound[a]
        best = tol * tol
        pick = -1
        j = lo
        while j < old_count and old_key[j] == key:
            d2 = 0.0
            for m in range(4):
                t = old_point[j, m] - cloc[c, m]
                d2 += t * t
            if d2 < best:
                best = d2
                pick = j
            j += 1
        if pick >= 0:
            lam[c, 0] = old_normal[pick]
            for r in range(3):
                s = 0.0
                for m in range(4):
                    s += old_friction[pick, m] * tb[r + 1, m]
                lam[c, r + 1] = s
    keep(own)
    _prepare_spins(nc, body_a, body_b, rows, cmu, shape, bound, iinv, iso, spin_radius, rolling, spin)


@njit(cache=True)
def _prepare_spins(nc, body_a, body_b, frames, friction, shape, bound, iinv, iso, spin_radius, rolling, spin):
    """Spin friction and rolling resistance of the contacts involving a ball.

    A ball touching at one point can spin freely in the three planes of the
    contact hyperplane (``t_i ^ t_j``) - point friction has no lever there -
    so a ball in a pile could twirl forever and never sleep. A real contact is
    a small patch; its friction resists that spin with a torque of at most
    ``mu * N * spin_radius * r``. Rolling (the planes ``n ^ t_k``) is resisted
    by at most ``rolling * N * r``. Rows: the unit bivectors acting on the
    relative angular velocity, three per group.

    ``frames`` are the contacts' row directions (normal, then tangents) and
    ``friction`` their friction coefficients, from :func:`prepare`. ``spin`` is
    the :class:`~.state.SpinRows` to fill; the limits are 0 for contacts without
    a ball. One loop over all contacts with the arrays taken out once:
    a call per contact would cost a reference-count call per array.
    """
    lim = spin.limits
    bv = spin.planes
    smass = spin.eff_mass
    slam = spin.impulse
    for c in range(nc):
        a = body_a[c]
        b = body_b[c]
        r = np.inf
        if shape[a] == 0:
            r = bound[a]
        if b >= 0 and shape[b] == 0:
            r = min(r, bound[b])
        if r == np.inf:
            lim[c, 0] = 0.0
            lim[c, 1] = 0.0
            continue
        lim[c, 0] = friction[c] * spin_radius * r
        lim[c, 1] = rolling * r
        if lim[c, 0] == 0.0 and lim[c, 1] == 0.0:
            continue
        for i in range(4):
            if lim[c, 0 if i > 0 else 1] == 0.0:
                continue  # a group that is off is never solved: its rows need not be built
            for j in range(i + 1, 4):
                # Unit bivectors t_i ^ t_j (k = 0..2) then n ^ t_j (k = 3..5); the
                # frame is orthonormal.
                row = j + 2 if i == 0 else i + j - 3
                for q in range(6):
                    pi = PLANE_I[q]
                    pj = PLANE_J[q]
                    bv[c, row, q] = frames[c, i, pi] * frames[c, j, pj] - frames[c, i, pj] * frames[c, j, pi]
                # The inverse angular mass B . I^-1 B of each body, added term by
                # term to one running sum (a's, then b's).
                kk = 0.0
                if iso[a] >= 0.0:
                    kk = kk + iso[a]
                else:
                    for q in range(6):
                        t = 0.0
                        for m in range(6):
                            t += iinv[a, q, m] * bv[c, row, m]
                        kk += bv[c, row, q] * t
                if b >= 0:
                    if iso[b] >= 0.0:
                        kk = kk + iso[b]
                    else:
                        for q in range(6):
                            t = 0.0
                            for m in range(6):
                                t += iinv[b, q, m] * bv[c, row, m]
                            kk += bv[c, row, q] * t
                smass[c, row] = 1.0 / kk if kk > 0.0 else 0.0
                slam[c, row] = 0.0


# Scalar helpers of the hot loops. Vectors travel as tuples (4 floats for a
# velocity or point, 6 for a bivector), which the compiler keeps in registers:
# small work arrays would go through memory, and a helper taking arrays would
# cost a reference-count call each time it runs.


@njit(inline="always")
def _load4(x, i):
    return x[i, 0], x[i, 1], x[i, 2], x[i, 3]


@njit(inline="always")
def _load6(x, i):
    return x[i, 0], x[i, 1], x[i, 2], x[i, 3], x[i, 4], x[i, 5]


@njit(inline="always")
def _store4(x, i, v):
    x[i, 0] = v[0]
    x[i, 1] = v[1]
    x[i, 2] = v[2]
    x[i, 3] = v[3]


@njit(inline="always")
def _store6(x, i, v):
    x[i, 0] = v[0]
    x[i, 1] = v[1]
    x[i, 2] = v[2]
    x[i, 3] = v[3]
    x[i, 4] = v[4]
    x[i, 5] = v[5]


@njit(inline="always")
def _row(rows, c, r):
    return rows[c, r, 0], rows[c, r, 1], rows[c, r, 2], rows[c, r, 3]


@njit(inline="always")
def _dot4(x, y):
    # Summed in pairs: two short dependency chains instead of one long one.
    return (x[0] * y[0] + x[1] * y[1]) + (x[2] * y[2] + x[3] * y[3])


@njit(inline="always")
def _add4(x, y):
    return x[0] + y[0], x[1] + y[1], x[2] + y[2], x[3] + y[3]


@njit(inline="always")
def _sub4(x, y):
    return x[0] - y[0], x[1] - y[1], x[2] - y[2], x[3] - y[3]


@njit(inline="always")
def _axpy4(s, x, y):
    """``s x + y``."""
    return s * x[0] + y[0], s * x[1] + y[1], s * x[2] + y[2], s * x[3] + y[3]


@njit(inline="always")
def _axpy6(s, x, y):
    """``s x + y``."""
    return s * x[0] + y[0], s * x[1] + y[1], s * x[2] + y[2], s * x[3] + y[3], s * x[4] + y[4], s * x[5] + y[5]


@njit(inline="always")
def _spin_velocity(w0, w1, w2, w3, w4, w5, r0, r1, r2, r3):
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
def _point_velocity(v, w, r):
    """Velocity of the point at offset ``r`` of a body moving at ``v`` and spinning at ``w``."""
    s = _spin_velocity(w[0], w[1], w[2], w[3], w[4], w[5], r[0], r[1], r[2], r[3])
    return v[0] + s[0], v[1] + s[1], v[2] + s[2], v[3] + s[3]


@njit(inline="always")
def _wedge(r, p):
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
def _wedge_into(r, rows, k, out):
    """``out = r ^ rows[k]`` (arrays: the anisotropic path of :func:`prepare`)."""
    out[0] = r[0] * rows[k, 1] - r[1] * rows[k, 0]
    out[1] = r[0] * rows[k, 2] - r[2] * rows[k, 0]
    out[2] = r[1] * rows[k, 2] - r[2] * rows[k, 1]
    out[3] = r[0] * rows[k, 3] - r[3] * rows[k, 0]
    out[4] = r[1] * rows[k, 3] - r[3] * rows[k, 1]
    out[5] = r[2] * rows[k, 3] - r[3] * rows[k, 2]


@njit(inline="always")
def _mat6_row(m, i, k, w):
    return (
        (m[i, k, 0] * w[0] + m[i, k, 1] * w[1])
        + (m[i, k, 2] * w[2] + m[i, k, 3] * w[3])
        + (m[i, k, 4] * w[4] + m[i, k, 5] * w[5])
    )


@njit(inline="always")
def _spin_change(i, iso, iinv, q):
    """``I^-1 q``: the spin that angular impulse ``q`` (a bivector) gives body ``i``."""
    f = iso[i]
    if f >= 0.0:
        return f * q[0], f * q[1], f * q[2], f * q[3], f * q[4], f * q[5]
    return (
        _mat6_row(iinv, i, 0, q),
        _mat6_row(iinv, i, 1, q),
        _mat6_row(iinv, i, 2, q),
        _mat6_row(iinv, i, 3, q),
        _mat6_row(iinv, i, 4, q),
        _mat6_row(iinv, i, 5, q),
    )


@njit(inline="always")
def _push(i, r, p, sign, inv_mass, iso, iinv, vel, omg):
    """Apply impulse ``sign * p`` at offset ``r`` of body ``i`` (in place)."""
    v = _axpy4(sign * inv_mass[i], p, _load4(vel, i))
    w = _axpy6(sign, _spin_change(i, iso, iinv, _wedge(r, p)), _load6(omg, i))
    _store4(vel, i, v)
    _store6(omg, i, w)


@njit(cache=True)
def warm_start(nc, contacts, rows_in, bodies, iso, iinv):
    """Apply the accumulated impulses so the iterations start near the answer.

    Spin friction is not warm started: it only damps, so it restarts from zero
    each substep.

    ``iso`` and ``iinv`` are the bodies' inverse inertias (see :func:`prepare`).
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
    slam = rows_in.spin.impulse
    for c in range(nc):
        for k in range(6):
            slam[c, k] = 0.0
        if lam[c, 0] == 0.0 and lam[c, 1] == 0.0 and lam[c, 2] == 0.0 and lam[c, 3] == 0.0:
            continue
        a = body_a[c]
        b = body_b[c]
        p = _axpy4(lam[c, 0], _row(rows, c, 0), (0.0, 0.0, 0.0, 0.0))
        for r in range(1, 4):
            p = _axpy4(lam[c, r], _row(rows, c, r), p)
        _push(a, _load4(anchor_a, c), p, -1.0, inv_mass, iso, iinv, vel, omg)
        if b >= 0:
            _push(b, _load4(anchor_b, c), p, 1.0, inv_mass, iso, iinv, vel, omg)


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


@njit(cache=True)
def solve(
    nc,
    contacts,
    rows_in,
    bodies,
    iso,
    iinv,
    inv_h,
    use_bias,
    bias_rate,
    mass_scale,
    impulse_scale,
    max_push,
    iterations,
):
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
        Rows from :func:`prepare`, ``separation`` from :func:`current_separation`
        (negative when overlapping); the impulses are updated.
    bodies : Bodies
        Velocities updated in place.
    iso : (N,) float64
        Scalar inverse inertia, or -1 (see :func:`prepare`).
    iinv : (N, 6, 6) float64
        World-frame inverse inertias (used where ``iso`` is -1).
    inv_h : float
        One over the substep.
    use_bias : bool
        True for the solve pass (soft push-out of overlap at most ``max_push``
        m/s), False for the relax pass.
    bias_rate, mass_scale, impulse_scale : float
        From :func:`soft_params`.
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
            ra = _load4(anchor_a, c)
            va = _load4(vel, a)
            wa = _load6(omg, a)
            ima = inv_mass[a]
            if b >= 0:
                rb = _load4(anchor_b, c)
                vb = _load4(vel, b)
                wb = _load6(omg, b)
                imb = inv_mass[b]
                u = _sub4(_point_velocity(vb, wb, rb), _point_velocity(va, wa, ra))
            else:
                # The static world: still, or a moving tet mesh's surface (see Contacts).
                rb = zero4
                vb = zero4
                wb = zero6
                imb = 0.0
                u = _sub4(_load4(surf, c), _point_velocity(va, wa, ra))
            # Normal: a speculative contact (s > 0) may close its gap this
            # substep; an overlapping one is pushed out softly (solve pass only).
            n = _row(rows, c, 0)
            vn = _dot4(n, u)
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
            u = _axpy4(dn, _load4(resp, c), u)
            # Friction: one vector impulse clamped to the friction ball.
            t1 = _row(rows, c, 1)
            t2 = _row(rows, c, 2)
            t3 = _row(rows, c, 3)
            f1 = o1 - rmass[c, 1] * _dot4(t1, u)
            f2 = o2 - rmass[c, 2] * _dot4(t2, u)
            f3 = o3 - rmass[c, 3] * _dot4(t3, u)
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
            p = _axpy4(dn, n, _axpy4(f1 - o1, t1, _axpy4(f2 - o2, t2, _axpy4(f3 - o3, t3, zero4))))
            va = _axpy4(-ima, p, va)
            wa = _axpy6(-1.0, _spin_change(a, iso, iinv, _wedge(ra, p)), wa)
            if b >= 0:
                vb = _axpy4(imb, p, vb)
                wb = _axpy6(1.0, _spin_change(b, iso, iinv, _wedge(rb, p)), wb)
            # A ball's spin friction and rolling resistance: angular rows on
            # the relative spin, each group one impulse clamped to its ball.
            for g in range(2):
                if slim[c, g] == 0.0:
                    continue
                limit = slim[c, g] * new
                rel = _axpy6(-1.0, wa, wb)
                q0 = 3 * g
                d1 = slam[c, q0] - smass[c, q0] * _dot6(sbv, c, q0, rel)
                d2 = slam[c, q0 + 1] - smass[c, q0 + 1] * _dot6(sbv, c, q0 + 1, rel)
                d3 = slam[c, q0 + 2] - smass[c, q0 + 2] * _dot6(sbv, c, q0 + 2, rel)
                s2 = d1 * d1 + d2 * d2 + d3 * d3
                if s2 > limit * limit:
                    sc = limit / np.sqrt(s2) if s2 > 0.0 else 0.0
                    d1 *= sc
                    d2 *= sc
                    d3 *= sc
                q = _axpy6(d1 - slam[c, q0], _load6r(sbv, c, q0), zero6)
                q = _axpy6(d2 - slam[c, q0 + 1], _load6r(sbv, c, q0 + 1), q)
                q = _axpy6(d3 - slam[c, q0 + 2], _load6r(sbv, c, q0 + 2), q)
                slam[c, q0] = d1
                slam[c, q0 + 1] = d2
                slam[c, q0 + 2] = d3
                wa = _axpy6(-1.0, _spin_change(a, iso, iinv, q), wa)
                if b >= 0:
                    wb = _axpy6(1.0, _spin_change(b, iso, iinv, q), wb)
            _store4(vel, a, va)
            _store6(omg, a, wa)
            if b >= 0:
                _store4(vel, b, vb)
                _store6(omg, b, wb)


@njit(inline="always")
def _load6r(x, c, r):
    return x[c, r, 0], x[c, r, 1], x[c, r, 2], x[c, r, 3], x[c, r, 4], x[c, r, 5]


@njit(inline="always")
def _dot6(x, c, r, w):
    return (
        (x[c, r, 0] * w[0] + x[c, r, 1] * w[1])
        + (x[c, r, 2] * w[2] + x[c, r, 3] * w[3])
        + (x[c, r, 4] * w[4] + x[c, r, 5] * w[5])
    )


@njit(cache=True)
def restitution(nc, contacts, rows_in, bodies, iso, iinv, threshold):
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
    for c in range(nc):
        if ce[c] == 0.0 or vn0[c] > -threshold or maxlam[c] == 0.0:
            continue
        a = body_a[c]
        b = body_b[c]
        ra = _load4(anchor_a, c)
        rb = _load4(anchor_b, c)
        pa = _point_velocity(_load4(vel, a), _load6(omg, a), ra)
        pb = _point_velocity(_load4(vel, b), _load6(omg, b), rb) if b >= 0 else _load4(surf, c)
        n = _row(rows, c, 0)
        vn = _dot4(n, _sub4(pb, pa))
        lam = -rmass[c, 0] * (vn + ce[c] * vn0[c])
        new = impulse[c, 0] + lam
        if new < 0.0:
            new = 0.0
        d = new - impulse[c, 0]
        impulse[c, 0] = new
        if d != 0.0:
            p = _axpy4(d, n, (0.0, 0.0, 0.0, 0.0))
            _push(a, ra, p, -1.0, inv_mass, iso, iinv, vel, omg)
            if b >= 0:
                _push(b, rb, p, 1.0, inv_mass, iso, iinv, vel, omg)


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
