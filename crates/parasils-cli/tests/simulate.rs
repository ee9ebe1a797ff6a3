//! `parasils simulate` run as a process: the paper's scenario, the CSV
//! contract, and every error path.

use std::path::Path;
use std::process::{Command, Output};

fn parasils(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_parasils"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

struct Table {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Table {
    fn parse(text: &str) -> Table {
        let mut lines = text.lines();
        let header = lines
            .next()
            .expect("a header")
            .split(',')
            .map(str::to_owned)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().expect("a float"))
                    .collect()
            })
            .collect();
        Table { header, rows }
    }

    fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

fn paper_csv() -> Table {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(
        &["simulate", "--psi", "15", "--theta", "25", "-o", "-"],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Table::parse(&String::from_utf8(out.stdout).expect("utf8"))
}

const REQUIRED: &[&str] = &[
    "t_s",
    "x_mm",
    "y_mm",
    "z_mm",
    "psi_deg",
    "theta_deg",
    "phi_deg",
    "psi_rate_deg_s",
    "theta_rate_deg_s",
    "psi_acc_deg_s2",
    "theta_acc_deg_s2",
    "module1_serial_margin",
    "module1_parallel_margin",
];

#[test]
fn the_paper_scenario() {
    let t = paper_csv();
    for c in REQUIRED {
        assert!(t.header.iter().any(|h| h == c), "missing {c}");
    }
    for j in 1..=6 {
        for c in [
            format!("q{j}_mm"),
            format!("q{j}_rate_mm_s"),
            format!("q{j}_acc_mm_s2"),
        ] {
            assert!(t.header.contains(&c), "missing {c}");
        }
    }
    for side in ["left", "right"] {
        for c in [
            "qs1_deg",
            "qs2_deg",
            "qs3_mm",
            "qs1_rate_deg_s",
            "qs2_rate_deg_s",
            "qs3_rate_mm_s",
            "qs1_acc_deg_s2",
            "qs2_acc_deg_s2",
            "qs3_acc_mm_s2",
            "cos_qs2",
            "tip_err_mm",
        ] {
            assert!(
                t.header.contains(&format!("{side}_{c}")),
                "missing {side}_{c}"
            );
        }
    }
    // 4501 samples over 4.5 s.
    let time = t.col("t_s");
    assert_eq!(time.len(), 4501);
    assert_eq!(time[0], 0.0);
    assert_eq!(time[4500], 4.5);
    // The tips do not drift.
    for side in ["left", "right"] {
        let worst = t
            .col(&format!("{side}_tip_err_mm"))
            .into_iter()
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{side} drift {worst} mm");
    }
    // Platform: psi -15 -> 0, theta 10 -> 35 deg.
    let (psi, theta) = (t.col("psi_deg"), t.col("theta_deg"));
    assert!((psi[0] + 15.0).abs() < 1e-12 && psi[4500].abs() < 1e-12);
    assert!((theta[0] - 10.0).abs() < 1e-12 && (theta[4500] - 35.0).abs() < 1e-12);
    // The paper's joints at the start and the end (docs/model.md, *Check
    // values*).
    let check = |side: &str, k: usize, want: [f64; 3]| {
        let got = [
            t.col(&format!("{side}_qs1_deg"))[k],
            t.col(&format!("{side}_qs2_deg"))[k],
            t.col(&format!("{side}_qs3_mm"))[k],
        ];
        for i in 0..3 {
            assert!(
                (got[i] - want[i]).abs() < 5e-5,
                "{side} at {k}: {got:?} vs {want:?}"
            );
        }
    };
    check("left", 0, [3.0889, -38.8695, 147.7687]);
    check("right", 0, [3.0889, -38.8695, 147.7687]);
    check("left", 4500, [20.7942, -61.8435, 151.0378]);
    check("right", 4500, [18.5977, -13.0799, 143.6301]);
    // Module 1 at P0 (docs/model.md, *Check values*; assumed geometry).
    let p0 = [117.942, 151.459, 56.937, 89.428, 132.193, 77.441];
    for (j, want) in p0.iter().enumerate() {
        let got = t.col(&format!("q{}_mm", j + 1))[0];
        assert!((got - want).abs() < 5e-4, "q{} = {got}", j + 1);
    }
}

/// Central differences of `pos` at every sample more than 2 ms from a switch
/// of the profile (0, 2, 2.5 and 4.5 s for the paper's theta axis, which
/// psi's phase-synchronised profile shares) against `rate`.
fn worst_fd_error(time: &[f64], pos: &[f64], rate: &[f64]) -> f64 {
    let switches = [0.0, 2.0, 2.5, 4.5];
    let mut worst = 0.0f64;
    for k in 1..time.len() - 1 {
        if switches.iter().any(|s| (time[k] - s).abs() <= 0.002 + 1e-9) {
            continue;
        }
        let fd = (pos[k + 1] - pos[k - 1]) / (time[k + 1] - time[k - 1]);
        worst = worst.max((fd - rate[k]).abs());
    }
    worst
}

#[test]
fn rates_and_accelerations_match_finite_differences() {
    let t = paper_csv();
    let time = t.col("t_s");
    let mut pairs: Vec<(String, String, String)> = vec![
        (
            "psi_deg".into(),
            "psi_rate_deg_s".into(),
            "psi_acc_deg_s2".into(),
        ),
        (
            "theta_deg".into(),
            "theta_rate_deg_s".into(),
            "theta_acc_deg_s2".into(),
        ),
    ];
    for j in 1..=6 {
        pairs.push((
            format!("q{j}_mm"),
            format!("q{j}_rate_mm_s"),
            format!("q{j}_acc_mm_s2"),
        ));
    }
    for side in ["left", "right"] {
        for (q, u) in [("qs1", "deg"), ("qs2", "deg"), ("qs3", "mm")] {
            pairs.push((
                format!("{side}_{q}_{u}"),
                format!("{side}_{q}_rate_{u}_s"),
                format!("{side}_{q}_acc_{u}_s2"),
            ));
        }
    }
    for (p, r, a) in &pairs {
        let (pos, rate, acc) = (t.col(p), t.col(r), t.col(a));
        let e_rate = worst_fd_error(&time, &pos, &rate);
        let e_acc = worst_fd_error(&time, &rate, &acc);
        assert!(e_rate < 1e-4, "{r}: {e_rate}");
        assert!(e_acc < 1e-4, "{a}: {e_acc}");
    }
}

#[test]
fn same_inputs_give_byte_identical_csv() {
    let dir = tempfile::tempdir().expect("tempdir");
    let a = parasils(&["simulate", "-o", "a.csv"], dir.path());
    let b = parasils(
        &["simulate", "--psi", "15", "--theta", "25", "-o", "b.csv"],
        dir.path(),
    );
    assert!(a.status.success() && b.status.success());
    let a = std::fs::read(dir.path().join("a.csv")).expect("a.csv");
    let b = std::fs::read(dir.path().join("b.csv")).expect("b.csv");
    assert!(a.len() > 1000);
    assert!(a == b, "the two runs differ");
}

#[test]
fn summary_without_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&["simulate"], dir.path());
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).expect("utf8");
    assert!(text.contains("duration 4.500 s, 4501 samples"), "{text}");
    assert!(text.contains("ASSUMED"), "{text}");
    assert!(text.contains("largest tip drift"), "{text}");
    assert!(text.contains("q6"), "{text}");
    assert!(text.contains("smallest margins"), "{text}");
}

#[test]
fn absolute_angles_and_other_syncs() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(
        &[
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
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let t = Table::parse(&String::from_utf8(out.stdout).expect("utf8"));
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
    let before: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").collect();
    let out = parasils(args, dir.path());
    assert!(!out.status.success(), "{args:?} succeeded");
    let err = String::from_utf8(out.stderr).expect("utf8");
    assert!(
        err.contains(needle),
        "{args:?}: message {err:?} lacks {needle:?}"
    );
    let after: Vec<_> = std::fs::read_dir(dir.path()).expect("dir").collect();
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
    let out = parasils(&["robot"], dir);
    let text = String::from_utf8(out.stdout).expect("utf8");
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
    let out = parasils(
        &[
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
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let t = Table::parse(&String::from_utf8(out.stdout).expect("utf8"));
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
    use std::process::Stdio;

    let dir = tempfile::tempdir().expect("tempdir");
    let mut child = Command::new(env!("CARGO_BIN_EXE_parasils"))
        .args(["simulate", "-o", "-"])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // Read the header only, then close the pipe, as `| head -1` does (the
    // whole CSV, 4 MB, is far more than the pipe holds).
    let mut first = [0u8; 64];
    child
        .stdout
        .take()
        .expect("stdout")
        .read_exact(&mut first)
        .expect("a header");
    assert!(first.starts_with(b"t_s,x_mm"));
    let out = child.wait_with_output().expect("ends");
    assert!(out.status.success(), "{:?}", out.status);
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}

#[test]
fn messages_write_huge_numbers_with_an_exponent() {
    let dir = tempfile::tempdir().expect("tempdir");
    // One sample per 1e300 s: the summary's times are huge (the 4.5 s turn
    // is stretched to one whole period).
    let out = parasils(&["simulate", "--rate", "1e-300"], dir.path());
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).expect("utf8");
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
    let out = parasils(&["simulate", "-o", "missing/run.csv"], dir.path());
    assert!(!out.status.success());
    assert_eq!(
        String::from_utf8(out.stderr).expect("utf8"),
        "parasils: error: cannot write in missing: No such file or directory (os error 2)\n"
    );
}

/// FNV-1a, 64 bits: a digest of a file, to compare it with a recorded one.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The paper's CSV is the one `parasils simulate -o paper.csv` wrote before
/// commands existed, byte for byte: its 53 columns, no `command`, every
/// number to the last bit. The digest is of that file on Linux x86-64 (other
/// platforms' maths libraries may round some functions differently). A
/// change that means to alter the paper's numbers updates it, and says so.
#[test]
fn the_paper_csv_is_unchanged_byte_for_byte() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&["simulate", "-o", "paper.csv"], dir.path());
    assert!(out.status.success());
    let bytes = std::fs::read(dir.path().join("paper.csv")).expect("paper.csv");
    let header = bytes.split(|b| *b == b'\n').next().expect("a header");
    assert_eq!(header.split(|b| *b == b',').count(), 53);
    assert!(!header.windows(7).any(|w| w == b"command"));
    assert_eq!(bytes.len(), 4_003_152);
    if cfg!(all(target_os = "linux", target_arch = "x86_64")) {
        assert_eq!(
            fnv1a(&bytes),
            0x3140_e691_69d4_96cf,
            "the paper's CSV changed"
        );
    }
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
    let out = parasils(
        &[&["simulate"], COMMANDS, &["-o", "-"]].concat(),
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("utf8");
    let t = Table::parse(&text);
    assert_eq!(t.header.len(), 54);
    assert_eq!(t.header.last().map(String::as_str), Some("command"));
    // The index as an integer, grown by one at each command's sample.
    assert!(text.lines().nth(1).is_some_and(|r| r.ends_with(",0")));
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
    let out = parasils(&[&["simulate"], COMMANDS].concat(), dir.path());
    let summary = String::from_utf8(out.stdout).expect("utf8");
    assert!(summary.contains("\ncommands (each active"), "{summary}");
    assert!(
        summary.contains("  3   retarget        at    3.500 s, active from    3.500 s: psi +5.0000, theta +30.0000 deg\n"),
        "{summary}"
    );
    let out = parasils(
        &[&["simulate"], COMMANDS, &["-o", "run.mcap"]].concat(),
        dir.path(),
    );
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "parasils: wrote 8895 samples (8.894 s) to run.mcap\n"
    );
}

#[test]
fn retargets_read_like_psi_and_theta() {
    // With --absolute, the retarget's angles are final ones too.
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(
        &[
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
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let t = Table::parse(&String::from_utf8(out.stdout).expect("utf8"));
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
    let out = parasils(&["simulate", "--stop-at", "-2"], dir.path());
    assert!(!out.status.success());
    assert_eq!(
        String::from_utf8(out.stderr).expect("utf8"),
        "parasils: error: commands: the stop: t = -2 s is before the start (t = 0)\n"
    );
}

#[test]
fn the_supervisor_stops_where_the_plain_run_fails() {
    // Without commands this turn fails at module 1's parallel singularity
    // (`trajectory_through_a_joint_limit` above); with a command it runs
    // through the online controller, whose supervisor stops the platform.
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(
        &[
            "simulate",
            "--psi",
            "0",
            "--theta",
            "60",
            "--stop-at",
            "10",
            "--rate",
            "100",
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).expect("utf8");
    assert!(text.contains("  1   supervisor_stop demanded,"), "{text}");
    assert!(text.contains("supervisor warnings on "), "{text}");
}
