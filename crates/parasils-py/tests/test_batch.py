"""One sample or a batch: the same numbers, the same leading shape."""

import threading

import numpy as np
import pytest

import parasils
from conftest import LEFT_TIP, P0

RNG = np.random.default_rng(20240601)
N = 200


def poses(n=N, spread=1.0):
    """Poses around P0 (mm, rad)."""
    return P0 + RNG.normal(0.0, 1.0, (n, 6)) * spread * np.array([5, 5, 5, 0.05, 0.05, 0.05])


def tips(n=N):
    return LEFT_TIP + RNG.normal(0.0, 5.0, (n, 3))


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def assert_same_bits(a, b):
    assert np.asarray(a).shape == np.asarray(b).shape
    assert np.array_equal(bits(a), bits(b))


@pytest.mark.parametrize("side", ["left", "right"])
def test_instrument_ik_batch_equals_single(robot, side):
    p, t = poses(), tips()
    batch = robot.instrument_ik(side, p, t)
    assert batch.shape == (N, 3) and batch.dtype == np.float64
    single = np.array([robot.instrument_ik(side, p[i], t[i]) for i in range(N)])
    assert single.shape == (N, 3)
    assert_same_bits(batch, single)


@pytest.mark.parametrize("side", ["left", "right"])
def test_instrument_fk_batch_equals_single_and_inverts_ik(robot, side):
    p, t = poses(), tips()
    qs = robot.instrument_ik(side, p, t)
    batch = robot.instrument_fk(side, p, qs)
    single = np.array([robot.instrument_fk(side, p[i], qs[i]) for i in range(N)])
    assert_same_bits(batch, single)
    assert np.max(np.abs(batch - t)) < 1e-9


def test_module1_ik_fk_batch_equals_single(robot):
    p = poses()
    q = robot.module1_ik(p)
    assert q.shape == (N, 6)
    assert_same_bits(q, np.array([robot.module1_ik(x) for x in p]))
    guess = p + 0.5
    back = robot.module1_fk(q, guess)
    assert_same_bits(back, np.array([robot.module1_fk(q[i], guess[i]) for i in range(N)]))
    np.testing.assert_allclose(back, p, atol=1e-8, rtol=0)


@pytest.mark.parametrize("side", ["left", "right"])
def test_instrument_rates_batch_equals_single(robot, side):
    p, t = poses(), tips()
    rate = RNG.normal(0, 0.1, (N, 6))
    acc = RNG.normal(0, 0.1, (N, 6))
    tip_rate = RNG.normal(0, 1.0, (N, 3))
    tip_acc = RNG.normal(0, 1.0, (N, 3))
    q, qd, qdd = robot.instrument_rates(side, p, rate, acc, t, tip_rate, tip_acc)
    assert q.shape == qd.shape == qdd.shape == (N, 3)
    for i in range(0, N, 17):
        s = robot.instrument_rates(side, p[i], rate[i], acc[i], t[i], tip_rate[i], tip_acc[i])
        assert isinstance(s, tuple) and len(s) == 3
        assert_same_bits(np.array([q[i], qd[i], qdd[i]]), np.array(s))
    # The joints are those of the IK.
    assert_same_bits(q, robot.instrument_ik(side, p, t))


def test_module1_rates_batch_equals_single(robot):
    p = poses()
    rate = RNG.normal(0, 0.1, (N, 6))
    acc = RNG.normal(0, 0.1, (N, 6))
    q, qd, qdd = robot.module1_rates(p, rate, acc)
    assert q.shape == qd.shape == qdd.shape == (N, 6)
    for i in range(0, N, 23):
        assert_same_bits(np.array([q[i], qd[i], qdd[i]]), np.array(robot.module1_rates(p[i], rate[i], acc[i])))
    assert_same_bits(q, robot.module1_ik(p))


@pytest.mark.parametrize(
    "old, new, args",
    [
        ("platform_ik", "module1_ik", lambda p: (p,)),
        ("platform_fk", "module1_fk", lambda p: (parasils.Robot().module1_ik(p), p + 0.5)),
        ("platform_rates", "module1_rates", lambda p: (p, np.full(6, 0.01), np.full(6, 0.02))),
    ],
)
def test_platform_names_are_deprecated_aliases(robot, old, new, args):
    p = poses(5)
    a = args(p)
    with pytest.warns(DeprecationWarning, match=f"Robot.{old} is deprecated: use Robot.{new}") as record:
        got = getattr(robot, old)(*a)
    assert record[0].filename == __file__  # the warning points at the caller
    assert_same_bits(np.array(got), np.array(getattr(robot, new)(*a)))
    # Keyword arguments too, errors="nan" included.
    with pytest.warns(DeprecationWarning):
        *_, ok = getattr(robot, old)(*a, errors="nan")
    assert ok.all()


def motion(t):
    """A smooth motion of the platform (mm, rad) and of the tip (mm)."""
    pose = P0 + np.array(
        [3 * np.sin(t), 2 * t * t, -4 * t, 0.2 * np.sin(1.3 * t), 0.1 * t * t, 0.05 * t]
    )
    tip = LEFT_TIP + np.array([10 * np.sin(t), 5 * t, -3 * t * t])
    return pose, tip


def test_instrument_rates_match_finite_differences(robot):
    h = 1e-4
    ts = np.linspace(-0.5, 0.5, 11)
    for side in ("left", "right"):
        tip_of = {"left": lambda t: motion(t)[1], "right": lambda t: motion(t)[1] + [-60.0, 100.0, 0.0]}[side]
        pose_at = np.array([motion(t)[0] for t in ts])
        p_p = np.array([motion(t + h)[0] for t in ts])
        p_m = np.array([motion(t - h)[0] for t in ts])
        tip = np.array([tip_of(t) for t in ts])
        t_p = np.array([tip_of(t + h) for t in ts])
        t_m = np.array([tip_of(t - h) for t in ts])
        pose_rate = (p_p - p_m) / (2 * h)
        pose_acc = (p_p - 2 * pose_at + p_m) / (h * h)
        tip_rate = (t_p - t_m) / (2 * h)
        tip_acc = (t_p - 2 * tip + t_m) / (h * h)
        q, qd, qdd = robot.instrument_rates(side, pose_at, pose_rate, pose_acc, tip, tip_rate, tip_acc)
        q_p = robot.instrument_ik(side, p_p, t_p)
        q_m = robot.instrument_ik(side, p_m, t_m)
        np.testing.assert_allclose(qd, (q_p - q_m) / (2 * h), atol=1e-6, rtol=1e-6)
        np.testing.assert_allclose(qdd, (q_p - 2 * q + q_m) / (h * h), atol=2e-3, rtol=1e-3)


def test_rates_agree_with_the_simulation(robot, default_right):
    table = parasils.simulate(rate_hz=100.0)
    n = len(table["t_s"])
    rad = np.radians
    pose = np.column_stack(
        [table["x_mm"], table["y_mm"], table["z_mm"], rad(table["psi_deg"]), rad(table["theta_deg"]), rad(table["phi_deg"])]
    )
    zero = np.zeros(n)
    rate = np.column_stack([zero, zero, zero, rad(table["psi_rate_deg_s"]), rad(table["theta_rate_deg_s"]), zero])
    acc = np.column_stack([zero, zero, zero, rad(table["psi_acc_deg_s2"]), rad(table["theta_acc_deg_s2"]), zero])
    for side, tip in (("left", LEFT_TIP), ("right", default_right)):
        q, qd, qdd = robot.instrument_rates(side, pose, rate, acc, tip)
        for k, j in enumerate(("qs1", "qs2")):
            np.testing.assert_allclose(np.degrees(q[:, k]), table[f"{side}_{j}_deg"], atol=1e-9)
            np.testing.assert_allclose(np.degrees(qd[:, k]), table[f"{side}_{j}_rate_deg_s"], atol=1e-9)
            np.testing.assert_allclose(np.degrees(qdd[:, k]), table[f"{side}_{j}_acc_deg_s2"], atol=1e-9)
        np.testing.assert_allclose(qd[:, 2], table[f"{side}_qs3_rate_mm_s"], atol=1e-9)
    q, qd, qdd = robot.module1_rates(pose, rate, acc)
    for j in range(6):
        np.testing.assert_allclose(q[:, j], table[f"q{j + 1}_mm"], atol=1e-9)
        np.testing.assert_allclose(qd[:, j], table[f"q{j + 1}_rate_mm_s"], atol=1e-9)
        np.testing.assert_allclose(qdd[:, j], table[f"q{j + 1}_acc_mm_s2"], atol=1e-9)


def test_a_single_row_goes_with_every_row_of_a_batch(robot):
    t = tips()
    broadcast = robot.instrument_ik("left", P0, t)
    assert broadcast.shape == (N, 3)
    assert_same_bits(broadcast, robot.instrument_ik("left", np.tile(P0, (N, 1)), t))
    # Rates: one pose, a batch of tips, tip_rate given once.
    q, qd, qdd = robot.instrument_rates("left", P0, np.zeros(6), np.zeros(6), t, [1.0, 0.0, 0.0])
    assert q.shape == qd.shape == qdd.shape == (N, 3)


def test_a_single_sample_gives_1d_arrays(robot):
    qs = robot.instrument_ik("left", P0, LEFT_TIP)
    assert isinstance(qs, np.ndarray) and qs.shape == (3,)
    assert robot.module1_ik(P0).shape == (6,)
    assert robot.module1_fk(robot.module1_ik(P0), P0).shape == (6,)
    # A batch of one stays a batch.
    assert robot.instrument_ik("left", P0[None, :], LEFT_TIP).shape == (1, 3)


def test_array_likes_are_accepted(robot):
    expected = robot.instrument_ik("left", P0, LEFT_TIP)
    assert_same_bits(robot.instrument_ik("left", list(P0), tuple(LEFT_TIP)), expected)
    assert_same_bits(robot.instrument_ik("left", P0, np.array([50, -50, -620])), expected)  # int
    assert_same_bits(robot.instrument_ik("left", P0.astype(np.float32).astype(np.float64), LEFT_TIP),
                     robot.instrument_ik("left", P0.astype(np.float32), LEFT_TIP))


def test_non_contiguous_batches(robot):
    p, t = poses(), tips()
    wide = np.zeros((N, 12))
    wide[:, ::2] = p  # strided columns
    fortran = np.asfortranarray(t)
    assert_same_bits(robot.instrument_ik("left", wide[:, ::2], fortran), robot.instrument_ik("left", p, t))
    assert_same_bits(robot.instrument_ik("left", p[::-1], t[::-1]), robot.instrument_ik("left", p, t)[::-1])


def test_empty_batch(robot):
    out = robot.instrument_ik("left", np.empty((0, 6)), np.empty((0, 3)))
    assert out.shape == (0, 3)
    out, ok = robot.module1_ik(np.empty((0, 6)), errors="nan")
    assert out.shape == (0, 6) and ok.shape == (0,) and ok.dtype == np.bool_


def test_errors_nan_gives_nan_rows_and_a_mask(robot):
    p, t = poses(10), tips(10)
    t[3] = [5000.0, 0.0, 0.0]  # out of reach or beyond qs3's limit
    p[7, 4] = np.nan  # non-finite input
    good = robot.instrument_ik("left", np.delete(p, [3, 7], axis=0), np.delete(t, [3, 7], axis=0))
    qs, ok = robot.instrument_ik("left", p, t, errors="nan")
    assert ok.dtype == np.bool_ and ok.shape == (10,)
    assert list(np.flatnonzero(~ok)) == [3, 7]
    assert np.all(np.isnan(qs[~ok])) and not np.any(np.isnan(qs[ok]))
    assert_same_bits(qs[ok], good)
    # The same with the rates: NaN in all three outputs.
    q, qd, qdd, ok2 = robot.instrument_rates("left", p, np.zeros(6), np.zeros(6), t, errors="nan")
    assert np.array_equal(ok, ok2)
    for a in (q, qd, qdd):
        assert np.all(np.isnan(a[~ok])) and not np.any(np.isnan(a[ok]))
    # One sample: a bool.
    qs, ok = robot.instrument_ik("left", P0, [5000.0, 0.0, 0.0], errors="nan")
    assert ok is False and qs.shape == (3,) and np.all(np.isnan(qs))
    qs, ok = robot.instrument_ik("left", P0, LEFT_TIP, errors="nan")
    assert ok is True
    # FK and module 1 too.
    tip, ok = robot.instrument_fk("left", [P0, P0 * np.nan], [0.1, 0.2, 100.0], errors="nan")
    assert list(ok) == [True, False]
    q, ok = robot.module1_ik([P0, P0 + [0, 0, -5000, 0, 0, 0]], errors="nan")
    assert list(ok) == [True, False] and np.all(np.isnan(q[1]))
    pose, ok = robot.module1_fk(q[0], [P0, [15, 20, -500, 0, np.pi / 2, 0]], errors="nan")
    assert list(ok) == [True, False]
    *_, ok = robot.module1_rates([P0, P0 * np.nan], np.zeros(6), np.zeros(6), errors="nan")
    assert list(ok) == [True, False]


def test_batches_release_the_gil(robot):
    # Two threads on big batches: both finish, with the same result as one.
    p, t = poses(20000), tips(20000)
    expected = robot.instrument_ik("left", p, t)
    results = [None, None]

    def work(k):
        results[k] = robot.instrument_ik("left", p, t)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for r in results:
        assert_same_bits(r, expected)
