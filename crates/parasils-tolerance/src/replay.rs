//! The model error of one perturbed robot: the nominal commands replayed on
//! it. Module 1's forward kinematics (Newton, from the previous sample's
//! pose) gives where the platform really is; each instrument module's
//! forward kinematics with its own perturbed parameters gives where its tip
//! really is.

use parasils_kin::{Actuators, Error, Instrument, ParallelRobot, Pose, RobotGeometry};

use crate::trace::Trace;

/// The largest deviations of one robot along the motion.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Deviation {
    /// The largest distance of the real left tip from the commanded one, mm.
    pub left_tip_dev_mm: f64,
    /// The same for the right tip, mm.
    pub right_tip_dev_mm: f64,
    /// The largest distance of the platform's real position from the
    /// commanded one, mm.
    pub pose_position_err_mm: f64,
    /// The largest angle of the rotation from the commanded platform
    /// orientation to the real one, deg.
    pub pose_rotation_err_deg: f64,
}

impl Deviation {
    /// The larger of the two tip deviations, mm.
    pub fn tip_dev_mm(&self) -> f64 {
        self.left_tip_dev_mm.max(self.right_tip_dev_mm)
    }

    fn max(&mut self, other: &Deviation) {
        self.left_tip_dev_mm = self.left_tip_dev_mm.max(other.left_tip_dev_mm);
        self.right_tip_dev_mm = self.right_tip_dev_mm.max(other.right_tip_dev_mm);
        self.pose_position_err_mm = self.pose_position_err_mm.max(other.pose_position_err_mm);
        self.pose_rotation_err_deg = self.pose_rotation_err_deg.max(other.pose_rotation_err_deg);
    }
}

/// Why a perturbed robot could not be followed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplayFailure {
    /// The trace's sample where it failed, `None` when the perturbed
    /// geometry itself is invalid.
    pub index: Option<usize>,
    /// The time of that sample, s.
    pub t_s: f64,
    /// The kinematics' error.
    pub error: Error,
}

impl core::fmt::Display for ReplayFailure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.index {
            Some(k) => write!(f, "at sample {k} (t = {} s): {}", self.t_s, self.error),
            None => write!(f, "invalid perturbed geometry: {}", self.error),
        }
    }
}

/// The angle between two rotations, rad: `2 asin(|A - B|_F / sqrt(8))`,
/// accurate down to the smallest angles (where `acos` of the trace is not).
pub(crate) fn rotation_angle(a: &nalgebra::Matrix3<f64>, b: &nalgebra::Matrix3<f64>) -> f64 {
    let s = (a - b).norm() / 8f64.sqrt();
    2.0 * s.min(1.0).asin()
}

/// The commands of `trace` replayed on `robot`.
///
/// # Errors
/// A [`ReplayFailure`]: the geometry is invalid, or module 1's forward
/// kinematics fails at a sample (no convergence, a singular Jacobian, a link
/// on the other branch), or a tip overflows.
pub fn replay(robot: &RobotGeometry<f64>, trace: &Trace) -> Result<Deviation, ReplayFailure> {
    let invalid = |error| ReplayFailure {
        index: None,
        t_s: 0.0,
        error,
    };
    let module1 = ParallelRobot::new(robot.module1).map_err(invalid)?;
    let left = Instrument::new(robot.left).map_err(invalid)?;
    let right = Instrument::new(robot.right).map_err(invalid)?;
    let mut worst = Deviation::default();
    let mut guess: Option<Pose<f64>> = None;
    for (k, c) in trace.commands().iter().enumerate() {
        let fail = |error| ReplayFailure {
            index: Some(k),
            t_s: c.t_s,
            error,
        };
        let from = guess.unwrap_or(c.pose);
        let pose = module1.fk(&Actuators(c.q_mm), &from).map_err(fail)?.pose;
        let tip_left = left.fk(&pose, &c.left).map_err(fail)?;
        let tip_right = right.fk(&pose, &c.right).map_err(fail)?;
        worst.max(&Deviation {
            left_tip_dev_mm: (tip_left - c.tip_left_mm).norm(),
            right_tip_dev_mm: (tip_right - c.tip_right_mm).norm(),
            pose_position_err_mm: (pose.position() - c.pose.position()).norm(),
            pose_rotation_err_deg: rotation_angle(&pose.rotation(), &c.pose.rotation())
                .to_degrees(),
        });
        guess = Some(pose);
    }
    Ok(worst)
}
