"""Online profiles side by side with Ruckig in its second-order mode.

Random problems (a current position and velocity, up to 1.5 v_max in either
direction, a target to reach at rest, velocity and acceleration limits), one
axis and two axes, go through parasils (the `online_durations` example of
parasils-traj, reading the problems as CSV on its standard input) and through
the `ruckig` package with an infinite jerk limit, which makes Ruckig plan
acceleration-limited (second-order) profiles. Two axes are time-synchronised
on both sides (Ruckig's default).

The durations must agree within 1e-9 relative where both succeed. Every case
that does not is listed with the reason found:
- one side fails: its error is shown, with where the target lies relative
  to the stopping point (a parasils failure is a failure of the script);
- the target lies within the rounding of the positions of the stopping point
  (braking at a_max straight away): there the minimum time is ill-conditioned,
  the duration moving by up to 2 sqrt(delta / a_max) for a position rounding
  delta (brake only, or overshoot by delta and come back), and the two
  implementations may round to different sides;
- otherwise the case is unexplained, and the script exits with status 1.

Usage (from the repository root, in a Python environment with ruckig and numpy):

    python benches/python/ruckig_compare.py [--cases 10000] [--seed 1]
        [--binary PATH]

Without --binary the example is built in release mode with cargo.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from ruckig import InputParameter, Result, Ruckig, Trajectory

ROOT = Path(__file__).resolve().parents[2]
RELATIVE = 1e-9
EPS = np.finfo(float).eps


@dataclass
class Axis:
    p0: float
    v0: float
    target: float
    v_max: float
    a_max: float

    def csv(self) -> str:
        fields = (self.p0, self.v0, self.target, self.v_max, self.a_max)
        return ",".join(repr(float(x)) for x in fields)

    def stop_gap(self) -> float:
        """Distance from the stopping point (braking at a_max now) to the target."""
        return self.target - (self.p0 + 0.5 * self.v0 * abs(self.v0) / self.a_max)

    def time_slack(self) -> float:
        """How far rounding of the positions can move the minimum time (s)."""
        delta = 16 * EPS * (abs(self.p0) + abs(self.target) + self.v0**2 / self.a_max)
        gap = max(abs(self.stop_gap()), delta)
        return 4 * delta / min(self.v_max, math.sqrt(self.a_max * gap))


def random_axis(rng: np.random.Generator) -> Axis:
    v_max = 10 ** rng.uniform(-1, 1)
    a_max = 10 ** rng.uniform(-1, 1.5)
    p0 = rng.uniform(-10, 10)
    kind = rng.uniform()
    v0 = 0.0 if kind < 0.05 else rng.uniform(-1.5, 1.5) * v_max
    stop = p0 + 0.5 * v0 * abs(v0) / a_max
    if kind < 0.15:
        # At or next to the stopping point.
        target = stop * (1 + rng.choice([0.0, 1e-3, -1e-3, 1e-9, -1e-9]))
    elif kind < 0.25:
        target = p0  # on the target, maybe moving
    else:
        target = rng.uniform(-10, 10)
    return Axis(float(p0), float(v0), float(target), float(v_max), float(a_max))


def build_binary() -> Path:
    subprocess.run(
        ["cargo", "build", "--release", "-p", "parasils-traj", "--example", "online_durations"],
        cwd=ROOT,
        check=True,
    )
    return ROOT / "target" / "release" / "examples" / "online_durations"


def parasils(binary: Path, problems: list[list[Axis]]) -> list[tuple[float | None, str]]:
    """(duration, detail) per problem; duration None on an error."""
    lines = "\n".join(",".join(a.csv() for a in axes) for axes in problems) + "\n"
    out = subprocess.run([str(binary)], input=lines, capture_output=True, text=True, check=True)
    results = []
    for line in out.stdout.splitlines():
        if line.startswith("error"):
            results.append((None, line))
        else:
            fields = line.split(",")
            results.append((float(fields[0]), ",".join(fields[1:])))
    if len(results) != len(problems):
        raise SystemExit(f"parasils answered {len(results)} lines for {len(problems)} problems")
    return results


def ruckig(axes: list[Axis]) -> tuple[float | None, str]:
    n = len(axes)
    otg = Ruckig(n)
    inp = InputParameter(n)
    inp.current_position = [a.p0 for a in axes]
    inp.current_velocity = [a.v0 for a in axes]
    inp.current_acceleration = [0.0] * n
    inp.target_position = [a.target for a in axes]
    inp.target_velocity = [0.0] * n
    inp.target_acceleration = [0.0] * n
    inp.max_velocity = [a.v_max for a in axes]
    inp.max_acceleration = [a.a_max for a in axes]
    inp.max_jerk = [math.inf] * n  # second order: acceleration-limited
    traj = Trajectory(n)
    try:
        result = otg.calculate(inp, traj)
    except Exception as e:  # RuckigError: no profile found, or invalid input
        first = str(e).strip().splitlines()[0]
        return None, f"ruckig raised {type(e).__name__}: {first}"
    if result not in (Result.Working, Result.Finished):
        return None, f"ruckig: {result}"
    return traj.duration, ""


def compare(kind: str, problems: list[list[Axis]], ours: list[tuple[float | None, str]]) -> int:
    """Prints the summary for one kind; returns the number of unexplained cases."""
    agree = 0
    worst = 0.0
    explained: list[str] = []
    unexplained: list[str] = []
    ruckig_fails: list[str] = []
    for axes, (t_ours, detail) in zip(problems, ours):
        t_theirs, why = ruckig(axes)
        case = " | ".join(a.csv() for a in axes)
        gaps = ", ".join(f"{a.stop_gap():.3g}" for a in axes)
        if t_ours is None:
            unexplained.append(f"{case}: parasils fails ({detail}); ruckig {t_theirs!r} {why}")
            continue
        if t_theirs is None:
            ruckig_fails.append(
                f"{case}: parasils {t_ours!r}; {why} "
                f"(target minus stopping point: {gaps})"
            )
            continue
        diff = abs(t_ours - t_theirs)
        rel = diff / max(abs(t_ours), abs(t_theirs), 1e-300)
        if rel <= RELATIVE:
            agree += 1
            worst = max(worst, rel)
            continue
        # Two axes: the common duration is the longer own minimum time; the
        # slack of either axis may move it.
        slack = max(a.time_slack() for a in axes)
        line = (
            f"{case}: parasils {t_ours!r} ({detail or 'one axis'}), ruckig {t_theirs!r}, "
            f"relative {rel:.2e}"
        )
        if diff <= slack:
            explained.append(
                f"{line}; target within rounding of the stopping point "
                f"(gap {min(abs(a.stop_gap()) for a in axes):.1e}, duration slack {slack:.1e} s)"
            )
        else:
            unexplained.append(line)
    total = len(problems)
    print(
        f"{kind}: {total} problems, {agree} agree within {RELATIVE:g} relative "
        f"(worst {worst:.1e}), {len(explained)} differ near the stopping point, "
        f"{len(ruckig_fails)} where ruckig finds no profile, {len(unexplained)} unexplained"
    )
    for line in ruckig_fails:
        print(f"  ruckig fails: {line}")
    for line in explained:
        print(f"  near the stopping point: {line}")
    for line in unexplained:
        print(f"  UNEXPLAINED: {line}")
    return len(unexplained)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=10_000, help="problems of each kind")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--binary", type=Path, help="the online_durations example, built")
    args = parser.parse_args()
    binary = args.binary or build_binary()
    rng = np.random.default_rng(args.seed)
    bad = 0
    for kind, n_axes in (("one axis", 1), ("two axes, time-synchronised", 2)):
        problems = [[random_axis(rng) for _ in range(n_axes)] for _ in range(args.cases)]
        bad += compare(kind, problems, parasils(binary, problems))
    print("all durations agree or are explained" if bad == 0 else f"{bad} unexplained differences")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
