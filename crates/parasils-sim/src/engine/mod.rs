//! The engine: a [`Scenario`] planned and sampled at a fixed rate through
//! the controller's per-cycle call, one [`Record`] at a time.
//!
//! Two kinds of run ([`Run`](crate::Run)), one loop shape:
//! - **Planned** ([`Timeline`](crate::Timeline)): the motions one after the
//!   other on one time line of samples ([`procedure::ProcedurePlan`]), each
//!   planned rest to rest (its trapezoids, or its time-optimal law) and
//!   stretched onto the control cycle (a whole number of periods, the last
//!   sample at rest exactly on its target), each from the state the one
//!   before ended in; each sample's state goes through
//!   [`Controller::step_commanded`](parasils::kin::Controller::step_commanded).
//!   The paper's run is a timeline of one reorientation: its 4.5 s at
//!   1 kHz already is a whole number of periods, and its records are those
//!   of every earlier release, to the last bit. A procedure is checked in
//!   full before its first record ([`procedure::ProcedureCheck`]).
//! - **Online** ([`Online`](crate::Online): retargets, a stop; see
//!   [`Command`](crate::Command)), the run is an
//!   [`OnlineController`](parasils::OnlineController) loop, as a robot's
//!   controller runs it: the turn is commanded at `t = 0`, and each command
//!   at the first sample at or after its time, replanned from the state of
//!   that sample (position and velocity continuous; the acceleration may
//!   jump, and is 0 at the sample a motion starts on, as at the start of
//!   every profile). The run ends at the first sample at which every command
//!   has taken effect and the last motion is at rest. The controller's
//!   margin [`Supervisor`](parasils::Supervisor) watches every cycle and
//!   stops the platform before a margin reaches its hard threshold (a
//!   [`CommandKind::SupervisorStop`](crate::CommandKind::SupervisorStop)),
//!   where a planned run would fail there with an error.
//!
//! - **Teleoperation** ([`TeleopRun`], [`Replay`]): the teleoperation core
//!   stepped at the control rate from what each input device holds, a
//!   recorded session's rows or live devices; every cycle is a record, with
//!   the inputs and the core's state ([`TeleopRecord`](crate::TeleopRecord)).
//!
//! A planned run's clearance is also certified between its samples, motion
//! by motion, on demand ([`Simulation::certify_clearance`], `certify`).
//!
//! Nothing is integrated: every record is computed from the trajectory's
//! analytic state at its time, so the tips' drift is the kinematics' rounding
//! only. Records stream to a [`Sink`] in [`Simulation::run`], the one loop
//! that the command line and the Python bindings both run; memory stays flat
//! however long the run.

mod certify;
mod error;
pub mod procedure;
mod records;
mod schedule;
mod simulation;
mod teleop;

pub use certify::{CERTIFY_MAX_DEPTH, CERTIFY_TOLERANCE_MM, MotionClearance, RegionCertificate};
pub use error::{CommandError, CommandName, RunError, SimulationError};
pub use records::Records;
pub use schedule::Scheduled;
pub use simulation::Simulation;
pub use teleop::{Replay, SETTLE_S, TeleopRun};

#[cfg(test)]
mod tests;
