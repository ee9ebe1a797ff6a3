"""Large batches split across threads: the same bits, the same first error, the same mask.

A batch of 4096 rows or more is cut into chunks of consecutive rows that
parasils.batch_threads() threads compute (PARASILS_NUM_THREADS sets it, read
at each call). These tests run batches big enough to be split, under several
thread counts, against row-by-row results.
"""

import numpy as np
import pytest

import parasils
from conftest import LEFT_TIP, P0

BIG = 200_000
THREADS = ["1", "2", "3", "8"]


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def assert_same_bits(a, b):
    assert np.asarray(a).shape == np.asarray(b).shape
    assert np.array_equal(bits(a), bits(b))


def poses(rng, n):
    return P0 + rng.normal(0.0, 1.0, (n, 6)) * np.array([5, 5, 5, 0.05, 0.05, 0.05])


def tips(rng, n):
    return LEFT_TIP + rng.normal(0.0, 5.0, (n, 3))


@pytest.fixture(scope="module")
def big():
    rng = np.random.default_rng(7)
    return poses(rng, BIG), tips(rng, BIG)


@pytest.fixture(params=THREADS)
def threads(request, monkeypatch):
    monkeypatch.setenv("PARASILS_NUM_THREADS", request.param)
    return int(request.param)


def in_small_batches(fn, n, *arrays, size=1000, **kw):
    """fn on batches of `size` rows (below the threshold: one thread), joined."""
    parts = [fn(*(a[i : i + size] for a in arrays), **kw) for i in range(0, n, size)]
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate(p) for p in zip(*parts))
    return np.concatenate(parts)


def test_batch_threads_follows_the_environment(monkeypatch):
    monkeypatch.delenv("PARASILS_NUM_THREADS", raising=False)
    default = parasils.batch_threads()
    assert isinstance(default, int) and default >= 1
    monkeypatch.setenv("PARASILS_NUM_THREADS", "3")
    assert parasils.batch_threads() == 3
    monkeypatch.setenv("PARASILS_NUM_THREADS", "")
    assert parasils.batch_threads() == default
    for bad in ("0", "-2", "two", "1.5"):
        monkeypatch.setenv("PARASILS_NUM_THREADS", bad)
        with pytest.raises(ValueError, match="PARASILS_NUM_THREADS must be a positive integer"):
            parasils.batch_threads()
        with pytest.raises(ValueError, match="PARASILS_NUM_THREADS"):
            parasils.Robot().instrument_ik("left", np.tile(P0, (10, 1)), LEFT_TIP)
    # A single sample never reads it.
    parasils.Robot().instrument_ik("left", P0, LEFT_TIP)


def test_instrument_ik_big_batch_equals_row_by_row(robot, big, threads):
    p, t = big
    assert parasils.batch_threads() == threads
    batch = robot.instrument_ik("left", p, t)
    assert batch.shape == (BIG, 3) and batch.flags.c_contiguous
    single = np.array([robot.instrument_ik("left", p[i], t[i]) for i in range(BIG)])
    assert_same_bits(batch, single)


@pytest.mark.parametrize("side", ["left", "right"])
def test_every_batch_method_is_independent_of_the_thread_count(robot, big, threads, side):
    p, t = big
    rng = np.random.default_rng(11)
    rate, acc = rng.normal(0, 0.1, (BIG, 6)), rng.normal(0, 0.1, (BIG, 6))
    tip_rate, tip_acc = rng.normal(0, 1.0, (BIG, 3)), rng.normal(0, 1.0, (BIG, 3))
    qs = robot.instrument_ik(side, p, t)
    assert_same_bits(qs, in_small_batches(lambda a, b: robot.instrument_ik(side, a, b), BIG, p, t))
    assert_same_bits(
        robot.instrument_fk(side, p, qs),
        in_small_batches(lambda a, b: robot.instrument_fk(side, a, b), BIG, p, qs),
    )
    rates = robot.instrument_rates(side, p, rate, acc, t, tip_rate, tip_acc)
    expected = in_small_batches(
        lambda *a: robot.instrument_rates(side, *a), BIG, p, rate, acc, t, tip_rate, tip_acc
    )
    for got, want in zip(rates, expected):
        assert got.shape == (BIG, 3) and got.flags.c_contiguous
        assert_same_bits(got, want)
    if side == "left":
        q = robot.module1_ik(p)
        assert_same_bits(q, in_small_batches(robot.module1_ik, BIG, p))
        for got, want in zip(
            robot.module1_rates(p, rate, acc), in_small_batches(robot.module1_rates, BIG, p, rate, acc)
        ):
            assert got.shape == (BIG, 6)
            assert_same_bits(got, want)
        # Newton is slower: fewer rows, still several chunks.
        n = 20_000
        guess = p[:n] + 0.5
        assert_same_bits(robot.module1_fk(q[:n], guess), in_small_batches(robot.module1_fk, n, q[:n], guess))


def with_bad_rows(big, bad):
    """The big batch with rows spoilt: {row: 'nan' | 'far'}."""
    p, t = big[0].copy(), big[1].copy()
    for row, how in bad.items():
        if how == "nan":
            p[row, 4] = np.nan  # NonFiniteError (pose.theta)
        else:
            t[row] = [5000.0, 0.0, 0.0]  # out of reach or beyond qs3's limit
    return p, t


@pytest.mark.parametrize(
    "bad",
    [
        {1_500: "far", 190_000: "nan"},  # an early row, a late one
        {70_001: "nan", 120_000: "far", 199_999: "far"},  # the first in a middle chunk
        {199_999: "far"},  # the very last row
        {0: "nan", 1: "far"},  # the first two rows
        {150_000: "far", 150_001: "nan", 3: "nan"},  # out of order
    ],
)
def test_errors_raise_names_the_first_bad_row(robot, big, threads, bad):
    p, t = with_bad_rows(big, bad)
    first = min(bad)
    with pytest.raises(parasils.KinematicsError) as single:
        robot.instrument_ik("left", p[first], t[first])
    for _ in range(3):  # the threads race differently each time
        with pytest.raises(parasils.KinematicsError) as e:
            robot.instrument_ik("left", p, t)
        assert type(e.value) is type(single.value)
        assert e.value.row == first
        assert str(e.value) == f"row {first}: {single.value}"
        assert e.value.kind == single.value.kind
    # The same through the rates (the same loop, three outputs).
    with pytest.raises(parasils.KinematicsError) as e:
        robot.instrument_rates("left", p, np.zeros(6), np.zeros(6), t)
    assert e.value.row == first and type(e.value) is type(single.value)


def test_errors_raise_with_bad_rows_in_every_chunk(robot, big, threads):
    # Bad rows all along the batch (in every chunk, whatever the chunk size).
    bad = {row: "far" for row in range(4095, BIG, 997)}
    p, t = with_bad_rows(big, bad)
    for _ in range(3):
        with pytest.raises(parasils.KinematicsError) as e:
            robot.instrument_ik("left", p, t)
        assert e.value.row == 4095 and str(e.value).startswith("row 4095: ")


def test_errors_nan_masks_exactly_the_bad_rows(robot, big, threads):
    rng = np.random.default_rng(3)
    rows = np.sort(rng.choice(BIG, 300, replace=False))
    bad = {int(r): ("nan" if k % 2 else "far") for k, r in enumerate(rows)}
    p, t = with_bad_rows(big, bad)
    good = np.ones(BIG, dtype=bool)
    good[rows] = False
    expected = robot.instrument_ik("left", p[good], t[good])

    qs, ok = robot.instrument_ik("left", p, t, errors="nan")
    assert ok.dtype == np.bool_ and ok.shape == (BIG,)
    assert np.array_equal(ok, good)
    assert np.all(np.isnan(qs[~ok]))
    assert_same_bits(qs[ok], expected)

    q, qd, qdd, ok2 = robot.instrument_rates("left", p, np.zeros(6), np.zeros(6), t, errors="nan")
    assert np.array_equal(ok2, good)
    assert_same_bits(q[ok2], expected)
    for a in (q, qd, qdd):
        assert np.all(np.isnan(a[~ok2])) and not np.any(np.isnan(a[ok2]))

    q, ok3 = robot.module1_ik(p, errors="nan")
    nan_rows = np.isnan(p).any(axis=1)
    assert np.array_equal(ok3, ~nan_rows)
    assert np.all(np.isnan(q[nan_rows]))
    assert_same_bits(q[ok3], robot.module1_ik(p[ok3]))
