"""Kinematics and motion of PARA-SILSROB, the parallel robot for
single-incision laparoscopic surgery, from Python.

The same Rust code as the firmware and the ``parasils`` command, on NumPy
arrays. Units are those of the libraries: mm, rad, s (``simulate`` speaks the
CLI's units, which its argument names and column names carry).

- :class:`Robot`: the robot's geometry and its solvers (instrument modules'
  IK, FK and rates; module 1's IK, FK and rates), each on one sample or a
  batch of rows, looped in Rust without the GIL.
- :func:`simulate`: the CLI's ``parasils simulate``, returning its CSV table
  as a dict of NumPy columns (``pandas.DataFrame(parasils.simulate())``), and
  writing CSV or MCAP with ``out=``.
- :data:`COLUMNS`: the names of those columns, each with its unit.
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
    TrajectoryError,
    __version__,
    batch_threads,
    simulate,
)

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
    "TrajectoryError",
    "__version__",
    "batch_threads",
    "simulate",
]
