"""simulate(tip_load_left_n=, tip_load_right_n=): the force columns checked
in NumPy by virtual work against central differences of the bindings' own
inverse and forward kinematics, and against the CLI's table to the bit."""

import numpy as np
import pytest

import parasils
from conftest import LEFT_TIP, P0, ROOT, default_right_tip, rotation
from test_simulate import read_csv

LEFT_N = np.array([5.0, -3.0, 8.0])
RIGHT_N = np.array([-2.0, 4.0, 10.0])
FORCES = [f"q{j}_force_n" for j in range(1, 7)] + [
    f"{side}_{name}"
    for side in ("left", "right")
    for name in ("qs1_torque_nmm", "qs2_torque_nmm", "qs3_force_n")
]
DEFLECTIONS = ["left_tip_deflection_mm", "right_tip_deflection_mm"]


@pytest.fixture(scope="module")
def table():
    return parasils.simulate(
        rate_hz=200.0, tip_load_left_n=list(LEFT_N), tip_load_right_n=list(RIGHT_N)
    )


def pose_at(table, k):
    """The row's pose, mm and rad."""
    return np.array(
        [table["x_mm"][k], table["y_mm"][k], table["z_mm"][k]]
        + [np.radians(table[f"{a}_deg"][k]) for a in ("psi", "theta", "phi")]
    )


def test_the_columns_come_last_only_with_a_load(table):
    assert list(table)[-14:] == FORCES + DEFLECTIONS
    plain = parasils.simulate(rate_hz=200.0)
    assert list(table)[:-14] == list(plain)
    assert np.all(table["left_tip_deflection_mm"] > 0) and np.all(table["right_tip_deflection_mm"] > 0)
    for name in plain:
        assert np.array_equal(table[name], plain[name]), name


def test_module1_by_virtual_work_against_the_ik(table, robot):
    # The generalised forces of the tips' wrench on (x, y, z, psi, theta,
    # phi), written here: the force, and the moment about P on the angular
    # velocity per unit rate of each Euler angle (R = R_X R_Y R_Z: x, R_X y,
    # R_X R_Y z).
    right_tip = default_right_tip(P0, LEFT_TIP)
    checked = 0
    for k in range(0, len(table["t_s"]), 45):
        pose = pose_at(table, k)
        p = pose[:3]
        moment = np.cross(LEFT_TIP - p, LEFT_N) + np.cross(right_tip - p, RIGHT_N)
        rx = rotation(pose[3], 0.0, 0.0)
        rxy = rotation(pose[3], pose[4], 0.0)
        axes = [np.array([1.0, 0, 0]), rx @ [0, 1.0, 0], rxy @ [0, 0, 1.0]]
        expected = np.concatenate([LEFT_N + RIGHT_N, [moment @ a for a in axes]])
        tau = np.array([table[f"q{j}_force_n"][k] for j in range(1, 7)])
        fd = np.empty(6)
        for i in range(6):
            h = 1e-3 if i < 3 else 1e-5
            dx = np.zeros(6)
            dx[i] = h
            dq = (robot.module1_ik(pose + dx) - robot.module1_ik(pose - dx)) / (2 * h)
            fd[i] = tau @ dq
        assert np.linalg.norm(fd - expected) <= 1e-7 * np.linalg.norm(expected), (k, fd, expected)
        checked += 1
    assert checked >= 20


@pytest.mark.parametrize("side, load", [("left", LEFT_N), ("right", RIGHT_N)])
def test_each_module_by_virtual_work_against_the_fk(table, robot, side, load):
    for k in range(0, len(table["t_s"]), 90):
        pose = pose_at(table, k)
        qs = np.array(
            [
                np.radians(table[f"{side}_qs1_deg"][k]),
                np.radians(table[f"{side}_qs2_deg"][k]),
                table[f"{side}_qs3_mm"][k],
            ]
        )
        tau = [table[f"{side}_{n}"][k] for n in ("qs1_torque_nmm", "qs2_torque_nmm", "qs3_force_n")]
        for i in range(3):
            h = 1e-6 if i < 2 else 1e-4
            dq = np.zeros(3)
            dq[i] = h
            v = (robot.instrument_fk(side, pose, qs + dq) - robot.instrument_fk(side, pose, qs - dq)) / (2 * h)
            assert abs(load @ v - tau[i]) <= 1e-7 * max(abs(t) for t in tau), (side, k, i)


def test_the_cli_s_table_to_the_bit(run_cli, tmp_path, table):
    path = tmp_path / "cli.csv"
    run_cli(
        "simulate", "--rate", "200", "--tip-load-left", "5,-3,8", "--tip-load-right", "-2,4,10", "-o", path
    )
    expected = read_csv(path)
    assert list(table) == list(expected)
    for name in table:
        assert np.array_equal(
            table[name].view(np.uint64), np.ascontiguousarray(expected[name], dtype=np.float64).view(np.uint64)
        ), name


def test_a_load_of_the_wrong_shape_is_refused():
    with pytest.raises(ValueError, match="tip_load_left_n"):
        parasils.simulate(rate_hz=50.0, tip_load_left_n=[1.0, 2.0])


DYNAMICS_FILE = ROOT / "robots" / "dynamics.toml"
# robots/dynamics.toml's body (assumed), written here: kg, mm, kg mm^2, mm/s^2.
MASS, COM = 6.0, np.array([0.0, 0.0, 120.0])
INERTIA = np.diag([6.0 * (3 * 150.0**2 + 200.0**2) / 12] * 2 + [6.0 * 150.0**2 / 2])
GRAVITY = np.array([0.0, 0.0, -9810.0])


def test_a_robot_with_dynamics_holds_its_body_by_newton_euler(robot):
    """The robot file's [dynamics] alone gives the force columns, and module
    1's forces are the body's Newton-Euler wrench, written here in NumPy from
    the table's own pose, Euler rates and accelerations (P and phi held),
    by virtual work against central differences of the bindings' IK."""
    table = parasils.simulate(robot=parasils.Robot.from_toml(DYNAMICS_FILE), rate_hz=100.0)
    assert list(table)[-14:] == FORCES + DEFLECTIONS
    assert np.all(table["left_qs3_force_n"] == 0.0)
    e = np.eye(3)
    checked = 0
    for k in range(0, len(table["t_s"]), 25):
        pose = pose_at(table, k)
        psi, theta, phi = pose[3:]
        rate = [np.radians(table[f"{a}_rate_deg_s"][k]) for a in ("psi", "theta")]
        acc = [np.radians(table[f"{a}_acc_deg_s2"][k]) for a in ("psi", "theta")]
        r = rotation(psi, theta, phi)
        y1 = rotation(psi, 0.0, 0.0) @ e[1]
        omega = rate[0] * e[0] + rate[1] * y1
        alpha = acc[0] * e[0] + acc[1] * y1 + rate[0] * rate[1] * np.cross(e[0], y1)
        c = r @ COM
        a_c = np.cross(alpha, c) + np.cross(omega, np.cross(omega, c))
        force = MASS * (a_c - GRAVITY) / 1000.0
        inertia = r @ INERTIA @ r.T
        moment = np.cross(c, force) + (inertia @ alpha + np.cross(omega, inertia @ omega)) / 1000.0
        axes = [e[0], y1, rotation(psi, theta, 0.0) @ e[2]]
        expected = np.concatenate([force, [moment @ a for a in axes]])
        tau = np.array([table[f"q{j}_force_n"][k] for j in range(1, 7)])
        fd = np.empty(6)
        for i in range(6):
            h = 1e-3 if i < 3 else 1e-5
            dx = np.zeros(6)
            dx[i] = h
            dq = (robot.module1_ik(pose + dx) - robot.module1_ik(pose - dx)) / (2 * h)
            fd[i] = tau @ dq
        assert np.linalg.norm(fd - expected) <= 1e-7 * np.linalg.norm(expected), (k, fd, expected)
        checked += 1
    assert checked >= 15


def test_the_stiffness_map_is_linear_in_its_load_and_empty_where_infeasible():
    robot = parasils.Robot()
    once = robot.reach_map(P0, step_deg=7.5, line=False, deflection_load_n=[0.0, 0.0, -10.0])
    twice = robot.reach_map(P0, step_deg=7.5, line=False, deflection_load_n=[0.0, 0.0, -20.0])
    feasible = once["feasible"]
    assert feasible.any() and not feasible.all()
    for key in ("left_tip_deflection_mm", "right_tip_deflection_mm"):
        d = once[key]
        assert d.shape == feasible.shape
        assert np.all(np.isnan(d[~feasible])) and np.all(d[feasible] > 0)
        np.testing.assert_allclose(twice[key][feasible], 2 * d[feasible], rtol=1e-12)
    plain = robot.reach_map(P0, step_deg=7.5, line=False)
    assert "left_tip_deflection_mm" not in plain
    with pytest.raises(ValueError, match="deflection load"):
        robot.reach_map(P0, step_deg=7.5, deflection_load_n=[0.0, float("nan"), 1.0])
