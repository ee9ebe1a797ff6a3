"""Robot.reorientation_path and Robot.optimal_reorientation: motion type 4 as
a path with its exact derivatives, and its time-optimal timing."""

import math

import numpy as np
import pytest

import parasils
from conftest import LEFT_TIP, P0

DPSI, DTHETA = math.radians(15.0), math.radians(25.0)


def test_path_positions_are_the_inverse_kinematics_along_the_line():
    robot = parasils.Robot()
    s = np.array([0.0, 0.3, 1.0])
    q = robot.reorientation_path(P0, None, DPSI, DTHETA, s, 0)
    assert q.shape == (3, 12)
    for k, sk in enumerate(s):
        pose = P0.copy()
        pose[3] += sk * DPSI
        pose[4] += sk * DTHETA
        np.testing.assert_allclose(q[k, :6], robot.module1_ik(pose), rtol=0, atol=1e-9)
        np.testing.assert_allclose(q[k, 6:9], robot.instrument_ik("left", pose, LEFT_TIP), atol=1e-12)


def test_derivatives_match_finite_differences():
    robot = parasils.Robot()
    s = np.linspace(0.05, 0.95, 7)
    h = 1e-4
    q = lambda x, order=0: robot.reorientation_path(P0, None, DPSI, DTHETA, x, order)
    d1, d2 = q(s, 1), q(s, 2)
    fd1 = (q(s + h) - q(s - h)) / (2 * h)
    fd2 = (q(s + h) - 2 * q(s) + q(s - h)) / h**2
    np.testing.assert_allclose(d1, fd1, rtol=0, atol=1e-6 * np.abs(d1).max())
    np.testing.assert_allclose(d2, fd2, rtol=0, atol=1e-4 * np.abs(d2).max())


def test_bad_order_and_tips_are_value_errors():
    robot = parasils.Robot()
    with pytest.raises(ValueError, match="order"):
        robot.reorientation_path(P0, None, DPSI, DTHETA, [0.5], 3)
    with pytest.raises(ValueError, match="tips"):
        robot.reorientation_path(P0, np.zeros(3), DPSI, DTHETA, [0.5], 0)


def test_a_turn_out_of_reach_names_the_kinematics_error():
    with pytest.raises(parasils.KinematicsError, match="path at s ="):
        parasils.Robot().reorientation_path(P0, None, 0.0, math.radians(170.0), [1.0], 0)


def test_optimal_timing_of_the_paper_turn_is_faster_than_the_trapezoid_and_within_limits():
    robot = parasils.Robot()
    r = robot.optimal_reorientation(P0, None, DPSI, DTHETA)
    assert 0 < r["duration_s"] < 4.5
    assert r["phases"][0]["binding"] == "module 1 q6"
    assert {p["limit"] for p in r["phases"]} == {"velocity", "acceleration"}
    s, s_dot, s_ddot = r["s"], r["s_dot"], r["s_ddot"]
    assert s_dot[0] == 0 and s_dot[-1] == 0 and r["t_s"][-1] == r["duration_s"]
    # Every actuator within its assumed limit at the knots, from the exact derivatives.
    d1 = robot.reorientation_path(P0, None, DPSI, DTHETA, s, 1)
    d2 = robot.reorientation_path(P0, None, DPSI, DTHETA, s, 2)
    v_max = np.array([50.0] * 6 + [math.radians(30), math.radians(30), 60.0] * 2)
    a_max = np.array([100.0] * 6 + [math.radians(60), math.radians(60), 60.0] * 2)
    vel = np.abs(d1 * s_dot[:, None]) / v_max
    acc = np.abs(d1 * s_ddot[:, None] + d2 * (s_dot**2)[:, None]) / a_max
    assert vel.max() <= 1 + 1e-9 and acc.max() <= 1 + 1e-9
    assert max(vel.max(), acc.max()) > 0.999


def test_angular_limits_bind_when_given():
    robot = parasils.Robot()
    unlimited = np.full(12, np.inf)
    r = robot.optimal_reorientation(
        P0,
        None,
        DPSI,
        DTHETA,
        velocity_max=unlimited,
        acceleration_max=unlimited,
        omega_max_deg_s=10.0,
        eps_max_deg_s2=5.0,
    )
    # theta's own trapezoid: 4.5 s, within the grid's resolution.
    assert 4.5 * (1 - 1e-12) <= r["duration_s"] <= 4.5 * (1 + 2e-3)
    assert {p["binding"] for p in r["phases"]} == {"theta"}


def test_angular_limits_in_rad_under_their_old_names_warn_and_agree():
    robot = parasils.Robot()
    unlimited = np.full(12, np.inf)
    common = dict(velocity_max=unlimited, acceleration_max=unlimited)
    new = robot.optimal_reorientation(P0, None, DPSI, DTHETA, omega_max_deg_s=10.0, eps_max_deg_s2=5.0, **common)
    with pytest.warns(DeprecationWarning, match=r"optimal_reorientation\(omega_max=...\) is deprecated: use omega_max_deg_s"):
        with pytest.warns(DeprecationWarning, match="use eps_max_deg_s2"):
            old = robot.optimal_reorientation(
                P0, None, DPSI, DTHETA, omega_max=math.radians(10.0), eps_max=math.radians(5.0), **common
            )
    assert old["duration_s"] == new["duration_s"]
    for key in ("s", "t_s", "s_dot", "s_ddot"):
        np.testing.assert_array_equal(old[key], new[key], err_msg=key)
    # One limit alone binds as well: 10 deg/s caps theta's 25 deg turn from
    # below at 2.5 s, whatever the name.
    with pytest.warns(DeprecationWarning):
        old = robot.optimal_reorientation(P0, None, DPSI, DTHETA, omega_max=math.radians(10.0), **common)
    new = robot.optimal_reorientation(P0, None, DPSI, DTHETA, omega_max_deg_s=10.0, **common)
    assert old["duration_s"] == new["duration_s"] >= 2.5
    with pytest.raises(TypeError, match="both eps_max_deg_s2 and its deprecated name eps_max"):
        robot.optimal_reorientation(P0, None, DPSI, DTHETA, eps_max=0.1, eps_max_deg_s2=5.0)


def test_optimal_timing_uses_the_robot_files_limits(tmp_path):
    # q6, which binds the paper's turn, at half its default velocity (50 mm/s)
    # and a quarter of its acceleration (100 mm/s^2) in the robot file.
    text = parasils.Robot().to_toml()
    guides = text.split("[[module1.guides]]")
    assert len(guides) == 7
    q6 = guides[6].replace("velocity_max_mm_s = 50.0", "velocity_max_mm_s = 25.0")
    q6 = q6.replace("acceleration_max_mm_s2 = 100.0", "acceleration_max_mm_s2 = 25.0")
    assert q6 != guides[6]
    path = tmp_path / "slow-q6.toml"
    path.write_text("[[module1.guides]]".join(guides[:6] + [q6]))
    slow = parasils.Robot.from_toml(path)
    default = parasils.Robot().optimal_reorientation(P0, None, DPSI, DTHETA)
    r = slow.optimal_reorientation(P0, None, DPSI, DTHETA)
    assert r["duration_s"] > 1.5 * default["duration_s"]
    # Passing the defaults explicitly gives the default robot's law back.
    v_max = np.array([50.0] * 6 + [math.radians(30), math.radians(30), 60.0] * 2)
    a_max = np.array([100.0] * 6 + [math.radians(60), math.radians(60), 60.0] * 2)
    back = slow.optimal_reorientation(
        P0, None, DPSI, DTHETA, velocity_max=v_max, acceleration_max=a_max
    )
    assert back["duration_s"] == default["duration_s"]
    # The slow robot's own limits hold at the knots.
    s, s_dot, s_ddot = r["s"], r["s_dot"], r["s_ddot"]
    d1 = slow.reorientation_path(P0, None, DPSI, DTHETA, s, 1)
    d2 = slow.reorientation_path(P0, None, DPSI, DTHETA, s, 2)
    v_max[5], a_max[5] = 25.0, 25.0
    vel = np.abs(d1 * s_dot[:, None]) / v_max
    acc = np.abs(d1 * s_ddot[:, None] + d2 * (s_dot**2)[:, None]) / a_max
    assert vel.max() <= 1 + 1e-9 and acc.max() <= 1 + 1e-9
