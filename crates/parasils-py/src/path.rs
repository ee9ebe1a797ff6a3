//! `Robot.reorientation_path` and `Robot.optimal_reorientation`: motion
//! type 4 as a path with its exact derivatives, and its time-optimal timing
//! under the actuators' limits, as NumPy arrays.

use numpy::IntoPyArray;
use numpy::ndarray::{Array1, Array2};
use parasils_kin::nalgebra::Vector3;
use parasils_kin::{Controller, Pose, TipTargets, default_right_tip, presets};
use parasils_sim::timing::{MotionPath, OptimalMotion, RobotState, TimingError, TimingOptions};
use parasils_traj::Limits;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::batch::{ArrayArg, Rows};
use crate::errors;

/// The start pose (6,) and the tips (2, 3), the paper's left tip and the
/// default right tip at `pose` (`default_right_tip`) when `tips` is None.
fn pose_and_tips(
    pose: &ArrayArg<'_>,
    tips: Option<&ArrayArg<'_>>,
) -> PyResult<(Pose<f64>, TipTargets<f64>)> {
    let rows = Rows::new(pose, "pose", 6)?;
    if crate::batch::batch_size(&[("pose", &rows)])?.is_some() {
        return Err(PyValueError::new_err("pose must have shape (6,)"));
    }
    let pose = Pose::from_array(rows.get::<6>(0));
    let tips = match tips {
        None => {
            let left = Vector3::from(presets::LEFT_TIP_MM);
            TipTargets {
                left,
                right: default_right_tip(&pose, &left),
            }
        }
        Some(t) => {
            let rows = Rows::new(t, "tips", 3)?;
            if crate::batch::batch_size(&[("tips", &rows)])? != Some(2) {
                return Err(PyValueError::new_err(
                    "tips must have shape (2, 3): the left tip, then the right one (mm)",
                ));
            }
            TipTargets {
                left: Vector3::from(rows.get::<3>(0)),
                right: Vector3::from(rows.get::<3>(1)),
            }
        }
    };
    Ok((pose, tips))
}

/// `robot.reorientation_path(...)`: see the method's docs in `robot.rs`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn reorientation_path<'py>(
    py: Python<'py>,
    controller: &Controller<f64>,
    pose: ArrayArg<'py>,
    tips: Option<ArrayArg<'py>>,
    dpsi: f64,
    dtheta: f64,
    s: ArrayArg<'py>,
    order: usize,
) -> PyResult<Bound<'py, PyAny>> {
    if order > 2 {
        return Err(PyValueError::new_err(format!(
            "order must be 0 (positions), 1 (first derivatives) or 2 (second), got {order}"
        )));
    }
    let (start, tips) = pose_and_tips(&pose, tips.as_ref())?;
    let state = RobotState::solved(controller, start, &tips, 0.0)
        .map_err(|e| errors::kinematics(py, &e, None, None, "path at s = 0: "))?;
    let goal = [start.psi + dpsi, start.theta + dtheta];
    let path = MotionPath::turning(controller, &state, goal, [tips.left, tips.right]);
    let s: Vec<f64> = s.as_array().iter().copied().collect();
    let n = s.len();
    let rows = py.detach(|| -> Result<Vec<f64>, (f64, parasils_kin::Error)> {
        let mut out = Vec::with_capacity(n * 12);
        for &si in &s {
            let p = path.point(si).map_err(|e| (si, e))?;
            out.extend_from_slice(match order {
                0 => &p.q,
                1 => &p.q_s,
                _ => &p.q_ss,
            });
        }
        Ok(out)
    });
    let rows = rows.map_err(|(si, e)| {
        errors::kinematics(py, &e, None, None, &format!("path at s = {si}: "))
    })?;
    Ok(Array2::from_shape_vec((n, 12), rows)
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .into_pyarray(py)
        .into_any())
}

/// `robot.optimal_reorientation(...)`: see the method's docs in `robot.rs`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn optimal_reorientation<'py>(
    py: Python<'py>,
    controller: &Controller<f64>,
    pose: ArrayArg<'py>,
    tips: Option<ArrayArg<'py>>,
    dpsi: f64,
    dtheta: f64,
    velocity_max: Option<ArrayArg<'py>>,
    acceleration_max: Option<ArrayArg<'py>>,
    omega_max: Option<f64>,
    eps_max: Option<f64>,
    knots: usize,
    checks: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let (start, tips) = pose_and_tips(&pose, tips.as_ref())?;
    // The robot's own limits (its robot file's), each overridden when given.
    let mut limits = controller.limits;
    for (arg, name, dst) in [
        (&velocity_max, "velocity_max", &mut limits.velocity),
        (
            &acceleration_max,
            "acceleration_max",
            &mut limits.acceleration,
        ),
    ] {
        if let Some(a) = arg {
            let values: Vec<f64> = a.as_array().iter().copied().collect();
            if values.len() != 12 || a.as_array().ndim() != 1 {
                return Err(PyValueError::new_err(format!(
                    "{name} must have shape (12,): q1..q6 (mm), then left and right qs1, qs2 (rad), qs3 (mm)"
                )));
            }
            dst.copy_from_slice(&values);
        }
    }
    let angular = match (omega_max, eps_max) {
        (None, None) => None,
        (w, e) => {
            let w = w.unwrap_or(f64::INFINITY);
            let e = e.unwrap_or(f64::INFINITY);
            Some([Limits::new(w, e); 2])
        }
    };
    let options = TimingOptions {
        knots,
        checks,
        angular,
    };
    let goal = [start.psi + dpsi, start.theta + dtheta];
    let plan = py
        .detach(|| OptimalMotion::turn(controller, start, goal, tips, &limits, &options))
        .map_err(|e| match e {
            TimingError::Kinematics { s, error } => {
                errors::kinematics(py, &error, None, None, &format!("path at s = {s}: "))
            }
            e => PyValueError::new_err(e.to_string()),
        })?;
    let out = PyDict::new(py);
    out.set_item("duration_s", plan.duration())?;
    let phases = PyList::empty(py);
    for p in plan.phases() {
        let d = PyDict::new(py);
        d.set_item("start_s", p.start_s)?;
        d.set_item("end_s", p.end_s)?;
        d.set_item("binding", p.binding.to_string())?;
        d.set_item("limit", p.kind.to_string())?;
        d.set_item("usage", p.usage)?;
        phases.append(d)?;
    }
    out.set_item("phases", phases)?;
    let knots = plan.schedule().knots();
    let column = |f: &dyn Fn(&parasils_traj::optimal::Knot<f64, 14>) -> f64| {
        Array1::from_iter(knots.iter().map(f)).into_pyarray(py)
    };
    out.set_item("s", column(&|k| k.s))?;
    out.set_item("t_s", column(&|k| k.t()))?;
    out.set_item("s_dot", column(&|k| k.s_dot()))?;
    out.set_item("s_ddot", column(&|k| k.s_ddot()))?;
    if let Some(c) = plan.certificate() {
        out.set_item("worst_before_check", c.worst)?;
        out.set_item("stretch", c.stretch)?;
        out.set_item("passes", c.passes)?;
    }
    Ok(out)
}
