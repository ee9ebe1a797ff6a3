"""Property tests of the batch functions (hypothesis): any shape, dtype,
memory layout, broadcasting and placement of NaN and infinity gives the
documented result or the documented exception, never a crash.

The truth each batch is held to is the same function called one row at a
time (the single-sample path, which shares no code with the batching: the
shapes, strides, dtype conversion, broadcasting and threads); the rows that
succeed are held to the kinematics too (FK inverts IK).

The examples are drawn from a fixed seed unless PARASILS_HYPOTHESIS_EXPLORE
is set (any value), so the test command's verdict is reproducible; a run with
it set draws new examples.
"""

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import parasils
from conftest import LEFT_TIP, P0

EXPLORE = bool(os.environ.get("PARASILS_HYPOTHESIS_EXPLORE"))


def examples(n):
    return settings(
        max_examples=n,
        deadline=None,
        derandomize=not EXPLORE,
        database=None,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


ROBOT = parasils.Robot()
QS0 = ROBOT.instrument_ik("left", P0, LEFT_TIP)
Q0 = ROBOT.module1_ik(P0)
ZERO6 = np.zeros(6)
ZERO3 = np.zeros(3)
POSE_SPREAD = np.array([5.0, 5.0, 5.0, 0.05, 0.05, 0.05])

# name: (arguments as (name, width, base value, spread), number of outputs)
SPECS = {
    "instrument_ik": ([("pose", 6, P0, POSE_SPREAD), ("tip", 3, LEFT_TIP, 20.0)], 1),
    "instrument_fk": ([("pose", 6, P0, POSE_SPREAD), ("qs", 3, QS0, np.array([0.3, 0.3, 20.0]))], 1),
    "instrument_rates": (
        [
            ("pose", 6, P0, POSE_SPREAD),
            ("pose_rate", 6, ZERO6, 0.5),
            ("pose_acc", 6, ZERO6, 0.5),
            ("tip", 3, LEFT_TIP, 20.0),
            ("tip_rate", 3, ZERO3, 5.0),
            ("tip_acc", 3, ZERO3, 5.0),
        ],
        3,
    ),
    "module1_ik": ([("pose", 6, P0, POSE_SPREAD)], 1),
    "module1_fk": ([("q", 6, Q0, 5.0), ("guess", 6, P0, POSE_SPREAD / 5.0)], 1),
    "module1_rates": (
        [("pose", 6, P0, POSE_SPREAD), ("pose_rate", 6, ZERO6, 0.5), ("pose_acc", 6, ZERO6, 0.5)],
        3,
    ),
}
SIDED = {"instrument_ik", "instrument_fk", "instrument_rates"}
MODED = {"instrument_ik", "instrument_rates"}

SPECIAL = [np.nan, np.inf, -np.inf, 1e300, -1e300, -0.0, 5e-324]


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def same_bits(a, b):
    return np.asarray(a).shape == np.asarray(b).shape and np.array_equal(bits(a), bits(b))


@st.composite
def values(draw, shape, base, spread, specials):
    """Values around `base` (broadcast to `shape`), some replaced by the
    special values (NaN, infinities, huge, -0, subnormal) when allowed."""
    noise = draw(hnp.arrays(np.float64, shape, elements=st.floats(-1.0, 1.0)))
    a = np.broadcast_to(base, shape) + noise * spread
    if specials:
        codes = draw(hnp.arrays(np.int8, shape, elements=st.integers(0, 3 * len(SPECIAL))))
        for k, v in enumerate(SPECIAL):
            a = np.where(codes == k, v, a)
    return np.array(a, dtype=np.float64)


@st.composite
def layout(draw, a):
    """`a` as the caller might hand it over: another dtype (what
    `numpy.asarray(x, float)` takes), Fortran order, strided, reversed,
    read-only, or a list. Returns (argument, the float64 values it holds)."""
    dtype = draw(st.sampled_from(["float64", "float32", "float16", "int64", "int32", "uint8", "bool"]))
    if dtype in ("float32", "float16"):
        with np.errstate(over="ignore"):
            a = a.astype(dtype)
    elif dtype != "float64":
        finite = np.nan_to_num(a, nan=0.0, posinf=0.0, neginf=0.0)
        info = np.iinfo(dtype) if dtype != "bool" else None
        if info is not None:
            a = np.clip(np.round(finite), max(info.min, -1e6), min(info.max, 1e6)).astype(dtype)
        else:
            a = finite > 0
    truth = np.asarray(a, dtype=np.float64)
    how = draw(st.sampled_from(["c", "fortran", "strided", "reversed", "read-only", "list"]))
    if how == "fortran":
        a = np.asfortranarray(a)
    elif how == "strided":
        wide = np.zeros(a.shape[:-1] + (2 * a.shape[-1],), dtype=a.dtype)
        wide[..., ::2] = a
        a = wide[..., ::2]
    elif how == "reversed" and a.ndim == 2:
        a = a[::-1].copy()[::-1]
    elif how == "read-only":
        a = a.copy()
        a.flags.writeable = False
    elif how == "list" and a.size > 0:
        # (An empty list has no second dimension: numpy reads it as (0,).)
        a = a.tolist()
    return a, truth


def call(name, args, side="left", mode="A", errors="raise"):
    f = getattr(ROBOT, name)
    kw = {"errors": errors}
    if name in MODED:
        kw["mode"] = mode
    lead = (side,) if name in SIDED else ()
    return f(*lead, *args, **kw)


def outputs(result, n_out):
    """The output arrays of a call with errors="nan", and its mask."""
    if n_out == 1:
        out, ok = result
        return [out], ok
    *outs, ok = result
    return outs, ok


def row(a, i):
    return a if a.ndim == 1 else a[i]


@st.composite
def cases(draw, name, max_rows=6, specials=True):
    """Arguments of `name`: each one row (broadcast) or a batch of the same
    N rows, N possibly 0; with the float64 values each holds."""
    arg_specs, _ = SPECS[name]
    n = draw(st.integers(0, max_rows))
    args, truths = [], []
    for _, width, base, spread in arg_specs:
        single = draw(st.booleans())
        shape = (width,) if single else (n, width)
        a, truth = draw(layout(draw(values(shape, base, spread, specials))))
        args.append(a)
        truths.append(truth)
    batch = any(t.ndim == 2 for t in truths)
    return args, truths, (n if batch else None)


def check(name, args, truths, n, side, mode):
    _, n_out = SPECS[name]
    outs, ok = outputs(call(name, args, side, mode, errors="nan"), n_out)
    if n is None:
        assert isinstance(ok, bool)
        rows = [(truths, outs, ok)]
    else:
        assert ok.shape == (n,) and ok.dtype == np.bool_
        for o in outs:
            assert o.shape[0] == n and o.dtype == np.float64
        rows = [([row(t, i) for t in truths], [o[i] for o in outs], bool(ok[i])) for i in range(n)]
    # Each row as the single-sample call gives it, bit for bit.
    first_error = None
    for i, (one, got, flag) in enumerate(rows):
        r_outs, r_ok = outputs(call(name, one, side, mode, errors="nan"), n_out)
        assert flag == r_ok
        for g, r in zip(got, r_outs):
            assert same_bits(g, r)
            if not flag:
                assert np.all(np.isnan(g))
        if not flag and first_error is None:
            first_error = (i, one)
    # errors="raise": the values, or the first failing row's own exception.
    if first_error is None:
        result = call(name, args, side, mode)
        got = [result] if n_out == 1 else list(result)
        for g, o in zip(got, outs):
            assert same_bits(g, o)
    else:
        i, one = first_error
        with pytest.raises(parasils.KinematicsError) as single:
            call(name, one, side, mode)
        with pytest.raises(parasils.KinematicsError) as batch:
            call(name, args, side, mode)
        assert type(batch.value) is type(single.value)
        if n is None:
            assert batch.value.row is None
            assert str(batch.value) == str(single.value)
        else:
            assert batch.value.row == i
            assert str(batch.value) == f"row {i}: {single.value}"
    return rows


SIDES = st.sampled_from(["left", "right"])
MODES = st.sampled_from(["A", "B"])


@pytest.mark.parametrize("name", sorted(SPECS))
def test_batches_equal_their_rows_whatever_the_layout(name):
    @examples(60)
    @given(case=cases(name), side=SIDES, mode=MODES)
    def run(case, side, mode):
        args, truths, n = case
        check(name, args, truths, n, side, mode)

    run()


@examples(40)
@given(case=cases("instrument_ik", specials=False), side=SIDES)
def test_ik_rows_that_succeed_invert_through_fk(case, side):
    args, truths, n = case
    qs, ok = call("instrument_ik", args, side, errors="nan")
    pose, tip = truths
    if n is None:
        qs, ok, pose, tip = qs[None, :], np.array([ok]), pose[None, :], tip[None, :]
    else:
        pose, tip = np.broadcast_to(pose, (n, 6)), np.broadcast_to(tip, (n, 3))
    if not ok.any():
        return
    back = ROBOT.instrument_fk(side, pose[ok], qs[ok])
    assert np.max(np.abs(back - tip[ok])) < 1e-9


@examples(40)
@given(case=cases("module1_ik", specials=False))
def test_module1_ik_rows_that_succeed_invert_through_fk(case):
    args, truths, n = case
    q, ok = call("module1_ik", args, errors="nan")
    pose = truths[0]
    if n is None:
        q, ok, pose = q[None, :], np.array([ok]), pose[None, :]
    if not ok.any():
        return
    back = ROBOT.module1_fk(q[ok], pose[ok])
    assert np.max(np.abs(back - pose[ok])) < 1e-9


@examples(5)
@given(
    nan_rows=st.lists(st.integers(0, 4999), max_size=5),
    side=SIDES,
)
def test_threaded_batches_equal_their_rows(nan_rows, side):
    # Past the size at which a batch is cut into chunks for several threads.
    rng = np.random.default_rng(len(nan_rows))
    pose = P0 + rng.normal(0.0, 1.0, (5000, 6)) * POSE_SPREAD
    tip = LEFT_TIP + rng.normal(0.0, 20.0, (5000, 3))
    tip[nan_rows, 1] = np.nan
    check("instrument_ik", [pose, tip], [pose, tip], 5000, side, "A")


@st.composite
def bad_shapes(draw, width):
    """A shape that is neither (width,) nor (N, width)."""
    return draw(
        hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=7).filter(
            lambda s: not (len(s) == 1 and s[0] == width) and not (len(s) == 2 and s[1] == width)
        )
    )


@pytest.mark.parametrize("name", sorted(SPECS))
def test_a_wrong_shape_is_a_value_error_naming_the_argument(name):
    arg_specs, _ = SPECS[name]

    @examples(30)
    @given(k=st.integers(0, len(arg_specs) - 1), data=st.data())
    def run(k, data):
        arg_name, width, _, _ = arg_specs[k]
        shape = data.draw(bad_shapes(width))
        args = [base for _, _, base, _ in arg_specs]
        args[k] = np.zeros(shape)
        with pytest.raises(ValueError, match=f"^{arg_name} must have shape"):
            call(name, args)

    run()


@pytest.mark.parametrize("name", sorted(SPECS))
def test_batches_of_different_lengths_are_a_value_error(name):
    arg_specs, _ = SPECS[name]
    if len(arg_specs) < 2:
        pytest.skip("one argument")

    @examples(20)
    @given(n=st.integers(0, 5), m=st.integers(0, 5))
    def run(n, m):
        args = [np.tile(base, (n if k == 0 else m, 1)) for k, (_, _, base, _) in enumerate(arg_specs)]
        if n == m:
            call(name, args)
        else:
            with pytest.raises(ValueError, match="batches must have the same length"):
                call(name, args)

    run()


@examples(30)
@given(
    side=st.text(max_size=6),
    mode=st.text(max_size=3),
    errors=st.text(max_size=6),
)
def test_unknown_side_mode_or_errors_is_a_value_error(side, mode, errors):
    valid = side in ("left", "right") and mode in ("A", "B") and errors in ("raise", "nan")
    if valid:
        ROBOT.instrument_ik(side, P0, LEFT_TIP, mode=mode, errors=errors)
    else:
        with pytest.raises(ValueError, match="must be"):
            ROBOT.instrument_ik(side, P0, LEFT_TIP, mode=mode, errors=errors)


@examples(20)
@given(
    value=st.one_of(
        st.text(max_size=5).filter(lambda s: not _is_number(s)),
        st.just(object()),
        st.just({"a": 1}),
        st.just([[1.0, 2.0], [3.0]]),
    )
)
def test_what_is_not_numbers_is_refused_with_an_exception(value):
    with pytest.raises((TypeError, ValueError)):
        ROBOT.module1_ik(value)


def _is_number(s):
    try:
        float(s)
    except ValueError:
        return False
    return True
