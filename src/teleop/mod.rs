//! Teleoperation: the surgeon's console driving the robot, cycle by cycle.
//!
//! A [`Teleop`] takes, each cycle, one input per hand and one for the
//! camera ([`Inputs`]) and returns the twelve actuator setpoints
//! ([`TeleopCycle`]) through the controller ([`Controller::step_commanded`]:
//! each tip moving in the fixed frame while the platform turns), the
//! margin [`Supervisor`] and, when given, the clearance thresholds. One call
//! per cycle, [`Teleop::step`]`(t, &inputs)`; a replay, a device loop or a
//! firmware is a thin layer that fills [`Inputs`].
//!
//! | part | module | what |
//! |---|---|---|
//! | inputs | `input` | [`HandInput`] (a rate: six normalised axes; or a master's position), [`CameraInput`] (a rate of the view, or follow the tips), the buttons ([`BUTTON_ENABLE`], [`BUTTON_CLUTCH`]), a [`Command`] |
//! | shaping | `filter` | the dead zone ([`dead_zone`]) and the tremor filter ([`LowPass`], critically damped, second order) |
//! | parameters | `params` | [`TeleopParams`]: scales, filter, the tip's and the view's limits, the timeout; [`TeleopError`] |
//! | states | `state` | [`OperatingState`] (CRTK's DISABLED, ENABLED, PAUSED, FAULT) and its table ([`Transition`]) |
//! | report | `cycle` | [`TeleopCycle`], [`HoldAt`], [`Fault`], [`CommandOutcome`] |
//! | the core | `core` | [`Teleop`]: construction, the cycle, the commands, the hands' assignment |
//! | moves | `moves` | the planned moves ([`Goal`]: home, look at a point or the tips, move to a pose; [`Teleop::start_move`], [`MoveRefused`]) |
//! | mapping | `motion` | the hands' and the camera's velocities, a planned move's, the controlled stop's |
//! | limits | `hold` | every candidate checked at its setpoint and its stopping point, reduced by a verified regula falsi step when it would cross a limit |
//!
//! # The mapping
//! A rate hand's translation `(tx, ty, tz)` in the image frame (`u`
//! rightwards, `v` upwards, into the picture) passes the dead zone, is
//! scaled to mm/s, turned into the fixed frame with the camera's current
//! axes (`R A`, `R` the platform's rotation, `A` the camera's axes in the
//! platform frame), filtered against tremor, limited in speed and then in
//! acceleration (its change per cycle at most `a_max dt`), and integrated
//! into the tip's setpoint. A master's change of position per cycle, scaled,
//! is the same kind of velocity. The left hand drives the tip that appears
//! on the left of the picture when the core is enabled, the right hand the
//! other; the assignment holds until the next enable.
//!
//! # The clutch and the dead-man
//! A hand moves its tip while its enable button is held and its clutch is
//! not. The first cycle it is engaged again moves nothing (the master is
//! re-anchored there); while it is not engaged, its tip's velocity decays
//! through the filter and the acceleration limit to exactly 0. A tip at
//! rest stays bit for bit where it was across a clutch press and release.
//!
//! # Limits and faults
//! A candidate cycle is solved and checked at its setpoint and at the point
//! where a stop at the acceleration limits would end: every supervised
//! margin and gap must be at or above its stop threshold (or not below its
//! current value), and every actuator's velocity and acceleration within
//! its limit. If not, the cycle's change of velocity is reduced to a
//! fraction between the controlled stop and the candidate, predicted from
//! the limiting slack by regula falsi and verified by the same checks, and the cycle
//! reports the limit it holds at ([`HoldAt`]). A non-finite input or a
//! device silent for longer than the timeout while ENABLED is a [`Fault`]:
//! state FAULT, a controlled stop within the acceleration limits, then held.
//!
//! ```
//! use parasils::kin::{Controller, Pose, Side, TipTargets};
//! use parasils::teleop::{
//!     BUTTON_ENABLE, Command, HandCommand, Inputs, OperatingState, Teleop, TeleopParams,
//! };
//!
//! let mut teleop = Teleop::new(
//!     Controller::<f64>::paper(),
//!     Pose::paper_start(),
//!     TipTargets::paper(),
//!     60.0, // the endoscope's depth, mm
//!     TeleopParams::assumed(),
//! )?;
//! let dt = 1e-3;
//! let start = teleop.tips();
//! let mut cycle = teleop.step(0.0, &Inputs::idle(0.0).with_command(Command::Enable))?;
//! assert_eq!(cycle.state, OperatingState::Enabled);
//! for k in 1..=500 {
//!     let t = f64::from(k) * dt;
//!     let mut inputs = Inputs::idle(t);
//!     // The left hand pushes full scale to the right of the picture.
//!     inputs.left.command = HandCommand::Rate([1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
//!     inputs.left.buttons = BUTTON_ENABLE;
//!     cycle = teleop.step(t, &inputs)?;
//! }
//! // The left hand drives the tip on the left of the picture: here the
//! // right module's (the instruments cross).
//! assert_eq!(teleop.hands(), [Side::Right, Side::Left]);
//! let moved = cycle.tips[1] - start[1];
//! // Along the image's u axis in the fixed frame, at up to 20 mm/s.
//! let u = cycle.step.frame.rotation * teleop.camera().axes().column(0);
//! assert!(moved.dot(&u) > 3.0 && moved.dot(&u) < 10.0);
//! assert!((moved - u * moved.dot(&u)).norm() < 1e-9);
//! assert_eq!(cycle.tips[0], start[0]); // the right hand did nothing
//! assert!(cycle.hold.is_none() && cycle.setpoints.iter().all(|q| q.is_finite()));
//! # Ok::<(), parasils::teleop::TeleopError>(())
//! ```
//!
//! [`Controller::step_commanded`]: crate::kin::Controller::step_commanded
//! [`Supervisor`]: crate::Supervisor

mod core;
mod cycle;
mod filter;
mod hold;
mod input;
mod motion;
mod moves;
mod params;
mod state;

pub use self::core::Teleop;
pub use cycle::{CommandOutcome, Fault, HoldAt, TeleopCycle};
pub use filter::{LowPass, dead_zone};
pub use input::{
    BUTTON_CLUTCH, BUTTON_ENABLE, CameraCommand, CameraInput, Command, Device, HandCommand,
    HandInput, Inputs,
};
pub use moves::{Goal, MoveRefused};
pub use params::{TeleopError, TeleopParams};
pub use state::{OperatingState, Transition};
