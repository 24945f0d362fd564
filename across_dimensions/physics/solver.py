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

Per substep (Box2D v3's "soft step" without the springs): warm start, solve
with a Baumgarte bias that pushes overlapping bodies apart, move the bodies,
then relax without the bias so that the push-out speed is not kept as momentum,
and finally apply restitution from the approach speed measured before solving.

Arrays use ``b = -1 - s`` for a contact against static world collider ``s``:
those rows have no second body.
"""

from __future__ import annotations

import numpy as np

from across_dimensions.core._jit import njit

from .bivector import mat6_vec, tangent_basis, wedge


@njit(cache=True)
def prepare(nc, ci, cp, cn, cd, clam, cft, cmu, ce, pos, rot, vel, omg, inv_mass, iinv,
            bound, mu, rest, world_mu, world_e, ok, oloc, olam, oft, ocnt,
            rows, ja, jb, ija, ijb, rmass, vn0, maxlam, cloc):
    """Build the solver rows of every contact and warm start them from last substep.

    Parameters
    ----------
    nc : int
        Number of contacts.
    ci : (C, 3) int64
        Body a, body b (or ``-1 - static``), pair key.
    cp, cn : (C, 4) float64
        Contact points and normals (a to b).
    cd : (C,) float64
        Depths.
    clam : (C, 4) float64
        Output: accumulated impulses (normal, three tangents), warm-started.
    cft : (C, 4) float64
        Unused on input; scratch for the friction impulse vector.
    cmu, ce : (C,) float64
        Output: mixed friction and restitution.
    pos, rot, vel, omg : body arrays
    inv_mass : (N,) float64
    iinv : (N, 6, 6) float64
        World-frame inverse inertias (zero for non-dynamic bodies).
    bound : (N,) float64
        Bounding radii, used to scale the warm-start matching distance.
    mu, rest : (N,) float64
    world_mu, world_e : float
    ok : (C,) int64
        Keys of last substep's contacts (sorted).
    oloc : (C, 4) float64
        Their points in body a's frame.
    olam : (C,) float64
    oft : (C, 4) float64
        Their normal impulses and friction impulse vectors.
    ocnt : int
    rows : (C, 4, 4) float64
        Output: row directions (normal, tangents).
    ja, jb, ija, ijb : (C, 4, 6) float64
        Output: angular Jacobians ``r ^ d`` and their images under ``I^-1``.
    rmass : (C, 4) float64
        Output: effective masses.
    vn0 : (C,) float64
        Output: normal relative velocity before solving (for restitution).
    maxlam : (C,) float64
        Output: zeroed; largest normal impulse seen while solving.
    cloc : (C, 4) float64
        Output: contact points in body a's frame (for next substep's matching).
    """
    ra = np.empty(4)
    rb = np.empty(4)
    tb = np.empty((3, 4))
    wtmp = np.empty(6)
    for c in range(nc):
        a = ci[c, 0]
        b = ci[c, 1]
        for m in range(4):
            ra[m] = cp[c, m] - pos[a, m]
            rows[c, 0, m] = cn[c, m]
        if b >= 0:
            for m in range(4):
                rb[m] = cp[c, m] - pos[b, m]
            cmu[c] = np.sqrt(mu[a] * mu[b])
            ce[c] = max(rest[a], rest[b])
            imb = inv_mass[b]
        else:
            cmu[c] = np.sqrt(mu[a] * world_mu)
            ce[c] = max(rest[a], world_e)
            imb = 0.0
        tangent_basis(cn[c], tb)
        for r in range(3):
            for m in range(4):
                rows[c, r + 1, m] = tb[r, m]
        for r in range(4):
            wedge(ra, rows[c, r], wtmp)
            for k in range(6):
                ja[c, r, k] = wtmp[k]
            mat6_vec(iinv[a], ja[c, r], wtmp)
            kk = inv_mass[a] + imb
            for k in range(6):
                ija[c, r, k] = wtmp[k]
                kk += ja[c, r, k] * wtmp[k]
            if b >= 0:
                wedge(rb, rows[c, r], wtmp)
                for k in range(6):
                    jb[c, r, k] = wtmp[k]
                mat6_vec(iinv[b], jb[c, r], wtmp)
                for k in range(6):
                    ijb[c, r, k] = wtmp[k]
                    kk += jb[c, r, k] * wtmp[k]
            else:
                for k in range(6):
                    jb[c, r, k] = 0.0
                    ijb[c, r, k] = 0.0
            rmass[c, r] = 1.0 / kk if kk > 0.0 else 0.0
        vn0[c] = _rel_vel(c, 0, a, b, rows, ja, jb, vel, omg)
        maxlam[c] = 0.0
        # Contact point in a's frame: the same material point next substep.
        for m in range(4):
            s = 0.0
            for q in range(4):
                s += rot[a, q, m] * ra[q]
            cloc[c, m] = s
        # Warm start from the nearest old contact of the same pair.
        for r in range(4):
            clam[c, r] = 0.0
        lo = 0
        hi = ocnt
        key = ci[c, 2]
        while lo < hi:
            mid = (lo + hi) // 2
            if ok[mid] < key:
                lo = mid + 1
            else:
                hi = mid
        tol = 0.1 * bound[a]
        best = tol * tol
        pick = -1
        j = lo
        while j < ocnt and ok[j] == key:
            d2 = 0.0
            for m in range(4):
                t = oloc[j, m] - cloc[c, m]
                d2 += t * t
            if d2 < best:
                best = d2
                pick = j
            j += 1
        if pick >= 0:
            clam[c, 0] = olam[pick]
            for r in range(3):
                s = 0.0
                for m in range(4):
                    s += oft[pick, m] * tb[r, m]
                clam[c, r + 1] = s


@njit(cache=True)
def _rel_vel(c, r, a, b, rows, ja, jb, vel, omg):
    """Relative velocity of b with respect to a along row ``r`` of contact ``c``."""
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
    return v


@njit(cache=True)
def _apply(c, r, a, b, lam, rows, ija, ijb, vel, omg, inv_mass):
    """Apply impulse ``lam`` along row ``r``: +lam on b, -lam on a."""
    ima = inv_mass[a] * lam
    for m in range(4):
        vel[a, m] -= ima * rows[c, r, m]
    for k in range(6):
        omg[a, k] -= lam * ija[c, r, k]
    if b >= 0:
        imb = inv_mass[b] * lam
        for m in range(4):
            vel[b, m] += imb * rows[c, r, m]
        for k in range(6):
            omg[b, k] += lam * ijb[c, r, k]


@njit(cache=True)
def warm_start(nc, ci, clam, rows, ija, ijb, vel, omg, inv_mass):
    """Apply last substep's impulses so the iterations start near the answer."""
    for c in range(nc):
        for r in range(4):
            if clam[c, r] != 0.0:
                _apply(c, r, ci[c, 0], ci[c, 1], clam[c, r], rows, ija, ijb, vel, omg, inv_mass)


@njit(cache=True)
def solve(nc, ci, cd, clam, cmu, rows, ja, jb, ija, ijb, rmass, maxlam, vel, omg,
          inv_mass, inv_h, use_bias, beta, slop, max_bias, iterations):
    """Gauss-Seidel sweeps over all contacts: friction first, then the normal.

    Parameters
    ----------
    use_bias : bool
        True for the solve pass (push overlapping bodies apart at
        ``beta * overlap / h``, at most ``max_bias``), False for the relax pass.
    iterations : int
    """
    dl = np.empty(3)
    for _ in range(iterations):
        for c in range(nc):
            a = ci[c, 0]
            b = ci[c, 1]
            # Friction: one vector impulse clamped to the friction ball.
            limit = cmu[c] * clam[c, 0]
            s2 = 0.0
            for r in range(3):
                vt = _rel_vel(c, r + 1, a, b, rows, ja, jb, vel, omg)
                dl[r] = clam[c, r + 1] - rmass[c, r + 1] * vt
                s2 += dl[r] * dl[r]
            if s2 > limit * limit:
                sc = limit / np.sqrt(s2)
                for r in range(3):
                    dl[r] *= sc
            for r in range(3):
                d = dl[r] - clam[c, r + 1]
                clam[c, r + 1] = dl[r]
                if d != 0.0:
                    _apply(c, r + 1, a, b, d, rows, ija, ijb, vel, omg, inv_mass)
            # Normal: speculative contacts may close their gap this substep;
            # overlapping ones are pushed apart (solve pass only).
            vn = _rel_vel(c, 0, a, b, rows, ja, jb, vel, omg)
            sep = -cd[c]
            if sep > 0.0:
                bias = sep * inv_h
            elif use_bias:
                bias = beta * inv_h * min(0.0, sep + slop)
                if bias < -max_bias:
                    bias = -max_bias
            else:
                bias = 0.0
            lam = -rmass[c, 0] * (vn + bias)
            new = clam[c, 0] + lam
            if new < 0.0:
                new = 0.0
            d = new - clam[c, 0]
            clam[c, 0] = new
            if new > maxlam[c]:
                maxlam[c] = new
            if d != 0.0:
                _apply(c, 0, a, b, d, rows, ija, ijb, vel, omg, inv_mass)


@njit(cache=True)
def restitution(nc, ci, clam, ce, rows, ja, jb, ija, ijb, rmass, vn0, maxlam, vel, omg,
                inv_mass, threshold):
    """Bounce: drive the normal velocity to ``-e * vn0`` for contacts that were hit.

    Only contacts approaching faster than ``threshold`` and that actually pushed
    (a speculative contact that never engaged must not bounce early).
    """
    for c in range(nc):
        if ce[c] == 0.0 or vn0[c] > -threshold or maxlam[c] == 0.0:
            continue
        a = ci[c, 0]
        b = ci[c, 1]
        vn = _rel_vel(c, 0, a, b, rows, ja, jb, vel, omg)
        lam = -rmass[c, 0] * (vn + ce[c] * vn0[c])
        new = clam[c, 0] + lam
        if new < 0.0:
            new = 0.0
        d = new - clam[c, 0]
        clam[c, 0] = new
        if d != 0.0:
            _apply(c, 0, a, b, d, rows, ija, ijb, vel, omg, inv_mass)


@njit(cache=True)
def store(nc, ci, clam, rows, cloc, ok, oloc, olam, oft):
    """Keep this substep's impulses, keyed by pair, for the next warm start.

    Returns
    -------
    int
        Number of stored contacts (``nc``).
    """
    for c in range(nc):
        ok[c] = ci[c, 2]
        olam[c] = clam[c, 0]
        for m in range(4):
            oloc[c, m] = cloc[c, m]
            s = 0.0
            for r in range(3):
                s += clam[c, r + 1] * rows[c, r + 1, m]
            oft[c, m] = s
    return nc
