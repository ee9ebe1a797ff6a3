//! `Robot.reach_map`: the simulation library's reach map as NumPy arrays.

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use parasils_reach::{Constraint, ReachError, ReachMap, ReachOptions};
use parasils_sim::{Scenario, SimulationError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::batch::{ArrayArg, Rows};
use crate::errors;
use parasils_kin::RobotGeometry;

/// The Python exception of a map that cannot be made.
fn reach_error(py: Python<'_>, error: &ReachError) -> PyErr {
    match error {
        ReachError::Scenario(SimulationError::Geometry(e)) => {
            errors::kinematics(py, e, None, None, "robot geometry: ")
        }
        ReachError::Scenario(SimulationError::Kinematics { error, .. }) => {
            errors::kinematics(py, error, None, None, "")
        }
        e => PyValueError::new_err(e.to_string()),
    }
}

/// A `(rows, cols)` array of `values`.
fn grid<'py, T: numpy::Element>(
    py: Python<'py>,
    shape: (usize, usize),
    values: Vec<T>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(Array2::from_shape_vec(shape, values)
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .into_pyarray(py)
        .into_any())
}

/// `robot.reach_map(...)`: see the method's docs in `robot.rs`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn reach_map<'py>(
    py: Python<'py>,
    geometry: &RobotGeometry<f64>,
    pose: ArrayArg<'py>,
    tips: Option<ArrayArg<'py>>,
    psi_range: (f64, f64),
    theta_range: (f64, f64),
    step: f64,
    line: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let pose_rows = Rows::new(&pose, "pose", 6)?;
    if crate::batch::batch_size(&[("pose", &pose_rows)])?.is_some() {
        return Err(PyValueError::new_err("pose must have shape (6,)"));
    }
    let [x, y, z, psi, theta, phi] = pose_rows.get::<6>(0);
    let paper = Scenario::paper();
    let (tip_left_mm, tip_right_mm) = match &tips {
        None => (paper.tip_left_mm, None),
        Some(t) => {
            let rows = Rows::new(t, "tips", 3)?;
            if crate::batch::batch_size(&[("tips", &rows)])? != Some(2) {
                return Err(PyValueError::new_err(
                    "tips must have shape (2, 3): the left tip, then the right one (mm)",
                ));
            }
            (rows.get::<3>(0), Some(rows.get::<3>(1)))
        }
    };
    let scenario = Scenario {
        start_mm_deg: [
            x,
            y,
            z,
            psi.to_degrees(),
            theta.to_degrees(),
            phi.to_degrees(),
        ],
        tip_left_mm,
        tip_right_mm,
        robot: *geometry,
        ..paper
    };
    let options = ReachOptions {
        psi_range_deg: [psi_range.0.to_degrees(), psi_range.1.to_degrees()],
        theta_range_deg: [theta_range.0.to_degrees(), theta_range.1.to_degrees()],
        step_deg: step.to_degrees(),
        line,
        threads: crate::batch::threads()?,
    };
    let map = py
        .detach(|| ReachMap::compute(&scenario, &options))
        .map_err(|e| reach_error(py, &e))?;
    let shape = (map.theta.count, map.psi.count);
    let dict = PyDict::new(py);
    let axis = |a: &parasils_reach::Axis| {
        (0..a.count)
            .map(|i| a.value_deg(i).to_radians())
            .collect::<Vec<_>>()
    };
    dict.set_item("dpsi", axis(&map.psi).into_pyarray(py))?;
    dict.set_item("dtheta", axis(&map.theta).into_pyarray(py))?;
    let cells = &map.cells;
    dict.set_item(
        "feasible",
        grid(py, shape, cells.iter().map(|c| c.feasible).collect())?,
    )?;
    dict.set_item(
        "reachable",
        grid(py, shape, cells.iter().map(|c| c.reachable).collect())?,
    )?;
    if line {
        let lines = cells.iter().map(|c| c.line == Some(true)).collect();
        dict.set_item("line", grid(py, shape, lines)?)?;
    } else {
        dict.set_item("line", py.None())?;
    }
    let codes = |c: Constraint| i64::try_from(c.index()).unwrap_or(-1);
    dict.set_item(
        "limiting",
        grid(py, shape, cells.iter().map(|c| codes(c.limiting)).collect())?,
    )?;
    dict.set_item(
        "margin",
        grid(py, shape, cells.iter().map(|c| c.margin).collect())?,
    )?;
    let names: Vec<&str> = Constraint::all()
        .into_iter()
        .map(Constraint::code)
        .collect();
    dict.set_item("codes", PyTuple::new(py, names)?)?;
    let points = &map.boundary.points;
    let mut xy = Vec::with_capacity(2 * points.len());
    for p in points {
        let [a, b] = p.deg();
        xy.extend([a.to_radians(), b.to_radians()]);
    }
    dict.set_item("boundary_points", grid(py, (points.len(), 2), xy)?)?;
    dict.set_item(
        "boundary_limiting",
        points
            .iter()
            .map(|p| codes(p.limiting))
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    let lines = PyList::empty(py);
    for l in &map.boundary.polylines {
        let mut idx: Vec<i64> = l
            .points
            .iter()
            .map(|&i| i64::try_from(i).unwrap_or(-1))
            .collect();
        if l.closed
            && let Some(&first) = idx.first()
        {
            idx.push(first);
        }
        lines.append(idx.into_pyarray(py))?;
    }
    dict.set_item("boundary", lines)?;
    dict.set_item("module1_assumed", map.module1_assumed)?;
    Ok(dict)
}
