//! Motion profiles for PARA-SILSROB's axes: rest-to-rest trapezoidal (see
//! `docs/model.md`, *Trajectories*) and jerk-limited, online (from any moving
//! state to rest, and the controlled stop), synchronised across axes, sampled
//! at a fixed rate. `#![no_std]`, no allocation, no panics, generic over `f32`
//! and `f64`.
//!
//! The paper's reorientation: `psi` moves 15 deg and `theta` 25 deg, each
//! under `omega_max = 10 deg/s` and `epsilon_max = 5 deg/s^2`, phase-synchronised:
//!
//! ```
//! use parasils_traj::{Limits, Multi, Synchronization, Trapezoid};
//!
//! let deg = core::f64::consts::PI / 180.0;
//! let limits = Limits::paper(); // 10 deg/s, 5 deg/s^2, in rad
//! let start = [-15.0 * deg, 10.0 * deg]; // psi, theta at P0 (rad)
//! let goal = [0.0, 35.0 * deg];
//!
//! let psi = Trapezoid::new(start[0], goal[0], limits)?;
//! let theta = Trapezoid::new(start[1], goal[1], limits)?;
//! let both = Multi::new(start, goal, [limits; 2], Synchronization::Phase)?;
//! println!("psi alone:   {:.4} s (triangular: {})", psi.duration(), psi.is_triangular());
//! println!("theta alone: {:.4} s (triangular: {})", theta.duration(), theta.is_triangular());
//! println!("together:    {:.4} s", both.duration());
//!
//! assert!((psi.duration() - 2.0 * (15.0_f64 / 5.0).sqrt()).abs() < 1e-12); // 3.4641 s
//! assert!((theta.duration() - 4.5).abs() < 1e-12);
//! assert!((both.duration() - 4.5).abs() < 1e-12);
//! // psi becomes a scaled copy of theta: 6 deg/s and 3 deg/s^2 at most.
//! let [psi_sync, _] = both.axes();
//! assert!((psi_sync.peak_velocity() / deg - 6.0).abs() < 1e-9);
//! # Ok::<(), parasils_traj::Error>(())
//! ```
//!
//! # Conventions
//! - **Units**: each axis has its own position unit (rad, mm, ...); velocity
//!   is in units/s, acceleration units/s^2, jerk units/s^3, time in s. The
//!   project's code speaks rad and mm; the crate never converts.
//! - **Time** runs from the start of the motion: `t <= 0` (and a NaN `t`) is
//!   the start at rest (for the online profiles, the start state as given,
//!   moving or not), `t >= duration` the goal at rest, returned exactly as
//!   given (not recomputed).
//! - **Acceleration** is analytic everywhere; at a switch instant it is that of
//!   the phase that begins (right-continuous), and exactly 0 for `t <= 0` and
//!   `t >= duration` (`docs/model.md`, *Trajectories*).
//! - **Limits** are magnitudes applying to each axis separately (the project's
//!   reading, `docs/model.md`, *Trajectories*); they must be positive and finite.
//! - **Directions**: a motion towards smaller positions is the mirror image;
//!   a zero distance stays still.
//! - **Errors**, not panics and not NaN: every constructor returns
//!   `Result<_, Error>`; every sample of a built profile is finite for finite
//!   (or infinite, or NaN) `t`.
//!
//! # Modules
//! - [`trapezoid`]: [`Trapezoid`] and [`Limits`], the single-axis profile;
//! - [`double_s`]: [`DoubleS`] and [`JerkLimits`], the jerk-limited profile;
//! - [`sync`]: [`Multi`] and [`Synchronization`], `N` axes together;
//! - [`online`]: [`OnlineTrapezoid`] and [`OnlineMulti`], from any current
//!   state (moving or not) to rest at a target, and the controlled stop;
//! - [`optimal`]: the time-optimal timing of a given path under velocity
//!   and acceleration limits (reachability analysis over a caller's grid);
//! - [`sampler`]: [`Sampler`], the fixed-rate iterator;
//! - [`profile`]: the [`Motion`] and [`Profile`] traits and [`State`];
//! - [`error`]: [`Error`]; [`real`]: the [`Real`] float trait, the
//!   workspace's one (from `parasils-num`, also `parasils_kin::Real`).
//!
//! The three one-axis profiles share one crate-private vocabulary, the
//! `axis` module: the time conventions, the check of an imposed duration,
//! the ramp every last phase is written with from the goal, and the
//! rest-to-rest axis (a shape, trapezoidal or double S, placed between a
//! start and a goal) that [`Trapezoid`], [`DoubleS`] and [`Multi`]'s one
//! builder are made of. Modules import only those before them: `real`,
//! `error`, `profile`, `sampler`, `axis`, `trapezoid`, `double_s`, `sync`,
//! `online`, `optimal`.
//!
//! # Precision
//! The end state is exact in both float types (the stored goal is returned).
//! Inside the motion, `f64` is accurate to a few ulps of the positions
//! involved. Error budget of `f32` against the same profile computed in `f64`,
//! tested over random inputs (`tests/trapezoid.rs`, `f32_error_budget`):
//! position within `4 f32::EPSILON = 4.8e-7` of `|start| + |goal| + distance`,
//! duration within `4 f32::EPSILON` relative, for both [`Trapezoid`] and
//! [`DoubleS`] (measured worst case: 1.6 epsilons). Limits hold within
//! 16 epsilons relative in both types; most peaks are clamped to the limit.
//!
//! # Features
//! - `std` (default): no effect today; the crate is `no_std` always.
//! - `serde`: `Serialize`/`Deserialize` for the plain data types
//!   ([`Limits`], [`JerkLimits`], [`State`], [`Sample`], [`Synchronization`]).
#![no_std]
#![deny(missing_docs)]

mod axis;
pub mod double_s;
pub mod error;
pub mod online;
pub mod optimal;
pub mod profile;
pub mod real;
pub mod sampler;
pub mod sync;
pub mod trapezoid;

pub use double_s::{DoubleS, JerkLimits};
pub use error::{Endpoint, Error, LimitKind};
pub use online::{OnlineMulti, OnlineTrapezoid};
pub use optimal::{
    Certificate, Derivatives, Error as OptimalError, Knot, Path, Phase, Phases, Planned, RowLimits,
    Schedule,
};
pub use profile::{Motion, Profile, State};
pub use real::Real;
pub use sampler::{Sample, Sampler};
pub use sync::{Multi, Synchronization};
pub use trapezoid::{Limits, Trapezoid};
