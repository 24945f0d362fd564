"""The tick's speed-ups change nothing: the broadphase sweep finds exactly the overlapping pairs,
the linear pair sort orders exactly as the merge sort, and borrowed arrays are the same data."""

import numpy as np

from across_dimensions.core._jit import njit
from across_dimensions.physics import bivector, broadphase, narrowphase, sorting
from across_dimensions.physics.borrow import borrowed, keep
from across_dimensions.physics.state import DYNAMIC, Inertia


def test_argsort_by_body_matches_the_stable_merge_sort():
    rng = np.random.default_rng(5)
    for n, nb, nbody_b in ((0, 4, 4), (1, 3, 3), (500, 40, 6), (3000, 200, 300)):
        a = rng.integers(0, nb, n)
        keys = (a << 32) | rng.integers(0, nbody_b, n)  # few distinct b: many ties
        order = sorting.argsort_by_body(keys, a, nb)
        assert np.array_equal(order, sorting.argsort_stable(keys))


def _brute_pairs(lo, hi, dyn):
    n = lo.shape[0]
    out = set()
    for i in range(n):
        for j in range(i + 1, n):
            if (dyn[i] or dyn[j]) and np.all(lo[i] <= hi[j]) and np.all(lo[j] <= hi[i]):
                out.add((i, j))
    return out


def test_sweep_finds_exactly_the_overlapping_pairs_and_survives_a_small_buffer():
    rng = np.random.default_rng(7)
    n = 300
    centre = rng.uniform(0.0, 3.0, (n, 4))
    ext = rng.uniform(0.05, 0.4, (n, 4))
    lo, hi = centre - ext, centre + ext
    dyn = rng.random(n) < 0.8
    want = _brute_pairs(lo, hi, dyn)
    assert len(want) > 100
    for ax in range(4):
        order = sorting.argsort_stable(lo[:, ax].copy())
        slo = np.ascontiguousarray(lo[order].T)
        shi = np.ascontiguousarray(hi[order].T)
        cand = np.empty((len(want) + 5, 2), np.int64)
        got = broadphase._sweep(order, slo, shi, dyn[order].copy(), ax, cand)
        assert got == len(want)
        assert {(int(i), int(j)) for i, j in cand[:got]} == want
        # Too small a buffer is reported, never overrun.
        small = np.full((len(want) // 2, 2), -7, np.int64)
        assert broadphase._sweep(order, slo, shi, dyn[order].copy(), ax, small) == -1


@njit
def _write_through_borrowed(a):
    own = np.zeros(3)
    b = borrowed(a)
    w = borrowed(own)
    for i in range(a.shape[0]):
        b[i] += 1.0
        w[i % 3] += b[i]
    keep(own)
    return own


def test_borrowed_arrays_are_the_same_data():
    a = np.arange(6.0)
    own = _write_through_borrowed(a)
    assert np.array_equal(a, np.arange(6.0) + 1.0)
    assert np.array_equal(own, [1.0 + 4.0, 2.0 + 5.0, 3.0 + 6.0])


def test_tangent_frame_is_tangent_basis():
    rng = np.random.default_rng(3)
    for _ in range(50):
        n = rng.normal(size=4)
        n[rng.integers(0, 4)] = 0.0  # ties among the smallest components too
        n /= np.linalg.norm(n)
        f = np.zeros((4, 4))
        f[0] = n
        _tangent_frame(f)
        t = np.empty((3, 4))
        bivector.tangent_basis(n, t)
        assert np.array_equal(f[1:], t)  # the same arithmetic, bit for bit


@njit
def _tangent_frame(f):
    bivector.tangent_frame(f)


def test_solver_tuple_helpers_match_the_bivector_routines():
    from across_dimensions.physics import scalars

    rng = np.random.default_rng(11)
    for _ in range(20):
        w, r, p = rng.normal(size=6), rng.normal(size=4), rng.normal(size=4)
        want_v, want_b = np.empty(4), np.empty(6)
        bivector.spin_velocity(w, r, want_v)
        bivector.wedge(r, p, want_b)
        np.testing.assert_allclose(scalars.spin_velocity(*w, *r), want_v, atol=1e-14)
        np.testing.assert_allclose(scalars.wedge(tuple(r), tuple(p)), want_b, atol=1e-14)


def test_prepared_rows_match_the_contact_jacobians():
    """The solver's effective masses and normal response, computed from ``|r|^2 - (r.d)^2`` and
    point velocities, against the Jacobian definition ``J M^-1 J^T`` of every row pair, for a
    pile with anisotropic boxes (full inverse inertias) as well as hypercubes and balls."""
    from across_dimensions.physics.bench import build_pile
    from across_dimensions.physics.body_def import BodyDef
    from across_dimensions.physics.prepare import prepare

    world = build_pile(60, seed=3)
    for k in range(8):
        world.add_body(BodyDef("box", size=(0.6, 0.3, 0.4, 0.2), position=(0.3 * k - 1.0, 3.0, 0.2, 0.1 * k - 0.4)))
    for _ in range(90):
        world.step(1.0 / 60.0)
    b, prm = world.bodies, world.params[0]
    npairs = broadphase.find_pairs(
        b, world.static, prm["tick_dt"], prm["margin"], world._scratch.pairs, world._scratch.margin
    )
    kept = world._kept
    prm_off = world.params.copy()
    prm_off["reuse_angle"] = 0.0
    nc = narrowphase.narrowphase(npairs, b, world.static, world._scratch, world.contacts, kept[0], kept[1], prm_off[0])
    nb = b.count
    iinv = np.zeros((nb, 6, 6))
    iso = np.zeros(nb)
    for i in range(nb):
        if b.alive[i] and b.kind[i] == DYNAMIC and b.awake[i]:
            bivector.world_inverse_inertia(b.rotation[i], b.inv_inertia[i], iinv[i])
            ii = b.inv_inertia[i]
            iso[i] = ii[0] if np.all(ii == ii[0]) else -1.0
    assert (iso < 0).sum() == 8 and nc > 100
    rows = world._rows
    prepare(nc, world.contacts, b, Inertia(iso, iinv), prm, world.warm, rows)
    ab = world.contacts.body_a[:nc], world.contacts.body_b[:nc]
    aniso = 0
    for c in range(nc):
        a, o = ab[0][c], ab[1][c]
        d = rows.direction[c]
        m_inv = np.zeros((20, 20))
        m_inv[:4, :4] = b.inv_mass[a] * np.eye(4)
        m_inv[4:10, 4:10] = iinv[a]
        jac = np.zeros((4, 20))
        for r in range(4):
            wa, wb = np.empty(6), np.empty(6)
            bivector.wedge(rows.anchor_a[c], d[r], wa)
            jac[r, :4], jac[r, 4:10] = -d[r], -wa
            if o >= 0:
                bivector.wedge(rows.anchor_b[c], d[r], wb)
                jac[r, 10:14], jac[r, 14:] = d[r], wb
        if o >= 0:
            m_inv[10:14, 10:14] = b.inv_mass[o] * np.eye(4)
            m_inv[14:, 14:] = iinv[o]
        k = jac @ m_inv @ jac.T
        np.testing.assert_allclose(1.0 / rows.eff_mass[c], np.diag(k), rtol=1e-10)
        np.testing.assert_allclose(d @ rows.normal_response[c], k[:, 0], rtol=1e-10, atol=1e-12)
        aniso += iso[a] < 0 or (o >= 0 and iso[o] < 0)
    assert aniso > 10


def test_expm_skew_matches_a_reference_exponential():
    from scipy.linalg import expm

    from across_dimensions.core import transform

    rng = np.random.default_rng(2)
    cases = [rng.normal(size=6) * s for s in (1e-6, 0.01, 0.3, 2.0, 40.0)]
    cases += [np.array([1.0, 0, 0, 0, 0, 1.0]), np.array([0.5, 0, 0, 0, 0, -0.5])]  # isoclinic
    cases += [np.zeros(6), np.array([0, 0, 3.0, 0, 0, 0])]
    for w in cases:
        out = np.empty((4, 4))
        transform.expm_skew(w, 0.37, out, np.empty((3, 4, 4)))
        want = expm(0.37 * transform.skew(w))
        np.testing.assert_allclose(out, want, atol=1e-13 * max(1.0, np.abs(w).sum()))
        assert transform.orthonormality_error(out) < 1e-12
