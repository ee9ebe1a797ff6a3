"""The clearance kernel on NumPy batches (``parasils.segment_distance_mm``)
against an independent NumPy brute force, hand-derived cases, and its
errors. Needs no collision library (the comparison with coal is
``benches/python/clearance_vs_coal.py``)."""

import numpy as np
import pytest

import parasils

RNG = np.random.default_rng(27)


def brute_force(a0, a1, b0, b1, n=401):
    """The smallest distance over an n x n grid of parameters of each pair,
    refined by a second grid around the best cell, and the bound on how far
    below it the true minimum can be (half the finer step along each
    segment)."""
    out = np.empty(len(a0))
    slack = np.empty(len(a0))
    for k in range(len(a0)):
        u, v = a1[k] - a0[k], b1[k] - b0[k]
        lo_s, hi_s, lo_t, hi_t = 0.0, 1.0, 0.0, 1.0
        for _ in range(2):
            s = np.linspace(lo_s, hi_s, n)
            t = np.linspace(lo_t, hi_t, n)
            pa = a0[k] + s[:, None] * u  # (n, 3)
            pb = b0[k] + t[:, None] * v
            d = np.linalg.norm(pa[:, None, :] - pb[None, :, :], axis=2)
            i, j = np.unravel_index(np.argmin(d), d.shape)
            best = d[i, j]
            hs, ht = (hi_s - lo_s) / (n - 1), (hi_t - lo_t) / (n - 1)
            lo_s, hi_s = max(0.0, s[i] - hs), min(1.0, s[i] + hs)
            lo_t, hi_t = max(0.0, t[j] - ht), min(1.0, t[j] + ht)
        out[k] = best
        slack[k] = 0.5 * (hs * np.linalg.norm(u) + ht * np.linalg.norm(v))
    return out, slack


def test_random_pairs_match_the_brute_force():
    n = 60
    a0, a1, b0, b1 = (RNG.uniform(-100, 100, (n, 3)) for _ in range(4))
    # A third of them points, a third nearly parallel.
    b1[: n // 3] = b0[: n // 3]
    turn = RNG.normal(0, 1e-6, (n // 3, 3))
    u = a1[n // 3 : 2 * n // 3] - a0[n // 3 : 2 * n // 3]
    b1[n // 3 : 2 * n // 3] = b0[n // 3 : 2 * n // 3] + u + np.cross(turn, u)
    d, pa, pb = parasils.segment_distance_mm(a0, a1, b0, b1)
    assert d.shape == (n,) and pa.shape == (n, 3) and pb.shape == (n, 3)
    truth, slack = brute_force(a0, a1, b0, b1)
    assert np.all(d <= truth + 1e-12)
    assert np.all(d >= truth - slack - 1e-12)
    # The points are the segments' and the distance is theirs.
    np.testing.assert_allclose(np.linalg.norm(pa - pb, axis=1), d, rtol=0, atol=1e-12)
    for p, s0, s1 in ((pa, a0, a1), (pb, b0, b1)):
        w = s1 - s0
        along = np.einsum("ij,ij->i", p - s0, w) / np.maximum(np.einsum("ij,ij->i", w, w), 1e-300)
        assert np.all((along >= -1e-12) & (along <= 1 + 1e-12))
        off = np.linalg.norm(p - (s0 + along[:, None] * w), axis=1)
        assert np.all(off <= 1e-10)


def test_hand_derived_cases_single_rows():
    # Crossing at right angles one unit apart, half way along each.
    d, pa, pb = parasils.segment_distance_mm([0, 0, 0], [2, 0, 0], [1, -1, 1], [1, 1, 1])
    assert d == 1.0 and list(pa) == [1, 0, 0] and list(pb) == [1, 0, 1]
    # Parallel, overlapping, 2 apart; collinear, 2 apart; point to point, 5.
    assert parasils.segment_distance_mm([0, 0, 0], [4, 0, 0], [1, 2, 0], [6, 2, 0])[0] == 2.0
    assert parasils.segment_distance_mm([0, 0, 0], [1, 0, 0], [3, 0, 0], [5, 0, 0])[0] == 2.0
    assert parasils.segment_distance_mm([1, 2, 3], [1, 2, 3], [4, 6, 3], [4, 6, 3])[0] == 5.0
    # Near-parallel lines crossing in the middle: 0, while their ends are
    # delta apart.
    for delta in (1e-4, 1e-8, 1e-12):
        d = parasils.segment_distance_mm([0, 0, 0], [100, 0, 0], [0, -delta, 0], [100, delta, 0])[0]
        assert d <= 1e-13


def test_a_single_row_goes_with_every_row():
    b0 = RNG.uniform(-10, 10, (5, 3))
    b1 = RNG.uniform(-10, 10, (5, 3))
    d, _, _ = parasils.segment_distance_mm([0, 0, 0], [1, 0, 0], b0, b1)
    for k in range(5):
        assert d[k] == parasils.segment_distance_mm([0, 0, 0], [1, 0, 0], b0[k], b1[k])[0]


def test_non_finite_input_raises_or_is_masked():
    with pytest.raises(parasils.NonFiniteError) as e:
        parasils.segment_distance_mm([0, 0, 0], [1, 0, 0], [0, np.nan, 0], [1, 1, 1])
    assert e.value.what == "segment b.start.y"
    a0 = np.zeros((3, 3))
    a1 = np.ones((3, 3))
    b0 = np.array([[0, 0, 1], [np.inf, 0, 0], [0, 0, 2.0]])
    d, pa, pb, ok = parasils.segment_distance_mm(a0, a1, b0, b0, errors="nan")
    assert list(ok) == [True, False, True]
    assert np.isnan(d[1]) and np.all(np.isfinite(d[[0, 2]]))
    with pytest.raises(parasils.NonFiniteError) as e:
        parasils.segment_distance_mm([0, 0, 0], [1, 0, 0], [1e300, 0, 0], [-1e300, 1e300, 0])
    assert e.value.what == "segment distance (overflow)"


def test_a_batch_is_the_scalar_call_row_by_row():
    # Random, near-parallel and degenerate rows: every output of the batch
    # call is, to the bit, the scalar call's on that row (one kernel).
    n = 90
    a0, a1, b0, b1 = (RNG.uniform(-300, 300, (n, 3)) for _ in range(4))
    b1[:30] = b0[:30]
    a1[30:45] = a0[30:45]
    u = a1[45:] - a0[45:]
    b1[45:] = b0[45:] + u + np.cross(RNG.normal(0, 1e-9, (n - 45, 3)), u)
    d, pa, pb = parasils.segment_distance_mm(a0, a1, b0, b1)
    for k in range(n):
        dk, pak, pbk = parasils.segment_distance_mm(a0[k], a1[k], b0[k], b1[k])
        assert isinstance(dk, float) and pak.shape == (3,) and pbk.shape == (3,)
        assert d[k] == dk
        assert np.array_equal(pa[k], pak) and np.array_equal(pb[k], pbk)
    # And the distance is |pa - pb| by NumPy's own arithmetic.
    np.testing.assert_allclose(d, np.sqrt(np.sum((pa - pb) ** 2, axis=1)), rtol=1e-15, atol=1e-12)
