//! The MCAP writer: a simulation as a Foxglove recording.
//!
//! [`McapSink`] streams samples into an [MCAP](https://mcap.dev) file with
//! zstd-compressed chunks and a summary (statistics, chunk indexes, message
//! indexes), so that readers can seek. Every message is JSON (message
//! encoding `json`) with a JSON Schema per channel (schema encoding
//! `jsonschema`). Log time and publish time are the simulation time, ns.
//!
//! # Channels
//! One message per sample on each of the six data channels, every field a
//! number named with its unit (the CSV column names of
//! [`COLUMNS`]), `t_s` first in each, so that
//! Foxglove's plot panel draws the paper's figures 5-7 directly:
//!
//! | topic | fields (besides `t_s`) |
//! |---|---|
//! | `/platform` | `x_mm y_mm z_mm psi_deg theta_deg phi_deg psi_rate_deg_s theta_rate_deg_s psi_acc_deg_s2 theta_acc_deg_s2` |
//! | `/module1` | `q1_mm..q6_mm`, `q1_rate_mm_s..q6_rate_mm_s`, `q1_acc_mm_s2..q6_acc_mm_s2` |
//! | `/left` | `left_qs1_deg left_qs2_deg left_qs3_mm`, their `_rate_` and `_acc_` |
//! | `/right` | the same for `right_` |
//! | `/tips` | `left_tip_x_mm left_tip_y_mm left_tip_z_mm right_tip_x_mm right_tip_y_mm right_tip_z_mm left_tip_err_mm right_tip_err_mm` |
//! | `/margins` | `module1_serial_margin module1_parallel_margin left_cos_qs2 right_cos_qs2` |
//!
//! Every CSV column is on exactly one of them; the tips are the positions
//! recomputed from the joints by forward kinematics (fixed frame) and their
//! distances to the targets.
//!
//! For the 3D view, in metres as Foxglove expects:
//! - `/tf`, `foxglove.FrameTransforms`: `world -> platform` (`P` and `R`),
//!   `platform -> left_rcm`, `platform -> right_rcm` (the ports), and
//!   `left_rcm -> left_tool`, `right_rcm -> right_tool` (the last frame of
//!   each spherical module: the tool points along its `-z`, the tip at
//!   `z = -qs3`);
//! - `/scene`, `foxglove.SceneUpdate`, in the `world` frame: module 1's six
//!   guides (over their strokes), sliders and legs (slider `B_j` to node
//!   `A_i`), the platform triangle and its spokes to `P`, the endoscope along
//!   `-z'` from `P` (a nominal length: its insertion is not simulated), both
//!   instrument shafts (RCM to tip) and the target tips.
//!
//! `/tf` and `/scene` are published at a lower rate than the data channels:
//! at the first sample, then at the first sample of each
//! [`McapOptions::scene_period_s`] of simulation time (20 ms by default, the
//! 50 Hz of a screen), and at the last sample. At 1 kHz, drawing every sample
//! would double the file for frames no display shows; the exact numbers are
//! on the data channels. A period of 0 publishes every sample.
//!
//! # Metadata
//! A metadata record `parasils.scenario`, written first: the [`Scenario`] as
//! JSON (library units: mm, rad, s), the [`SceneGeometry`] as JSON (mm), the
//! resolved tips, whether module 1's geometry is assumed, the channels'
//! units. A record `parasils.run`, written by [`McapSink::finish`]: the number
//! of samples and the first and last times.
//!
//! # Memory and speed
//! The writer holds one chunk (about [`McapOptions::chunk_size`] bytes) and
//! the small indexes of the file's chunks: memory stays flat however long the
//! run. JSON is written directly as text (shortest round-trip floats, `ryu`)
//! into buffers reused from sample to sample.
//!
//! Three threads share the work. The caller's formats the JSON (most of it
//! number formatting) into batches of messages of about 64 KiB; a writer
//! thread, which owns the `mcap` writer, turns them into records (message
//! headers, indexes, checksums) and feeds the compressor; zstd's
//! multithreaded encoder (the `mcap` crate's default: one worker per physical
//! core) compresses a job once it has about 2 MiB of input, so with 4 MiB
//! chunks (the default) a chunk's first half is compressed while its second
//! half is written (with 1 MiB chunks each chunk was compressed while the
//! writer waited at its end). The batches travel through a bounded channel
//! (at most 32 in flight, 2 MiB) and are reused, so memory stays flat. The file is the same,
//! byte for byte, as one written on a single thread; an I/O error of the
//! writer thread is reported by the next [`Sink::push`] or by
//! [`McapSink::finish`]. The paper's run (8.6 MB of JSON) takes 3 chunks;
//! `BENCHMARKS.md` has the measurements.

use std::collections::BTreeMap;
use std::io::{Seek, Write};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use mcap::records::{MessageHeader, Metadata};
use mcap::{WriteOptions, Writer};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use parasils_kin::controller::RobotGeometry;
use parasils_kin::instrument::{InstrumentGeometry, Side};
use parasils_kin::{Joints, Pose};
use serde::Serialize;

use crate::sample::{COLUMNS, NUM_COLUMNS, Sample, Sink};
use crate::scenario::Scenario;

/// The six data channels' topics, one message per sample on each.
pub const SAMPLE_TOPICS: [&str; 6] = [
    "/platform",
    "/module1",
    "/left",
    "/right",
    "/tips",
    "/margins",
];
/// The topic of the `foxglove.FrameTransforms` messages.
pub const TF_TOPIC: &str = "/tf";
/// The topic of the `foxglove.SceneUpdate` messages.
pub const SCENE_TOPIC: &str = "/scene";
/// The name of the metadata record with the scenario and the geometry.
pub const SCENARIO_METADATA: &str = "parasils.scenario";
/// The name of the metadata record written at the end: sample count, times.
pub const RUN_METADATA: &str = "parasils.run";

/// Foxglove's official schema of `foxglove.FrameTransforms` (MIT, see
/// `schemas/LICENSE`).
pub const FRAME_TRANSFORMS_SCHEMA: &str = include_str!("../schemas/FrameTransforms.json");
/// Foxglove's official schema of `foxglove.SceneUpdate` (MIT, see
/// `schemas/LICENSE`).
pub const SCENE_UPDATE_SCHEMA: &str = include_str!("../schemas/SceneUpdate.json");

/// The recomputed tips' field names, after the CSV columns.
const TIP_FIELDS: [&str; 6] = [
    "left_tip_x_mm",
    "left_tip_y_mm",
    "left_tip_z_mm",
    "right_tip_x_mm",
    "right_tip_y_mm",
    "right_tip_z_mm",
];
/// The CSV columns, then the recomputed tips.
const NUM_FIELDS: usize = NUM_COLUMNS + TIP_FIELDS.len();

/// The schema names of the data channels, in the order of [`SAMPLE_TOPICS`].
const SCHEMA_NAMES: [&str; 6] = [
    "parasils.Platform",
    "parasils.Module1",
    "parasils.LeftModule",
    "parasils.RightModule",
    "parasils.Tips",
    "parasils.Margins",
];
const SCHEMA_TITLES: [&str; 6] = [
    "Platform pose (paper's figure 5: psi, theta), fixed frame",
    "Module 1 actuators q1..q6 (paper's figure 6)",
    "Left instrument module joints (paper's figure 7)",
    "Right instrument module joints",
    "Instrument tips recomputed by forward kinematics (fixed frame) and their distance to the targets",
    "Singularity margins: module 1 serial and parallel, cos qs2 of each instrument module",
];

/// The display length of the endoscope along `-z'` below `P`, mm: its
/// insertion is not simulated.
const ENDOSCOPE_BELOW_MM: f64 = 120.0;
/// The display length of the endoscope along `+z'` above `P`, mm.
const ENDOSCOPE_ABOVE_MM: f64 = 80.0;

/// What can go wrong while writing an MCAP file.
///
/// When this happens, the file is incomplete (no summary): discard it. The
/// CLI writes to a temporary file and renames it only on success.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum McapError {
    /// The MCAP library failed, most often an I/O error of the writer.
    #[error("MCAP: {0}")]
    Mcap(#[from] mcap::McapError),
    /// The scenario or the geometry could not be turned into JSON.
    #[error("scenario to JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A value is NaN or infinite: JSON has no such number, and the schema
    /// asks for one.
    #[error("{field} = {value} on {topic} at t = {t} s: JSON numbers must be finite")]
    NonFinite {
        /// The channel.
        topic: &'static str,
        /// The field (or the part of a 3D message).
        field: &'static str,
        /// The sample's time, s.
        t: f64,
        /// The value.
        value: f64,
    },
    /// A sample's time is negative, non-finite or too large for a `u64` of
    /// nanoseconds.
    #[error("sample time t = {t} s cannot be a log time (finite, >= 0, < 1.8e10 s)")]
    InvalidTime {
        /// The sample's time, s.
        t: f64,
    },
    /// A sample's time is not after the previous sample's, to the
    /// nanosecond: log times must increase strictly on each channel.
    #[error("sample time t = {t} s is not after the previous sample's, {previous} s (to the ns)")]
    TimeNotIncreasing {
        /// The sample's time, s.
        t: f64,
        /// The previous sample's time, s.
        previous: f64,
    },
    /// An option is out of range.
    #[error("MCAP option {what} = {value} is invalid")]
    InvalidOption {
        /// The option.
        what: &'static str,
        /// Its value.
        value: f64,
    },
}

/// How the MCAP file is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McapOptions {
    /// The simulation-time period of `/tf` and `/scene`, s (0: every sample).
    /// The first and the last samples are always published.
    pub scene_period_s: f64,
    /// The zstd level of the chunks (1 fast .. 19 small; 0 for zstd's
    /// default, 3).
    pub compression_level: u32,
    /// The target size of a chunk before compression, bytes.
    pub chunk_size: u64,
}

impl Default for McapOptions {
    /// 20 ms scene period, zstd level 1, 4 MiB chunks.
    fn default() -> Self {
        Self {
            scene_period_s: 0.02,
            compression_level: 1,
            chunk_size: 4 << 20,
        }
    }
}

/// What the 3D scene is drawn from: module 1 and the instrument ports, in
/// plain arrays, mm and rad.
///
/// Built from a [`RobotGeometry`] by [`SceneGeometry::from_robot`], the one
/// place that reads module 1's types.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SceneGeometry {
    /// Guide points `G_j`, mm, fixed frame.
    pub guide_points_mm: [[f64; 3]; 6],
    /// Guide unit directions `u_j`, fixed frame.
    pub guide_directions: [[f64; 3]; 6],
    /// Each actuator's stroke `[min, max]`, mm.
    pub strokes_mm: [[f64; 2]; 6],
    /// Link lengths `l_j`, mm.
    pub link_lengths_mm: [f64; 6],
    /// Platform nodes `a_i`, mm, platform frame.
    pub nodes_mm: [[f64; 3]; 3],
    /// Whether module 1's geometry is assumed (not the real robot's).
    pub module1_assumed: bool,
    /// The instrument ports (RCMs), left then right, mm, platform frame.
    pub rcms_mm: [[f64; 3]; 2],
    /// The spherical modules' `alpha`, left then right, rad.
    pub alphas_rad: [f64; 2],
    /// The spherical modules' `beta`, left then right, rad.
    pub betas_rad: [f64; 2],
}

impl SceneGeometry {
    /// The scene's geometry from the robot's.
    pub fn from_robot(robot: &RobotGeometry<f64>) -> Self {
        let m1 = &robot.module1;
        let v = |v: &Vector3<f64>| [v.x, v.y, v.z];
        let modules: [&InstrumentGeometry<f64>; 2] = [&robot.left, &robot.right];
        Self {
            guide_points_mm: m1.guides.map(|g| v(&g.point)),
            guide_directions: m1.guides.map(|g| v(&g.direction)),
            strokes_mm: m1.guides.map(|g| [g.stroke.min, g.stroke.max]),
            link_lengths_mm: m1.guides.map(|g| g.link_length),
            nodes_mm: m1.nodes.map(|n| v(&n)),
            module1_assumed: m1.assumed,
            rcms_mm: modules.map(|m| v(&m.rcm)),
            alphas_rad: modules.map(|m| m.alpha),
            betas_rad: modules.map(|m| m.beta),
        }
    }

    /// The last frame of a spherical module relative to its RCM frame:
    /// `R_Y(+-alpha) R_X(qs1) R_Y(+-qs2) R_X(beta)` (signs `-` for the right
    /// module, the mirror of the left). The tool points along its `-z`.
    pub fn tool_rotation(&self, side: Side, q: &Joints<f64>) -> Matrix3<f64> {
        let (k, s) = match side {
            Side::Left => (0, 1.0),
            Side::Right => (1, -1.0),
        };
        let ry = |a: f64| Rotation3::from_axis_angle(&Vector3::y_axis(), a);
        let rx = |a: f64| Rotation3::from_axis_angle(&Vector3::x_axis(), a);
        (ry(s * self.alphas_rad[k]) * rx(q.qs1) * ry(s * q.qs2) * rx(self.betas_rad[k]))
            .into_inner()
    }
}

/// One data channel: its id and, per field, the index into the extended row
/// and the JSON text before the value (`{"t_s":` or `,"x_mm":`).
#[derive(Debug)]
struct DataChannel {
    id: u16,
    topic: &'static str,
    fields: Vec<(usize, &'static str, Vec<u8>)>,
    sequence: u32,
}

/// Streams samples into an MCAP file; see the module docs.
pub struct McapSink<W: Write + Seek> {
    /// The writer thread, which owns the `mcap` writer.
    thread: WriterThread<W>,
    /// The messages formatted since the last batch was sent.
    batch: Batch,
    data: Vec<DataChannel>,
    tf: (u16, u32),
    scene: (u16, u32),
    geometry: SceneGeometry,
    targets: [Vector3<f64>; 2],
    options: McapOptions,
    scene_period_ns: u64,
    /// The log time at or after which `/tf` and `/scene` are next published.
    next_scene_ns: u64,
    /// The last sample, its log time, and whether `/tf` and `/scene` have it.
    last: Option<(Sample, u64, bool)>,
    first_t: Option<f64>,
    count: u64,
    buf: Vec<u8>,
    ryu: ryu::Buffer,
}

/// Messages formatted and not yet written: each header with the end of its
/// data in `bytes`, the data back to back.
#[derive(Debug, Default)]
struct Batch {
    headers: Vec<(MessageHeader, usize)>,
    bytes: Vec<u8>,
}

/// The size at which a batch goes to the writer thread, bytes.
const BATCH_BYTES: usize = 64 << 10;

/// The most batches queued for the writer thread (2 MiB of JSON): enough for
/// the formatting to go on while the writer waits at a chunk's end for zstd
/// to finish compressing it (4 in flight: 53 ms for the paper's run, 32:
/// 44 ms; see `BENCHMARKS.md`).
const BATCHES_IN_FLIGHT: usize = 32;

/// What the writer thread returns: the writer, and the first error.
type Written<W> = (Writer<W>, Result<(), McapError>);

/// The writer thread and the channels to it (batches to write) and from it
/// (written batches, to reuse).
struct WriterThread<W: Write + Seek> {
    to: Option<SyncSender<Batch>>,
    back: Receiver<Batch>,
    handle: Option<JoinHandle<Written<W>>>,
}

impl<W: Write + Seek + Send + 'static> WriterThread<W> {
    fn spawn(writer: Writer<W>) -> Result<Self, McapError> {
        let (to, from_main) = sync_channel::<Batch>(BATCHES_IN_FLIGHT);
        let (to_main, back) = sync_channel::<Batch>(BATCHES_IN_FLIGHT + 2);
        let handle = std::thread::Builder::new()
            .name("parasils-mcap".to_owned())
            .spawn(move || {
                let mut writer = writer;
                for mut batch in from_main {
                    let mut start = 0;
                    for (header, end) in &batch.headers {
                        let data = batch.bytes.get(start..*end).unwrap_or_default();
                        if let Err(e) = writer.write_to_known_channel(header, data) {
                            return (writer, Err(McapError::from(e)));
                        }
                        start = *end;
                    }
                    batch.headers.clear();
                    batch.bytes.clear();
                    // Reused if the sender wants it; dropped otherwise.
                    let _ = to_main.try_send(batch);
                }
                (writer, Ok(()))
            })
            .map_err(|e| McapError::Mcap(e.into()))?;
        Ok(Self {
            to: Some(to),
            back,
            handle: Some(handle),
        })
    }

    /// Sends `batch` to be written; on failure, the writer thread's error.
    fn send(&mut self, batch: Batch) -> Result<(), McapError> {
        let sent = match &self.to {
            Some(to) => to.send(batch).is_ok(),
            None => false,
        };
        if sent {
            Ok(())
        } else {
            // The thread stopped on an error: report it (once; then a
            // generic one).
            match self.join() {
                Ok((_, Err(e))) => Err(e),
                _ => Err(McapError::Mcap(
                    std::io::Error::other("the MCAP writer stopped on an earlier error").into(),
                )),
            }
        }
    }

    /// An empty batch, reused when one came back.
    fn empty_batch(&self) -> Batch {
        self.back.try_recv().unwrap_or_else(|_| Batch {
            headers: Vec::with_capacity(256),
            bytes: Vec::with_capacity(BATCH_BYTES + (16 << 10)),
        })
    }

    /// Ends the thread once it has written everything sent; its writer and
    /// first error.
    fn join(&mut self) -> Result<Written<W>, McapError> {
        self.to = None;
        let handle = self.handle.take().ok_or_else(|| {
            McapError::Mcap(std::io::Error::other("the MCAP writer thread is gone").into())
        })?;
        handle.join().map_err(|_| {
            McapError::Mcap(std::io::Error::other("the MCAP writer thread panicked").into())
        })
    }
}

impl<W: Write + Seek> core::fmt::Debug for McapSink<W> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("McapSink")
            .field("options", &self.options)
            .field("geometry", &self.geometry)
            .field("count", &self.count)
            .finish_non_exhaustive()
    }
}

/// The name of field `i` of the extended row.
fn field_name(i: usize) -> &'static str {
    if i < NUM_COLUMNS {
        COLUMNS[i]
    } else {
        TIP_FIELDS[i - NUM_COLUMNS]
    }
}

/// Which data channel (index into [`SAMPLE_TOPICS`]) a field goes to;
/// `None` for `t_s`, which goes to all.
fn channel_of(name: &str) -> Option<usize> {
    Some(if name == "t_s" {
        return None;
    } else if name.contains("_tip_") {
        4
    } else if name.contains("margin") || name.ends_with("_cos_qs2") {
        5
    } else if name.starts_with("left_") {
        2
    } else if name.starts_with("right_") {
        3
    } else if name.starts_with('q') {
        1
    } else {
        0
    })
}

/// What a field's name says about its unit, for the schema's description.
fn unit_of(name: &str) -> &'static str {
    const UNITS: [(&str, &str); 9] = [
        ("_deg_s2", "deg/s^2"),
        ("_deg_s", "deg/s"),
        ("_deg", "deg"),
        ("_mm_s2", "mm/s^2"),
        ("_mm_s", "mm/s"),
        ("_mm", "mm"),
        ("_s", "s"),
        ("margin", "1 (dimensionless)"),
        ("cos_qs2", "1 (dimensionless)"),
    ];
    UNITS
        .iter()
        .find(|(suffix, _)| name.ends_with(suffix))
        .map_or("", |(_, unit)| unit)
}

/// The JSON Schema of data channel `k`.
fn data_schema(k: usize, fields: &[(usize, &'static str, Vec<u8>)]) -> serde_json::Value {
    let mut properties = serde_json::Map::new();
    for (_, name, _) in fields {
        properties.insert(
            (*name).to_owned(),
            serde_json::json!({
                "type": "number",
                "description": format!("unit: {}", unit_of(name)),
            }),
        );
    }
    let required: Vec<&str> = fields.iter().map(|(_, n, _)| *n).collect();
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": SCHEMA_NAMES[k],
        "description": SCHEMA_TITLES[k],
        "type": "object",
        "properties": properties,
        "required": required,
        "additionalProperties": false,
    })
}

/// The log time of `t` seconds, ns.
fn log_time(t: f64) -> Result<u64, McapError> {
    let ns = (t * 1e9).round();
    // 1.8e19 < u64::MAX = 1.8446e19.
    if ns.is_finite() && (0.0..1.8e19).contains(&ns) {
        // In range, checked just above.
        Ok(ns as u64)
    } else {
        Err(McapError::InvalidTime { t })
    }
}

/// Appends `v` to `out` as a JSON number (shortest round-trip form).
fn push_num(out: &mut Vec<u8>, ryu: &mut ryu::Buffer, v: f64) -> Result<(), f64> {
    if v.is_finite() {
        out.extend_from_slice(ryu.format_finite(v).as_bytes());
        Ok(())
    } else {
        Err(v)
    }
}

/// A small JSON text builder for the 3D messages, over a reused buffer.
struct Json<'a> {
    out: &'a mut Vec<u8>,
    ryu: &'a mut ryu::Buffer,
    /// The first non-finite value met, if any.
    bad: Option<f64>,
}

impl Json<'_> {
    fn raw(&mut self, s: &str) -> &mut Self {
        self.out.extend_from_slice(s.as_bytes());
        self
    }
    fn num(&mut self, v: f64) -> &mut Self {
        if let Err(v) = push_num(self.out, self.ryu, v) {
            self.bad.get_or_insert(v);
            self.out.push(b'0');
        }
        self
    }
    fn int(&mut self, v: u64) -> &mut Self {
        self.out
            .extend_from_slice(itoa::Buffer::new().format(v).as_bytes());
        self
    }
    /// `{"x":..,"y":..,"z":..}`.
    fn vec3(&mut self, v: &Vector3<f64>) -> &mut Self {
        self.raw("{\"x\":")
            .num(v.x)
            .raw(",\"y\":")
            .num(v.y)
            .raw(",\"z\":")
            .num(v.z)
            .raw("}")
    }
    /// `{"x":..,"y":..,"z":..,"w":..}`.
    fn quat(&mut self, q: &UnitQuaternion<f64>) -> &mut Self {
        self.raw("{\"x\":")
            .num(q.i)
            .raw(",\"y\":")
            .num(q.j)
            .raw(",\"z\":")
            .num(q.k)
            .raw(",\"w\":")
            .num(q.w)
            .raw("}")
    }
    /// `{"sec":..,"nsec":..}`.
    fn time(&mut self, ns: u64) -> &mut Self {
        self.raw("{\"sec\":")
            .int(ns / 1_000_000_000)
            .raw(",\"nsec\":")
            .int(ns % 1_000_000_000)
            .raw("}")
    }
    fn color(&mut self, c: [f64; 4]) -> &mut Self {
        self.raw("{\"r\":")
            .num(c[0])
            .raw(",\"g\":")
            .num(c[1])
            .raw(",\"b\":")
            .num(c[2])
            .raw(",\"a\":")
            .num(c[3])
            .raw("}")
    }
    /// The identity pose.
    fn identity_pose(&mut self) -> &mut Self {
        self.raw(
            "{\"position\":{\"x\":0,\"y\":0,\"z\":0},\"orientation\":{\"x\":0,\"y\":0,\"z\":0,\"w\":1}}",
        )
    }
}

/// Millimetres to metres.
const M: f64 = 1e-3;

/// A line primitive, in metres, world frame.
struct Line<'p> {
    /// `LINE_STRIP`, `LINE_LOOP` or `LINE_LIST`.
    kind: u8,
    /// m.
    thickness: f64,
    color: [f64; 4],
    points: &'p [Vector3<f64>],
}

/// Spheres of one size and colour, in metres, world frame.
struct Spheres<'p> {
    /// m.
    diameter: f64,
    color: [f64; 4],
    centres: &'p [Vector3<f64>],
}

fn line(kind: u8, thickness: f64, color: [f64; 4], points: &[Vector3<f64>]) -> Line<'_> {
    Line {
        kind,
        thickness,
        color,
        points,
    }
}

fn spheres(diameter: f64, color: [f64; 4], centres: &[Vector3<f64>]) -> Spheres<'_> {
    Spheres {
        diameter,
        color,
        centres,
    }
}

/// One scene entity's primitives, in metres, world frame.
#[derive(Default)]
struct Entity<'p> {
    id: &'static str,
    lines: Vec<Line<'p>>,
    spheres: Vec<Spheres<'p>>,
    /// One filled triangle list: `(color, points)`.
    triangles: Option<([f64; 4], &'p [Vector3<f64>])>,
    /// Metadata key/values.
    metadata: &'static [(&'static str, &'static str)],
}

const LINE_STRIP: u8 = 0;
const LINE_LOOP: u8 = 1;
const LINE_LIST: u8 = 2;

const GREY: [f64; 4] = [0.55, 0.55, 0.6, 1.0];
const STEEL: [f64; 4] = [0.2, 0.45, 0.8, 1.0];
const ORANGE: [f64; 4] = [0.95, 0.55, 0.1, 1.0];
const PLATFORM: [f64; 4] = [0.3, 0.7, 0.4, 0.6];
const GREEN: [f64; 4] = [0.2, 0.6, 0.3, 1.0];
const LEFT: [f64; 4] = [0.85, 0.2, 0.2, 1.0];
const RIGHT: [f64; 4] = [0.6, 0.2, 0.85, 1.0];
const ENDOSCOPE: [f64; 4] = [0.1, 0.1, 0.1, 1.0];
const TARGET: [f64; 4] = [1.0, 0.85, 0.0, 0.8];

impl Json<'_> {
    fn entity(&mut self, ns: u64, e: &Entity<'_>) -> &mut Self {
        self.raw("{\"timestamp\":")
            .time(ns)
            .raw(",\"frame_id\":\"world\",\"id\":\"")
            .raw(e.id)
            .raw("\",\"lifetime\":{\"sec\":0,\"nsec\":0},\"frame_locked\":false,\"metadata\":[");
        for (k, (key, value)) in e.metadata.iter().enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.raw("{\"key\":\"")
                .raw(key)
                .raw("\",\"value\":\"")
                .raw(value)
                .raw("\"}");
        }
        self.raw("],\"arrows\":[],\"cubes\":[],\"spheres\":[");
        let mut first = true;
        for sp in &e.spheres {
            for p in sp.centres {
                if !first {
                    self.raw(",");
                }
                first = false;
                self.raw("{\"pose\":{\"position\":")
                    .vec3(p)
                    .raw(",\"orientation\":{\"x\":0,\"y\":0,\"z\":0,\"w\":1}},\"size\":")
                    .vec3(&Vector3::repeat(sp.diameter))
                    .raw(",\"color\":")
                    .color(sp.color)
                    .raw("}");
            }
        }
        self.raw("],\"cylinders\":[],\"lines\":[");
        for (k, line) in e.lines.iter().enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.raw("{\"type\":")
                .int(u64::from(line.kind))
                .raw(",\"pose\":")
                .identity_pose()
                .raw(",\"thickness\":")
                .num(line.thickness)
                .raw(",\"scale_invariant\":false,\"points\":[");
            for (i, p) in line.points.iter().enumerate() {
                if i > 0 {
                    self.raw(",");
                }
                self.vec3(p);
            }
            self.raw("],\"color\":")
                .color(line.color)
                .raw(",\"colors\":[],\"indices\":[]}");
        }
        self.raw("],\"triangles\":[");
        if let Some((c, points)) = e.triangles {
            self.raw("{\"pose\":").identity_pose().raw(",\"points\":[");
            for (i, p) in points.iter().enumerate() {
                if i > 0 {
                    self.raw(",");
                }
                self.vec3(p);
            }
            self.raw("],\"color\":")
                .color(c)
                .raw(",\"colors\":[],\"indices\":[]}");
        }
        self.raw("],\"texts\":[],\"models\":[]}")
    }
}

impl<W: Write + Seek + Send + 'static> McapSink<W> {
    /// Starts the file with the default [`McapOptions`]: header, schemas,
    /// channels and the `parasils.scenario` metadata record.
    ///
    /// # Errors
    /// [`McapError::Mcap`] when writing fails, [`McapError::Json`] when the
    /// scenario cannot be serialised.
    pub fn new(writer: W, scenario: &Scenario) -> Result<Self, McapError> {
        Self::with_options(writer, scenario, McapOptions::default())
    }

    /// Starts the file with the given options.
    ///
    /// # Errors
    /// As [`McapSink::new`], and [`McapError::InvalidOption`] for a negative
    /// or non-finite scene period or a zero chunk size.
    pub fn with_options(
        writer: W,
        scenario: &Scenario,
        options: McapOptions,
    ) -> Result<Self, McapError> {
        let period = options.scene_period_s;
        let scene_period_ns = match log_time(period) {
            Ok(ns) => ns,
            Err(_) => {
                return Err(McapError::InvalidOption {
                    what: "scene_period_s",
                    value: period,
                });
            }
        };
        if options.chunk_size == 0 {
            return Err(McapError::InvalidOption {
                what: "chunk_size",
                value: 0.0,
            });
        }
        let mut writer = WriteOptions::new()
            .profile("")
            .library(concat!("parasils-cli ", env!("CARGO_PKG_VERSION")))
            .compression(Some(mcap::Compression::Zstd))
            .compression_level(options.compression_level)
            .chunk_size(Some(options.chunk_size))
            .create(writer)?;

        let geometry = SceneGeometry::from_robot(&scenario.robot);
        let tips = scenario.tips();
        let mut meta = BTreeMap::new();
        meta.insert("scenario".to_owned(), serde_json::to_string(scenario)?);
        meta.insert("scenario_units".to_owned(), "mm, rad, s".to_owned());
        meta.insert("geometry".to_owned(), serde_json::to_string(&geometry)?);
        meta.insert(
            "tips_mm".to_owned(),
            serde_json::to_string(&[
                [tips.left.x, tips.left.y, tips.left.z],
                [tips.right.x, tips.right.y, tips.right.z],
            ])?,
        );
        meta.insert(
            "module1_geometry".to_owned(),
            if geometry.module1_assumed {
                "assumed: not the real robot's dimensions (unpublished)"
            } else {
                "given by the user"
            }
            .to_owned(),
        );
        meta.insert(
            "units".to_owned(),
            "data channels: each field's name ends with its unit (deg, mm, s; margins \
             dimensionless); /tf and /scene: metres, quaternions; log times: simulation \
             time, ns"
                .to_owned(),
        );
        meta.insert(
            "scene_period_s".to_owned(),
            ryu::Buffer::new().format(period).to_owned(),
        );
        meta.insert(
            "generator".to_owned(),
            concat!("parasils-cli ", env!("CARGO_PKG_VERSION")).to_owned(),
        );
        writer.write_metadata(&Metadata {
            name: SCENARIO_METADATA.to_owned(),
            metadata: meta,
        })?;

        let mut fields: Vec<Vec<(usize, &'static str, Vec<u8>)>> =
            vec![vec![(0, "t_s", b"{\"t_s\":".to_vec())]; SAMPLE_TOPICS.len()];
        for i in 1..NUM_FIELDS {
            let name = field_name(i);
            if let Some(k) = channel_of(name) {
                fields[k].push((i, name, format!(",\"{name}\":").into_bytes()));
            }
        }
        let no_meta = BTreeMap::new();
        let mut data = Vec::with_capacity(SAMPLE_TOPICS.len());
        for (k, fields) in fields.into_iter().enumerate() {
            let schema = serde_json::to_vec_pretty(&data_schema(k, &fields))?;
            let schema_id = writer.add_schema(SCHEMA_NAMES[k], "jsonschema", &schema)?;
            let id = writer.add_channel(schema_id, SAMPLE_TOPICS[k], "json", &no_meta)?;
            data.push(DataChannel {
                id,
                topic: SAMPLE_TOPICS[k],
                fields,
                sequence: 0,
            });
        }
        let tf_schema = writer.add_schema(
            "foxglove.FrameTransforms",
            "jsonschema",
            FRAME_TRANSFORMS_SCHEMA.as_bytes(),
        )?;
        let tf = writer.add_channel(tf_schema, TF_TOPIC, "json", &no_meta)?;
        let scene_schema = writer.add_schema(
            "foxglove.SceneUpdate",
            "jsonschema",
            SCENE_UPDATE_SCHEMA.as_bytes(),
        )?;
        let scene = writer.add_channel(scene_schema, SCENE_TOPIC, "json", &no_meta)?;

        let thread = WriterThread::spawn(writer)?;
        Ok(Self {
            batch: thread.empty_batch(),
            thread,
            data,
            tf: (tf, 0),
            scene: (scene, 0),
            geometry,
            targets: [tips.left, tips.right],
            options,
            scene_period_ns,
            next_scene_ns: 0,
            last: None,
            first_t: None,
            count: 0,
            buf: Vec::with_capacity(8192),
            ryu: ryu::Buffer::new(),
        })
    }

    /// The options in use.
    pub fn options(&self) -> &McapOptions {
        &self.options
    }

    /// The geometry the scene is drawn from.
    pub fn geometry(&self) -> &SceneGeometry {
        &self.geometry
    }

    /// The number of samples written so far.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Publishes any sample still owed to `/tf` and `/scene` (the last one),
    /// writes the `parasils.run` metadata record and the summary (statistics,
    /// schemas, channels, chunk and message indexes), and returns the writer.
    ///
    /// # Errors
    /// [`McapError::Mcap`] when writing fails.
    pub fn finish(mut self) -> Result<W, McapError> {
        if let Some((sample, ns, false)) = self.last {
            self.write_visuals(&sample, ns)?;
        }
        let batch = core::mem::take(&mut self.batch);
        self.thread.send(batch)?;
        let (mut writer, written) = self.thread.join()?;
        written?;
        let mut meta = BTreeMap::new();
        meta.insert("samples".to_owned(), self.count.to_string());
        let mut ryu = ryu::Buffer::new();
        if let (Some(first), Some((last, _, _))) = (self.first_t, &self.last) {
            meta.insert("t_first_s".to_owned(), ryu.format(first).to_owned());
            meta.insert("t_last_s".to_owned(), ryu.format(last.t).to_owned());
        }
        writer.write_metadata(&Metadata {
            name: RUN_METADATA.to_owned(),
            metadata: meta,
        })?;
        writer.finish()?;
        Ok(writer.into_inner())
    }

    /// Queues the message in `buf` for the writer thread.
    fn write(&mut self, id: u16, sequence: u32, ns: u64) -> Result<(), McapError> {
        let header = MessageHeader {
            channel_id: id,
            sequence,
            log_time: ns,
            publish_time: ns,
        };
        self.batch.bytes.extend_from_slice(&self.buf);
        self.batch.headers.push((header, self.batch.bytes.len()));
        Ok(())
    }

    /// Writes `/tf` and `/scene` for `s`.
    fn write_visuals(&mut self, s: &Sample, ns: u64) -> Result<(), McapError> {
        let pose = Pose::from_array(s.pose);
        let r = pose.rotation();
        let p = pose.position();
        let g = self.geometry;
        let q_of = |m: &crate::sample::ModuleSample| Joints::new(m.q[0], m.q[1], m.q[2]);
        let tools = [
            g.tool_rotation(Side::Left, &q_of(&s.left)),
            g.tool_rotation(Side::Right, &q_of(&s.right)),
        ];
        let rcm = |k: usize| Vector3::from(g.rcms_mm[k]);

        // /tf
        self.buf.clear();
        let quat = |m: &Matrix3<f64>| {
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*m))
        };
        let identity = UnitQuaternion::identity();
        let zero = Vector3::zeros();
        let frames: [(&str, &str, Vector3<f64>, UnitQuaternion<f64>); 5] = [
            ("world", "platform", p * M, quat(&r)),
            ("platform", "left_rcm", rcm(0) * M, identity),
            ("platform", "right_rcm", rcm(1) * M, identity),
            ("left_rcm", "left_tool", zero, quat(&tools[0])),
            ("right_rcm", "right_tool", zero, quat(&tools[1])),
        ];
        let mut j = Json {
            out: &mut self.buf,
            ryu: &mut self.ryu,
            bad: None,
        };
        j.raw("{\"transforms\":[");
        for (k, (parent, child, t, q)) in frames.iter().enumerate() {
            if k > 0 {
                j.raw(",");
            }
            j.raw("{\"timestamp\":")
                .time(ns)
                .raw(",\"parent_frame_id\":\"")
                .raw(parent)
                .raw("\",\"child_frame_id\":\"")
                .raw(child)
                .raw("\",\"translation\":")
                .vec3(t)
                .raw(",\"rotation\":")
                .quat(q)
                .raw("}");
        }
        j.raw("]}");
        if let Some(value) = j.bad {
            return Err(McapError::NonFinite {
                topic: TF_TOPIC,
                field: "transforms",
                t: s.t,
                value,
            });
        }
        let (id, seq) = self.tf;
        self.write(id, seq, ns)?;
        self.tf.1 = seq.wrapping_add(1);

        // /scene, all in the world frame, metres.
        let world = |v: Vector3<f64>| v * M;
        let mut guides = [Vector3::zeros(); 12];
        let mut legs = [Vector3::zeros(); 12];
        let mut sliders = [Vector3::zeros(); 6];
        let nodes: [Vector3<f64>; 3] = g.nodes_mm.map(|a| p + r * Vector3::from(a));
        for j in 0..6 {
            let gp = Vector3::from(g.guide_points_mm[j]);
            let u = Vector3::from(g.guide_directions[j]);
            let b = gp + s.q[j] * u;
            guides[2 * j] = world(gp + g.strokes_mm[j][0] * u);
            guides[2 * j + 1] = world(gp + g.strokes_mm[j][1] * u);
            sliders[j] = world(b);
            legs[2 * j] = world(b);
            legs[2 * j + 1] = world(nodes[j / 2]);
        }
        let nodes_m = nodes.map(world);
        let centre = [world(p)];
        let spokes = [
            world(p),
            nodes_m[0],
            world(p),
            nodes_m[1],
            world(p),
            nodes_m[2],
        ];
        let z = r.column(2).into_owned();
        let endoscope = [
            world(p + ENDOSCOPE_ABOVE_MM * z),
            world(p - ENDOSCOPE_BELOW_MM * z),
        ];
        let rcms_world = [world(p + r * rcm(0)), world(p + r * rcm(1))];
        let shafts = [
            [rcms_world[0], world(s.left.tip)],
            [rcms_world[1], world(s.right.tip)],
        ];
        let tips = [world(s.left.tip), world(s.right.tip)];
        let targets = self.targets.map(world);
        let module1_note: &'static [(&str, &str)] = if g.module1_assumed {
            &[("geometry", "assumed, not the real robot's")]
        } else {
            &[]
        };
        let entities = [
            Entity {
                id: "module1_guides",
                lines: vec![line(LINE_LIST, 0.004, GREY, &guides[..])],
                metadata: module1_note,
                ..Entity::default()
            },
            Entity {
                id: "module1_legs",
                lines: vec![line(LINE_LIST, 0.006, STEEL, &legs[..])],
                spheres: vec![spheres(0.016, ORANGE, &sliders[..])],
                metadata: module1_note,
                ..Entity::default()
            },
            Entity {
                id: "platform",
                lines: vec![
                    line(LINE_LOOP, 0.005, GREEN, &nodes_m[..]),
                    line(LINE_LIST, 0.003, GREEN, &spokes[..]),
                ],
                spheres: vec![
                    spheres(0.012, GREEN, &nodes_m[..]),
                    spheres(0.01, ENDOSCOPE, &centre[..]),
                ],
                triangles: Some((PLATFORM, &nodes_m[..])),
                ..Entity::default()
            },
            Entity {
                id: "endoscope",
                lines: vec![line(LINE_STRIP, 0.006, ENDOSCOPE, &endoscope[..])],
                metadata: &[("length", "nominal: the insertion is not simulated")],
                ..Entity::default()
            },
            Entity {
                id: "left_instrument",
                lines: vec![line(LINE_STRIP, 0.004, LEFT, &shafts[0][..])],
                spheres: vec![
                    spheres(0.008, LEFT, &rcms_world[..1]),
                    spheres(0.006, LEFT, &tips[..1]),
                ],
                ..Entity::default()
            },
            Entity {
                id: "right_instrument",
                lines: vec![line(LINE_STRIP, 0.004, RIGHT, &shafts[1][..])],
                spheres: vec![
                    spheres(0.008, RIGHT, &rcms_world[1..]),
                    spheres(0.006, RIGHT, &tips[1..]),
                ],
                ..Entity::default()
            },
            Entity {
                id: "tip_targets",
                spheres: vec![spheres(0.012, TARGET, &targets[..])],
                ..Entity::default()
            },
        ];
        self.buf.clear();
        let mut j = Json {
            out: &mut self.buf,
            ryu: &mut self.ryu,
            bad: None,
        };
        j.raw("{\"deletions\":[],\"entities\":[");
        for (k, e) in entities.iter().enumerate() {
            if k > 0 {
                j.raw(",");
            }
            j.entity(ns, e);
        }
        j.raw("]}");
        if let Some(value) = j.bad {
            return Err(McapError::NonFinite {
                topic: SCENE_TOPIC,
                field: "entities",
                t: s.t,
                value,
            });
        }
        let (id, seq) = self.scene;
        self.write(id, seq, ns)?;
        self.scene.1 = seq.wrapping_add(1);
        Ok(())
    }
}

impl<W: Write + Seek + Send + 'static> Sink for McapSink<W> {
    type Error = McapError;

    fn push(&mut self, s: &Sample) -> Result<(), McapError> {
        let ns = log_time(s.t)?;
        if let Some((prev, prev_ns, _)) = &self.last
            && ns <= *prev_ns
        {
            return Err(McapError::TimeNotIncreasing {
                t: s.t,
                previous: prev.t,
            });
        }
        let row = s.row();
        let mut ext = [0.0; NUM_FIELDS];
        ext[..NUM_COLUMNS].copy_from_slice(&row);
        ext[NUM_COLUMNS..NUM_COLUMNS + 3].copy_from_slice(s.left.tip.as_slice());
        ext[NUM_COLUMNS + 3..].copy_from_slice(s.right.tip.as_slice());

        for k in 0..self.data.len() {
            self.buf.clear();
            let ch = &self.data[k];
            for (i, name, key) in &ch.fields {
                self.buf.extend_from_slice(key);
                if let Err(value) = push_num(&mut self.buf, &mut self.ryu, ext[*i]) {
                    return Err(McapError::NonFinite {
                        topic: ch.topic,
                        field: name,
                        t: s.t,
                        value,
                    });
                }
            }
            self.buf.push(b'}');
            let (id, seq) = (ch.id, ch.sequence);
            self.write(id, seq, ns)?;
            self.data[k].sequence = seq.wrapping_add(1);
        }

        let publish = self.last.is_none() || ns >= self.next_scene_ns;
        if publish {
            self.write_visuals(s, ns)?;
            self.next_scene_ns = match self.scene_period_ns {
                0 => 0,
                p => (ns / p).saturating_add(1).saturating_mul(p),
            };
        }
        self.first_t.get_or_insert(s.t);
        self.last = Some((*s, ns, publish));
        self.count += 1;
        if self.batch.bytes.len() >= BATCH_BYTES {
            let next = self.thread.empty_batch();
            let full = core::mem::replace(&mut self.batch, next);
            self.thread.send(full)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::io::Cursor;

    use crate::simulate::Simulation;

    /// The paper's scenario at `rate_hz`.
    fn scenario(rate_hz: f64) -> Scenario {
        Scenario {
            rate_hz,
            ..Scenario::paper()
        }
    }

    /// Runs `scenario` into an in-memory MCAP.
    fn write(scenario: &Scenario, options: McapOptions) -> (Vec<u8>, usize) {
        let sim = Simulation::new(scenario.clone()).expect("valid scenario");
        let mut sink =
            McapSink::with_options(Cursor::new(Vec::new()), sim.scenario(), options).expect("new");
        sim.run(&mut sink).expect("run");
        (
            sink.finish().expect("finish").into_inner(),
            sim.sample_count(),
        )
    }

    #[test]
    fn every_column_is_on_exactly_one_data_channel() {
        let mut counts = [0usize; 6];
        for i in 1..NUM_FIELDS {
            let k = channel_of(field_name(i)).expect("only t_s goes everywhere");
            counts[k] += 1;
        }
        assert_eq!(channel_of("t_s"), None);
        assert_eq!(counts, [10, 18, 9, 9, 8, 4]);
        assert_eq!(counts.iter().sum::<usize>() + 1, NUM_COLUMNS + 6);
        for name in ["left_qs1_deg", "left_qs3_acc_mm_s2"] {
            assert_eq!(channel_of(name), Some(2));
        }
        assert_eq!(channel_of("left_tip_err_mm"), Some(4));
        assert_eq!(channel_of("right_cos_qs2"), Some(5));
        assert_eq!(channel_of("module1_parallel_margin"), Some(5));
        assert_eq!(channel_of("q6_acc_mm_s2"), Some(1));
        assert_eq!(channel_of("psi_deg"), Some(0));
        assert_eq!(unit_of("psi_rate_deg_s"), "deg/s");
        assert_eq!(unit_of("q1_acc_mm_s2"), "mm/s^2");
        assert_eq!(unit_of("t_s"), "s");
    }

    #[test]
    fn reads_back_with_counts_schemas_times_and_metadata() {
        let sc = scenario(100.0);
        let (bytes, n) = write(&sc, McapOptions::default());
        assert_eq!(n, 451);

        let summary = mcap::Summary::read(&bytes)
            .expect("summary readable")
            .expect("summary present");
        let stats = summary.stats.as_ref().expect("statistics");
        assert!(!summary.chunk_indexes.is_empty());
        assert!(
            summary
                .chunk_indexes
                .iter()
                .all(|c| !c.message_index_offsets.is_empty()),
            "message indexes"
        );
        assert_eq!(stats.metadata_count, 2);

        let mut per_topic: HashMap<String, Vec<(u64, serde_json::Value)>> = HashMap::new();
        for m in mcap::MessageStream::new(&bytes).expect("stream") {
            let m = m.expect("message");
            assert_eq!(m.channel.message_encoding, "json");
            let schema = m.channel.schema.as_ref().expect("schema");
            assert_eq!(schema.encoding, "jsonschema");
            assert_eq!(m.log_time, m.publish_time);
            let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON message");
            per_topic
                .entry(m.channel.topic.clone())
                .or_default()
                .push((m.log_time, v));
        }
        for (k, topic) in SAMPLE_TOPICS.iter().enumerate() {
            let msgs = &per_topic[*topic];
            assert_eq!(msgs.len(), n, "{topic}");
            let ch = summary
                .channels
                .values()
                .find(|c| c.topic == *topic)
                .expect("channel");
            assert_eq!(stats.channel_message_counts[&ch.id], n as u64);
            let schema: serde_json::Value =
                serde_json::from_slice(&ch.schema.as_ref().expect("schema").data).expect("schema");
            assert_eq!(schema["title"], SCHEMA_NAMES[k]);
            assert_eq!(schema["additionalProperties"], false);
            let required = schema["required"].as_array().expect("required");
            for (j, (ns, v)) in msgs.iter().enumerate() {
                let obj = v.as_object().expect("object");
                assert_eq!(obj.len(), required.len());
                assert!(
                    required
                        .iter()
                        .all(|f| obj[f.as_str().expect("name")].is_f64())
                );
                let t = obj["t_s"].as_f64().expect("t_s");
                assert_eq!(t.to_bits(), (j as f64 / 100.0).to_bits());
                assert_eq!(*ns, (t * 1e9).round() as u64);
            }
        }
        // The data agree with the CSV row to the last bit.
        let sim = Simulation::new(sc.clone()).expect("valid");
        let s100 = sim.samples().nth(100).expect("a sample").expect("ok");
        let row = s100.row();
        for topic in SAMPLE_TOPICS {
            let obj = per_topic[topic][100].1.as_object().expect("object").clone();
            for (name, v) in obj {
                let value = v.as_f64().expect("number");
                if let Some(c) = COLUMNS.iter().position(|c| *c == name) {
                    assert_eq!(value.to_bits(), row[c].to_bits(), "{name}");
                }
            }
        }
        assert_eq!(
            per_topic["/tips"][100].1["left_tip_z_mm"].as_f64(),
            Some(s100.left.tip.z)
        );

        // /tf and /scene: the first sample, every 20 ms, the last.
        let tf = &per_topic[TF_TOPIC];
        assert_eq!(tf.len(), 226);
        assert_eq!(tf[0].0, 0);
        assert_eq!(tf[1].0, 20_000_000);
        assert_eq!(tf.last().map(|m| m.0), Some(4_500_000_000));
        assert_eq!(per_topic[SCENE_TOPIC].len(), tf.len());

        // Metadata.
        let by_name: HashMap<String, Metadata> = summary
            .metadata_indexes
            .iter()
            .map(|i| {
                let m = mcap::read::metadata(&bytes, i).expect("metadata");
                (m.name.clone(), m)
            })
            .collect();
        let sc_meta = &by_name[SCENARIO_METADATA].metadata;
        let scen: serde_json::Value = serde_json::from_str(&sc_meta["scenario"]).expect("json");
        assert_eq!(scen["rate_hz"], 100.0);
        let geo: serde_json::Value = serde_json::from_str(&sc_meta["geometry"]).expect("json");
        assert_eq!(geo["link_lengths_mm"][0], 350.0);
        assert!(sc_meta["module1_geometry"].starts_with("assumed"));
        let run = &by_name[RUN_METADATA].metadata;
        assert_eq!(run["samples"], "451");
        assert_eq!(run["t_last_s"], "4.5");
    }

    #[test]
    fn the_frames_put_the_tool_tip_on_the_recomputed_tip() {
        let sim = Simulation::new(scenario(10.0)).expect("valid");
        let g = SceneGeometry::from_robot(&sim.scenario().robot);
        for s in sim.samples() {
            let s = s.expect("ok");
            let pose = Pose::from_array(s.pose);
            for (side, m, k) in [(Side::Left, &s.left, 0), (Side::Right, &s.right, 1)] {
                let q = Joints::new(m.q[0], m.q[1], m.q[2]);
                let tool = g.tool_rotation(side, &q);
                let local = Vector3::from(g.rcms_mm[k]) + tool * Vector3::new(0.0, 0.0, -m.q[2]);
                let world = pose.position() + pose.rotation() * local;
                assert!((world - m.tip).norm() < 1e-9, "{side:?} at {}", s.t);
                assert!((tool.determinant() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn scene_and_tf_follow_the_official_shapes() {
        let (bytes, _) = write(
            &scenario(50.0),
            McapOptions {
                scene_period_s: 0.0,
                ..McapOptions::default()
            },
        );
        let mut scenes = 0;
        for m in mcap::MessageStream::new(&bytes).expect("stream") {
            let m = m.expect("message");
            let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
            match m.channel.topic.as_str() {
                TF_TOPIC => {
                    assert_eq!(
                        m.channel.schema.as_ref().map(|s| s.name.as_str()),
                        Some("foxglove.FrameTransforms")
                    );
                    let tr = v["transforms"].as_array().expect("transforms");
                    assert_eq!(tr.len(), 5);
                    let q = &tr[0]["rotation"];
                    let norm: f64 = ["x", "y", "z", "w"]
                        .iter()
                        .map(|c| q[c].as_f64().expect("number").powi(2))
                        .sum();
                    assert!((norm - 1.0).abs() < 1e-12);
                    assert_eq!(
                        tr[0]["timestamp"]["sec"].as_u64().expect("sec") * 1_000_000_000
                            + tr[0]["timestamp"]["nsec"].as_u64().expect("nsec"),
                        m.log_time
                    );
                }
                SCENE_TOPIC => {
                    scenes += 1;
                    assert_eq!(
                        m.channel.schema.as_ref().map(|s| s.name.as_str()),
                        Some("foxglove.SceneUpdate")
                    );
                    let entities = v["entities"].as_array().expect("entities");
                    assert_eq!(entities.len(), 7);
                    let legs = &entities[1]["lines"][0]["points"];
                    assert_eq!(legs.as_array().map(Vec::len), Some(12));
                    // Metres: the platform is about half a metre below the base.
                    let z = entities[2]["spheres"][3]["pose"]["position"]["z"]
                        .as_f64()
                        .expect("z");
                    assert!((z + 0.5).abs() < 1e-9, "{z}");
                }
                _ => {}
            }
        }
        assert_eq!(scenes, 226);
    }

    #[test]
    fn the_error_can_cross_threads() {
        fn send_sync<T: Send + Sync + 'static>() {}
        send_sync::<McapError>();
    }

    #[test]
    fn embedded_schemas_are_the_official_ones() {
        let tf: serde_json::Value = serde_json::from_str(FRAME_TRANSFORMS_SCHEMA).expect("json");
        assert_eq!(tf["title"], "foxglove.FrameTransforms");
        let scene: serde_json::Value = serde_json::from_str(SCENE_UPDATE_SCHEMA).expect("json");
        assert_eq!(scene["title"], "foxglove.SceneUpdate");
    }

    #[test]
    fn non_finite_values_and_time_going_back_are_errors() {
        let sc = Scenario::paper();
        let mut sink = McapSink::new(Cursor::new(Vec::new()), &sc).expect("new");
        let good = Simulation::new(sc.clone())
            .expect("valid")
            .samples()
            .next()
            .expect("one")
            .expect("ok");
        let mut bad = good;
        bad.q[2] = f64::NAN;
        match sink.push(&bad) {
            Err(McapError::NonFinite { topic, field, .. }) => {
                assert_eq!((topic, field), ("/module1", "q3_mm"));
            }
            other => panic!("expected NonFinite, got {other:?}"),
        }
        let mut sink = McapSink::new(Cursor::new(Vec::new()), &sc).expect("new");
        sink.push(&good).expect("first");
        assert!(matches!(
            sink.push(&good),
            Err(McapError::TimeNotIncreasing { .. })
        ));
        let mut late = good;
        late.t = -1.0;
        assert!(matches!(
            sink.push(&late),
            Err(McapError::InvalidTime { .. })
        ));
        assert!(matches!(
            McapSink::with_options(
                Cursor::new(Vec::new()),
                &sc,
                McapOptions {
                    scene_period_s: f64::NAN,
                    ..McapOptions::default()
                }
            ),
            Err(McapError::InvalidOption { .. })
        ));
    }

    #[test]
    fn an_empty_run_is_still_a_valid_file() {
        let sink = McapSink::new(Cursor::new(Vec::new()), &Scenario::paper()).expect("new");
        let bytes = sink.finish().expect("finish").into_inner();
        let summary = mcap::Summary::read(&bytes).expect("ok").expect("summary");
        assert_eq!(summary.stats.map(|s| s.message_count), Some(0));
        assert_eq!(summary.channels.len(), 8);
    }
}
