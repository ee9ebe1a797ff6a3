//! The first-order model: the tips' and the platform's deviations as linear
//! functions of the [`Perturbation`]'s coordinates, from analytic
//! derivatives at every commanded sample, and the sensitivity ranking it
//! gives.
//!
//! Module 1: at fixed actuators `q(pose, x) = q_cmd`, so
//! `d pose = -(dq/dpose)^-1 (dq/dx) dx`, both Jacobians in closed form from
//! the calibration's model ([`parasils_calib::model`]). A tip
//! `p = R (rcm + l(q; alpha, beta)) + P` then moves by
//! `dP + (dR/dangles . v) d angles + R (d rcm + dl/dalpha d alpha +
//! dl/dbeta d beta)`, with `l = R_Y(alpha) R_X(qs1) R_Y(qs2) R_X(beta)
//! (0, 0, -qs3)` for the left module (`dl/dalpha = e_y x l`, `dl/dbeta =
//! R_Y R_X R_Y (e_x x R_X(beta) (0, 0, -qs3))`) and its mirror image
//! `S l`, `S = diag(-1, 1, 1)`, for the right.
//!
//! This is a second, independent account of the model error: it shares no
//! code with [`replay`](mod@crate::replay) (module 1's forward kinematics by
//! Newton, the instruments' forward kinematics), and the two agree to first
//! order (the crate's tests hold them within 2% for small tolerances).

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use parasils_calib::model::Model;
use parasils_calib::params::{NODES_START, PER_GUIDE};
use parasils_calib::{PARAMETERS, ParameterMap};
use parasils_kin::{Joints, RobotGeometry, Side};

use crate::perturbation::{COORDINATES, Perturbation};
use crate::replay::Deviation;
use crate::spec::{Family, Spec};
use crate::trace::Trace;

type Rows = SMatrix<f64, 3, COORDINATES>;

/// The first-order derivatives at one commanded sample.
#[derive(Debug, Clone, PartialEq)]
struct Sample {
    left: Rows,
    right: Rows,
    position: Rows,
    /// The rotation vector from the commanded orientation to the real one,
    /// rad.
    rotation: Rows,
}

/// The first-order model of a trace's model error.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearisation {
    samples: Vec<Sample>,
}

/// A point of the first-order model that cannot be formed: a commanded
/// pose where module 1 is singular or out of reach for its own model.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("the first-order model fails at sample {index}: {why}")]
pub struct LinearError {
    /// The trace's sample.
    pub index: usize,
    /// What failed.
    pub why: &'static str,
}

/// The family of coordinate `k` of a perturbation.
pub fn family_of(k: usize) -> Family {
    if k < NODES_START {
        match k % PER_GUIDE {
            0..=2 => Family::GuidePoint,
            3 | 4 => Family::GuideDirection,
            5 => Family::LinkLength,
            _ => Family::EncoderOffset,
        }
    } else if k < PARAMETERS {
        Family::LegNode
    } else {
        match (k - PARAMETERS) % 5 {
            0 => Family::Alpha,
            1 => Family::Beta,
            _ => Family::Rcm,
        }
    }
}

/// The variance of coordinate `k` under `spec` (in the coordinate's unit:
/// mm, rad, or a direction's dimensionless tangent component, whose
/// variance is half the tilt's, in rad, to first order).
fn variance(spec: &Spec, k: usize) -> f64 {
    let family = family_of(k);
    let Some(d) = spec.get(family) else {
        return 0.0;
    };
    let s = d.std_dev();
    match family {
        Family::GuideDirection => 0.5 * s.to_radians().powi(2),
        Family::Alpha | Family::Beta => s.to_radians().powi(2),
        _ => s * s,
    }
}

fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

fn rot_y(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

fn skew(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// The tip in the module's RCM frame and its derivatives with respect to
/// `alpha` and `beta` (rad).
fn local_tip(alpha: f64, beta: f64, side: Side, q: &Joints<f64>) -> [Vector3<f64>; 3] {
    let v0 = Vector3::new(0.0, 0.0, -q.qs3);
    let head = rot_y(alpha) * rot_x(q.qs1) * rot_y(q.qs2);
    let tail = rot_x(beta) * v0;
    let l = head * tail;
    let dl_alpha = Vector3::y().cross(&l);
    let dl_beta = head * Vector3::x().cross(&tail);
    let s = match side {
        Side::Left => Matrix3::identity(),
        Side::Right => Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0)),
    };
    [s * l, s * dl_alpha, s * dl_beta]
}

impl Linearisation {
    /// The first-order model of `trace`'s commands on `robot` (the
    /// nominal robot the trace was computed with).
    ///
    /// # Errors
    /// [`LinearError`] at a commanded pose where module 1's model is out of
    /// reach or its pose Jacobian is singular.
    pub fn new(robot: &RobotGeometry<f64>, trace: &Trace) -> Result<Self, LinearError> {
        let map = ParameterMap::new(&robot.module1).map_err(|_| LinearError {
            index: 0,
            why: "invalid module-1 geometry",
        })?;
        let model = Model::new(&map, &map.nominal_vector());
        let deg = core::f64::consts::PI / 180.0;
        let mut samples = Vec::with_capacity(trace.len());
        for (index, c) in trace.commands().iter().enumerate() {
            let p = c.pose;
            let mm_deg = [
                p.x,
                p.y,
                p.z,
                p.psi.to_degrees(),
                p.theta.to_degrees(),
                p.phi.to_degrees(),
            ];
            let eval = model.eval(&mm_deg, true).map_err(|_| LinearError {
                index,
                why: "module 1 out of reach",
            })?;
            let d_pose = SMatrix::<f64, 6, 6>::from_fn(|j, k| eval.d_pose[j][k]);
            let d_params = SMatrix::<f64, 6, PARAMETERS>::from_fn(|j, k| eval.d_params[j][k]);
            let Some(inverse) = d_pose.try_inverse() else {
                return Err(LinearError {
                    index,
                    why: "module 1's pose Jacobian is singular",
                });
            };
            // Pose deviation (mm, deg) per module-1 parameter.
            let m = -(inverse * d_params);
            let (rx, ry, rz) = (rot_x(p.psi), rot_y(p.theta), rot_z(p.phi));
            let r = rx * ry * rz;
            // dR/d angle, per deg.
            let d_r = [
                skew(&Vector3::x()) * r * deg,
                rx * skew(&Vector3::y()) * ry * rz * deg,
                r * skew(&Vector3::z()) * deg,
            ];
            let mut position = Rows::zeros();
            let mut rotation = Rows::zeros();
            for k in 0..PARAMETERS {
                let mut w = Vector3::zeros();
                for (a, d) in d_r.iter().enumerate() {
                    let dw = d * r.transpose();
                    w += Vector3::new(dw[(2, 1)], dw[(0, 2)], dw[(1, 0)]) * m[(3 + a, k)];
                }
                position.set_column(k, &Vector3::new(m[(0, k)], m[(1, k)], m[(2, k)]));
                rotation.set_column(k, &w);
            }
            let tip_rows =
                |g: &parasils_kin::InstrumentGeometry<f64>, q: &Joints<f64>, b: usize| {
                    let [l, dl_alpha, dl_beta] = local_tip(g.alpha, g.beta, g.side, q);
                    let v = g.rcm + l;
                    let mut rows = Rows::zeros();
                    for k in 0..PARAMETERS {
                        let mut col: Vector3<f64> = position.column(k).into();
                        for (a, d) in d_r.iter().enumerate() {
                            col += d * v * m[(3 + a, k)];
                        }
                        rows.set_column(k, &col);
                    }
                    rows.set_column(b, &(r * dl_alpha));
                    rows.set_column(b + 1, &(r * dl_beta));
                    for axis in 0..3 {
                        rows.set_column(b + 2 + axis, &r.column(axis).into_owned());
                    }
                    rows
                };
            samples.push(Sample {
                left: tip_rows(&robot.left, &c.left, PARAMETERS),
                right: tip_rows(&robot.right, &c.right, PARAMETERS + 5),
                position,
                rotation,
            });
        }
        Ok(Self { samples })
    }

    /// The first-order prediction of [`replay`](crate::replay::replay)'s
    /// result for `perturbation`.
    pub fn predict(&self, perturbation: &Perturbation) -> Deviation {
        let z = SVector::<f64, COORDINATES>::from(perturbation.coordinates());
        let mut d = Deviation::default();
        for s in &self.samples {
            d.left_tip_dev_mm = d.left_tip_dev_mm.max((s.left * z).norm());
            d.right_tip_dev_mm = d.right_tip_dev_mm.max((s.right * z).norm());
            d.pose_position_err_mm = d.pose_position_err_mm.max((s.position * z).norm());
            d.pose_rotation_err_deg = d
                .pose_rotation_err_deg
                .max((s.rotation * z).norm().to_degrees());
        }
        d
    }

    /// The sensitivity ranking under `spec`: each perturbed family's
    /// first-order mean-square tip deviation (over both tips and every
    /// sample of the motion) and its share of the total, largest first.
    pub fn sensitivity(&self, spec: &Spec) -> Vec<Sensitivity> {
        let mut sums = [0.0; Family::ALL.len()];
        for s in &self.samples {
            for k in 0..COORDINATES {
                let v = variance(spec, k);
                if v > 0.0 {
                    let c = s.left.column(k).norm_squared() + s.right.column(k).norm_squared();
                    sums[family_of(k).index()] += 0.5 * v * c;
                }
            }
        }
        let n = self.samples.len().max(1) as f64;
        let total: f64 = sums.iter().sum();
        let mut out: Vec<Sensitivity> = spec
            .iter()
            .map(|(family, _)| {
                let ms = sums[family.index()] / n;
                Sensitivity {
                    family,
                    rms_tip_mm: ms.sqrt(),
                    share: if total > 0.0 {
                        sums[family.index()] / total
                    } else {
                        0.0
                    },
                }
            })
            .collect();
        out.sort_by(|a, b| b.share.total_cmp(&a.share));
        out
    }
}

/// One family's part in the tip deviation, to first order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivity {
    /// The family.
    pub family: Family,
    /// The RMS tip deviation this family's tolerance causes alone, averaged
    /// over the motion's samples and both tips, mm.
    pub rms_tip_mm: f64,
    /// Its share of the total mean-square tip deviation, in `[0, 1]`.
    pub share: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use parasils_kin::Instrument;

    #[test]
    fn the_local_tip_is_the_kinematics_one_with_its_derivatives() {
        for side in [Side::Left, Side::Right] {
            let module = Instrument::<f64>::paper(side);
            let g = module.geometry();
            let q = Joints::new(0.4, -0.7, 130.0);
            let [l, dl_alpha, dl_beta] = local_tip(g.alpha, g.beta, side, &q);
            assert!((l - module.fk_local(&q)).norm() < 1e-12, "{side:?}");
            // Central differences, step 1e-6 rad: truncation ~1e-12 relative.
            let h = 1e-6;
            let fd = |da: f64, db: f64| {
                (local_tip(g.alpha + da, g.beta + db, side, &q)[0]
                    - local_tip(g.alpha - da, g.beta - db, side, &q)[0])
                    / (2.0 * h)
            };
            assert!((fd(h, 0.0) - dl_alpha).norm() < 1e-6, "{side:?}");
            assert!((fd(0.0, h) - dl_beta).norm() < 1e-6, "{side:?}");
        }
    }
}
