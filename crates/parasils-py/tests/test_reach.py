"""Robot.reach_map: the simulation library's reach map as NumPy arrays."""

import numpy as np
import pytest

import parasils
from conftest import P0


def test_the_paper_map_has_its_grid_flags_codes_and_boundary():
    robot = parasils.Robot()
    step = np.radians(5.0)
    m = robot.reach_map(P0, step=step)
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
        robot.reach_map(P0, psi_range=(0.1, 0.2))
    m = robot.reach_map(P0, step=np.radians(15.0), line=False)
    assert m["line"] is None
