//! `Robot.reach_map`: the reach map (`parasils-reach`) as NumPy arrays.

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use parasils_reach::{Constraint, ReachError, ReachMap, ReachOptions};
use parasils_sim::{Scenario, SimulationError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::batch::{ArrayArg, Rows};
use crate::errors;
use parasils_sim::{Anatomy, AnatomyError, Robot};
use pyo3::exceptions::PyOSError;
use std::path::Path;
use std::sync::Arc;

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

/// A range of increments, (min, max).
type Range = (f64, f64);

/// The grid a reach map is asked for, in the command line's degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Grid {
    psi_range_deg: Range,
    theta_range_deg: Range,
    step_deg: f64,
}

impl Grid {
    /// The defaults of `Robot.reach_map`, the library's (`ReachOptions`).
    fn defaults() -> Self {
        let o = ReachOptions::default();
        Self {
            psi_range_deg: (o.psi_range_deg[0], o.psi_range_deg[1]),
            theta_range_deg: (o.theta_range_deg[0], o.theta_range_deg[1]),
            step_deg: o.step_deg,
        }
    }

    /// The grid from `Robot.reach_map`'s arguments: the deprecated ones in
    /// rad (`psi_range`, `theta_range`, `step`; each warns), then those in
    /// deg.
    pub(crate) fn of(
        py: Python<'_>,
        (psi_range, theta_range, step): (Option<Range>, Option<Range>, Option<f64>),
        (psi_range_deg, theta_range_deg, step_deg): (Range, Range, f64),
    ) -> PyResult<Self> {
        let method = "Robot.reach_map";
        let d = Self::defaults();
        let deg = |(a, b): (f64, f64)| (a.to_degrees(), b.to_degrees());
        Ok(Self {
            psi_range_deg: errors::renamed_argument(
                py,
                method,
                ("psi_range", psi_range.map(deg)),
                ("psi_range_deg", psi_range_deg, d.psi_range_deg),
            )?,
            theta_range_deg: errors::renamed_argument(
                py,
                method,
                ("theta_range", theta_range.map(deg)),
                ("theta_range_deg", theta_range_deg, d.theta_range_deg),
            )?,
            step_deg: errors::renamed_argument(
                py,
                method,
                ("step", step.map(f64::to_degrees)),
                ("step_deg", step_deg, d.step_deg),
            )?,
        })
    }
}

/// The anatomy file `path`, read: an `OSError` when it does not read, a
/// `ValueError` naming the region and key when it is wrong.
fn anatomy_of(path: &Path) -> PyResult<Arc<Anatomy>> {
    Anatomy::load(path).map(Arc::new).map_err(|e| match e {
        AnatomyError::Read { .. } => PyOSError::new_err(e.to_string()),
        e => PyValueError::new_err(e.to_string()),
    })
}

/// `robot.reach_map(...)`: see the method's docs in `robot.rs`.
pub(crate) fn reach_map<'py>(
    py: Python<'py>,
    robot: &Robot,
    pose: ArrayArg<'py>,
    tips: Option<ArrayArg<'py>>,
    grid_deg: Grid,
    (line, deflection_load_n): (bool, Option<[f64; 3]>),
    anatomy: Option<&Path>,
) -> PyResult<Bound<'py, PyDict>> {
    let anatomy = anatomy.map(anatomy_of).transpose()?;
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
        robot: robot.geometry,
        supervisor: robot.supervisor,
        bodies: robot.bodies,
        dynamics: robot.dynamics,
        stiffness: robot.stiffness,
        anatomy,
        ..paper
    };
    let options = ReachOptions {
        psi_range_deg: [grid_deg.psi_range_deg.0, grid_deg.psi_range_deg.1],
        theta_range_deg: [grid_deg.theta_range_deg.0, grid_deg.theta_range_deg.1],
        step_deg: grid_deg.step_deg,
        line,
        threads: crate::batch::threads()?,
        deflection_load_n,
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
    if deflection_load_n.is_some() {
        for (side, key) in [
            (0, "left_tip_deflection_mm"),
            (1, "right_tip_deflection_mm"),
        ] {
            let values = cells
                .iter()
                .map(|c| c.deflection_mm.map_or(f64::NAN, |d| d[side]))
                .collect();
            dict.set_item(key, grid(py, shape, values)?)?;
        }
    }
    let names: Vec<String> = map
        .constraints()
        .into_iter()
        .map(|c| map.code(c).into_owned())
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
