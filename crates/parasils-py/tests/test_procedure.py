"""parasils.simulate(procedure=...): the CLI's procedure, the same bits; the
motion types against independent truths written here with NumPy."""

import numpy as np
import pytest

import parasils
from conftest import ROOT, rotation
from test_simulate import read_csv

DEMO = ROOT / "procedures" / "sils-demo.toml"

EXTRA = [
    "motion",
    "motion_type",
    "endoscope_depth_mm",
    "left_tip_x_mm",
    "left_tip_y_mm",
    "left_tip_z_mm",
    "right_tip_x_mm",
    "right_tip_y_mm",
    "right_tip_z_mm",
    "endoscope_tip_x_mm",
    "endoscope_tip_y_mm",
    "endoscope_tip_z_mm",
]


def bits(a):
    return np.asarray(a, dtype=np.float64).view(np.uint64)


def test_the_demo_equals_the_cli_csv_to_the_last_bit(run_cli, tmp_path):
    path = tmp_path / "demo.csv"
    run_cli("simulate", "--procedure", DEMO, "--rate", "200", "-o", path)
    expected = read_csv(path)
    table = parasils.simulate(procedure=DEMO, rate_hz=200.0)
    assert list(table) == list(parasils.COLUMNS) + EXTRA == list(expected)
    for name in table:
        assert np.array_equal(bits(table[name]), bits(expected[name])), name
    assert table["motion"].dtype == np.int64
    assert list(np.unique(table["motion"])) == [0, 1, 2, 3, 4, 5]
    assert list(table["motion_type"][np.unique(table["motion"], return_index=True)[1]]) == [1, 2, 3, 4, 3, 2]


def test_check_prints_the_table_and_writes_nothing(run_cli, tmp_path):
    out = run_cli("simulate", "--procedure", DEMO, "--check").stdout
    assert out.startswith("procedure OK: 6 motions")
    for name in ["platform down to the port", "endoscope in", "camera to the target"]:
        assert name in out


def test_a_dict_is_read_like_the_file():
    motions = [
        {"type": "insert", "instrument": "endoscope", "depth_mm": 40},
        {"type": "manipulate", "instrument": "left", "tip_mm": [55, -45, -600], "velocity_mm_s": 8},
        {"type": "reorient", "psi_deg": 5, "theta_deg": -5, "name": "look left"},
    ]
    start = {"pose": [15, 20, -460, -15, 10, -60], "tip_left_mm": [50, -50, -580]}
    table = parasils.simulate(procedure={**start, "motion": motions}, rate_hz=100.0)
    # The insertion: 40 mm at 20 mm/s and 20 mm/s^2 takes 3 s, a whole
    # number of periods: its last row is at 3 s, at rest on its target, and
    # the next motion starts on the next cycle.
    first = table["motion"] == 0
    assert table["t_s"][first][-1] == 3.0
    assert table["t_s"][table["motion"] == 1][0] == 3.01
    assert table["endoscope_depth_mm"][first][-1] == 40.0
    assert table["endoscope_depth_mm"][first][:-1].max() < 40.0
    assert table["endoscope_depth_mm"][-1] == 40.0
    # The endoscope tip is P + R (0, 0, -depth), written here independently.
    for k in range(0, len(table["t_s"]), 37):
        pose = np.array([table[c][k] for c in ["x_mm", "y_mm", "z_mm"]])
        r = rotation(*np.radians([table[c][k] for c in ["psi_deg", "theta_deg", "phi_deg"]]))
        tip = pose + r @ np.array([0.0, 0.0, -table["endoscope_depth_mm"][k]])
        got = np.array([table[f"endoscope_tip_{a}_mm"][k] for a in "xyz"])
        assert np.abs(tip - got).max() < 1e-9
    # The left tip on its straight line during motion 1, at its target at the end.
    m1 = table["motion"] == 1
    tips = np.stack([table[f"left_tip_{a}_mm"][m1] for a in "xyz"], axis=1)
    target = np.array([55.0, -45.0, -600.0])
    u = (target - tips[0]) / np.linalg.norm(target - tips[0])
    d = tips - tips[0]
    off = d - np.outer(d @ u, u)
    assert np.abs(off).max() < 1e-9
    # Motion 1 ends on its target, where motion 2 starts a cycle later.
    end = np.argmax(table["motion"] == 2) - 1
    assert table["motion"][end] == 1
    tip_end = np.array([table[f"left_tip_{a}_mm"][end] for a in "xyz"])
    assert np.linalg.norm(tip_end - target) < 1e-9
    assert table["left_tip_err_mm"].max() < 1e-9
    # The last motion turns the camera by (5, -5) deg from where it was (the
    # platform is still during motion 1).
    last, before = table["motion"] == 2, table["motion"] == 1
    assert table["psi_deg"][last][-1] - table["psi_deg"][before][-1] == pytest.approx(5.0, abs=1e-9)
    assert table["theta_deg"][last][-1] - table["theta_deg"][before][-1] == pytest.approx(-5.0, abs=1e-9)


def test_a_failing_motion_is_named():
    motions = [
        {"type": "insert", "instrument": "endoscope", "depth_mm": 20},
        {"type": "reorient", "psi_deg": 2, "theta_deg": 2},
        {"type": "manipulate", "instrument": "left", "tip_mm": [55, -45, -600]},
        {"type": "insert", "instrument": "left", "depth_mm": 250, "name": "too deep"},
    ]
    start = {"pose": [15, 20, -460, -15, 10, -60], "tip_left_mm": [50, -50, -580]}
    with pytest.raises(parasils.JointLimitError) as e:
        parasils.simulate(procedure={**start, "motion": motions}, rate_hz=100.0)
    assert str(e.value).startswith('motion 3 (insert "too deep"), ')
    assert "qs3" in str(e.value)
    assert e.value.t > 0


@pytest.mark.parametrize(
    "procedure, needle",
    [
        ({"motion": [{"type": "insert", "instrument": "left"}]}, "motion 0, key `depth_mm`: missing"),
        ({"motion": [{"type": "jump"}]}, "unknown motion type \"jump\""),
        ({"motion": []}, "at least one [[motion]]"),
        ({"motion": [{"type": "reorient", "psi_deg": 1, "theta_deg": 1, "speed": 2}]}, "unknown field `speed`"),
    ],
)
def test_bad_procedures_are_value_errors(procedure, needle):
    with pytest.raises(ValueError, match=None) as e:
        parasils.simulate(procedure=procedure)
    assert needle in str(e.value)


def test_scenario_arguments_do_not_mix_with_a_procedure():
    with pytest.raises(TypeError, match="psi_deg"):
        parasils.simulate(procedure=DEMO, psi_deg=3.0)
    with pytest.raises(TypeError, match="procedure must be"):
        parasils.simulate(procedure=3)


def test_a_motion_cut_short_then_stopped():
    table = parasils.simulate(
        procedure={
            "motion": [
                {"type": "reorient", "psi_deg": 15, "theta_deg": 25, "until_s": 2.0},
                {"type": "stop", "name": "pedal released"},
            ]
        },
        rate_hz=1000.0,
    )
    t, motion = table["t_s"], table["motion"]
    cut = np.argmax(motion == 1)
    assert t[cut] == 2.0
    # The stop keeps the type of the turn it stops; the angles' rates are
    # continuous at the cut and zero at the end.
    assert set(table["motion_type"]) == {4}
    for a in ["psi", "theta"]:
        rate = table[f"{a}_rate_deg_s"]
        assert abs(rate[cut] - rate[cut - 1]) < 5.0 * 1e-3 + 1e-9
        assert rate[-1] == 0.0
        # It decelerates at the turn's own 5 deg/s^2 (the first sample of a
        # stop has its deceleration; the turn before was accelerating).
        acc = table[f"{a}_acc_deg_s2"][motion == 1]
        assert np.abs(acc).max() <= 5.0 + 1e-9
    assert table["left_tip_err_mm"].max() < 1e-9
