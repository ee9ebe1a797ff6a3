//! The engine: a [`Scenario`] planned and sampled at a fixed rate through
//! the controller's per-cycle call, one [`Record`] at a time.
//!
//! Two paths, one loop shape:
//! - **Without commands** (the paper's run), the reorientation is planned
//!   rest to rest as a [`Reorientation`] (or its time-optimal law),
//!   stretched onto the control cycle ([`OnCycle`]: a whole number of
//!   periods, the last sample at rest exactly on the goal), and each
//!   sample's state goes through [`Controller::step`]. The paper's 4.5 s at
//!   1 kHz already is a whole number of periods: its records are those of
//!   every earlier release, to the last bit.
//! - **With commands** (retargets, a stop; see [`Command`]), the run is an
//!   [`OnlineController`] loop, as a robot's controller runs it: the
//!   reorientation is commanded at `t = 0`, and each command at the first
//!   sample at or after its time, replanned from the state of that sample
//!   (position and velocity continuous; the acceleration may jump, and is 0
//!   at the sample a motion starts on, as at the start of every profile).
//!   The run ends at the first sample at which every command has taken
//!   effect and the last motion is at rest. The controller's margin
//!   [`Supervisor`] watches every cycle and stops the platform before a
//!   margin reaches its hard threshold (a [`CommandKind::SupervisorStop`]),
//!   where the rest-to-rest path would fail there with an error.
//!
//! Nothing is integrated: every record is computed from the trajectory's
//! analytic state at its time, so the tips' drift is the kinematics' rounding
//! only. Records stream to a [`Sink`] in [`Simulation::run`], the one loop
//! that the command line and the Python bindings both run; memory stays flat
//! however long the run.

mod error;
pub mod procedure;
mod records;
mod schedule;
mod simulation;

pub use error::{CommandError, CommandName, RunError, SimulationError};
pub use records::Records;
pub use schedule::Scheduled;
pub use simulation::Simulation;

#[cfg(test)]
mod tests;
