"""Contact preparation: the solver rows of a tick's contacts, warm started from the last tick.

Once per tick, before the substeps: each body's world-frame inverse inertia
(:func:`world_inertia`), then for every contact its four rows (the normal and
three tangents, see :mod:`.solver`) with their effective masses, its ``K n``
response, its approach speed (for restitution), its material and the impulses
of the nearest contact of the same pair last tick (:func:`prepare`); contacts
of a ball also get spin-friction and rolling rows (:func:`prepare_spins`).
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import PLANE_I, PLANE_J, tangent_frame, world_inverse_inertia
from .borrow import borrowed, keep
from .scalars import axpy4, dot4, load4, load6, point_velocity, spin_change, store4, sub4, wedge, wedge_into
from .state import DYNAMIC, Inertia


@njit(cache=True)
def world_inertia(bodies):
    """The awake dynamic bodies' world-frame inverse inertias (zero for the others).

    Returns
    -------
    Inertia
        ``full`` the operators, ``iso`` the scalar where the operator is
        isotropic (balls, hypercubes, non-dynamic bodies at 0), else -1.
    """
    nb = bodies.count
    alive = bodies.alive
    kind = bodies.kind
    rot = bodies.rotation
    inv_inertia = bodies.inv_inertia
    awake = bodies.awake
    iinv = np.zeros((nb, 6, 6))
    iso = np.zeros(nb)
    for i in range(nb):
        if alive[i] and kind[i] == DYNAMIC and awake[i]:
            world_inverse_inertia(rot[i], inv_inertia[i], iinv[i])
            iso[i] = inv_inertia[i, 0]
            for k in range(1, 6):
                if inv_inertia[i, k] != inv_inertia[i, 0]:
                    iso[i] = -1.0
    return Inertia(iso, iinv)


# size: one hot loop over the contacts (split into helpers taking arrays, it ran five times slower)
@njit(cache=True)
def prepare(nc, contacts, bodies, inertia, prm, warm, rows_out):
    """Build the solver rows of every contact and warm start them from the last tick.

    Parameters
    ----------
    nc : int
        Number of contacts (sorted by pair key).
    contacts : Contacts
    bodies : Bodies
    inertia : Inertia
        From :func:`world_inertia`.
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
    keys = contacts.key
    iso = inertia.iso
    iinv = inertia.full
    world_mu = prm.world_friction
    world_e = prm.world_restitution
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
                wedge_into(ra, tb, r, wa)
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
                    wedge_into(rb, tb, r, wb)
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
        ka = spin_change(a, iso, iinv, wedge(pa, n))
        kn = axpy4(inv_mass[a] + imb, n, point_velocity((0.0, 0.0, 0.0, 0.0), ka, pa))
        if b >= 0:
            kb = spin_change(b, iso, iinv, wedge(pb, n))
            kn = point_velocity(kn, kb, pb)
        store4(resp, c, kn)
        # The approach speed, for restitution.
        u = point_velocity(load4(vel, b), load6(omg, b), pb) if b >= 0 else load4(surf, c)
        vn = dot4(n, sub4(u, point_velocity(load4(vel, a), load6(omg, a), pa)))
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
    prepare_spins(nc, contacts, bodies, inertia, prm, rows_out)


@njit(cache=True)
def prepare_spins(nc, contacts, bodies, inertia, prm, rows_out):
    """Spin friction and rolling resistance of the contacts involving a ball.

    A ball touching at one point can spin freely in the three planes of the
    contact hyperplane (``t_i ^ t_j``) - point friction has no lever there -
    so a ball in a pile could twirl forever and never sleep. A real contact is
    a small patch; its friction resists that spin with a torque of at most
    ``mu * N * spin_radius * r``. Rolling (the planes ``n ^ t_k``) is resisted
    by at most ``rolling * N * r``. Rows: the unit bivectors acting on the
    relative angular velocity, three per group.

    Reads the row directions and friction of ``rows_out`` (:func:`prepare`), fills
    ``rows_out.spin`` (limits 0 for contacts without a ball). One loop with the
    arrays taken out once: a call per contact would cost a reference count per array.
    """
    body_a = contacts.body_a
    body_b = contacts.body_b
    frames = rows_out.direction
    friction = rows_out.friction
    shape = bodies.shape
    bound = bodies.bound
    iso = inertia.iso
    iinv = inertia.full
    spin_radius = prm.spin_friction
    rolling = prm.rolling_resistance
    spin = rows_out.spin
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
