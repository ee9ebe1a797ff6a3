//! The MCAP writer: a simulation as a Foxglove recording.
//!
//! [`McapSink`] streams records into an [MCAP](https://mcap.dev) file with
//! zstd-compressed chunks and a summary (statistics, chunk indexes, message
//! indexes), so that readers can seek. Every message is JSON (message
//! encoding `json`) with a JSON Schema per channel (schema encoding
//! `jsonschema`). Log time and publish time are the simulation time, ns.
//!
//! # Channels
//! One message per record on each of the seven data channels ([`Channel`](crate::Channel)),
//! every field a number named with its unit, `t_s` first in each, then the
//! channel's columns in the order of the [column table](crate::columns::ALL),
//! so that Foxglove's plot panel draws the paper's figures 5-7 directly:
//!
//! | topic | fields (besides `t_s`) |
//! |---|---|
//! | `/platform` | `x_mm y_mm z_mm psi_deg theta_deg phi_deg psi_rate_deg_s theta_rate_deg_s psi_acc_deg_s2 theta_acc_deg_s2` |
//! | `/module1` | `q1_mm..q6_mm`, `q1_rate_mm_s..q6_rate_mm_s`, `q1_acc_mm_s2..q6_acc_mm_s2` |
//! | `/left` | `left_qs1_deg left_qs2_deg left_qs3_mm`, their `_rate_` and `_acc_` |
//! | `/right` | the same for `right_` |
//! | `/tips` | `left_tip_err_mm right_tip_err_mm left_tip_x_mm left_tip_y_mm left_tip_z_mm right_tip_x_mm right_tip_y_mm right_tip_z_mm`, the ports `left_port_x_mm` .. `endoscope_port_z_mm` |
//! | `/margins` | `module1_serial_margin module1_parallel_margin left_cos_qs2 right_cos_qs2`, the clearance columns |
//! | `/camera` | `left_tip_u left_tip_v right_tip_u right_tip_v left_tip_in_view right_tip_in_view camera_aim_error_deg camera_roll_deg` |
//!
//! Every CSV column is on exactly one of them; the tips are the positions
//! recomputed from the joints by forward kinematics (fixed frame, MCAP only)
//! and their distances to the targets.
//!
//! A run with commands (retargets, a stop) has one more channel, `/motion`
//! (schema `parasils.Motion`), with one message per record:
//! `{"t_s": .., "command": 2, "kind": "stop"}`, the index of the active
//! command (the CSV's `command` column) and what it is (`reorient`,
//! `retarget` or `stop`). Its channel comes after `/scene`, so the other
//! channels keep their ids; a run without commands has no `/motion`.
//!
//! A teleoperation run ([`McapSink::teleop`]) has one more channel after
//! every other, `/teleop` (schema `parasils.Teleop`): per record each
//! device's axes and buttons, the command, state, hold, fault and hands as
//! the CSV's codes ([`crate::teleop`]), and the state (`ENABLED`), the
//! limit held at and the fault in words (empty strings when none).
//!
//! A run with forces ([`Scenario::has_forces`](crate::Scenario::has_forces):
//! a tip load or the robot file's `[dynamics]`) has one more channel after
//! every other, `/forces` (schema `parasils.Forces`), one message per
//! record: `t_s` and the fourteen force columns
//! ([`columns::FORCES`](crate::columns::FORCES)); and its `/scene` draws
//! the forces as arrows (entity `forces`: each slider's force along its
//! guide from the slider, each tip's load from the tip, at
//! [`FORCE_ARROW_MM_PER_N`], 2 mm per newton).
//!
//! For the 3D view, in metres as Foxglove expects:
//! - `/tf`, `foxglove.FrameTransforms`: `world -> platform` (`P` and `R`),
//!   `platform -> left_rcm`, `platform -> right_rcm` (the ports), and
//!   `left_rcm -> left_tool`, `right_rcm -> right_tool` (the last frame of
//!   each spherical module: the tool points along its `-z`, the tip at
//!   `z = -qs3`), and `platform -> camera` (at the endoscope's tip, `x`
//!   along the image's `u`, `y` down the image, `z` along the view);
//! - `/scene`, `foxglove.SceneUpdate`, in the `world` frame: module 1's six
//!   guides (over their strokes), sliders and legs (slider `B_j` to node
//!   `A_i`), the platform triangle and its spokes to `P`, the endoscope and
//!   both instrument shafts as translucent cylinders of their diameters
//!   (the robot file's `[bodies]`, in the `bodies_mm` metadata), each from
//!   its tip to its port (inside the patient) and from its port to its end
//!   (outside), the ports and tips, the target tips and the camera's view
//!   frustum (`camera_frustum`: lines from the eye to the image's corners). With an anatomy,
//!   one more `/scene` message at the first record draws every forbidden
//!   region (entities `no_go_0`, `no_go_1`, ..., semi-transparent red, kept
//!   for the whole run).
//!
//! For Foxglove's image panel, a schematic endoscope view (no picture: the
//! annotations on an empty image of the calibration's size):
//! - `/camera/calibration`, `foxglove.CameraCalibration`: the pinhole of
//!   the camera's field of view and aspect for a 1280 pixels wide image
//!   ([`CameraImage`]), in the `camera` frame;
//! - `/camera/annotations`, `foxglove.ImageAnnotations`: the image's centre
//!   and each tip ahead of the camera, in pixels.
//!
//! Their channels come after `/scene` and before `/motion`; their schemas
//! are written from Foxglove's documented fields (`schemas/README.md`).
//!
//! `/tf`, `/scene` and the two camera topics are published at a lower rate than the data channels:
//! at the first record, then at the first record of each
//! [`McapOptions::scene_period_s`] of simulation time (20 ms by default, the
//! 50 Hz of a screen), and at the last record. At 1 kHz, drawing every record
//! would double the file for frames no display shows; the exact numbers are
//! on the data channels. A period of 0 publishes every record.
//!
//! # Metadata
//! A metadata record `parasils.scenario`, written first: the [`Scenario`](crate::Scenario) in
//! library units ([`Scenario::library_units`](crate::Scenario::library_units): mm, rad, s) as JSON, the
//! [`SceneGeometry`] as JSON (mm), the resolved tips, the bodies' sizes
//! (`bodies_mm`: the robot file's `[bodies]`, as the scene draws them),
//! whether module 1's geometry is assumed, the channels' units. A record `parasils.run`, written
//! by [`McapSink::finish`]: the number of records and the first and last
//! times, and in a run with commands, `commands`: a JSON list of the
//! commands as they took effect, `{"command": 1, "kind": "retarget",
//! "t_s": 1.2}` (`t_s` the first sample each was active at).
//!
//! # Memory and threads
//! The writer holds one chunk (about [`McapOptions::chunk_size`] bytes) and
//! the small indexes of the file's chunks: memory stays flat however long the
//! run. JSON is written directly as text (shortest round-trip floats) into
//! buffers reused from record to record.
//!
//! Three threads share the work. The caller's formats the JSON into batches
//! of messages of about 64 KiB; a writer thread, which owns the `mcap`
//! writer, turns them into records and feeds the compressor; zstd's
//! multithreaded encoder compresses a job once it has about 2 MiB of input,
//! so with 4 MiB chunks (the default) a chunk's first half is compressed
//! while its second half is written. The file is the same, byte for byte, as
//! one written on a single thread; an I/O error of the writer thread is
//! reported by the next [`Sink::push`](crate::Sink::push) or by [`McapSink::finish`].
//!
//! # Modules
//! `camera` (the schematic image: its calibration, annotations and the
//! frustum's lines), `error` ([`McapError`]), `json` (the JSON text
//! builder), `schema` (the data channels' fields and schemas from the
//! column table, and the Foxglove schemas), `scene` (the `/tf` frames and
//! the `/scene` drawing),
//! `regions` (the forbidden regions in the scene), `forces` (`/forces` and
//! the force arrows),
//! `writer` (the writer thread), and `sink` ([`McapSink`], which ties them
//! together).
//!
//! The message builders are public ([`fields`] and [`data_schema`] for the
//! data channels, [`write_tf`], [`write_scene`], [`write_calibration`],
//! [`write_annotations`], [`log_time`], [`push_num`]) so that the live
//! server (`parasils-live`) publishes the same messages as this file.

mod camera;
mod error;
mod forces;
mod json;
mod regions;
mod scene;
mod schema;
mod sink;
mod writer;

pub use camera::{
    ANNOTATIONS_TOPIC, CALIBRATION_TOPIC, CAMERA_FRAME, CameraImage, IMAGE_WIDTH_PX,
    write_annotations, write_calibration,
};
pub use error::McapError;
pub use forces::{FORCE_ARROW_MM_PER_N, FORCES_TOPIC};
pub use json::{log_time, push_num};
pub use scene::{ProcedureScene, SCENE_TOPIC, SceneGeometry, TF_TOPIC, write_scene, write_tf};
pub use schema::{
    CAMERA_CALIBRATION_SCHEMA, FRAME_TRANSFORMS_SCHEMA, Field, IMAGE_ANNOTATIONS_SCHEMA,
    SCENE_UPDATE_SCHEMA, data_schema, fields,
};
pub use sink::{
    GENERATOR, MOTION_TOPIC, McapOptions, McapSink, RUN_METADATA, SAMPLE_TOPICS, SCENARIO_METADATA,
    TELEOP_TOPIC, scenario_metadata,
};

#[cfg(test)]
mod tests;
