//! The paper's scenario (its section 4), stated once.
//!
//! The reorientation of the endoscope that the paper simulates: from the start
//! pose `P0 = (15, 20, -500 mm, -15, 10, -60 deg)`
//! ([`Pose::paper_start`](crate::kin::Pose::paper_start)), `psi` increases by
//! 15 deg and `theta` by 25 deg, each within 10 deg/s and 5 deg/s^2,
//! phase-synchronised (4.5 s), while the left tip stays at
//! `(50, -50, -620) mm` and the right one at its mirror image
//! ([`TipTargets::paper`](crate::kin::TipTargets::paper)). The simulation
//! samples it at 1 kHz.
//!
//! The numbers are in the units a user gives them in (degrees, Hz); every
//! default of the command line, the Python bindings and the simulation
//! library comes from here. See `docs/model.md`, *Check values*.

/// The increment of `psi` from the start pose, deg.
pub const PSI_DEG: f64 = 15.0;
/// The increment of `theta` from the start pose, deg.
pub const THETA_DEG: f64 = 25.0;
/// The velocity limit of each Euler angle, deg/s.
pub const OMEGA_MAX_DEG_S: f64 = 10.0;
/// The acceleration limit of each Euler angle, deg/s^2.
pub const EPS_MAX_DEG_S2: f64 = 5.0;
/// The sampling rate of the simulation, Hz.
pub const RATE_HZ: f64 = 1000.0;
