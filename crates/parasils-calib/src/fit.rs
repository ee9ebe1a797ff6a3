//! The fit: Levenberg-Marquardt on the weighted inverse-kinematic residual
//! `q_measured - q_ik(pose; x)` over the identifiable parameters, then
//! their standard deviations and the observability indices.
//!
//! **Weighting.** Without standard deviations every equation weighs the
//! same (mm). With them, the six equations of a pose are whitened by the
//! Cholesky factor of their covariance `C = s_q^2 I + J_p S_p J_p^T`, where
//! `J_p = d q / d pose` and `S_p = diag(s_pos^2 (x3), s_ang^2 (x3))`: the
//! pose's measurement noise maps through the inverse kinematics and
//! correlates the six readings of a pose (the errors-in-variables model to
//! first order). `C` is evaluated at the nominal geometry for a first fit,
//! then once more at its result for the final one.
//!
//! **Iterations.** The step solves `(J^T J + lambda diag(J^T J)) d = -J^T r`
//! on the scaled parameters (Marquardt's scaling); `lambda` follows
//! Nielsen's rule. A trial step at which a measured pose is out of reach is
//! refused like one that increases the residual. Converged when a step is
//! below `1e-12` of the scaled parameters' norm, when the gradient is
//! orthogonal to the residual to `1e-13`, or when no step can decrease the
//! residual any more (the predicted decrease is below `1e-10` of it).

use nalgebra::{DMatrix, DVector, Matrix6};
use parasils_kin::{Calibration, ParallelGeometry};

use crate::data::{self, Measurement};
use crate::error::CalibError;
use crate::identify::{self, Selection};
use crate::model::{Model, PoseEval};
use crate::params::{PARAMETERS, Parameter, ParameterMap};
use crate::report::{FixedParameter, Identified, Observability, Outcome, Report, Worst};

/// The parameters the data cannot see in any case: each guide point along
/// its own direction against the encoder offset.
pub const STRUCTURAL_DEFICIENCY: usize = 6;

/// The fit's options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Levenberg-Marquardt iterations at most (per pass).
    pub max_iterations: u32,
    /// A parameter is fixed to its nominal value when the kept parameters
    /// with it would have a normalised identification Jacobian (unit
    /// columns) whose smallest singular value is below this
    /// ([`identify::select`]).
    pub rank_tolerance: f64,
    /// A length that moves farther than this from its nominal value means
    /// divergence, mm.
    pub max_change_mm: f64,
    /// A guide direction that tilts farther than this from its nominal one
    /// means divergence, deg.
    pub max_tilt_deg: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            rank_tolerance: 1e-3,
            max_change_mm: 50.0,
            max_tilt_deg: 20.0,
        }
    }
}

/// A fitted geometry and its report.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The fitted module 1: `assumed = false`, with its [`Calibration`]
    /// record.
    pub geometry: ParallelGeometry<f64>,
    /// The fitted parameter vector.
    pub vector: [f64; PARAMETERS],
    /// What the fit found.
    pub report: Report,
}

/// Every pose's readings and derivatives, or the first out of reach.
fn eval_all(model: &Model, data: &[Measurement]) -> Result<Vec<PoseEval>, CalibError> {
    data.iter()
        .enumerate()
        .map(|(k, m)| {
            model
                .eval(&m.pose, true)
                .map_err(|e| CalibError::OutOfReach {
                    row: k + 1,
                    actuator: e.actuator,
                    discriminant_mm2: e.discriminant_mm2,
                })
        })
        .collect()
}

/// Per pose, the inverse of the lower Cholesky factor of the readings'
/// covariance (identity without standard deviations).
fn whitening(
    evals: &[PoseEval],
    data: &[Measurement],
    weighted: bool,
) -> Result<Vec<Matrix6<f64>>, CalibError> {
    evals
        .iter()
        .zip(data)
        .enumerate()
        .map(|(k, (e, m))| {
            if !weighted {
                return Ok(Matrix6::identity());
            }
            let s = m.sigma;
            let var = [
                s.position_mm.powi(2),
                s.position_mm.powi(2),
                s.position_mm.powi(2),
                s.angle_deg.powi(2),
                s.angle_deg.powi(2),
                s.angle_deg.powi(2),
            ];
            let jp = Matrix6::from_fn(|r, c| e.d_pose[r][c]);
            let sp = Matrix6::from_diagonal(&var.into());
            let c = Matrix6::identity() * s.q_mm.powi(2) + jp * sp * jp.transpose();
            let l = c
                .cholesky()
                .ok_or(CalibError::ZeroSigma { row: k + 1 })?
                .l();
            l.try_inverse().ok_or(CalibError::ZeroSigma { row: k + 1 })
        })
        .collect()
}

/// The raw residuals `q_measured - q_predicted`, mm, pose by pose.
fn raw_residuals(evals: &[PoseEval], data: &[Measurement]) -> Vec<[f64; 6]> {
    evals
        .iter()
        .zip(data)
        .map(|(e, m)| core::array::from_fn(|j| m.q_mm[j] - e.q_mm[j]))
        .collect()
}

/// The whitened residual and its Jacobian over the `kept` scaled
/// parameters (`d r / d z`, `x = x0 + scale z`).
fn assemble(
    evals: &[PoseEval],
    data: &[Measurement],
    white: &[Matrix6<f64>],
    kept: &[usize],
    scales: &[f64; PARAMETERS],
) -> (DVector<f64>, DMatrix<f64>) {
    let m = 6 * evals.len();
    let mut r = DVector::zeros(m);
    let mut jm = DMatrix::zeros(m, kept.len());
    let mut raw_j = DMatrix::zeros(6, kept.len());
    for (k, ((e, d), w)) in evals.iter().zip(data).zip(white).enumerate() {
        let raw = nalgebra::Vector6::from_fn(|j, _| d.q_mm[j] - e.q_mm[j]);
        r.rows_mut(6 * k, 6).copy_from(&(w * raw));
        for (c, &p) in kept.iter().enumerate() {
            for j in 0..6 {
                raw_j[(j, c)] = -e.d_params[j][p] * scales[p];
            }
        }
        jm.rows_mut(6 * k, 6).copy_from(&(w * &raw_j));
    }
    (r, jm)
}

/// The scaled, unweighted Jacobian over `columns` (`d q / d z`).
pub(crate) fn scaled_jacobian(
    evals: &[PoseEval],
    columns: &[usize],
    scales: &[f64; PARAMETERS],
) -> DMatrix<f64> {
    DMatrix::from_fn(6 * evals.len(), columns.len(), |r, c| {
        let p = columns[c];
        evals[r / 6].d_params[r % 6][p] * scales[p]
    })
}

/// The observability indices of a scaled Jacobian.
pub fn observability(j: &DMatrix<f64>) -> Observability {
    let s = j.singular_values();
    let max = s.max();
    let min = s.min();
    Observability {
        singular_value_max: max,
        singular_value_min: min,
        condition_number: max / min,
        noise_amplification_index: min * min / max,
    }
}

fn rms(res: &[[f64; 6]]) -> f64 {
    let n = (6 * res.len()).max(1) as f64;
    (res.iter().flatten().map(|v| v * v).sum::<f64>() / n).sqrt()
}

struct Lm<'a> {
    map: &'a ParameterMap,
    data: &'a [Measurement],
    white: &'a [Matrix6<f64>],
    kept: &'a [usize],
    scales: &'a [f64; PARAMETERS],
    nominal: [f64; PARAMETERS],
    options: &'a FitOptions,
}

impl Lm<'_> {
    fn evaluate(&self, x: &[f64; PARAMETERS]) -> Result<Vec<PoseEval>, CalibError> {
        eval_all(&Model::new(self.map, x), self.data)
    }

    /// `Err(reason)` when a kept parameter left its bound.
    fn check_bounds(&self, x: &[f64; PARAMETERS]) -> Result<(), String> {
        for &p in self.kept {
            let change = x[p] - self.nominal[p];
            match Parameter::from_index(p) {
                Some(Parameter::GuideDirection { guide, .. }) => {
                    let u0 = self.map.nominal().guides[guide].direction;
                    let u = self.map.raw_direction(x, guide).normalize();
                    let tilt = u.dot(&u0).clamp(-1.0, 1.0).acos().to_degrees();
                    if !(tilt <= self.options.max_tilt_deg) {
                        return Err(format!(
                            "guides[{guide}].direction tilted {tilt:.3} deg from the nominal, beyond the {} deg bound",
                            self.options.max_tilt_deg
                        ));
                    }
                }
                Some(param) if !(change.abs() <= self.options.max_change_mm) => {
                    return Err(format!(
                        "{} moved {change:.3} mm from the nominal, beyond the {} mm bound",
                        param.name(),
                        self.options.max_change_mm
                    ));
                }
                Some(_) => {}
                None => {}
            }
        }
        Ok(())
    }

    fn run(&self, start: [f64; PARAMETERS]) -> Result<([f64; PARAMETERS], Outcome), CalibError> {
        let n = self.kept.len();
        let mut x = start;
        let mut evals = self.evaluate(&x)?;
        let (mut r, mut jm) = assemble(&evals, self.data, self.white, self.kept, self.scales);
        let mut cost = r.norm_squared();
        let (mut lambda, mut nu) = (1e-3, 2.0);
        let rms_of = |evals: &[PoseEval]| rms(&raw_residuals(evals, self.data));
        let mut last_step = f64::INFINITY;
        for iteration in 1..=self.options.max_iterations {
            let g = jm.tr_mul(&r);
            let a = jm.tr_mul(&jm);
            let r_norm = cost.sqrt();
            let cosine = (0..n)
                .map(|k| g[k].abs() / (a[(k, k)].sqrt() * r_norm).max(f64::MIN_POSITIVE))
                .fold(0.0, f64::max);
            if cost == 0.0 || cosine <= 1e-13 {
                return Ok((
                    x,
                    Outcome {
                        iterations: iteration - 1,
                        converged_by: "gradient",
                    },
                ));
            }
            let diag_floor = 1e-12 * (0..n).map(|k| a[(k, k)]).fold(0.0, f64::max);
            loop {
                let mut damped = a.clone();
                for k in 0..n {
                    damped[(k, k)] += lambda * a[(k, k)].max(diag_floor);
                }
                let step = damped.cholesky().map(|c| c.solve(&(-&g)));
                let Some(delta) = step.filter(|d| d.iter().all(|v| v.is_finite())) else {
                    lambda *= nu;
                    nu *= 2.0;
                    continue;
                };
                let predicted = -(2.0 * g.dot(&delta) + delta.dot(&(&a * &delta)));
                let mut trial = x;
                for (c, &p) in self.kept.iter().enumerate() {
                    trial[p] += delta[c] * self.scales[p];
                }
                let trial_evals = self.evaluate(&trial);
                let accepted = match trial_evals {
                    Ok(trial_evals) => {
                        let (tr, tj) =
                            assemble(&trial_evals, self.data, self.white, self.kept, self.scales);
                        let trial_cost = tr.norm_squared();
                        let rho = (cost - trial_cost) / predicted;
                        if trial_cost.is_finite() && predicted > 0.0 && rho > 1e-4 {
                            Some((trial_evals, tr, tj, trial_cost, rho))
                        } else {
                            None
                        }
                    }
                    Err(_) => None,
                };
                if let Some((trial_evals, tr, tj, trial_cost, rho)) = accepted {
                    x = trial;
                    evals = trial_evals;
                    r = tr;
                    jm = tj;
                    cost = trial_cost;
                    self.check_bounds(&x)
                        .map_err(|reason| CalibError::Diverged {
                            iteration,
                            rms_mm: rms_of(&evals),
                            reason,
                        })?;
                    lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    last_step = delta.norm();
                    let size: f64 = self
                        .kept
                        .iter()
                        .map(|&p| (x[p] / self.scales[p]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    if last_step <= 1e-12 * (size + 1e-12) {
                        return Ok((
                            x,
                            Outcome {
                                iterations: iteration,
                                converged_by: "step",
                            },
                        ));
                    }
                    break;
                }
                if !(predicted > 1e-10 * cost) {
                    return Ok((
                        x,
                        Outcome {
                            iterations: iteration,
                            converged_by: "no decrease",
                        },
                    ));
                }
                lambda *= nu;
                nu *= 2.0;
                if lambda > 1e16 {
                    return Err(CalibError::Diverged {
                        iteration,
                        rms_mm: rms_of(&evals),
                        reason: format!(
                            "no step reduces the residual (the model predicts a decrease of {predicted:e} of the weighted sum of squares {cost:e})"
                        ),
                    });
                }
            }
        }
        Err(CalibError::MaxIterations {
            iterations: self.options.max_iterations,
            rms_mm: rms_of(&evals),
            step: last_step,
        })
    }
}

/// Fits module 1's geometry to `data`, starting from (and fixing the
/// unidentifiable parameters at) `nominal`.
///
/// Errors: a non-finite value or a negative standard deviation
/// ([`CalibError::BadValue`]), standard deviations in some rows only
/// ([`CalibError::ZeroSigma`]), an invalid nominal robot
/// ([`CalibError::Robot`]), a pose out of its reach
/// ([`CalibError::OutOfReach`]), too few poses
/// ([`CalibError::TooFewPoses`]), divergence ([`CalibError::Diverged`]) and
/// no convergence ([`CalibError::MaxIterations`]); each names the row or
/// the parameter.
pub fn calibrate(
    nominal: &ParallelGeometry<f64>,
    data: &[Measurement],
    options: &FitOptions,
) -> Result<Fit, CalibError> {
    data::check(data)?;
    let map = ParameterMap::new(nominal)?;
    let poses = data.len();
    let too_few = |parameters: usize| CalibError::TooFewPoses {
        poses,
        equations: 6 * poses,
        parameters,
        needed: parameters / 6 + 1,
    };
    if 6 * poses <= PARAMETERS - STRUCTURAL_DEFICIENCY {
        return Err(too_few(PARAMETERS - STRUCTURAL_DEFICIENCY));
    }
    let weighted = data.iter().any(|m| !m.sigma.is_zero());
    let scales = map.scales();
    let x0 = map.nominal_vector();
    let evals0 = eval_all(&Model::new(&map, &x0), data)?;
    let white0 = whitening(&evals0, data, weighted)?;
    let all: Vec<usize> = (0..PARAMETERS).collect();
    let (_, j_all) = assemble(&evals0, data, &white0, &all, &scales);
    let selection = identify::select(&j_all, options.rank_tolerance, &scales);
    if 6 * poses <= selection.kept.len() {
        return Err(too_few(selection.kept.len()));
    }
    let mut lm = Lm {
        map: &map,
        data,
        white: &white0,
        kept: &selection.kept,
        scales: &scales,
        nominal: x0,
        options,
    };
    let (mut x, mut outcome) = lm.run(x0)?;
    let white1;
    if weighted {
        white1 = whitening(&lm.evaluate(&x)?, data, true)?;
        lm.white = &white1;
        let (x1, second) = lm.run(x)?;
        x = x1;
        outcome.iterations += second.iterations;
        outcome.converged_by = second.converged_by;
    }
    let evals = lm.evaluate(&x)?;
    let (r, jm) = assemble(&evals, data, lm.white, &selection.kept, &scales);
    let residuals = raw_residuals(&evals, data);
    let rms_after = rms(&residuals);
    let dof = (r.len() - selection.kept.len()) as f64;
    let variance_factor = r.norm_squared() / dof;
    let svd = jm.svd(false, true);
    let v_t = svd.v_t.unwrap_or_else(|| DMatrix::zeros(0, 0));
    let std_dev = |c: usize| -> f64 {
        let s2: f64 = (0..svd.singular_values.len())
            .map(|i| (v_t[(i, c)] / svd.singular_values[i]).powi(2))
            .sum();
        (variance_factor * s2).sqrt()
    };
    let identified = selection
        .kept
        .iter()
        .enumerate()
        .filter_map(|(c, &p)| {
            let param = Parameter::from_index(p)?;
            Some(Identified {
                name: param.name(),
                unit: param.unit(),
                nominal: x0[p],
                fitted: x[p],
                change: x[p] - x0[p],
                std_dev: std_dev(c) * scales[p],
            })
        })
        .collect();
    let worst = worst(&residuals);
    let observability = observability(&scaled_jacobian(&evals, &selection.kept, &scales));
    let mut geometry = map.geometry(&x);
    geometry.assumed = false;
    geometry.calibration = Some(Calibration {
        poses: u32::try_from(poses).unwrap_or(u32::MAX),
        rms_mm: rms_after,
    });
    let report = Report {
        poses,
        equations: 6 * poses,
        weighting: if weighted {
            String::from(
                "per pose, by the covariance of its six readings: sigma_q_mm^2 I + J_pose diag(sigma_position_mm^2, sigma_angle_deg^2) J_pose^T",
            )
        } else {
            String::from("none: every equation weighs the same (mm)")
        },
        outcome,
        rms_before_mm: rms(&raw_residuals(&evals0, data)),
        rms_after_mm: rms_after,
        worst_after: worst,
        variance_factor,
        identified,
        fixed: fixed_report(&selection, &x0),
        observability,
    };
    Ok(Fit {
        geometry,
        vector: x,
        report,
    })
}

fn worst(residuals: &[[f64; 6]]) -> Worst {
    let mut w = Worst {
        row: 1,
        actuator: 1,
        residual_mm: 0.0,
    };
    for (k, row) in residuals.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            if v.abs() > w.residual_mm.abs() {
                w = Worst {
                    row: k + 1,
                    actuator: j as u8 + 1,
                    residual_mm: v,
                };
            }
        }
    }
    w
}

fn fixed_report(selection: &Selection, x0: &[f64; PARAMETERS]) -> Vec<FixedParameter> {
    let name = |p: usize| Parameter::from_index(p).map_or_else(String::new, Parameter::name);
    selection
        .fixed
        .iter()
        .map(|f| {
            let param = Parameter::from_index(f.index);
            let combination: Vec<String> = f
                .equivalent
                .iter()
                .map(|(p, c)| format!("{} by {c:.6}", name(*p)))
                .collect();
            let reason = if f.independence == 0.0 && f.equivalent.is_empty() {
                String::from("no measured reading depends on it")
            } else if f.independence <= 1e-6 {
                format!(
                    "not observable: changing it by 1 changes the readings as changing {} does (independent part {:.1e} of its column)",
                    combination.join(", "),
                    f.independence
                )
            } else {
                format!(
                    "poorly observable from these poses: with it the smallest singular value of the normalised Jacobian would be {:.1e}, below the tolerance; its nearest combination is {}",
                    f.smallest,
                    combination.join(", ")
                )
            };
            FixedParameter {
                name: name(f.index),
                unit: param.map_or("mm", Parameter::unit),
                value: x0[f.index],
                reason,
                equivalent_to: f.equivalent.iter().map(|(p, c)| (name(*p), *c)).collect(),
            }
        })
        .collect()
}
