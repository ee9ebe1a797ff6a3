"""Kinematics and motion of PARA-SILSROB, the parallel robot for
single-incision laparoscopic surgery, from Python.

The same Rust code as the firmware and the ``parasils`` command, on NumPy
arrays. Units are those of the libraries: mm, rad, s (``simulate`` speaks the
CLI's units, which its argument names and column names carry).

- :class:`Robot`: the robot's geometry and its solvers (instrument modules'
  IK, FK and rates; module 1's IK, FK and rates), each on one sample or a
  batch of rows, looped in Rust without the GIL; the endoscope's turn as a
  path with its exact derivatives (``Robot.reorientation_path``) and timed as
  fast as the actuators' limits allow (``Robot.optimal_reorientation``).
- :func:`teleop`: a recorded teleoperation session (the issue's CSV
  format) replayed, as ``parasils teleop --input`` does: the same table as
  :func:`simulate`, then the tips, each device's axes and buttons and the
  teleoperation core's codes (state, hold, fault, hands).
- :func:`simulate`: the simulation library's run, as ``parasils simulate``
  does it, returning its CSV table as a dict of NumPy columns
  (``pandas.DataFrame(parasils.simulate())``), and writing CSV or MCAP with
  ``out=``; new goals and a stop commanded while the platform moves with
  ``retarget=`` and ``stop_at_s=``.
- :func:`calibrate`: module 1's geometry fitted to actuator readings at
  measured poses, returning the fitted :class:`Robot` and a report.
- :func:`tolerance`: a tolerance study, robots built within a tolerance
  specification driven by the nominal model's commands, on this machine's
  threads or mapped over a Dask cluster (``client=``); :class:`ToleranceStudy`
  runs any range or list of its samples and pickles to workers.
- :data:`COLUMNS`: the names of those columns, each with its unit.
- :mod:`parasils.live`: a client of ``parasils serve`` (the robot live over
  Foxglove's WebSocket protocol): subscribe, publish a hand's input, send a
  command; it needs the ``websockets`` package (``parasils[live]``) and is
  imported on its own (``from parasils.live import LiveClient``).
- :func:`segment_distance_mm`: the closest points of two segments and their
  distance (the clearance kernel), on batches of segment pairs.
- :func:`batch_threads`: the number of threads a large batch runs on
  (``PARASILS_NUM_THREADS``, else the CPUs available).
- Errors: :class:`KinematicsError` (a ``ValueError``) and one subclass per
  kind of failure, carrying the Rust error's fields; :class:`TrajectoryError`,
  :class:`RobotFileError`.

>>> import numpy as np, parasils
>>> robot = parasils.Robot()
>>> p0 = np.array([15, 20, -500, *np.radians([-15, 10, -60])])  # mm, rad
>>> qs = robot.instrument_ik("left", p0, [50, -50, -620])  # rad, rad, mm
>>> print(np.degrees(qs[:2]).round(4), qs[2].round(4))
[  3.0889 -38.8695] 147.7687
"""

import warnings as _warnings

from . import _parasils
from ._parasils import (
    COLUMNS,
    ActuatorLimitError,
    BranchMismatchError,
    InvalidParameterError,
    JointLimitError,
    KinematicsError,
    LegOutOfReachError,
    NoConvergenceError,
    NonFiniteError,
    OutOfReachError,
    ParallelSingularError,
    Robot,
    RobotFileError,
    SerialSingularError,
    SingularError,
    SingularJacobianError,
    ToleranceStudy,
    TrajectoryError,
    __version__,
    batch_threads,
    segment_distance_mm,
    teleop,
)

#: The paper's scenario in the units of ``simulate``'s arguments, from the
#: Rust library (where it is stated once): the defaults of ``simulate``.
_PAPER = _parasils.PAPER


def simulate(
    *,
    psi_deg=None,
    theta_deg=None,
    absolute=None,
    omega_max_deg_s=None,
    eps_max_deg_s2=None,
    sync=None,
    rate_hz=None,
    pose_mm_deg=None,
    tip_left_mm=None,
    tip_right_mm=None,
    robot=None,
    out=None,
    format=None,
    retarget=None,
    stop_at_s=None,
    pose=None,
    force=False,
    procedure=None,
    timing=None,
    tip_load_left_n=None,
    tip_load_right_n=None,
    look_at=None,
    anatomy=None,
):
    """Simulates an endoscope reorientation (motion type 4) with the
    simulation library, as ``parasils simulate`` does: the platform turns
    about the endoscope's RCM from ``pose_mm_deg`` by (psi_deg, theta_deg)
    along a synchronised trapezoidal profile, and both instrument modules
    keep their tips still. The defaults are the paper's scenario (see
    docs/model.md, "Check values"): 4501 samples over 4.5 s.

    Keyword arguments (the CLI's options, names with their units). Each
    is None when not given, which is not the same as giving its default:
    the rules (defaults, what a procedure excludes, which limits bind under
    timing="optimal") are the simulation library's, the same code the CLI's
    flags go through, so the same request gives the same table to the bit.

    - psi_deg, theta_deg: the increments of psi and theta from the start
      pose, deg (the final angles with absolute=True); default 15, 25.
    - absolute: take psi_deg and theta_deg as final angles (--absolute).
    - look_at: what the camera should look at instead of psi_deg and
      theta_deg (--look-at): a point [x, y, z] in mm (fixed frame), or
      "tips" (their midpoint), "left" or "right". The turn is the one, phi
      and both tips held, that puts it on the view axis, nearest the start;
      either timing applies. TypeError with psi_deg, theta_deg, absolute,
      retarget or stop_at_s.
    - omega_max_deg_s: each Euler angle's velocity limit, deg/s; default 10.
    - eps_max_deg_s2: each Euler angle's acceleration limit, deg/s^2;
      default 5.
    - sync: "phase" (default), "time" or "none": how psi and theta are timed.
    - rate_hz: samples per second, Hz; default 1000.
    - pose_mm_deg: the start pose (x, y, z mm, psi, theta, phi deg, like the
      CLI's --pose and the CSV columns); default the paper's P0 =
      (15, 20, -500, -15, 10, -60).
    - tip_left_mm: the left tip held still, (x, y, z) mm, fixed frame;
      default (50, -50, -620).
    - tip_right_mm: the right tip, (x, y, z) mm; default the mirror image of
      the left tip across the platform's Y'Z' plane at the start pose, moved
      35 mm along X' and 100 mm along Y' so that the shafts do not meet
      (docs/model.md, *The paper's scenario*).
    - robot: a robot file's path (TOML, as --robot) or a parasils.Robot;
      default the paper's robot (module 1 assumed).
    - out: also write every sample to this file exactly as
      ``parasils simulate -o out`` does: CSV or MCAP from the extension
      (.csv, .mcap), through a temporary file renamed on success. Its
      estimated size is checked first: OSError (errno ENOSPC) when it
      exceeds the free space of the file's file system, ValueError when it
      exceeds the 10 GB cap without force=True.
    - format: "csv" or "mcap", overriding the extension (--format).
    - retarget: new goals commanded while the platform moves, a sequence of
      (t_s, psi_deg, theta_deg) triples in time order (--retarget
      T:PSI,THETA): at t_s (s), the goal becomes (psi_deg, theta_deg), read
      like psi_deg and theta_deg (increments from the start pose, final
      angles with absolute=True). Each takes effect at the first sample at
      or after t_s, replanned from the state of that sample: the angles and
      their rates stay continuous.
    - stop_at_s: a controlled stop commanded at this time, s (--stop-at):
      psi and theta brought to rest together at the acceleration limit,
      along their current direction; a later retarget replans from wherever
      the stop has got to.
    - tip_load_left_n, tip_load_right_n: the force each tip exerts on the
      tissue, (fx, fy, fz) N, fixed frame (--tip-load-left,
      --tip-load-right); default none. With either, the table has fourteen
      more columns, last: every actuator's force holding the loads,
      ``q1_force_n`` .. ``q6_force_n`` (N, positive pushing the slider along
      its guide's direction), ``left_qs1_torque_nmm``,
      ``left_qs2_torque_nmm`` (N mm), ``left_qs3_force_n`` (N), the same for
      the right module, then ``left_tip_deflection_mm`` and
      ``right_tip_deflection_mm``: how far each tip gives way under the
      tissue's push with the robot's actuator stiffnesses (its file's
      [stiffness], assumed by default; see docs/model.md, "Forces").
      Allowed with a procedure. A robot whose file has a [dynamics] table
      (the platform as one rigid body) gives the same columns without a
      load: every actuator's force holding its weight and moving its
      inertia, the tips' loads added when given.
    - anatomy: a path to an anatomy file of forbidden regions (--anatomy):
      spheres, boxes, capsules and STL/OBJ meshes, fixed frame, mm. Every
      cycle checks the in-body part of each shaft and of the endoscope
      against each region; the table gets ``no_go_clearance_mm``, last, and
      a planned run or procedure closer to a region than the clearance stop
      threshold (0.5 mm by default) raises ValueError naming the region, the
      body and the time. Allowed with a procedure that names none itself.
    - force: write ``out`` even above the 10 GB cap (--force).
    - pose: deprecated name of pose_mm_deg (a DeprecationWarning; removed in
      the next release).
    - timing: "trapezoid" (default: the paper's, within omega_max_deg_s and
      eps_max_deg_s2) or "optimal" (--timing optimal): the fastest turn along
      the same straight line whose twelve actuators stay within the robot's
      velocity and acceleration limits; omega_max_deg_s and eps_max_deg_s2
      bind as well only when given (even at the paper's values). It plans
      from rest to rest, so it takes no retarget or stop_at_s. With
      procedure, every motion is timed so, from rest to rest; the limits the
      procedure states for a motion bind as well (an endoscope insertion,
      which moves no actuator, keeps its own limits, stated or default).
    - procedure: run a procedure instead (--procedure): a procedure file's
      path (TOML) or a dict of the same structure, e.g.
      ``{"motion": [{"type": "insert", "instrument": "endoscope",
      "depth_mm": 40}]}``. It gives the start (pose, tips, endoscope depth),
      the robot and the motions (motion types 1 to 4: "position", "insert",
      "manipulate", "reorient"), so only rate_hz, timing, the tip loads, out,
      format and force may be given with it (TypeError otherwise). The whole procedure is planned
      and checked before anything is returned or written. Its table has
      twelve more columns after the others: ``motion`` and ``motion_type``
      (int64: the motion's index from 0, the paper's type 1 to 4),
      ``endoscope_depth_mm``, and the tips ``left_tip_x_mm`` ..
      ``right_tip_z_mm``, ``endoscope_tip_x_mm`` .. ``endoscope_tip_z_mm``
      (mm, fixed frame).

    A run with commands (retarget or stop_at_s) goes through the online
    controller, as a robot's controller runs it, with its margin supervisor:
    a margin heading below its stop threshold stops the platform (a
    "supervisor_stop") instead of failing at the hard threshold. It ends at
    the first sample at which every command has taken effect and the last
    motion is at rest.

    Returns a dict of 1-D float64 arrays keyed by the CSV's column names, in
    the CSV's order and units (t_s, x_mm, ..., psi_deg, ..., q1_mm, ...,
    left_qs1_deg, ..., right_tip_err_mm; rates are ``_rate_``, accelerations
    ``_acc_``): the CLI's CSV to the last bit. The Euler angle columns start
    on the start pose's own degrees. A run with commands has one more
    column, last: ``command``, an int64 array, the index of the active
    command (0 for the reorientation, one more at each retarget and at each
    stop), as in the CLI's CSV. Every run has what the camera sees:
    ``left_tip_u``, ``left_tip_v``, ``right_tip_u``, ``right_tip_v`` (each
    commanded tip's normalised image coordinates, -1 to 1 across the image),
    ``left_tip_in_view``, ``right_tip_in_view`` (1.0 or 0.0),
    ``camera_aim_error_deg`` (the view axis to the look-at target, or to the
    tips' midpoint) and ``camera_roll_deg`` (the image's roll about the view
    axis since the start; docs/model.md, "What the camera sees").
    ``pandas.DataFrame(parasils.simulate())`` makes it a table.

    Raises a KinematicsError subclass when a sample fails (with .row, the
    sample's index, and .t, its time in s), TrajectoryError for limits or a
    rate that cannot be planned, RobotFileError or OSError for the robot
    file, OSError when ``out`` cannot be written, ValueError when an actuator's
    velocity or acceleration exceeds its limit at a sample (naming the actuator,
    the value, the limit and the time, as the CLI does) and for a bad
    argument (retargets out of time order, a negative or non-finite time,
    two commands on one sample, a command with timing="optimal"). The
    simulation runs without the GIL.
    """
    if pose is not None:
        if pose_mm_deg is not None:
            raise TypeError("simulate() got both pose_mm_deg and its deprecated name pose")
        _warnings.warn(
            "simulate(pose=...) is deprecated: use pose_mm_deg=... (the same values: "
            "x, y, z in mm, psi, theta, phi in deg); pose will be removed in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        pose_mm_deg = pose
    return _parasils.simulate(
        psi_deg=psi_deg,
        theta_deg=theta_deg,
        absolute=absolute,
        omega_max_deg_s=omega_max_deg_s,
        eps_max_deg_s2=eps_max_deg_s2,
        sync=sync,
        rate_hz=rate_hz,
        pose_mm_deg=pose_mm_deg,
        tip_left_mm=tip_left_mm,
        tip_right_mm=tip_right_mm,
        robot=robot,
        out=out,
        format=format,
        retarget=retarget,
        stop_at_s=stop_at_s,
        force=force,
        procedure=procedure,
        timing=timing,
        tip_load_left_n=tip_load_left_n,
        tip_load_right_n=tip_load_right_n,
        look_at=look_at,
        anatomy=anatomy,
    )


def calibrate(robot, q, poses, sigma=None):
    """Calibrate module 1: fit its geometry to actuator readings at measured
    platform poses (``parasils calibrate``'s fit, the same Rust code).

    ``q`` holds the readings ``q1..q6`` (mm) and ``poses`` the measured
    poses ``(x, y, z, psi, theta, phi)`` (mm, rad), one row per pose, shape
    ``(N, 6)``: NumPy arrays, pandas frames or nested lists. ``sigma`` gives
    the measurements' standard deviations ``(readings mm, position mm,
    angles rad)``, three numbers for every row or an ``(N, 3)`` array; with
    ``None`` every equation weighs the same. ``robot`` is the nominal robot:
    the fit starts from its module 1 and keeps the parameters the poses
    cannot see at its values.

    Returns ``(fitted, report)``: the fitted :class:`Robot` (module 1 no
    longer assumed, its calibration recorded; ``fitted.to_toml()`` writes
    it) and the report as a dict (RMS residual before and after, each
    identified parameter with its standard deviation, the fixed ones with
    the reason, the observability indices). Raises ``ValueError`` naming
    the row or the problem: a NaN, a pose out of the nominal robot's reach,
    too few poses, divergence.
    """
    import json

    import numpy as np

    def table(name, a, width):
        a = np.ascontiguousarray(np.asarray(a, dtype=np.float64))
        if a.ndim == 1 and a.shape[0] == width:
            a = a.reshape(1, width)
        return a

    s = None if sigma is None else table("sigma", sigma, 3)
    fitted, report = _parasils._calibrate(robot, table("q", q, 6), table("poses", poses, 6), s)
    return fitted, json.loads(report)


#: The columns of a tolerance study's result, in order (``failures`` aside).
_TOLERANCE_COLUMNS = (
    "sample",
    "left_tip_dev_mm",
    "right_tip_dev_mm",
    "pose_position_err_mm",
    "pose_rotation_err_deg",
    "failed",
)


def tolerance(
    spec,
    n,
    *,
    seed=0,
    procedure=None,
    rate_hz=100.0,
    chunks=None,
    client=None,
    robot=None,
):
    """A tolerance study, as ``parasils tolerance`` runs it: ``n`` robots
    built within the tolerances of ``spec``, each driven along a motion by
    the commands the controller computes on the nominal robot, and how far
    their instrument tips and platform really go from the commanded ones.

    - spec: the tolerances: a path to a specification file (TOML, as
      ``parasils tolerance --print-spec`` prints it), a dict of the same
      structure, e.g. ``{"module1": {"guides": {"point_mm": {"sigma":
      0.05}}}, "instruments": {"alpha_deg": {"half_width": 0.02}}}``
      (``sigma``: normal, one standard deviation; ``half_width``: uniform;
      in the unit the key names, mm or deg; families left out are not
      perturbed), or None for the default tolerances.
    - n: the number of perturbed robots, samples 0 to n - 1.
    - seed: sample i's robot depends only on the seed and i, so that any
      split of the samples (chunks, threads, workers, machines) gives the
      same numbers, bit for bit.
    - procedure: the motion: a procedure file's path (TOML) or a dict of
      the same structure (see ``simulate``); default the paper's
      reorientation.
    - rate_hz: the samples per second along the motion, Hz; default 100.
    - robot: the nominal robot, a :class:`Robot` or a robot file's path;
      default the paper's (not with ``procedure``, which names its own).
    - client: a ``dask.distributed.Client``: the samples are cut into chunks
      of ``chunks`` consecutive samples, mapped over the cluster's workers
      (the study pickled once and sent to each) and gathered in sample
      order. Each chunk runs on one thread of its worker
      (``PARASILS_NUM_THREADS=1``) unless ``PARASILS_NUM_THREADS`` is set in
      the worker's environment: give the workers one Dask thread per core.
      Without ``client``: this process, on ``batch_threads()`` threads.
      Dask is not imported by parasils: any cluster the client reaches
      works (``LocalCluster``, ``dask scheduler`` and ``dask worker`` on
      several machines, with the same parasils version everywhere).
    - chunks: samples per chunk with ``client``; default about four chunks
      per worker thread.

    Returns a dict of NumPy columns, one row per sample in order:
    ``sample`` (uint64), ``left_tip_dev_mm`` and ``right_tip_dev_mm`` (each
    tip's largest distance from the commanded one along the motion, mm),
    ``pose_position_err_mm`` (mm) and ``pose_rotation_err_deg`` (deg, the
    platform's), float64, and ``failed`` (bool); a failed sample (a
    perturbed robot the replay cannot follow, e.g. module 1's forward
    kinematics does not converge) keeps its row with NaN deviations, and
    ``failures`` lists ``(sample, message)`` for each. The same whether
    ``client`` is given or not, bit for bit. ``pandas.DataFrame`` takes
    the columns (leave ``failures`` out).

    The percentiles a designer reads, from NumPy (its default ``linear``
    method, as ``parasils tolerance`` reports them)::

        r = parasils.tolerance(None, 10_000)
        ok = ~r["failed"]
        tip = np.maximum(r["left_tip_dev_mm"], r["right_tip_dev_mm"])[ok]
        p50, p95, p99, p999 = np.percentile(tip, [50, 95, 99, 99.9])

    and which tolerance to tighten, from the first-order model (analytic
    derivatives, not the samples):
    ``ToleranceStudy(spec, ...).sensitivity()``.

    Raises ValueError for a bad specification (an unknown key, a negative
    width, a tolerance whose extreme takes a leg of module 1 out of reach
    along the motion) or argument, the simulation's errors when the nominal
    motion fails, RobotFileError or OSError for the files.
    """
    import operator

    n = operator.index(n)
    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    if chunks is not None:
        chunks = operator.index(chunks)
        if chunks < 1:
            raise ValueError(f"chunks must be at least 1 sample, got {chunks}")
    study = ToleranceStudy(spec, seed=seed, procedure=procedure, rate_hz=rate_hz, robot=robot)
    if client is None:
        return study.run(0, n)
    return _tolerance_on_dask(study, n, chunks, client)


def _tolerance_chunk(start, count, study):
    """Samples ``start .. start + count - 1`` of ``study`` on a worker: on
    one thread, unless the worker's environment sets PARASILS_NUM_THREADS
    (the worker's own Dask threads are the parallelism)."""
    import os

    threads = None if os.environ.get("PARASILS_NUM_THREADS", "").strip() else 1
    return study.run(start, count, threads=threads)


def _tolerance_on_dask(study, n, chunks, client):
    """``tolerance``'s samples mapped over a Dask client's workers, chunk
    by chunk, gathered and joined in sample order."""
    if chunks is None:
        threads = sum(client.nthreads().values())
        chunks = max(1, -(-n // (4 * max(1, threads))))
    starts = list(range(0, n, chunks))
    if not starts:
        return study.run(0, 0)
    counts = [min(chunks, n - s) for s in starts]
    [remote] = client.scatter([study], broadcast=True, hash=False)
    futures = client.map(_tolerance_chunk, starts, counts, study=remote, pure=False)
    try:
        parts = client.gather(futures)
    except BaseException:
        client.cancel(futures)
        raise
    return _tolerance_join(parts)


def _tolerance_join(parts):
    """The results of consecutive chunks as one."""
    import numpy as np

    out = {name: np.concatenate([p[name] for p in parts]) for name in _TOLERANCE_COLUMNS}
    out["failures"] = [f for p in parts for f in p["failures"]]
    return out


__all__ = [
    "COLUMNS",
    "ActuatorLimitError",
    "BranchMismatchError",
    "InvalidParameterError",
    "JointLimitError",
    "KinematicsError",
    "LegOutOfReachError",
    "NoConvergenceError",
    "NonFiniteError",
    "OutOfReachError",
    "ParallelSingularError",
    "Robot",
    "RobotFileError",
    "SerialSingularError",
    "SingularError",
    "SingularJacobianError",
    "ToleranceStudy",
    "TrajectoryError",
    "__version__",
    "batch_threads",
    "calibrate",
    "segment_distance_mm",
    "simulate",
    "teleop",
    "tolerance",
]
