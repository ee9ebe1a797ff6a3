//! The publisher: on a thread of its own, it turns the control loop's
//! frames into messages and logs them on the Foxglove channels, which hand
//! each one to every sink: the WebSocket server (each subscribed client's
//! queue, which drops its oldest message when a client does not keep up)
//! and the MCAP recording. So the live channels and the file hold the same
//! messages, built by the simulation's own builders: the data channels from
//! its column table, `/tf`, `/scene` and the camera's two topics by its
//! scene and camera writers, as in `parasils simulate`'s MCAP file; then
//! the CRTK topics ([`crate::crtk`]), `/diagnostics` and `/command_ack`.

use std::collections::HashMap;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::sync::{Arc, Mutex};

use foxglove::websocket::{Client, Status};
use foxglove::{Context, PartialMetadata, RawChannel, Schema};
use nalgebra::Vector3;
use parasils_sim::mcap::{
    ANNOTATIONS_TOPIC, CALIBRATION_TOPIC, CAMERA_CALIBRATION_SCHEMA, FRAME_TRANSFORMS_SCHEMA,
    IMAGE_ANNOTATIONS_SCHEMA, SCENE_TOPIC, SCENE_UPDATE_SCHEMA, TF_TOPIC,
};
use parasils_sim::{CameraImage, Channel, Field, McapError, SceneGeometry};
use serde_json::json;

use crate::control::{Ack, ClientTag, Frame, Reply};
use crate::crtk::{self, Arm, Crtk};
use crate::error::LiveError;
use crate::service::Calls;

/// The topic of the loop's timing and the session's counts.
pub const DIAGNOSTICS_TOPIC: &str = "/diagnostics";
/// The topic of the commands' acknowledgements.
pub const ACK_TOPIC: &str = "/command_ack";
/// The period of `/diagnostics`, s.
pub const DIAGNOSTICS_PERIOD_S: f64 = 0.1;

/// How long the publisher sleeps when its queues are empty, s.
pub const POLL_PERIOD_S: f64 = 0.5e-3;

/// The clients a command can come from, by their tag, for the replies.
pub type Clients = Arc<Mutex<HashMap<ClientTag, Client>>>;

/// The JSON Schema of `/diagnostics`.
pub fn diagnostics_schema() -> serde_json::Value {
    let n = |d: &str| json!({"type": "number", "description": d});
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "parasils.Diagnostics",
        "description": "The control loop's timing and the session's counts since its start",
        "type": "object",
        "properties": {
            "t_s": n("unit: s"),
            "rate_hz": n("the control rate, Hz"),
            "publish_hz": n("the publishing rate of the data channels, Hz"),
            "cycles": n("cycles run"),
            "deadline_misses": n("cycles that started late or overran (either or both)"),
            "late_starts": n("cycles that started more than late_tolerance_us after their deadline"),
            "overruns": n("cycles whose work ended after the next cycle was due"),
            "late_tolerance_us": n("how long after its deadline a cycle may start and be on time, us"),
            "scheduling": {"type": "string", "description": "the control thread's scheduling: SCHED_FIFO and its priority, or the ordinary policy and why"},
            "worst_cycle_us": n("the longest cycle's work, us"),
            "mean_cycle_us": n("the mean cycle's work, us"),
            "worst_late_us": n("the latest start of a cycle after its deadline, us"),
            "dropped_frames": n("published cycles dropped because the publisher was behind"),
            "last_input": {
                "type": ["object", "null"],
                "description": "the last client input the loop applied: its device and number, when it arrived, the time of the cycle that first used it and when that cycle read it (s since the session's start)",
                "properties": {
                    "device": {"type": "string", "enum": ["left", "right", "camera"]},
                    "id": {"type": ["integer", "null"]},
                    "arrival_s": n("unit: s"),
                    "applied_t_s": n("unit: s (the cycle's time, k / rate)"),
                    "applied_s": n("unit: s (when that cycle read it)"),
                    "previous_read_s": n("unit: s (when the cycle before read its inputs)"),
                },
            },
        },
        "required": ["t_s", "rate_hz", "publish_hz", "cycles", "deadline_misses", "late_starts", "overruns", "late_tolerance_us", "scheduling", "worst_cycle_us", "mean_cycle_us", "worst_late_us", "dropped_frames", "last_input"],
        "additionalProperties": false,
    })
}

/// The JSON Schema of `/command_ack`.
pub fn ack_schema() -> serde_json::Value {
    json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "parasils.CommandAck",
        "description": "A command's outcome: the state it came in, the state it led to, whether CRTK's table accepts it there, and why not",
        "type": "object",
        "properties": {
            "t_s": {"type": "number", "description": "unit: s (the cycle that took it)"},
            "command": {"type": "string", "enum": crate::message::LiveCommand::NAMES},
            "id": {"type": ["integer", "null"]},
            "accepted": {"type": "boolean"},
            "before": {"type": "string", "enum": ["DISABLED", "ENABLED", "PAUSED", "FAULT"]},
            "state": {"type": "string", "enum": ["DISABLED", "ENABLED", "PAUSED", "FAULT"]},
            "reason": {"type": ["string", "null"], "description": "why it was refused"},
        },
        "required": ["t_s", "command", "id", "accepted", "before", "state", "reason"],
        "additionalProperties": false,
    })
}

/// Every channel of a session, made in one [`Context`].
#[derive(Debug)]
pub struct Channels {
    data: Vec<(Arc<RawChannel>, Vec<Field>, &'static str)>,
    tf: Arc<RawChannel>,
    scene: Arc<RawChannel>,
    calibration: Arc<RawChannel>,
    annotations: Arc<RawChannel>,
    crtk: Vec<(Arm, Crtk, Arc<RawChannel>)>,
    diagnostics: Arc<RawChannel>,
    ack: Arc<RawChannel>,
}

fn channel(
    ctx: &Arc<Context>,
    topic: &str,
    schema_name: &str,
    schema: Vec<u8>,
) -> Result<Arc<RawChannel>, LiveError> {
    ctx.channel_builder(topic)
        .message_encoding("json")
        .schema(Schema::new(schema_name, "jsonschema", schema))
        .build_raw()
        .map_err(|e| LiveError::Server {
            address: topic.to_owned(),
            reason: format!("cannot make the channel: {e}"),
        })
}

/// `v` as pretty JSON bytes (a schema's text).
pub fn pretty(v: &serde_json::Value) -> Vec<u8> {
    serde_json::to_vec_pretty(v).unwrap_or_default()
}

impl Channels {
    /// The channels, in `ctx`.
    ///
    /// # Errors
    /// [`LiveError::Server`] when a channel cannot be made.
    pub fn new(ctx: &Arc<Context>) -> Result<Self, LiveError> {
        let mut data = Vec::new();
        for c in Channel::ALL {
            let fields = parasils_sim::mcap::fields(c);
            let schema = pretty(&parasils_sim::mcap::data_schema(c, &fields));
            data.push((
                channel(ctx, c.topic(), c.schema_name(), schema)?,
                fields,
                c.topic(),
            ));
        }
        let official = |s: &str| s.as_bytes().to_vec();
        let mut crtk = Vec::new();
        for arm in Arm::ALL {
            for kind in Crtk::ALL {
                let ch = channel(
                    ctx,
                    &crtk::topic(arm, kind),
                    kind.schema_name(),
                    pretty(&kind.schema()),
                )?;
                crtk.push((arm, kind, ch));
            }
        }
        Ok(Self {
            data,
            tf: channel(
                ctx,
                TF_TOPIC,
                "foxglove.FrameTransforms",
                official(FRAME_TRANSFORMS_SCHEMA),
            )?,
            scene: channel(
                ctx,
                SCENE_TOPIC,
                "foxglove.SceneUpdate",
                official(SCENE_UPDATE_SCHEMA),
            )?,
            calibration: channel(
                ctx,
                CALIBRATION_TOPIC,
                "foxglove.CameraCalibration",
                official(CAMERA_CALIBRATION_SCHEMA),
            )?,
            annotations: channel(
                ctx,
                ANNOTATIONS_TOPIC,
                "foxglove.ImageAnnotations",
                official(IMAGE_ANNOTATIONS_SCHEMA),
            )?,
            crtk,
            diagnostics: channel(
                ctx,
                DIAGNOSTICS_TOPIC,
                "parasils.Diagnostics",
                pretty(&diagnostics_schema()),
            )?,
            ack: channel(ctx, ACK_TOPIC, "parasils.CommandAck", pretty(&ack_schema()))?,
        })
    }

    /// Every topic, in the order the channels were made.
    pub fn topics(&self) -> Vec<String> {
        let mut t: Vec<String> = self
            .data
            .iter()
            .map(|(c, _, _)| c.topic().to_owned())
            .collect();
        for c in [&self.tf, &self.scene, &self.calibration, &self.annotations] {
            t.push(c.topic().to_owned());
        }
        t.extend(self.crtk.iter().map(|(_, _, c)| c.topic().to_owned()));
        t.push(DIAGNOSTICS_TOPIC.to_owned());
        t.push(ACK_TOPIC.to_owned());
        t
    }
}

/// The publisher's settings.
#[derive(Debug, Clone)]
pub struct PublishSettings {
    /// The control rate, Hz.
    pub rate_hz: f64,
    /// The data channels' rate, Hz.
    pub publish_hz: f64,
    /// The period of `/tf`, `/scene`, the camera and `operating_state`, s.
    pub scene_period_s: f64,
    /// The tips the scene draws as targets (the start's), mm.
    pub targets: [Vector3<f64>; 2],
    /// The schematic endoscope image.
    pub image: CameraImage,
    /// The control thread's scheduling, in words (`/diagnostics`).
    pub scheduling: String,
}

/// What the publisher did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PublishReport {
    /// Frames published.
    pub frames: u64,
    /// Messages logged.
    pub messages: u64,
    /// Acknowledgements sent.
    pub acks: u64,
}

/// The publisher's state between frames.
struct Publisher {
    channels: Channels,
    geometry: SceneGeometry,
    settings: PublishSettings,
    /// The last frame, and whether its visuals and diagnostics went out.
    last: Option<(Frame, bool, bool)>,
    next_scene_s: f64,
    next_diagnostics_s: f64,
    buf: Vec<u8>,
    ryu: ryu::Buffer,
    report: PublishReport,
}

impl Publisher {
    fn log(&mut self, which: &Arc<RawChannel>, ns: u64) {
        which.log_with_meta(&self.buf, PartialMetadata::with_log_time(ns));
        self.report.messages += 1;
    }

    fn frame(&mut self, f: &Frame) -> Result<(), McapError> {
        let r = &f.record;
        let ns = parasils_sim::mcap::log_time(r.t)?;
        for k in 0..self.channels.data.len() {
            self.buf.clear();
            let (ch, fields, topic) = &self.channels.data[k];
            for field in fields {
                self.buf.extend_from_slice(&field.key);
                if let Err(value) = parasils_sim::mcap::push_num(
                    &mut self.buf,
                    &mut self.ryu,
                    field.column.value(r),
                ) {
                    return Err(McapError::NonFinite {
                        topic,
                        field: field.column.name,
                        t: r.t,
                        value,
                    });
                }
            }
            self.buf.push(b'}');
            let ch = Arc::clone(ch);
            self.log(&ch, ns);
        }
        let scene = r.t >= self.next_scene_s;
        self.crtk(f, ns, false);
        if scene {
            self.next_scene_s = r.t + self.settings.scene_period_s;
            self.visuals(f, ns)?;
        }
        let diagnostics = r.t >= self.next_diagnostics_s;
        if diagnostics {
            self.next_diagnostics_s = r.t + DIAGNOSTICS_PERIOD_S;
            self.diagnostics(f, ns);
        }
        self.report.frames += 1;
        self.last = Some((*f, scene, diagnostics));
        Ok(())
    }

    /// The CRTK topics for `f`: the joints and poses, or (`state`) the
    /// operating states.
    fn crtk(&mut self, f: &Frame, ns: u64, state: bool) {
        for k in 0..self.channels.crtk.len() {
            let (arm, kind, ch) = &self.channels.crtk[k];
            if (*kind == Crtk::OperatingState) != state {
                continue;
            }
            self.buf = crtk::message(*arm, *kind, &self.geometry, &f.record, f.busy);
            let ch = Arc::clone(ch);
            self.log(&ch, ns);
        }
    }

    /// The operating states, `/tf`, `/scene` and the camera's two topics
    /// for `f`.
    fn visuals(&mut self, f: &Frame, ns: u64) -> Result<(), McapError> {
        self.crtk(f, ns, true);
        let r = &f.record;
        self.buf.clear();
        parasils_sim::mcap::write_tf(&self.geometry, r, ns, &mut self.buf, &mut self.ryu)?;
        let ch = Arc::clone(&self.channels.tf);
        self.log(&ch, ns);
        self.buf.clear();
        parasils_sim::mcap::write_scene(
            &self.geometry,
            &self.settings.targets,
            r,
            None,
            ns,
            &mut self.buf,
            &mut self.ryu,
        )?;
        let ch = Arc::clone(&self.channels.scene);
        self.log(&ch, ns);
        self.buf.clear();
        parasils_sim::mcap::write_calibration(
            &self.settings.image,
            ns,
            r.t,
            &mut self.buf,
            &mut self.ryu,
        )?;
        let ch = Arc::clone(&self.channels.calibration);
        self.log(&ch, ns);
        self.buf.clear();
        parasils_sim::mcap::write_annotations(
            &self.settings.image,
            r,
            ns,
            &mut self.buf,
            &mut self.ryu,
        )?;
        let ch = Arc::clone(&self.channels.annotations);
        self.log(&ch, ns);
        Ok(())
    }

    /// The last frame's visuals and diagnostics, if its own period did
    /// not publish them, so that the recording ends on the last cycle.
    fn finish(&mut self) -> Result<(), McapError> {
        if let Some((f, scene, diagnostics)) = self.last.take() {
            let ns = parasils_sim::mcap::log_time(f.record.t)?;
            if !scene {
                self.visuals(&f, ns)?;
            }
            if !diagnostics {
                self.diagnostics(&f, ns);
            }
        }
        Ok(())
    }

    fn diagnostics(&mut self, f: &Frame, ns: u64) {
        let s = &f.stats;
        let input = f.input.map(|i| {
            json!({
                "device": i.device.name(),
                "id": i.id,
                "arrival_s": i.arrival_s,
                "applied_t_s": i.applied_t_s,
                "applied_s": i.applied_s,
                "previous_read_s": i.previous_read_s,
            })
        });
        let v = json!({
            "t_s": f.record.t,
            "rate_hz": self.settings.rate_hz,
            "publish_hz": self.settings.publish_hz,
            "cycles": s.cycles,
            "deadline_misses": s.deadline_misses,
            "late_starts": s.late_starts,
            "overruns": s.overruns,
            "late_tolerance_us": crate::timing::LATE_TOLERANCE * 1e6 / self.settings.rate_hz,
            "scheduling": self.settings.scheduling,
            "worst_cycle_us": s.worst_cycle_s * 1e6,
            "mean_cycle_us": s.mean_cycle_s() * 1e6,
            "worst_late_us": s.worst_late_s * 1e6,
            "dropped_frames": s.dropped_frames,
            "last_input": input,
        });
        self.buf = v.to_string().into_bytes();
        let ch = Arc::clone(&self.channels.diagnostics);
        self.log(&ch, ns);
    }

    fn ack(&mut self, a: &Ack, clients: &Clients, calls: &Calls) {
        let reason = match (a.accepted, a.refusal) {
            (true, _) => None,
            (false, Some(why)) => Some(format!(
                "{} refused: {why}; the state stays {}",
                a.request.command.name(),
                a.after.name()
            )),
            (false, None) => Some(format!(
                "{} is not valid in {} (CRTK's table); the state stays {}",
                a.request.command.name(),
                a.before.name(),
                a.after.name()
            )),
        };
        let v = json!({
            "t_s": a.t_s,
            "command": a.request.command.name(),
            "id": a.request.id,
            "accepted": a.accepted,
            "before": a.before.name(),
            "state": a.after.name(),
            "reason": reason,
        });
        let text = v.to_string();
        self.buf = text.clone().into_bytes();
        let ns = parasils_sim::mcap::log_time(a.t_s).unwrap_or(0);
        let ch = Arc::clone(&self.channels.ack);
        self.log(&ch, ns);
        match a.reply {
            Reply::Status(tag) => {
                if let Ok(map) = clients.lock()
                    && let Some(client) = map.get(&tag)
                {
                    let status = if a.accepted {
                        Status::info(text)
                    } else {
                        Status::error(text)
                    };
                    let id = a
                        .request
                        .id
                        .map_or_else(|| "command".to_owned(), |i| format!("command-{i}"));
                    client.send_status(status.with_id(id));
                }
            }
            Reply::Service(key) => {
                if let Some(responder) = calls.lock().ok().and_then(|mut c| c.remove(&key)) {
                    responder.respond_ok(text);
                }
            }
        }
        self.report.acks += 1;
    }
}

/// Publishes every frame and acknowledgement until the control loop has
/// ended (its queues closed); what it did.
///
/// It polls its queues (every [`POLL_PERIOD_S`] when they are empty)
/// rather than waiting on them, so that the control loop's `try_send`
/// never has a sleeping receiver to wake: handing a frame on costs the
/// loop no system call.
///
/// # Errors
/// [`McapError`] when a builder refuses a record's value (a non-finite one).
pub fn run_publisher(
    channels: Channels,
    geometry: SceneGeometry,
    settings: PublishSettings,
    frames: &Receiver<Frame>,
    acks: &Receiver<Ack>,
    clients: &Clients,
    calls: &Calls,
) -> Result<PublishReport, McapError> {
    let mut p = Publisher {
        channels,
        last: None,
        geometry,
        settings,
        next_scene_s: 0.0,
        next_diagnostics_s: 0.0,
        buf: Vec::with_capacity(8192),
        ryu: ryu::Buffer::new(),
        report: PublishReport::default(),
    };
    let poll = core::time::Duration::from_secs_f64(POLL_PERIOD_S);
    loop {
        let next = frames.try_recv();
        while let Ok(a) = acks.try_recv() {
            p.ack(&a, clients, calls);
        }
        match next {
            Ok(f) => p.frame(&f)?,
            Err(TryRecvError::Empty) => std::thread::sleep(poll),
            Err(TryRecvError::Disconnected) => break,
        }
    }
    while let Ok(a) = acks.try_recv() {
        p.ack(&a, clients, calls);
    }
    p.finish()?;
    Ok(p.report)
}
