//! Closed-form kinematics of PARA-SILSROB, the parallel robot for
//! single-incision laparoscopic surgery.
//!
//! A 6-DOF parallel robot (module 1) moves a platform carrying an endoscope
//! and two instruments; each instrument is held by a 3-DOF spherical module
//! with a remote centre of motion (RCM) at a port of the platform. When the
//! surgeon reorients the camera, the platform turns about the endoscope's RCM
//! and both instrument modules must move so that the instrument tips stay
//! exactly where they are. This crate computes that motion in closed form,
//! without allocation, `#![no_std]`, in `f32` or `f64`. The per-cycle call
//! [`Controller::step`] is closed-form but for module 1's parallel margin (a
//! smallest singular value): one factorisation from the previous cycle's
//! weakest direction, or, when that cannot be certified, a Jacobi SVD of at
//! most 30 sweeps. Module 1's forward kinematics, which the control cycle
//! does not need, iterates (Newton's method, bounded).
//!
//! The paper's start pose to the left module's joints:
//!
//! ```
//! use nalgebra::Vector3;
//! use parasils_kin::{AssemblyMode, Instrument, Pose, Side};
//!
//! let left = Instrument::<f64>::paper(Side::Left);
//! let p0 = Pose::paper_start(); // (15, 20, -500 mm, -15, 10, -60 deg)
//! let tip = Vector3::new(50.0, -50.0, -620.0); // mm, fixed frame
//! let q = left.ik(&p0, &tip, AssemblyMode::A)?;
//! println!(
//!     "qs1 = {:.4} deg, qs2 = {:.4} deg, qs3 = {:.4} mm",
//!     q.qs1.to_degrees(),
//!     q.qs2.to_degrees(),
//!     q.qs3
//! );
//! assert!((q.qs1.to_degrees() - 3.0889).abs() < 5e-5);
//! assert!((q.qs2.to_degrees() + 38.8695).abs() < 5e-5);
//! assert!((q.qs3 - 147.7687).abs() < 5e-5);
//! // And back: the forward kinematics puts the tip where it was asked.
//! assert!((left.fk(&p0, &q)? - tip).norm() < 1e-12);
//! # Ok::<(), parasils_kin::Error>(())
//! ```
//!
//! # Conventions
//! | quantity | convention |
//! |---|---|
//! | units | mm, rad, s inside the crate (degrees only at the edges) |
//! | fixed frame | `OXYZ`, module 1's base, `-Z` towards the patient |
//! | platform pose | `(X_P, Y_P, Z_P, psi, theta, phi)`, `R = R_X(psi) R_Y(theta) R_Z(phi)` ([`frame`]) |
//! | instrument joints | `qs1`, `qs2` rad, `qs3` mm = RCM to tip ([`instrument`]) |
//! | right module | mirror of the left across the platform's `Y'Z'` plane |
//! | assembly modes | A: `cos qs2 > 0` (default), B: `cos qs2 < 0` |
//!
//! # Modules
//! - [`frame`]: the platform pose, its rotation and the rotation's rates;
//! - [`instrument`]: the spherical module: geometry, FK, IK, Jacobian, rates
//!   (the value types, the geometry and the solver [`Instrument`]);
//! - [`parallel`]: module 1, the 6-DOF parallel robot: geometry (the default
//!   one **assumed**), IK, actuator rates, margins and Jacobian, FK by
//!   Newton's method, and the margin tracker of a control loop
//!   ([`parallel::margin`]);
//! - [`endoscope`]: the endoscope's insertion depth and its tip;
//! - [`clearance`]: the shafts and the endoscope as capsules (sizes
//!   **assumed**), the closest points and distance of two segments in closed
//!   form, the surface gaps between the three bodies at a cycle, and their
//!   smallest value certified over an interval of time;
//! - [`controller`]: the one call per control cycle, and the whole robot's
//!   geometry;
//! - [`limits`]: the actuators' velocity, acceleration and force limits (assumed
//!   defaults) and the check of a cycle against them;
//! - [`statics`]: the forces every actuator exerts to hold the tips' forces
//!   and the payload's weight (`tau = J^-T W` for module 1, `J^T R^T F` for
//!   an instrument module), the payload's Newton-Euler wrench, the
//!   platform's stiffness and a tip's deflection, checked by the balance of
//!   power, virtual work and Lagrange's equations;
//! - [`presets`]: the paper's numbers and module 1's assumed geometry, from
//!   which every named constructor (`paper`, `assumed`, `paper_start`) is built;
//! - [`error`]: what can go wrong, typed;
//! - [`Side`] and [`Interval`], shared by the modules; [`real`]: the
//!   [`Real`] trait (`f32` or `f64`), the workspace's one float trait from
//!   `parasils-num` (also `parasils_traj::Real`), with the crate's own sine
//!   and cosine ([`Real::sincos`]).
//!
//! Private: `check` (the finiteness checks on inputs), `linalg` (the
//! panic-free 6x6 kernels: Jacobi SVD, Gram product, shifted `L D L^T`).
//! Every public type is also at
//! the crate root. Imports go one way, from the leaves to the solvers, with
//! no circle: `real`, `presets`, `side`, then `interval` and
//! `linalg`, then `error`, `frame`, `check`, then `instrument` and
//! `parallel` (each split by concept, the `mod.rs` only re-exporting), then
//! `endoscope`, `clearance` and `limits`, then `controller`, then `statics` (the order of
//! `ARCHITECTURE.md`'s table, which the workspace's tests check). The model
//! is described in `docs/model.md`.
//!
//! # Features
//! - `std` (default): nalgebra's std back end. Without it the crate builds for
//!   bare-metal targets such as `thumbv7em-none-eabihf`.
//! - `serde`: `Serialize`/`Deserialize` for every parameter, pose and joint type.
#![no_std]
#![deny(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

pub mod camera;
mod check;
pub mod clearance;
pub mod controller;
pub mod endoscope;
pub mod error;
pub mod frame;
pub mod instrument;
mod interval;
pub mod limits;
mod linalg;
pub mod parallel;
pub mod presets;
pub mod real;
mod side;
pub mod statics;

pub use camera::{Camera, CameraError, ImagePoint, Projection};
pub use clearance::{
    AxisAccelerations, AxisState, Bodies, BodyGeometry, Capsule, CapsuleGap, Certificate,
    Clearance, ClearancePair, ClosestPoints, Probe, Segment, certify, gap_lower_bound, rate_over,
    segment_distance,
};
pub use controller::{
    ControlStep, Controller, ModuleCommand, RobotGeometry, TipTargets, default_right_tip,
    mirror_across_platform, step_positions, step_rates,
};
pub use endoscope::EndoscopeGeometry;
#[allow(deprecated)]
pub use error::Margin;
pub use error::{Error, InstrumentSingularity, Joint, ParallelSingularity};
pub use frame::{PlatformFrame, PlatformState, Pose, PoseRate};
pub use instrument::{
    AssemblyMode, Instrument, InstrumentGeometry, InstrumentMargins, InstrumentSolution,
    JointLimits, JointMotion, Joints, JointsTrig, Thresholds, TipMotion,
};
pub use interval::Interval;
pub use limits::{ACTUATOR_COUNT, Actuator, ActuatorLimits, LimitError, RateKind};
pub use nalgebra;
pub use parallel::{
    Actuators, Branch, Calibration, FkChord, FkOptions, FkSolution, Guide, MAX_OFFSET_LINKS,
    MarginTracker, ParallelGeometry, ParallelMargins, ParallelRobot, ParallelSolution,
    ParallelThresholds, Provenance, SymmetricLayout,
};
pub use real::Real;
pub use side::Side;
pub use statics::{
    ActuatorStiffness, JointForces, Loads, Payload, RobotForces, SliderForces, Wrench,
};
