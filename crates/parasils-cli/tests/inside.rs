//! `parasils simulate --procedure`: the paper's rules while anything is
//! inside the patient, refused by `--check` and by a run before any output,
//! and the shipped example that goes out and back in.

mod common;

use std::path::PathBuf;

use common::files::{demo, names, s};
use common::process::parasils;

/// The issue's procedure: the platform over the port, the endoscope in,
/// then a positioning to `last_pose` (x, y, z mm; psi, theta, phi deg).
fn issue(last_pose: &str) -> String {
    format!(
        r#"pose = [5, 10, -455, -10, 5, -55]
tip_left_mm = [32.0, -18.5, -518.0]
endoscope_depth_mm = 0

[[motion]]
type = "position"
pose = [15, 20, -500, -15, 10, -60]

[[motion]]
type = "insert"
instrument = "endoscope"
depth_mm = 60

[[motion]]
type = "position"
pose = {last_pose}
"#
    )
}

fn retract_reposition() -> String {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "procedures",
        "retract-reposition.toml",
    ]
    .iter()
    .collect();
    path.to_string_lossy().into_owned()
}

/// `--check` and a run of the procedure `text` both fail with one line
/// that contains each of `want`, and leave the folder as they found it.
fn refused(text: &str, want: &[&str]) {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("issue.toml");
    std::fs::write(&file, text).expect("write the procedure");
    for extra in [&["--check"][..], &["-o", "out.csv"], &["-o", "out.mcap"]] {
        let err = parasils(&["simulate", "--procedure", s(&file)])
            .args(extra)
            .dir(dir.path())
            .run()
            .error_line();
        for w in want {
            assert!(err.contains(w), "{extra:?}: {w:?} not in {err}");
        }
        assert_eq!(names(dir.path()), ["issue.toml"], "{extra:?}");
    }
}

#[test]
fn the_issues_turn_about_the_endoscopes_axis_fails_naming_motion_2() {
    refused(
        &issue("[15, 20, -500, -15, 10, -30]"),
        &[
            "motion 2 (position): turns about the endoscope's axis while the endoscope is inside",
            // phi from -60 to -30 deg.
            "phi would turn by 30.000 deg",
        ],
    );
}

#[test]
fn moving_only_x_with_the_endoscope_inside_fails_on_the_incision_point() {
    refused(
        &issue("[25, 20, -500, -15, 10, -60]"),
        &[
            "motion 2 (position): moves the incision point while the endoscope is inside",
            // x from 15 to 25 mm.
            "P would leave the incision point by 10.000 mm",
        ],
    );
}

#[test]
fn the_same_moves_before_the_insertion_pass() {
    // With the endoscope still out, the turn and the move are type 1's to
    // make: the procedure without its insertion passes.
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("out.toml");
    let text = issue("[25, 20, -500, -15, 10, -30]").replace("depth_mm = 60", "depth_mm = 0");
    std::fs::write(&file, text).expect("write the procedure");
    let stdout = parasils(&["simulate", "--procedure", s(&file), "--check"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(stdout.starts_with("procedure OK: 3 motions"), "{stdout}");
}

/// The `inside` column of each motion's row in a `--check` table.
fn states(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .filter(|l| l.contains(':') && l.trim_start().starts_with(char::is_numeric))
        .map(
            |l| match l.find(" outside").or_else(|| l.find(" inside:")) {
                Some(k) => l[k + 1..].to_string(),
                None => String::from("?"),
            },
        )
        .collect()
}

#[test]
fn retract_reposition_passes_check_and_its_table_shows_each_motions_state() {
    let dir = tempfile::tempdir().expect("tempdir");
    let stdout = parasils(&["simulate", "--procedure", &retract_reposition(), "--check"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(stdout.starts_with("procedure OK: 8 motions"), "{stdout}");
    assert!(
        stdout
            .lines()
            .nth(2)
            .is_some_and(|l| l.ends_with(" inside"))
    );
    assert_eq!(
        states(&stdout),
        [
            "outside",
            "outside",
            "inside: endoscope",
            "inside: endoscope, left",
            "inside: endoscope, left",
            "inside: endoscope",
            "outside",
            "outside"
        ],
        "{stdout}"
    );
    assert!(names(dir.path()).is_empty());
}

#[test]
fn the_demo_keeps_to_the_rules() {
    let stdout = parasils(&["simulate", "--procedure", &demo(), "--check"])
        .run()
        .ok();
    assert_eq!(
        states(&stdout),
        [
            "outside",
            "outside",
            "inside: endoscope",
            "inside: endoscope",
            "inside: endoscope",
            "inside: endoscope"
        ],
        "{stdout}"
    );
}
