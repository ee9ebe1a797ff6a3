//! `parasils simulate --timing optimal`: the fastest turn within the
//! actuators' limits, checked on the CSV it writes.

mod common;

use common::files::demo;
use common::process::parasils;
use common::table::Table;

/// The twelve actuators' rate and acceleration columns with their assumed
/// limits (mm/s, mm/s^2; deg/s, deg/s^2 as the CSV writes them).
fn actuators() -> Vec<(String, String, f64, f64)> {
    let mut out = Vec::new();
    for j in 1..=6 {
        out.push((
            format!("q{j}_rate_mm_s"),
            format!("q{j}_acc_mm_s2"),
            50.0,
            100.0,
        ));
    }
    for side in ["left", "right"] {
        out.push((
            format!("{side}_qs1_rate_deg_s"),
            format!("{side}_qs1_acc_deg_s2"),
            30.0,
            60.0,
        ));
        out.push((
            format!("{side}_qs2_rate_deg_s"),
            format!("{side}_qs2_acc_deg_s2"),
            30.0,
            60.0,
        ));
        out.push((
            format!("{side}_qs3_rate_mm_s"),
            format!("{side}_qs3_acc_mm_s2"),
            60.0,
            60.0,
        ));
    }
    out
}

/// Every actuator's rate and acceleration columns of `table` within their
/// limits (1e-9 relative) at every sample; the largest fraction used.
fn peak_use(table: &Table) -> f64 {
    let mut peak: f64 = 0.0;
    for (rate, acc, v_max, a_max) in actuators() {
        for (k, (v, a)) in table.col(&rate).iter().zip(table.col(&acc)).enumerate() {
            assert!(
                v.abs() <= v_max * (1.0 + 1e-9),
                "{rate} = {v} at sample {k}"
            );
            assert!(a.abs() <= a_max * (1.0 + 1e-9), "{acc} = {a} at sample {k}");
            peak = peak.max(v.abs() / v_max).max(a.abs() / a_max);
        }
    }
    peak
}

#[test]
fn the_optimal_turn_keeps_every_actuator_within_its_limits_and_is_shorter() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (args, file) in [
        (
            &["simulate", "--timing", "optimal", "-o", "opt.csv"][..],
            "opt.csv",
        ),
        (&["simulate", "-o", "trap.csv"][..], "trap.csv"),
    ] {
        parasils(args).dir(dir.path()).run().ok();
        assert!(dir.path().join(file).is_file());
    }
    let opt = Table::read(&dir.path().join("opt.csv"));
    let trap = Table::read(&dir.path().join("trap.csv"));
    let t = opt.col("t_s");
    let n = t.len();
    let duration = t[n - 1];
    assert!(duration < 4.5 * 0.6, "{duration}");
    // Some limit binds: the law is as fast as the actuators allow.
    let peak = peak_use(&opt);
    assert!(peak > 0.999, "{peak}");
    // The rates are those of the positions: a central difference over
    // +-1 ms differs from the rate by at most a_max h / 2 where the
    // acceleration jumps (100 mm/s^2 x 1 ms / 2), and by h^2 / 6 of the jerk
    // elsewhere.
    for j in 1..=6 {
        let q = opt.col(&format!("q{j}_mm"));
        let v = opt.col(&format!("q{j}_rate_mm_s"));
        for k in 1..n - 1 {
            let fd = (q[k + 1] - q[k - 1]) / (t[k + 1] - t[k - 1]);
            assert!((fd - v[k]).abs() < 100.0 * 1e-3 / 2.0, "q{j} at {}", t[k]);
        }
    }
    // The tips held, at rest at both ends, on the trapezoid's straight line
    // in (psi, theta).
    for side in ["left", "right"] {
        assert!(
            opt.col(&format!("{side}_tip_err_mm"))
                .iter()
                .all(|e| *e < 1e-9)
        );
    }
    for c in [
        "psi_rate_deg_s",
        "theta_rate_deg_s",
        "q1_rate_mm_s",
        "left_qs2_rate_deg_s",
    ] {
        assert_eq!(opt.col(c)[0], 0.0, "{c}");
        assert!(opt.col(c)[n - 1].abs() < 1e-9, "{c}");
    }
    let (psi, theta) = (opt.col("psi_deg"), opt.col("theta_deg"));
    let (tp, tt) = (trap.col("psi_deg"), trap.col("theta_deg"));
    let (p0, t0) = (tp[0], tt[0]);
    let (p1, t1) = (tp[tp.len() - 1], tt[tt.len() - 1]);
    assert!((psi[n - 1] - p1).abs() < 1e-9 && (theta[n - 1] - t1).abs() < 1e-9);
    for k in 0..n {
        // (psi - p0) / (p1 - p0) == (theta - t0) / (t1 - t0)
        let cross = (psi[k] - p0) * (t1 - t0) - (theta[k] - t0) * (p1 - p0);
        assert!(cross.abs() < 1e-9, "off the line at {}", t[k]);
    }
}

#[test]
fn limits_the_trapezoid_exceeds_fail_it_and_slow_the_optimal_law() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = parasils(&["robot"]).dir(dir.path()).run().ok();
    // Module 1's sliders limited to 20 mm/s: the paper's turn needs 35.7.
    let slow = text.replace("velocity_max_mm_s = 50.0", "velocity_max_mm_s = 20.0");
    assert_ne!(slow, text);
    std::fs::write(dir.path().join("slow.toml"), slow).expect("write");
    let trap = parasils(&["simulate", "--robot", "slow.toml", "-o", "t.csv"])
        .dir(dir.path())
        .run();
    let err = trap.fails();
    assert!(err.contains("module 1 q"), "{err}");
    assert!(err.contains("is beyond its limit 20 mm/s"), "{err}");
    assert!(!dir.path().join("t.csv").exists());
    let opt = parasils(&[
        "simulate",
        "--robot",
        "slow.toml",
        "--timing",
        "optimal",
        "-o",
        "o.csv",
    ])
    .dir(dir.path())
    .run();
    opt.ok();
    let table = Table::read(&dir.path().join("o.csv"));
    let t = table.col("t_s");
    assert!(
        t[t.len() - 1] > 4.5,
        "slower than the paper's 4.5 s: {}",
        t[t.len() - 1]
    );
    for j in 1..=6 {
        assert!(
            table
                .col(&format!("q{j}_rate_mm_s"))
                .iter()
                .all(|v| v.abs() <= 20.0 * (1.0 + 1e-9))
        );
    }
    // The summary says what binds.
    let summary = parasils(&["simulate", "--robot", "slow.toml", "--timing", "optimal"])
        .dir(dir.path())
        .run();
    let text = summary.stdout();
    assert!(
        text.contains("time-optimal timing, what limits each phase:"),
        "{text}"
    );
    assert!(text.contains("velocity limit"), "{text}");
}

#[test]
fn the_plot_of_an_optimal_run_adds_its_phase_plane() {
    let dir = tempfile::tempdir().expect("temp dir");
    let svg = |timing: &str| {
        let out = parasils(&[
            "simulate", "--timing", timing, "--rate", "100", "--plot", "p.svg",
        ])
        .dir(dir.path())
        .run();
        out.ok();
        std::fs::read_to_string(dir.path().join("p.svg")).expect("the picture")
    };
    let optimal = svg("optimal");
    assert!(optimal.contains("(d) Phase plane of the time-optimal law"));
    assert!(optimal.contains("module 1 q6 velocity to s = 0.863"));
    assert!(!svg("trapezoid").contains("Phase plane"));
}

#[test]
fn a_procedure_timed_optimally_keeps_every_limit_and_names_what_binds() {
    let dir = tempfile::tempdir().expect("tempdir");
    let demo = demo();
    let out = parasils(&[
        "simulate",
        "--procedure",
        &demo,
        "--timing",
        "optimal",
        "-o",
        "opt.csv",
    ])
    .dir(dir.path())
    .run();
    out.ok();
    let opt = Table::read(&dir.path().join("opt.csv"));
    let t = opt.col("t_s");
    // Shorter than the trapezoids' 20.238 s: the platform (1.3 s instead
    // of 3 s) and the turn (2.22 s instead of 4.5 s) at the actuators'
    // limits; the endoscope and the tip motions at the limits the
    // procedure gives (the endoscope's defaults bind it: no actuator
    // moves it).
    let duration = t[t.len() - 1];
    assert!((16.0..17.0).contains(&duration), "{duration}");
    let peak = peak_use(&opt);
    assert!(peak > 0.999, "{peak}");
    // Every motion of the procedure is in the file, in order.
    let motions = opt.col("motion");
    assert_eq!((motions[0], motions[motions.len() - 1]), (0.0, 5.0));
    assert!(
        motions
            .windows(2)
            .all(|w| w[1] - w[0] == 0.0 || w[1] - w[0] == 1.0)
    );
    // --check names what limits each phase of each motion, on the
    // procedure's time line: each law's phases stretched with it onto the
    // control cycle (motion 0's 1.2999 s law to 1.301 s: its first phase
    // ends at 0.4998 s / r = 0.5002 s), each motion a cycle after the last.
    let text = parasils(&[
        "simulate",
        "--procedure",
        &demo,
        "--timing",
        "optimal",
        "--check",
    ])
    .dir(dir.path())
    .run()
    .ok();
    for line in [
        "  motion 0 (position \"platform down to the port\"): 0.0000 s to 0.5002 s: module 1 q1 acceleration limit",
        "  motion 1 (insert \"endoscope in\"): 2.3007 s to 4.3043 s: depth velocity limit",
        "  motion 2 (manipulate \"left tip to the tissue\"): 5.8039 s to 7.0371 s: left tip velocity limit",
        "  motion 3 (reorient \"camera to the target\"): 8.0378 s to 9.2632 s: module 1 q6 velocity limit",
    ] {
        assert!(text.lines().any(|l| l == line), "{line:?} not in\n{text}");
    }
}

#[test]
fn a_procedure_motion_cut_short_is_refused_under_optimal_timing() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(
        dir.path().join("cut.toml"),
        "[[motion]]\ntype = \"insert\"\ninstrument = \"left\"\ndepth_mm = 30\nuntil_s = 0.5\n\n[[motion]]\ntype = \"stop\"\n",
    )
    .expect("write");
    let out = parasils(&[
        "simulate",
        "--procedure",
        "cut.toml",
        "--timing",
        "optimal",
        "-o",
        "cut.csv",
    ])
    .dir(dir.path())
    .run();
    let stderr = out.fails_with(1);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("motion 0 (insert)"), "{stderr}");
    assert!(stderr.contains("from rest to rest"), "{stderr}");
    assert!(!dir.path().join("cut.csv").exists());
    // The trapezoid takes it: cut short, then stopped.
    let out = parasils(&["simulate", "--procedure", "cut.toml", "-o", "cut.csv"])
        .dir(dir.path())
        .run();
    out.ok();
}

#[test]
fn commands_are_refused_under_optimal_timing_naming_the_flag() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (args, flag) in [
        (&["--stop-at", "1"][..], "--stop-at"),
        (&["--retarget", "1:5,5", "--stop-at", "2"][..], "--retarget"),
    ] {
        let mut all = vec!["simulate", "--timing", "optimal", "-o", "run.csv"];
        all.extend_from_slice(args);
        let stderr = parasils(&all).dir(dir.path()).run().fails_with(1);
        assert_eq!(
            stderr,
            format!(
                "parasils: error: {flag} cannot be given with --timing optimal: it plans one motion from rest to rest, while commands are taken online\n"
            )
        );
        assert!(!dir.path().join("run.csv").exists());
    }
}
