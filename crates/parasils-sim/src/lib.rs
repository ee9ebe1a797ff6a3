//! The PARA-SILSROB simulation library: what `parasils simulate` and the
//! Python bindings' `parasils.simulate` both run, so that they give the same
//! numbers to the last bit.
//!
//! Data flows one way: a [`Scenario`] (the inputs in user units, the paper's
//! by default, resolved from a front end's [`Input`]) is validated and
//! planned into a [`Simulation`], whose [`Simulation::run`] steps the
//! controller through the run sampled at a fixed rate and hands each
//! [`Record`] to a [`Sink`]: the [`csv`] and [`mcap`] writers (into an
//! atomic [`OutputFile`]), the [`summary`], the `plot` (feature `plot`), or
//! several at once through a [`Tee`]. Nothing holds the whole run in memory.
//! Every writer reads the records through one table of [`columns`] (name,
//! unit, MCAP channel, value).
//!
//! A run is a type ([`Run`]), one of two kinds:
//! - **planned** ([`Timeline`]): motions of the paper's four types, each
//!   from where the previous one ended, planned on the control cycle and
//!   checked in full by [`Simulation::new`] before any record is written.
//!   The paper's run is a timeline of one reorientation ([`Motions::Turn`]);
//!   a **procedure** is a list of motions read from a file by [`procedure`]
//!   ([`Motions::Procedure`]), whose output has twelve more columns
//!   ([`columns::PROCEDURE`]: the motion, the endoscope's depth, the three
//!   tips). One path plans and samples both.
//! - **online** ([`Online`]): a turn with new goals and a stop commanded
//!   while the platform moves. Such a run goes through the online controller
//!   ([`parasils::OnlineController`], with its margin supervisor), each
//!   command taking effect at the first sample at or after its time, and its
//!   output has one more column, `command`, the index of the active command
//!   (the CSV's last column, and `/motion` in MCAP). A run without commands
//!   is written exactly as before they existed.
//!
//! With a tip load ([`Scenario::tip_load_left_n`],
//! [`Scenario::tip_load_right_n`]: the force a tip exerts on the tissue, N,
//! fixed frame) or a platform body ([`Scenario::dynamics`], the robot
//! file's `[dynamics]`), every record carries the twelve actuators' forces
//! holding the loads and moving the body by Newton-Euler ([`Record::forces`],
//! from `parasils_kin::statics`), written as the fourteen columns
//! [`columns::FORCES`] after the run's others (the last two each tip's
//! deflection under the tissue's push, with [`Scenario::stiffness`], the
//! robot file's `[stiffness]`) and in MCAP on `/forces`.
//!
//! The paper's run, written as CSV in memory:
//!
//! ```
//! use parasils_sim::csv::CsvSink;
//! use parasils_sim::{Scenario, Simulation};
//!
//! let sim = Simulation::new(Scenario::paper())?;
//! assert_eq!(sim.sample_count(), 4501);
//! let mut csv = CsvSink::new(Vec::new())?;
//! sim.run(&mut csv)?;
//! let text = String::from_utf8(csv.finish()?)?;
//! let mut lines = text.lines();
//! assert!(lines.next().is_some_and(|h| h.starts_with("t_s,x_mm,y_mm,z_mm,psi_deg,")));
//! // The first row starts at the user's own degrees: -15, 10, -60.
//! assert!(lines.next().is_some_and(|r| r.starts_with("0.0,15.0,20.0,-500.0,-15.0,10.0,-60.0,")));
//! assert_eq!(lines.count(), 4500);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Modules
//! In import order (a module uses only those above it); the private ones
//! (`supervisor`, `motion`, `record`, `sink`, `engine`, `robot`) have their
//! types at the crate root.
//!
//! | module | concept |
//! |---|---|
//! | `supervisor` | [`SupervisorTable`]: the margin supervisor's thresholds a robot file gives |
//! | [`timing`] | [`OptimalLaw`]: a path timed as fast as the actuators allow |
//! | `motion` | a procedure's motions in user units ([`MotionSpec`]): goals of the paper's four types, limits, names |
//! | [`scenario`] | [`Scenario`]: a run resolved, in user units (mm, deg, deg/s, deg/s^2, Hz): what every run shares, and its kind, [`Run`] (a planned [`Timeline`] of motions, the paper's [`Turn`] or a procedure's; an [`Online`] run with its commands) |
//! | `record` | [`Record`]: one instant, typed, in library units |
//! | [`columns`] | the one table of output columns |
//! | `sink` | [`Sink`] and [`Tee`] |
//! | `engine` | [`Simulation`]: validation, planning (one path for every timeline), the commands' schedule, the records |
//! | [`csv`], [`mcap`], [`summary`], `plot` | the sinks |
//! | [`output`] | [`OutputFile`]: CSV or MCAP written atomically (with `parasils_io`'s [`AtomicFile`](parasils_io::AtomicFile)) |
//! | `robot` | [`Robot`]: a robot file's whole content (geometry and supervisor thresholds), read once |
//! | [`robot_file`] | the robot file as TOML |
//! | [`procedure`] | procedure files (TOML) into a scenario with motions |
//! | [`teleop`] | a teleoperation run's columns ([`teleop::TELEOP`]) and summary ([`TeleopSummary`]); the run itself is the engine's ([`TeleopRun`], [`Replay`]) |
//! | [`input`] | [`Input`]: what a user asks for, each field given or not; the one resolution of defaults, exclusions and the timing rule that every front end calls |
//!
//! The plumbing (files written atomically, numbers in messages, the plot
//! kit) is `parasils-io`'s; the reach maps are a study of their own, in
//! `parasils-reach`.
//!
//! The robot's geometry (module 1 and both instrument modules, with their
//! limits) is read from and written to TOML by [`robot_file`]. Module 1's
//! default geometry is **assumed** (its real dimensions are not published:
//! see `docs/model.md`, *Module 1, the parallel robot*); `robots/default.toml`
//! holds it, with `assumed = true`, for users to copy and edit.
//!
//! # Features
//! - `plot`: the paper's figures as SVG or PNG (`plot::PlotSink`), with
//!   plotters and an embedded font. Off by default: the `parasils` command
//!   turns it on, the Python bindings leave it off.

pub mod columns;
pub mod csv;
mod engine;
pub mod input;
#[cfg(test)]
mod input_tests;
pub mod mcap;
mod motion;
pub mod no_go;
pub mod output;
#[cfg(feature = "plot")]
pub mod plot;
pub mod procedure;
#[cfg(test)]
mod procedure_tests;
mod record;
mod robot;
pub mod robot_file;
pub mod scenario;
mod sink;
pub mod summary;
mod supervisor;
pub mod teleop;
pub mod timing;

pub use columns::{Channel, Column, InstrumentColumns};
pub use csv::CsvSink;
pub use engine::RegionCertificate;
pub use engine::procedure::{
    CameraCheck, MotionCheck, PlannedMotion, ProcedureCheck, ProcedurePlan, Warning,
};
pub use engine::{
    CERTIFY_MAX_DEPTH, CERTIFY_TOLERANCE_MM, CommandError, CommandName, MotionClearance, Records,
    Replay, RunError, SETTLE_S, Scheduled, Simulation, SimulationError, TeleopRun,
};
pub use input::{Input, InputError, InputField, ProcedureSource, RobotSource, TimingKind};
pub use mcap::{
    CameraImage, Field, McapError, McapOptions, McapSink, ProcedureScene, SceneGeometry,
};
pub use motion::{
    CameraMode, Inside, InsideRule, LookAt, LookAtTips, MotionGoal, MotionLimits, MotionName,
    MotionSpec,
};
pub use output::{Flushed, Format, OutputError, OutputFile};
pub use parasils_anatomy::Body;
pub use parasils_anatomy::{Anatomy, AnatomyError};
#[cfg(feature = "plot")]
pub use plot::PlotSink;
pub use procedure::ProcedureError;
pub use record::{
    CameraRecord, ClearanceRecord, ForceRecord, InstrumentRecord, Module1Record, Record,
    TeleopRecord,
};
pub use robot::Robot;
pub use robot_file::{
    BodiesFile, CameraFile, DynamicsFile, EndoscopeFile, GuideFile, InstrumentFile, LegFile,
    Module1File, RobotFile, RobotFileError, StiffnessFile,
};
pub use scenario::{
    Command, CommandKind, LibraryUnits, Motions, Online, Retarget, RetargetUnits, Run, Scenario,
    Timeline, Timing, Turn,
};
pub use sink::{BoxError, Sink, Tee};
pub use summary::{CheckReport, Summary};
pub use supervisor::SupervisorTable;
pub use teleop::TeleopSummary;
pub use timing::{
    Binding, OptimalLaw, OptimalMotion, PhasePlane, PhaseSummary, TimingError, TimingOptions,
};
