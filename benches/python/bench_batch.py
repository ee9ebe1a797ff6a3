"""The Python bindings' batch API against NumPy: `parasils.Robot().instrument_ik`
on (N, 6) poses and (N, 3) tips, and the same closed-form equations written
here in vectorised NumPy (see `docs/model.md`, *Instrument modules*), for
N = 10^3 to 10^6 rows.

    python -m venv /tmp/venv && /tmp/venv/bin/pip install numpy ./crates/parasils-py
    /tmp/venv/bin/python benches/python/bench_batch.py [--max-rows 1000000] [--repeat 7] [--threads T]

For each N it prints the median time of each (of at least `--repeat` runs,
more for the small batches, after one warm-up run; the two alternate, so that
a change of the machine's load hits both alike), the ratio NumPy / parasils,
and the largest difference of the joints between the two (rad and mm): they
solve the same equations, so they agree to rounding. Results are logged in
BENCHMARKS.md.

parasils splits a batch of 4096 rows or more across `parasils.batch_threads()`
threads (`--threads` sets PARASILS_NUM_THREADS; default: every CPU this
process may use); NumPy runs on one thread (its element-wise functions do
not use threads). The load average before and after is printed: on a busy
machine the threads have fewer cores to run on.

The rows are the paper's reorientation (see `docs/model.md`, *Check
values*): poses along the motion from P0 (psi and theta spread over their
ranges, position and phi fixed) with the left tip held at (50, -50, -620)
mm, shuffled; every row is reachable and within the joint limits, so
`errors="raise"` never raises and the NumPy code needs no masking beyond
what the binding does (it computes the same reach, singularity and limit
tests and returns NaN rows for them, as `errors="nan"` would).
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import numpy as np

import parasils

DEG = np.pi / 180.0
ALPHA = BETA = 10.0 * DEG  # the paper's spherical modules
RCM_LEFT = np.array([-10.0, 0.0, 0.0])  # mm, platform frame
# The assumed default joint limits (see `docs/model.md`, *Singularities and
# thresholds*): qs1, qs2 rad, qs3 mm.
LIMITS = (
    (-120.0 * DEG, 120.0 * DEG),
    (-80.0 * DEG, 80.0 * DEG),
    (10.0, 300.0),
)


def numpy_instrument_ik(pose: np.ndarray, tip: np.ndarray) -> np.ndarray:
    """The left module's closed-form IK in mode A, vectorised.

    See `docs/model.md`, *Instrument modules* (inverse kinematics).

    pose: (N, 6) x, y, z mm, psi, theta, phi rad; tip: (N, 3) mm, fixed frame.
    Returns (N, 3) qs1, qs2 rad, qs3 mm; NaN rows where the tip is out of
    reach, singular or beyond a joint limit.
    """
    s1, c1 = np.sin(pose[:, 3]), np.cos(pose[:, 3])
    s2, c2 = np.sin(pose[:, 4]), np.cos(pose[:, 4])
    s3, c3 = np.sin(pose[:, 5]), np.cos(pose[:, 5])
    # d = tip - P; p = R^T d with R = R_X(psi) R_Y(theta) R_Z(phi), by columns of R.
    d = tip - pose[:, :3]
    dx, dy, dz = d[:, 0], d[:, 1], d[:, 2]
    r10 = c1 * s3 + s1 * s2 * c3
    r11 = c1 * c3 - s1 * s2 * s3
    r20 = s1 * s3 - c1 * s2 * c3
    r21 = s1 * c3 + c1 * s2 * s3
    px = c2 * c3 * dx + r10 * dy + r20 * dz - RCM_LEFT[0]
    py = -c2 * s3 * dx + r11 * dy + r21 * dz - RCM_LEFT[1]
    pz = s2 * dx - s1 * c2 * dy + c1 * c2 * dz - RCM_LEFT[2]
    qs3 = np.sqrt(px * px + py * py + pz * pz)
    # u = -p / qs3, v = R_Y(-alpha) u
    ux, uy, uz = -px / qs3, -py / qs3, -pz / qs3
    sa, ca = np.sin(ALPHA), np.cos(ALPHA)
    sb, cb = np.sin(BETA), np.cos(BETA)
    vx = ca * ux - sa * uz
    vy = uy
    vz = sa * ux + ca * uz
    sin_qs2 = vx / cb
    reach = np.abs(sin_qs2) <= 1.0 + 1e-12
    s = np.clip(sin_qs2, -1.0, 1.0)
    cos_qs2 = np.sqrt((1.0 - s) * (1.0 + s))  # mode A
    qs2 = np.arcsin(s)
    qs1 = np.arctan2(-sb * vz - cb * cos_qs2 * vy, cb * cos_qs2 * vz - sb * vy)
    ok = reach & (np.abs(cos_qs2) >= 1e-6) & (qs3 >= 1e-6)
    for q, (lo, hi) in zip((qs1, qs2, qs3), LIMITS):
        ok &= (q >= lo) & (q <= hi)
    out = np.stack([qs1, qs2, qs3], axis=1)
    out[~ok] = np.nan
    return out


def rows(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """n poses of the paper's reorientation and the left tip, shuffled."""
    f = rng.random(n)
    pose = np.empty((n, 6))
    pose[:, 0], pose[:, 1], pose[:, 2] = 15.0, 20.0, -500.0
    pose[:, 3] = (-15.0 + 15.0 * f) * DEG  # psi: -15 -> 0 deg
    pose[:, 4] = (10.0 + 25.0 * f) * DEG  # theta: 10 -> 35 deg, the same line
    pose[:, 5] = -60.0 * DEG
    tip = np.broadcast_to(np.array([50.0, -50.0, -620.0]), (n, 3)).copy()
    return pose, tip


def medians(repeat: int, *fs) -> list[float]:
    """The median time of each function over at least `repeat` runs (more
    for fast ones: about 0.3 s of runs, at most 200), the runs of the
    functions alternating, after one warm-up run of each."""
    warm = []
    for f in fs:
        t = time.perf_counter()
        f()  # warm-up: page faults, caches, lazy imports
        warm.append(time.perf_counter() - t)
    runs = max(repeat, min(200, int(0.3 / max(sum(warm), 1e-9))))
    times = [[] for _ in fs]
    for _ in range(runs):
        for f, ts in zip(fs, times):
            t = time.perf_counter()
            f()
            ts.append(time.perf_counter() - t)
    return [statistics.median(ts) for ts in times]


def load() -> str:
    return "load average " + ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--max-rows", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument(
        "--threads", type=int, default=None, help="parasils' threads (PARASILS_NUM_THREADS)"
    )
    args = ap.parse_args()
    if args.threads is not None:
        os.environ["PARASILS_NUM_THREADS"] = str(args.threads)

    robot = parasils.Robot()
    rng = np.random.default_rng(2024)
    print(
        f"parasils {parasils.__version__}, numpy {np.__version__}, "
        f"Python {platform.python_version()}, {platform.machine()}"
    )
    # batch_threads() is missing from parasils before the threaded batches.
    threads = getattr(parasils, "batch_threads", lambda: 1)()
    print(
        f"parasils threads: {threads} (from 4096 rows), CPUs: {os.cpu_count()}, "
        f"{load()}"
    )
    print(f"{'rows':>9} {'parasils':>12} {'numpy':>12} {'numpy/parasils':>15} {'max |diff|':>11}")
    n = 1000
    while n <= args.max_rows:
        pose, tip = rows(n, rng)
        ours = robot.instrument_ik("left", pose, tip)
        theirs = numpy_instrument_ik(pose, tip)
        if np.isnan(theirs).any() or np.isnan(ours).any():
            raise SystemExit("a row failed: the rows are meant to be all regular")
        diff = float(np.max(np.abs(ours - theirs)))
        t_ours, t_numpy = medians(
            args.repeat,
            lambda: robot.instrument_ik("left", pose, tip),
            lambda: numpy_instrument_ik(pose, tip),
        )
        print(
            f"{n:>9} {t_ours * 1e3:>9.3f} ms {t_numpy * 1e3:>9.3f} ms "
            f"{t_numpy / t_ours:>14.2f}x {diff:>11.1e}"
        )
        n *= 10
    per_row = t_ours / (n // 10) * 1e9
    print(f"parasils at the largest batch: {per_row:.0f} ns per row; {load()}")


if __name__ == "__main__":
    main()
