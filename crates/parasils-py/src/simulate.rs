//! `parasils.simulate`: the CLI's `parasils simulate`, returning its CSV table.

use std::path::{Path, PathBuf};

use parasils_cli::cli::{Format, OutputFile, SimulateArgs, SyncArg};
use parasils_cli::robot_file::RobotFileError as FileError;
use parasils_cli::sample::{COLUMNS, NUM_COLUMNS, Sink};
use parasils_cli::simulate::{Simulation, SimulationError};
use parasils_kin::controller::RobotGeometry;
use pyo3::exceptions::{PyMemoryError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use numpy::IntoPyArray;

use crate::batch::{ArrayArg, Rows};
use crate::errors;
use crate::robot::Robot;

/// Why a run failed, in the thread without the GIL.
enum Failure {
    /// The engine failed, at the sample `row` if any.
    Simulation(SimulationError, Option<usize>),
    /// The output file could not be written.
    Output(anyhow::Error, PathBuf),
    /// The table does not fit in memory.
    Memory(usize),
}

/// `Some([f64; N])` from a sequence or array of shape `(N,)`.
fn fixed<const N: usize>(value: Option<ArrayArg<'_>>, name: &str) -> PyResult<Option<[f64; N]>> {
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

/// An error of the CLI library (anyhow) as a Python exception: a robot
/// file's as `errors::robot_file`, an I/O error as `OSError` naming `path`,
/// anything else as `ValueError` with the chain of causes.
fn cli_error(py: Python<'_>, error: &anyhow::Error, path: Option<&Path>) -> PyErr {
    if let Some(e) = error.downcast_ref::<FileError>() {
        return errors::robot_file(py, e);
    }
    let text: Vec<String> = error.chain().map(ToString::to_string).collect();
    let text = text.join(": ");
    // The OS error number, wherever in the chain (tempfile wraps it), picks
    // the subclass (FileNotFoundError, PermissionError, ...).
    let io_errors: Vec<&std::io::Error> = error
        .chain()
        .filter_map(|c| c.downcast_ref::<std::io::Error>())
        .collect();
    if let Some(errno) = io_errors.iter().find_map(|e| e.raw_os_error()) {
        return match path {
            Some(p) => PyOSError::new_err((errno, text, p.display().to_string())),
            None => PyOSError::new_err((errno, text)),
        };
    }
    if let Some(io) = io_errors.first() {
        // No number: the subclass from the error's kind.
        let err = PyErr::from(std::io::Error::new(io.kind(), text));
        if let Some(p) = path {
            // Best effort: the message already names the place.
            let _ = err.value(py).setattr("filename", p.display().to_string());
        }
        return err;
    }
    PyValueError::new_err(text)
}

fn simulation_error(py: Python<'_>, error: &SimulationError, row: Option<usize>) -> PyErr {
    match error {
        SimulationError::Geometry(e) => errors::kinematics(py, e, None, None, "robot geometry: "),
        SimulationError::Trajectory(e) => errors::trajectory(py, e),
        SimulationError::Kinematics { t, error } => {
            errors::kinematics(py, error, row, Some(*t), &format!("at t = {t:.3} s: "))
        }
    }
}

/// Runs the simulation and keeps every sample's row, column by column;
/// streams the samples to `out` as well.
fn run(sim: &Simulation, out: Option<(PathBuf, Format)>) -> Result<Vec<Vec<f64>>, Failure> {
    let n = sim.sample_count();
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(NUM_COLUMNS);
    for _ in 0..NUM_COLUMNS {
        let mut c = Vec::new();
        c.try_reserve_exact(n).map_err(|_| Failure::Memory(n))?;
        columns.push(c);
    }
    let mut file = match out {
        Some((path, format)) => {
            Some(OutputFile::create(&path, format, sim).map_err(|e| Failure::Output(e, path))?)
        }
        None => None,
    };
    for (k, sample) in sim.samples().enumerate() {
        let s = sample.map_err(|e| Failure::Simulation(e, Some(k)))?;
        if let Some(f) = &mut file {
            f.push(&s)
                .map_err(|e| Failure::Output(e, f.path().to_owned()))?;
        }
        for (c, v) in columns.iter_mut().zip(s.row()) {
            c.push(v);
        }
    }
    if let Some(f) = file {
        let path = f.path().to_owned();
        f.finish().map_err(|e| Failure::Output(e, path))?;
    }
    Ok(columns)
}

/// Simulates an endoscope reorientation (motion type 4), as the CLI's
/// `parasils simulate` does, with the same library: the platform turns about
/// the endoscope's RCM from `pose` by (psi_deg, theta_deg) along a
/// synchronised trapezoidal profile, and both instrument modules keep their
/// tips still. The defaults are the paper's scenario (SPEC section 7): 4501
/// samples over 4.5 s.
///
/// Keyword arguments (the CLI's options, names with their units):
///
/// - psi_deg, theta_deg: the increments of psi and theta from the start pose,
///   deg (the final angles with absolute=True); default 15, 25.
/// - absolute: take psi_deg and theta_deg as final angles (--absolute).
/// - omega_max_deg_s: each Euler angle's velocity limit, deg/s; default 10.
/// - eps_max_deg_s2: each Euler angle's acceleration limit, deg/s^2; default 5.
/// - sync: "phase" (default), "time" or "none": how psi and theta are timed.
/// - rate_hz: samples per second, Hz; default 1000.
/// - pose: the start pose (x, y, z mm, psi, theta, phi DEG, like the CLI's
///   --pose and the CSV columns); default the paper's P0 =
///   (15, 20, -500, -15, 10, -60).
/// - tip_left_mm: the left tip held still, (x, y, z) mm, fixed frame; default
///   (50, -50, -620).
/// - tip_right_mm: the right tip, (x, y, z) mm; default the mirror image of
///   the left tip across the platform's Y'Z' plane at the start pose.
/// - robot: a robot file's path (TOML, as --robot) or a parasils.Robot;
///   default the paper's robot (module 1 assumed).
/// - out: also write every sample to this file exactly as
///   `parasils simulate -o out` does: CSV or MCAP from the extension (.csv,
///   .mcap), through a temporary file renamed on success.
/// - format: "csv" or "mcap", overriding the extension (--format).
///
/// Returns a dict of 1-D float64 arrays keyed by the CSV's column names, in
/// the CSV's order and units (t_s, x_mm, ..., psi_deg, ..., q1_mm, ...,
/// left_qs1_deg, ..., right_tip_err_mm): the CLI's CSV to the last bit.
/// `pandas.DataFrame(parasils.simulate())` makes it a table.
///
/// Raises a KinematicsError subclass when a sample fails (with .row, the
/// sample's index, and .t, its time in s), TrajectoryError for limits or a
/// rate that cannot be planned, RobotFileError or OSError for the robot
/// file, OSError when `out` cannot be written, ValueError for a bad
/// argument. The simulation runs without the GIL.
#[pyfunction]
#[pyo3(signature = (
    *,
    psi_deg = 15.0,
    theta_deg = 25.0,
    absolute = false,
    omega_max_deg_s = 10.0,
    eps_max_deg_s2 = 5.0,
    sync = "phase",
    rate_hz = 1000.0,
    pose = None,
    tip_left_mm = None,
    tip_right_mm = None,
    robot = None,
    out = None,
    format = None,
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    psi_deg: f64,
    theta_deg: f64,
    absolute: bool,
    omega_max_deg_s: f64,
    eps_max_deg_s2: f64,
    sync: &str,
    rate_hz: f64,
    pose: Option<ArrayArg<'py>>,
    tip_left_mm: Option<ArrayArg<'py>>,
    tip_right_mm: Option<ArrayArg<'py>>,
    robot: Option<Bound<'py, PyAny>>,
    out: Option<PathBuf>,
    format: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let sync = match sync {
        "phase" => SyncArg::Phase,
        "time" => SyncArg::Time,
        "none" => SyncArg::None,
        _ => {
            return Err(PyValueError::new_err(format!(
                "sync must be 'phase', 'time' or 'none', got {sync:?}"
            )));
        }
    };
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
    let (robot_path, robot_geometry): (Option<PathBuf>, Option<RobotGeometry<f64>>) = match &robot
    {
        None => (None, None),
        Some(r) => match r.cast::<Robot>() {
            Ok(r) => (None, Some(*r.get().geometry())),
            Err(_) => (Some(r.extract::<PathBuf>().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(
                    "robot must be a path to a robot file (str or os.PathLike) or a parasils.Robot",
                )
            })?), None),
        },
    };
    let args = SimulateArgs {
        psi: psi_deg,
        theta: theta_deg,
        absolute,
        omega_max: omega_max_deg_s,
        eps_max: eps_max_deg_s2,
        sync,
        rate: rate_hz,
        pose: fixed::<6>(pose, "pose")?,
        tip_left: fixed::<3>(tip_left_mm, "tip_left_mm")?,
        tip_right: fixed::<3>(tip_right_mm, "tip_right_mm")?,
        robot: robot_path,
        output: out.clone(),
        format,
        plot: None,
    };
    let (mut scenario, _assumed) = args.scenario().map_err(|e| cli_error(py, &e, None))?;
    if let Some(g) = robot_geometry {
        scenario.robot = g;
    }
    let out = match out {
        Some(p) => {
            let f = args.format(&p).map_err(|e| cli_error(py, &e, None))?;
            Some((p, f))
        }
        None => None,
    };
    let result = py.detach(move || {
        let sim = Simulation::new(scenario).map_err(|e| Failure::Simulation(e, None))?;
        run(&sim, out)
    });
    let columns = result.map_err(|f| match f {
        Failure::Simulation(e, row) => simulation_error(py, &e, row),
        Failure::Output(e, path) => cli_error(py, &e, Some(&path)),
        Failure::Memory(n) => PyMemoryError::new_err(format!(
            "{n} samples of {NUM_COLUMNS} columns do not fit in memory: lower rate_hz"
        )),
    })?;
    let table = PyDict::new(py);
    for (name, values) in COLUMNS.iter().zip(columns) {
        table.set_item(*name, values.into_pyarray(py))?;
    }
    Ok(table)
}
