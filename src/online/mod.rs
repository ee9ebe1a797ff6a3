//! The online controller: the per-cycle loop of motion type 4 that accepts a
//! new goal or a stop at any cycle, while the platform moves.
//!
//! An [`OnlineController`] holds the kinematics ([`Controller`]), the two tips
//! it keeps still, the platform's fixed part of the pose (`P` and `phi`), the
//! `(psi, theta)` limits, a margin [`Supervisor`], and the active motion: an
//! [`OnlineMulti`] of `(psi, theta)` started at some instant of the
//! controller's clock. Its calls, each taking the time `t` in s on that clock
//! (any origin; never decreasing from one call to the next):
//!
//! | call | what it does |
//! |---|---|
//! | [`new`](OnlineController::new) | at rest at a pose; checks the supervisor's thresholds; seeds module 1's margin tracker (the one full SVD) here, outside the loop |
//! | [`command`](OnlineController::command)`(t, [psi, theta])` | replans from the state of the active motion at `t` to rest at the goal (rad), time-optimal, `Phase` synchronisation requested; returns the one used |
//! | [`command_look_at`](OnlineController::command_look_at)`(t, target)` | the goal that aims the camera's view axis through `target` (mm, fixed frame; [`Camera::look_at`](crate::kin::Camera::look_at) from the orientation at `t`, `phi` held), then as `command` |
//! | [`stop`](OnlineController::stop)`(t)` | the controlled stop from the state at `t`: both angles to rest together, on a straight line |
//! | [`set_tips`](OnlineController::set_tips)`(t, tips)`, [`move_tips`](OnlineController::move_tips)`(t, [left, right])` | the tips (mm, fixed frame; with velocities and accelerations for `move_tips`) the next cycles put the instruments at, checked: finite, at most [`max_tip_step`](OnlineController::max_tip_step) from the tips held so far, reachable at the current pose |
//! | [`follow`](OnlineController::follow)`(t, params)` | the camera follows the tips: every tick runs the follow law ([`Follow`]) and its recentrings become the active motion, until a command or a stop |
//! | [`tick`](OnlineController::tick)`(t)` | one cycle: the platform state at `t`, the kinematics for it with the tips as set ([`Controller::step_commanded`]), the supervisor's verdict; returns a [`Setpoint`] |
//! | [`tick_with`](OnlineController::tick_with)`(t, &regions)` | the same cycle, also watching the gap from the in-body parts to forbidden regions ([`ForbiddenRegions`]) |
//! | [`command_index`](OnlineController::command_index) | 0 for the first motion, +1 at each command and each stop (a stop the supervisor demanded included) |
//! | [`is_at_rest`](OnlineController::is_at_rest)`(t)` | whether the active motion has ended at `t` |
//! | [`rebase`](OnlineController::rebase)`(origin)` | moves the clock's origin (see *Time* below) |
//!
//! A command at `t` takes effect at `t`: the new motion starts from the old
//! one's position and velocity at `t` exactly (the online profiles' start
//! state is returned as given), so both are continuous across every command;
//! the acceleration may jump (the profiles are second order). At its first
//! instant a motion reports the acceleration 0, as every profile of
//! [`parasils_traj`] does at `t <= 0`. A loop that commands at a cycle calls
//! `command(t, ..)` and then `tick(t)` with the same `t`.
//!
//! # The supervisor
//! Every tick checks the cycle's margins with
//! [`Supervisor::check_ahead`]: warnings for margins below their warning
//! thresholds, and a stop demanded for a decreasing margin that would end
//! below its stop threshold if a controlled stop began now. The rates are
//! the change since the previous tick; the stop's duration is that of the
//! controlled stop from this cycle's velocities. A demanded stop is carried
//! out at once: the controlled stop is planned from this cycle's state (as
//! [`stop`](OnlineController::stop) would), the command index grows by one,
//! and [`kind`](OnlineController::kind) becomes
//! [`MotionKind::SupervisorStop`]; the setpoint returned is this cycle's,
//! computed before the stop (same position and velocity; the next cycle
//! follows the stop). While a stop is under way a demand changes nothing. A
//! new command after a stop is accepted as any other: if it heads back
//! towards the limit, the supervisor stops it again; if it leaves, the margin
//! grows and nothing is demanded.
//!
//! # Clearance
//! [`with_clearance`](OnlineController::with_clearance) gives the
//! controller the bodies ([`ClearanceWatch`]: the shafts' and the
//! endoscope's sizes, the endoscope's depth, the warning and stop
//! thresholds in mm). Every tick then computes the three surface gaps
//! ([`Bodies::clearance`], in [`Setpoint::clearance`]) and their rates and
//! bends from the previous ticks, and the supervisor demands the controlled
//! stop for a decreasing gap predicted to end below the stop threshold
//! ([`ClearanceThresholds::check_ahead`]); the stop is carried out as a
//! margin's. Without it, nothing of the clearance is computed.
//!
//! # Tips that move
//! The tips start where [`new`](OnlineController::new) was given them and
//! stay there until [`set_tips`](OnlineController::set_tips) or
//! [`move_tips`](OnlineController::move_tips) moves them: from that call on,
//! every cycle solves both instrument modules for the tips as set, in the
//! fixed frame, under the cycle's moving platform, so a tip is exactly
//! where it was commanded whatever the platform does (the modules' joint
//! rates include the tip's own velocity, given with `move_tips`). A call is
//! checked before it changes anything: every number finite, each tip moved
//! by at most [`max_tip_step`](OnlineController::max_tip_step) (default
//! [`MAX_TIP_STEP_MM`], 1 mm: a caller streaming tips sends small steps; a
//! leap is refused as [`Error::TipStep`], never taken in one cycle), and
//! both modules able to reach the new tips at the platform's state at the
//! call's time. The supervisor watches every cycle as before; a stop it
//! demands stops the platform, and the tips remain the caller's.
//!
//! # The camera follows the tips
//! [`follow`](OnlineController::follow) switches the follow mode on (the
//! endoscope's depth must be known: [`with_endoscope_depth`](OnlineController::with_endoscope_depth)
//! or [`with_clearance`](OnlineController::with_clearance)). Every tick
//! then first runs the follow law ([`Follow`]: dead zones, hysteresis, the
//! dwell) on the tips as set; when it plans or replans a recentring (the
//! closed-form look-at of the tips' midpoint, reached with the same online
//! time-optimal profile as every command, from the moving state), that
//! profile becomes the active motion, and the cycle's platform state is the
//! law's setpoint. The margins, the gaps and the regions are supervised as
//! for any motion; a stop the supervisor demands ends the follow mode, as a
//! [`command`](OnlineController::command), a look-at command or a
//! [`stop`](OnlineController::stop) do. The law's phase is in every
//! [`Setpoint::follow`] and in [`follow_phase`](OnlineController::follow_phase);
//! the motion's kind is [`MotionKind::Follow`].
//!
//! # Forbidden regions
//! [`tick_with`](OnlineController::tick_with) takes the regions the bodies
//! must keep out of ([`ForbiddenRegions`]; `parasils-anatomy`'s `Anatomy`
//! is one); [`tick`](OnlineController::tick) is `tick_with` with
//! [`NoRegions`](crate::NoRegions). With the clearance watched
//! ([`with_clearance`](OnlineController::with_clearance): the bodies' sizes
//! and the thresholds), every such tick asks for the smallest gap from each
//! in-body part ([`InBodyCapsules`](crate::InBodyCapsules), one query per
//! part) to the regions, reports the smallest with its region's index
//! ([`Setpoint::region`]), tracks each part's rate and bend from the
//! previous ticks (apart, because the smallest over the parts has kinks
//! where the nearest part changes, and a rate measured across one lags),
//! and the supervisor demands the controlled stop for a decreasing gap
//! predicted to end below the stop threshold exactly as for the pairs of
//! bodies ([`ClearanceThresholds::check_gap_ahead`],
//! [`Setpoint::region_stop`]). Unlike the pairs', a command does not look
//! the regions' rates one cycle ahead (the regions are known only at the
//! ticks): from a rest just above the stop threshold, a command heading
//! inwards is seen one cycle later, by micrometres. A tick without regions
//! forgets their rates.
//!
//! # Time
//! The controller only uses the time since the active motion's start,
//! `t - start`, computed in `T`. In `f32` the spacing of the values near
//! `t` is about `t * 1.2e-7`: 0.12 us at 1 s, but 0.24 ms after an hour and
//! 1 ms after about 2.3 hours, where a 1 kHz loop no longer sees its cycles
//! apart. A
//! long-running `f32` loop keeps its clock small with
//! [`rebase`](OnlineController::rebase) (for example at every command, or
//! every minute), or runs the controller in `f64`.
//!
//! # Errors and cost
//! Every call returns a typed [`Error`]: a NaN or infinite time
//! ([`Error::NonFiniteTime`]), a time before the latest one
//! ([`Error::TimeReversed`]), a NaN goal or invalid limits
//! ([`Error::Trajectory`]), a kinematics failure ([`Error::Kinematics`]:
//! the cycle's pose is out of reach or beyond a hard threshold). A failed
//! call changes nothing: the active motion goes on, and the loop decides
//! (hold the drives, or command a stop). Nothing allocates, panics or loops
//! without a fixed bound. A tick costs one [`Controller::step`], with module
//! 1's margin tracked from the previous cycle (the full decomposition was
//! done by `new`), plus the supervisor's arithmetic; a command or a stop adds
//! one two-axis online plan. In `f32` the tracked margin is certified only
//! while the parallel margin is above about 0.2 (with module 1's assumed
//! geometry): below, rounding leaves the tracker nothing to certify, and
//! every cycle takes the full decomposition again (see
//! [`MarginTracker`]), about twice a tracked
//! cycle's cost; `f64` tracks down to the hard threshold.
//!
//! ```
//! use parasils::{OnlineController, Supervisor};
//! use parasils::kin::{Controller, Pose, TipTargets};
//! use parasils::traj::{Limits, Synchronization};
//!
//! let p0 = Pose::<f64>::paper_start();
//! let mut online = OnlineController::new(
//!     Controller::paper(),
//!     TipTargets::paper(),
//!     p0,
//!     [Limits::paper(); 2], // 10 deg/s, 5 deg/s^2
//!     Supervisor::default(),
//! )?;
//! let deg = 1f64.to_radians();
//! // The paper's goal at t = 0, then psi +5 / theta +10 deg from P0 at 1.2 s.
//! online.command(0.0, [p0.psi + 15.0 * deg, p0.theta + 25.0 * deg])?;
//! let mut k = 0u32;
//! loop {
//!     let t = f64::from(k) / 1000.0;
//!     if k == 1200 {
//!         let sync = online.command(t, [p0.psi + 5.0 * deg, p0.theta + 10.0 * deg])?;
//!         assert_eq!(sync, Synchronization::Time); // the velocity is not along the new way
//!     }
//!     let cycle = online.tick(t)?;
//!     // cycle.step: module 1's actuators, both modules' joints, rates, margins
//!     assert!(cycle.warnings.is_empty() && cycle.stop.is_empty());
//!     if online.is_at_rest(t) {
//!         break;
//!     }
//!     k += 1;
//! }
//! assert_eq!(online.command_index(), 1);
//! # Ok::<(), parasils::Error>(())
//! ```

//!
//! | module | concept |
//! |---|---|
//! | `watch` | what is watched besides the margins: [`ClearanceWatch`], the gaps' rates and bends |
//! | `setpoint` | what a cycle reports: [`Setpoint`], [`MotionKind`] |
//! | `controller` | [`OnlineController`]: its state, construction, accessors |
//! | `command` | the calls between cycles: goals, look-at, stops, tips, follow mode |
//! | `tick` | the cycle itself |
//!
//! [`Controller::step_commanded`]: crate::kin::Controller::step_commanded
//! [`Controller::step`]: crate::kin::Controller::step
//! [`Follow`]: crate::Follow
//! [`ForbiddenRegions`]: crate::ForbiddenRegions
//! [`ClearanceThresholds::check_gap_ahead`]: crate::supervisor::ClearanceThresholds::check_gap_ahead
//! [`ClearanceThresholds::check_ahead`]: crate::supervisor::ClearanceThresholds::check_ahead
//! [`Supervisor::check_ahead`]: crate::supervisor::Supervisor::check_ahead
//! [`Supervisor`]: crate::supervisor::Supervisor
//! [`Bodies::clearance`]: crate::kin::Bodies::clearance
//! [`Error`]: crate::Error
//! [`Error::NonFiniteTime`]: crate::Error::NonFiniteTime
//! [`Error::TimeReversed`]: crate::Error::TimeReversed
//! [`Error::Trajectory`]: crate::Error::Trajectory
//! [`Error::Kinematics`]: crate::Error::Kinematics
//! [`Error::TipStep`]: crate::Error::TipStep
//! [`OnlineMulti`]: crate::traj::OnlineMulti
//! [`MarginTracker`]: crate::kin::MarginTracker
//! [`Controller`]: crate::kin::Controller

mod command;
mod controller;
mod setpoint;
mod tick;
mod watch;

pub use controller::{MAX_TIP_STEP_MM, OnlineController};
pub use setpoint::{MotionKind, Setpoint};
pub use watch::{ClearanceWatch, PROBE_BAND_MM};
