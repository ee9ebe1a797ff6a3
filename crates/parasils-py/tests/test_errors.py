"""Every error path: the exception type, its attributes, its message."""

import math

import numpy as np
import pytest

import parasils
from conftest import LEFT_TIP, P0, to_fixed

IDENTITY = np.zeros(6)
A = math.radians(10.0)  # alpha = beta of the paper's modules

KINEMATICS_ERRORS = [
    parasils.NonFiniteError,
    parasils.InvalidParameterError,
    parasils.OutOfReachError,
    parasils.SingularError,
    parasils.JointLimitError,
    parasils.LegOutOfReachError,
    parasils.ActuatorLimitError,
    parasils.SerialSingularError,
    parasils.ParallelSingularError,
    parasils.NoConvergenceError,
    parasils.SingularJacobianError,
    parasils.BranchMismatchError,
]


def test_hierarchy():
    assert issubclass(parasils.KinematicsError, ValueError)
    for cls in KINEMATICS_ERRORS:
        assert issubclass(cls, parasils.KinematicsError), cls
        assert cls.__module__ == "parasils"
        assert cls.__doc__ and "kind '" in cls.__doc__
    assert issubclass(parasils.TrajectoryError, ValueError)
    assert issubclass(parasils.RobotFileError, ValueError)
    assert not issubclass(parasils.TrajectoryError, parasils.KinematicsError)


def robot_with(tmp_path, **replace):
    """A robot file: the default one with `key = value` lines replaced."""
    lines = []
    for line in parasils.Robot().to_toml().splitlines():
        key = line.split("=")[0].strip()
        if key in replace:
            line = f"{key} = {replace[key]}"
        lines.append(line)
    path = tmp_path / "robot.toml"
    path.write_text("\n".join(lines) + "\n")
    return parasils.Robot.from_toml(path)


# --- instrument modules -------------------------------------------------------


def test_nan_pose(robot):
    pose = P0.copy()
    pose[4] = np.nan
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.instrument_ik("left", pose, LEFT_TIP)
    err = e.value
    assert (err.kind, err.what, err.row, err.t) == ("non_finite", "pose.theta", None, None)
    assert math.isnan(err.value)
    assert str(err) == "non-finite input: pose.theta = NaN"


def test_infinite_tip(robot):
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.instrument_ik("right", P0, [50.0, np.inf, -620.0])
    assert (e.value.what, e.value.value) == ("tip.y", math.inf)


def test_nan_joints_in_fk(robot):
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.instrument_fk("left", P0, [0.1, np.nan, 100.0])
    assert e.value.what == "joints.qs2"


def test_nan_rates(robot):
    rate = np.zeros(6)
    rate[3] = np.nan
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.instrument_rates("left", P0, rate, np.zeros(6), LEFT_TIP)
    assert e.value.what == "velocity.psi"
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.instrument_rates("left", P0, np.zeros(6), np.zeros(6), LEFT_TIP, None, [0, 0, np.nan])
    assert e.value.what == "tip_acceleration.z"


def test_unreachable_tip(robot):
    # A tool direction with v = R_Y(-alpha) u = (-1, 0, 0): |sin qs2| = 1 / cos(beta).
    tip = np.array([-10.0, 0.0, 0.0]) + 100.0 * np.array([math.cos(A), 0.0, -math.sin(A)])
    with pytest.raises(parasils.OutOfReachError) as e:
        robot.instrument_ik("left", IDENTITY, tip)
    err = e.value
    assert (err.kind, err.side) == ("out_of_reach", "left")
    assert err.sin_qs2 == pytest.approx(1.0 / math.cos(A), rel=1e-12)
    assert "left instrument: tip out of reach" in str(err)
    # The right module: the mirror image.
    mirrored = tip * [-1.0, 1.0, 1.0]
    with pytest.raises(parasils.OutOfReachError) as e:
        robot.instrument_ik("right", IDENTITY, mirrored)
    assert e.value.side == "right"


def test_tip_at_the_rcm(robot):
    rcm = to_fixed(P0, [-10.0, 0.0, 0.0])
    with pytest.raises(parasils.SingularError) as e:
        robot.instrument_ik("left", P0, rcm)
    err = e.value
    assert (err.kind, err.side, err.margin, err.threshold) == ("singular", "left", "qs3", 1e-6)
    assert err.value < 1e-6


def test_reach_boundary_is_singular(robot):
    # u = (1, 0, 0): v_x = cos(alpha) = cos(beta), so cos qs2 = 0.
    with pytest.raises(parasils.SingularError) as e:
        robot.instrument_ik("left", IDENTITY, [-110.0, 0.0, 0.0])
    assert (e.value.margin, e.value.value) == ("cos_qs2", 0.0)


def test_joint_limit(robot):
    rcm = to_fixed(P0, [-10.0, 0.0, 0.0])
    far = rcm + 3.0 * (LEFT_TIP - rcm)  # qs3 = 3 * 147.77 mm > 300 mm
    with pytest.raises(parasils.JointLimitError) as e:
        robot.instrument_ik("left", P0, far)
    err = e.value
    assert (err.kind, err.side, err.joint, err.min, err.max, err.limit) == (
        "joint_limit", "left", "qs3", 10.0, 300.0, 300.0,
    )
    assert err.value == pytest.approx(3 * 147.7687, abs=1e-3)
    assert "joint qs3 = 443.30" in str(err) and "[10, 300] mm" in str(err)
    # The rates solve the joints first: the same error.
    with pytest.raises(parasils.JointLimitError):
        robot.instrument_rates("left", P0, np.zeros(6), np.zeros(6), far)


def test_joint_limit_in_radians_with_degrees_in_the_message(robot):
    with pytest.raises(parasils.JointLimitError) as e:
        robot.instrument_ik("left", P0, LEFT_TIP, mode="B")
    err = e.value
    assert err.joint == "qs1"
    assert err.min == pytest.approx(-math.radians(120)) and err.limit == err.min
    assert "deg is outside [-120, 120] deg" in str(err)


def test_batch_error_names_the_first_bad_row(robot):
    tips = np.tile(LEFT_TIP, (6, 1))
    tips[4] = to_fixed(P0, [-10.0, 0.0, 0.0])  # singular
    tips[5, 0] = np.nan
    with pytest.raises(parasils.SingularError) as e:
        robot.instrument_ik("left", P0, tips)
    assert e.value.row == 4
    assert str(e.value).startswith("row 4: left instrument: singular configuration")
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.instrument_fk("left", np.tile(P0, (3, 1)), [[0, 0, 100], [0, 0, 100], [0, np.nan, 1]])
    assert e.value.row == 2


# --- arguments ----------------------------------------------------------------


@pytest.mark.parametrize("side", ["up", "Left", "", "left "])
def test_bad_side(robot, side):
    with pytest.raises(ValueError, match="side must be 'left' or 'right'") as e:
        robot.instrument_ik(side, P0, LEFT_TIP)
    assert not isinstance(e.value, parasils.KinematicsError)
    for call in (
        lambda: robot.instrument_fk(side, P0, [0, 0, 100]),
        lambda: robot.instrument_rates(side, P0, np.zeros(6), np.zeros(6), LEFT_TIP),
    ):
        with pytest.raises(ValueError, match="side must be"):
            call()


@pytest.mark.parametrize(
    "pose, tip, message",
    [
        (P0[:5], LEFT_TIP, r"pose must have shape \(6,\) or \(N, 6\), got \(5,\)"),
        (np.zeros((4, 5)), LEFT_TIP, r"pose must have shape \(6,\) or \(N, 6\), got \(4, 5\)"),
        (np.zeros((2, 3, 6)), LEFT_TIP, r"got \(2, 3, 6\)"),
        (1.0, LEFT_TIP, r"got \(\)"),
        (P0, np.zeros((2, 4)), r"tip must have shape \(3,\) or \(N, 3\), got \(2, 4\)"),
        (np.zeros((4, 6)), np.zeros((5, 3)), "pose has 4 rows but tip has 5"),
    ],
)
def test_bad_shape(robot, pose, tip, message):
    with pytest.raises(ValueError, match=message):
        robot.instrument_ik("left", pose, tip)


def test_bad_shapes_elsewhere(robot):
    with pytest.raises(ValueError, match=r"qs must have shape \(3,\)"):
        robot.instrument_fk("left", P0, [1.0, 2.0])
    with pytest.raises(ValueError, match=r"q must have shape \(6,\)"):
        robot.module1_fk(np.zeros(5), P0)
    with pytest.raises(ValueError, match=r"guess must have shape"):
        robot.module1_fk(np.zeros(6), np.zeros(3))
    with pytest.raises(ValueError, match="pose_rate has 2 rows but pose_acc has 3"):
        robot.module1_rates(P0, np.zeros((2, 6)), np.zeros((3, 6)))
    with pytest.raises(ValueError, match=r"tip_rate must have shape"):
        robot.instrument_rates("left", P0, np.zeros(6), np.zeros(6), LEFT_TIP, [1.0])


def test_not_numbers(robot):
    with pytest.raises((ValueError, TypeError)):
        robot.instrument_ik("left", ["a"] * 6, LEFT_TIP)
    with pytest.raises((ValueError, TypeError)):
        robot.instrument_ik("left", None, LEFT_TIP)


def test_bad_errors_and_mode(robot):
    with pytest.raises(ValueError, match="errors must be 'raise' or 'nan'"):
        robot.instrument_ik("left", P0, LEFT_TIP, errors="ignore")
    with pytest.raises(ValueError, match="mode must be 'A' or 'B'"):
        robot.instrument_ik("left", P0, LEFT_TIP, mode="C")
    with pytest.raises(TypeError):
        robot.instrument_ik("left", P0, LEFT_TIP, "B")  # mode is keyword-only


# --- module 1 -----------------------------------------------------------------


def test_leg_out_of_reach(robot):
    with pytest.raises(parasils.LegOutOfReachError) as e:
        robot.module1_ik([0.0, 0.0, -500.0, math.radians(60), 0.0, 0.0])
    err = e.value
    assert (err.kind, err.actuator) == ("leg_out_of_reach", 1)
    assert err.discriminant < 0


def test_actuator_limit(robot):
    with pytest.raises(parasils.ActuatorLimitError) as e:
        robot.module1_ik([0.0, 0.0, -900.0, 0.0, 0.0, 0.0])
    err = e.value
    assert (err.kind, err.actuator, err.min, err.max, err.limit) == ("actuator_limit", 1, 0.0, 320.0, 320.0)
    assert err.value > 320.0
    with pytest.raises(parasils.ActuatorLimitError) as e:
        robot.module1_ik([0.0, 0.0, -200.0, 0.0, 0.0, 0.0])
    assert e.value.limit == 0.0 and e.value.value < 0.0


def test_serial_singular(tmp_path):
    robot = robot_with(tmp_path, serial_margin_min="0.999")
    with pytest.raises(parasils.SerialSingularError) as e:
        robot.module1_ik(P0)
    err = e.value
    assert (err.kind, err.threshold) == ("serial_singular", 0.999)
    assert 1 <= err.actuator <= 6 and err.margin < 0.999


def test_parallel_singular(tmp_path):
    robot = robot_with(tmp_path, parallel_margin_command_min="0.99")
    robot.module1_ik(P0)  # the IK itself does not watch the parallel margin
    with pytest.raises(parasils.ParallelSingularError) as e:
        robot.module1_rates(P0, np.zeros(6), np.zeros(6))
    assert (e.value.kind, e.value.threshold) == ("parallel_singular", 0.99)
    assert e.value.margin < 0.99


def test_fk_singular_guess(robot):
    q = robot.module1_ik(P0)
    with pytest.raises(parasils.SingularJacobianError) as e:
        robot.module1_fk(q, [15.0, 20.0, -500.0, 0.0, math.pi / 2, 0.0])
    err = e.value
    assert (err.kind, err.singularity, err.iteration, err.threshold) == (
        "singular_jacobian", "euler_angles", 0, 1e-6,
    )
    assert err.margin < 1e-6


def test_fk_no_convergence(tmp_path):
    robot = robot_with(tmp_path, fk_max_iterations="1")
    q = robot.module1_ik(P0)
    with pytest.raises(parasils.NoConvergenceError) as e:
        robot.module1_fk(q, P0 + [20.0, -10.0, 15.0, 0.1, -0.1, 0.1])
    err = e.value
    assert err.kind == "no_convergence" and err.iterations >= 1 and err.residual > 1e-13


def test_fk_other_branch(robot):
    with pytest.raises(parasils.BranchMismatchError) as e:
        robot.module1_fk([1e4] * 6, P0)
    assert (e.value.kind, e.value.actuator) == ("branch_mismatch", 1)


def test_nan_actuators(robot):
    with pytest.raises(parasils.NonFiniteError) as e:
        robot.module1_fk([100.0, np.nan, 0, 0, 0, 0], P0)
    assert e.value.what == "q2"


# --- robot files ----------------------------------------------------------------


def test_missing_robot_file(tmp_path):
    with pytest.raises(FileNotFoundError) as e:
        parasils.Robot.from_toml(tmp_path / "nowhere.toml")
    assert e.value.filename == str(tmp_path / "nowhere.toml")


def test_malformed_toml(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[module1]\nassumed = [true\n")
    with pytest.raises(parasils.RobotFileError) as e:
        parasils.Robot.from_toml(path)
    err = e.value
    assert (err.kind, err.path, err.line) == ("parse", str(path), 2)
    assert str(path) in str(err)


def test_robot_file_bad_key_value(tmp_path):
    with pytest.raises(parasils.RobotFileError) as e:
        robot_with(tmp_path, link_length_mm="-350.0")
    err = e.value
    assert err.kind == "parse" and err.key == "link_length_mm" and err.line is not None
    assert "link_length_mm" in err.text


def test_robot_file_invalid_geometry(tmp_path):
    with pytest.raises(parasils.RobotFileError) as e:
        robot_with(tmp_path, beta_deg="95.0")
    err = e.value
    assert err.kind == "invalid" and err.key == "[left] beta_deg"
    cause = err.__cause__
    assert isinstance(cause, parasils.InvalidParameterError)
    assert cause.what == "instrument.beta" and cause.value == pytest.approx(math.radians(95))
