//! Module 1's inverse kinematics at a parameter vector, with its
//! derivatives: the actuator readings a pose needs, the identification
//! Jacobian `d q / d x` (every parameter of [`crate::params`]) and the pose
//! Jacobian `d q / d pose` (mm and deg), in closed form.
//!
//! With `r = A_i - G_j` (`A_i = P + R a_i`), `e_j = A_i - B_j` the link and
//! `e_j . u_j = s_j sqrt(l_j^2 - |r - (r.u_j) u_j|^2)`, the reading is
//! `q_j = r.u_j - e_j.u_j + o_j` and
//!
//! ```text
//! d q_j / d G_j = -e_j / (e_j.u_j)        d q_j / d a_i = R^T e_j / (e_j.u_j)
//! d q_j / d l_j = -l_j / (e_j.u_j)        d q_j / d o_j = 1
//! d q_j / d u_j = -(q_j - o_j) r / (e_j.u_j)   (then through the normalisation)
//! d q_j / d P   = e_j / (e_j.u_j)         d q_j / d angle = e_j . (dR/d angle a_i) / (e_j.u_j)
//! ```

use nalgebra::{Matrix3, Vector3};

use crate::params::{NODES_START, PARAMETERS, PER_GUIDE, ParameterMap};

/// A measured or planned pose: `[x_mm, y_mm, z_mm, psi_deg, theta_deg,
/// phi_deg]`, the platform's position and Euler angles
/// (`R = R_X(psi) R_Y(theta) R_Z(phi)`).
pub type PoseMmDeg = [f64; 6];

/// A leg that cannot reach its node at a pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutOfReach {
    /// The actuator, 1 to 6.
    pub actuator: u8,
    /// `l_j^2 - d^2` (negative), mm^2, `d` the node's distance to the guide.
    pub discriminant_mm2: f64,
}

/// The readings at one pose and their derivatives.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseEval {
    /// `q1..q6`, mm.
    pub q_mm: [f64; 6],
    /// Row `j`: `d q_j / d x` over the parameter vector.
    pub d_params: [[f64; PARAMETERS]; 6],
    /// Row `j`: `d q_j / d pose`, per mm for the position, per deg for the angles.
    pub d_pose: [[f64; 6]; 6],
    /// `|e_j . u_j| / l_j`, the serial margins.
    pub serial_margin: [f64; 6],
}

#[derive(Debug, Clone, Copy)]
struct GuideModel {
    point: Vector3<f64>,
    u: Vector3<f64>,
    raw_norm: f64,
    length: f64,
    offset: f64,
    sign: f64,
    tangents: [Vector3<f64>; 2],
}

/// Module 1 at one parameter vector, ready to evaluate poses.
#[derive(Debug, Clone)]
pub struct Model {
    guides: [GuideModel; 6],
    nodes: [Vector3<f64>; 3],
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)` and its derivatives with respect to
/// the three angles (rad).
fn rotation_and_derivatives(psi: f64, theta: f64, phi: f64) -> [Matrix3<f64>; 4] {
    let (sa, ca) = psi.sin_cos();
    let (sb, cb) = theta.sin_cos();
    let (sc, cc) = phi.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, ca, -sa, 0.0, sa, ca);
    let ry = Matrix3::new(cb, 0.0, sb, 0.0, 1.0, 0.0, -sb, 0.0, cb);
    let rz = Matrix3::new(cc, -sc, 0.0, sc, cc, 0.0, 0.0, 0.0, 1.0);
    let drx = Matrix3::new(0.0, 0.0, 0.0, 0.0, -sa, -ca, 0.0, ca, -sa);
    let dry = Matrix3::new(-sb, 0.0, cb, 0.0, 0.0, 0.0, -cb, 0.0, -sb);
    let drz = Matrix3::new(-sc, -cc, 0.0, cc, -sc, 0.0, 0.0, 0.0, 0.0);
    [rx * ry * rz, drx * ry * rz, rx * dry * rz, rx * ry * drz]
}

impl Model {
    /// The model at parameter vector `x`.
    pub fn new(map: &ParameterMap, x: &[f64; PARAMETERS]) -> Self {
        let nominal = map.nominal();
        let guides = core::array::from_fn(|j| {
            let b = PER_GUIDE * j;
            let raw = map.raw_direction(x, j);
            let raw_norm = raw.norm();
            GuideModel {
                point: Vector3::new(x[b], x[b + 1], x[b + 2]),
                u: raw / raw_norm,
                raw_norm,
                length: x[b + 5],
                offset: x[b + 6],
                sign: nominal.guides[j].branch.sign::<f64>(),
                tangents: map.tangents()[j],
            }
        });
        let nodes = core::array::from_fn(|i| {
            let b = NODES_START + 3 * i;
            Vector3::new(x[b], x[b + 1], x[b + 2])
        });
        Self { guides, nodes }
    }

    /// The readings at `pose`, and with `derivatives` their Jacobians
    /// (else left 0).
    pub fn eval(&self, pose: &PoseMmDeg, derivatives: bool) -> Result<PoseEval, OutOfReach> {
        let [x, y, z, psi, theta, phi] = *pose;
        let [rot, d_psi, d_theta, d_phi] =
            rotation_and_derivatives(psi.to_radians(), theta.to_radians(), phi.to_radians());
        let p = Vector3::new(x, y, z);
        let mut out = PoseEval {
            q_mm: [0.0; 6],
            d_params: [[0.0; PARAMETERS]; 6],
            d_pose: [[0.0; 6]; 6],
            serial_margin: [0.0; 6],
        };
        let deg = core::f64::consts::PI / 180.0;
        for (j, g) in self.guides.iter().enumerate() {
            let i = j / 2;
            let a = self.nodes[i];
            let r = p + rot * a - g.point;
            let ru = r.dot(&g.u);
            let d = (r - g.u * ru).norm();
            let disc = (g.length - d) * (g.length + d);
            if !(disc >= 0.0) {
                return Err(OutOfReach {
                    actuator: j as u8 + 1,
                    discriminant_mm2: disc,
                });
            }
            let eu = g.sign * disc.sqrt();
            let slider = ru - eu;
            out.q_mm[j] = slider + g.offset;
            out.serial_margin[j] = eu.abs() / g.length;
            if !derivatives {
                continue;
            }
            let e = r - g.u * slider;
            let n = e / eu;
            let row = &mut out.d_params[j];
            let b = PER_GUIDE * j;
            row[b] = -n.x;
            row[b + 1] = -n.y;
            row[b + 2] = -n.z;
            for (k, t) in g.tangents.iter().enumerate() {
                let du = (t - g.u * g.u.dot(t)) / g.raw_norm;
                row[b + 3 + k] = -(slider / eu) * r.dot(&du);
            }
            row[b + 5] = -g.length / eu;
            row[b + 6] = 1.0;
            let na = rot.tr_mul(&n);
            let c = NODES_START + 3 * i;
            row[c] = na.x;
            row[c + 1] = na.y;
            row[c + 2] = na.z;
            out.d_pose[j] = [
                n.x,
                n.y,
                n.z,
                n.dot(&(d_psi * a)) * deg,
                n.dot(&(d_theta * a)) * deg,
                n.dot(&(d_phi * a)) * deg,
            ];
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parasils_kin::{ParallelGeometry, ParallelRobot, Pose};

    #[test]
    fn rotation_matches_the_kinematics() {
        let pose = Pose::<f64>::from_mm_deg(1.0, 2.0, 3.0, -15.0, 10.0, -60.0);
        let [r, ..] = rotation_and_derivatives(pose.psi, pose.theta, pose.phi);
        assert!((r - pose.rotation()).norm() < 1e-15);
    }

    #[test]
    fn readings_match_the_kinematics_with_an_encoder_offset() {
        let mut g = ParallelGeometry::<f64>::assumed();
        g.guides[3].encoder_offset = 2.5;
        g.guides[1].direction = Vector3::new(0.01, -0.02, -1.0);
        let map = ParameterMap::new(&g).expect("valid");
        let model = Model::new(&map, &map.nominal_vector());
        let robot = ParallelRobot::new(g).expect("valid");
        let pose = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];
        let q = model.eval(&pose, false).expect("reachable").q_mm;
        let [x, y, z, a, b, c] = pose;
        let want = robot
            .ik_unchecked(&Pose::from_mm_deg(x, y, z, a, b, c))
            .expect("reachable");
        for j in 0..6 {
            assert!((q[j] - want[j]).abs() < 1e-11, "{j}: {} {}", q[j], want[j]);
        }
    }
}
