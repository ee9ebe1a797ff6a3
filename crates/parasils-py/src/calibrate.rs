//! `parasils.calibrate`: module 1's geometry fitted to actuator readings at
//! measured poses, by the calibration library (`parasils-calib`), the same
//! code as `parasils calibrate`.

use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use parasils_calib::{FitOptions, Measurement, Sigma, calibrate};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::robot::Robot;

/// The rows of an `(N, width)` array, checked.
fn rows<const W: usize>(name: &str, a: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<[f64; W]>> {
    let shape = a.shape();
    if shape.len() != 2 || shape[1] != W {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (N, {W}), got {shape:?}"
        )));
    }
    let view = a.as_array();
    Ok(view
        .rows()
        .into_iter()
        .map(|r| core::array::from_fn(|k| r[k]))
        .collect())
}

/// _calibrate(robot, q, poses, sigma) -> (Robot, str)
///
/// The fit behind `parasils.calibrate` (which documents it): `q` (N, 6) mm,
/// `poses` (N, 6) mm and rad, `sigma` None or (1, 3) or (N, 3):
/// readings mm, position mm, angles rad. Returns the fitted robot and the
/// report as JSON.
#[pyfunction]
#[pyo3(signature = (robot, q, poses, sigma=None))]
pub fn _calibrate(
    py: Python<'_>,
    robot: &Robot,
    q: PyReadonlyArray2<'_, f64>,
    poses: PyReadonlyArray2<'_, f64>,
    sigma: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<(Robot, String)> {
    let q = rows::<6>("q", &q)?;
    let poses = rows::<6>("poses", &poses)?;
    if q.len() != poses.len() {
        return Err(PyValueError::new_err(format!(
            "q has {} rows and poses {}: one reading row per pose",
            q.len(),
            poses.len()
        )));
    }
    let sigma = match &sigma {
        None => vec![[0.0; 3]],
        Some(s) => rows::<3>("sigma", s)?,
    };
    if sigma.len() != 1 && sigma.len() != q.len() {
        return Err(PyValueError::new_err(format!(
            "sigma must have 3 values or one row of 3 per pose ({}), got {} rows",
            q.len(),
            sigma.len()
        )));
    }
    let data: Vec<Measurement> = q
        .iter()
        .zip(&poses)
        .enumerate()
        .map(|(k, (q, p))| {
            let s = sigma.get(k).unwrap_or(&sigma[0]);
            Measurement {
                q_mm: *q,
                pose: [
                    p[0],
                    p[1],
                    p[2],
                    p[3].to_degrees(),
                    p[4].to_degrees(),
                    p[5].to_degrees(),
                ],
                sigma: Sigma {
                    q_mm: s[0],
                    position_mm: s[1],
                    angle_deg: s[2].to_degrees(),
                },
            }
        })
        .collect();
    let nominal = *robot.geometry();
    let fit = py
        .detach(|| calibrate(&nominal.module1, &data, &FitOptions::default()))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let mut geometry = nominal;
    geometry.module1 = fit.geometry;
    Ok((Robot::from_geometry(py, geometry)?, fit.report.to_json()))
}
