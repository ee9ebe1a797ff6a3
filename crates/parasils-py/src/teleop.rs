//! `parasils.teleop`: a recorded teleoperation session replayed by the
//! simulation library's [`Replay`] (the loop `parasils teleop --input`
//! runs), returning the CLI's CSV table as NumPy columns (and writing CSV or
//! MCAP with `out=`).

use core::convert::Infallible;
use std::path::PathBuf;

use parasils::teleop::TeleopParams;
use parasils_device::Recording;
use parasils_sim::teleop::CSV_WITH_TELEOP;
use parasils_sim::{Format, Input, OutputFile, Record, Replay, RunError, SETTLE_S, Tee};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::batch::ArrayArg;
use crate::simulate::{fixed, input_error, robot_source, simulation_error};

/// The compiled part of `parasils.teleop` (see its docstring in
/// `python/parasils/__init__.py`): `input` the session's CSV file, the rest
/// keyword-only, `None` when not given, translated into the simulation
/// library's [`Input`] as `simulate`'s are.
#[pyfunction]
#[pyo3(signature = (
    input,
    *,
    rate_hz = None,
    pose_mm_deg = None,
    tip_left_mm = None,
    tip_right_mm = None,
    robot = None,
    settle_s = None,
    out = None,
    format = None,
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn teleop<'py>(
    py: Python<'py>,
    input: PathBuf,
    rate_hz: Option<f64>,
    pose_mm_deg: Option<ArrayArg<'py>>,
    tip_left_mm: Option<ArrayArg<'py>>,
    tip_right_mm: Option<ArrayArg<'py>>,
    robot: Option<Bound<'py, PyAny>>,
    settle_s: Option<f64>,
    out: Option<PathBuf>,
    format: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let format = match (format, &out) {
        (None, None) => None,
        (Some("csv"), _) => Some(Format::Csv),
        (Some("mcap"), _) => Some(Format::Mcap),
        (None, Some(p)) => {
            Some(Format::from_path(p).map_err(|e| PyValueError::new_err(e.to_string()))?)
        }
        (Some(f), _) => {
            return Err(PyValueError::new_err(format!(
                "format must be 'csv' or 'mcap', got {f:?}"
            )));
        }
    };
    let scenario = Input {
        rate_hz,
        pose_mm_deg: fixed::<6>(pose_mm_deg, "pose_mm_deg")?,
        tip_left_mm: fixed::<3>(tip_left_mm, "tip_left_mm")?,
        tip_right_mm: fixed::<3>(tip_right_mm, "tip_right_mm")?,
        robot: robot.map(|r| robot_source(&r)).transpose()?,
        ..Input::default()
    }
    .resolve()
    .map_err(|e| input_error(py, e))?;
    let recording = Recording::read(&input).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let replay = Replay::new(
        scenario,
        TeleopParams::assumed(),
        recording,
        settle_s.unwrap_or(SETTLE_S),
    )
    .map_err(|e| simulation_error(py, &e))?;
    let columns = &CSV_WITH_TELEOP;
    let table = py.detach(move || -> Result<Vec<Vec<f64>>, String> {
        let mut table: Vec<Vec<f64>> = columns
            .iter()
            .map(|_| Vec::with_capacity(replay.cycle_count()))
            .collect();
        let mut file = match (&out, format) {
            (Some(p), Some(f)) => Some(
                OutputFile::create_with(p, f, replay.scenario(), columns)
                    .map_err(|e| e.to_string())?,
            ),
            _ => None,
        };
        let mut keep = |r: &Record| {
            for (values, column) in table.iter_mut().zip(columns) {
                values.push(column.value(r));
            }
            Ok::<(), Infallible>(())
        };
        match replay.run(&mut Tee::new().with_some(file.as_mut()).with(&mut keep)) {
            Ok(()) => {}
            Err(RunError::Simulation(e)) => return Err(e.to_string()),
            Err(RunError::Sink(e)) => return Err(e.to_string()),
        }
        if let Some(f) = file {
            f.finish().map_err(|e| e.to_string())?;
        }
        Ok(table)
    });
    let table = table.map_err(PyValueError::new_err)?;
    crate::simulate::columns_dict(py, columns, table)
}
