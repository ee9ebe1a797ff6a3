"""Reach maps from Python: `Robot.reach_map` against the obvious alternative,
the same grid of orientations through the batch API in NumPy-style code.

    python -m venv /tmp/venv && /tmp/venv/bin/pip install numpy ./crates/parasils-py
    /tmp/venv/bin/python benches/python/reach_numpy.py [--step-deg 0.5] [--repeat 5]

The grid is the default map's: dpsi and dtheta from -45 to 45 deg around
the paper's start pose P0, with the paper's tips. The alternative builds
the (N, 6) array of poses and calls `module1_ik` and `instrument_ik` (both
sides, mode A) with errors="nan", a cell being feasible where every call
succeeded. It checks module 1's reach, serial margins and strokes and each
instrument's reach, singularities and joint limits, but not module 1's
parallel margin (the batch API does not expose it) and gives neither the
limiting constraint nor the margin: it does less than the map, so the
comparison flatters it. `reach_map` is run without the straight lines
(line=False), the part the alternative has no counterpart for, and with
them. The script prints the median times and the cells per second, and
how many cells the two call feasible (they differ only by the cells
beyond the parallel threshold).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import parasils

P0 = np.array([15.0, 20.0, -500.0, *np.radians([-15.0, 10.0, -60.0])])


def numpy_style(robot: parasils.Robot, step: float) -> np.ndarray:
    """The feasible cells through the batch API, as a (R, C) bool array."""
    k = np.arange(-round(45.0 / step), round(45.0 / step) + 1)
    d = np.radians(k * step)
    dpsi, dtheta = np.meshgrid(d, d)
    poses = np.tile(P0, (dpsi.size, 1))
    poses[:, 3] += dpsi.ravel()
    poses[:, 4] += dtheta.ravel()
    left = np.array([50.0, -50.0, -620.0])
    right = mirror(left)
    _, ok1 = robot.module1_ik(poses, errors="nan")
    _, okl = robot.instrument_ik("left", poses, left, errors="nan")
    _, okr = robot.instrument_ik("right", poses, right, errors="nan")
    return (ok1 & okl & okr).reshape(dpsi.shape)


def mirror(p: np.ndarray) -> np.ndarray:
    """The mirror image of `p` across the platform's Y'Z' plane at P0."""
    psi, theta, phi = P0[3:]
    cx, sx, cy, sy, cz, sz = np.cos(psi), np.sin(psi), np.cos(theta), np.sin(theta), np.cos(phi), np.sin(phi)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    r = rx @ ry @ rz
    c = r.T @ (p - P0[:3])
    c[0] = -c[0]
    return r @ c + P0[:3]


def median_time(f, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--step-deg", type=float, default=0.5)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    robot = parasils.Robot()
    step = args.step_deg
    m = robot.reach_map(P0, step_deg=step, line=False)
    cells = m["feasible"].size
    ours = m["feasible"]
    base = numpy_style(robot, step)
    print(f"grid {m['dtheta'].size} x {m['dpsi'].size} = {cells} cells, step {step} deg")
    print(f"feasible: reach_map {int(ours.sum())}, batch API {int(base.sum())} (no parallel margin)")
    rows = [
        ("reach_map(line=False)", lambda: robot.reach_map(P0, step_deg=step, line=False)),
        ("batch API, NumPy-style", lambda: numpy_style(robot, step)),
        ("reach_map(line=True)", lambda: robot.reach_map(P0, step_deg=step)),
    ]
    for name, f in rows:
        t = median_time(f, args.repeat)
        print(f"{name:<24} {t * 1e3:9.1f} ms  {cells / t / 1e6:7.3f} M cells/s")


if __name__ == "__main__":
    main()
