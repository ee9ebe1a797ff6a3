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
    let out = parasils(&[
        "simulate",
        "--rate",
        "100",
        "--tip-right",
        "mirror",
        "-o",
        "-",
    ])
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
    // The default right tip clears the left shaft by 6.932 mm at the start.
    let out = parasils(&["simulate", "--rate", "100", "-o", "-"])
        .run()
        .ok();
    let t = Table::parse(&out);
    assert!((t.col("clearance_left_right_mm")[0] - 6.932).abs() < 5e-4);
}

#[test]
fn the_check_prints_each_motions_smallest_and_certified_gaps_and_ports() {
    let stdout = parasils(&["simulate", "--procedure", &demo(), "--check"])
        .run()
        .ok();
    let at = stdout
        .find("clearance per motion, mm, smallest sampled gap / certified minimum between samples: left_right left_endoscope right_endoscope\n")
        .expect("the clearance table");
    let rows: Vec<Vec<&str>> = stdout[at..]
        .lines()
        .skip(1)
        .take(6)
        .map(|l| l.split_whitespace().collect())
        .collect();
    // docs/model.md, *Clearance*: motion 0 starts as the paper's run does
    // (6.932, 1.287, 2.315 mm), the left shaft meets the endoscope once it
    // is in (-3.397 mm); each certified minimum at most 1e-3 mm lower.
    let number = |s: &str| s.parse::<f64>().expect("a number");
    for (row, sampled) in [(0, [6.932, 1.287, 2.315]), (1, [6.932, -3.397, 2.155])] {
        assert_eq!(rows[row][0], row.to_string());
        for pair in 0..3 {
            let (s, slash, c) = (
                rows[row][1 + 3 * pair],
                rows[row][2 + 3 * pair],
                rows[row][3 + 3 * pair],
            );
            assert_eq!((number(s), slash), (sampled[pair], "/"), "{:?}", rows[row]);
            assert!(
                number(c) <= number(s) && number(c) >= number(s) - 2e-3,
                "{:?}",
                rows[row]
            );
        }
    }
    assert_eq!(rows[5][0], "5");
    let at = stdout
        .find("ports per motion, largest displacement from the motion's start, mm: left right endoscope\n")
        .expect("the ports table");
    let first: Vec<&str> = stdout[at..]
        .lines()
        .nth(1)
        .expect("motion 0")
        .split_whitespace()
        .collect();
    // Motion 0 lowers the platform 40 mm without turning.
    assert_eq!(first, ["0", "40.000", "40.000", "40.000"]);
}

#[test]
fn a_clearance_stop_fails_the_run_before_any_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let robot = dir.path().join("robot.toml");
    let text = std::fs::read_to_string(ROBOT).expect("robots/default.toml")
        + "\n[supervisor]\nclearance_stop_mm = 0.5\n";
    std::fs::write(&robot, text).expect("robot file");
    let line = parasils(&[
        "simulate",
        "--robot",
        "robot.toml",
        "--tip-right",
        "mirror",
        "-o",
        "run.csv",
    ])
    .dir(dir.path())
    .run()
    .error_line();
    assert!(
        line.contains("at t = 0.000 s: clearance left shaft - right shaft = -5.000 mm is below the stop threshold 0.5 mm"),
        "{line}"
    );
    assert_eq!(names(dir.path()), ["robot.toml"]);
}
