"""Procedures aimed by what the camera looks at, and jerk-limited motions,
through parasils.simulate(procedure=dict): checked against a pinhole and
finite differences written here with NumPy."""

import numpy as np
import pytest

import parasils
from conftest import rotation

START = {
    "pose": [15, 20, -500, -15, 10, -60],
    "tip_left_mm": [50, -50, -580],
    "endoscope_depth_mm": 60,
}


def row(table, k, names):
    return np.array([table[n][k] for n in names])


def image(table, k, point, hfov_deg=70.0, aspect=16 / 9):
    """A straight scope's normalised image coordinates of `point` at row k."""
    r = rotation(*np.radians(row(table, k, ["psi_deg", "theta_deg", "phi_deg"])))
    p = row(table, k, ["x_mm", "y_mm", "z_mm"])
    eye = p + r @ np.array([0.0, 0.0, -table["endoscope_depth_mm"][k]])
    d = point - eye
    ahead = -r[:, 2] @ d
    tan = np.tan(np.radians(hfov_deg) / 2)
    return (r[:, 0] @ d) / ahead / tan, (r[:, 1] @ d) / ahead / (tan / aspect)


def test_looking_at_the_tips_puts_their_midpoint_at_the_image_centre():
    table = parasils.simulate(
        procedure={**START, "motion": [{"type": "reorient", "look_at": "tips"}]},
        rate_hz=200.0,
    )
    left = row(table, 0, [f"left_tip_{a}_mm" for a in "xyz"])
    right = row(table, 0, [f"right_tip_{a}_mm" for a in "xyz"])
    mid = (left + right) / 2
    u0, v0 = image(table, 0, mid)
    assert np.hypot(u0, v0) > 0.05  # off centre before the turn
    last = len(table["t_s"]) - 1
    u, v = image(table, last, mid)
    assert abs(u) < 1e-9 and abs(v) < 1e-9
    # The tips held, phi still.
    tips = np.stack([table[f"left_tip_{a}_mm"] for a in "xyz"], axis=1)
    assert np.abs(tips - left).max() < 1e-9
    assert np.all(table["phi_deg"] == table["phi_deg"][0])


def test_a_jerk_limited_insertion_has_a_continuous_acceleration():
    insert = {"type": "insert", "instrument": "left", "depth_mm": 30}
    smooth = parasils.simulate(
        procedure={**START, "motion": [{**insert, "jerk_mm_s3": 40}]}, rate_hz=1000.0
    )
    plain = parasils.simulate(procedure={**START, "motion": [insert]}, rate_hz=1000.0)
    for table in (smooth, plain):
        qs3 = table["left_qs3_mm"]
        assert qs3[-1] - qs3[0] == pytest.approx(30.0, abs=1e-12)
    # The double S: 3 s by hand (v 20 mm/s, a 20 mm/s^2, j 40 mm/s^3);
    # its acceleration moves by at most j dt per row, the trapezoid's jumps.
    assert smooth["t_s"][-1] == pytest.approx(3.0, abs=1e-12)
    step = np.abs(np.diff(smooth["left_qs3_acc_mm_s2"])).max()
    assert step <= 40.0 * 1e-3 * (1 + 1e-9)
    assert np.abs(np.diff(plain["left_qs3_acc_mm_s2"])).max() == pytest.approx(20.0)
    # The rate column against central differences of the position.
    t, q, v = smooth["t_s"], smooth["left_qs3_mm"], smooth["left_qs3_rate_mm_s"]
    fd = (q[2:] - q[:-2]) / (t[2:] - t[:-2])
    assert np.abs(fd - v[1:-1]).max() < 1e-4


@pytest.mark.parametrize(
    "motion, needle",
    [
        ({"type": "reorient", "look_at": "spleen"}, '"spleen" is not one of'),
        ({"type": "reorient", "look_at": "tips", "theta_deg": 3}, "theta_deg"),
        ({"type": "stop", "jerk_mm_s3": 10}, "jerk_mm_s3"),
    ],
)
def test_bad_look_at_and_jerk_keys_are_value_errors(motion, needle):
    with pytest.raises(ValueError) as e:
        parasils.simulate(procedure={**START, "motion": [motion]})
    assert needle in str(e.value)


def paper_image(table, k, point, hfov_deg=70.0, aspect=16 / 9):
    """The paper's run (the endoscope at its port: the eye at P): a straight
    scope's normalised image coordinates of `point` at row k, and whether it
    is ahead."""
    r = rotation(*np.radians(row(table, k, ["psi_deg", "theta_deg", "phi_deg"])))
    d = np.asarray(point) - row(table, k, ["x_mm", "y_mm", "z_mm"])
    ahead = -r[:, 2] @ d
    tan = np.tan(np.radians(hfov_deg) / 2)
    return (r[:, 0] @ d) / ahead / tan, (r[:, 1] @ d) / ahead / (tan / aspect), ahead > 0


def twist_deg(r_rel, axis):
    """The twist about `axis` of the rotation `r_rel` (its quaternion's
    part along the axis), deg in (-180, 180]."""
    w = np.sqrt(max(1.0 + np.trace(r_rel), 0.0)) / 2
    v = np.array(
        [
            r_rel[2, 1] - r_rel[1, 2],
            r_rel[0, 2] - r_rel[2, 0],
            r_rel[1, 0] - r_rel[0, 1],
        ]
    ) / (4 * w)
    g = np.degrees(2 * np.arctan2(v @ axis, w))
    return (g + 180.0) % 360.0 - 180.0


def test_the_image_columns_are_a_numpy_pinhole_of_the_tips():
    table = parasils.simulate(rate_hz=100.0)
    left = np.array([50.0, -50.0, -620.0])
    tips = {"left": left, "right": None}
    # The right tip: the left one's mirror across the platform's Y'Z'
    # plane, moved 35 mm along X' and 100 mm along Y' (the default).
    r0 = rotation(*np.radians([-15.0, 10.0, -60.0]))
    p0 = np.array([15.0, 20.0, -500.0])
    local = r0.T @ (left - p0)
    tips["right"] = p0 + r0 @ (local * np.array([-1.0, 1.0, 1.0]) + np.array([35.0, 100.0, 0.0]))
    for k in range(0, len(table["t_s"]), 7):
        for side, tip in tips.items():
            u, v, ahead = paper_image(table, k, tip)
            assert table[f"{side}_tip_u"][k] == pytest.approx(u, abs=1e-12)
            assert table[f"{side}_tip_v"][k] == pytest.approx(v, abs=1e-12)
            seen = int(ahead and abs(u) <= 1 and abs(v) <= 1)
            assert table[f"{side}_tip_in_view"][k] == seen
    assert table["left_tip_in_view"].dtype == np.float64


def test_the_roll_is_the_twist_of_the_rotation_between_frames():
    table = parasils.simulate(rate_hz=100.0)
    angles = np.radians(np.stack([table[c] for c in ("psi_deg", "theta_deg", "phi_deg")], axis=1))
    r0 = rotation(*angles[0])
    view0 = -r0[:, 2]
    for k in range(len(table["t_s"])):
        expected = twist_deg(rotation(*angles[k]) @ r0.T, view0)
        assert table["camera_roll_deg"][k] == pytest.approx(expected, abs=1e-9)
    # About the integral of -psi_dot sin theta (deg), the straight scope's
    # spin about its view with phi held.
    rate = -table["psi_rate_deg_s"] * np.sin(angles[:, 1])
    spin = np.sum(0.5 * (rate[1:] + rate[:-1]) * np.diff(table["t_s"]))
    assert table["camera_roll_deg"][-1] == pytest.approx(spin, rel=0.05)


@pytest.mark.parametrize("timing", ["trapezoid", "optimal"])
@pytest.mark.parametrize("look_at", ["tips", "left", [40.0, 50.0, -650.0]])
def test_look_at_ends_with_the_target_at_the_image_centre(look_at, timing):
    table = parasils.simulate(look_at=look_at, timing=timing, rate_hz=200.0)
    assert table["camera_aim_error_deg"][0] > 0.1
    assert table["camera_aim_error_deg"][-1] < 1e-9
    if look_at == "left":
        assert abs(table["left_tip_u"][-1]) < 1e-9 and abs(table["left_tip_v"][-1]) < 1e-9
    assert np.all(table["phi_deg"] == table["phi_deg"][0])


def test_look_at_with_angles_is_refused():
    with pytest.raises(TypeError, match="look_at cannot be given with psi_deg"):
        parasils.simulate(look_at="tips", psi_deg=10.0)
    with pytest.raises(ValueError, match="look_at must be"):
        parasils.simulate(look_at="middle")
