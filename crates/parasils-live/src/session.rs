//! A live session: the WebSocket server, the MCAP recording, the control
//! loop's thread and the publisher's thread, started together and ended
//! together.

use core::net::SocketAddr;
use core::sync::atomic::{AtomicBool, Ordering};
use std::collections::{HashMap, HashSet};
use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;
use std::sync::mpsc::{SyncSender, TrySendError, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use foxglove::websocket::service::{Service, ServiceSchema};
use foxglove::websocket::{Capability, Client, ClientChannel, ServerListener, Status};
use foxglove::{Context, McapWriterHandle, Schema, WebSocketServerHandle};
use parasils_sim::{CameraImage, SceneGeometry, TeleopRun};

use crate::control::{Event, LoopSettings, PENDING_COMMANDS, Queues, Reply, run_loop};
use crate::error::LiveError;
use crate::message::{
    AUTH_TOPIC, COMMAND_TOPIC, ClientMessage, InputDevice, command_schema, parse,
};
use crate::publish::{
    Channels, Clients, PublishReport, PublishSettings, ack_schema, pretty, run_publisher,
};
use crate::realtime::{Scheduling, schedule_current_thread};
use crate::service::{Calls, CommandService, Drivers};
use crate::timing::CycleStats;

/// The WebSocket subprotocol the server speaks (the Foxglove SDK's); the
/// legacy `foxglove.websocket.v1` is refused with HTTP 400.
pub const SUBPROTOCOL: &str = "foxglove.sdk.v1";
/// The subprotocol refused.
pub const LEGACY_SUBPROTOCOL: &str = "foxglove.websocket.v1";
/// The default port, Foxglove's.
pub const DEFAULT_PORT: u16 = 8765;

/// How a session runs.
#[derive(Debug, Clone, PartialEq)]
pub struct LiveOptions {
    /// The address to bind, `127.0.0.1` by default (loopback only).
    pub bind: String,
    /// The port (`0`: a free one, see [`Session::address`]).
    pub port: u16,
    /// The data channels' publishing rate, Hz (at most the control rate; a
    /// whole divisor of it is published exactly).
    pub publish_hz: f64,
    /// The period of `/tf`, `/scene`, the camera and the operating state, s.
    pub scene_period_s: f64,
    /// The session's length, s (`None`: until stopped).
    pub duration_s: Option<f64>,
    /// The MCAP file the session is recorded to, if any.
    pub record: Option<PathBuf>,
    /// The frames the publisher's queue holds before the loop drops them.
    pub queue_frames: usize,
    /// The messages each client's queue holds before its oldest is dropped.
    pub client_backlog: usize,
    /// A token a client must publish on [`AUTH_TOPIC`] (`{"token": ...}`)
    /// before its inputs and commands are taken (`None`: none needed).
    /// Watching needs no token.
    pub token: Option<String>,
    /// The control thread's `SCHED_FIFO` priority, 1 to 99, when the
    /// system allows it (`None`: the ordinary policy); see
    /// [`Session::scheduling`] for what it got.
    pub realtime_priority: Option<u8>,
    /// How long before each deadline the control loop stops sleeping and
    /// spins, s (see [`crate::wait_until`]): from 0 to half the control
    /// period (a real-time thread that never sleeps is throttled by Linux).
    pub spin_margin_s: f64,
}

impl Default for LiveOptions {
    /// Loopback on 8765, 100 Hz publishing, 20 ms scenes, no end, no
    /// recording, 1024 frames (1 s of frames at 1 kHz publishing), 32768
    /// messages per client (about 1.5 s of every channel at 1 kHz
    /// publishing, some 10 MB), no token, `SCHED_FIFO` priority 80 where
    /// allowed, a spin of the last 100 us before each deadline (the
    /// wake-up's measured jitter: BENCHMARKS.md, *Live*).
    fn default() -> Self {
        Self {
            bind: "127.0.0.1".to_owned(),
            port: DEFAULT_PORT,
            publish_hz: 100.0,
            scene_period_s: 0.02,
            duration_s: None,
            record: None,
            queue_frames: 1024,
            client_backlog: 32768,
            token: None,
            realtime_priority: Some(80),
            spin_margin_s: 100e-6,
        }
    }
}

impl LiveOptions {
    /// The options as the recording's `parasils.scenario` metadata gives
    /// them (`live_options`, JSON): the control rate (Hz) and every option
    /// but the token, of which only whether one is needed.
    pub fn metadata(&self, rate_hz: f64) -> serde_json::Value {
        serde_json::json!({
            "rate_hz": rate_hz,
            "bind": self.bind,
            "port": self.port,
            "publish_hz": self.publish_hz,
            "scene_period_s": self.scene_period_s,
            "duration_s": self.duration_s,
            "queue_frames": self.queue_frames,
            "client_backlog": self.client_backlog,
            "token_required": self.token.is_some(),
            "realtime_priority": self.realtime_priority,
            "spin_margin_s": self.spin_margin_s,
        })
    }

    /// Whether the address is this machine's loopback only.
    pub fn is_loopback(&self) -> bool {
        matches!(self.bind.as_str(), "127.0.0.1" | "localhost" | "::1")
            || self.bind.starts_with("127.")
    }
}

/// The clients' messages, from the server's tasks to the control loop.
struct Listener {
    events: SyncSender<Event>,
    clients: Clients,
    /// The token, and the clients that sent it.
    token: Option<Arc<Drivers>>,
}

impl Listener {
    /// Whether `client` may drive; a message on [`AUTH_TOPIC`] is checked
    /// here and answered (`false`: nothing more to do with it).
    fn authorised(&self, client: &Client, topic: &str, payload: &[u8]) -> bool {
        let Some(drivers) = &self.token else {
            return topic != AUTH_TOPIC;
        };
        let Ok(mut allowed) = drivers.allowed.lock() else {
            return false;
        };
        if topic == AUTH_TOPIC {
            let sent = serde_json::from_slice::<serde_json::Value>(payload)
                .ok()
                .and_then(|v| {
                    v.get("token")
                        .and_then(serde_json::Value::as_str)
                        .map(str::to_owned)
                });
            if sent.as_deref() == Some(drivers.token.as_str()) {
                allowed.insert(tag(client));
                client.send_status(Status::info(
                    "/auth: token accepted; inputs and commands are taken",
                ));
            } else {
                client.send_status(Status::error("/auth: wrong token"));
            }
            return false;
        }
        if allowed.contains(&tag(client)) {
            true
        } else {
            client.send_status(Status::error(format!(
                "{topic}: refused: this server needs a token; publish {{\"token\": ...}} on {AUTH_TOPIC} first"
            )));
            false
        }
    }
}

fn tag(client: &Client) -> u32 {
    u32::from(client.id())
}

impl ServerListener for Listener {
    fn on_client_advertise(&self, client: Client, channel: &ClientChannel) {
        let known = channel.topic == COMMAND_TOPIC
            || channel.topic == AUTH_TOPIC
            || InputDevice::ALL.iter().any(|d| d.topic() == channel.topic);
        if !known {
            client.send_status(Status::warning(format!(
                "{}: not an input topic; its messages will be refused",
                channel.topic
            )));
        }
        if let Ok(mut map) = self.clients.lock() {
            map.insert(tag(&client), client);
        }
    }

    fn on_message_data(&self, client: Client, channel: &ClientChannel, payload: &[u8]) {
        let at = Instant::now();
        if !self.authorised(&client, &channel.topic, payload) {
            if self.token.is_none() {
                client.send_status(Status::error(format!(
                    "{AUTH_TOPIC}: this server needs no token"
                )));
            }
            return;
        }
        let event = match parse(&channel.topic, payload) {
            Ok(ClientMessage::Input(input)) => Event::Input(input, at),
            Ok(ClientMessage::Command(request)) => {
                Event::Command(request, Reply::Status(tag(&client)), at)
            }
            Err(e) => {
                client.send_status(Status::error(e.to_string()));
                return;
            }
        };
        match self.events.try_send(event) {
            Ok(()) => {}
            Err(TrySendError::Full(_)) => client.send_status(Status::error(format!(
                "{}: the control loop's input queue is full; message dropped",
                channel.topic
            ))),
            Err(TrySendError::Disconnected(_)) => {
                client.send_status(Status::error("the session has ended".to_owned()))
            }
        }
    }
}

/// What a session did.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionReport {
    /// The control loop's timing.
    pub stats: CycleStats,
    /// The publisher's counts.
    pub published: PublishReport,
    /// The recording, if any.
    pub record: Option<PathBuf>,
}

/// A session under way.
pub struct Session {
    address: SocketAddr,
    topics: Vec<String>,
    stop: Arc<AtomicBool>,
    control: Option<JoinHandle<Result<CycleStats, parasils_sim::SimulationError>>>,
    publisher: Option<JoinHandle<Result<PublishReport, parasils_sim::McapError>>>,
    server: Option<WebSocketServerHandle>,
    mcap: Option<McapWriterHandle<BufWriter<File>>>,
    record: Option<PathBuf>,
    scheduling: Scheduling,
    /// The channels' context: the server and the recording hold it weakly,
    /// so it lives as long as the session.
    _context: Arc<Context>,
}

impl Drop for Session {
    /// A session dropped without [`Session::wait`] stops its loop (the
    /// server and the recording end with their handles).
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
    }
}

impl core::fmt::Debug for Session {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Session")
            .field("address", &self.address)
            .field("record", &self.record)
            .field("scheduling", &self.scheduling)
            .finish_non_exhaustive()
    }
}

fn positive(what: &'static str, value: f64) -> Result<(), LiveError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(LiveError::InvalidOption {
            what,
            value,
            expected: "a positive, finite number",
        })
    }
}

impl Session {
    /// Starts `run` live with `options`: the recording first (if asked),
    /// the channels, the server, then the two threads.
    ///
    /// # Errors
    /// [`LiveError::InvalidOption`], [`LiveError::Recording`],
    /// [`LiveError::Server`], [`LiveError::Thread`], and the geometry's
    /// errors ([`LiveError::Message`]).
    pub fn start(run: TeleopRun, options: &LiveOptions) -> Result<Self, LiveError> {
        let rate_hz = run.rate_hz();
        positive("publish_hz", options.publish_hz)?;
        if options.publish_hz > rate_hz * (1.0 + 1e-9) {
            return Err(LiveError::InvalidOption {
                what: "publish_hz",
                value: options.publish_hz,
                expected: "at most the control rate",
            });
        }
        if !(options.scene_period_s.is_finite() && options.scene_period_s >= 0.0) {
            return Err(LiveError::InvalidOption {
                what: "scene_period_s",
                value: options.scene_period_s,
                expected: "a finite number from 0",
            });
        }
        if let Some(d) = options.duration_s {
            positive("duration_s", d)?;
        }
        // A thread that spins most of each cycle never sleeps: at
        // `SCHED_FIFO`, Linux then takes the processor from it for 50 ms of
        // every second (`kernel.sched_rt_runtime_us`), 50 late cycles a
        // second at 1 kHz (BENCHMARKS.md, *Live*).
        if !(options.spin_margin_s.is_finite()
            && options.spin_margin_s >= 0.0
            && options.spin_margin_s <= 0.5 / rate_hz)
        {
            return Err(LiveError::InvalidOption {
                what: "spin_margin_s",
                value: options.spin_margin_s,
                expected: "from 0 to half the control period, so that the control thread sleeps at least half of each cycle",
            });
        }
        if options.queue_frames == 0 || options.client_backlog == 0 {
            return Err(LiveError::InvalidOption {
                what: "queue size",
                value: 0.0,
                expected: "at least 1",
            });
        }
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "positive, finite, checked above"
        )]
        let publish_every = ((rate_hz / options.publish_hz).round() as u64).max(1);
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "positive, finite, checked above"
        )]
        let cycles = options.duration_s.map(|d| (d * rate_hz).round() as u64 + 1);

        let scenario = run.scenario();
        let geometry = SceneGeometry::from_robot(&scenario.robot)
            .and_then(|g| g.with_bodies(scenario.bodies))
            .map_err(|e| LiveError::Message(parasils_sim::McapError::Geometry(e)))?;
        let tips = scenario.tips();
        let mut settings = PublishSettings {
            rate_hz,
            publish_hz: rate_hz / publish_every as f64,
            scene_period_s: options.scene_period_s,
            targets: [tips.left, tips.right],
            image: CameraImage::of(&scenario.robot.endoscope.camera),
            scheduling: String::new(),
        };

        let ctx = Context::new();
        let mcap =
            match &options.record {
                None => None,
                Some(path) => Some(ctx.mcap_writer().create_new_buffered_file(path).map_err(
                    |e| LiveError::Recording {
                        path: path.clone(),
                        reason: e.to_string(),
                    },
                )?),
            };
        if let (Some(handle), Some(path)) = (&mcap, &options.record) {
            let mut meta =
                parasils_sim::mcap::scenario_metadata(scenario, &geometry, options.scene_period_s)?;
            meta.insert(
                "live_options".to_owned(),
                options.metadata(rate_hz).to_string(),
            );
            handle
                .write_metadata(parasils_sim::mcap::SCENARIO_METADATA, meta)
                .map_err(|e| LiveError::Recording {
                    path: path.clone(),
                    reason: e.to_string(),
                })?;
        }
        let channels = Channels::new(&ctx)?;
        let topics = channels.topics();

        let (events_in, events) = sync_channel(1024);
        let (frames, frames_out) = sync_channel(options.queue_frames);
        let (acks, acks_out) = sync_channel(PENDING_COMMANDS);
        let clients: Clients = Arc::new(Mutex::new(HashMap::new()));
        let calls: Calls = Arc::new(Mutex::new(HashMap::new()));
        let drivers = options.token.clone().map(|token| {
            Arc::new(Drivers {
                token,
                allowed: Mutex::new(HashSet::new()),
            })
        });
        let service = Service::builder(
            COMMAND_TOPIC,
            ServiceSchema::new("parasils.Command")
                .with_request(
                    "json",
                    Schema::new("parasils.Command", "jsonschema", pretty(&command_schema())),
                )
                .with_response(
                    "json",
                    Schema::new("parasils.CommandAck", "jsonschema", pretty(&ack_schema())),
                ),
        )
        .handler(CommandService::new(
            events_in.clone(),
            Arc::clone(&calls),
            drivers.clone(),
        ));
        let listener = Arc::new(Listener {
            events: events_in,
            clients: Arc::clone(&clients),
            token: drivers,
        });
        let address = format!("{}:{}", options.bind, options.port);
        let server = ctx
            .websocket_server()
            .name(concat!("parasils ", env!("CARGO_PKG_VERSION")))
            .bind(options.bind.clone(), options.port)
            .capabilities([Capability::ClientPublish])
            .services([service])
            .supported_encodings(["json"])
            .message_backlog_size(options.client_backlog)
            .listener(listener)
            .start_blocking()
            .map_err(|e| LiveError::Server {
                address: address.clone(),
                reason: e.to_string(),
            })?;
        let ip = options
            .bind
            .parse()
            .unwrap_or(core::net::IpAddr::V4(core::net::Ipv4Addr::LOCALHOST));
        let address = SocketAddr::new(ip, server.port());

        let stop = Arc::new(AtomicBool::new(false));
        let loop_stop = Arc::clone(&stop);
        let (scheduled, scheduling) = sync_channel(1);
        let priority = options.realtime_priority;
        let spin_margin = core::time::Duration::from_secs_f64(options.spin_margin_s);
        let start = Instant::now();
        let control = std::thread::Builder::new()
            .name("parasils-control".to_owned())
            .spawn(move || {
                // Told before the first cycle; the session waits for it.
                let _ = scheduled.send(schedule_current_thread(priority));
                let queues = Queues {
                    events,
                    frames,
                    acks,
                };
                run_loop(
                    run,
                    LoopSettings {
                        publish_every,
                        cycles,
                        spin_margin,
                    },
                    &queues,
                    &loop_stop,
                    start,
                )
            })
            .map_err(|_| LiveError::Thread {
                which: "control",
                what: "could not start",
            })?;
        let scheduling = scheduling.recv().map_err(|_| LiveError::Thread {
            which: "control",
            what: "ended before its first cycle",
        })?;
        settings.scheduling = scheduling.to_string();
        let publisher = std::thread::Builder::new()
            .name("parasils-publish".to_owned())
            .spawn(move || {
                run_publisher(
                    channels,
                    geometry,
                    settings,
                    &frames_out,
                    &acks_out,
                    &clients,
                    &calls,
                )
            })
            .map_err(|_| LiveError::Thread {
                which: "publisher",
                what: "could not start",
            })?;
        Ok(Self {
            address,
            topics,
            stop,
            control: Some(control),
            publisher: Some(publisher),
            server: Some(server),
            mcap,
            record: options.record.clone(),
            scheduling,
            _context: ctx,
        })
    }

    /// The address the server listens on (the port the system chose for
    /// port 0).
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    /// Every topic served, in the order the channels were made.
    pub fn topics(&self) -> &[String] {
        &self.topics
    }

    /// How the control thread is scheduled: `SCHED_FIFO` when asked for
    /// and allowed, the ordinary policy otherwise (with the reason).
    pub fn scheduling(&self) -> &Scheduling {
        &self.scheduling
    }

    /// Whether the control loop has ended (its duration run, or a failure).
    pub fn is_finished(&self) -> bool {
        self.control.as_ref().is_none_or(JoinHandle::is_finished)
    }

    /// Asks the control loop to end after its current cycle.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::SeqCst);
    }

    /// Waits for the loop to end (its duration, or [`Session::stop`]), then
    /// for the publisher to log what it was given, stops the server and
    /// finishes the recording; what the session did.
    ///
    /// # Errors
    /// The loop's failure ([`LiveError::Simulation`]), the publisher's
    /// ([`LiveError::Message`]), the recording's ([`LiveError::Recording`]),
    /// a thread that panicked ([`LiveError::Thread`]). The recording is
    /// finished in every case.
    pub fn wait(mut self) -> Result<SessionReport, LiveError> {
        let control = self.control.take().map(JoinHandle::join);
        let publisher = self.publisher.take().map(JoinHandle::join);
        if let Some(server) = self.server.take() {
            server.stop().wait_blocking();
        }
        let finished = match (self.mcap.take(), &self.record) {
            (Some(handle), Some(path)) => {
                handle
                    .close()
                    .map(|_| ())
                    .map_err(|e| LiveError::Recording {
                        path: path.clone(),
                        reason: e.to_string(),
                    })
            }
            _ => Ok(()),
        };
        let stats = match control {
            Some(Ok(r)) => r?,
            _ => {
                return Err(LiveError::Thread {
                    which: "control",
                    what: "panicked",
                });
            }
        };
        let published = match publisher {
            Some(Ok(r)) => r?,
            _ => {
                return Err(LiveError::Thread {
                    which: "publisher",
                    what: "panicked",
                });
            }
        };
        finished?;
        Ok(SessionReport {
            stats,
            published,
            record: self.record.take(),
        })
    }
}
