//! The commands as a Foxglove service, `/command`: the same JSON as on the
//! `/command` channel in the request, the acknowledgement (`/command_ack`'s
//! message) in the response, sent when the control loop has taken the
//! command. A request that does not parse, or one from a client without the
//! session's token, is answered with an error and changes nothing.
//!
//! The handler runs on the server's tasks: it parses, files the call's
//! responder under a number ([`Calls`]) and queues the command like a
//! channel's; the publisher answers the call when the acknowledgement comes
//! ([`Reply::Service`]).

use core::sync::atomic::{AtomicU32, Ordering};
use std::collections::{HashMap, HashSet};
use std::sync::mpsc::{SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use foxglove::websocket::service::{Handler, Request, Responder};

use crate::control::{Event, Reply};
use crate::message::{AUTH_TOPIC, COMMAND_TOPIC, ClientMessage, parse};

/// The service calls waiting for their acknowledgement, by number.
pub type Calls = Arc<Mutex<HashMap<u32, Responder>>>;

/// The session's token and the clients that sent it.
#[derive(Debug)]
pub struct Drivers {
    /// The token.
    pub token: String,
    /// The clients (their ids) that sent it.
    pub allowed: Mutex<HashSet<u32>>,
}

impl Drivers {
    /// Whether the client `id` sent the token.
    pub fn allows(&self, id: u32) -> bool {
        self.allowed.lock().is_ok_and(|a| a.contains(&id))
    }
}

/// The `/command` service's handler.
#[derive(Debug)]
pub struct CommandService {
    events: SyncSender<Event>,
    calls: Calls,
    next: AtomicU32,
    drivers: Option<Arc<Drivers>>,
}

impl CommandService {
    /// A handler queueing commands on `events`, filing calls in `calls`,
    /// taking them only from `drivers` when a token is needed.
    pub fn new(events: SyncSender<Event>, calls: Calls, drivers: Option<Arc<Drivers>>) -> Self {
        Self {
            events,
            calls,
            next: AtomicU32::new(0),
            drivers,
        }
    }
}

impl Handler for CommandService {
    fn call(&self, request: Request, responder: Responder) {
        let at = Instant::now();
        let client = u32::from(request.client_id());
        if self.drivers.as_ref().is_some_and(|d| !d.allows(client)) {
            responder.respond_err(format!(
                "{COMMAND_TOPIC}: refused: this server needs a token; publish {{\"token\": ...}} on {AUTH_TOPIC} first"
            ));
            return;
        }
        let command = match parse(COMMAND_TOPIC, request.payload()) {
            Ok(ClientMessage::Command(c)) => c,
            Ok(ClientMessage::Input(_)) => {
                responder.respond_err(format!("{COMMAND_TOPIC}: not a command"));
                return;
            }
            Err(e) => {
                responder.respond_err(e.to_string());
                return;
            }
        };
        let key = self.next.fetch_add(1, Ordering::Relaxed);
        let Ok(mut calls) = self.calls.lock() else {
            responder.respond_err("the session is ending".to_owned());
            return;
        };
        calls.insert(key, responder);
        drop(calls);
        let refused = match self
            .events
            .try_send(Event::Command(command, Reply::Service(key), at))
        {
            Ok(()) => return,
            Err(TrySendError::Full(_)) => "the control loop's input queue is full; command dropped",
            Err(TrySendError::Disconnected(_)) => "the session has ended",
        };
        if let Some(responder) = self.calls.lock().ok().and_then(|mut c| c.remove(&key)) {
            responder.respond_err(format!("{COMMAND_TOPIC}: {refused}"));
        }
    }
}
