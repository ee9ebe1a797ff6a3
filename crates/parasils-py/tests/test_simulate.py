"""parasils.simulate against the CLI: the same library, the same bits."""

import os
import subprocess

import numpy as np
import pytest

import parasils
from conftest import ROOT

ROBOT_FILE = ROOT / "robots" / "default.toml"


def read_csv(path):
    """The CLI's CSV as a dict of arrays; float() reads ryu's shortest round-trip text back exactly."""
    with open(path) as f:
        header = f.readline().rstrip("\n").split(",")
        rows = [[float(v) for v in line.rstrip("\n").split(",")] for line in f]
    values = np.array(rows, dtype=np.float64).reshape(len(rows), len(header))
    return {name: values[:, k] for k, name in enumerate(header)}


def assert_bit_equal(table, expected):
    assert list(table) == list(expected) == list(parasils.COLUMNS)
    for name in parasils.COLUMNS:
        a, b = table[name], expected[name]
        assert a.dtype == np.float64 and a.shape == b.shape, name
        assert np.array_equal(a.view(np.uint64), b.view(np.uint64)), name


#: (keyword arguments of simulate, the CLI's arguments for the same run)
CASES = [
    ({}, []),
    (
        dict(psi_deg=-10.0, theta_deg=12.5, sync="time", rate_hz=250.0, omega_max_deg_s=7.5, eps_max_deg_s2=3.25),
        ["--psi", "-10.0", "--theta", "12.5", "--sync", "time", "--rate", "250.0", "--omega-max", "7.5", "--eps-max", "3.25"],
    ),
    (
        dict(psi_deg=15.0, theta_deg=25.0, absolute=True, sync="none", rate_hz=333.0),
        ["--psi", "15", "--theta", "25", "--absolute", "--sync", "none", "--rate", "333"],
    ),
    (
        dict(
            pose_mm_deg=[10.0, 25.0, -510.0, -12.0, 8.0, -55.0],
            tip_left_mm=(45.0, -52.5, -615.0),
            tip_right_mm=np.array([-12.0, 50.0, -630.0]),
            psi_deg=0.1 + 0.2,  # not a short decimal: passed as repr()
            rate_hz=100.0,
        ),
        ["--pose", "10,25,-510,-12,8,-55", "--tip-left", "45,-52.5,-615", "--tip-right", "-12,50,-630",
         "--psi", repr(0.1 + 0.2), "--rate", "100"],
    ),
    (dict(robot=str(ROBOT_FILE), rate_hz=200.0), ["--robot", ROBOT_FILE, "--rate", "200"]),
]


@pytest.mark.parametrize("kwargs, args", CASES, ids=["paper", "time-sync", "absolute", "pose-tips", "robot-file"])
def test_table_equals_the_cli_csv_to_the_last_bit(run_cli, tmp_path, kwargs, args):
    path = tmp_path / "cli.csv"
    run_cli("simulate", *args, "-o", path)
    assert_bit_equal(parasils.simulate(**kwargs), read_csv(path))


def test_paper_table(run_cli):
    table = parasils.simulate()
    assert len(table) == 74 and all(len(v) == 4501 for v in table.values())
    assert table["t_s"][0] == 0.0 and table["t_s"][-1] == 4.5
    assert tuple(table) == parasils.COLUMNS


def rotation(psi, theta, phi):
    """R = R_X(psi) R_Y(theta) R_Z(phi), written out."""
    (sx, cx), (sy, cy), (sz, cz) = [(np.sin(a), np.cos(a)) for a in (psi, theta, phi)]
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rx @ ry @ rz


def test_the_ports_are_p_plus_r_times_their_offsets():
    # The modules' RCMs at (-10, 0, 0) and (10, 0, 0) mm in the platform
    # frame (the paper's), the endoscope's port at P itself.
    table = parasils.simulate(rate_hz=100.0)
    assert parasils.COLUMNS[-9:] == tuple(
        f"{body}_port_{a}_mm" for body in ("left", "right", "endoscope") for a in "xyz"
    )
    offsets = {"left": [-10.0, 0.0, 0.0], "right": [10.0, 0.0, 0.0], "endoscope": [0.0, 0.0, 0.0]}
    for k in range(0, 451, 50):
        p = np.array([table[f"{a}_mm"][k] for a in "xyz"])
        r = rotation(*(np.radians(table[f"{a}_deg"][k]) for a in ("psi", "theta", "phi")))
        for body, offset in offsets.items():
            got = [table[f"{body}_port_{a}_mm"][k] for a in "xyz"]
            np.testing.assert_allclose(got, p + r @ offset, rtol=0, atol=1e-9)
    # The turn moves the instruments' ports, never the endoscope's.
    assert np.ptp(table["left_port_x_mm"]) > 0.5
    assert np.ptp(table["endoscope_port_z_mm"]) == 0.0


def test_robot_object_equals_robot_file(run_cli, tmp_path):
    robot = parasils.Robot.from_toml(ROBOT_FILE)
    a = parasils.simulate(robot=robot, rate_hz=100.0)
    b = parasils.simulate(robot=ROBOT_FILE, rate_hz=100.0)  # os.PathLike
    assert_bit_equal(a, b)
    assert_bit_equal(parasils.simulate(robot=parasils.Robot(), rate_hz=100.0), b)


@pytest.mark.parametrize("ext, fmt", [("csv", None), ("mcap", None), ("data", "csv"), ("bin", "mcap")])
def test_out_writes_the_same_file_as_the_cli(run_cli, tmp_path, ext, fmt):
    cli_path = tmp_path / f"cli.{ext}"
    py_path = tmp_path / f"py.{ext}"
    extra = ["--format", fmt] if fmt else []
    run_cli("simulate", "--rate", "200", "-o", cli_path, *extra)
    table = parasils.simulate(rate_hz=200.0, out=py_path, format=fmt)
    assert py_path.read_bytes() == cli_path.read_bytes()
    assert len(table["t_s"]) == 901
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([cli_path.name, py_path.name])
    if (fmt or ext) == "csv":
        assert_bit_equal(table, read_csv(py_path))


def test_the_first_row_is_on_the_start_s_own_degrees():
    table = parasils.simulate(rate_hz=10.0)
    assert (table["psi_deg"][0], table["theta_deg"][0]) == (-15.0, 10.0)
    assert (table["phi_deg"] == -60.0).all()
    table = parasils.simulate(pose_mm_deg=[15, 20, -500, -14.3, 10.56, -57.89], psi_deg=1, theta_deg=1, rate_hz=10.0)
    assert [table[c][0] for c in ("psi_deg", "theta_deg", "phi_deg")] == [-14.3, 10.56, -57.89]


def test_pose_is_a_deprecated_name_of_pose_mm_deg():
    start = [10.0, 25.0, -510.0, -12.0, 8.0, -55.0]
    with pytest.warns(DeprecationWarning, match="pose_mm_deg") as record:
        old = parasils.simulate(pose=start, rate_hz=10.0)
    assert record[0].filename == __file__  # the warning points at the caller
    assert_bit_equal(old, parasils.simulate(pose_mm_deg=start, rate_hz=10.0))
    with pytest.raises(TypeError, match="pose_mm_deg"):
        parasils.simulate(pose=start, pose_mm_deg=start)


def test_pandas_dataframe():
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(parasils.simulate(rate_hz=10.0))
    assert list(df.columns) == list(parasils.COLUMNS) and len(df) == 46


# --- commands: retargets and a stop --------------------------------------------

#: The paper's reorientation, a new goal at 1.2 s while turning, a stop at 3 s,
#: a last goal at 3.5 s while stopping: as keyword arguments and as CLI flags.
COMMANDS = dict(retarget=[(1.2, 25.0, 15.0), (3.5, 5.0, 30.0)], stop_at_s=3.0)
COMMAND_FLAGS = ["--retarget", "1.2:25,15", "--stop-at", "3", "--retarget", "3.5:5,30"]


def test_commands_equal_the_cli_csv_to_the_last_bit(run_cli, tmp_path):
    path = tmp_path / "cli.csv"
    run_cli("simulate", *COMMAND_FLAGS, "--rate", "200", "-o", path)
    table = parasils.simulate(rate_hz=200.0, **COMMANDS)
    expected = read_csv(path)
    assert list(table) == list(expected) == [*parasils.COLUMNS, "command"]
    for name in parasils.COLUMNS:
        assert table[name].dtype == np.float64, name
        assert np.array_equal(table[name].view(np.uint64), expected[name].view(np.uint64)), name
    command = table["command"]
    assert command.dtype == np.int64
    assert np.array_equal(command, expected["command"].astype(np.int64))
    t = table["t_s"]
    assert np.array_equal(command, (t >= 1.2).astype(int) + (t >= 3.0) + (t >= 3.5))
    assert command[0] == 0 and command[-1] == 3


def test_commands_keep_the_motion_continuous_and_the_tips_still():
    table = parasils.simulate(**COMMANDS)
    changes = np.flatnonzero(np.diff(table["command"])) + 1
    assert list(changes) == [1200, 3000, 3500]
    for axis in ("psi", "theta"):
        angle, rate, acc = (table[f"{axis}{s}"] for s in ("_deg", "_rate_deg_s", "_acc_deg_s2"))
        assert np.all(np.abs(acc) <= 5.0 * (1 + 1e-9))
        assert np.all(np.abs(np.diff(angle)[changes - 1]) <= 10.0 * 1e-3 * (1 + 1e-9))
        assert np.all(np.abs(np.diff(rate)[changes - 1]) <= 5.0 * 1e-3 * (1 + 1e-9))
    assert max(table["left_tip_err_mm"].max(), table["right_tip_err_mm"].max()) < 1e-9
    # At rest on the last goal, read like psi_deg and theta_deg: -15 + 5, 10 + 30.
    assert table["psi_deg"][-1] == pytest.approx(-10.0, abs=1e-9)
    assert table["theta_deg"][-1] == pytest.approx(40.0, abs=1e-9)


@pytest.mark.parametrize("ext", ["csv", "mcap"])
def test_commands_out_writes_the_same_file_as_the_cli(run_cli, tmp_path, ext):
    cli_path, py_path = tmp_path / f"cli.{ext}", tmp_path / f"py.{ext}"
    run_cli("simulate", *COMMAND_FLAGS, "--rate", "100", "-o", cli_path)
    parasils.simulate(rate_hz=100.0, out=py_path, **COMMANDS)
    assert py_path.read_bytes() == cli_path.read_bytes()


def test_a_stop_alone_and_absolute_retargets():
    table = parasils.simulate(stop_at_s=2.0, rate_hz=100.0)
    assert table["command"][-1] == 1 and table["t_s"][-1] == pytest.approx(4.0, abs=1e-12)
    table = parasils.simulate(
        absolute=True, psi_deg=0.0, theta_deg=30.0, retarget=np.array([[1.0, -10.0, 20.0]]), rate_hz=100.0
    )
    assert (table["psi_deg"][-1], table["theta_deg"][-1]) == pytest.approx((-10.0, 20.0), abs=1e-9)
    # Without commands, no command column.
    assert "command" not in parasils.simulate(rate_hz=10.0, retarget=[])


def test_bad_commands(cli, tmp_path):
    out = tmp_path / "run.csv"
    with pytest.raises(ValueError, match="give the retargets in time order") as e:
        parasils.simulate(retarget=[(2.0, 5, 6), (1.0, 5, 6)], out=out)
    assert str(e.value) == cli_error(cli, "--retarget", "2:5,6", "--retarget", "1:5,6")
    with pytest.raises(ValueError, match=r"the stop: t = -1 s is before the start"):
        parasils.simulate(stop_at_s=-1.0)
    with pytest.raises(ValueError, match="the stop: t = NaN is not a finite number"):
        parasils.simulate(stop_at_s=float("nan"))
    with pytest.raises(ValueError, match="retarget 1: theta = inf is not a finite number"):
        parasils.simulate(retarget=[(1.0, 0.0, float("inf"))])
    with pytest.raises(ValueError, match="the same sample"):
        parasils.simulate(retarget=[(1.0, 0.0, 0.0)], stop_at_s=1.0)
    with pytest.raises(ValueError, match=r"\(t_s, psi_deg, theta_deg\) triples.*item 0 is 1.2"):
        parasils.simulate(retarget=(1.2, 5.0, 10.0))  # one triple, not a list of them
    with pytest.raises(ValueError, match="item 1 is"):
        parasils.simulate(retarget=[(1.2, 5.0, 10.0), (2.0, 1.0)])
    with pytest.raises(TypeError, match="retarget must be"):
        parasils.simulate(retarget="1.2:5,10")
    with pytest.raises(TypeError, match="retarget must be"):
        parasils.simulate(retarget=3)
    with pytest.raises(TypeError):
        parasils.simulate(stop_at_s="soon")
    assert list(tmp_path.iterdir()) == []


# --- errors -------------------------------------------------------------------


def cli_error(cli, *args):
    proc = subprocess.run([cli, "simulate", *map(str, args)], capture_output=True, text=True, check=False)
    assert proc.returncode != 0
    return proc.stderr.strip().removeprefix("parasils: error: ")


def fast_robot(cli, folder):
    """The default robot file with every actuator rate limit raised out of
    the way (1e9), so that joint limits and singularities are met first."""
    text = subprocess.run([cli, "robot"], capture_output=True, text=True, check=True).stdout
    lines = [
        line.split(" = ")[0] + " = 1e9"
        if ("velocity_max" in line or "acceleration_max" in line) and " = " in line
        else line
        for line in text.splitlines()
    ]
    path = folder / "fast.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_an_actuator_too_fast_during_the_motion(cli):
    # Within the assumed rate limits, the left module's qs1 is too fast first.
    with pytest.raises(ValueError) as e:
        parasils.simulate(psi_deg=60.0, theta_deg=60.0)
    assert str(e.value) == cli_error(cli, "--psi", 60, "--theta", 60)
    assert "is beyond its limit" in str(e.value)


def test_joint_limit_during_the_motion(cli, tmp_path):
    robot = fast_robot(cli, tmp_path)
    out = tmp_path / "run.csv"
    with pytest.raises(parasils.JointLimitError) as e:
        parasils.simulate(psi_deg=60.0, theta_deg=60.0, out=out, robot=robot)
    err = e.value
    assert (err.side, err.joint) == ("left", "qs2")
    assert err.row == 4075 and err.t == pytest.approx(4.075, abs=1e-12)
    assert str(err) == cli_error(cli, "--psi", 60, "--theta", 60, "--robot", robot)
    assert str(err).startswith("at t = 4.075 s: left instrument: joint qs2")
    # A failed run leaves nothing behind, like the CLI.
    assert list(tmp_path.iterdir()) == [robot]


def test_parallel_singularity_during_the_motion(cli, tmp_path):
    robot = fast_robot(cli, tmp_path)
    with pytest.raises(parasils.ParallelSingularError) as e:
        parasils.simulate(psi_deg=-60.0, theta_deg=40.0, robot=robot)
    assert e.value.t > 0 and e.value.row == round(e.value.t * 1000)
    assert str(e.value) == cli_error(cli, "--psi", -60, "--theta", 40, "--robot", robot)


def test_unreachable_tip():
    with pytest.raises(parasils.KinematicsError) as e:
        parasils.simulate(tip_left_mm=[5000.0, 0.0, -620.0])
    assert e.value.row == 0 and e.value.t == 0.0
    assert e.value.kind in ("out_of_reach", "joint_limit")


def test_non_finite_tip():
    with pytest.raises(parasils.NonFiniteError) as e:
        parasils.simulate(tip_right_mm=[np.nan, 0.0, 0.0])
    assert e.value.what == "right tip" and e.value.t == 0.0 and e.value.row is None


def test_non_finite_pose():
    with pytest.raises(parasils.NonFiniteError) as e:
        parasils.simulate(pose_mm_deg=[np.nan, 20, -500, -15, 10, -60], tip_right_mm=[-10, 54, -637])
    assert e.value.what == "pose.x" and e.value.row == 0


@pytest.mark.parametrize(
    "kwargs, kind, axis",
    [
        (dict(omega_max_deg_s=0.0), "invalid_limit", 0),
        (dict(eps_max_deg_s2=-5.0), "invalid_limit", 0),
        (dict(rate_hz=0.0), "invalid_rate", None),
        (dict(rate_hz=float("nan")), "invalid_rate", None),
        (dict(theta_deg=float("inf")), "non_finite_position", 1),
    ],
)
def test_trajectory_errors(kwargs, kind, axis):
    with pytest.raises(parasils.TrajectoryError) as e:
        parasils.simulate(**kwargs)
    assert (e.value.kind, e.value.axis) == (kind, axis)
    assert str(e.value).startswith("trajectory: ")


def test_trajectory_error_message_is_the_cli_s(cli):
    with pytest.raises(parasils.TrajectoryError) as e:
        parasils.simulate(omega_max_deg_s=0.0)
    assert str(e.value) == cli_error(cli, "--omega-max", 0)


def test_invalid_robot_in_simulate(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("not toml at all [")
    with pytest.raises(parasils.RobotFileError):
        parasils.simulate(robot=path)
    with pytest.raises(FileNotFoundError):
        parasils.simulate(robot=tmp_path / "missing.toml")
    with pytest.raises(TypeError, match="robot must be"):
        parasils.simulate(robot=42)


def test_bad_arguments(tmp_path):
    with pytest.raises(ValueError, match="sync must be 'phase', 'time' or 'none'"):
        parasils.simulate(sync="fast")
    with pytest.raises(ValueError, match="format must be 'csv' or 'mcap'"):
        parasils.simulate(format="json")
    with pytest.raises(ValueError, match="cannot tell the output format"):
        parasils.simulate(out=tmp_path / "run.txt")
    with pytest.raises(ValueError, match=r"pose_mm_deg must have shape \(6,\)"):
        parasils.simulate(pose_mm_deg=[1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"tip_left_mm must have shape \(3,\)"):
        parasils.simulate(tip_left_mm=np.zeros((2, 3)))
    with pytest.raises(TypeError):
        parasils.simulate(15.0)  # keyword arguments only
    assert list(tmp_path.iterdir()) == []


def test_unwritable_output(tmp_path):
    target = tmp_path / "missing" / "run.csv"
    with pytest.raises(FileNotFoundError) as e:
        parasils.simulate(rate_hz=10.0, out=target)
    assert e.value.filename == str(target)
    assert str(tmp_path / "missing") in str(e.value)
    if os.geteuid() != 0:  # root writes anywhere
        ro = tmp_path / "ro"
        ro.mkdir(mode=0o500)
        with pytest.raises(PermissionError):
            parasils.simulate(rate_hz=10.0, out=ro / "run.csv")


def test_commands_are_refused_under_the_optimal_timing_naming_the_argument():
    for kwargs, name in [
        (dict(stop_at_s=1.0), "stop_at_s"),
        (dict(retarget=[(1.0, 5.0, 5.0)]), "retarget"),
    ]:
        with pytest.raises(ValueError) as e:
            parasils.simulate(timing="optimal", **kwargs)
        assert str(e.value) == (
            f"{name} cannot be given with timing='optimal': it plans one motion"
            " from rest to rest, while commands are taken online"
        )
    # No retarget at all is no command: the planned turn, timed optimally.
    run = parasils.simulate(timing="optimal", retarget=[])
    assert run["t_s"][-1] == pytest.approx(2.225, abs=1e-12)
