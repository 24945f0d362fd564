"""Sequential-impulse contact solver (Catto's scheme) generalised to 4D.

Each contact has four rows: the normal and three tangents spanning the contact
hyperplane (a 3D space in 4D). A row along unit direction ``d`` at offsets
``rA``, ``rB`` from the body centres has the Jacobian ``(-d, -(rA ^ d), d, rB ^ d)``
on ``(vA, wA, vB, wB)``, so the relative velocity along ``d`` is
``d . (vB - vA) + (rB ^ d) . wB - (rA ^ d) . wA`` and its effective mass is
``1 / (1/mA + 1/mB + (rA^d) . IA^-1 (rA^d) + (rB^d) . IB^-1 (rB^d))``.

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
    ja = rows_out.jac_a
    jb = rows_out.jac_b
    ija = rows_out.inv_i_jac_a
    ijb = rows_out.inv_i_jac_b
    rmass = rows_out.eff_mass
    lam = rows_out.impulse
    cmu = rows_out.friction
    ce = rows_out.restitution
    vn0 = rows_out.approach_speed
    maxlam = rows_out.max_normal_impulse
    cloc = rows_out.local_point
    # Small work arrays, borrowed (see .borrow): the helpers inlined below
    # would otherwise count references to them for every row.
    own = np.empty((10, 6))
    work = borrowed(own)
    ra = work[0, :4]
    rb = work[1, :4]
    wa = work[2]
    wb = work[3]
    ia = work[4]
    ib = work[5]
    tb = work[6:10, :4]
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
        vn = 0.0
        for r in range(4):
            # wa = ra ^ row r, ia = I_a^-1 wa (bivector.wedge and mat6_vec written
            # out: a helper, even inlined, costs a reference-count call per
            # array per row, and each such call makes the compiler reload).
            wa[0] = ra[0] * tb[r, 1] - ra[1] * tb[r, 0]
            wa[1] = ra[0] * tb[r, 2] - ra[2] * tb[r, 0]
            wa[2] = ra[1] * tb[r, 2] - ra[2] * tb[r, 1]
            wa[3] = ra[0] * tb[r, 3] - ra[3] * tb[r, 0]
            wa[4] = ra[1] * tb[r, 3] - ra[3] * tb[r, 1]
            wa[5] = ra[2] * tb[r, 3] - ra[3] * tb[r, 2]
            if iso[a] >= 0.0:
                for k in range(6):
                    ia[k] = iso[a] * wa[k]
            else:
                for k in range(6):
                    t = 0.0
                    for j in range(6):
                        t += iinv[a, k, j] * wa[j]
                    ia[k] = t
            kk = inv_mass[a] + imb
            for k in range(6):
                kk += wa[k] * ia[k]
            if b >= 0:
                wb[0] = rb[0] * tb[r, 1] - rb[1] * tb[r, 0]
                wb[1] = rb[0] * tb[r, 2] - rb[2] * tb[r, 0]
                wb[2] = rb[1] * tb[r, 2] - rb[2] * tb[r, 1]
                wb[3] = rb[0] * tb[r, 3] - rb[3] * tb[r, 0]
                wb[4] = rb[1] * tb[r, 3] - rb[3] * tb[r, 1]
                wb[5] = rb[2] * tb[r, 3] - rb[3] * tb[r, 2]
                if iso[b] >= 0.0:
                    for k in range(6):
                        ib[k] = iso[b] * wb[k]
                else:
                    for k in range(6):
                        t = 0.0
                        for j in range(6):
                            t += iinv[b, k, j] * wb[j]
                        ib[k] = t
                for k in range(6):
                    kk += wb[k] * ib[k]
            else:
                for k in range(6):
                    wb[k] = 0.0
                    ib[k] = 0.0
            for m in range(4):
                rows[c, r, m] = tb[r, m]
            for k in range(6):
                ja[c, r, k] = wa[k]
                jb[c, r, k] = wb[k]
            # I^-1 J is only stored where the inertia is not a multiple of
            # the identity; elsewhere the solver scales J (less memory to
            # stream through every pass).
            if iso[a] < 0.0:
                for k in range(6):
                    ija[c, r, k] = ia[k]
            if b >= 0 and iso[b] < 0.0:
                for k in range(6):
                    ijb[c, r, k] = ib[k]
            rmass[c, r] = 1.0 / kk if kk > 0.0 else 0.0
            if r == 0:
                for m in range(4):
                    vn -= tb[0, m] * vel[a, m]
                for k in range(6):
                    vn -= wa[k] * omg[a, k]
                if b >= 0:
                    for m in range(4):
                        vn += tb[0, m] * vel[b, m]
                    for k in range(6):
                        vn += wb[k] * omg[b, k]
                else:
                    for m in range(4):
                        vn += tb[0, m] * surf[c, m]
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
    a ball, and ``I^-1 B`` is only stored for anisotropic bodies (as in
    :func:`prepare`). One loop over all contacts with the arrays taken out once:
    a call per contact would cost a reference-count call per array.
    """
    lim = spin.limits
    bv = spin.planes
    sia = spin.inv_i_planes_a
    sib = spin.inv_i_planes_b
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
                # term to one running sum (a's, then b's); I^-1 B is stored for
                # an anisotropic body only.
                kk = 0.0
                if iso[a] >= 0.0:
                    kk = kk + iso[a]
                else:
                    for q in range(6):
                        t = 0.0
                        for m in range(6):
                            t += iinv[a, q, m] * bv[c, row, m]
                        sia[c, row, q] = t
                        kk += bv[c, row, q] * t
                if b >= 0:
                    if iso[b] >= 0.0:
                        kk = kk + iso[b]
                    else:
                        for q in range(6):
                            t = 0.0
                            for m in range(6):
                                t += iinv[b, q, m] * bv[c, row, m]
                            sib[c, row, q] = t
                            kk += bv[c, row, q] * t
                smass[c, row] = 1.0 / kk if kk > 0.0 else 0.0
                slam[c, row] = 0.0


@njit(cache=True)
def _rel_vel(c, r, a, b, rows, ja, jb, vel, omg, surf):
    """Relative velocity of b (or the static surface, ``surf``) with respect to a along row
    ``r`` of contact ``c``."""
    v = 0.0
    for m in range(4):
        v -= rows[c, r, m] * vel[a, m]
    for k in range(6):
        v -= ja[c, r, k] * omg[a, k]
    if b >= 0:
        for m in range(4):
            v += rows[c, r, m] * vel[b, m]
        for k in range(6):
            v += jb[c, r, k] * omg[b, k]
    else:
        for m in range(4):
            v += rows[c, r, m] * surf[c, m]
    return v


@njit(cache=True)
def _apply(c, r, a, b, lam, rows, ja, jb, ija, ijb, vel, omg, inv_mass, iso):
    """Apply impulse ``lam`` along row ``r``: +lam on b, -lam on a."""
    ima = inv_mass[a] * lam
    for m in range(4):
        vel[a, m] -= ima * rows[c, r, m]
    if iso[a] >= 0.0:
        for k in range(6):
            omg[a, k] -= lam * iso[a] * ja[c, r, k]
    else:
        for k in range(6):
            omg[a, k] -= lam * ija[c, r, k]
    if b >= 0:
        imb = inv_mass[b] * lam
        for m in range(4):
            vel[b, m] += imb * rows[c, r, m]
        if iso[b] >= 0.0:
            for k in range(6):
                omg[b, k] += lam * iso[b] * jb[c, r, k]
        else:
            for k in range(6):
                omg[b, k] += lam * ijb[c, r, k]


@njit(cache=True)
def warm_start(nc, contacts, rows_in, bodies, iso):
    """Apply the accumulated impulses so the iterations start near the answer.

    Spin friction is not warm started: it only damps, so it restarts from zero
    each substep.
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    lam = rows_in.impulse
    rows = rows_in.direction
    ja = rows_in.jac_a
    jb = rows_in.jac_b
    ija = rows_in.inv_i_jac_a
    ijb = rows_in.inv_i_jac_b
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_mass = bodies.inv_mass
    slam = rows_in.spin.impulse
    p = np.empty(4)
    for c in range(nc):
        for k in range(6):
            slam[c, k] = 0.0
        a = body_a[c]
        b = body_b[c]
        for m in range(4):
            s = 0.0
            for r in range(4):
                s += lam[c, r] * rows[c, r, m]
            p[m] = s
        for m in range(4):
            vel[a, m] -= inv_mass[a] * p[m]
        ia = ja if iso[a] >= 0.0 else ija
        fa = iso[a] if iso[a] >= 0.0 else 1.0
        for k in range(6):
            s = 0.0
            for r in range(4):
                s += lam[c, r] * ia[c, r, k]
            omg[a, k] -= fa * s
        if b >= 0:
            for m in range(4):
                vel[b, m] += inv_mass[b] * p[m]
            ib = jb if iso[b] >= 0.0 else ijb
            fb = iso[b] if iso[b] >= 0.0 else 1.0
            for k in range(6):
                s = 0.0
                for r in range(4):
                    s += lam[c, r] * ib[c, r, k]
                omg[b, k] += fb * s


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
    nc, contacts, rows_in, bodies, iso, inv_h, use_bias, bias_rate, mass_scale, impulse_scale, max_push, iterations
):
    """Gauss-Seidel sweeps over all contacts: normal, then friction.

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
    ja = rows_in.jac_a
    jb = rows_in.jac_b
    ija = rows_in.inv_i_jac_a
    ijb = rows_in.inv_i_jac_b
    rmass = rows_in.eff_mass
    maxlam = rows_in.max_normal_impulse
    vel = bodies.velocity
    omg = bodies.angular_velocity
    inv_mass = bodies.inv_mass
    spin = rows_in.spin
    slim = spin.limits
    sbv = spin.planes
    sia = spin.inv_i_planes_a
    sib = spin.inv_i_planes_b
    smass = spin.eff_mass
    slam = spin.impulse
    # The two bodies' velocities live in small local arrays while a contact is
    # solved: writing straight into vel/omg would make the compiler reload
    # every Jacobian after each store (it cannot rule out aliasing), which
    # made this loop three times slower.
    va = np.empty(4)
    vb = np.empty(4)
    wa = np.empty(6)
    wb = np.empty(6)
    dl = np.empty(3)
    for _ in range(iterations):
        for c in range(nc):
            a = body_a[c]
            b = body_b[c]
            for m in range(4):
                va[m] = vel[a, m]
            for k in range(6):
                wa[k] = omg[a, k]
            if b >= 0:
                for m in range(4):
                    vb[m] = vel[b, m]
                for k in range(6):
                    wb[k] = omg[b, k]
                imb = inv_mass[b]
            else:
                # The static world: still, or a moving tet mesh's surface (see Contacts).
                for m in range(4):
                    vb[m] = surf[c, m]
                for k in range(6):
                    wb[k] = 0.0
                imb = 0.0
            ima = inv_mass[a]
            R = rows[c]
            JA = ja[c]
            JB = jb[c]
            # Isotropic bodies: I^-1 J = iso * J (see prepare).
            if iso[a] >= 0.0:
                IA = JA
                fa = iso[a]
            else:
                IA = ija[c]
                fa = 1.0
            if b >= 0 and iso[b] < 0.0:
                IB = ijb[c]
                fb = 1.0
            else:
                IB = JB
                fb = iso[b] if b >= 0 else 0.0
            # Normal: a speculative contact (s > 0) may close its gap this
            # substep; an overlapping one is pushed out softly (solve pass only).
            vn = 0.0
            for m in range(4):
                vn += R[0, m] * (vb[m] - va[m])
            for k in range(6):
                vn += JB[0, k] * wb[k] - JA[0, k] * wa[k]
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
            d = new - old
            lam[c, 0] = new
            if new > maxlam[c]:
                maxlam[c] = new
            for m in range(4):
                va[m] -= ima * d * R[0, m]
                vb[m] += imb * d * R[0, m]
            for k in range(6):
                wa[k] -= d * fa * IA[0, k]
            if b >= 0:
                # (The static side's spin stays +0.0 whatever is added to it,
                # since fb is 0 there: skipping it changes no bit.)
                for k in range(6):
                    wb[k] += d * fb * IB[0, k]
            # Friction: one vector impulse lamped to the friction ball.
            limit = cmu[c] * new
            s2 = 0.0
            for r in range(3):
                v = 0.0
                for m in range(4):
                    v += R[r + 1, m] * (vb[m] - va[m])
                for k in range(6):
                    v += JB[r + 1, k] * wb[k] - JA[r + 1, k] * wa[k]
                dl[r] = lam[c, r + 1] - rmass[c, r + 1] * v
                s2 += dl[r] * dl[r]
            if s2 > limit * limit:
                sc = limit / np.sqrt(s2) if s2 > 0.0 else 0.0
                for r in range(3):
                    dl[r] *= sc
            for r in range(3):
                d = dl[r] - lam[c, r + 1]
                lam[c, r + 1] = dl[r]
                for m in range(4):
                    va[m] -= ima * d * R[r + 1, m]
                    vb[m] += imb * d * R[r + 1, m]
                for k in range(6):
                    wa[k] -= d * fa * IA[r + 1, k]
                if b >= 0:
                    for k in range(6):
                        wb[k] += d * fb * IB[r + 1, k]
            sa = sbv if iso[a] >= 0.0 else sia
            sb = sbv if b < 0 or iso[b] >= 0.0 else sib
            for g in range(2):
                if slim[c, g] == 0.0:
                    continue
                limit = slim[c, g] * new
                s2 = 0.0
                for r in range(3):
                    v = 0.0
                    for k in range(6):
                        v += sbv[c, 3 * g + r, k] * (wb[k] - wa[k])
                    dl[r] = slam[c, 3 * g + r] - smass[c, 3 * g + r] * v
                    s2 += dl[r] * dl[r]
                if s2 > limit * limit:
                    sc = limit / np.sqrt(s2) if s2 > 0.0 else 0.0
                    for r in range(3):
                        dl[r] *= sc
                for r in range(3):
                    d = dl[r] - slam[c, 3 * g + r]
                    slam[c, 3 * g + r] = dl[r]
                    for k in range(6):
                        wa[k] -= d * fa * sa[c, 3 * g + r, k]
                    if b >= 0:
                        for k in range(6):
                            wb[k] += d * fb * sb[c, 3 * g + r, k]
            for m in range(4):
                vel[a, m] = va[m]
            for k in range(6):
                omg[a, k] = wa[k]
            if b >= 0:
                for m in range(4):
                    vel[b, m] = vb[m]
                for k in range(6):
                    omg[b, k] = wb[k]


@njit(cache=True)
def restitution(nc, contacts, rows_in, bodies, iso, threshold):
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
    ja = rows_in.jac_a
    jb = rows_in.jac_b
    ija = rows_in.inv_i_jac_a
    ijb = rows_in.inv_i_jac_b
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
        vn = _rel_vel(c, 0, a, b, rows, ja, jb, vel, omg, surf)
        lam = -rmass[c, 0] * (vn + ce[c] * vn0[c])
        new = impulse[c, 0] + lam
        if new < 0.0:
            new = 0.0
        d = new - impulse[c, 0]
        impulse[c, 0] = new
        if d != 0.0:
            _apply(c, 0, a, b, d, rows, ja, jb, ija, ijb, vel, omg, inv_mass, iso)


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
