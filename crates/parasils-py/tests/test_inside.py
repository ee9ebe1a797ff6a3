"""parasils.simulate(procedure=...): the paper's rules while anything is
inside the patient, raised with the command line's message and no file
written; the shipped example that goes out and back in."""

import pytest

import parasils
from conftest import ROOT

START = {
    "pose": [5, 10, -455, -10, 5, -55],
    "tip_left_mm": [32.0, -18.5, -518.0],
    "endoscope_depth_mm": 0,
}


def issue(last_pose):
    """The issue's procedure: over the port, the endoscope in, then a
    positioning to last_pose (x, y, z mm; psi, theta, phi deg)."""
    return {
        **START,
        "motion": [
            {"type": "position", "pose": [15, 20, -500, -15, 10, -60]},
            {"type": "insert", "instrument": "endoscope", "depth_mm": 60},
            {"type": "position", "pose": last_pose},
        ],
    }


@pytest.mark.parametrize(
    "last_pose, words",
    [
        # phi from -60 to -30 deg.
        (
            [15, 20, -500, -15, 10, -30],
            "motion 2 (position): turns about the endoscope's axis while the "
            "endoscope is inside: phi would turn by 30.000 deg",
        ),
        # x from 15 to 25 mm.
        (
            [25, 20, -500, -15, 10, -60],
            "motion 2 (position): moves the incision point while the endoscope "
            "is inside: P would leave the incision point by 10.000 mm",
        ),
    ],
)
def test_a_motion_breaking_a_rule_inside_raises_and_writes_nothing(tmp_path, last_pose, words):
    out = tmp_path / "out.csv"
    with pytest.raises(ValueError) as e:
        parasils.simulate(procedure=issue(last_pose), rate_hz=100.0, out=out)
    assert str(e.value).startswith(words), str(e.value)
    assert list(tmp_path.iterdir()) == []


def test_retract_reposition_goes_out_and_back_in():
    table = parasils.simulate(
        procedure=ROOT / "procedures" / "retract-reposition.toml", rate_hz=100.0
    )
    depth = table["endoscope_depth_mm"]
    # In by 60 mm, out to 0, in again by 50 mm at the new port.
    assert depth.max() == pytest.approx(60.0, abs=1e-12)
    assert depth[-1] == pytest.approx(50.0, abs=1e-12)
    # The platform crossed from one port to the next (x from 15 to 25 mm)
    # only with the endoscope out; with it in, x is on one port or the other.
    x = table["x_mm"]
    between = (x > 15.0 + 1e-9) & (x < 25.0 - 1e-9)
    assert between.any()
    assert (depth[between] == 0.0).all()
    inside = depth > 1e-9
    on_a_port = (abs(x - 15.0) < 1e-9) | (abs(x - 25.0) < 1e-9)
    assert on_a_port[inside].all()
