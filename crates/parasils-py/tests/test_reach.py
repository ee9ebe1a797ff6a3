"""Robot.reach_map: the simulation library's reach map as NumPy arrays."""

import inspect
import math
import warnings

import numpy as np
import pytest

import parasils
from conftest import P0


def test_the_paper_map_has_its_grid_flags_codes_and_boundary():
    robot = parasils.Robot()
    m = robot.reach_map(P0, step_deg=5.0)
    assert m["dpsi"].shape == (19,) and m["dtheta"].shape == (19,)
    np.testing.assert_allclose(m["dpsi"], np.radians(np.arange(-45.0, 46.0, 5.0)), atol=1e-12)
    for key in ("feasible", "reachable", "line"):
        assert m[key].shape == (19, 19) and m[key].dtype == bool
    assert m["margin"].shape == (19, 19)
    codes = m["codes"]
    assert codes[0] == "ok"
    # Rows are dtheta, columns dpsi: the start at the middle, the paper's
    # target (15, 25) deg straight ahead.
    assert m["line"][9, 9] and m["line"][9 + 5, 9 + 3]
    feasible = m["feasible"]
    assert np.array_equal(feasible, m["limiting"] == 0)
    assert np.all(m["margin"][feasible] >= 0) and np.all(m["margin"][~feasible] < 0)
    assert np.all(m["reachable"] <= feasible) and np.all(m["line"] <= feasible)
    assert "module1.parallel_singular" in {codes[i] for i in m["limiting"][~feasible]}
    points = m["boundary_points"]
    assert points.shape[1] == 2 and len(points) == len(m["boundary_limiting"]) > 0
    assert all(codes[i] != "ok" for i in m["boundary_limiting"])
    assert sum(len(line) for line in m["boundary"]) >= len(points)
    assert m["module1_assumed"]


def test_the_tips_and_the_grid_are_checked():
    robot = parasils.Robot()
    with pytest.raises(ValueError, match="tips must have shape"):
        robot.reach_map(P0, tips=np.zeros(3))
    with pytest.raises(ValueError, match="contain 0"):
        robot.reach_map(P0, psi_range_deg=(5.0, 10.0))
    m = robot.reach_map(P0, step_deg=15.0, line=False)
    assert m["line"] is None


def test_the_grid_is_in_the_command_line_s_degrees():
    sig = inspect.signature(parasils.Robot.reach_map)
    for name in ("psi_range_deg", "theta_range_deg", "step_deg", "line"):
        assert sig.parameters[name].kind is inspect.Parameter.KEYWORD_ONLY, name
    assert sig.parameters["step_deg"].default == 0.5
    robot = parasils.Robot()
    # The default ranges: -45 to 45 deg, as `parasils reach`'s.
    m = robot.reach_map(P0, step_deg=15.0, line=False)
    np.testing.assert_allclose(m["dpsi"], np.radians(np.arange(-45.0, 46.0, 15.0)), atol=1e-12)
    np.testing.assert_allclose(m["dtheta"], np.radians(np.arange(-45.0, 46.0, 15.0)), atol=1e-12)
    m = robot.reach_map(P0, psi_range_deg=(-10.0, 20.0), theta_range_deg=(-5.0, 30.0), step_deg=5.0)
    # (20 - -10) / 5 + 1 columns, (30 - -5) / 5 + 1 rows, in rad.
    assert m["dpsi"].shape == (7,) and m["dtheta"].shape == (8,)
    np.testing.assert_allclose(m["dpsi"], np.radians(np.arange(-10.0, 21.0, 5.0)), atol=1e-12)
    np.testing.assert_allclose(m["dtheta"], np.radians(np.arange(-5.0, 31.0, 5.0)), atol=1e-12)


def rad(deg):
    """deg in rad, the neighbour that the library's `to_degrees` (x * (180 /
    pi)) turns back into deg exactly, when there is one."""
    r = math.radians(deg)
    for x in (r, np.nextafter(r, np.inf), np.nextafter(r, -np.inf)):
        if x * (180.0 / math.pi) == deg:
            return float(x)
    return r


def test_the_old_names_in_rad_warn_and_give_the_same_map():
    robot = parasils.Robot()
    new = robot.reach_map(P0, psi_range_deg=(-10.0, 20.0), theta_range_deg=(-5.0, 30.0), step_deg=5.0)
    psi, theta, step = (rad(-10.0), rad(20.0)), (rad(-5.0), rad(30.0)), rad(5.0)
    for old_name, kwargs in [
        ("psi_range", dict(psi_range=psi, theta_range_deg=(-5.0, 30.0), step_deg=5.0)),
        ("theta_range", dict(psi_range_deg=(-10.0, 20.0), theta_range=theta, step_deg=5.0)),
        ("step", dict(psi_range_deg=(-10.0, 20.0), theta_range_deg=(-5.0, 30.0), step=step)),
    ]:
        with pytest.warns(DeprecationWarning, match=f"reach_map\\({old_name}=...\\) is deprecated: use {old_name}_deg"):
            old = robot.reach_map(P0, **kwargs)
        for key in ("feasible", "reachable", "line", "limiting", "boundary_limiting"):
            np.testing.assert_array_equal(old[key], new[key], err_msg=f"{old_name}: {key}")
        for key in ("dpsi", "dtheta", "margin", "boundary_points"):
            np.testing.assert_allclose(old[key], new[key], rtol=0, atol=1e-12, err_msg=f"{old_name}: {key}")
    # Positionally, as before the rename: rad, with the warning.
    with pytest.warns(DeprecationWarning):
        old = robot.reach_map(P0, None, psi, theta, step)
    np.testing.assert_array_equal(old["limiting"], new["limiting"])
    np.testing.assert_allclose(old["margin"], new["margin"], rtol=0, atol=1e-12)
    with pytest.raises(TypeError, match="both step_deg and its deprecated name step"):
        robot.reach_map(P0, step=0.1, step_deg=5.0)
    # The new names alone: no warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        robot.reach_map(P0, step_deg=15.0, line=False)


def test_a_forbidden_region_limits_the_cells_it_reaches_with_its_name(tmp_path):
    # A ball whose surface is 2 mm from the paper's left tip, which the map
    # holds still: every cell the kinematics allow is limited by it
    # (the distance itself is checked cell by cell in the reach crate's
    # tests); a ball far from everything changes nothing.
    ball = tmp_path / "ball.toml"
    ball.write_text(
        '[[region]]\nname = "ball"\nshape = "sphere"\ncentre_mm = [50, -50, -630]\nradius_mm = 8\n'
    )
    far = tmp_path / "far.toml"
    far.write_text(
        '[[region]]\nname = "far"\nshape = "sphere"\ncentre_mm = [0, 0, 500]\nradius_mm = 1\n'
    )
    robot = parasils.Robot()
    grid = dict(psi_range_deg=(-10.0, 20.0), theta_range_deg=(-10.0, 30.0), step_deg=5.0, line=False)
    free = robot.reach_map(P0, **grid)
    m = robot.reach_map(P0, anatomy=ball, **grid)
    assert m["codes"][-1] == "no_go.ball" and m["codes"][:-1] == free["codes"]
    names = np.array(m["codes"])[m["limiting"]]
    assert np.all(names[free["feasible"]] == "no_go.ball")
    assert np.array_equal(m["limiting"][~free["feasible"]], free["limiting"][~free["feasible"]])
    assert not m["feasible"].any() and free["feasible"].sum() > 10
    # Normalised by the shaft's radius: (gap - 0.5 mm) / 2.5 mm, the gap
    # -0.5 mm at the start (the surface 2 mm from the tip, the shaft 2.5).
    assert m["margin"][2, 2] == pytest.approx((-0.5 - 0.5) / 2.5, abs=1e-9)
    unchanged = robot.reach_map(P0, anatomy=str(far), **grid)
    assert unchanged["codes"][-1] == "no_go.far"
    for key in ("feasible", "limiting", "margin"):
        assert np.array_equal(unchanged[key], free[key]), key
    with pytest.raises(OSError):
        robot.reach_map(P0, anatomy=tmp_path / "missing.toml", **grid)
