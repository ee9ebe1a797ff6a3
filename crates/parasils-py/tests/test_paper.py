"""The paper's numbers (docs/model.md, "Check values"), from Python."""

import numpy as np
import pytest

import parasils
from conftest import LEFT_TIP, P0, mirror_tip, rotation

DEG = np.degrees
#: The paper prints 4 decimals.
TOL = 5e-5


def deg_mm(qs):
    return np.array([DEG(qs[0]), DEG(qs[1]), qs[2]])


def test_left_at_p0(robot):
    qs = robot.instrument_ik("left", P0, LEFT_TIP)
    np.testing.assert_allclose(deg_mm(qs), [3.0889, -38.8695, 147.7687], atol=TOL, rtol=0)


def test_right_at_p0_is_the_mirror(robot, right_tip):
    np.testing.assert_allclose(right_tip, [-9.6103, 53.9889, -636.9821], atol=TOL, rtol=0)
    qs = robot.instrument_ik("right", P0, right_tip)
    np.testing.assert_allclose(deg_mm(qs), [3.0889, -38.8695, 147.7687], atol=TOL, rtol=0)


def test_left_mode_b_at_p0(tmp_path):
    # Mode B is outside the default limits (qs1 in [-120, 120] deg, qs2 in
    # [-80, 80] deg): a robot file with them widened.
    text = (
        parasils.Robot()
        .to_toml()
        .replace("qs1_deg = [-120.0, 120.0]", "qs1_deg = [-180.0, 180.0]")
        .replace("qs2_deg = [-80.0, 80.0]", "qs2_deg = [-180.0, 180.0]")
    )
    path = tmp_path / "wide.toml"
    path.write_text(text)
    robot = parasils.Robot.from_toml(path)
    qs = robot.instrument_ik("left", P0, LEFT_TIP, mode="B")
    np.testing.assert_allclose(deg_mm(qs), [-151.3897, -141.1305, 147.7687], atol=TOL, rtol=0)
    with pytest.raises(parasils.JointLimitError) as e:
        parasils.Robot().instrument_ik("left", P0, LEFT_TIP, mode="B")
    assert e.value.joint == "qs1"


def test_end_of_the_increments_reading(robot, right_tip):
    end = P0.copy()
    end[3:5] = np.radians([0.0, 35.0])
    left = robot.instrument_ik("left", end, LEFT_TIP)
    right = robot.instrument_ik("right", end, right_tip)
    np.testing.assert_allclose(deg_mm(left), [20.7942, -61.8435, 151.0378], atol=TOL, rtol=0)
    np.testing.assert_allclose(deg_mm(right), [18.5977, -13.0799, 143.6301], atol=TOL, rtol=0)


def test_module1_at_p0(robot):
    q = robot.module1_ik(P0)
    np.testing.assert_allclose(
        q, [117.942, 151.459, 56.937, 89.428, 132.193, 77.441], atol=5e-4, rtol=0
    )
    # And back, from a guess a little off.
    guess = P0 + [2.0, -1.0, 3.0, 0.01, -0.02, 0.01]
    np.testing.assert_allclose(robot.module1_fk(q, guess), P0, atol=1e-9, rtol=0)


def test_tips_held_along_the_paper_motion(robot, default_right):
    table = parasils.simulate()
    assert len(table["t_s"]) == 4501
    assert table["t_s"][-1] == 4.5
    assert table["psi_deg"][-1] == pytest.approx(0.0, abs=1e-12)
    assert table["theta_deg"][-1] == pytest.approx(35.0, abs=1e-12)
    assert np.max(table["left_tip_err_mm"]) < 1e-9
    assert np.max(table["right_tip_err_mm"]) < 1e-9
    # The joints of the table put the tips back where they were (FK here, in
    # this test, from the table's degrees).
    poses = np.column_stack(
        [table["x_mm"], table["y_mm"], table["z_mm"]]
        + [np.radians(table[c]) for c in ("psi_deg", "theta_deg", "phi_deg")]
    )
    for side, tip in (("left", LEFT_TIP), ("right", default_right)):
        qs = np.column_stack(
            [np.radians(table[f"{side}_qs1_deg"]), np.radians(table[f"{side}_qs2_deg"]), table[f"{side}_qs3_mm"]]
        )
        tips = robot.instrument_fk(side, poses, qs)
        assert np.max(np.linalg.norm(tips - tip, axis=1)) < 1e-9


def test_rotation_convention_is_xyz_intrinsic(robot):
    # The tip of a module at joints qs, from the crate, equals the formula of
    # The instrument chain (docs/model.md, "Instrument modules") written here: p_F = R (RCM + R_Y(a) R_X(qs1) R_Y(qs2) R_X(b) (0, 0, -qs3)) + P.
    def ry(a):
        return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])

    def rx(a):
        return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])

    a = b = np.radians(10.0)
    qs = np.array([0.3, -0.5, 120.0])
    local = ry(a) @ rx(qs[0]) @ ry(qs[1]) @ rx(b) @ np.array([0, 0, -qs[2]])
    expected = rotation(*P0[3:]) @ (np.array([-10.0, 0, 0]) + local) + P0[:3]
    np.testing.assert_allclose(robot.instrument_fk("left", P0, qs), expected, atol=1e-9)
    # The right module is the mirror image: S M_L S.
    s = np.diag([-1.0, 1.0, 1.0])
    expected_r = rotation(*P0[3:]) @ (np.array([10.0, 0, 0]) + s @ local) + P0[:3]
    np.testing.assert_allclose(robot.instrument_fk("right", P0, qs), expected_r, atol=1e-9)
    assert mirror_tip(P0, LEFT_TIP).shape == (3,)
