"""The tick's speed-ups change nothing: the broadphase sweep finds exactly the overlapping pairs,
the linear pair sort orders exactly as the merge sort, and borrowed arrays are the same data."""

import numpy as np

from across_dimensions.core._jit import njit
from across_dimensions.physics import bivector, pipeline, sorting
from across_dimensions.physics.borrow import borrowed, keep


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
        got = pipeline._sweep(order, slo, shi, dyn[order].copy(), ax, cand)
        assert got == len(want)
        assert {(int(i), int(j)) for i, j in cand[:got]} == want
        # Too small a buffer is reported, never overrun.
        small = np.full((len(want) // 2, 2), -7, np.int64)
        assert pipeline._sweep(order, slo, shi, dyn[order].copy(), ax, small) == -1


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
