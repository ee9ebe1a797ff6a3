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
