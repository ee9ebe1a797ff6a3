"""The time-optimal timing of the paper's reorientation side by side with toppra.

The same path (motion type 4: psi +15 deg, theta +25 deg from the paper's
start pose, both tips held), the same limits (the assumed actuator limits of
docs/model.md, *Time-optimal timing*), on grids of 100, 300, 1000 and 3000
points:

- parasils: ``Robot.optimal_reorientation`` (the solver, then its check 10
  times denser than the grid and the correction);
- toppra (PyPI), reachability analysis with its constant-acceleration
  parametrizer (``ParametrizeConstAccel``), fed the path through a custom
  path object whose values and derivatives are parasils' exact closed-form
  ones (``Robot.reorientation_path``, orders 0, 1, 2): no spline; both of
  toppra's discretisations of the acceleration constraint (collocation and
  interpolation).

Both results are then measured the same way, 10 times denser than their grid
in s: on each grid interval, s_dot^2 is linear in s and s_ddot constant (the
constant-acceleration schedule), and every actuator's velocity q' s_dot and
acceleration q' s_ddot + q'' s_dot^2 come from the exact derivatives there.
The script prints, per grid: both durations, both worst limit excesses
(relative: max(|value| / limit) - 1, negative when within), and both wall
times (parasils: the whole call from Python; toppra: building the problem and
computing the parametrization).

Usage (from the repository root, in a Python environment with the parasils
wheel, toppra and numpy installed):

    python benches/python/toppra_compare.py [--repeat 5]

Targets (issue: time-optimal motions): parasils' duration within 0.5 % of
toppra's best, its excess never above 1e-9, its 1000-point solve under 1 ms
(the Rust solver alone: ``cargo bench -p parasils --bench optimal``) and 100
times faster than toppra's.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import parasils
import toppra
import toppra.constraint as constraint

# The assumed actuator limits (docs/model.md): module 1's sliders 50 mm/s and
# 100 mm/s^2; qs1, qs2 30 deg/s and 60 deg/s^2; qs3 60 mm/s and 60 mm/s^2;
# in library units (mm, rad), in the order q1..q6, left qs1..qs3, right qs1..qs3.
_INSTRUMENT_V = [math.radians(30.0), math.radians(30.0), 60.0]
_INSTRUMENT_A = [math.radians(60.0), math.radians(60.0), 60.0]
V_MAX = np.array([50.0] * 6 + _INSTRUMENT_V * 2)
A_MAX = np.array([100.0] * 6 + _INSTRUMENT_A * 2)

POSE = np.array([15.0, 20.0, -500.0, *np.radians([-15.0, 10.0, -60.0])])
DPSI, DTHETA = math.radians(15.0), math.radians(25.0)
GRIDS = (100, 300, 1000, 3000)


class ExactPath(toppra.interpolator.AbstractGeometricPath):
    """The reorientation as a toppra path, evaluated by parasils in closed form."""

    def __init__(self, robot: parasils.Robot):
        self.robot = robot

    def __call__(self, path_positions, order=0):
        s = np.atleast_1d(np.asarray(path_positions, dtype=float))
        out = self.robot.reorientation_path(POSE, None, DPSI, DTHETA, s, order)
        return out if np.ndim(path_positions) else out[0]

    @property
    def dof(self):
        return 12

    @property
    def path_interval(self):
        return np.array([0.0, 1.0])


def worst_excess(robot: parasils.Robot, s: np.ndarray, x: np.ndarray, dense: int = 10) -> float:
    """max(|q' s_dot| / v_max, |q' u + q'' x| / a_max) - 1, `dense` points per interval."""
    x = np.maximum(x, 0.0)
    h = np.diff(s)
    u = np.diff(x) / (2.0 * h)
    frac = np.arange(dense + 1) / dense
    ss = (s[:-1, None] + h[:, None] * frac[None, :]).ravel()
    xs = (x[:-1, None] + 2.0 * u[:, None] * (h[:, None] * frac[None, :])).ravel()
    xs[frac.size - 1 :: frac.size] = x[1:]  # the interval's end exactly
    us = np.repeat(u, frac.size)
    d1 = robot.reorientation_path(POSE, None, DPSI, DTHETA, ss, 1)
    d2 = robot.reorientation_path(POSE, None, DPSI, DTHETA, ss, 2)
    vel = np.abs(d1 * np.sqrt(np.maximum(xs, 0.0))[:, None]) / V_MAX
    acc = np.abs(d1 * us[:, None] + d2 * xs[:, None]) / A_MAX
    return float(max(vel.max(), acc.max()) - 1.0)


def run_parasils(robot, n, repeat):
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = robot.optimal_reorientation(POSE, None, DPSI, DTHETA, knots=n, checks=10)
        best = min(best, time.perf_counter() - t0)
    return r["duration_s"], worst_excess(robot, r["s"], r["s_dot"] ** 2), best, r


def run_toppra(robot, n, scheme, repeat):
    path = ExactPath(robot)
    grid = np.linspace(0.0, 1.0, n)
    best, result = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        pc_vel = constraint.JointVelocityConstraint(np.column_stack([-V_MAX, V_MAX]))
        pc_acc = constraint.JointAccelerationConstraint(
            np.column_stack([-A_MAX, A_MAX]), discretization_scheme=scheme
        )
        algo = toppra.algorithm.TOPPRA(
            [pc_vel, pc_acc],
            path,
            gridpoints=grid,
            parametrizer="ParametrizeConstAccel",
            solver_wrapper="seidel",
        )
        traj = algo.compute_trajectory(0.0, 0.0)
        best = min(best, time.perf_counter() - t0)
        result = (algo, traj)
    algo, traj = result
    if traj is None:
        return math.nan, math.nan, best
    sd = algo.problem_data.sd_vec
    return float(traj.duration), worst_excess(robot, grid, sd**2), best


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="best wall time of this many runs")
    args = parser.parse_args()
    robot = parasils.Robot()
    schemes = {
        "collocation": constraint.DiscretizationType.Collocation,
        "interpolation": constraint.DiscretizationType.Interpolation,
    }
    print("grid  side                     duration_s   worst_excess   wall_ms")
    status = 0
    for n in GRIDS:
        t_ours, e_ours, w_ours, r = run_parasils(robot, n, args.repeat)
        print(f"{n:5d} parasils                 {t_ours:10.6f}  {e_ours:+12.3e}  {1e3 * w_ours:8.3f}")
        toppra_best = math.inf
        for name, scheme in schemes.items():
            t, e, w = run_toppra(robot, n, scheme, args.repeat)
            print(f"{n:5d} toppra {name:17s} {t:10.6f}  {e:+12.3e}  {1e3 * w:8.3f}")
            if np.isfinite(t):
                toppra_best = min(toppra_best, t)
        gap = t_ours / toppra_best - 1.0
        print(f"      parasils vs toppra's best: {100 * gap:+.4f} %")
        if e_ours > 1e-9 or gap > 0.005:
            status = 1
        if n == 1000:
            phases = ", ".join(f"{p['binding']} {p['limit']}" for p in r["phases"])
            print(f"      phases at 1000 points: {phases}")
    return status


if __name__ == "__main__":
    raise SystemExit(main())
