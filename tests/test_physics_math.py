"""Physics building blocks: bivector kinematics and 4D mass properties."""

import numpy as np
import pytest

from across_dimensions.core import transform
from across_dimensions.physics import bivector, mass


def _rng():
    return np.random.default_rng(1234)


def test_spin_velocity_is_skew_times_r():
    rng = _rng()
    for _ in range(10):
        w = rng.normal(size=6)
        r = rng.normal(size=4)
        out = np.empty(4)
        bivector.spin_velocity(w, r, out)
        np.testing.assert_allclose(out, transform.skew(w) @ r, atol=1e-14)


def test_torque_wedge_is_dual_to_spin_velocity():
    # Power of a force f at r on a body spinning at w: w . (r ^ f) == (W r) . f.
    rng = _rng()
    for _ in range(10):
        w, r, f = rng.normal(size=6), rng.normal(size=4), rng.normal(size=4)
        tau = np.empty(6)
        bivector.wedge(r, f, tau)
        assert w @ tau == pytest.approx((transform.skew(w) @ r) @ f, abs=1e-12)


def test_compound_matrix_rotates_bivectors():
    rng = _rng()
    rot = transform.angles_to_rotation({p: a for p, a in zip(transform.PLANES, rng.normal(size=6))})
    m = np.empty((6, 6))
    bivector.compound(rot, m)
    np.testing.assert_allclose(m @ m.T, np.eye(6), atol=1e-12)
    a, b = rng.normal(size=4), rng.normal(size=4)
    ab, rab = np.empty(6), np.empty(6)
    bivector.wedge(a, b, ab)
    bivector.wedge(rot @ a, rot @ b, rab)
    np.testing.assert_allclose(m @ ab, rab, atol=1e-12)
    # Same as conjugating the skew matrix.
    np.testing.assert_allclose(transform.skew(m @ ab), rot @ transform.skew(ab) @ rot.T, atol=1e-12)


@pytest.mark.parametrize("scale", [0.01, 1.0, 7.0])
def test_expm_skew_matches_core_bivector_rotation(scale):
    w = _rng().normal(size=6) * scale
    out = np.empty((4, 4))
    bivector.expm_skew(w, 0.3, out, np.empty((3, 4, 4)))
    np.testing.assert_allclose(out, transform.bivector_rotation(w, 0.3), atol=1e-12)
    assert transform.orthonormality_error(out) < 1e-13


def test_tangent_basis_is_orthonormal_complement():
    rng = _rng()
    for _ in range(20):
        n = rng.normal(size=4)
        n /= np.linalg.norm(n)
        t = np.empty((3, 4))
        bivector.tangent_basis(n, t)
        frame = np.vstack([n, t])
        np.testing.assert_allclose(frame @ frame.T, np.eye(4), atol=1e-12)


def test_hypersphere_inertia_by_sampling():
    # Uniform points in the 4-ball: the plane inertia is m E[x_i^2 + x_j^2].
    rng = _rng()
    r = 0.7
    pts = rng.uniform(-r, r, size=(400_000, 4))
    pts = pts[np.linalg.norm(pts, axis=1) <= r]
    sampled = np.mean(pts[:, 0] ** 2 + pts[:, 3] ** 2)
    assert sampled == pytest.approx(mass.hypersphere_inertia(1.0, r)[3], rel=0.01)
    assert mass.hypersphere_inertia(2.0, r)[0] == pytest.approx(2.0 * r * r / 3.0)
    # Volume pi^2 r^4 / 2: the fraction of the cube the ball fills.
    assert pts.shape[0] / 400_000 == pytest.approx(mass.hypersphere_volume(r) / (2 * r) ** 4, rel=0.01)


def test_box_inertia_by_sampling():
    rng = _rng()
    half = np.array([0.5, 0.2, 0.3, 0.8])
    pts = rng.uniform(-half, half, size=(200_000, 4))
    inertia = mass.box_inertia(1.0, half)
    for k, (i, j) in enumerate(zip(bivector.PLANE_I, bivector.PLANE_J)):
        assert np.mean(pts[:, i] ** 2 + pts[:, j] ** 2) == pytest.approx(inertia[k], rel=0.01)
    assert mass.box_volume(half) == pytest.approx(np.prod(2 * half))


def test_stable_argsort_matches_numpy():
    from across_dimensions.physics.sorting import argsort_stable

    rng = _rng()
    for n in (0, 1, 2, 7, 64, 1000):
        keys = rng.integers(0, 20, size=n).astype(np.int64)
        np.testing.assert_array_equal(argsort_stable(keys), np.argsort(keys, kind="stable"))
        fkeys = rng.normal(size=n)
        np.testing.assert_array_equal(argsort_stable(fkeys), np.argsort(fkeys, kind="stable"))
