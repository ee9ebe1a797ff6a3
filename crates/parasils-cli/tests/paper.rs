//! `parasils simulate` on the paper's scenario (`docs/model.md`, *Check
//! values*), its CSV read back: the columns, the check values at named
//! instants, every 100th row against the closed forms, the minima of the
//! margins, and the rates against finite differences.
//!
//! The file is checked against values that come from outside the run: the
//! paper's numbers, its trapezoid written out by hand, and the kinematics'
//! closed forms evaluated at the poses that trapezoid gives. Never against a
//! recorded copy of the output: a change in the last digits elsewhere (a
//! reordered sum, another code path for the same run) leaves these tests
//! passing, and a change of a value fails them. When a deliberate change
//! moves a value, re-baseline as `docs/model.md` says (*Check values*, *How
//! the paper's run is checked*).

mod common;

use common::process::parasils;
use common::table::Table;
use parasils::kin::{ControlStep, Controller, MarginTracker, PlatformState, Pose, TipTargets};

/// The paper's run: `simulate` with its defaults, written to `paper.csv`.
fn paper_file() -> Table {
    let dir = tempfile::tempdir().expect("tempdir");
    parasils(&["simulate", "-o", "paper.csv"])
        .dir(dir.path())
        .run()
        .ok();
    Table::read(&dir.path().join("paper.csv"))
}

/// The paper's run with its increments given, written to standard output.
fn paper_csv() -> Table {
    Table::parse(
        &parasils(&["simulate", "--psi", "15", "--theta", "25", "-o", "-"])
            .run()
            .ok(),
    )
}

// The paper's numbers (its section 4; `docs/model.md`, *The paper's
// scenario*).

/// The start pose `P0`: mm and deg.
const P0: [f64; 6] = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];
/// The turn: `psi` and `theta` increased by these, deg.
const TURN_DEG: [f64; 2] = [15.0, 25.0];
/// The limits of each angle: deg/s and deg/s^2.
const OMEGA_MAX: f64 = 10.0;
const EPS_MAX: f64 = 5.0;
/// The sampling rate, Hz.
const RATE_HZ: f64 = 1000.0;

/// `theta`'s trapezoid written out (`docs/model.md`, *Trapezoid*): 25 deg
/// with 10 deg/s and 5 deg/s^2 is trapezoidal (`d a = 125 > v^2 = 100`),
/// accelerating for `v / a = 2 s`, cruising `d / v - v / a = 0.5 s`,
/// decelerating 2 s: `T = 4.5 s`. Its displacement (deg), rate (deg/s) and
/// acceleration (deg/s^2) at `t`.
fn theta_profile(t: f64) -> [f64; 3] {
    let (v, a) = (OMEGA_MAX, EPS_MAX);
    let t_a = v / a;
    let t_c = TURN_DEG[1] / v - v / a;
    let duration = 2.0 * t_a + t_c;
    if t <= 0.0 {
        [0.0, 0.0, 0.0]
    } else if t < t_a {
        [a * t * t / 2.0, a * t, a]
    } else if t < t_a + t_c {
        [v * t_a / 2.0 + v * (t - t_a), v, 0.0]
    } else if t < duration {
        let left = duration - t;
        [TURN_DEG[1] - a * left * left / 2.0, a * left, -a]
    } else {
        [TURN_DEG[1], 0.0, 0.0]
    }
}

/// The platform at `t` (deg, deg/s, deg/s^2 for `psi` then `theta`): phase
/// synchronisation makes `psi` `theta`'s profile scaled by 15 / 25
/// (`docs/model.md`, *Synchronisation*).
fn platform(t: f64) -> [[f64; 3]; 2] {
    let theta = theta_profile(t);
    let scale = TURN_DEG[0] / TURN_DEG[1];
    [
        [P0[3] + scale * theta[0], scale * theta[1], scale * theta[2]],
        [P0[4] + theta[0], theta[1], theta[2]],
    ]
}

/// The kinematics' closed forms at the hand-written platform state of
/// sample `k`: module 1's IK, rates and margins, both instrument modules'
/// IK and rates with the paper's tips held.
fn closed_form(k: usize) -> ControlStep<f64> {
    let [psi, theta] = platform(k as f64 / RATE_HZ);
    let pose = Pose::from_mm_deg(P0[0], P0[1], P0[2], psi[0], theta[0], P0[5]);
    let state = PlatformState::reorientation(
        pose,
        [psi[1].to_radians(), theta[1].to_radians()],
        [psi[2].to_radians(), theta[2].to_radians()],
    );
    Controller::paper()
        .step(&state, &TipTargets::paper(), &mut MarginTracker::new())
        .expect("the paper's motion is regular")
}

/// The CSV's columns at sample `k` as the closed forms give them, with the
/// tolerance of each: 1e-9 in the column's unit (mm, deg, deg/s, ...). The
/// accelerations are left out at `theta`'s switches inside the motion (2 s,
/// 2.5 s), where the profile's acceleration jumps and which side a sample
/// falls on is a matter of rounding.
fn expected(k: usize) -> Vec<(String, f64)> {
    let t = k as f64 / RATE_HZ;
    // The samples at `t_a = v / a` and `t_a + t_c = d / v`: 2000 and 2500.
    let switches = [OMEGA_MAX / EPS_MAX, TURN_DEG[1] / OMEGA_MAX].map(|s| s * RATE_HZ);
    let switch = switches.contains(&(k as f64));
    let [psi, theta] = platform(t);
    let mut want: Vec<(String, f64)> = vec![
        ("t_s".into(), t),
        ("x_mm".into(), P0[0]),
        ("y_mm".into(), P0[1]),
        ("z_mm".into(), P0[2]),
        ("psi_deg".into(), psi[0]),
        ("theta_deg".into(), theta[0]),
        ("phi_deg".into(), P0[5]),
        ("psi_rate_deg_s".into(), psi[1]),
        ("theta_rate_deg_s".into(), theta[1]),
    ];
    if !switch {
        want.push(("psi_acc_deg_s2".into(), psi[2]));
        want.push(("theta_acc_deg_s2".into(), theta[2]));
    }
    let step = closed_form(k);
    let m1 = &step.module1;
    for j in 0..6 {
        want.push((format!("q{}_mm", j + 1), m1.q[j]));
        want.push((format!("q{}_rate_mm_s", j + 1), m1.q_dot[j]));
        if !switch {
            want.push((format!("q{}_acc_mm_s2", j + 1), m1.q_ddot[j]));
        }
    }
    want.push(("module1_serial_margin".into(), m1.margins.serial_min));
    want.push(("module1_parallel_margin".into(), m1.margins.parallel));
    for (side, s) in [("left", &step.left), ("right", &step.right)] {
        let (q, v, a) = (s.q, s.q_dot, s.q_ddot);
        let rows = [
            (
                "qs1",
                "deg",
                q.qs1.to_degrees(),
                v.qs1.to_degrees(),
                a.qs1.to_degrees(),
            ),
            (
                "qs2",
                "deg",
                q.qs2.to_degrees(),
                v.qs2.to_degrees(),
                a.qs2.to_degrees(),
            ),
            ("qs3", "mm", q.qs3, v.qs3, a.qs3),
        ];
        for (joint, unit, pos, rate, acc) in rows {
            want.push((format!("{side}_{joint}_{unit}"), pos));
            want.push((format!("{side}_{joint}_rate_{unit}_s"), rate));
            if !switch {
                want.push((format!("{side}_{joint}_acc_{unit}_s2"), acc));
            }
        }
        want.push((format!("{side}_cos_qs2"), q.qs2.cos()));
        // The tip recomputed from the joints is where it was asked.
        want.push((format!("{side}_tip_err_mm"), 0.0));
    }
    want
}

/// Every expected column of sample `k` within 1e-9 of the table's.
fn assert_sample(table: &Table, k: usize, what: &str) {
    for (name, want) in expected(k) {
        let got = table.at(&name, k);
        assert!(
            (got - want).abs() <= 1e-9,
            "{what} (sample {k}): {name} = {got}, the closed form gives {want}"
        );
    }
}

/// The named instants of the paper's run, each against the closed forms,
/// and the check values `docs/model.md` prints (their printed digits).
#[test]
fn the_paper_s_csv_at_named_instants() {
    let table = paper_file();
    for (k, what) in [
        (0, "the start"),
        (1000, "mid-acceleration"),
        (2000, "the end of the acceleration"),
        (2250, "mid-cruise"),
        (2500, "the start of the deceleration"),
        (3500, "mid-deceleration"),
        (4500, "t = 4.5 s, the end"),
    ] {
        assert_sample(&table, k, what);
    }
    // The phases' ends, by hand: theta 10 + 10 deg after 2 s at 10 deg/s,
    // 10 + 12.5 deg mid-cruise, 10 + 15 deg at 2.5 s; psi at 15/25 of it.
    let exact = [
        (2000, -9.0, 20.0, 6.0, 10.0),
        (2250, -7.5, 22.5, 6.0, 10.0),
        (2500, -6.0, 25.0, 6.0, 10.0),
    ];
    for (k, psi, theta, psi_rate, theta_rate) in exact {
        for (name, want) in [
            ("psi_deg", psi),
            ("theta_deg", theta),
            ("psi_rate_deg_s", psi_rate),
            ("theta_rate_deg_s", theta_rate),
        ] {
            let got = table.at(name, k);
            assert!((got - want).abs() <= 1e-9, "{name} at {k}: {got}");
        }
    }
    // At rest at both ends, exactly (the sampler's first and last samples).
    for k in [0, 4500] {
        for name in [
            "psi_rate_deg_s",
            "theta_rate_deg_s",
            "psi_acc_deg_s2",
            "theta_acc_deg_s2",
        ] {
            assert_eq!(table.at(name, k), 0.0, "{name} at {k}");
        }
    }
    // The start on the user's own degrees, the end on the goal.
    assert_eq!(
        [table.at("psi_deg", 0), table.at("theta_deg", 0)],
        [-15.0, 10.0]
    );
    assert!(table.at("psi_deg", 4500).abs() < 1e-12);
    assert!((table.at("theta_deg", 4500) - 35.0).abs() < 1e-12);
    // docs/model.md, *Check values*: the joints at the start and the end
    // (four decimals) and module 1 at P0 (three).
    let printed = |k: usize, side: &str, want: [f64; 3]| {
        for (joint, w) in ["qs1_deg", "qs2_deg", "qs3_mm"].into_iter().zip(want) {
            let got = table.at(&format!("{side}_{joint}"), k);
            assert!((got - w).abs() < 5e-5, "{side}_{joint} at {k}: {got}");
        }
    };
    printed(0, "left", [3.0889, -38.8695, 147.7687]);
    printed(0, "right", [37.6768, -18.1170, 185.6585]);
    printed(4500, "left", [20.7942, -61.8435, 151.0378]);
    printed(4500, "right", [50.6487, 3.3476, 182.3246]);
    let q_p0 = [117.942, 151.459, 56.937, 89.428, 132.193, 77.441];
    for (j, want) in q_p0.iter().enumerate() {
        let got = table.at(&format!("q{}_mm", j + 1), 0);
        assert!((got - want).abs() < 5e-4, "q{} = {got}", j + 1);
    }
}

/// The whole file, coarser: its shape, every sample's time, every 100th
/// row against the closed forms, and the margins' minima over the motion.
#[test]
fn the_paper_s_csv_as_a_whole() {
    let table = paper_file();
    // 74 columns, no `command` (a run without commands).
    assert_eq!(table.header().len(), 74, "{:?}", table.header());
    assert!(!table.has("command"));
    // 4501 samples, t_k = k / 1000 exactly.
    let time = table.col("t_s");
    assert_eq!(time.len(), 4501);
    for (k, t) in time.iter().enumerate() {
        assert_eq!(*t, k as f64 / RATE_HZ, "t at sample {k}");
    }
    for k in (0..=4500).step_by(100) {
        assert_sample(&table, k, "every 100th row");
    }
    // docs/model.md, *Singularities and thresholds*: the smallest margins
    // along the paper's motion (four decimals).
    let smallest = |name: &str| table.col(name).into_iter().fold(f64::INFINITY, f64::min);
    for (name, want) in [
        ("left_cos_qs2", 0.4719),
        ("right_cos_qs2", 0.9504),
        ("module1_serial_margin", 0.7324),
        ("module1_parallel_margin", 0.5262),
    ] {
        let got = smallest(name);
        assert!((got - want).abs() < 5e-5, "the smallest {name}: {got}");
    }
    // The tips never drift.
    for side in ["left", "right"] {
        let worst = table
            .col(&format!("{side}_tip_err_mm"))
            .into_iter()
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{side} drift {worst} mm");
    }
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
        assert!(t.has(c), "missing {c}");
    }
    for j in 1..=6 {
        for c in [
            format!("q{j}_mm"),
            format!("q{j}_rate_mm_s"),
            format!("q{j}_acc_mm_s2"),
        ] {
            assert!(t.has(&c), "missing {c}");
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
            assert!(t.has(&format!("{side}_{c}")), "missing {side}_{c}");
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
    check("right", 0, [37.6768, -18.1170, 185.6585]);
    check("left", 4500, [20.7942, -61.8435, 151.0378]);
    check("right", 4500, [50.6487, 3.3476, 182.3246]);
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
    parasils(&["simulate", "-o", "a.csv"])
        .dir(dir.path())
        .run()
        .ok();
    parasils(&["simulate", "--psi", "15", "--theta", "25", "-o", "b.csv"])
        .dir(dir.path())
        .run()
        .ok();
    let a = std::fs::read(dir.path().join("a.csv")).expect("a.csv");
    let b = std::fs::read(dir.path().join("b.csv")).expect("b.csv");
    assert!(a.len() > 1000);
    assert!(a == b, "the two runs differ");
}
