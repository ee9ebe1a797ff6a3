//! The fuzz targets' checks, one plain function per target, shared by the
//! libFuzzer binaries (`fuzz_targets/`, built by `scripts/fuzz`) and the
//! corpus replay test (`tests/corpus.rs`, part of the test command). Each
//! takes the fuzzer's bytes and panics when a property fails; see
//! `FUZZING.md` for what each target checks.

// The `parasils` command's argument definitions, compiled unchanged: the
// command is a binary, so its files sit at this crate's root under the names
// the command gives them (`crate::args`, and `crate::calibrate` with the
// `crate::stdout` it uses).
#[allow(
    dead_code,
    missing_docs,
    clippy::all,
    reason = "the command's own files"
)]
#[path = "../../crates/parasils-cli/src/args.rs"]
mod args;
#[allow(
    dead_code,
    missing_docs,
    clippy::all,
    reason = "the command's own files"
)]
#[path = "../../crates/parasils-cli/src/calibrate.rs"]
mod calibrate;
#[allow(
    dead_code,
    missing_docs,
    clippy::all,
    reason = "the command's own files"
)]
#[path = "../../crates/parasils-cli/src/stdout.rs"]
mod stdout;

pub mod calibration;
pub mod clearance;
pub mod cli;
pub mod input;
pub mod kin;
pub mod procedure;
pub mod robot_file;
pub mod traj;
pub mod writers;

/// A target: its name (the folder of its corpus and the binary's name) and
/// its check.
pub type Target = (&'static str, fn(&[u8]));

/// Every target, in the campaign's order.
pub const TARGETS: [Target; 12] = [
    ("robot_file", robot_file::robot_file),
    ("cli_simulate", cli::cli_simulate),
    ("instrument", kin::instrument),
    ("module1", kin::module1),
    ("controller", kin::controller),
    ("trajectory", traj::trajectory),
    ("csv", writers::csv),
    ("mcap", writers::mcap),
    ("procedure_file", procedure::procedure_file),
    ("calibration_data", calibration::calibration_data),
    ("tolerance_spec", calibration::tolerance_spec),
    ("segment_distance", clearance::segment_distance),
];
