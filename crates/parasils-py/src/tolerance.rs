//! `parasils.ToleranceStudy`: the tolerance library's study (`parasils-tolerance`,
//! the same code as `parasils tolerance`) on NumPy columns, any range or
//! list of its samples at a time, without the GIL.
//!
//! A study is built from its inputs as text (the specification as TOML,
//! the robot as a robot file, the procedure as its file's text and the
//! folder its robot path is relative to), and keeps them: `__reduce__`
//! hands them to `ToleranceStudy._from_state`, which builds the same study
//! again, so that a study pickles to a Dask or Ray worker and gives there
//! the same numbers, bit for bit. Sample `i`'s robot depends only on the
//! seed and `i`, so the rows do not depend on how the samples are split.

use std::path::{Path, PathBuf};

use numpy::{IntoPyArray, PyReadonlyArray1};
use parasils_io::AtTime;
use parasils_sim::{Scenario, SimulationError, procedure, robot_file};
use parasils_tolerance::{Results, Spec, Study, Trace};
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use crate::batch;
use crate::errors;
use crate::robot::Robot;

/// Where a procedure comes from, as text: what a pickle carries.
#[derive(Debug, Clone)]
enum ProcedureSource {
    /// A procedure file's text, its path (naming it in errors) and its
    /// folder, absolute (a robot it names is read relative to it).
    Toml {
        text: String,
        origin: String,
        base: PathBuf,
    },
    /// A dict, as JSON, and the working directory it was given in, absolute.
    Json { text: String, base: PathBuf },
}

/// The inputs of a study, as text: enough to build it again anywhere.
#[derive(Debug, Clone)]
struct Inputs {
    /// The specification as TOML ([`Spec::to_toml`], which reads back to
    /// the same value).
    spec: String,
    seed: u64,
    rate_hz: f64,
    /// The nominal robot as a robot file's text, `None` for the paper's.
    robot: Option<String>,
    procedure: Option<ProcedureSource>,
}

/// The error of a procedure as a Python exception (as `simulate` raises it).
fn procedure_error(py: Python<'_>, e: procedure::ProcedureError) -> PyErr {
    match e {
        procedure::ProcedureError::Robot(e) => errors::robot_file(py, &e),
        procedure::ProcedureError::Io { .. } => PyOSError::new_err(e.to_string()),
        e => PyValueError::new_err(e.to_string()),
    }
}

/// The nominal motion's failure as a Python exception (as `simulate`
/// raises it: the kinematics' classes, `TrajectoryError`, `ValueError`).
fn motion_error(py: Python<'_>, error: &SimulationError) -> PyErr {
    let prefix = "the nominal motion: ";
    match error {
        SimulationError::Geometry(e) => {
            errors::kinematics(py, e, None, None, "the nominal robot's geometry: ")
        }
        SimulationError::Trajectory(e) => errors::trajectory(py, e),
        SimulationError::Kinematics { t, sample, error } => errors::kinematics(
            py,
            error,
            *sample,
            Some(*t),
            &format!("{prefix}{}", AtTime(*t)),
        ),
        other => PyValueError::new_err(format!("{prefix}{other}")),
    }
}

impl Inputs {
    /// The motion the study follows.
    fn scenario(&self, py: Python<'_>) -> PyResult<Scenario> {
        if !(self.rate_hz > 0.0 && self.rate_hz.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "rate_hz must be a positive number of Hz, got {}",
                self.rate_hz
            )));
        }
        let base = match &self.procedure {
            Some(ProcedureSource::Toml { text, origin, base }) => {
                procedure::parse(text, origin, base).map_err(|e| procedure_error(py, e))?
            }
            Some(ProcedureSource::Json { text, base }) => {
                procedure::parse_json(text, base).map_err(|e| procedure_error(py, e))?
            }
            None => Scenario::paper(),
        };
        let mut scenario = Scenario {
            rate_hz: self.rate_hz,
            ..base
        };
        if let Some(text) = &self.robot {
            let robot = robot_file::parse_robot(text).map_err(|e| errors::robot_file(py, &e))?;
            scenario.robot = robot.geometry;
            scenario.supervisor = robot.supervisor;
            scenario.bodies = robot.bodies;
        }
        Ok(scenario)
    }

    /// The study of these inputs: the nominal motion simulated, the
    /// specification checked against it.
    fn study(&self, py: Python<'_>) -> PyResult<Study> {
        let spec = Spec::from_toml(&self.spec).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let scenario = self.scenario(py)?;
        let seed = self.seed;
        let built = py.detach(move || -> Result<Study, BuildFailure> {
            let trace = Trace::from_scenario(scenario).map_err(BuildFailure::Motion)?;
            Study::new(spec, trace, seed).map_err(|e| BuildFailure::Study(e.to_string()))
        });
        match built {
            Ok(study) => Ok(study),
            Err(BuildFailure::Motion(e)) => Err(motion_error(py, &e)),
            Err(BuildFailure::Study(text)) => Err(PyValueError::new_err(text)),
        }
    }
}

/// Why a study could not be built, in the thread without the GIL.
enum BuildFailure {
    Motion(SimulationError),
    Study(String),
}

/// `spec=`: a path to a TOML file, a dict of the same structure, or `None`
/// for the default specification; returned as a value.
fn read_spec(py: Python<'_>, value: Option<&Bound<'_, PyAny>>) -> PyResult<Spec> {
    let Some(value) = value else {
        return Ok(Spec::default());
    };
    let invalid = |e: parasils_tolerance::SpecError| PyValueError::new_err(e.to_string());
    if value.is_instance_of::<PyDict>() {
        let json = py.import("json")?.call_method1("dumps", (value,))?;
        let text: String = json.extract()?;
        return Spec::from_json(&text).map_err(invalid);
    }
    let path: PathBuf = value.extract().map_err(|_| {
        PyTypeError::new_err(
            "spec must be a path to a tolerance specification (TOML; str or os.PathLike), \
             a dict of the same structure, or None for the default",
        )
    })?;
    // The file's own error as OSError (FileNotFoundError...); its contents'
    // errors name it.
    std::fs::metadata(&path).map_err(|e| errors::os_error(&e, &path))?;
    Spec::load(&path).map_err(invalid)
}

/// `robot=`: a `Robot`, a robot file's path, or `None` (the paper's); as
/// the robot file's text.
fn read_robot(py: Python<'_>, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<String>> {
    let Some(value) = value else {
        return Ok(None);
    };
    if let Ok(robot) = value.cast::<Robot>() {
        return robot_file::robot_to_toml_string(robot.get().model())
            .map(Some)
            .map_err(|e| PyValueError::new_err(e.to_string()));
    }
    let path: PathBuf = value.extract().map_err(|_| {
        PyTypeError::new_err(
            "robot must be a parasils.Robot or a path to a robot file (str or os.PathLike)",
        )
    })?;
    let text = std::fs::read_to_string(&path).map_err(|e| errors::os_error(&e, &path))?;
    // Its errors name the file here; the text alone is what a pickle carries.
    robot_file::load_robot(&path).map_err(|e| errors::robot_file(py, &e))?;
    Ok(Some(text))
}

/// `procedure=`: a procedure file's path, or a dict of the same structure
/// (its robot path relative to the working directory).
fn read_procedure(
    py: Python<'_>,
    value: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<ProcedureSource>> {
    let Some(value) = value else {
        return Ok(None);
    };
    let absolute = |p: &Path| std::path::absolute(p).map_err(|e| errors::os_error(&e, p));
    if value.is_instance_of::<PyDict>() {
        let json = py.import("json")?.call_method1("dumps", (value,))?;
        return Ok(Some(ProcedureSource::Json {
            text: json.extract()?,
            base: absolute(Path::new("."))?,
        }));
    }
    let path: PathBuf = value.extract().map_err(|_| {
        PyTypeError::new_err(
            "procedure must be a path to a procedure file (str or os.PathLike) or a dict",
        )
    })?;
    let text = std::fs::read_to_string(&path).map_err(|e| errors::os_error(&e, &path))?;
    let folder = path.parent().unwrap_or(Path::new(""));
    let folder = if folder.as_os_str().is_empty() {
        Path::new(".")
    } else {
        folder
    };
    Ok(Some(ProcedureSource::Toml {
        text,
        origin: path.display().to_string(),
        base: absolute(folder)?,
    }))
}

/// The sample indices of `run_indices`: a 1-D array-like of integers >= 0.
fn read_indices(py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<Vec<u64>> {
    let array = py.import("numpy")?.call_method1("asarray", (value,))?;
    let ndim: usize = array.getattr("ndim")?.extract()?;
    if ndim != 1 {
        let shape = array.getattr("shape")?.repr()?.to_string();
        return Err(PyValueError::new_err(format!(
            "indices must be a 1-D array of sample indices, got shape {shape}"
        )));
    }
    let size: usize = array.getattr("size")?.extract()?;
    if size == 0 {
        return Ok(Vec::new());
    }
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    match kind.as_str() {
        "u" => {
            let a = array.call_method1("astype", ("uint64",))?;
            let a: PyReadonlyArray1<'_, u64> = a.extract()?;
            Ok(a.as_array().iter().copied().collect())
        }
        "i" => {
            let a = array.call_method1("astype", ("int64",))?;
            let a: PyReadonlyArray1<'_, i64> = a.extract()?;
            a.as_array()
                .iter()
                .enumerate()
                .map(|(k, &i)| {
                    u64::try_from(i).map_err(|_| {
                        PyValueError::new_err(format!("indices must be >= 0: indices[{k}] is {i}"))
                    })
                })
                .collect()
        }
        _ => Err(PyTypeError::new_err(format!(
            "indices must be integers, got an array of dtype {}",
            dtype.str()?
        ))),
    }
}

/// The threads of a run: `threads`, or the batch's rule.
fn run_threads(threads: Option<usize>) -> PyResult<usize> {
    match threads {
        None => batch::threads(),
        Some(0) => Err(PyValueError::new_err(
            "threads must be at least 1 (or None for parasils.batch_threads())",
        )),
        Some(n) => Ok(n),
    }
}

/// The columns of `results` as a dict of NumPy arrays, with the failures.
fn columns(py: Python<'_>, results: Results) -> PyResult<Bound<'_, PyDict>> {
    let Results {
        sample,
        left_tip_dev_mm,
        right_tip_dev_mm,
        pose_position_err_mm,
        pose_rotation_err_deg,
        failed,
        failures,
    } = results;
    let d = PyDict::new(py);
    d.set_item("sample", sample.into_pyarray(py))?;
    d.set_item("left_tip_dev_mm", left_tip_dev_mm.into_pyarray(py))?;
    d.set_item("right_tip_dev_mm", right_tip_dev_mm.into_pyarray(py))?;
    d.set_item(
        "pose_position_err_mm",
        pose_position_err_mm.into_pyarray(py),
    )?;
    d.set_item(
        "pose_rotation_err_deg",
        pose_rotation_err_deg.into_pyarray(py),
    )?;
    d.set_item("failed", failed.into_pyarray(py))?;
    let list = PyList::empty(py);
    for (sample, why) in failures {
        list.append((sample, why.to_string()))?;
    }
    d.set_item("failures", list)?;
    Ok(d)
}

/// A tolerance study: robots drawn within a tolerance specification, each
/// driven along a motion by the nominal model's commands.
///
/// ToleranceStudy(spec, *, seed=0, procedure=None, rate_hz=100.0, robot=None)
///
/// spec: the tolerances: a path to a specification file (TOML, the format
///     `parasils tolerance --print-spec` prints), a dict of the same
///     structure, e.g. {"instruments": {"alpha_deg": {"sigma": 0.01}}}
///     (sigma: normal, one standard deviation; half_width: uniform; in the
///     unit the key names, mm or deg), or None for the default tolerances.
/// seed: sample i's robot depends only on the seed and i.
/// procedure: the motion: a procedure file's path or a dict of the same
///     structure (its start, robot and motions); default the paper's
///     reorientation.
/// rate_hz: the samples per second along the motion, Hz.
/// robot: the nominal robot: a parasils.Robot or a robot file's path;
///     default the paper's (not with procedure, which names its own).
///
/// The nominal motion is simulated and the specification checked when the
/// study is built: ValueError for a bad specification (an unknown key, a
/// negative width, a tolerance whose extreme takes one of module 1's legs
/// out of reach along the motion), the simulation's errors for a motion
/// that fails, RobotFileError or OSError for the files.
///
/// A study pickles (its inputs as text: the specification, the robot
/// file, the procedure's text) and gives the same rows, bit for bit, after
/// a round trip: what Dask or Ray send to their workers. A procedure's
/// robot file is read again where the study is unpickled, at the same
/// absolute path.
#[pyclass(frozen, module = "parasils")]
#[derive(Debug)]
pub struct ToleranceStudy {
    study: Study,
    inputs: Inputs,
}

impl ToleranceStudy {
    fn build(py: Python<'_>, inputs: Inputs) -> PyResult<Self> {
        let study = inputs.study(py)?;
        Ok(Self { study, inputs })
    }

    /// Runs `f` on the study without the GIL; Ctrl-C stops it when it runs
    /// on Python's main thread (KeyboardInterrupt).
    fn run_with<'py, F>(&self, py: Python<'py>, f: F) -> PyResult<Bound<'py, PyDict>>
    where
        F: FnOnce(
                &Study,
                &(dyn Fn(u64) -> bool + Sync),
            ) -> Result<Results, parasils_tolerance::Interrupted>
            + Send,
    {
        let threading = py.import("threading")?;
        let main = threading
            .call_method0("current_thread")?
            .is(&threading.call_method0("main_thread")?);
        let caller = std::thread::current().id();
        let interrupt: std::sync::Mutex<Option<PyErr>> = std::sync::Mutex::new(None);
        let progress = |_: u64| -> bool {
            if !main || std::thread::current().id() != caller {
                return true;
            }
            Python::attach(|py| match py.check_signals() {
                Ok(()) => true,
                Err(e) => {
                    if let Ok(mut slot) = interrupt.lock() {
                        *slot = Some(e);
                    }
                    false
                }
            })
        };
        let study = &self.study;
        let ran = py.detach(|| f(study, &progress));
        match ran {
            Ok(results) => columns(py, results),
            Err(parasils_tolerance::Interrupted) => Err(interrupt
                .into_inner()
                .ok()
                .flatten()
                .unwrap_or_else(|| PyValueError::new_err("the run was interrupted"))),
        }
    }
}

#[pymethods]
impl ToleranceStudy {
    #[new]
    #[pyo3(signature = (spec, *, seed = 0, procedure = None, rate_hz = 100.0, robot = None))]
    fn new(
        py: Python<'_>,
        spec: Option<Bound<'_, PyAny>>,
        seed: u64,
        procedure: Option<Bound<'_, PyAny>>,
        rate_hz: f64,
        robot: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        if procedure.is_some() && robot.is_some() {
            return Err(PyTypeError::new_err(
                "robot cannot be given with procedure=: a procedure has its own start, robot and motions",
            ));
        }
        let spec = read_spec(py, spec.as_ref())?;
        let robot = read_robot(py, robot.as_ref())?;
        let procedure = read_procedure(py, procedure.as_ref())?;
        Self::build(
            py,
            Inputs {
                spec: spec.to_toml(),
                seed,
                rate_hz,
                robot,
                procedure,
            },
        )
    }

    /// The study again from the inputs `__reduce__` gives (the pickle's
    /// constructor): the specification's TOML, the seed, the rate, the
    /// robot file's text or None, the procedure as None, ("toml", text,
    /// origin, folder) or ("json", text, folder), and the version of
    /// parasils that pickled it (which must be this one).
    #[staticmethod]
    #[pyo3(signature = (version, spec, seed, rate_hz, robot, procedure))]
    fn _from_state(
        py: Python<'_>,
        version: &str,
        spec: String,
        seed: u64,
        rate_hz: f64,
        robot: Option<String>,
        procedure: Option<Bound<'_, PyTuple>>,
    ) -> PyResult<Self> {
        let ours = env!("CARGO_PKG_VERSION");
        if version != ours {
            return Err(PyValueError::new_err(format!(
                "this tolerance study was pickled by parasils {version}, and this is parasils \
                 {ours}: install the same version everywhere (the numbers may differ otherwise)"
            )));
        }
        let procedure = match procedure {
            None => None,
            Some(t) => {
                let kind: String = t.get_item(0)?.extract()?;
                match (kind.as_str(), t.len()) {
                    ("toml", 4) => Some(ProcedureSource::Toml {
                        text: t.get_item(1)?.extract()?,
                        origin: t.get_item(2)?.extract()?,
                        base: t.get_item(3)?.extract()?,
                    }),
                    ("json", 3) => Some(ProcedureSource::Json {
                        text: t.get_item(1)?.extract()?,
                        base: t.get_item(2)?.extract()?,
                    }),
                    _ => {
                        return Err(PyValueError::new_err(
                            "procedure must be None, ('toml', text, origin, folder) or ('json', text, folder)",
                        ));
                    }
                }
            }
        };
        Self::build(
            py,
            Inputs {
                spec,
                seed,
                rate_hz,
                robot,
                procedure,
            },
        )
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let inputs = &slf.get().inputs;
        let procedure: Option<Bound<'py, PyTuple>> = match &inputs.procedure {
            None => None,
            Some(ProcedureSource::Toml { text, origin, base }) => Some(PyTuple::new(
                py,
                [
                    PyString::new(py, "toml").into_any(),
                    PyString::new(py, text).into_any(),
                    PyString::new(py, origin).into_any(),
                    base.into_pyobject(py)?.into_any(),
                ],
            )?),
            Some(ProcedureSource::Json { text, base }) => Some(PyTuple::new(
                py,
                [
                    PyString::new(py, "json").into_any(),
                    PyString::new(py, text).into_any(),
                    base.into_pyobject(py)?.into_any(),
                ],
            )?),
        };
        let args = (
            env!("CARGO_PKG_VERSION"),
            inputs.spec.as_str(),
            inputs.seed,
            inputs.rate_hz,
            inputs.robot.as_deref(),
            procedure,
        );
        let constructor = slf.get_type().getattr("_from_state")?;
        PyTuple::new(py, [constructor, args.into_pyobject(py)?.into_any()])
    }

    /// run(start, count, *, threads=None) -> dict
    ///
    /// The samples start, start + 1, ..., start + count - 1, on `threads`
    /// threads (None: parasils.batch_threads(), from PARASILS_NUM_THREADS
    /// or the CPUs), without the GIL. The rows do not depend on how the
    /// samples are split or on the threads, bit for bit.
    ///
    /// Returns a dict of NumPy columns, one row per sample in order:
    /// "sample" (uint64), "left_tip_dev_mm", "right_tip_dev_mm" (the
    /// largest distance of each real tip from the commanded one along the
    /// motion, mm), "pose_position_err_mm" (mm), "pose_rotation_err_deg"
    /// (deg) (float64; NaN on a failed sample), "failed" (bool: the
    /// perturbed robot could not be followed, e.g. module 1's forward
    /// kinematics did not converge); and "failures", a list of (sample,
    /// message) for each failed row.
    #[pyo3(signature = (start, count, *, threads = None))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        start: u64,
        count: u64,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let end = start.checked_add(count).ok_or_else(|| {
            PyValueError::new_err(format!(
                "start + count must fit in 64 bits, got {start} + {count}"
            ))
        })?;
        let threads = run_threads(threads)?;
        self.run_with(py, |study, progress| {
            study.run(start..end, threads, progress)
        })
    }

    /// run_indices(indices, *, threads=None) -> dict
    ///
    /// The samples listed in `indices` (a 1-D array-like of integers >= 0,
    /// any order, repeats allowed; read-only arrays are fine), as run()
    /// does a range: the same columns, the rows in the order of `indices`.
    #[pyo3(signature = (indices, *, threads = None))]
    fn run_indices<'py>(
        &self,
        py: Python<'py>,
        indices: &Bound<'py, PyAny>,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let indices = read_indices(py, indices)?;
        let threads = run_threads(threads)?;
        self.run_with(py, |study, progress| {
            study.run_indices(&indices, threads, progress)
        })
    }

    /// sensitivity() -> list of dict
    ///
    /// Which tolerance to tighten: each perturbed family's share of the
    /// mean-square tip deviation, to first order (from the analytic
    /// derivatives of the tips in the parameters along the nominal motion,
    /// not from the samples), largest first. Each dict has "family" (the
    /// specification's key, e.g. "module1.guides.point_mm"), "share" (in
    /// [0, 1], adding up to 1) and "rms_tip_mm" (the RMS tip deviation that
    /// family's tolerance causes alone, over the motion and both tips, mm).
    ///
    /// Raises ValueError when the first-order model cannot be formed (a
    /// commanded pose where module 1 is singular).
    fn sensitivity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let study = &self.study;
        let ranking = py
            .detach(|| study.linearisation().map(|l| l.sensitivity(study.spec())))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let list = PyList::empty(py);
        for s in ranking {
            let d = PyDict::new(py);
            d.set_item("family", s.family.key())?;
            d.set_item("share", s.share)?;
            d.set_item("rms_tip_mm", s.rms_tip_mm)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The number of samples of the motion (its commands), at rate_hz.
    #[getter]
    fn n_motion_samples(&self) -> usize {
        self.study.trace().len()
    }

    /// The seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.study.seed()
    }

    /// The motion's sampling rate, Hz.
    #[getter]
    fn rate_hz(&self) -> f64 {
        self.inputs.rate_hz
    }

    /// The specification as TOML (every family perturbed, with its
    /// distribution), as `parasils tolerance --print-spec` prints it.
    #[getter]
    fn spec(&self) -> String {
        self.study.spec().to_toml()
    }

    fn __repr__(&self) -> String {
        let motion = match &self.inputs.procedure {
            None => "the paper's reorientation".to_owned(),
            Some(ProcedureSource::Toml { origin, .. }) => format!("procedure {origin:?}"),
            Some(ProcedureSource::Json { .. }) => "a procedure (dict)".to_owned(),
        };
        format!(
            "<parasils.ToleranceStudy: {motion} at {} Hz ({} samples), seed {}>",
            self.inputs.rate_hz,
            self.study.trace().len(),
            self.study.seed()
        )
    }
}
