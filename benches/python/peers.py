"""The instrument IK side by side in one run: `parasils.Robot().instrument_ik`
on a batch against the project's vectorised NumPy baseline
(`bench_batch.numpy_instrument_ik`), a plain NumPy version (one row at a
time, the same equations on (3,) arrays), the binding called row by row,
and, where installed, Pinocchio and the Robotics Toolbox for Python solving
the same module numerically (neither has the module's closed form).

    python benches/python/peers.py [--rows 1000000] [--peer-rows 1000] [--repeat 7]

The rows are bench_batch's (the paper's reorientation, the left tip held,
every row regular). The batch methods run on `--rows` rows (median of
`--repeat` runs, alternating, after a warm-up); the row-by-row methods on
the first `--plain-rows` (plain NumPy, the binding row by row) or
`--peer-rows` (Pinocchio, the toolbox) rows, timed once each after a
warm-up of ten rows. Every method's time is printed per row, with its ratio
to the parasils batch's, and the largest difference of its joints from the
parasils batch's (rad and mm).

The peers model the left module as the serial chain of `docs/model.md`
(*Instrument modules*): `R_Y(alpha) R_X(qs1) R_Y(qs2) R_X(beta)`, the tip
at `z = -qs3` of the last frame, in the module's RCM frame; the tip
(fixed frame) is taken into that frame with NumPy per row, and each solves
the position by its own iterative IK from the paper's start joints
(Pinocchio: damped Gauss-Newton on its frame Jacobian, to 1e-10 mm; the
toolbox: `ik_LM` with a position-only mask). A peer that is not installed
is skipped with a printed line (`pip install pin roboticstoolbox-python`).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_batch import ALPHA, BETA, RCM_LEFT, load, medians, numpy_instrument_ik, rows  # noqa: E402

import parasils  # noqa: E402

Q0 = np.array([3.0889 * np.pi / 180.0, -38.8695 * np.pi / 180.0, 147.7687])  # the paper's start


def rotation(psi: float, theta: float, phi: float) -> np.ndarray:
    """R = R_X(psi) R_Y(theta) R_Z(phi) as a (3, 3) array."""
    s1, c1 = np.sin(psi), np.cos(psi)
    s2, c2 = np.sin(theta), np.cos(theta)
    s3, c3 = np.sin(phi), np.cos(phi)
    return np.array(
        [
            [c2 * c3, -c2 * s3, s2],
            [c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2],
            [s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2],
        ]
    )


def local_tip(pose: np.ndarray, tip: np.ndarray) -> np.ndarray:
    """The tip in the left module's RCM frame: R^T (tip - P) - RCM."""
    return rotation(*pose[3:]).T @ (tip - pose[:3]) - RCM_LEFT


def plain_numpy_ik(pose: np.ndarray, tip: np.ndarray) -> np.ndarray:
    """The closed form for one row, NumPy on (3,) arrays (mode A, no checks
    beyond the reach: the rows are regular)."""
    p = local_tip(pose, tip)
    qs3 = np.linalg.norm(p)
    u = -p / qs3
    sa, ca, sb, cb = np.sin(ALPHA), np.cos(ALPHA), np.sin(BETA), np.cos(BETA)
    v = np.array([ca * u[0] - sa * u[2], u[1], sa * u[0] + ca * u[2]])
    s = np.clip(v[0] / cb, -1.0, 1.0)
    c = np.sqrt((1.0 - s) * (1.0 + s))
    qs1 = np.arctan2(-sb * v[2] - cb * c * v[1], cb * c * v[2] - sb * v[1])
    return np.array([qs1, np.arcsin(s), qs3])


def pinocchio_solver():
    """A Pinocchio model of the left module and a per-row IK, or None."""
    try:
        import pinocchio as pin
    except ImportError:
        return None, "not installed (pip install pin)"
    model = pin.Model()
    ry = pin.SE3(pin.utils.rotate("y", ALPHA), np.zeros(3))
    j1 = model.addJoint(0, pin.JointModelRX(), ry, "qs1")
    j2 = model.addJoint(j1, pin.JointModelRY(), pin.SE3.Identity(), "qs2")
    rx = pin.SE3(pin.utils.rotate("x", BETA), np.zeros(3))
    j3 = model.addJoint(j2, pin.JointModelPrismaticUnaligned(np.array([0.0, 0.0, -1.0])), rx, "qs3")
    tip_frame = model.addFrame(pin.Frame("tip", j3, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    data = model.createData()

    def solve(pose: np.ndarray, tip: np.ndarray) -> np.ndarray:
        target = local_tip(pose, tip)
        q = Q0.copy()
        for _ in range(50):
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacement(model, data, tip_frame)
            err = data.oMf[tip_frame].translation - target
            if np.linalg.norm(err) < 1e-10:
                break
            jac = pin.computeFrameJacobian(
                model, data, q, tip_frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
            )[:3]
            q = q - np.linalg.solve(jac.T @ jac + 1e-12 * np.eye(3), jac.T @ err)
        return q

    return solve, f"pinocchio {pin.__version__}"


def toolbox_solver():
    """A Robotics Toolbox ETS of the left module and a per-row IK, or None."""
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3
    except ImportError:
        return None, "not installed (pip install roboticstoolbox-python)"
    # The tip at z = -qs3: a half turn about x, then the prismatic joint
    # along z (the toolbox's IK ignores `flip`).
    ets = rtb.ET.Ry(ALPHA) * rtb.ET.Rx() * rtb.ET.Ry() * rtb.ET.Rx(BETA) * rtb.ET.Rx(np.pi) * rtb.ET.tz()
    mask = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])

    def solve(pose: np.ndarray, tip: np.ndarray) -> np.ndarray:
        target = SE3.Trans(*local_tip(pose, tip))
        sol = ets.ik_LM(target, q0=Q0, mask=mask, tol=1e-20, ilimit=100, slimit=1, joint_limits=False)
        return np.asarray(sol[0])

    return solve, f"roboticstoolbox {rtb.__version__}"


def per_row(solve, pose: np.ndarray, tip: np.ndarray) -> tuple[float, np.ndarray]:
    """Seconds per row of `solve` over the rows, and its results."""
    for i in range(min(10, len(pose))):
        solve(pose[i], tip[i])
    t = time.perf_counter()
    out = np.array([solve(pose[i], tip[i]) for i in range(len(pose))])
    return (time.perf_counter() - t) / len(pose), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--plain-rows", type=int, default=20_000)
    ap.add_argument("--peer-rows", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()

    robot = parasils.Robot()
    pose, tip = rows(args.rows, np.random.default_rng(2024))
    print(
        f"parasils {parasils.__version__} (batch threads {parasils.batch_threads()}), "
        f"numpy {np.__version__}, Python {platform.python_version()}, {platform.machine()}, "
        f"CPUs {os.cpu_count()}"
    )
    print(f"{load()} (before)")
    ours = robot.instrument_ik("left", pose, tip)
    t_batch, t_numpy = medians(
        args.repeat,
        lambda: robot.instrument_ik("left", pose, tip),
        lambda: numpy_instrument_ik(pose, tip),
    )
    base = t_batch / args.rows
    results = [
        (f"parasils batch ({args.rows} rows)", base, 0.0),
        (
            f"NumPy vectorised ({args.rows} rows)",
            t_numpy / args.rows,
            float(np.max(np.abs(numpy_instrument_ik(pose, tip) - ours))),
        ),
    ]
    m = min(args.plain_rows, args.rows)
    t, out = per_row(plain_numpy_ik, pose[:m], tip[:m])
    results.append((f"NumPy plain, row by row ({m} rows)", t, float(np.max(np.abs(out - ours[:m])))))
    t, out = per_row(lambda p, q: robot.instrument_ik("left", p, q), pose[:m], tip[:m])
    results.append((f"parasils, row by row ({m} rows)", t, float(np.max(np.abs(out - ours[:m])))))
    k = min(args.peer_rows, args.rows)
    for make in (pinocchio_solver, toolbox_solver):
        solve, name = make()
        if solve is None:
            print(f"skipped: {make.__name__[:-7]} {name}")
            continue
        t, out = per_row(solve, pose[:k], tip[:k])
        results.append((f"{name}, row by row ({k} rows)", t, float(np.max(np.abs(out - ours[:k])))))
    print(f"{'method':<48} {'ns per row':>12} {'x parasils batch':>17} {'max |diff|':>11}")
    for name, t, diff in results:
        print(f"{name:<48} {t * 1e9:>12.1f} {t / base:>16.1f}x {diff:>11.1e}")
    print(f"{load()} (after)")


if __name__ == "__main__":
    main()
