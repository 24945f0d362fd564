"""5x5 transforms: properties against linear algebra, and drift of composed rotations."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from across_dimensions.core import transform as T

angle = st.floats(-np.pi, np.pi, allow_nan=False)
angles6 = st.fixed_dictionaries({p: angle for p in T.PLANES})
coord = st.floats(-100, 100, allow_nan=False)
vec4 = st.lists(coord, min_size=4, max_size=4)
scale4 = st.lists(st.floats(0.05, 20), min_size=4, max_size=4)


@given(angles6)
def test_rotation_is_proper_orthonormal(a):
    r = T.angles_to_rotation(a)
    assert T.orthonormality_error(r) < 1e-12
    assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-12)


@given(angles6)
def test_angles_round_trip_gives_same_rotation(a):
    r = T.angles_to_rotation(a)
    back = T.rotation_to_angles(r)
    assert np.allclose(T.angles_to_rotation(back), r, atol=1e-10)


@given(st.fixed_dictionaries({p: st.floats(-1.2, 1.2) for p in T.PLANES}))
def test_small_angles_come_back_exactly(a):
    # Within (-pi/2, pi/2) the Givens decomposition is unique: the angles themselves return.
    back = T.rotation_to_angles(T.angles_to_rotation(a))
    for p in T.PLANES:
        assert back[p] == pytest.approx(a[p], abs=1e-9)


@pytest.mark.parametrize("plane", T.PLANES)
def test_single_plane_rotation_turns_first_axis_towards_second(plane):
    i, j = "xyzw".index(plane[0]), "xyzw".index(plane[1])
    e = np.zeros(4)
    e[i] = 1.0
    out = T.apply(T.rotation(plane, np.pi / 2), e)
    expected = np.zeros(4)
    expected[j] = 1.0
    assert np.allclose(out, expected, atol=1e-15)
    # Axes outside the plane do not move.
    for k in set(range(4)) - {i, j}:
        e = np.zeros(4)
        e[k] = 1
        assert np.allclose(T.apply(T.rotation(plane, 0.7), e), e)


@given(vec4, angles6, scale4, st.lists(vec4, min_size=1, max_size=5))
def test_inverse_undoes_pose(position, a, scale, points):
    m = T.pose(position, a, scale)
    p = np.asarray(points)
    assert np.allclose(T.apply(T.inverse(m), T.apply(m, p)), p, atol=1e-6)
    assert np.allclose(T.inverse(m) @ m, np.eye(5), atol=1e-9)


@given(vec4, angles6, scale4)
def test_decompose_recovers_pose(position, a, scale):
    m = T.pose(position, a, scale)
    pos, ang, sc = T.decompose(m)
    assert np.allclose(pos, position)
    assert np.allclose(sc, scale, rtol=1e-9)
    assert np.allclose(T.pose(pos, ang, sc), m, atol=1e-8)


@given(angles6, angles6, vec4)
def test_composition_is_application_in_sequence(a, b, p):
    ma, mb = T.pose([1, 2, 3, 4], a, [1, 2, 0.5, 3]), T.pose([0, -1, 0, 2], b)
    assert np.allclose(T.apply(T.compose(ma, mb), p), T.apply(ma, T.apply(mb, p)), atol=1e-8)


@given(angles6, vec4)
def test_rigid_inverse_matches_general_inverse(a, position):
    m = T.pose(position, a)
    assert np.allclose(T.rigid_inverse(m), T.inverse(m), atol=1e-10)


def _general_inverse(m):
    """:func:`T.inverse`'s general path (LAPACK's inverse of the linear part)."""
    out = np.eye(5)
    inv = np.linalg.inv(m[:4, :4])
    out[:4, :4] = inv
    out[:4, 4] = -inv @ m[:4, 4]
    return out


@pytest.mark.parametrize(
    "t", [(0.0, 0.0, 0.0, 0.013), (1.5, -2.0, 0.0, -0.5), (-0.0, 0.0, -0.0, 0.0), (3e-17, -1e300, 7.0, -0.0)]
)
def test_inverse_of_a_translation_is_the_general_paths_bits(t):
    # The fast path for a plain slice's pose must give the very bits the general one gives
    # (zeros' signs included): sections and replays are compared bit for bit.
    m = T.translation(t)
    assert T.inverse(m).tobytes() == _general_inverse(m).tobytes()
    assert (T.inverse(m) @ m == np.eye(5)).all()


def test_hyper_depth_scaling_scales_only_w():
    p = np.array([[1.0, 2.0, 3.0, 4.0]])
    assert np.allclose(T.apply(T.scaling([1, 1, 1, 2.5]), p), [[1, 2, 3, 10]])


@settings(deadline=None)  # the first example imports scipy (a third of a second), run alone
@given(st.lists(st.floats(-3, 3), min_size=6, max_size=6), st.floats(0.01, 2))
def test_bivector_rotation_is_exponential_of_skew(omega, dt):
    from scipy.linalg import expm

    r = T.bivector_rotation(omega, dt)
    assert np.allclose(r, expm(T.skew(omega) * dt), atol=1e-10)
    assert np.allclose(T.unskew(T.skew(omega)), omega)


def test_million_composed_small_rotations_stay_orthonormal():
    # One million random small rotations composed (as a balanced product tree,
    # batched) drift measurably from orthonormal in float64; one
    # re-orthonormalization brings the result back within 1e-6.
    rng = np.random.default_rng(7)
    n = 1 << 20
    omega = rng.normal(scale=1e-3, size=(n, 6))
    a = T.skew(omega)
    # Second-order approximations of expm: deliberately not exactly orthonormal,
    # like an integrator's update, so there is drift to remove.
    r = np.eye(4) + a + 0.5 * a @ a
    per_step = T.orthonormality_error(r[:1000])
    assert per_step > 1e-13
    while len(r) > 1:
        r = r[0::2] @ r[1::2]
    drifted = T.orthonormality_error(r[0])
    assert drifted > 1e-9  # the drift is real
    fixed = T.orthonormalize(r[0])
    assert T.orthonormality_error(fixed) < 1e-6
    assert np.linalg.det(fixed) == pytest.approx(1.0)


def test_orthonormalize_keeps_proper_rotation_close():
    rng = np.random.default_rng(1)
    r = T.angles_to_rotation({p: rng.uniform(-3, 3) for p in T.PLANES})
    noisy = r + rng.normal(scale=1e-4, size=(4, 4))
    fixed = T.orthonormalize(noisy)
    assert T.orthonormality_error(fixed) < 1e-12
    assert np.abs(fixed - r).max() < 1e-3


@pytest.mark.parametrize(
    "bad, kind", [(["xq=3"], "plane"), (["xw=abc"], "plane"), (["w0.3"], "axis"), (["v=1"], "axis")]
)
def test_parse_axis_assignments_rejects_bad_items(bad, kind):
    with pytest.raises(ValueError, match=bad[0].split("=")[0]):
        T.parse_axis_assignments(bad, kind)


def test_parse_axis_assignments_sums_repeats():
    assert T.parse_axis_assignments(["xw=30", "yw=10", "xw=5"], "plane") == {"xw": 35.0, "yw": 10.0}
