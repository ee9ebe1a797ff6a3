//! Clearance from the command line: the four columns of a run, the check's
//! per-motion table, and a robot file's clearance stop threshold failing a
//! run before it writes anything.

mod common;

use common::files::{demo, names};
use common::process::parasils;
use common::table::Table;

const ROBOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../robots/default.toml");

#[test]
fn a_run_has_the_four_clearance_columns_and_the_minimum_is_the_smallest() {
    let out = parasils(&["simulate", "--rate", "100", "-o", "-"])
        .run()
        .ok();
    let t = Table::parse(&out);
    let pairs = [
        t.col("clearance_left_right_mm"),
        t.col("clearance_left_endoscope_mm"),
        t.col("clearance_right_endoscope_mm"),
    ];
    let min = t.col("clearance_min_mm");
    for k in 0..t.rows() {
        let smallest = pairs[0][k].min(pairs[1][k]).min(pairs[2][k]);
        assert_eq!(min[k], smallest, "row {k}");
    }
    // The mirror right tip: the shafts' axes meet at the start (docs/model.md, *Clearance*).
    assert!((pairs[0][0] + 5.0).abs() < 1e-9, "{}", pairs[0][0]);
}

#[test]
fn the_check_prints_each_motions_smallest_gaps() {
    let stdout = parasils(&["simulate", "--procedure", &demo(), "--check"])
        .run()
        .ok();
    let at = stdout
        .find("clearance per motion, smallest sampled gap, mm: left_right left_endoscope right_endoscope\n")
        .expect("the clearance table");
    let rows: Vec<&str> = stdout[at..].lines().skip(1).take(6).collect();
    assert_eq!(
        rows[0].split_whitespace().collect::<Vec<_>>(),
        ["0", "-5.000", "1.287", "1.287"]
    );
    assert_eq!(
        rows[1].split_whitespace().collect::<Vec<_>>(),
        ["1", "-5.000", "-3.397", "-3.397"]
    );
    assert_eq!(rows[5].split_whitespace().next(), Some("5"));
}

#[test]
fn a_clearance_stop_fails_the_run_before_any_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let robot = dir.path().join("robot.toml");
    let text = std::fs::read_to_string(ROBOT).expect("robots/default.toml")
        + "\n[supervisor]\nclearance_stop_mm = 0.5\n";
    std::fs::write(&robot, text).expect("robot file");
    let line = parasils(&["simulate", "--robot", "robot.toml", "-o", "run.csv"])
        .dir(dir.path())
        .run()
        .error_line();
    assert!(
        line.contains("at t = 0.000 s: clearance left shaft - right shaft = -5.000 mm is below the stop threshold 0.5 mm"),
        "{line}"
    );
    assert_eq!(names(dir.path()), ["robot.toml"]);
}
