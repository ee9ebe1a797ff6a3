//! The typed errors of a live session.

use std::path::PathBuf;

/// What can stop a live session from starting or finishing.
///
/// # When this happens / how to handle it
/// - [`LiveError::InvalidOption`]: an option out of its range (a rate that
///   is not positive, a publishing rate above the control rate): fix the
///   option; nothing was started.
/// - [`LiveError::Server`]: the WebSocket server could not start (the port
///   is taken, the address is not this machine's): choose another port
///   (`0` lets the system pick a free one).
/// - [`LiveError::Recording`]: the MCAP file could not be created or
///   finished: check the folder and the free space.
/// - [`LiveError::Simulation`]: the scenario or the teleoperation core
///   refused the setup, or a cycle failed; its message names the cause.
/// - [`LiveError::Thread`]: a thread of the session could not be started
///   or ended abnormally.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LiveError {
    /// An option out of its range.
    #[error("live: {what} = {value} is out of range: {expected}")]
    InvalidOption {
        /// The option's name.
        what: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The WebSocket server could not start.
    #[error("live: cannot serve on {address}: {reason}")]
    Server {
        /// The address asked for, `host:port`.
        address: String,
        /// Why.
        reason: String,
    },
    /// The MCAP recording could not be created or finished.
    #[error("live: recording to {}: {reason}", path.display())]
    Recording {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The scenario, the core's setup or a cycle failed.
    #[error("live: {0}")]
    Simulation(#[from] parasils_sim::SimulationError),
    /// A message builder of the simulation's MCAP writer refused a value.
    #[error("live: {0}")]
    Message(#[from] parasils_sim::McapError),
    /// A thread of the session could not start or ended abnormally.
    #[error("live: the {which} thread {what}")]
    Thread {
        /// Which thread: `control`, `publisher`.
        which: &'static str,
        /// What went wrong.
        what: &'static str,
    },
}
