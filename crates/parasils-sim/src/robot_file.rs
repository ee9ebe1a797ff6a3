//! The robot file: the whole robot's geometry as TOML, to load, edit and save.
//!
//! One file holds module 1 (the parallel robot: six guides with their links
//! and strokes, three platform nodes, thresholds) and both instrument modules
//! (angles, radius, port, joint limits, thresholds): a
//! [`RobotGeometry<f64>`](parasils::kin::RobotGeometry). Every key names its unit (`link_length_mm`,
//! `alpha_deg`, `qs1_deg = [min, max]`); angles are in degrees in the file
//! and in radians in memory, lengths in mm in both. `parasils robot` prints
//! the default file, which is also under version control as
//! `robots/default.toml`.
//!
//! **Module 1's default dimensions are assumed**, not the real robot's (which
//! are not published; see `docs/model.md`, *Module 1, the parallel robot*):
//! the file says so with `assumed = true` in its `[module1]` table, which
//! the CLI reads to label every module-1 number it prints. A user with the
//! real dimensions edits them and sets `assumed = false`.
//!
//! ```
//! use parasils::kin::RobotGeometry;
//! use parasils_sim::robot_file;
//!
//! let text = robot_file::to_toml_string(&RobotGeometry::paper())?;
//! assert!(text.contains("link_length_mm = 350.0"));
//! assert_eq!(robot_file::parse(&text)?, RobotGeometry::paper());
//! # Ok::<(), robot_file::RobotFileError>(())
//! ```
//!
//! Errors say where: a malformed file, a missing, unknown or mistyped key, or
//! a value out of its range (a negative length, an interval with
//! `min > max`, a branch other than `1` or `-1`) is a
//! [`RobotFileError::Parse`] with the line, the column, the key and the line's
//! text; parameters that parse but do not make a valid robot are a
//! [`RobotFileError::Invalid`] naming the parameter.

mod dynamics;
mod error;
mod locate;
mod read;
mod schema;
mod write;

pub use dynamics::{DynamicsFile, StiffnessFile};
pub use error::RobotFileError;
pub use read::{load, load_robot, parse, parse_robot, save};
pub use schema::{
    BodiesFile, CameraFile, EndoscopeFile, GuideFile, InstrumentFile, LegFile, Module1File,
    RobotFile,
};
pub use write::{robot_to_toml_string, to_toml_string};
