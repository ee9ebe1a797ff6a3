//! Online profiles: from any current state `(p0, v0)` to rest at a target,
//! time-optimal under velocity and acceleration limits (second order), for
//! one axis ([`OnlineTrapezoid`]) or several synchronised ([`OnlineMulti`]);
//! and the controlled stop.
//!
//! These are what a controller replans with when a new target arrives while
//! the axes move: the new profile starts from the state the old one has at
//! that instant, so position and velocity are continuous across the command
//! (the acceleration may jump: the profiles are second order).
//!
//! # One axis
//! Every profile has at most three phases: a constant acceleration
//! `a_1 = +-a_max` from `v0` to a cruise velocity `v_c` (`|v_c| <= v_max`),
//! a cruise at `v_c`, and a constant acceleration `a_3 = -+a_max` from `v_c`
//! to rest at the target. In units of the axis's own limits (time in
//! `v_max / a_max`, velocity in `v_max`, distance in `v_max^2 / a_max`), with
//! `x = target - p0` and `u = v0 / v_max`:
//! - braking straight away stops at `u |u| / 2`; the excess `e = x - u |u| / 2`
//!   gives the direction `s` of the final approach (`sign(e)`, or `sign(u)`
//!   when `e = 0`: the target is exactly the stopping point). In that
//!   direction (`u0 = s u`, `h = |e|`):
//! - **braking** when `u0 > 1` (faster than `v_max` towards the approach):
//!   decelerate to `v_max` (`u0 - 1`), cruise for `h`, decelerate (`1`):
//!   `T = u0 + h`;
//! - otherwise, with `q = h + max(u0, 0)^2`, a **trapezoid** when `q >= 1`:
//!   accelerate to `v_max` (`1 - u0`), cruise `q - 1`, decelerate `1`:
//!   `T = q + 1 - u0`;
//! - or a **triangle** when `q < 1`: peak `sqrt(q)`, `T = 2 sqrt(q) - u0`.
//!
//! When `u0 < 0` (`v0` against the approach: the axis moves away from the
//! target, or towards a target too close to stop before it), the first phase
//! decelerates through zero and comes back: the **overshoot**. When `v0`
//! points towards a target beyond the stopping point, the velocity keeps its
//! sign and the position is monotone. The first phase's time is written
//! `h / (sqrt(q) + u0)` where `sqrt(q) - u0` would cancel.
//!
//! Near the stopping point the minimum time is ill-conditioned: a target a
//! distance `delta` behind it needs an overshoot by `delta` and the way back,
//! `2 sqrt(delta / a_max)` longer than braking. So a moving axis whose excess
//! `|e|` is within the rounding of its numbers,
//! `4 eps (2 max(|p0|, |target|) + u^2)` in the units above (`eps` the float
//! epsilon), takes the target as its stopping point: it brakes, and the end state is the target exactly.
//! Replanning from a state sampled on the way to rest therefore brakes on,
//! instead of overshooting by a rounding error and coming back.
//!
//! # Several axes
//! [`OnlineMulti::new`] takes a [`Synchronization`](crate::Synchronization) request and reports the
//! one it used ([`OnlineMulti::synchronization`]):
//! - [`Synchronization::Phase`](crate::Synchronization::Phase): a straight line in joint space, possible
//!   only when the current velocity is parallel (or anti-parallel) to the
//!   remaining displacement, or when every axis is at rest, and when no axis
//!   is faster than its `v_max` (up to 64 float epsilons, relative): an axis
//!   above its limit must brake at its own `a_max`, which a straight line
//!   cannot keep for every axis at once. The line's normalised profile takes
//!   the per-axis limits scaled as in [`Multi`](crate::Multi)
//!   (`min_i v_max_i / |k_i|`, `min_i a_max_i / |k_i|`, `k_i` the axis's share
//!   of the displacement), and each axis follows it within its own limits.
//!   Otherwise the request falls back to `Time`, and that is what is
//!   reported.
//! - [`Synchronization::Time`](crate::Synchronization::Time): every axis arrives at the longest minimum time
//!   `T`, each keeping its `a_max` and lowering its cruise velocity (see
//!   below).
//! - [`Synchronization::None`](crate::Synchronization::None): each axis on its own minimum-time profile.
//!
//! **Parallel, with tolerance.** The displacement `d_i = target_i - p0_i` is
//! written `k_i S` with `S = max_i |d_i|` (or, when every `d_i` is zero, the
//! velocity is written `k_i w0` with `w0 = max_i |v0_i|`), and the velocity is
//! taken as parallel when on every axis
//! `|v0_i - k_i w0| <= min(64 eps m_i + |w0| (r_i + |k_i| r_L) / S, m_i / 1024)`,
//! with `m_i = |v0_i| + |k_i w0|`, `w0 = k_L v0_L` on the longest axis `L`,
//! `r_i = 4 eps (|p0_i| + |target_i|)` the rounding of the positions and `eps`
//! the float epsilon: parallel up to the rounding of the velocities and of
//! the displacement, never beyond 1/1024 relative. An axis that does not move
//! along the line must have exactly zero velocity. The small residual allowed
//! is absorbed without any jump: each axis plans from its own exact state
//! under its share of the line's limits, and every axis is then given the
//! longest of these times (as `Time` does, keeping the share's acceleration),
//! so it stays within the rounding of the straight line. When the velocity is
//! exactly parallel these times are equal, up to rounding.
//!
//! **Time synchronisation has no blocked durations here.** For a target at
//! rest, every duration at or above an axis's minimum time is reachable: an
//! axis that could arrive earlier can arrive and wait, so the set of positions
//! reachable at rest by time `T` only grows with `T`. (Blocked intervals of
//! second-order time synchronisation exist only for a non-zero target
//! velocity.) The common duration is always the longest minimum time. For
//! `T` above its own minimum, an axis keeps `a_max` in its first and last
//! phases and takes the cruise velocity `v_c` (of the approach direction `s`)
//! that covers the distance in `T`; the distance is non-decreasing in `v_c`
//! (its derivative is the cruise time), so the solution is unique, in closed
//! form, in one of three cases (units as above, `theta = T a_max / v_max`):
//! - `u0 > 1`, or `0 < u0` and `h <= u0 (theta - u0)`: decelerate to
//!   `v_c = h / (theta - u0)` and cruise for `theta - u0`;
//! - otherwise accelerate to the smaller root of
//!   `v_c^2 - (theta + u0) v_c + q = 0`, `v_c = 2 q / (b + sqrt(b^2 - 4 q))`
//!   with `b = theta + u0` (above `u0` in exact arithmetic; a computed root
//!   below it, near the first case's boundary, is raised to `u0`);
//! - `e = 0`: brake to rest at the target and wait there.
//!
//! # Controlled stop
//! [`OnlineMulti::stop`] (and [`OnlineTrapezoid::stop`]) brings every axis to
//! rest at the same instant `T = max_i |v0_i| / a_max_i`, each decelerating
//! uniformly at `|v0_i| / T <= a_max_i`: `p_i(t) = p0_i + v0_i (t - t^2 / (2 T))`,
//! so the path keeps its direction (a straight line along `v0`) and the axis
//! needing the longest stop does so at its limit. It ignores `v_max`: an axis
//! faster than `v_max` brakes at `a_max`, which is the fastest way back.
//!
//! # Conventions
//! As for the rest-to-rest profiles, except at the start: for `t <= 0` (and a
//! NaN `t`) the state is the start state, position and velocity exactly as
//! given, with zero acceleration; for `t >= duration()` the target at rest,
//! exactly as given. Inside the motion the acceleration is that of the phase
//! that begins at a switch (right-continuous). The velocity of the first
//! phase is clamped to the interval between `v0` and `v_c`, that of the last
//! one to `|v_c|`, so rounding never exceeds the limits. Errors are typed
//! ([`Error`](crate::Error)), never a panic or a NaN; the acceleration of the given start
//! state is not used.

mod axis;
mod multi;

pub use axis::OnlineTrapezoid;
pub use multi::OnlineMulti;
