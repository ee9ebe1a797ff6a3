"""One input model for both front ends: every option of ``simulate`` that the
CLI has too, given in both, gives the same table to the last bit; what a
procedure excludes is refused by both, naming the same field; a Robot read
from a file carries its supervisor thresholds."""

import subprocess

import numpy as np
import pytest

import parasils
from conftest import ROOT
from test_simulate import ROBOT_FILE, read_csv

DEMO = ROOT / "procedures" / "sils-demo.toml"

#: (id, keyword arguments of simulate, the CLI's flags for the same request):
#: each option at least once, alone where it can be, at 200 Hz to stay quick.
PAIRS = [
    ("psi", dict(psi_deg=-7.5), ["--psi", "-7.5"]),
    ("theta", dict(theta_deg=12.0), ["--theta", "12"]),
    ("absolute", dict(absolute=True, psi_deg=-5.0, theta_deg=20.0), ["--absolute", "--psi", "-5", "--theta", "20"]),
    ("omega-max", dict(omega_max_deg_s=6.0), ["--omega-max", "6"]),
    ("eps-max", dict(eps_max_deg_s2=2.5), ["--eps-max", "2.5"]),
    ("sync-phase", dict(sync="phase"), ["--sync", "phase"]),
    ("sync-time", dict(sync="time"), ["--sync", "time"]),
    ("sync-none", dict(sync="none"), ["--sync", "none"]),
    ("timing-trapezoid", dict(timing="trapezoid"), ["--timing", "trapezoid"]),
    ("timing-optimal", dict(timing="optimal"), ["--timing", "optimal"]),
    # The paper's own limits, given: under the optimal timing they bind.
    ("optimal-omega-10", dict(timing="optimal", omega_max_deg_s=10.0), ["--timing", "optimal", "--omega-max", "10"]),
    ("optimal-eps-5", dict(timing="optimal", eps_max_deg_s2=5.0), ["--timing", "optimal", "--eps-max", "5"]),
    ("pose", dict(pose_mm_deg=[10.0, 25.0, -510.0, -12.0, 8.0, -55.0]), ["--pose", "10,25,-510,-12,8,-55"]),
    ("tip-left", dict(tip_left_mm=[45.0, -52.5, -615.0]), ["--tip-left", "45,-52.5,-615"]),
    ("tip-right", dict(tip_right_mm=[-48.0, -50.0, -625.0]), ["--tip-right", "-48,-50,-625"]),
    ("robot-file", dict(robot=str(ROBOT_FILE)), ["--robot", ROBOT_FILE]),
    ("retarget", dict(retarget=[(1.0, 5.0, 10.0)]), ["--retarget", "1:5,10"]),
    ("stop-at", dict(stop_at_s=2.0), ["--stop-at", "2"]),
    ("look-at-tips", dict(look_at="tips"), ["--look-at", "tips"]),
    ("look-at-point-optimal", dict(look_at=[40.0, 50.0, -650.0], timing="optimal"), ["--look-at", "40,50,-650", "--timing", "optimal"]),
    ("procedure", dict(procedure=str(DEMO)), ["--procedure", DEMO]),
    ("procedure-optimal", dict(procedure=str(DEMO), timing="optimal"), ["--procedure", DEMO, "--timing", "optimal"]),
]


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


@pytest.mark.parametrize("kwargs, args", [p[1:] for p in PAIRS], ids=[p[0] for p in PAIRS])
def test_each_option_gives_the_cli_s_table_to_the_bit(run_cli, tmp_path, kwargs, args):
    path = tmp_path / "cli.csv"
    run_cli("simulate", *args, "--rate", "200", "-o", path)
    expected = read_csv(path)
    table = parasils.simulate(rate_hz=200.0, **kwargs)
    assert list(table) == list(expected)
    for name in table:
        assert np.array_equal(bits(table[name]), bits(expected[name])), name


def test_the_issue_s_request_at_the_paper_s_rate(run_cli, tmp_path):
    # `--timing optimal --omega-max 10` and timing="optimal",
    # omega_max_deg_s=10: the same law, and a slower one than without the
    # limit (10 deg/s binds although it is the paper's value).
    path = tmp_path / "a.csv"
    run_cli("simulate", "--timing", "optimal", "--omega-max", "10", "-o", path)
    expected = read_csv(path)
    table = parasils.simulate(timing="optimal", omega_max_deg_s=10)
    for name in table:
        assert np.array_equal(bits(table[name]), bits(expected[name])), name
    free = parasils.simulate(timing="optimal")
    assert table["t_s"][-1] > free["t_s"][-1] + 0.1
    assert np.abs(table["psi_rate_deg_s"]).max() <= 10.0 * (1 + 1e-9)
    assert np.abs(table["theta_rate_deg_s"]).max() <= 10.0 * (1 + 1e-9)


def test_not_given_is_the_paper_s_value_for_the_trapezoid():
    plain = parasils.simulate(rate_hz=100.0)
    given = parasils.simulate(
        rate_hz=100.0,
        psi_deg=15.0,
        theta_deg=25.0,
        absolute=False,
        omega_max_deg_s=10.0,
        eps_max_deg_s2=5.0,
        sync="phase",
        timing="trapezoid",
        pose_mm_deg=parasils._PAPER["pose_mm_deg"],
        tip_left_mm=parasils._PAPER["tip_left_mm"],
    )
    for name in plain:
        assert np.array_equal(bits(plain[name]), bits(given[name])), name


#: Each field a procedure brings itself: its Python name, the CLI's flag, a value for each.
EXCLUDED = [
    ("psi_deg", 3.0, ["--psi", "3"]),
    ("theta_deg", 3.0, ["--theta", "3"]),
    ("absolute", True, ["--absolute"]),
    ("omega_max_deg_s", 10.0, ["--omega-max", "10"]),
    ("eps_max_deg_s2", 5.0, ["--eps-max", "5"]),
    ("sync", "phase", ["--sync", "phase"]),
    ("pose_mm_deg", [15.0, 20.0, -500.0, -15.0, 10.0, -60.0], ["--pose", "15,20,-500,-15,10,-60"]),
    ("tip_left_mm", [50.0, -50.0, -620.0], ["--tip-left", "50,-50,-620"]),
    ("tip_right_mm", [-50.0, -50.0, -620.0], ["--tip-right", "-50,-50,-620"]),
    ("robot", str(ROBOT_FILE), ["--robot", str(ROBOT_FILE)]),
    ("retarget", [(1.0, 5.0, 5.0)], ["--retarget", "1:5,5"]),
    ("stop_at_s", 1.0, ["--stop-at", "1"]),
    ("look_at", "tips", ["--look-at", "tips"]),
]


@pytest.mark.parametrize("name, value, args", EXCLUDED, ids=[e[0] for e in EXCLUDED])
def test_a_procedure_excludes_the_same_fields_in_both(cli, tmp_path, name, value, args):
    with pytest.raises(TypeError) as e:
        parasils.simulate(procedure=DEMO, **{name: value})
    assert str(e.value).startswith(f"{name} cannot be given with procedure=")
    proc = subprocess.run(
        [cli, "simulate", "--procedure", str(DEMO), *args, "-o", str(tmp_path / "x.csv")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode != 0
    assert f"{args[0]} cannot be given with --procedure" in proc.stderr, proc.stderr
    assert list(tmp_path.iterdir()) == []


def robot_with_supervisor(folder, table):
    path = folder / "robot.toml"
    path.write_text(ROBOT_FILE.read_text() + "\n[supervisor]\n" + table)
    return path


def test_a_robot_object_carries_its_file_s_supervisor_thresholds(tmp_path):
    # The turn takes the left |cos qs2| from 0.778 down to 0.472; a stop
    # threshold at 0.6 (warning 0.65) makes the online controller's
    # supervisor stop the platform on the way, a "supervisor_stop" command.
    path = robot_with_supervisor(tmp_path, "cos_qs2_warn = 0.65\ncos_qs2_stop = 0.6\n")
    robot = parasils.Robot.from_toml(path)
    assert robot.supervisor == {"cos_qs2_warn": 0.65, "cos_qs2_stop": 0.6}
    run = dict(rate_hz=200.0, retarget=[(0.5, 15.0, 25.0)])
    by_object = parasils.simulate(robot=robot, **run)
    by_path = parasils.simulate(robot=path, **run)
    for name in by_object:
        assert np.array_equal(bits(by_object[name]), bits(by_path[name])), name
    plain = parasils.simulate(robot=parasils.Robot(), **run)
    # Commands 0 (the turn) and 1 (the retarget), then the supervisor's stop.
    assert by_object["command"].max() == 2 and plain["command"].max() == 1
    # It stops once the margin heads below 0.6 (braking ends 0.004 past it
    # at 200 Hz), far from the 0.472 the turn reaches without the table.
    assert 0.59 < np.abs(by_object["left_cos_qs2"]).min() < 0.6
    assert np.abs(plain["left_cos_qs2"]).min() < 0.48
    # The thresholds survive a pickle (the robot file's text, [supervisor] included).
    import pickle

    again = pickle.loads(pickle.dumps(robot))
    assert again.supervisor == robot.supervisor
    assert "[supervisor]" in robot.to_toml() and "[supervisor]" not in parasils.Robot().to_toml()
