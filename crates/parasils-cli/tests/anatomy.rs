//! Forbidden regions from the command line: the shipped example anatomy
//! cleared by the demo procedure (its check's per-region table), a run that
//! enters a region failing with one line and no output file, and a bad
//! anatomy file refused naming the file, the region and the key.

mod common;

use std::path::{Path, PathBuf};

use common::files::{demo, names};
use common::process::parasils;

/// The shipped example anatomy, `procedures/anatomy/demo.toml`.
fn example() -> String {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "procedures",
        "anatomy",
        "demo.toml",
    ]
    .iter()
    .collect();
    path.to_string_lossy().into_owned()
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).expect("write");
}

#[test]
fn the_demo_clears_the_shipped_anatomy_and_the_check_prints_each_region() {
    let stdout = parasils(&[
        "simulate",
        "--procedure",
        &demo(),
        "--anatomy",
        &example(),
        "--check",
    ])
    .run()
    .ok();
    let header = "no-go clearance per motion, smallest sampled gap / certified minimum between samples to each forbidden region, mm: organ vessel kidney spine\n";
    let at = stdout.find(header).expect("the no-go table");
    let rows: Vec<Vec<&str>> = stdout[at + header.len()..]
        .lines()
        .take(6)
        .map(|l| l.split_whitespace().collect())
        .collect();
    for (k, row) in rows.iter().enumerate() {
        // The motion, then `sampled / certified` per region.
        assert_eq!(row.len(), 13, "{row:?}");
        assert_eq!(row[0], k.to_string());
        for cell in row[1..].chunks(3) {
            assert_eq!(cell[1], "/", "{row:?}");
            let sampled: f64 = cell[0].parse().expect("a number");
            let certified: f64 = cell[2].parse().expect("a number");
            // Every region well clear of the stop threshold (0.5 mm), the
            // certificate never above the samples.
            assert!(
                certified > 10.0 && certified <= sampled,
                "motion {k}: {row:?}"
            );
        }
    }
}

#[test]
fn a_run_that_enters_a_region_fails_with_one_line_and_leaves_no_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A ball of 5 mm around the demo's third motion's left tip goal: the
    // shaft's tip reaches it in "left tip to the tissue".
    write(
        dir.path(),
        "lesion.toml",
        "[[region]]\nname = \"lesion\"\nshape = \"sphere\"\ncentre_mm = [60, -40, -630]\nradius_mm = 5\n",
    );
    let line = parasils(&[
        "simulate",
        "--procedure",
        &demo(),
        "--anatomy",
        "lesion.toml",
        "-o",
        "run.csv",
    ])
    .dir(dir.path())
    .run()
    .error_line();
    assert!(line.contains("motion 2"), "{line}");
    assert!(line.contains("left tip to the tissue"), "{line}");
    let (_, rest) = line.split_once("left shaft is ").expect("the body");
    let (gap, rest) = rest.split_once(" mm").expect("the gap");
    assert_eq!(
        rest, " from the forbidden region \"lesion\", below the stop threshold 0.5 mm\n",
        "{line}"
    );
    // The first sample below 0.5 mm: the tip moves at most 10 mm/s, 0.01
    // mm a sample at 1 kHz.
    let gap: f64 = gap.parse().expect("a number");
    assert!((0.489..0.5).contains(&gap), "{line}");
    assert_eq!(names(dir.path()), ["lesion.toml"]);
}

#[test]
fn the_paper_s_turn_into_a_region_fails_before_any_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    // A ball whose surface is 2 mm from the paper's left tip (50, -50, -620):
    // the shaft's surface (2.5 mm radius) is inside it from the start.
    write(
        dir.path(),
        "ball.toml",
        "[[region]]\nname = \"ball\"\nshape = \"sphere\"\ncentre_mm = [50, -50, -630]\nradius_mm = 8\n",
    );
    let ran = parasils(&["simulate", "--anatomy", "ball.toml", "-o", "-"])
        .dir(dir.path())
        .run();
    assert!(ran.stdout.is_empty(), "{} bytes written", ran.stdout.len());
    let line = ran.error_line();
    assert!(
        line.contains("at t = 0.000 s: left shaft is -0.500 mm from the forbidden region \"ball\""),
        "{line}"
    );
    let out = parasils(&["simulate", "--anatomy", "ball.toml", "-o", "run.csv"])
        .dir(dir.path())
        .run();
    out.fails();
    assert_eq!(names(dir.path()), ["ball.toml"]);
}

#[test]
fn a_bad_anatomy_file_is_refused_naming_the_file_the_region_and_the_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(
        dir.path(),
        "bad.toml",
        "[[region]]\nname = \"kidney\"\nshape = \"sphere\"\ncentre_mm = [0, 0, 0]\nradius_mm = -2\n",
    );
    let line = parasils(&["simulate", "--anatomy", "bad.toml", "-o", "run.csv"])
        .dir(dir.path())
        .run()
        .error_line();
    assert!(
        line.contains("anatomy file bad.toml: region kidney: radius_mm: -2 must be positive"),
        "{line}"
    );
    assert_eq!(names(dir.path()), ["bad.toml"]);
}

#[test]
fn the_reach_map_names_the_region_that_limits_a_cell() {
    let dir = tempfile::tempdir().expect("tempdir");
    // The ball of the test above, around the paper's left tip, which the
    // map holds still: every cell the kinematics allow is limited by it.
    write(
        dir.path(),
        "ball.toml",
        "[[region]]\nname = \"ball\"\nshape = \"sphere\"\ncentre_mm = [50, -50, -630]\nradius_mm = 8\n",
    );
    let grid = [
        "reach",
        "--step",
        "5",
        "--psi-range",
        "-10,20",
        "--theta-range",
        "-10,30",
        "--no-line",
        "-o",
        "-",
    ];
    let with = parasils(&[&grid[..], &["--anatomy", "ball.toml"]].concat())
        .dir(dir.path())
        .run()
        .ok();
    let without = parasils(&grid).dir(dir.path()).run().ok();
    let limiting = |text: &str| -> Vec<String> {
        text.lines()
            .skip(1)
            .map(|l| l.split(',').nth(7).expect("limiting").to_owned())
            .collect()
    };
    let (with, without) = (limiting(&with), limiting(&without));
    assert_eq!(with.len(), 7 * 9);
    let mut limited = 0;
    for (a, b) in with.iter().zip(&without) {
        if b == "ok" {
            assert_eq!(a, "no_go.ball");
            limited += 1;
        } else {
            assert_eq!(a, b);
        }
    }
    assert!(limited > 10, "{limited}");
    // The summary names it too.
    let summary = parasils(&["reach", "--step", "5", "--anatomy", "ball.toml"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(
        summary.contains("the start itself is infeasible: no_go.ball"),
        "{summary}"
    );
}
