//! `parasils simulate` run as a process: its options (final angles, other
//! synchronisations, the user's start degrees, commands while turning), the
//! summary, a closed pipe, and every error path. The paper's run itself is
//! checked in `paper.rs`.

use std::path::Path;

mod common;

use common::files::names;
use common::process::parasils;
use common::table::Table;

/// The paper's run with its increments given, written to standard output.
fn paper_csv() -> Table {
    Table::parse(
        &parasils(&["simulate", "--psi", "15", "--theta", "25", "-o", "-"])
            .run()
            .ok(),
    )
}

#[test]
fn summary_without_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = parasils(&["simulate"]).dir(dir.path()).run().ok();
    assert!(text.contains("duration 4.500 s, 4501 samples"), "{text}");
    assert!(text.contains("ASSUMED"), "{text}");
    assert!(text.contains("largest tip drift"), "{text}");
    assert!(text.contains("q6"), "{text}");
    assert!(text.contains("smallest margins"), "{text}");
}

#[test]
fn absolute_angles_and_other_syncs() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&[
        "simulate",
        "--absolute",
        "--psi",
        "15",
        "--theta",
        "25",
        "--sync",
        "time",
        "-o",
        "-",
    ])
    .dir(dir.path())
    .run()
    .ok();
    let t = Table::parse(&out);
    let time = t.col("t_s");
    // psi -15 -> 15 deg is the longer axis: 30 deg at 10 deg/s, 5 deg/s^2 = 5 s.
    assert_eq!(*time.last().expect("rows"), 5.0);
    assert!((t.col("psi_deg").last().expect("rows") - 15.0).abs() < 1e-12);
    assert!((t.col("theta_deg").last().expect("rows") - 25.0).abs() < 1e-12);
}

/// Runs a failing command in an empty folder: non-zero exit, a one-line
/// message containing `needle`, and no file left behind.
fn fails_cleanly(args: &[&str], needle: &str, setup: impl FnOnce(&Path)) {
    let dir = tempfile::tempdir().expect("tempdir");
    setup(dir.path());
    let before = names(dir.path());
    let err = parasils(args).dir(dir.path()).run().fails();
    assert!(
        err.contains(needle),
        "{args:?}: message {err:?} lacks {needle:?}"
    );
    let after = names(dir.path());
    assert_eq!(before.len(), after.len(), "{args:?} left a file: {after:?}");
}

#[test]
fn bad_arguments() {
    fails_cleanly(
        &["simulate", "--pose", "1,2,3", "-o", "x.csv"],
        "expected 6",
        |_| {},
    );
    fails_cleanly(
        &["simulate", "--rate", "abc", "-o", "x.csv"],
        "invalid value",
        |_| {},
    );
    fails_cleanly(&["simulate", "--rate", "-5", "-o", "x.csv"], "rate", |_| {});
    fails_cleanly(
        &["simulate", "--omega-max", "0", "-o", "x.csv"],
        "trajectory",
        |_| {},
    );
    fails_cleanly(&["simulate", "-o", "x.txt"], "format", |_| {});
    fails_cleanly(
        &["simulate", "--tip-left", "1,nan,3", "-o", "x.csv"],
        "finite",
        |_| {},
    );
}

#[test]
fn unreadable_or_malformed_robot_file() {
    fails_cleanly(
        &["simulate", "--robot", "missing.toml", "-o", "x.csv"],
        "missing.toml",
        |_| {},
    );
    fails_cleanly(
        &["simulate", "--robot", "bad.toml", "-o", "x.csv"],
        "bad.toml",
        |d| std::fs::write(d.join("bad.toml"), "[module1\nlink = ").expect("write"),
    );
}

#[test]
fn unreachable_tip() {
    // Straight out sideways from the left port: beyond the linkage's cone.
    fails_cleanly(
        &["simulate", "--tip-left", "-400,0,-500", "-o", "x.csv"],
        "at t = 0.000 s: left instrument",
        |_| {},
    );
}

/// The default robot file with every actuator limit raised out of the way
/// (1e9 mm/s, deg/s and per s^2), written as `fast.toml` into `dir`, so that
/// the joint limits, strokes and singularities are what a run meets first.
fn unlimited_robot(dir: &Path) {
    let text = parasils(&["robot"]).dir(dir).run().ok();
    let raised: Vec<String> = text
        .lines()
        .map(|line| match line.split_once(" = ") {
            Some((key, _)) if key.contains("velocity_max") || key.contains("acceleration_max") => {
                format!("{key} = 1e9")
            }
            _ => line.to_owned(),
        })
        .collect();
    std::fs::write(dir.join("fast.toml"), raised.join("\n")).expect("write");
}

#[test]
fn trajectory_through_a_joint_limit() {
    // A larger reorientation drives the left module's qs1 faster than its
    // assumed 30 deg/s at 4.336 s ...
    fails_cleanly(
        &["simulate", "--psi", "40", "--theta", "25", "-o", "x.mcap"],
        "error: at t = 4.336 s: left qs1: velocity -30.0074 deg/s is beyond its limit 30 deg/s\n",
        |_| {},
    );
    // ... and, without actuator limits, its qs2 past -80 deg at 4.444 s.
    fails_cleanly(
        &[
            "simulate",
            "--psi",
            "40",
            "--theta",
            "25",
            "--robot",
            "fast.toml",
            "-o",
            "x.mcap",
        ],
        "error: at t = 4.444 s: left instrument: joint qs2 = -80.0079 deg is outside [-80, 80] deg\n",
        unlimited_robot,
    );
    fails_cleanly(
        &[
            "simulate",
            "--psi",
            "40",
            "--theta",
            "25",
            "--robot",
            "fast.toml",
            "-o",
            "x.csv",
            "--plot",
            "p.svg",
        ],
        "at t = 4.444 s",
        unlimited_robot,
    );
    // Module 1 (assumed geometry) crosses a parallel singularity near
    // theta = 49.7 deg.
    fails_cleanly(
        &[
            "simulate",
            "--psi",
            "0",
            "--theta",
            "60",
            "--robot",
            "fast.toml",
            "-o",
            "x.csv",
        ],
        "at t = 4.927 s: module 1: parallel singularity: margin 0.0099445 is below 0.01",
        unlimited_robot,
    );
    // Module 1 runs out of stroke.
    fails_cleanly(
        &[
            "simulate",
            "--psi",
            "-60",
            "--theta",
            "0",
            "--robot",
            "fast.toml",
            "-o",
            "x.csv",
        ],
        "at t = 6.391 s: module 1: actuator q4 = 320.084 mm is outside [0, 320] mm",
        unlimited_robot,
    );
}

#[test]
fn the_csv_starts_on_the_user_s_degrees() {
    let t = paper_csv();
    assert_eq!(t.col("psi_deg")[0], -15.0);
    assert_eq!(t.col("theta_deg")[0], 10.0);
    // phi does not move: the user's -60 on every row, not -59.99999999999999.
    assert!(t.col("phi_deg").iter().all(|phi| *phi == -60.0));
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&[
        "simulate",
        "--pose",
        "15,20,-500,-14.3,10.56,-57.89",
        "--psi",
        "1",
        "--theta",
        "1",
        "--rate",
        "10",
        "-o",
        "-",
    ])
    .dir(dir.path())
    .run()
    .ok();
    let t = Table::parse(&out);
    assert_eq!(
        [
            t.col("psi_deg")[0],
            t.col("theta_deg")[0],
            t.col("phi_deg")[0]
        ],
        [-14.3, 10.56, -57.89]
    );
    assert!(t.col("phi_deg").iter().all(|phi| *phi == -57.89));
}

#[test]
fn a_closed_pipe_ends_the_run_quietly() {
    use std::io::Read;

    let mut child = parasils(&["simulate", "-o", "-"]).spawn();
    // Read the header only, then close the pipe, as `| head -1` does (the
    // whole CSV, 4 MB, is far more than the pipe holds).
    let mut first = [0u8; 64];
    child
        .take_stdout()
        .read_exact(&mut first)
        .expect("a header");
    assert!(first.starts_with(b"t_s,x_mm"));
    let out = child.finish();
    assert!(out.status.success(), "{:?}", out.status);
    assert_eq!(out.stderr(), "");
}

#[test]
fn messages_write_huge_numbers_with_an_exponent() {
    let dir = tempfile::tempdir().expect("tempdir");
    // One sample per 1e300 s: the summary's times are huge (the 4.5 s turn
    // is stretched to one whole period).
    let text = parasils(&["simulate", "--rate", "1e-300"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(
        text.starts_with(
            "duration 1.000e300 s, 2 samples (0.000 to 1.000e300 s); the law's 4.5000 s stretched to whole periods\n"
        ),
        "{text}"
    );
    assert!(text.lines().all(|l| l.len() < 200), "{text}");
    // A turn of 1e305 deg at 10 deg/s. (At 1e308 deg theta's share of it,
    // 25 deg, would scale its limits to subnormal numbers: refused as out
    // of range before any sampling.)
    fails_cleanly(
        &["simulate", "--psi", "1e305", "-o", "x.csv"],
        "error: trajectory: sampling 1e304 s at 1000 Hz needs more samples than usize can count\n",
        |_| {},
    );
    fails_cleanly(
        &["simulate", "--psi", "1e308", "-o", "x.csv"],
        "error: trajectory: axis 1: the profile over distance 0.436332 does not fit the float type",
        |_| {},
    );
}

#[test]
fn an_unwritable_folder_is_named_once() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = parasils(&["simulate", "-o", "missing/run.csv"])
        .dir(dir.path())
        .run()
        .fails();
    assert_eq!(
        err,
        "parasils: error: cannot write in missing: No such file or directory (os error 2)\n"
    );
}

/// The acceptance run's flags: the paper's reorientation, a new goal at
/// 1.2 s while turning, a stop at 3 s while turning, a last goal at 3.5 s
/// while stopping.
const COMMANDS: &[&str] = &[
    "--retarget",
    "1.2:25,15",
    "--stop-at",
    "3",
    "--retarget",
    "3.5:5,30",
];

#[test]
fn retargets_and_a_stop() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&[&["simulate"], COMMANDS, &["-o", "-"]].concat())
        .dir(dir.path())
        .run()
        .ok();
    let t = Table::parse(&out);
    assert_eq!(t.header().len(), 75);
    assert_eq!(t.header().last().map(String::as_str), Some("command"));
    // The index as an integer, grown by one at each command's sample.
    assert_eq!(t.text("command")[0], "0");
    let (time, command) = (t.col("t_s"), t.col("command"));
    for (k, c) in command.iter().enumerate() {
        let want = [1.2, 3.0, 3.5].iter().filter(|s| time[k] >= **s).count();
        assert_eq!(*c, want as f64, "at {}", time[k]);
    }
    // Continuous at every command, within the limits (10 deg/s, 5 deg/s^2,
    // 1 ms), the tips still.
    for axis in ["psi", "theta"] {
        let (angle, rate) = (
            t.col(&format!("{axis}_deg")),
            t.col(&format!("{axis}_rate_deg_s")),
        );
        for k in [1200, 3000, 3500] {
            assert!((angle[k] - angle[k - 1]).abs() <= 0.01 * (1.0 + 1e-9));
            assert!((rate[k] - rate[k - 1]).abs() <= 0.005 * (1.0 + 1e-9));
        }
        let acc = t.col(&format!("{axis}_acc_deg_s2"));
        assert!(acc.iter().all(|a| a.abs() <= 5.0 * (1.0 + 1e-9)));
    }
    for side in ["left", "right"] {
        let worst = t
            .col(&format!("{side}_tip_err_mm"))
            .into_iter()
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{side} drift {worst} mm");
    }
    // At rest on the last goal: psi -15 + 5, theta 10 + 30.
    assert!((t.col("psi_deg").last().expect("rows") + 10.0).abs() < 1e-9);
    assert!((t.col("theta_deg").last().expect("rows") - 40.0).abs() < 1e-9);

    // The summary lists the commands; the MCAP file is written.
    let summary = parasils(&[&["simulate"], COMMANDS].concat())
        .dir(dir.path())
        .run()
        .ok();
    assert!(summary.contains("\ncommands (each active"), "{summary}");
    assert!(
        summary.contains("  3   retarget        at    3.500 s, active from    3.500 s: psi +5.0000, theta +30.0000 deg\n"),
        "{summary}"
    );
    let out = parasils(&[&["simulate"], COMMANDS, &["-o", "run.mcap"]].concat())
        .dir(dir.path())
        .run();
    let stderr = out.stderr();
    out.ok();
    assert_eq!(
        stderr,
        "parasils: wrote 8895 samples (8.894 s) to run.mcap\n"
    );
}

#[test]
fn retargets_read_like_psi_and_theta() {
    // With --absolute, the retarget's angles are final ones too.
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&[
        "simulate",
        "--absolute",
        "--psi",
        "0",
        "--theta",
        "30",
        "--retarget",
        "1:-10,20",
        "--rate",
        "100",
        "-o",
        "-",
    ])
    .dir(dir.path())
    .run()
    .ok();
    let t = Table::parse(&out);
    assert!((t.col("psi_deg").last().expect("rows") + 10.0).abs() < 1e-9);
    assert!((t.col("theta_deg").last().expect("rows") - 20.0).abs() < 1e-9);
    assert_eq!(t.col("command").last(), Some(&1.0));
}

#[test]
fn bad_commands() {
    for (args, needle) in [
        (&["--retarget", "1.2"][..], "expected T:PSI,THETA"),
        (
            &["--retarget", "1.2:5"],
            "expected 2 comma-separated numbers",
        ),
        (&["--retarget", "x:5,6"], "`x` is not a number"),
        (&["--retarget", "1:nan,2"], "`nan` is not a finite number"),
        (&["--stop-at", "inf"], "`inf` is not a finite number"),
        (&["--stop-at", "soon"], "`soon` is not a number"),
        (
            &["--retarget", "-1:5,6"],
            "error: commands: retarget 1: t = -1 s is before the start (t = 0)\n",
        ),
        (
            &["--retarget", "2:5,6", "--retarget", "1:5,6"],
            "error: commands: retarget 2 at t = 1 s comes before retarget 1 at t = 2 s: give the retargets in time order\n",
        ),
        (
            &["--stop-at", "2", "--retarget", "2:5,6"],
            "error: commands: retarget 1 at t = 2 s takes effect at the same sample as the stop at t = 2 s (t = 2 s at 1000 Hz): give each command a sample of its own\n",
        ),
        (
            &[
                "--retarget",
                "0.51:5,6",
                "--retarget",
                "0.55:5,6",
                "--rate",
                "10",
            ],
            "retarget 2 at t = 0.55 s takes effect at the same sample as retarget 1 at t = 0.51 s (t = 0.6 s at 10 Hz)",
        ),
    ] {
        for output in ["x.csv", "x.mcap"] {
            fails_cleanly(
                &[&["simulate"], args, &["-o", output]].concat(),
                needle,
                |_| {},
            );
        }
    }
    // One line each.
    let dir = tempfile::tempdir().expect("tempdir");
    let err = parasils(&["simulate", "--stop-at", "-2"])
        .dir(dir.path())
        .run()
        .fails();
    assert_eq!(
        err,
        "parasils: error: commands: the stop: t = -2 s is before the start (t = 0)\n"
    );
}

#[test]
fn the_supervisor_stops_where_the_plain_run_fails() {
    // Without commands this turn fails at module 1's parallel singularity
    // (`trajectory_through_a_joint_limit` above); with a command it runs
    // through the online controller, whose supervisor stops the platform.
    let dir = tempfile::tempdir().expect("tempdir");
    let text = parasils(&[
        "simulate",
        "--psi",
        "0",
        "--theta",
        "60",
        "--stop-at",
        "10",
        "--rate",
        "100",
    ])
    .dir(dir.path())
    .run()
    .ok();
    assert!(text.contains("  1   supervisor_stop demanded,"), "{text}");
    assert!(text.contains("supervisor warnings on "), "{text}");
}
