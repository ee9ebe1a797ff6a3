//! Time-optimal timing along a given path under velocity and acceleration
//! limits (see `docs/model.md`, *Time-optimal timing*).
//!
//! A geometric path `s in [0, 1] -> q(s)` with `M` rows (actuators, or any
//! quantity with limits) is to be run rest to rest as fast as possible
//! with, for every row `j`, `|q_j' s_dot| <= v_j` and
//! `|q_j' s_ddot + q_j'' s_dot^2| <= a_j`. In `x = s_dot^2` and
//! `u = s_ddot` the constraints are linear, and `dx/ds = 2u`.
//!
//! # The discretised problem
//! The caller provides the knots `s_0 < ... < s_N` in a buffer of [`Knot`]s
//! (evenly on `[0, 1]`: [`fill_uniform`]) with the path's exact `q'` and
//! `q''` there (the [`Path`] trait: closed form, no finite differences, no
//! spline). On each interval `u` is constant, so `x(s)` is linear in `s`
//! and `s(t)` is a piece of constant acceleration. The solver ([`solve`])
//! enforces
//! - the velocity limits at every knot, and
//! - the acceleration limits at **both ends** of every interval, with that
//!   interval's `u` (at the end, with `x_{i+1} = x_i + 2 h u`).
//!
//! It is reachability analysis: backwards from rest at `s_N`, the largest
//! `x_i` from which the end can still be reached at rest (each a
//! two-variable linear problem, solved exactly by a finite descent on the
//! concave gap between the bands' envelopes); then forwards from rest at
//! `s_0`, the largest `u_i` keeping `x_{i+1}` controllable. The forward
//! pass's greedy choice is time-optimal for the discretised problem. Cost:
//! `O(N M)`, no allocation, no iteration but the descent's few steps.
//!
//! # Between the knots
//! The discretised constraints hold at the knots only; `q'` and `q''` vary
//! between them, so a use of a limit can peak inside an interval (near a
//! sign change of `q'` the velocity limit curve `(v / q')^2` is sharply
//! convex, and the straight `x(s)` between two knots on it cuts above it).
//! [`certify`] evaluates the path at `checks` evenly spaced points of every
//! interval (10 makes the check grid 10 times denser than the knots) and
//! estimates what lies between check points from the parabola through three
//! neighbouring ones (where it is concave and peaks between them), counting
//! that excess twice. Where an interval's worst use `r` (as a time stretch,
//! `max(|v| / v_max, sqrt(|a| / a_max))`) is above `1 + 1e-6`, the speed at
//! its two knots is capped at `x / r^2` and the problem solved again, up to
//! [`CERTIFY_PASSES`] times; what is left above `1 - 1e-12` is removed by
//! one uniform time stretch of the whole schedule, which leaves that
//! headroom (at least 64 ulps) for the rounding of whoever samples the law.
//!
//! What is guaranteed, and by what:
//! - at the knots and at every check point, every limit holds with `1e-12`
//!   of headroom: by the final stretch (so that a limit used to the full,
//!   recomputed by a caller as `q' s_ddot + q'' s_dot^2`, stays within it);
//! - between check points, every limit holds up to the error of the
//!   parabola's estimate, `O(delta^3 |g'''|)` for a use `g(s)` and a check
//!   spacing `delta`: an estimate, not a proof; the tests sample 10 times
//!   denser than the knots and at a fixed rate in time, on random paths and
//!   limits and on the robot's, and find no excess above `1e-9` relative;
//! - the schedule is at rest at both ends, `s(0) = s_0`, `s(T) = s_N`.
//!
//! Optimality: the solution is the fastest for the discretised problem;
//! the continuous optimum is approached as the grid is refined (the
//! durations differ by `O(1/N)`). The caps are local (they slow only the
//! intervals that exceeded); the final stretch, when there is one, is tiny
//! (1.3e-7 for the paper's reorientation at 1000 knots) and leaves the
//! schedule tight: no uniform time scaling of it is feasible and shorter.
//!
//! ```
//! use parasils_traj::optimal::{self, Derivatives, Knot, Path, RowLimits};
//!
//! /// One axis moved over 2 units: q(s) = 2 s.
//! struct Line;
//! impl Path<f64, 1> for Line {
//!     type Error = core::convert::Infallible;
//!     fn derivatives(&self, _s: f64) -> Result<Derivatives<f64, 1>, Self::Error> {
//!         Ok(Derivatives { first: [2.0], second: [0.0] })
//!     }
//! }
//! let limits = [RowLimits::new(1.0, 1.0)]; // 1 unit/s, 1 unit/s^2
//! let mut knots = [Knot::default(); 101];
//! let (schedule, _) = optimal::plan(&Line, &limits, &mut knots, 10)?;
//! // The fastest law is a trapezoid: 1 s up, 1 s at 1 unit/s, 1 s down.
//! assert!((schedule.duration() - 3.0).abs() < 0.03);
//! # Ok::<(), optimal::Error<core::convert::Infallible>>(())
//! ```

mod plan;
mod schedule;
mod solve;
mod types;

pub use plan::{CERTIFY_PASSES, Planned, certify, plan};
pub use schedule::{Phases, Schedule};
pub use solve::{fill_uniform, solve};
pub use types::{Certificate, Derivatives, Error, Knot, Path, Phase, RowLimits};
