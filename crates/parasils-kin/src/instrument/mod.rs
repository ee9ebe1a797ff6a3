//! The spherical instrument module (modules 2-L and 2-R): geometry, forward and
//! inverse kinematics, Jacobian, and joint rates.
//!
//! Each active instrument is held by a 3-DOF spherical linkage whose remote
//! centre of motion (RCM) sits at a port of the platform. The joints are
//! `qs1`, `qs2` (rotations, rad) and `qs3` (insertion: RCM to tip, mm). The
//! left module, in its RCM frame (parallel to the platform frame), is
//!
//! ```text
//! M_L = R_Y(alpha) R_X(qs1) R_Y(qs2) R_X(beta) T_Z(-qs3)
//! ```
//!
//! and the tip `p_local` is the last column of `M_L`: the tool points along
//! `-z` of the last frame. The right module is the mirror image of the left
//! across the platform's `Y'Z'` plane: with `S = diag(-1, 1, 1)`,
//! `M_R = S M_L S`, so `p_local_R(q) = S p_local_L(q)` and mirror-symmetric
//! poses have equal joint values (see `docs/model.md`, *Instrument modules*).
//!
//! ```
//! use nalgebra::Vector3;
//! use parasils_kin::instrument::{Instrument, Joints, Side};
//!
//! let left = Instrument::<f64>::paper(Side::Left);
//! let right = Instrument::<f64>::paper(Side::Right);
//! let q = Joints::new(0.3, -0.5, 120.0);
//! let s = Vector3::new(-1.0, 1.0, 1.0);
//! // The right tip is the mirror of the left tip, joint for joint.
//! assert!((right.fk_local(&q) - left.fk_local(&q).component_mul(&s)).norm() < 1e-12);
//! ```
//!
//! # Forward kinematics
//! [`Instrument::fk`] gives the tip in the fixed frame,
//! `p_F = R (RCM + p_local(q)) + P` at a platform pose;
//! [`Instrument::fk_platform`] gives it in the platform frame and
//! [`Instrument::fk_local`] in the module's RCM frame. The name is module 1's
//! too ([`ParallelRobot::fk`](crate::ParallelRobot::fk)): forward kinematics
//! from the joints, whatever it returns.
//!
//! # Inverse kinematics
//! In closed form (see `docs/model.md`, *Instrument modules*):
//! `qs3 = |p_local|`, the tool direction `u = -p_local / qs3`,
//! `v = R_Y(-alpha) u`, `sin qs2 = v_x / cos(beta)`.
//! Two assembly modes share every reachable tip: [`AssemblyMode::A`] with
//! `cos qs2 > 0` (`|qs2| < 90 deg`) and [`AssemblyMode::B`] with `cos qs2 < 0`;
//! the singularity `cos qs2 = 0` separates them, so a continuous motion never
//! changes mode. Then
//!
//! ```text
//! qs1 = atan2(-sin(beta) v_z - cos(beta) cos(qs2) v_y,  cos(beta) cos(qs2) v_z - sin(beta) v_y)
//! ```
//!
//! # Jacobian
//! `J = d p_local / d qs` (mm/rad, mm/rad, 1), with
//! `det J = -qs3^2 cos(qs2) cos(beta)` for the left module and the opposite
//! sign for the right. Writing `w = R_Y(-alpha) u` as a function of `qs1, qs2`,
//! `a = dw/dqs1 = e_x x w` and `b = dw/dqs2`, the left Jacobian is
//! `J = -R_Y(alpha) [qs3 a, qs3 b, w]`; `w` is orthogonal to `a` and `b` and
//! `a x b = cos(beta) cos(qs2) w`, which gives the inverse in closed form
//! ([`Instrument::jacobian_inverse`]).
//!
//! # Layout
//! The value types ([`Joints`], [`JointsTrig`], [`JointLimits`], [`Thresholds`], the
//! solutions) are defined in `types`, the module's parameters
//! ([`InstrumentGeometry`]) in `geometry`, and the solver ([`Instrument`]) in
//! `solver`; all are re-exported here. [`Side`] and [`Interval`] are the
//! crate's own ([`crate::Side`], [`crate::Interval`]), re-exported here too.

mod geometry;
mod solver;
mod types;

pub use crate::interval::Interval;
pub use crate::side::Side;
pub use geometry::InstrumentGeometry;
pub use solver::Instrument;
pub use types::{
    AssemblyMode, InstrumentMargins, InstrumentSolution, JointLimits, JointMotion, Joints,
    JointsTrig, Thresholds, TipMotion,
};
