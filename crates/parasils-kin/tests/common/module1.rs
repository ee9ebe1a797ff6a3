//! Module 1's check values (`docs/model.md`, *Check values*) and the robots
//! and poses the tests of module 1 share.

// Each test binary uses its own part of the shared modules.
#![allow(dead_code)]

use parasils_kin::instrument::Interval;
use parasils_kin::{Actuators, ParallelGeometry, ParallelRobot, Pose, Real};

/// `docs/model.md`, *Check values*: the actuators at `P0`, mm.
pub const Q_P0: [f64; 6] = [117.942, 151.459, 56.937, 89.428, 132.193, 77.441];
/// `docs/model.md`, *Check values*: every actuator at the symmetric pose, mm.
pub const Q_SYMMETRIC: f64 = 92.754;

/// The symmetric pose `(0, 0, -500 mm, 0, 0, -60 deg)`.
pub fn symmetric_pose<T: Real>() -> Pose<T> {
    Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, -60.0)
}

/// The actuators as `f64`, mm.
pub fn to_f64<T: Real>(q: &Actuators<T>) -> [f64; 6] {
    q.0.map(|v| v.to_f64())
}

/// The robot with unlimited strokes, for the properties that test the
/// kinematics and not the (assumed) strokes.
pub fn unlimited() -> ParallelRobot<f64> {
    let mut g = ParallelGeometry::assumed();
    for guide in g.guides.iter_mut() {
        guide.stroke = Interval::new(f64::NEG_INFINITY, f64::INFINITY);
    }
    ParallelRobot::new(g).expect("valid geometry")
}
