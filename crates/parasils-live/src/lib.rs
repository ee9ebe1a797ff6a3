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
//! behind (once the loop is over, the last cycle's frame waits for the
//! publisher, so a session and its recording always end on the same
//! cycle); each client has its own queue in the server, whose oldest
//! messages go when the client does not read. A slow client loses
//! messages, never cycles.
//!
//! Clients publish each device's input (six axes and buttons, or a
//! teleop panel's twist) and the CRTK commands; each command is
//! acknowledged to its client and on `/command_ack` with the state it led
//! to, and a message that does not parse is answered with an error naming
//! the field. The server binds to loopback unless told otherwise; with a
//! token ([`LiveOptions::token`]) a client publishes it on [`AUTH_TOPIC`]
//! before it may drive.
//!
//! # Why the Foxglove SDK
//! The `foxglove` crate (feature `websocket`, without its TLS backend)
//! serves the protocol Foxglove speaks today, `foxglove.sdk.v1`, refuses a
//! client offering only the legacy `foxglove.websocket.v1` with HTTP 400,
//! takes client-published channels, JSON channels with JSON Schemas, and
//! status messages to one client; and its MCAP writer is a sink of the same
//! channels, so the recording holds exactly what was served.
//!
//! # Modules
//! In import order: `error` ([`LiveError`]), `message` (what clients send:
//! [`ClientMessage`], [`parse`]), `crtk` (the CRTK topics' schemas and
//! builders: [`Arm`], [`Crtk`]), `realtime` (the control thread's
//! scheduling: [`Scheduling`]), `timing` ([`CycleStats`], [`wait_until`]),
//! `control` (the loop: [`run_loop`], [`Frame`], [`Ack`]), `service` (the
//! commands as the Foxglove service `/command`: [`CommandService`]), `publish` (the channels and the
//! publisher: [`Channels`], [`run_publisher`]), `session` ([`Session`],
//! [`LiveOptions`]).

pub mod control;
pub mod crtk;
mod error;
pub mod message;
pub mod publish;
mod realtime;
mod service;
mod session;
mod timing;

pub use control::{
    Ack, AppliedInput, ClientTag, Event, Frame, LoopSettings, PENDING_COMMANDS, Queues, Reply,
    run_loop,
};
pub use crtk::{Arm, Crtk};
pub use error::LiveError;
pub use message::{
    AUTH_TOPIC, COMMAND_TOPIC, ClientMessage, CommandRequest, DeviceInput, InputDevice,
    LiveCommand, MessageError, command_schema, parse,
};
pub use publish::{
    ACK_TOPIC, Channels, Clients, DIAGNOSTICS_TOPIC, PublishReport, PublishSettings, run_publisher,
};
pub use realtime::{Scheduling, schedule_current_thread};
pub use service::{Calls, CommandService, Drivers};
pub use session::{
    DEFAULT_PORT, LEGACY_SUBPROTOCOL, LiveOptions, SUBPROTOCOL, Session, SessionReport,
};
pub use timing::{CycleStats, LATE_TOLERANCE, wait_until};
