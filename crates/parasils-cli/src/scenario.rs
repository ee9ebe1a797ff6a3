//! A simulation's inputs: the start pose, the reorientation, the limits, the
//! tips and the robot.

use nalgebra::Vector3;
use parasils_kin::controller::{RobotGeometry, mirror_across_platform};
use parasils_kin::{Pose, TipTargets};
use parasils_traj::Synchronization;
use serde::Serialize;

/// The inputs of one endoscope reorientation (motion type 4).
///
/// Units as in the libraries: mm, rad, s. The defaults ([`Scenario::paper`])
/// are the paper's section 4 (SPEC section 7).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scenario {
    /// The platform's pose at `t = 0`, mm and rad.
    pub start: Pose<f64>,
    /// `psi`: the increment from the start (or, with `absolute`, the final value), rad.
    pub psi: f64,
    /// `theta`: the increment from the start (or, with `absolute`, the final value), rad.
    pub theta: f64,
    /// Whether `psi` and `theta` are final angles rather than increments.
    pub absolute: bool,
    /// The velocity limit of each Euler angle, rad/s.
    pub omega_max: f64,
    /// The acceleration limit of each Euler angle, rad/s^2.
    pub eps_max: f64,
    /// How the two angles are timed together.
    pub sync: Synchronization,
    /// Samples per second, Hz.
    pub rate_hz: f64,
    /// The left tip, held still, mm, fixed frame.
    pub tip_left: Vector3<f64>,
    /// The right tip, held still, mm, fixed frame; `None` for the mirror image
    /// of the left tip across the platform's `Y'Z'` plane at the start pose.
    pub tip_right: Option<Vector3<f64>>,
    /// The robot: module 1 and both instrument modules.
    pub robot: RobotGeometry<f64>,
}

impl Scenario {
    /// The paper's scenario: `P0 = (15, 20, -500 mm, -15, 10, -60 deg)`,
    /// `psi` and `theta` increased by 15 and 25 deg with 10 deg/s and
    /// 5 deg/s^2, phase-synchronised, the left tip at `(50, -50, -620)` mm and
    /// the right one its mirror, sampled at 1 kHz, on the paper's geometry
    /// (module 1 assumed).
    pub fn paper() -> Self {
        Self {
            start: Pose::paper_start(),
            psi: 15f64.to_radians(),
            theta: 25f64.to_radians(),
            absolute: false,
            omega_max: 10f64.to_radians(),
            eps_max: 5f64.to_radians(),
            sync: Synchronization::Phase,
            rate_hz: 1000.0,
            tip_left: TipTargets::<f64>::paper().left,
            tip_right: None,
            robot: RobotGeometry::paper(),
        }
    }

    /// The final `[psi, theta]`, rad.
    pub fn goal(&self) -> [f64; 2] {
        if self.absolute {
            [self.psi, self.theta]
        } else {
            [self.start.psi + self.psi, self.start.theta + self.theta]
        }
    }

    /// The two tips the controller holds still (the right one resolved).
    pub fn tips(&self) -> TipTargets<f64> {
        TipTargets {
            left: self.tip_left,
            right: self
                .tip_right
                .unwrap_or_else(|| mirror_across_platform(&self.start, &self.tip_left)),
        }
    }
}
