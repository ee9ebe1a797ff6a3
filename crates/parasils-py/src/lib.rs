//! Python bindings of parasils: the extension module `parasils._parasils`,
//! which the Python package `parasils` (`python/parasils/__init__.py`)
//! re-exports.
//!
//! The bindings only convert: the numbers come from `parasils-kin` (the
//! solvers, the same code as the firmware) and from `parasils-sim` (the
//! simulation library, the same code as the `parasils` command), so that a
//! notebook, the CLI and the firmware agree to the last bit.
//!
//! - [`robot`]: `parasils.Robot`, the solvers on one sample or a batch of
//!   NumPy rows, looped in Rust without the GIL;
//! - [`teleop`]: `parasils.teleop`, a recorded teleoperation session
//!   replayed by the simulation library, returning the CLI's table;
//! - [`simulate`]: `parasils.simulate`, the simulation library's run
//!   returning the CSV's table as NumPy columns (the package's Python
//!   wrapper gives it its signature, with the paper's defaults from
//!   `PAPER`);
//! - [`reach`]: `Robot.reach_map`, the simulation library's reach map as
//!   NumPy arrays;
//! - [`calibrate`]: `parasils.calibrate`, module 1's geometry fitted to
//!   measured poses by the calibration library (the package's Python
//!   wrapper turns the report into a dict);
//! - [`tolerance`]: `parasils.ToleranceStudy`, the tolerance library's
//!   study on NumPy columns, picklable for Dask and Ray workers (the
//!   package's `parasils.tolerance` maps its chunks over a Dask cluster);
//! - [`clearance`]: `parasils.segment_distance_mm`, the segment distance
//!   kernel of `parasils-kin` on NumPy batches;
//! - [`errors`]: the exception hierarchy (`KinematicsError` and its
//!   subclasses, `TrajectoryError`, `RobotFileError`);
//! - [`batch`]: shapes, broadcasting, the loop (split across threads for
//!   large batches, `parasils.batch_threads()`) and the `errors="nan"` mask;
//! - [`kernels`]: the instrument IK's batches on `parasils-batch`'s vector
//!   kernels (`PARASILS_BATCH_KERNEL` forces a level).
//!
//! Built by maturin (`pyproject.toml`); its tests are in Python (`tests/`,
//! run by `scripts/python-tests`).

use pyo3::prelude::*;

pub mod batch;
pub mod calibrate;
pub mod clearance;
pub mod errors;
pub mod kernels;
pub mod path;
pub mod reach;
pub mod robot;
pub mod simulate;
pub mod teleop;
pub mod tolerance;

/// Kinematics and motion of PARA-SILSROB from Python (the compiled part of
/// the `parasils` package; import `parasils`).
#[pymodule]
fn _parasils(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "COLUMNS",
        pyo3::types::PyTuple::new(m.py(), parasils_sim::columns::CSV_NAMES)?,
    )?;
    m.add("PAPER", simulate::paper_defaults(m.py())?)?;
    m.add_class::<robot::Robot>()?;
    m.add_class::<tolerance::ToleranceStudy>()?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(teleop::teleop, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_threads, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate::_calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(clearance::segment_distance_mm, m)?)?;
    errors::register(m)?;
    Ok(())
}
