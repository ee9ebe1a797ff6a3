//! `parasils.simulate`: the simulation library's run, returning the CSV's
//! table as NumPy columns (and writing CSV or MCAP with `out=`).
//!
//! The arguments build the simulation library's [`Input`] (user units, like
//! the CLI's flags, each given or not), resolved as the CLI resolves its
//! flags; the library's [`Simulation::run`] is the loop, the same as the
//! CLI's, into a [`Tee`] of the output file (if any) and the table. A run
//! with commands (`retarget=`, `stop_at_s=`) has the CLI's `command` column
//! too, as integers; a run with tip loads (`tip_load_left_n=`,
//! `tip_load_right_n=`) the CLI's force columns.

use core::convert::Infallible;
use std::path::PathBuf;

use numpy::IntoPyArray;
use parasils_io::{AtTime, WriteError};
use parasils_sim::input::{self, ProcedureSource, RobotSource};
use parasils_sim::procedure;
use parasils_sim::scenario::Retarget;
use parasils_sim::{
    Format, Input, InputError, LookAt, OutputError, OutputFile, Record, RunError, Scenario,
    Simulation, SimulationError, Tee, columns,
};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::batch::{ArrayArg, Rows};
use crate::errors;
use crate::robot::Robot;

/// Why a run failed, in the thread without the GIL.
enum Failure {
    /// The engine failed.
    Simulation(SimulationError),
    /// The output file `path` could not be written.
    Output(OutputError, PathBuf),
    /// The table does not fit in memory.
    Memory(usize),
}

/// `Some([f64; N])` from a sequence or array of shape `(N,)`.
pub(crate) fn fixed<const N: usize>(
    value: Option<ArrayArg<'_>>,
    name: &str,
) -> PyResult<Option<[f64; N]>> {
    let Some(array) = value else {
        return Ok(None);
    };
    let rows = Rows::new(&array, name, N)?;
    if crate::batch::batch_size(&[(name, &rows)])?.is_some() {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape ({N},): one value per component"
        )));
    }
    Ok(Some(rows.get::<N>(0)))
}

/// An output file's error as a Python exception: `OSError` (its subclass
/// from the error number, or from the kind) naming `path` when the system
/// failed, `ValueError` otherwise.
fn output_error(py: Python<'_>, error: &OutputError, path: &std::path::Path) -> PyErr {
    let text = error.to_string();
    match error {
        OutputError::File(WriteError::NoSpace { .. }) => {
            // ENOSPC: the file would not fit (refused before writing).
            const ENOSPC: i32 = 28;
            return PyOSError::new_err((ENOSPC, text, path.display().to_string()));
        }
        OutputError::File(WriteError::OverCap { .. }) => {
            return PyValueError::new_err(format!("{text}: pass force=True to write it anyway"));
        }
        _ => {}
    }
    let Some(io) = error.io_error() else {
        return PyValueError::new_err(text);
    };
    let filename = path.display().to_string();
    if let Some(errno) = io.raw_os_error() {
        return PyOSError::new_err((errno, text, filename));
    }
    let err = PyErr::from(std::io::Error::new(io.kind(), text));
    // Best effort: the message already names the place.
    let _ = err.value(py).setattr("filename", filename);
    err
}

pub(crate) fn simulation_error(py: Python<'_>, error: &SimulationError) -> PyErr {
    match error {
        SimulationError::Geometry(e) => errors::kinematics(py, e, None, None, "robot geometry: "),
        SimulationError::Trajectory(e) => errors::trajectory(py, e),
        SimulationError::Kinematics { t, sample, error } => {
            errors::kinematics(py, error, *sample, Some(*t), &AtTime(*t).to_string())
        }
        SimulationError::Motion { error: inner, .. } => {
            // The kinematics' exception class, with the whole message: the
            // motion, the time inside it, what failed.
            let text = error.to_string();
            match inner.as_ref() {
                SimulationError::Kinematics {
                    t,
                    sample,
                    error: e,
                } => {
                    let prefix = text.strip_suffix(&e.to_string()).unwrap_or("");
                    errors::kinematics(py, e, *sample, Some(*t), prefix)
                }
                _ => PyValueError::new_err(text),
            }
        }
        other => PyValueError::new_err(other.to_string()),
    }
}

/// `retarget=`: a sequence of `(t_s, psi_deg, theta_deg)` triples.
fn retargets(value: Bound<'_, PyAny>) -> PyResult<Vec<Retarget>> {
    let shape = "retarget must be a sequence of (t_s, psi_deg, theta_deg) triples, \
                 e.g. [(1.2, 25.0, 15.0)]";
    if value.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(shape));
    }
    let items = value.try_iter().map_err(|_| PyTypeError::new_err(shape))?;
    let mut out = Vec::new();
    for (k, item) in items.enumerate() {
        let item = item?;
        let [t_s, psi_deg, theta_deg] = item.extract::<[f64; 3]>().map_err(|_| {
            PyValueError::new_err(format!(
                "{shape}; item {k} is {}",
                item.repr()
                    .map_or_else(|_| "not one".to_owned(), |r| r.to_string())
            ))
        })?;
        out.push(Retarget {
            t_s,
            psi_deg,
            theta_deg,
        });
    }
    Ok(out)
}

/// Runs the simulation through the library's loop, keeping every record's
/// CSV row column by column, and streaming the records to `out` as well.
/// Returns the table and its columns.
fn run(
    scenario: Scenario,
    out: Option<(PathBuf, Format)>,
    force: bool,
) -> Result<(Vec<Vec<f64>>, &'static [columns::Column]), Failure> {
    let sim = Simulation::new(scenario).map_err(Failure::Simulation)?;
    let n = sim.sample_count();
    if let Some((path, format)) = &out {
        parasils_sim::output::check_size(path, *format, n, force)
            .map_err(|e| Failure::Output(e, path.clone()))?;
    }
    let csv = parasils_sim::no_go::csv_columns_of(sim.scenario());
    let mut table: Vec<Vec<f64>> = Vec::with_capacity(csv.len());
    for _ in csv {
        let mut c = Vec::new();
        c.try_reserve_exact(n).map_err(|_| Failure::Memory(n))?;
        table.push(c);
    }
    let (mut file, path) = match out {
        Some((path, format)) => (
            Some(
                OutputFile::create(&path, format, sim.scenario())
                    .map_err(|e| Failure::Output(e, path.clone()))?,
            ),
            path,
        ),
        None => (None, PathBuf::new()),
    };
    let mut keep = |r: &Record| {
        for (values, column) in table.iter_mut().zip(csv) {
            values.push(column.value(r));
        }
        Ok::<(), Infallible>(())
    };
    let ran = sim.run(&mut Tee::new().with_some(file.as_mut()).with(&mut keep));
    match ran {
        Ok(()) => {}
        Err(RunError::Simulation(e)) => return Err(Failure::Simulation(e)),
        Err(RunError::Sink(e)) => {
            // The table cannot fail: the output file did.
            return Err(match e.downcast::<OutputError>() {
                Ok(e) => Failure::Output(*e, path),
                Err(other) => Failure::Output(
                    OutputError::File(WriteError::Io {
                        path: path.clone(),
                        error: std::io::Error::other(other.to_string()),
                    }),
                    path,
                ),
            });
        }
    }
    if let Some(f) = file {
        f.finish().map_err(|e| Failure::Output(e, path))?;
    }
    Ok((table, csv))
}

/// The paper's scenario in the units of `simulate`'s arguments: the defaults
/// the package's `simulate` shows in its signature.
pub(crate) fn paper_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let paper = Scenario::paper();
    let turn = parasils_sim::Turn::paper();
    let d = PyDict::new(py);
    d.set_item("psi_deg", turn.psi_deg)?;
    d.set_item("theta_deg", turn.theta_deg)?;
    d.set_item("omega_max_deg_s", turn.omega_max_deg_s)?;
    d.set_item("eps_max_deg_s2", turn.eps_max_deg_s2)?;
    d.set_item("rate_hz", paper.rate_hz)?;
    d.set_item("pose_mm_deg", paper.start_mm_deg.to_vec())?;
    d.set_item("tip_left_mm", paper.tip_left_mm.to_vec())?;
    Ok(d)
}

/// The compiled part of `parasils.simulate` (see its docstring in
/// `python/parasils/__init__.py`): every argument keyword-only, `None` when
/// not given. The arguments are translated into the simulation library's
/// [`Input`], whose resolution (the same the CLI calls) applies the
/// defaults, the exclusions and the timing rule.
#[pyfunction]
#[pyo3(signature = (
    *,
    psi_deg = None,
    theta_deg = None,
    absolute = None,
    omega_max_deg_s = None,
    eps_max_deg_s2 = None,
    sync = None,
    rate_hz = None,
    pose_mm_deg = None,
    tip_left_mm = None,
    tip_right_mm = None,
    robot = None,
    out = None,
    format = None,
    retarget = None,
    stop_at_s = None,
    force = false,
    procedure = None,
    timing = None,
    tip_load_left_n = None,
    tip_load_right_n = None,
    look_at = None,
    anatomy = None,
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    psi_deg: Option<f64>,
    theta_deg: Option<f64>,
    absolute: Option<bool>,
    omega_max_deg_s: Option<f64>,
    eps_max_deg_s2: Option<f64>,
    sync: Option<&str>,
    rate_hz: Option<f64>,
    pose_mm_deg: Option<ArrayArg<'py>>,
    tip_left_mm: Option<ArrayArg<'py>>,
    tip_right_mm: Option<ArrayArg<'py>>,
    robot: Option<Bound<'py, PyAny>>,
    out: Option<PathBuf>,
    format: Option<&str>,
    retarget: Option<Bound<'py, PyAny>>,
    stop_at_s: Option<f64>,
    force: bool,
    procedure: Option<Bound<'py, PyAny>>,
    timing: Option<&str>,
    tip_load_left_n: Option<ArrayArg<'py>>,
    tip_load_right_n: Option<ArrayArg<'py>>,
    look_at: Option<Bound<'py, PyAny>>,
    anatomy: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let format = match format {
        None => None,
        Some("csv") => Some(Format::Csv),
        Some("mcap") => Some(Format::Mcap),
        Some(f) => {
            return Err(PyValueError::new_err(format!(
                "format must be 'csv' or 'mcap', got {f:?}"
            )));
        }
    };
    let input = Input {
        procedure: procedure.map(|p| procedure_source(&p)).transpose()?,
        psi_deg,
        theta_deg,
        absolute,
        omega_max_deg_s,
        eps_max_deg_s2,
        sync: sync
            .map(input::sync_named)
            .transpose()
            .map_err(value_error)?,
        timing: timing
            .map(input::timing_named)
            .transpose()
            .map_err(value_error)?,
        rate_hz,
        pose_mm_deg: fixed::<6>(pose_mm_deg, "pose_mm_deg")?,
        tip_left_mm: fixed::<3>(tip_left_mm, "tip_left_mm")?,
        tip_right_mm: fixed::<3>(tip_right_mm, "tip_right_mm")?,
        robot: robot.map(|r| robot_source(&r)).transpose()?,
        retarget: retarget.map(retargets).transpose()?,
        stop_at_s,
        tip_load_left_n: fixed::<3>(tip_load_left_n, "tip_load_left_n")?,
        tip_load_right_n: fixed::<3>(tip_load_right_n, "tip_load_right_n")?,
        look_at: look_at.map(|l| look_at_arg(&l)).transpose()?,
        anatomy,
    };
    let scenario = input.resolve().map_err(|e| input_error(py, e))?;
    finish(py, scenario, out, format, force)
}

/// `look_at=`: `"tips"`, `"left"`, `"right"`, or a point `[x, y, z]` in
/// mm (a sequence or an array of three numbers).
fn look_at_arg(value: &Bound<'_, PyAny>) -> PyResult<LookAt> {
    if let Ok(name) = value.extract::<String>() {
        return match name.as_str() {
            "tips" | "left" | "right" => input::look_at_named(&name).map_err(value_error),
            _ => Err(PyValueError::new_err(format!(
                "look_at must be 'tips', 'left', 'right' or a point [x, y, z] in mm, got {name:?}"
            ))),
        };
    }
    let point = value.extract::<[f64; 3]>().map_err(|_| {
        PyTypeError::new_err("look_at must be 'tips', 'left', 'right' or a point [x, y, z] in mm")
    })?;
    if let Some(v) = point.iter().find(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "look_at must be a finite point [x, y, z] in mm, got {v} in it"
        )));
    }
    Ok(LookAt::Point(point))
}

fn value_error(e: InputError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// An [`InputError`] as Python raises it: `TypeError` for an argument given
/// with `procedure=`, `ValueError` for an unknown name or a command with the
/// optimal timing, the files' own
/// exceptions for the procedure and the robot file.
pub(crate) fn input_error(py: Python<'_>, error: InputError) -> PyErr {
    match error {
        InputError::WithProcedure(field) => PyTypeError::new_err(format!(
            "{field} cannot be given with procedure=: a procedure has its own start, robot and motions"
        )),
        InputError::OptimalOnline(field) => PyValueError::new_err(format!(
            "{field} cannot be given with timing='optimal': it plans one motion from rest to rest, while commands are taken online"
        )),
        InputError::Conflict { field, with, why } => {
            PyTypeError::new_err(format!("{field} cannot be given with {with}: {why}"))
        }
        InputError::Procedure(procedure::ProcedureError::Robot(e)) | InputError::Robot(e) => {
            errors::robot_file(py, &e)
        }
        InputError::Procedure(e @ procedure::ProcedureError::Io { .. }) => {
            PyOSError::new_err(e.to_string())
        }
        e @ InputError::Anatomy(parasils_sim::AnatomyError::Read { .. }) => {
            PyOSError::new_err(e.to_string())
        }
        e => PyValueError::new_err(e.to_string()),
    }
}

/// `robot=`: a `parasils.Robot` (its geometry and supervisor thresholds) or
/// a path to a robot file.
pub(crate) fn robot_source(value: &Bound<'_, PyAny>) -> PyResult<RobotSource> {
    if let Ok(r) = value.cast::<Robot>() {
        return Ok(RobotSource::Loaded(Box::new(r.get().model().clone())));
    }
    value
        .extract::<PathBuf>()
        .map(RobotSource::File)
        .map_err(|_| {
            PyTypeError::new_err(
                "robot must be a path to a robot file (str or os.PathLike) or a parasils.Robot",
            )
        })
}

/// `procedure=`: a path to a procedure file (TOML), or a dict of the same
/// structure (its robot path relative to the working directory).
pub(crate) fn procedure_source(value: &Bound<'_, PyAny>) -> PyResult<ProcedureSource> {
    if value.is_instance_of::<PyDict>() {
        let json = value.py().import("json")?.call_method1("dumps", (value,))?;
        return Ok(ProcedureSource::Json(json.extract()?));
    }
    value
        .extract::<PathBuf>()
        .map(ProcedureSource::File)
        .map_err(|_| {
            PyTypeError::new_err(
                "procedure must be a path to a procedure file (str or os.PathLike) or a dict",
            )
        })
}

/// Runs `scenario` (into `out` if given) and returns its columns.
fn finish<'py>(
    py: Python<'py>,
    scenario: Scenario,
    out: Option<PathBuf>,
    format: Option<Format>,
    force: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let out = match out {
        Some(p) => {
            let f = match format {
                Some(f) => f,
                None => Format::from_path(&p).map_err(|e| PyValueError::new_err(e.to_string()))?,
            };
            Some((p, f))
        }
        None => None,
    };
    let result = py.detach(move || run(scenario, out, force));
    let (table, csv) = result.map_err(|f| match f {
        Failure::Simulation(e) => simulation_error(py, &e),
        Failure::Output(e, path) => output_error(py, &e, &path),
        Failure::Memory(n) => PyMemoryError::new_err(format!(
            "{n} samples of {} columns do not fit in memory: lower rate_hz",
            columns::CSV_COUNT
        )),
    })?;
    columns_dict(py, csv, table)
}

/// The table's columns as a dict of NumPy arrays named as the CSV's
/// columns: `int64` for the whole-number columns (command indices, codes,
/// bit masks: whole numbers widened to `f64`, exactly), `float64` for the
/// others.
pub(crate) fn columns_dict<'py>(
    py: Python<'py>,
    columns: &[parasils_sim::columns::Column],
    table: Vec<Vec<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (column, values) in columns.iter().zip(table) {
        if column.integer {
            #[allow(clippy::cast_possible_truncation, reason = "whole numbers")]
            let ints: Vec<i64> = values.iter().map(|v| *v as i64).collect();
            dict.set_item(column.name, ints.into_pyarray(py))?;
        } else {
            dict.set_item(column.name, values.into_pyarray(py))?;
        }
    }
    Ok(dict)
}
