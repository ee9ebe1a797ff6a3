"""Type stubs of the parasils package (the compiled module parasils._parasils).

Units: mm, rad, s, except in ``simulate``, whose argument and column names
carry their units (deg, deg/s, Hz, mm).
"""

import os
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
#: The CSV columns of ``parasils simulate`` and the keys of ``simulate()``'s
#: dict, in order, each named with its unit.
COLUMNS: Tuple[str, ...]

_Side = Literal["left", "right"]
_Mode = Literal["A", "B"]
_F64 = npt.NDArray[np.float64]
_Mask = npt.NDArray[np.bool_]
_Array = npt.ArrayLike
_Path = Union[str, "os.PathLike[str]"]

class Robot:
    """The PARA-SILSROB robot: module 1 and the two instrument modules.

    Every method takes one sample ((6,), (3,)) or a batch ((N, 6), (N, 3));
    a single row goes with every row of a batch. With errors="nan" a
    boolean mask (or a bool for one sample) is appended to the result.
    """

    def __init__(self) -> None:
        """The paper's robot (module 1's geometry assumed)."""
    @staticmethod
    def from_toml(path: _Path) -> "Robot":
        """The robot of a robot file (TOML, angles in deg, lengths in mm)."""
    @staticmethod
    def from_toml_str(text: str) -> "Robot":
        """The robot of a robot file's text (TOML, as to_toml() writes it);
        a Robot pickles as that text."""
    def to_toml(self) -> str:
        """The robot as a robot file (TOML): the geometry, and the
        [supervisor] table when the file it was read from had one."""
    @property
    def supervisor(self) -> Dict[str, float]:
        """The margin supervisor's thresholds the robot file set
        ([supervisor]), keyed as the file names them, in its units."""
    @property
    def module1_assumed(self) -> bool:
        """Whether module 1's geometry is assumed (not the real robot's)."""
    @property
    def module1_provenance(self) -> str:
        """Where module 1's geometry comes from: "assumed geometry (not the real
        robot's)", "calibrated (RMS ... mm over N poses)" or "measured"."""
    def reach_map(
        self,
        pose: npt.ArrayLike,
        tips: Optional[npt.ArrayLike] = None,
        psi_range: Optional[Tuple[float, float]] = None,
        theta_range: Optional[Tuple[float, float]] = None,
        step: Optional[float] = None,
        *,
        psi_range_deg: Tuple[float, float] = (-45.0, 45.0),
        theta_range_deg: Tuple[float, float] = (-45.0, 45.0),
        step_deg: float = 0.5,
        line: bool = True,
        anatomy: Optional[Union[str, os.PathLike]] = None,
        deflection_load_n: Optional[Sequence[float]] = None,
    ) -> Dict[str, Any]:
        """The reach map from `pose` (mm, rad) with both tips (2, 3) held, on
        the grid psi_range_deg x theta_range_deg by step_deg (deg, as
        `parasils reach`): "dpsi", "dtheta" (rad), "feasible", "reachable",
        "line", "limiting" (indices into "codes"), "margin",
        "boundary_points" (rad), "boundary_limiting", "boundary"
        (polylines), "module1_assumed". deflection_load_n: the force each
        tip exerts, (fx, fy, fz) N (`parasils reach --deflection-load`): the
        dict then has "left_tip_deflection_mm" and "right_tip_deflection_mm"
        ((R, C), NaN where infeasible), how far each tip gives way pressing
        with it, with this robot's [stiffness]. psi_range, theta_range, step:
        the deprecated names, in rad (a DeprecationWarning)."""
    def reorientation_path(
        self,
        pose: _Array,
        tips: Optional[_Array],
        dpsi: float,
        dtheta: float,
        s: _Array,
        order: Literal[0, 1, 2] = 0,
    ) -> _F64:
        """Motion type 4 as a path s in [0, 1]: psi and theta turn by dpsi,
        dtheta (rad) from `pose` (6,) along a straight line, tips (2, 3) mm
        held (None: the paper's left tip and the default right tip). Returns the
        twelve actuators (q1..q6 mm, left and right qs1, qs2 rad, qs3 mm) at
        each s for order 0, their first (order 1) or second (order 2)
        derivatives in s: shape (len(s), 12), exact."""
    def optimal_reorientation(
        self,
        pose: _Array,
        tips: Optional[_Array],
        dpsi: float,
        dtheta: float,
        *,
        velocity_max: Optional[_Array] = None,
        acceleration_max: Optional[_Array] = None,
        omega_max_deg_s: Optional[float] = None,
        eps_max_deg_s2: Optional[float] = None,
        knots: int = 1000,
        checks: int = 10,
        omega_max: Optional[float] = None,
        eps_max: Optional[float] = None,
    ) -> Dict[str, Any]:
        """The fastest rest-to-rest timing of reorientation_path's turn within
        the actuators' limits ((12,) each, mm or rad per s and s^2; None: this
        robot's own, from its robot file or the assumed defaults) and, when given, each Euler angle's
        omega_max_deg_s (deg/s) and eps_max_deg_s2 (deg/s^2), as `parasils
        simulate --omega-max --eps-max` (omega_max, eps_max: the deprecated
        names, in rad/s and rad/s^2, a DeprecationWarning): "duration_s", "phases" (dicts with
        "start_s", "end_s", "binding", "limit", "usage"), the schedule at the
        knots "s", "t_s", "s_dot", "s_ddot", and the check's
        "worst_before_check", "passes", "stretch"."""
    @overload
    def instrument_ik(
        self,
        side: _Side,
        pose: _Array,
        tip: _Array,
        *,
        mode: _Mode = "A",
        errors: Literal["raise"] = "raise",
    ) -> _F64:
        """Instrument IK: pose (x, y, z mm, psi, theta, phi rad), tip (mm,
        fixed frame) -> qs (qs1 rad, qs2 rad, qs3 mm)."""
    @overload
    def instrument_ik(
        self,
        side: _Side,
        pose: _Array,
        tip: _Array,
        *,
        mode: _Mode = "A",
        errors: Literal["nan"],
    ) -> Tuple[_F64, Union[_Mask, bool]]: ...
    @overload
    def instrument_fk(
        self, side: _Side, pose: _Array, qs: _Array, *, errors: Literal["raise"] = "raise"
    ) -> _F64:
        """Instrument FK: pose (mm, rad), qs (rad, rad, mm) -> tip (mm, fixed frame)."""
    @overload
    def instrument_fk(
        self, side: _Side, pose: _Array, qs: _Array, *, errors: Literal["nan"]
    ) -> Tuple[_F64, Union[_Mask, bool]]: ...
    @overload
    def instrument_rates(
        self,
        side: _Side,
        pose: _Array,
        pose_rate: _Array,
        pose_acc: _Array,
        tip: _Array,
        tip_rate: Optional[_Array] = None,
        tip_acc: Optional[_Array] = None,
        *,
        mode: _Mode = "A",
        errors: Literal["raise"] = "raise",
    ) -> Tuple[_F64, _F64, _F64]:
        """Instrument joints, rates, accelerations (rad, rad/s, rad/s^2; mm,
        mm/s, mm/s^2) from the pose (mm, rad), its rate (mm/s, rad/s) and
        acceleration (mm/s^2, rad/s^2), and the tip's (mm, mm/s, mm/s^2)."""
    @overload
    def instrument_rates(
        self,
        side: _Side,
        pose: _Array,
        pose_rate: _Array,
        pose_acc: _Array,
        tip: _Array,
        tip_rate: Optional[_Array] = None,
        tip_acc: Optional[_Array] = None,
        *,
        mode: _Mode = "A",
        errors: Literal["nan"],
    ) -> Tuple[_F64, _F64, _F64, Union[_Mask, bool]]: ...
    @overload
    def module1_ik(self, pose: _Array, *, errors: Literal["raise"] = "raise") -> _F64:
        """Module 1 IK: pose (mm, rad) -> actuators q1..q6 (mm)."""
    @overload
    def module1_ik(
        self, pose: _Array, *, errors: Literal["nan"]
    ) -> Tuple[_F64, Union[_Mask, bool]]: ...
    @overload
    def module1_fk(
        self, q: _Array, guess: _Array, *, errors: Literal["raise"] = "raise"
    ) -> _F64:
        """Module 1 FK (Newton from guess): actuators (mm) -> pose (mm, rad)."""
    @overload
    def module1_fk(
        self, q: _Array, guess: _Array, *, errors: Literal["nan"]
    ) -> Tuple[_F64, Union[_Mask, bool]]: ...
    @overload
    def module1_rates(
        self,
        pose: _Array,
        pose_rate: _Array,
        pose_acc: _Array,
        *,
        errors: Literal["raise"] = "raise",
    ) -> Tuple[_F64, _F64, _F64]:
        """Module 1 actuators, rates, accelerations (mm, mm/s, mm/s^2)."""
    @overload
    def module1_rates(
        self,
        pose: _Array,
        pose_rate: _Array,
        pose_acc: _Array,
        *,
        errors: Literal["nan"],
    ) -> Tuple[_F64, _F64, _F64, Union[_Mask, bool]]: ...
    def platform_ik(self, pose: _Array, *, errors: Literal["raise", "nan"] = "raise") -> Any:
        """Deprecated alias of module1_ik (a DeprecationWarning)."""
    def platform_fk(
        self, q: _Array, guess: _Array, *, errors: Literal["raise", "nan"] = "raise"
    ) -> Any:
        """Deprecated alias of module1_fk (a DeprecationWarning)."""
    def platform_rates(
        self,
        pose: _Array,
        pose_rate: _Array,
        pose_acc: _Array,
        *,
        errors: Literal["raise", "nan"] = "raise",
    ) -> Any:
        """Deprecated alias of module1_rates (a DeprecationWarning)."""

def teleop(
    input: _Path,
    *,
    rate_hz: Optional[float] = None,
    pose_mm_deg: Optional[Sequence[float]] = None,
    tip_left_mm: Optional[Sequence[float]] = None,
    tip_right_mm: Optional[Sequence[float]] = None,
    robot: Union[_Path, Robot, None] = None,
    settle_s: Optional[float] = None,
    out: Optional[_Path] = None,
    format: Optional[Literal["csv", "mcap"]] = None,
) -> Dict[str, npt.NDArray[Any]]:
    """``parasils teleop --input`` from the simulation library: the recorded
    session ``input`` (CSV: t_s, device, tx, ty, tz, rx, ry, rz, buttons,
    command) replayed at ``rate_hz`` (default 1000) until its last row plus
    ``settle_s`` (default 1 s). Returns the CLI's CSV table as NumPy columns:
    simulate's columns, then the tips (mm, fixed frame), each device's axes
    and buttons as held, and the codes ``teleop_command``, ``teleop_state``,
    ``teleop_hold``, ``teleop_fault``, ``left_hand_module``,
    ``right_hand_module`` (int64). ``out`` writes CSV or MCAP as well."""
    ...

def simulate(
    *,
    psi_deg: Optional[float] = None,
    theta_deg: Optional[float] = None,
    absolute: Optional[bool] = None,
    omega_max_deg_s: Optional[float] = None,
    eps_max_deg_s2: Optional[float] = None,
    sync: Optional[Literal["phase", "time", "none"]] = None,
    rate_hz: Optional[float] = None,
    pose_mm_deg: Optional[Sequence[float]] = None,
    tip_left_mm: Optional[Sequence[float]] = None,
    tip_right_mm: Optional[Sequence[float]] = None,
    robot: Union[_Path, Robot, None] = None,
    out: Optional[_Path] = None,
    format: Optional[Literal["csv", "mcap"]] = None,
    retarget: Optional[Sequence[Tuple[float, float, float]]] = None,
    stop_at_s: Optional[float] = None,
    pose: Optional[Sequence[float]] = None,
    force: bool = False,
    procedure: Union[_Path, Dict[str, Any], None] = None,
    timing: Optional[Literal["trapezoid", "optimal"]] = None,
    tip_load_left_n: Optional[Sequence[float]] = None,
    tip_load_right_n: Optional[Sequence[float]] = None,
    look_at: Union[Sequence[float], Literal["tips", "left", "right"], None] = None,
    anatomy: Optional[_Path] = None,
) -> Dict[str, npt.NDArray[Any]]:
    """``parasils simulate`` from the simulation library: the CSV table as
    NumPy columns keyed by COLUMNS (float64). ``pose_mm_deg`` is (x, y, z mm,
    psi, theta, phi deg) like the CLI's ``--pose``; ``pose`` is its deprecated
    name (a DeprecationWarning). ``retarget`` is a sequence of (t_s, psi_deg,
    theta_deg) goals commanded while the platform moves (``--retarget``),
    ``stop_at_s`` a controlled stop's time, s (``--stop-at``); a run with
    either has one more column, ``command`` (int64, the index of the active
    command). ``tip_load_left_n``, ``tip_load_right_n``: the force each tip
    exerts, (fx, fy, fz) N, fixed frame (``--tip-load-left``,
    ``--tip-load-right``); with either, fourteen more columns, last: every
    actuator's force (``q1_force_n`` .. ``q6_force_n``, N;
    ``left_qs1_torque_nmm``, ``left_qs2_torque_nmm``, N mm;
    ``left_qs3_force_n``, N; the same for the right) and each tip's
    deflection (``left_tip_deflection_mm``, ``right_tip_deflection_mm``);
    a robot whose file has a ``[dynamics]`` table gives the same columns
    without a load, with its body's weight and inertia.
    ``look_at``: a point [x, y, z] mm or ``"tips"``, ``"left"``,
    ``"right"`` for the camera to look at instead of the angles
    (``--look-at``). Every table has the camera's columns (``left_tip_u`` ..
    ``camera_roll_deg``).
    ``anatomy``: a path to an anatomy file of forbidden regions
    (``--anatomy``); the table then ends with ``no_go_clearance_mm``. ``out`` is checked before writing: OSError (ENOSPC) above the
    free space, ValueError above the 10 GB cap unless ``force=True``. The
    defaults are the paper's scenario.

    ``procedure`` runs a procedure instead (``--procedure``): a path to a
    procedure file (TOML) or a dict of the same structure, which gives the
    start, the robot and the motions (only ``rate_hz``, ``out``, ``format``
    and ``force`` may be given with it). The whole procedure is checked
    before anything is returned or written; a failure raises the error of
    the kinematics naming the motion (index from 0, type, name) and the time
    inside it. Its table has twelve more columns: ``motion`` and
    ``motion_type`` (int64), ``endoscope_depth_mm`` and the three tips
    ``left_tip_x_mm`` .. ``endoscope_tip_z_mm``."""

def calibrate(
    robot: Robot,
    q: npt.ArrayLike,
    poses: npt.ArrayLike,
    sigma: Optional[npt.ArrayLike] = None,
) -> Tuple[Robot, Dict[str, Any]]:
    """Fit module 1's geometry to actuator readings ``q`` (N, 6) mm at
    measured poses ``poses`` (N, 6) mm and rad; ``sigma``: the standard
    deviations (readings mm, position mm, angles rad), three numbers or
    (N, 3), or None for equal weights. Returns the fitted Robot and the
    report as a dict; raises ValueError naming the row or the problem."""

_ToleranceResult = Dict[str, Any]

class ToleranceStudy:
    """A tolerance study: robots drawn within a tolerance specification,
    each driven along a motion by the nominal model's commands. Pickles
    (its inputs as text) to Dask or Ray workers, with the same rows, bit
    for bit."""

    def __init__(
        self,
        spec: Union[_Path, Dict[str, Any], None],
        *,
        seed: int = 0,
        procedure: Union[_Path, Dict[str, Any], None] = None,
        rate_hz: float = 100.0,
        robot: Union[_Path, Robot, None] = None,
    ) -> None:
        """spec: a specification file's path (TOML), a dict of the same
        structure or None (the default tolerances); the motion: the paper's
        reorientation or ``procedure``, sampled at ``rate_hz`` (Hz); the
        nominal robot: ``robot`` or the paper's. ValueError for a bad
        specification."""
    def run(self, start: int, count: int, *, threads: Optional[int] = None) -> _ToleranceResult:
        """Samples start .. start + count - 1 without the GIL: "sample"
        (uint64), "left_tip_dev_mm", "right_tip_dev_mm",
        "pose_position_err_mm" (mm), "pose_rotation_err_deg" (deg) (float64,
        NaN where failed), "failed" (bool) and "failures", a list of
        (sample, message)."""
    def run_indices(
        self, indices: npt.ArrayLike, *, threads: Optional[int] = None
    ) -> _ToleranceResult:
        """The samples listed in ``indices`` (1-D integers >= 0, read-only
        arrays accepted), as run() does a range, in that order."""
    def sensitivity(self) -> List[Dict[str, Any]]:
        """Each perturbed family's share of the mean-square tip deviation,
        to first order (analytic derivatives), largest first: dicts with
        "family", "share" (0 to 1) and "rms_tip_mm" (mm)."""
    @property
    def n_motion_samples(self) -> int:
        """The number of samples of the motion at rate_hz."""
    @property
    def seed(self) -> int:
        """The seed: sample i's robot depends only on it and on i."""
    @property
    def rate_hz(self) -> float:
        """The motion's sampling rate, Hz."""
    @property
    def spec(self) -> str:
        """The specification as TOML."""
    @staticmethod
    def _from_state(
        version: str,
        spec: str,
        seed: int,
        rate_hz: float,
        robot: Optional[str],
        procedure: Optional[Tuple[str, ...]],
    ) -> "ToleranceStudy": ...

def tolerance(
    spec: Union[_Path, Dict[str, Any], None],
    n: int,
    *,
    seed: int = 0,
    procedure: Union[_Path, Dict[str, Any], None] = None,
    rate_hz: float = 100.0,
    chunks: Optional[int] = None,
    client: Any = None,
    robot: Union[_Path, Robot, None] = None,
) -> _ToleranceResult:
    """A tolerance study of ``n`` perturbed robots (samples 0 to n - 1):
    the columns of ToleranceStudy.run, in sample order. With ``client`` (a
    ``dask.distributed.Client``), chunks of ``chunks`` samples mapped over
    its workers, one thread each unless their PARASILS_NUM_THREADS says
    otherwise; the same rows, bit for bit."""

def segment_distance_mm(
    a0: _Array,
    a1: _Array,
    b0: _Array,
    b1: _Array,
    *,
    errors: Literal["raise", "nan"] = "raise",
) -> Any:
    """The closest points of the segments a0-a1 and b0-b1 (mm, each end of
    shape (3,) or (N, 3)) and their distance: (distance, point_a, point_b),
    distance a float or shape (N,), the points (3,) or (N, 3); with
    errors="nan" a mask last. Exact for parallel, near-parallel and
    zero-length segments, never NaN (NonFiniteError for non-finite input)."""

def batch_threads() -> int:
    """The number of threads a batch of 4096 rows or more runs on:
    PARASILS_NUM_THREADS (a positive integer) when set, else the CPUs this
    process may use. Results do not depend on it."""

class KinematicsError(ValueError):
    """A kinematics solver failed. Values in mm and rad."""

    kind: str
    row: Optional[int]
    t: Optional[float]

class NonFiniteError(KinematicsError):
    what: str
    value: float

class InvalidParameterError(KinematicsError):
    what: str
    value: float

class OutOfReachError(KinematicsError):
    side: _Side
    sin_qs2: float

class SingularError(KinematicsError):
    side: _Side
    margin: Literal["cos_qs2", "qs3"]
    value: float
    threshold: float

class JointLimitError(KinematicsError):
    side: _Side
    joint: Literal["qs1", "qs2", "qs3"]
    value: float
    min: float
    max: float
    limit: float

class LegOutOfReachError(KinematicsError):
    actuator: int
    discriminant: float

class ActuatorLimitError(KinematicsError):
    actuator: int
    value: float
    min: float
    max: float
    limit: float

class SerialSingularError(KinematicsError):
    actuator: int
    margin: float
    threshold: float

class ParallelSingularError(KinematicsError):
    margin: float
    threshold: float

class NoConvergenceError(KinematicsError):
    iterations: int
    residual: float

class SingularJacobianError(KinematicsError):
    singularity: Literal["parallel", "euler_angles"]
    iteration: int
    margin: float
    threshold: float

class BranchMismatchError(KinematicsError):
    actuator: int

class TrajectoryError(ValueError):
    kind: str
    axis: Optional[int]
    value: Optional[float]

class RobotFileError(ValueError):
    kind: Literal["parse", "invalid"]
    path: str
    line: Optional[int]
    column: Optional[int]
    key: Optional[str]
    text: Optional[str]

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
    "segment_distance_mm",
    "simulate",
]
