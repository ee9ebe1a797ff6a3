//! `parasils.Robot`: the whole robot's geometry and its solvers on arrays.

use std::path::PathBuf;

use parasils_kin::nalgebra::Vector3;
use parasils_kin::{
    Actuators, AssemblyMode, Controller, Instrument, Joints, PlatformState, Pose, PoseRate,
    RobotGeometry, TipMotion,
};
use parasils_sim::robot_file;
use pyo3::exceptions::{PyDeprecationWarning, PyValueError};
use pyo3::prelude::*;

use crate::batch::{self, ArrayArg, OnError, Rows};
use crate::errors;
use crate::kernels;

/// The PARA-SILSROB robot: module 1 (the 6-DOF parallel robot) and the two
/// spherical instrument modules, with their limits and thresholds.
///
/// Robot() is the paper's robot: instrument modules alpha = beta = 10 deg,
/// R = 110 mm, ports at (-10, 0, 0) and (10, 0, 0) mm, on module 1's
/// ASSUMED geometry (its real dimensions are not published). Robot.from_toml
/// reads another geometry from a robot file (see `parasils robot`).
///
/// Units everywhere: mm, rad, s. A platform pose is (x, y, z, psi, theta, phi):
/// the position of P (the endoscope's RCM) in the fixed frame in mm, then the
/// intrinsic X-Y-Z Euler angles in rad, R = R_X(psi) R_Y(theta) R_Z(phi).
/// Instrument joints are (qs1, qs2, qs3): rad, rad, mm (qs3 = RCM to tip).
/// Module 1's actuators are (q1, ..., q6), mm.
///
/// Every method takes one sample (pose of shape (6,), tip of shape (3,), ...)
/// or a batch ((N, 6), (N, 3), ...) and returns the same leading shape; a
/// single row goes with every row of a batch. Batches run in Rust without
/// the GIL, on parasils.batch_threads() threads from 4096 rows (the
/// environment variable PARASILS_NUM_THREADS sets it), with the same result
/// to the bit whatever the number of threads. errors="raise" (default)
/// raises the first failing row's KinematicsError (its .row is the index);
/// errors="nan" returns NaN rows and appends a boolean mask (True where the
/// row succeeded) to the result.
#[pyclass(frozen, module = "parasils")]
#[derive(Debug)]
pub struct Robot {
    /// The robot file's whole content: geometry and supervisor thresholds.
    model: parasils_sim::Robot,
    controller: Controller<f64>,
    source: Option<PathBuf>,
}

impl Robot {
    /// The geometry, as given (not normalised).
    pub(crate) fn geometry(&self) -> &RobotGeometry<f64> {
        &self.model.geometry
    }

    /// The geometry and the supervisor thresholds, as the robot file gave
    /// them: what `simulate(robot=...)` and the other runs use.
    pub(crate) fn model(&self) -> &parasils_sim::Robot {
        &self.model
    }

    /// The robot of a geometry (validated here), read from no file.
    pub(crate) fn from_geometry(py: Python<'_>, geometry: RobotGeometry<f64>) -> PyResult<Self> {
        Self::from_model(py, parasils_sim::Robot::from(geometry), None)
    }

    /// The robot of a robot file's content (its geometry validated here).
    fn from_model(
        py: Python<'_>,
        model: parasils_sim::Robot,
        source: Option<PathBuf>,
    ) -> PyResult<Self> {
        let controller = Controller::from_geometry(&model.geometry)
            .map_err(|e| errors::kinematics(py, &e, None, None, ""))?;
        Ok(Self {
            model,
            controller,
            source,
        })
    }

    fn instrument(&self, side: &str) -> PyResult<&Instrument<f64>> {
        match side {
            "left" => Ok(&self.controller.left),
            "right" => Ok(&self.controller.right),
            _ => Err(PyValueError::new_err(format!(
                "side must be 'left' or 'right', got {side:?}"
            ))),
        }
    }
}

fn parse_mode(mode: &str) -> PyResult<AssemblyMode> {
    match mode {
        "A" => Ok(AssemblyMode::A),
        "B" => Ok(AssemblyMode::B),
        _ => Err(PyValueError::new_err(format!(
            "mode must be 'A' or 'B', got {mode:?}"
        ))),
    }
}

fn pose_of(v: [f64; 6]) -> Pose<f64> {
    Pose::from_array(v)
}

fn rate_of(v: [f64; 6]) -> PoseRate<f64> {
    PoseRate::new(v[0], v[1], v[2], v[3], v[4], v[5])
}

#[pymethods]
impl Robot {
    /// The paper's robot (module 1's geometry assumed).
    #[new]
    fn new() -> Self {
        Self {
            model: parasils_sim::Robot::paper(),
            controller: Controller::paper(),
            source: None,
        }
    }

    /// Robot.from_toml(path) -> Robot
    ///
    /// The robot described by a robot file (TOML, the format `parasils robot`
    /// prints; angles in deg, lengths in mm), validated.
    ///
    /// Raises OSError (FileNotFoundError, ...) when the file cannot be read,
    /// RobotFileError for malformed TOML or a bad key or value (with .line,
    /// .column, .key), or for parameters that do not make a valid robot (the
    /// KinematicsError naming the parameter is its __cause__).
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let model = robot_file::load_robot(&path).map_err(|e| errors::robot_file(py, &e))?;
        Self::from_model(py, model, Some(path))
    }

    /// Robot.from_toml_str(text) -> Robot
    ///
    /// The robot described by a robot file's text (TOML, as to_toml()
    /// writes it; angles in deg, lengths in mm), validated: what a pickled
    /// Robot is built from again.
    ///
    /// Raises RobotFileError for malformed TOML or a bad key or value, or
    /// for parameters that do not make a valid robot.
    #[staticmethod]
    fn from_toml_str(py: Python<'_>, text: &str) -> PyResult<Self> {
        let model = robot_file::parse_robot(text).map_err(|e| errors::robot_file(py, &e))?;
        Self::from_model(py, model, None)
    }

    /// A Robot pickles as its robot file's text (to_toml()), which reads
    /// back to the same geometry, bit for bit, and the same supervisor
    /// thresholds.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let py = slf.py();
        let text = slf.get().to_toml()?;
        let constructor = slf.get_type().getattr("from_toml_str")?;
        pyo3::types::PyTuple::new(
            py,
            [
                constructor,
                pyo3::types::PyTuple::new(py, [text])?.into_any(),
            ],
        )
    }

    /// The robot as a robot file (TOML; angles in deg, lengths in mm): its
    /// geometry, and its [supervisor] table when the robot file it was read
    /// from had one.
    fn to_toml(&self) -> PyResult<String> {
        robot_file::robot_to_toml_string(&self.model)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The margin supervisor's thresholds the robot file set in its
    /// [supervisor] table, keyed as the file names them (cos_qs2_warn,
    /// qs3_stop_mm, joint_limit_warn_deg, ...; in the file's units); the
    /// ones not given are absent (they keep their defaults). simulate(),
    /// tolerance studies and every run on this Robot use them.
    #[getter]
    fn supervisor<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let dict = pyo3::types::PyDict::new(py);
        for (key, value) in self.model.supervisor.given() {
            dict.set_item(key, value)?;
        }
        Ok(dict)
    }

    /// True when module 1's geometry is assumed (the default: the real robot's
    /// dimensions are not published), False for a robot file that says
    /// `assumed = false`.
    #[getter]
    fn module1_assumed(&self) -> bool {
        self.model.geometry.module1.assumed
    }

    /// Where module 1's geometry comes from, as every output labels it:
    /// "assumed geometry (not the real robot's)", "calibrated (RMS ... mm
    /// over N poses)" for a calibrated robot file, or "measured".
    #[getter]
    fn module1_provenance(&self) -> String {
        self.model.geometry.module1.provenance().to_string()
    }

    /// The reach map: which camera orientations the platform can take from
    /// `pose` with both tips held still (motion type 4: `P` and `phi`
    /// fixed), over a grid of (dpsi, dtheta) increments, each checked by the
    /// per-cycle controller's own call (the same as `simulate`, both
    /// instrument modules in mode A).
    ///
    /// pose: the start pose (x, y, z mm, psi, theta, phi rad), shape (6,).
    /// tips: the left and right tips held still, mm, fixed frame, shape
    /// (2, 3); default the paper's left tip and the default right tip.
    /// psi_range_deg, theta_range_deg: (min, max) of the increments, deg,
    /// as `parasils reach --psi-range`; each must contain 0. step_deg: the
    /// grid step, deg (cells at whole multiples of it). line: whether to
    /// check the straight reorientation to each cell.
    /// Deprecated: psi_range, theta_range, step, the same in rad (a
    /// DeprecationWarning; removed in the next release).
    ///
    /// Returns a dict: "dpsi" (C,) and "dtheta" (R,) rad; "feasible",
    /// "reachable", "line" (bool, (R, C); "line" None without it);
    /// "limiting" (int, (R, C), an index into "codes", the constraint codes
    /// such as "left.qs2.limit", "codes"[0] == "ok"); "margin" (float,
    /// (R, C), the normalised margin: positive feasible, negative
    /// infeasible); "boundary_points" (K, 2) rad, refined to 1e-6 rad, with
    /// "boundary_limiting" (K,) their constraint just outside; "boundary", a
    /// list of index arrays into "boundary_points", one per polyline (a
    /// closed one repeats its first point); "module1_assumed".
    /// anatomy: an anatomy file of forbidden regions (as `parasils reach
    /// --anatomy`): a cell where the in-body part of a shaft or of the
    /// endoscope comes closer to a region than the clearance stop threshold
    /// (0.5 mm unless this robot's file gives one) is limited by
    /// "no_go.<region name>", one code per region after the others.
    /// deflection_load_n: the stiffness measure (as `parasils reach
    /// --deflection-load`): the force each tip exerts on the tissue, N,
    /// fixed frame, shape (3,); the dict then has "left_tip_deflection_mm"
    /// and "right_tip_deflection_mm" (float, (R, C), NaN on an infeasible
    /// cell): how far each tip gives way pressing with it, the other
    /// unloaded, with this robot's actuator stiffnesses (its robot file's
    /// [stiffness], assumed by default).
    ///
    /// Raises ValueError for a bad grid, deflection load or anatomy file, OSError for an
    /// anatomy file that does not read, KinematicsError for a bad robot or
    /// a non-finite pose or tip.
    #[pyo3(signature = (pose, tips = None, psi_range = None, theta_range = None, step = None, *, psi_range_deg = (-45.0, 45.0), theta_range_deg = (-45.0, 45.0), step_deg = 0.5, line = true, anatomy = None, deflection_load_n = None))]
    #[allow(clippy::too_many_arguments)]
    fn reach_map<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        tips: Option<ArrayArg<'py>>,
        psi_range: Option<(f64, f64)>,
        theta_range: Option<(f64, f64)>,
        step: Option<f64>,
        psi_range_deg: (f64, f64),
        theta_range_deg: (f64, f64),
        step_deg: f64,
        line: bool,
        anatomy: Option<std::path::PathBuf>,
        deflection_load_n: Option<[f64; 3]>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let grid = crate::reach::Grid::of(
            py,
            (psi_range, theta_range, step),
            (psi_range_deg, theta_range_deg, step_deg),
        )?;
        crate::reach::reach_map(
            py,
            self.model(),
            pose,
            tips,
            grid,
            (line, deflection_load_n),
            anatomy.as_deref(),
        )
    }

    /// Motion type 4 as a path: from `pose`, psi and theta turn by `dpsi`
    /// and `dtheta` (rad) along a straight line, s from 0 to 1, both tips
    /// held. Returns, at each s, the twelve actuators (q1..q6 mm, left
    /// qs1, qs2 rad, qs3 mm, right qs1, qs2 rad, qs3 mm) for order 0, their
    /// first derivatives in s for order 1, their second for order 2: shape
    /// (len(s), 12), exact (the closed-form rates), to feed other tools.
    ///
    /// pose: the start pose (x, y, z mm, psi, theta, phi rad), shape (6,).
    /// tips: (2, 3) mm, the left tip then the right one; None: the paper's
    ///     left tip and the default right tip at `pose` (the mirror image
    ///     moved 35 mm along X' and 100 mm along Y').
    ///
    /// Raises KinematicsError (subclass) where the path leaves the workspace.
    #[pyo3(signature = (pose, tips, dpsi, dtheta, s, order = 0))]
    #[allow(clippy::too_many_arguments)]
    fn reorientation_path<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        tips: Option<ArrayArg<'py>>,
        dpsi: f64,
        dtheta: f64,
        s: ArrayArg<'py>,
        order: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        crate::path::reorientation_path(py, &self.controller, pose, tips, dpsi, dtheta, s, order)
    }

    /// The fastest rest-to-rest timing of reorientation_path's turn within
    /// the actuators' limits (velocity_max, acceleration_max: shape (12,),
    /// mm/s or rad/s, mm/s^2 or rad/s^2, in reorientation_path's order;
    /// None: this robot's own, from its robot file or the assumed defaults) and, when given, each Euler angle's
    /// omega_max_deg_s (deg/s) and eps_max_deg_s2 (deg/s^2), as `parasils
    /// simulate --omega-max --eps-max`. knots: grid points on s; checks:
    /// check points per grid interval.
    /// Deprecated: omega_max (rad/s) and eps_max (rad/s^2) (a
    /// DeprecationWarning; removed in the next release).
    ///
    /// Returns a dict: "duration_s"; "phases", a list of dicts ("start_s",
    /// "end_s", "binding" such as "module 1 q6", "limit" ("velocity" or
    /// "acceleration"), "usage"); the schedule at the knots: "s", "t_s",
    /// "s_dot" (1/s), "s_ddot" (1/s^2, on the interval starting there);
    /// "worst_before_check", "passes", "stretch" (the check between knots).
    #[pyo3(signature = (pose, tips, dpsi, dtheta, *, velocity_max = None, acceleration_max = None, omega_max_deg_s = None, eps_max_deg_s2 = None, knots = 1000, checks = 10, omega_max = None, eps_max = None))]
    #[allow(clippy::too_many_arguments)]
    fn optimal_reorientation<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        tips: Option<ArrayArg<'py>>,
        dpsi: f64,
        dtheta: f64,
        velocity_max: Option<ArrayArg<'py>>,
        acceleration_max: Option<ArrayArg<'py>>,
        omega_max_deg_s: Option<f64>,
        eps_max_deg_s2: Option<f64>,
        knots: usize,
        checks: usize,
        omega_max: Option<f64>,
        eps_max: Option<f64>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        // In the library's rad/s and rad/s^2.
        let method = "Robot.optimal_reorientation";
        let omega_max = crate::errors::renamed_argument(
            py,
            method,
            ("omega_max", omega_max.map(Some)),
            (
                "omega_max_deg_s",
                omega_max_deg_s.map(f64::to_radians),
                None,
            ),
        )?;
        let eps_max = crate::errors::renamed_argument(
            py,
            method,
            ("eps_max", eps_max.map(Some)),
            ("eps_max_deg_s2", eps_max_deg_s2.map(f64::to_radians), None),
        )?;
        crate::path::optimal_reorientation(
            py,
            &self.controller,
            pose,
            tips,
            dpsi,
            dtheta,
            velocity_max,
            acceleration_max,
            omega_max,
            eps_max,
            knots,
            checks,
        )
    }

    fn __repr__(&self) -> String {
        match &self.source {
            None => "parasils.Robot()".to_owned(),
            Some(p) => format!("parasils.Robot.from_toml({:?})", p.display().to_string()),
        }
    }

    /// Inverse kinematics of an instrument module, in closed form: the joints
    /// that put its tip at `tip` with the platform at `pose`.
    ///
    /// side: "left" or "right".
    /// pose: platform pose (x, y, z mm, psi, theta, phi rad), shape (6,) or (N, 6).
    /// tip: the tip in the fixed frame, mm, shape (3,) or (N, 3).
    /// mode: assembly mode "A" (cos qs2 > 0, the default) or "B" (cos qs2 < 0).
    /// errors: "raise" or "nan" (then returns (qs, ok)).
    ///
    /// Returns qs = (qs1 rad, qs2 rad, qs3 mm), shape (3,) or (N, 3); qs1 and
    /// qs2 in (-pi, pi].
    ///
    /// Raises NonFiniteError, OutOfReachError, SingularError (tip at the RCM,
    /// or |cos qs2| < 1e-6), JointLimitError (limits are checked).
    ///
    /// Rows are solved several at a time in SIMD lanes (8 with AVX-512, 4
    /// with AVX2, 2 otherwise, chosen for the CPU; the environment variable
    /// PARASILS_BATCH_KERNEL = scalar, baseline, avx2 or avx512 forces one,
    /// ValueError if the CPU lacks it): qs3 has the scalar solver's bits,
    /// qs1 and qs2 are within 3 ulps of them, and a row that could fail is
    /// solved by the scalar solver, so errors are the same.
    #[pyo3(signature = (side, pose, tip, *, mode = "A", errors = "raise"))]
    fn instrument_ik<'py>(
        &self,
        py: Python<'py>,
        side: &str,
        pose: ArrayArg<'py>,
        tip: ArrayArg<'py>,
        mode: &str,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = self.instrument(side)?;
        let mode = parse_mode(mode)?;
        let on_error = OnError::parse(errors)?;
        let pose = Rows::new(&pose, "pose", 6)?;
        let tip = Rows::new(&tip, "tip", 3)?;
        let n = batch::batch_size(&[("pose", &pose), ("tip", &tip)])?;
        let kernel = kernels::instrument_ik(m, mode)?;
        batch::solve_chunks(py, n, on_error, &[3], |chunk| {
            kernels::ik_chunk(&kernel, &pose, &tip, on_error, chunk)
        })
    }

    /// Forward kinematics of an instrument module: the tip in the fixed
    /// frame, p_F = R (RCM + p_local(qs)) + P.
    ///
    /// side: "left" or "right".
    /// pose: platform pose (x, y, z mm, psi, theta, phi rad), shape (6,) or (N, 6).
    /// qs: joints (qs1 rad, qs2 rad, qs3 mm), shape (3,) or (N, 3); not
    ///     checked against the joint limits.
    /// errors: "raise" or "nan" (then returns (tip, ok)).
    ///
    /// Returns the tip, mm, fixed frame, shape (3,) or (N, 3).
    ///
    /// Raises NonFiniteError only.
    #[pyo3(signature = (side, pose, qs, *, errors = "raise"))]
    fn instrument_fk<'py>(
        &self,
        py: Python<'py>,
        side: &str,
        pose: ArrayArg<'py>,
        qs: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = self.instrument(side)?;
        let on_error = OnError::parse(errors)?;
        let pose = Rows::new(&pose, "pose", 6)?;
        let qs = Rows::new(&qs, "qs", 3)?;
        let n = batch::batch_size(&[("pose", &pose), ("qs", &qs)])?;
        batch::solve::<3, _>(py, n, on_error, &[3], |i| {
            let [a, b, c] = qs.get::<3>(i);
            let tip = m.fk(&pose_of(pose.get(i)), &Joints::new(a, b, c))?;
            Ok([tip.x, tip.y, tip.z])
        })
    }

    /// An instrument module's joints, joint velocities and joint accelerations
    /// from the platform's motion and the tip's (the general case; see
    /// docs/model.md, "Instrument modules"), with c = RCM + p_local(qs) in
    /// the platform frame:
    ///
    ///     qs_dot  = J^-1 R^T (p_F' - P' - R' c)
    ///     qs_ddot = J^-1 (R^T (p_F'' - P'' - R'' c - 2 R' J qs_dot) - J' qs_dot)
    ///
    /// Motion type 4 (endoscope reorientation) is tip_rate = tip_acc = 0 with
    /// P and phi still; motion type 3 (instrument manipulation) is
    /// pose_rate = pose_acc = 0.
    ///
    /// side: "left" or "right".
    /// pose: platform pose (x, y, z mm, psi, theta, phi rad), shape (6,) or (N, 6).
    /// pose_rate: its time derivative (mm/s, and the Euler rates in rad/s),
    ///     shape (6,) or (N, 6).
    /// pose_acc: its second derivative (mm/s^2, rad/s^2), shape (6,) or (N, 6).
    /// tip: the tip in the fixed frame, mm, shape (3,) or (N, 3).
    /// tip_rate: the tip's velocity, mm/s, fixed frame; None for a still tip.
    /// tip_acc: the tip's acceleration, mm/s^2, fixed frame; None for zero.
    /// mode: assembly mode "A" (default) or "B".
    /// errors: "raise" or "nan" (then returns (qs, qs_dot, qs_ddot, ok)).
    ///
    /// Returns qs (rad, rad, mm), qs_dot (rad/s, rad/s, mm/s) and qs_ddot
    /// (rad/s^2, rad/s^2, mm/s^2), each of shape (3,) or (N, 3).
    ///
    /// Raises as instrument_ik (the joints are solved first, limits checked).
    #[pyo3(signature = (side, pose, pose_rate, pose_acc, tip, tip_rate = None, tip_acc = None, *, mode = "A", errors = "raise"))]
    #[allow(clippy::too_many_arguments)]
    fn instrument_rates<'py>(
        &self,
        py: Python<'py>,
        side: &str,
        pose: ArrayArg<'py>,
        pose_rate: ArrayArg<'py>,
        pose_acc: ArrayArg<'py>,
        tip: ArrayArg<'py>,
        tip_rate: Option<ArrayArg<'py>>,
        tip_acc: Option<ArrayArg<'py>>,
        mode: &str,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = self.instrument(side)?;
        let mode = parse_mode(mode)?;
        let on_error = OnError::parse(errors)?;
        let pose = Rows::new(&pose, "pose", 6)?;
        let pose_rate = Rows::new(&pose_rate, "pose_rate", 6)?;
        let pose_acc = Rows::new(&pose_acc, "pose_acc", 6)?;
        let tip = Rows::new(&tip, "tip", 3)?;
        let tip_rate = match &tip_rate {
            Some(a) => Rows::new(a, "tip_rate", 3)?,
            None => Rows::zeros(3),
        };
        let tip_acc = match &tip_acc {
            Some(a) => Rows::new(a, "tip_acc", 3)?,
            None => Rows::zeros(3),
        };
        let n = batch::batch_size(&[
            ("pose", &pose),
            ("pose_rate", &pose_rate),
            ("pose_acc", &pose_acc),
            ("tip", &tip),
            ("tip_rate", &tip_rate),
            ("tip_acc", &tip_acc),
        ])?;
        // The joints by the vector kernel, as `instrument_ik` gives them;
        // the rates by the scalar solver (see `kernels::rates_chunk`).
        let kernel = kernels::instrument_ik(m, mode)?;
        batch::solve_chunks(py, n, on_error, &[3, 3, 3], |chunk| {
            kernels::rates_chunk(&kernel, &pose, &tip, on_error, chunk, |i| {
                let state = PlatformState {
                    pose: pose_of(pose.get(i)),
                    velocity: rate_of(pose_rate.get(i)),
                    acceleration: rate_of(pose_acc.get(i)),
                };
                let motion = TipMotion {
                    position: Vector3::from(tip.get::<3>(i)),
                    velocity: Vector3::from(tip_rate.get::<3>(i)),
                    acceleration: Vector3::from(tip_acc.get::<3>(i)),
                };
                m.solve_state(&state, &motion, mode)
            })
        })
    }

    /// Inverse kinematics of module 1, in closed form: the actuators that put
    /// the platform at `pose`.
    ///
    /// pose: platform pose (x, y, z mm, psi, theta, phi rad), shape (6,) or (N, 6).
    /// errors: "raise" or "nan" (then returns (q, ok)).
    ///
    /// Returns q = (q1, ..., q6), mm, shape (6,) or (N, 6).
    ///
    /// Raises NonFiniteError, LegOutOfReachError, SerialSingularError,
    /// ActuatorLimitError (strokes are checked).
    ///
    /// Rows are solved several at a time in SIMD lanes (as instrument_ik),
    /// to the scalar solver's bits; a row that could fail is solved by the
    /// scalar solver, so errors are the same.
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn module1_ik<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let on_error = OnError::parse(errors)?;
        let pose = Rows::new(&pose, "pose", 6)?;
        let n = batch::batch_size(&[("pose", &pose)])?;
        // Module 1's kernel in lanes: the scalar solver's bits.
        let kernel = kernels::module1_ik(&self.controller.module1)?;
        batch::solve_chunks(py, n, on_error, &[6], |chunk| {
            kernels::module1_chunk(&kernel, &pose, on_error, chunk)
        })
    }

    /// Forward kinematics of module 1: the platform pose at which the
    /// actuators `q` hold it, by Newton's method from `guess` (which picks the
    /// assembly mode: seed it with the previous pose along a motion).
    ///
    /// q: actuators (q1, ..., q6), mm, shape (6,) or (N, 6); strokes not checked.
    /// guess: a pose near the solution (x, y, z mm, psi, theta, phi rad),
    ///     shape (6,) or (N, 6).
    /// errors: "raise" or "nan" (then returns (pose, ok)).
    ///
    /// Returns the pose (mm, rad), shape (6,) or (N, 6); the angles are not
    /// wrapped (continuous with the guess).
    ///
    /// Raises NonFiniteError, NoConvergenceError, SingularJacobianError,
    /// BranchMismatchError.
    #[pyo3(signature = (q, guess, *, errors = "raise"))]
    fn module1_fk<'py>(
        &self,
        py: Python<'py>,
        q: ArrayArg<'py>,
        guess: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let on_error = OnError::parse(errors)?;
        let q = Rows::new(&q, "q", 6)?;
        let guess = Rows::new(&guess, "guess", 6)?;
        let n = batch::batch_size(&[("q", &q), ("guess", &guess)])?;
        let robot = &self.controller.module1;
        batch::solve::<6, _>(py, n, on_error, &[6], |i| {
            let sol = robot.fk(&Actuators::new(q.get(i)), &pose_of(guess.get(i)))?;
            Ok(sol.pose.to_array())
        })
    }

    /// Module 1's actuators, their velocities and accelerations from the
    /// platform's motion, in closed form.
    ///
    /// pose: platform pose (x, y, z mm, psi, theta, phi rad), shape (6,) or (N, 6).
    /// pose_rate: its time derivative (mm/s, Euler rates rad/s), shape (6,) or (N, 6).
    /// pose_acc: its second derivative (mm/s^2, rad/s^2), shape (6,) or (N, 6).
    /// errors: "raise" or "nan" (then returns (q, q_dot, q_ddot, ok)).
    ///
    /// Returns q (mm), q_dot (mm/s), q_ddot (mm/s^2), each (6,) or (N, 6).
    ///
    /// Raises as module1_ik.
    #[pyo3(signature = (pose, pose_rate, pose_acc, *, errors = "raise"))]
    fn module1_rates<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        pose_rate: ArrayArg<'py>,
        pose_acc: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let on_error = OnError::parse(errors)?;
        let pose = Rows::new(&pose, "pose", 6)?;
        let pose_rate = Rows::new(&pose_rate, "pose_rate", 6)?;
        let pose_acc = Rows::new(&pose_acc, "pose_acc", 6)?;
        let n = batch::batch_size(&[
            ("pose", &pose),
            ("pose_rate", &pose_rate),
            ("pose_acc", &pose_acc),
        ])?;
        let robot = &self.controller.module1;
        batch::solve::<18, _>(py, n, on_error, &[6, 6, 6], |i| {
            let state = PlatformState {
                pose: pose_of(pose.get(i)),
                velocity: rate_of(pose_rate.get(i)),
                acceleration: rate_of(pose_acc.get(i)),
            };
            let s = robot.solve_state(&state)?;
            let mut out = [0.0; 18];
            out[..6].copy_from_slice(&s.q.to_array());
            out[6..12].copy_from_slice(&s.q_dot.to_array());
            out[12..].copy_from_slice(&s.q_ddot.to_array());
            Ok(out)
        })
    }

    /// Deprecated alias of module1_ik (module 1's inverse kinematics: pose
    /// in mm and rad, shape (6,) or (N, 6), to actuators in mm; errors
    /// "raise" or "nan"). Warns with a DeprecationWarning; removed in the
    /// next release.
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn platform_ik<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        deprecated(py, "platform_ik", "module1_ik")?;
        self.module1_ik(py, pose, errors)
    }

    /// Deprecated alias of module1_fk (module 1's forward kinematics:
    /// actuators in mm and a guess in mm and rad, shape (6,) or (N, 6), to
    /// the pose; errors "raise" or "nan"). Warns with a DeprecationWarning;
    /// removed in the next release.
    #[pyo3(signature = (q, guess, *, errors = "raise"))]
    fn platform_fk<'py>(
        &self,
        py: Python<'py>,
        q: ArrayArg<'py>,
        guess: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        deprecated(py, "platform_fk", "module1_fk")?;
        self.module1_fk(py, q, guess, errors)
    }

    /// Deprecated alias of module1_rates (module 1's actuators, rates and
    /// accelerations: mm, mm/s, mm/s^2 from the pose in mm and rad and its
    /// rate and acceleration, shape (6,) or (N, 6); errors "raise" or
    /// "nan"). Warns with a DeprecationWarning; removed in the next release.
    #[pyo3(signature = (pose, pose_rate, pose_acc, *, errors = "raise"))]
    fn platform_rates<'py>(
        &self,
        py: Python<'py>,
        pose: ArrayArg<'py>,
        pose_rate: ArrayArg<'py>,
        pose_acc: ArrayArg<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        deprecated(py, "platform_rates", "module1_rates")?;
        self.module1_rates(py, pose, pose_rate, pose_acc, errors)
    }
}

/// Warns that `Robot.old` is deprecated in favour of `Robot.new`.
fn deprecated(py: Python<'_>, old: &str, new: &str) -> PyResult<()> {
    let message = std::ffi::CString::new(format!(
        "Robot.{old} is deprecated: use Robot.{new} (module 1 is `module1` in every name); \
         {old} will be removed in the next release"
    ))
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    PyErr::warn(py, &py.get_type::<PyDeprecationWarning>(), &message, 1)
}
