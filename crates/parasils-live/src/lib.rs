//! PARA-SILSROB live: the robot in real time, watched and driven from
//! Foxglove.
//!
//! A [`Session`] runs the teleoperation core ([`parasils_sim::TeleopRun`])
//! at the control rate on a thread of its own, serves every channel of the
//! simulation's MCAP file and the CRTK topics over Foxglove's WebSocket
//! protocol (`foxglove.sdk.v1`, through the Foxglove SDK, the `foxglove`
//! crate), takes each hand's input and the CRTK commands from clients, and
//! records the same messages to an MCAP file.
//!
//! ```text
//!  clients --(inputs, commands)--> [bounded queue] --> control loop (own thread, deadlines)
//!                                                        |  frames: [bounded queue, drop and count]
//!                                                        |  acks:   [queue]
//!                                                        v
//!  clients <--(each client's queue)-- WebSocket <-- publisher thread --> MCAP file
//! ```
//!
//! The control loop never waits on the network: it reads its input queue
//! without blocking, and hands each published cycle to the publisher with
//! a `try_send` that drops the frame (and counts it) when the publisher is
//! behind; each client has its own queue in the server, whose oldest
//! messages go when the client does not read. A slow client loses
//! messages, never cycles.
//!
//! # Modules
//! In import order: `error` ([`LiveError`]), `message` (what clients send:
//! [`ClientMessage`], [`parse`]), `crtk` (the CRTK topics' schemas and
//! builders: [`Arm`], [`Crtk`]), `timing` ([`CycleStats`]), `control` (the
//! loop: [`run_loop`], [`Frame`], [`Ack`]), `publish` (the channels and the
//! publisher: [`Channels`], [`run_publisher`]), `session` ([`Session`],
//! [`LiveOptions`]).

pub mod control;
pub mod crtk;
mod error;
pub mod message;
pub mod publish;
mod session;
mod timing;

pub use control::{Ack, AppliedInput, ClientTag, Event, Frame, LoopSettings, Queues, run_loop};
pub use crtk::{Arm, Crtk};
pub use error::LiveError;
pub use message::{
    COMMAND_TOPIC, ClientMessage, CommandRequest, DeviceInput, InputDevice, MessageError, parse,
};
pub use publish::{
    ACK_TOPIC, Channels, Clients, DIAGNOSTICS_TOPIC, PublishReport, PublishSettings, run_publisher,
};
pub use session::{
    AUTH_TOPIC, DEFAULT_PORT, LEGACY_SUBPROTOCOL, LiveOptions, SUBPROTOCOL, Session, SessionReport,
};
pub use timing::CycleStats;
