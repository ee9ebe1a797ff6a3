"""A tolerance study in one process and on a Dask LocalCluster: the same
study (the paper's reorientation sampled at 100 Hz, the default tolerances,
seed 0) run

  (a) in this process, on one thread (`ToleranceStudy.run(..., threads=1)`);
  (b) with `parasils.tolerance(..., client=...)` on a LocalCluster of one
      worker process with one thread;
  (c) the same on two worker processes with one thread each;

then, optionally, (d) 10^5 robots in this process on two threads.

    python -m venv /tmp/venv
    /tmp/venv/bin/pip install numpy "dask[distributed]" ./crates/parasils-py
    /tmp/venv/bin/python benches/python/tolerance_dask.py [--seconds 36] [--n N] [--repeat R] [--big 100000]

The number of robots is chosen from a short timed run so that (b) lasts
about `--seconds` (at least 30 s is what the two-worker speed-up is quoted
for), or given with `--n`. The cluster's start and a warm-up call (the
workers import parasils and receive the study) are left out of the times:
what is timed is `parasils.tolerance` from the call to the gathered columns.
It prints each wall time (the best of `--repeat` rounds of (a), (b), (c)
in turn), the cost per robot, the speed-up (b) / (c) and checks that (a),
(b) and (c) are the same rows, bit for bit; the load average before, after
each round and at the end (other work on the machine takes cores from the
workers). `--big 0` skips (d).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

import numpy as np

import parasils

COLUMNS = (
    "sample",
    "left_tip_dev_mm",
    "right_tip_dev_mm",
    "pose_position_err_mm",
    "pose_rotation_err_deg",
    "failed",
)


def same_bits(a, b):
    """Whether two results are the same rows, bit for bit."""
    for name in COLUMNS:
        x, y = np.asarray(a[name]), np.asarray(b[name])
        if x.dtype != y.dtype or x.shape != y.shape:
            return False
        if x.dtype == np.float64:
            x, y = x.view(np.uint64), y.view(np.uint64)
        if not np.array_equal(x, y):
            return False
    return a["failures"] == b["failures"]


def head(result, k):
    """The first `k` rows of a result."""
    out = {name: result[name][:k] for name in COLUMNS}
    out["failures"] = [f for f in result["failures"] if f[0] < k]
    return out


def on_cluster(workers, n, args):
    """parasils.tolerance on a LocalCluster of `workers` one-thread worker
    processes: (wall time, result)."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=workers,
        processes=True,
        threads_per_worker=1,
        dashboard_address=None,
        silence_logs=40,
    ) as cluster, Client(cluster) as client:
        # Warm-up: every worker imports parasils and builds the study.
        parasils.tolerance(None, 8 * workers, rate_hz=args.rate, client=client, chunks=1)
        t = time.perf_counter()
        result = parasils.tolerance(None, n, seed=args.seed, rate_hz=args.rate, client=client)
        return time.perf_counter() - t, result


def line(name, seconds, n):
    print(f"  {name:<44} {seconds:9.2f} s   {1e3 * seconds / n:7.3f} ms per robot")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=36.0, help="target wall time of (b), s")
    parser.add_argument("--n", type=int, default=None, help="robots in (a), (b), (c)")
    parser.add_argument("--big", type=int, default=100_000, help="robots in (d), 0 to skip")
    parser.add_argument("--rate", type=float, default=100.0, help="the motion's samples per s, Hz")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=1, help="rounds of (a), (b), (c)")
    args = parser.parse_args()

    print(f"parasils {parasils.__version__}, Python {platform.python_version()}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")
    study = parasils.ToleranceStudy(None, seed=args.seed, rate_hz=args.rate)
    print(f"the paper's reorientation at {args.rate:g} Hz ({study.n_motion_samples} samples), "
          f"default tolerances, seed {args.seed}")

    n = args.n
    if n is None:
        t = time.perf_counter()
        study.run(0, 400, threads=1)
        per_robot = (time.perf_counter() - t) / 400
        n = max(1000, math.ceil(args.seconds / per_robot / 100) * 100)
        print(f"probe: {1e3 * per_robot:.3f} ms per robot on one thread -> n = {n}", flush=True)

    times = {"a": [], "b": [], "c": []}
    identical = True
    a = None
    for r in range(args.repeat):
        # (a), (b) and (c) in turn, so that a change of the machine's load
        # hits all three alike; the best of each is kept.
        t = time.perf_counter()
        again = study.run(0, n, threads=1)
        times["a"].append(time.perf_counter() - t)
        a = again if a is None else a
        identical &= same_bits(a, again)
        for key, workers in (("b", 1), ("c", 2)):
            seconds, result = on_cluster(workers, n, args)
            times[key].append(seconds)
            identical &= same_bits(a, result)
        print(f"  round {r + 1}: (a) {times['a'][-1]:.2f} s, (b) {times['b'][-1]:.2f} s, "
              f"(c) {times['c'][-1]:.2f} s, load average {os.getloadavg()[0]:.2f}", flush=True)
    time_a, time_b, time_c = (min(times[k]) for k in "abc")

    print(f"\n{n} robots (best of {args.repeat}):")
    line("(a) one process, 1 thread", time_a, n)
    line("(b) LocalCluster, 1 worker x 1 thread", time_b, n)
    line("(c) LocalCluster, 2 workers x 1 thread", time_c, n)
    print(f"  speed-up (b) / (c): {time_b / time_c:.2f}x    Dask's overhead (b) / (a): "
          f"{time_b / time_a:.3f}")
    print(f"  (a), (b), (c) bit-identical: {identical}   failed robots: {int(a['failed'].sum())}")
    tip = np.maximum(a["left_tip_dev_mm"], a["right_tip_dev_mm"])[~a["failed"]]
    p = np.percentile(tip, [50, 95, 99, 99.9])
    print("  tip deviation, larger of both (mm): "
          + ", ".join(f"p{q:g} {v:.4f}" for q, v in zip([50, 95, 99, 99.9], p)))

    if args.big > 0:
        t = time.perf_counter()
        big = study.run(0, args.big, threads=2)
        time_d = time.perf_counter() - t
        print(f"\n{args.big} robots:")
        line("(d) one process, 2 threads", time_d, args.big)
        k = min(n, args.big)
        print(f"  the same rows as (a) where they overlap: {same_bits(head(big, k), head(a, k))}")
    print(f"\nload average after: {os.getloadavg()[0]:.2f}")
    if not identical:
        raise SystemExit("the three runs differ")


if __name__ == "__main__":
    main()
