//! The sink that ties the MCAP writer's parts together: the channels, the
//! metadata, one message per record on each data channel, the scene at its
//! period, the run's summary at the end.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use mcap::records::{MessageHeader, Metadata};
use mcap::{WriteOptions, Writer};
use nalgebra::Vector3;

/// The topic of the active command, in runs with commands.
pub const MOTION_TOPIC: &str = "/motion";
/// A teleoperation run's channel of the devices' inputs and the core's
/// state ([`McapSink::teleop`]).
pub const TELEOP_TOPIC: &str = "/teleop";

use super::camera::{self, ANNOTATIONS_TOPIC, CALIBRATION_TOPIC, CameraImage};
use super::error::McapError;
use super::forces::{self, FORCES_TOPIC};
use super::json::{log_time, push_num};
use super::regions;
use super::scene::{self, SCENE_TOPIC, SceneGeometry, TF_TOPIC};
use super::schema::{
    self, CAMERA_CALIBRATION_SCHEMA, FRAME_TRANSFORMS_SCHEMA, Field, IMAGE_ANNOTATIONS_SCHEMA,
    SCENE_UPDATE_SCHEMA,
};
use super::writer::{BATCH_BYTES, Batch, WriterThread};
use crate::columns::Channel;
use crate::record::Record;
use crate::scenario::{CommandKind, Scenario};
use crate::sink::Sink;
use parasils_anatomy::Anatomy;
use std::sync::Arc;

/// The seven data channels' topics, one message per record on each, in the
/// order of their channel ids.
pub const SAMPLE_TOPICS: [&str; 7] = [
    Channel::Platform.topic(),
    Channel::Module1.topic(),
    Channel::Left.topic(),
    Channel::Right.topic(),
    Channel::Tips.topic(),
    Channel::Margins.topic(),
    Channel::Camera.topic(),
];
/// The name of the metadata record with the scenario and the geometry.
pub const SCENARIO_METADATA: &str = "parasils.scenario";
/// The name of the metadata record written at the end: record count, times.
pub const RUN_METADATA: &str = "parasils.run";
/// The writer named in the file's header and metadata: the `parasils`
/// command's package and version (the Python bindings write the same file).
pub const GENERATOR: &str = concat!("parasils-cli ", env!("CARGO_PKG_VERSION"));

/// How the MCAP file is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McapOptions {
    /// The simulation-time period of `/tf` and `/scene`, s (0: every record).
    /// The first and the last records are always published.
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

/// One data channel: its id, its fields, its next sequence number.
#[derive(Debug)]
struct DataChannel {
    id: u16,
    topic: &'static str,
    fields: Vec<Field>,
    sequence: u32,
}

/// Streams records into an MCAP file; see the module docs.
pub struct McapSink<W: Write + Seek> {
    /// The writer thread, which owns the `mcap` writer.
    thread: WriterThread<W>,
    /// The messages formatted since the last batch was sent.
    batch: Batch,
    data: Vec<DataChannel>,
    tf: (u16, u32),
    scene: (u16, u32),
    /// `/camera/calibration`'s and `/camera/annotations`' channel ids and
    /// next sequence numbers.
    calibration: (u16, u32),
    annotations: (u16, u32),
    /// The schematic image they describe.
    image: CameraImage,
    /// `/motion`'s channel id and next sequence number, in a run with
    /// commands.
    motion: Option<(u16, u32)>,
    /// `/forces`, in a run that has forces, and the tip loads its arrows
    /// draw (N, fixed frame, left then right).
    forces: Option<(DataChannel, [Vector3<f64>; 2])>,
    /// `/teleop`'s channel id, next sequence number and numeric fields, in
    /// a teleoperation run.
    teleop: Option<(u16, u32, Vec<Field>)>,
    /// The commands as they took effect: index, kind, first time.
    commands: Vec<(u32, CommandKind, f64)>,
    /// In a procedure: each motion's name as a JSON string (`null` for
    /// none), for `/motion`.
    motion_names: Option<Vec<String>>,
    /// In a procedure: the three tips (left, right, endoscope) where the
    /// last `/scene` drew them, and how many path pieces were drawn.
    paths: Option<([Vector3<f64>; 3], u32)>,
    geometry: SceneGeometry,
    /// The forbidden regions, until the first `/scene` has drawn them.
    anatomy: Option<Arc<Anatomy>>,
    targets: [Vector3<f64>; 2],
    options: McapOptions,
    scene_period_ns: u64,
    /// The log time at or after which `/tf` and `/scene` are next published.
    next_scene_ns: u64,
    /// The last record, its log time, and whether `/tf` and `/scene` have it.
    last: Option<(Record, u64, bool)>,
    first_t: Option<f64>,
    count: u64,
    buf: Vec<u8>,
    ryu: ryu::Buffer,
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

/// The fields of the `parasils.scenario` metadata record of `scenario`
/// drawn with `geometry`, its scene every `period` s: the scenario (JSON,
/// library units), its units, the geometry, the tips, the bodies, module
/// 1's provenance, the channels' units, the scene's period, the generator.
/// `simulate`'s file and the live server's recording write the same.
///
/// # Errors
/// [`McapError`] when a value cannot be serialised.
pub fn scenario_metadata(
    scenario: &Scenario,
    geometry: &SceneGeometry,
    period: f64,
) -> Result<BTreeMap<String, String>, McapError> {
    let tips = scenario.tips();
    let mut meta = BTreeMap::new();
    meta.insert(
        "scenario".to_owned(),
        serde_json::to_string(&scenario.library_units())?,
    );
    meta.insert("scenario_units".to_owned(), "mm, rad, s".to_owned());
    meta.insert("geometry".to_owned(), serde_json::to_string(geometry)?);
    meta.insert(
        "tips_mm".to_owned(),
        serde_json::to_string(&[
            [tips.left.x, tips.left.y, tips.left.z],
            [tips.right.x, tips.right.y, tips.right.z],
        ])?,
    );
    // The shafts' and the endoscope's sizes the scene draws them at.
    meta.insert(
        "bodies_mm".to_owned(),
        serde_json::to_string(&scenario.bodies)?,
    );
    meta.insert(
        "module1_geometry".to_owned(),
        match scenario.robot.module1.provenance() {
            parasils::kin::Provenance::Assumed => {
                "assumed: not the real robot's dimensions (unpublished)".to_owned()
            }
            parasils::kin::Provenance::Measured => "given by the user".to_owned(),
            p => p.to_string(),
        },
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
    meta.insert("generator".to_owned(), GENERATOR.to_owned());
    Ok(meta)
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
        Self::build(writer, scenario, options, false)
    }

    /// Starts a teleoperation run's file: as [`McapSink::new`], with one more
    /// channel, `/teleop` (schema `parasils.Teleop`), after every other: one
    /// message per record with each device's axes and buttons, the codes of
    /// [`crate::teleop`] and the state, the limit held at and the fault in
    /// words (`{"t_s": .., "left_tx": .., .., "state": "ENABLED", "hold":
    /// "margin right.qs3_limits", "fault": ""}`).
    ///
    /// # Errors
    /// As [`McapSink::new`].
    pub fn teleop(writer: W, scenario: &Scenario) -> Result<Self, McapError> {
        Self::build(writer, scenario, McapOptions::default(), true)
    }

    fn build(
        writer: W,
        scenario: &Scenario,
        options: McapOptions,
        teleop: bool,
    ) -> Result<Self, McapError> {
        let period = options.scene_period_s;
        let Ok(scene_period_ns) = log_time(period) else {
            return Err(McapError::InvalidOption {
                what: "scene_period_s",
                value: period,
            });
        };
        if options.chunk_size == 0 {
            return Err(McapError::InvalidOption {
                what: "chunk_size",
                value: 0.0,
            });
        }
        let mut writer = WriteOptions::new()
            .profile("")
            .library(GENERATOR)
            .compression(Some(mcap::Compression::Zstd))
            .compression_level(options.compression_level)
            .chunk_size(Some(options.chunk_size))
            .create(writer)?;

        let geometry = SceneGeometry::from_robot(&scenario.robot)
            .and_then(|g| g.with_bodies(scenario.bodies))
            .map_err(McapError::Geometry)?;
        writer.write_metadata(&Metadata {
            name: SCENARIO_METADATA.to_owned(),
            metadata: scenario_metadata(scenario, &geometry, period)?,
        })?;

        let no_meta = BTreeMap::new();
        // One schema and the channel on it, in the order the ids are given.
        let mut add = |name: &str, schema: &[u8], topic: &str| -> Result<u16, McapError> {
            let schema_id = writer.add_schema(name, "jsonschema", schema)?;
            Ok(writer.add_channel(schema_id, topic, "json", &no_meta)?)
        };
        let mut data = Vec::with_capacity(Channel::ALL.len());
        for channel in Channel::ALL {
            let fields = schema::fields(channel);
            let schema = serde_json::to_vec_pretty(&schema::data_schema(channel, &fields))?;
            data.push(DataChannel {
                id: add(channel.schema_name(), &schema, channel.topic())?,
                topic: channel.topic(),
                fields,
                sequence: 0,
            });
        }
        let tf = add(
            "foxglove.FrameTransforms",
            FRAME_TRANSFORMS_SCHEMA.as_bytes(),
            TF_TOPIC,
        )?;
        let scene = add(
            "foxglove.SceneUpdate",
            SCENE_UPDATE_SCHEMA.as_bytes(),
            SCENE_TOPIC,
        )?;
        let calibration = add(
            "foxglove.CameraCalibration",
            CAMERA_CALIBRATION_SCHEMA.as_bytes(),
            CALIBRATION_TOPIC,
        )?;
        let annotations = add(
            "foxglove.ImageAnnotations",
            IMAGE_ANNOTATIONS_SCHEMA.as_bytes(),
            ANNOTATIONS_TOPIC,
        )?;
        let procedure = scenario.is_procedure();
        let motion = if procedure {
            let schema = serde_json::to_vec_pretty(&schema::procedure_motion_schema())?;
            Some((
                add(schema::PROCEDURE_MOTION_SCHEMA_NAME, &schema, MOTION_TOPIC)?,
                0,
            ))
        } else if scenario.has_commands() {
            let schema = serde_json::to_vec_pretty(&schema::motion_schema())?;
            Some((add(schema::MOTION_SCHEMA_NAME, &schema, MOTION_TOPIC)?, 0))
        } else {
            None
        };

        // After every other channel, so that theirs keep their ids.
        let forces = if scenario.has_forces() {
            let fields = schema::forces_fields();
            let schema = serde_json::to_vec_pretty(&schema::forces_schema(&fields))?;
            let id = add(schema::FORCES_SCHEMA_NAME, &schema, FORCES_TOPIC)?;
            let load = |l: Option<[f64; 3]>| Vector3::from(l.unwrap_or_default());
            Some((
                DataChannel {
                    id,
                    topic: FORCES_TOPIC,
                    fields,
                    sequence: 0,
                },
                [
                    load(scenario.tip_load_left_n),
                    load(scenario.tip_load_right_n),
                ],
            ))
        } else {
            None
        };
        // A teleoperation run's, last of all.
        let teleop = if teleop {
            let fields = schema::teleop_fields();
            let schema = serde_json::to_vec_pretty(&schema::teleop_schema(&fields))?;
            let id = add(schema::TELEOP_SCHEMA_NAME, &schema, TELEOP_TOPIC)?;
            Some((id, 0, fields))
        } else {
            None
        };

        let tips = scenario.tips();
        let thread = WriterThread::spawn(writer)?;
        Ok(Self {
            batch: thread.empty_batch(),
            thread,
            data,
            tf: (tf, 0),
            scene: (scene, 0),
            calibration: (calibration, 0),
            annotations: (annotations, 0),
            image: CameraImage::of(&geometry.camera),
            motion,
            forces,
            teleop,
            commands: Vec::new(),
            motion_names: procedure.then(|| {
                scenario
                    .motions()
                    .iter()
                    .map(|m| serde_json::to_string(&m.name).unwrap_or_else(|_| "null".to_owned()))
                    .collect()
            }),
            paths: None,
            anatomy: scenario.anatomy.clone(),
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

    /// The number of records written so far.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Publishes any record still owed to `/tf` and `/scene` (the last one),
    /// writes the `parasils.run` metadata record and the summary (statistics,
    /// schemas, channels, chunk and message indexes), and returns the writer.
    ///
    /// # Errors
    /// [`McapError::Mcap`] when writing fails; [`McapError::NonFinite`] when
    /// the last record's `/tf` or `/scene`, computed here (between scene
    /// periods a record's visuals are not computed when it is pushed), holds
    /// a number JSON cannot: a record whose every column is finite can still
    /// make one (a pose whose rotation or scene points overflow), and the
    /// error names the topic and the time. A simulation's records never do.
    pub fn finish(mut self) -> Result<W, McapError> {
        if let Some((record, ns, false)) = self.last {
            self.write_visuals(&record, ns)?;
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
        if self.motion.is_some() {
            let list: Vec<serde_json::Value> = self
                .commands
                .iter()
                .map(|(index, kind, t)| {
                    serde_json::json!({"command": index, "kind": kind.name(), "t_s": t})
                })
                .collect();
            meta.insert("commands".to_owned(), serde_json::to_string(&list)?);
        }
        write_run_metadata(&mut writer, meta)?;
        writer.finish()?;
        Ok(writer.into_inner())
    }

    /// Queues the message in `buf` for the writer thread.
    fn write(&mut self, id: u16, sequence: u32, ns: u64) {
        let header = MessageHeader {
            channel_id: id,
            sequence,
            log_time: ns,
            publish_time: ns,
        };
        self.batch.push(header, &self.buf);
    }

    /// Writes `/tf` and `/scene` for `record`.
    fn write_visuals(&mut self, record: &Record, ns: u64) -> Result<(), McapError> {
        self.buf.clear();
        scene::write_tf(&self.geometry, record, ns, &mut self.buf, &mut self.ryu)?;
        let (id, seq) = self.tf;
        self.write(id, seq, ns);
        self.tf.1 = seq.wrapping_add(1);

        // The forbidden regions, once, kept for the whole run.
        if let Some(anatomy) = self.anatomy.take() {
            self.buf.clear();
            regions::write_regions(&anatomy, record.t, ns, &mut self.buf, &mut self.ryu)?;
            let (id, seq) = self.scene;
            self.write(id, seq, ns);
            self.scene.1 = seq.wrapping_add(1);
        }
        self.buf.clear();
        // In a procedure: the endoscope at its true depth, and the piece of
        // each tip's path since the last scene (kept: no lifetime).
        let procedure = self.motion_names.as_ref().map(|_| {
            let now = [record.left.tip, record.right.tip, record.endoscope_tip];
            let (from, n) = self.paths.unwrap_or((now, 0));
            self.paths = Some((now, n.wrapping_add(1)));
            scene::ProcedureScene {
                path_from: from,
                path_piece: n,
            }
        });
        scene::write_scene(
            &self.geometry,
            &self.targets,
            record,
            procedure.as_ref(),
            ns,
            &mut self.buf,
            &mut self.ryu,
        )?;
        let (id, seq) = self.scene;
        self.write(id, seq, ns);
        self.scene.1 = seq.wrapping_add(1);

        if let Some((_, loads)) = &self.forces {
            self.buf.clear();
            forces::write_arrows(
                &self.geometry,
                loads,
                record,
                ns,
                &mut self.buf,
                &mut self.ryu,
            )?;
            let (id, seq) = self.scene;
            self.write(id, seq, ns);
            self.scene.1 = seq.wrapping_add(1);
        }

        self.buf.clear();
        camera::write_calibration(&self.image, ns, record.t, &mut self.buf, &mut self.ryu)?;
        let (id, seq) = self.calibration;
        self.write(id, seq, ns);
        self.calibration.1 = seq.wrapping_add(1);

        self.buf.clear();
        camera::write_annotations(&self.image, record, ns, &mut self.buf, &mut self.ryu)?;
        let (id, seq) = self.annotations;
        self.write(id, seq, ns);
        self.annotations.1 = seq.wrapping_add(1);
        Ok(())
    }
}

fn write_run_metadata<W: Write + Seek>(
    writer: &mut Writer<W>,
    metadata: BTreeMap<String, String>,
) -> Result<(), McapError> {
    writer.write_metadata(&Metadata {
        name: RUN_METADATA.to_owned(),
        metadata,
    })?;
    Ok(())
}

impl<W: Write + Seek + Send + 'static> Sink for McapSink<W> {
    type Error = McapError;

    fn push(&mut self, record: &Record) -> Result<(), McapError> {
        let ns = log_time(record.t)?;
        if let Some((prev, prev_ns, _)) = &self.last
            && ns <= *prev_ns
        {
            return Err(McapError::TimeNotIncreasing {
                t: record.t,
                previous: prev.t,
            });
        }
        for k in 0..self.data.len() {
            self.buf.clear();
            let ch = &self.data[k];
            write_fields(&mut self.buf, &mut self.ryu, &ch.fields, record, ch.topic)?;
            self.buf.push(b'}');
            let (id, seq) = (ch.id, ch.sequence);
            self.write(id, seq, ns);
            self.data[k].sequence = seq.wrapping_add(1);
        }

        if let Some((ch, _)) = &self.forces {
            self.buf.clear();
            write_fields(
                &mut self.buf,
                &mut self.ryu,
                &ch.fields,
                record,
                FORCES_TOPIC,
            )?;
            self.buf.push(b'}');
            let (id, seq) = (ch.id, ch.sequence);
            self.write(id, seq, ns);
            if let Some((ch, _)) = &mut self.forces {
                ch.sequence = seq.wrapping_add(1);
            }
        }

        if let (Some((id, seq)), Some(names)) = (self.motion, &self.motion_names) {
            self.buf.clear();
            let name = names
                .get(record.motion as usize)
                .map_or("null", String::as_str);
            write_procedure_motion(&mut self.buf, &mut self.ryu, record, name)?;
            self.write(id, seq, ns);
            self.motion = Some((id, seq.wrapping_add(1)));
        } else if let Some((id, seq)) = self.motion {
            self.buf.clear();
            self.buf.extend_from_slice(b"{\"t_s\":");
            if let Err(value) = push_num(&mut self.buf, &mut self.ryu, record.t) {
                return Err(McapError::NonFinite {
                    topic: MOTION_TOPIC,
                    field: "t_s",
                    t: record.t,
                    value,
                });
            }
            self.buf.extend_from_slice(b",\"command\":");
            self.buf
                .extend_from_slice(itoa::Buffer::new().format(record.command).as_bytes());
            self.buf.extend_from_slice(b",\"kind\":\"");
            self.buf.extend_from_slice(record.kind.name().as_bytes());
            self.buf.extend_from_slice(b"\"}");
            self.write(id, seq, ns);
            self.motion = Some((id, seq.wrapping_add(1)));
            if self.commands.last().is_none_or(|c| c.0 != record.command) {
                self.commands.push((record.command, record.kind, record.t));
            }
        }

        if let Some((id, seq, fields)) = &self.teleop {
            let (id, seq) = (*id, *seq);
            self.buf.clear();
            write_fields(&mut self.buf, &mut self.ryu, fields, record, TELEOP_TOPIC)?;
            let r = &record.teleop;
            let words = [
                ("state", r.state.to_string()),
                ("hold", r.hold.map(|h| h.to_string()).unwrap_or_default()),
                ("fault", r.fault.map(|f| f.to_string()).unwrap_or_default()),
            ];
            for (key, text) in words {
                self.buf.extend_from_slice(b",\"");
                self.buf.extend_from_slice(key.as_bytes());
                self.buf.extend_from_slice(b"\":");
                serde_json::to_writer(&mut self.buf, &text)?;
            }
            self.buf.push(b'}');
            self.write(id, seq, ns);
            if let Some(t) = &mut self.teleop {
                t.1 = seq.wrapping_add(1);
            }
        }

        let publish = self.last.is_none() || ns >= self.next_scene_ns;
        if publish {
            self.write_visuals(record, ns)?;
            self.next_scene_ns = match self.scene_period_ns {
                0 => 0,
                p => (ns / p).saturating_add(1).saturating_mul(p),
            };
        }
        self.first_t.get_or_insert(record.t);
        self.last = Some((*record, ns, publish));
        self.count += 1;
        if self.batch.bytes.len() >= BATCH_BYTES {
            let next = self.thread.empty_batch();
            let full = core::mem::replace(&mut self.batch, next);
            self.thread.send(full)?;
        }
        Ok(())
    }
}

/// The keys and values of `fields` for `record` into `buf` (the message's
/// opening brace is the first key's): whole-number columns (codes, bit
/// masks) as JSON integers, the others as shortest round-trip decimals.
///
/// # Errors
/// [`McapError::NonFinite`] naming `topic` and the field.
fn write_fields(
    buf: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
    fields: &[Field],
    record: &Record,
    topic: &'static str,
) -> Result<(), McapError> {
    for f in fields {
        buf.extend_from_slice(&f.key);
        let value = f.column.value(record);
        let written = if f.column.integer && value.fract() == 0.0 && value.abs() < 1e15 {
            #[allow(clippy::cast_possible_truncation, reason = "a whole number below 1e15")]
            let n = value as i64;
            buf.extend_from_slice(itoa::Buffer::new().format(n).as_bytes());
            Ok(())
        } else {
            push_num(buf, ryu, value)
        };
        if let Err(value) = written {
            return Err(McapError::NonFinite {
                topic,
                field: f.column.name,
                t: record.t,
                value,
            });
        }
    }
    Ok(())
}

/// A procedure's `/motion` message for `record`: the motion under way (its
/// index, type and `name`, a JSON string or `null`) and the endoscope.
fn write_procedure_motion(
    buf: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
    record: &Record,
    name: &str,
) -> Result<(), McapError> {
    let fields = [
        ("{\"t_s\":", "t_s", record.t),
        (
            ",\"endoscope_depth_mm\":",
            "endoscope_depth_mm",
            record.endoscope_depth,
        ),
        (
            ",\"endoscope_tip_x_mm\":",
            "endoscope_tip_x_mm",
            record.endoscope_tip.x,
        ),
        (
            ",\"endoscope_tip_y_mm\":",
            "endoscope_tip_y_mm",
            record.endoscope_tip.y,
        ),
        (
            ",\"endoscope_tip_z_mm\":",
            "endoscope_tip_z_mm",
            record.endoscope_tip.z,
        ),
    ];
    for (key, field, value) in fields {
        buf.extend_from_slice(key.as_bytes());
        if let Err(value) = push_num(buf, ryu, value) {
            return Err(McapError::NonFinite {
                topic: MOTION_TOPIC,
                field,
                t: record.t,
                value,
            });
        }
    }
    buf.extend_from_slice(b",\"motion\":");
    buf.extend_from_slice(itoa::Buffer::new().format(record.motion).as_bytes());
    buf.extend_from_slice(b",\"motion_type\":");
    buf.extend_from_slice(itoa::Buffer::new().format(record.motion_type).as_bytes());
    buf.extend_from_slice(b",\"type_name\":\"");
    let type_name = match record.motion_type {
        1 => "position",
        2 => "insert",
        3 => "manipulate",
        _ => "reorient",
    };
    buf.extend_from_slice(type_name.as_bytes());
    buf.extend_from_slice(b"\",\"name\":");
    buf.extend_from_slice(name.as_bytes());
    buf.push(b'}');
    Ok(())
}
