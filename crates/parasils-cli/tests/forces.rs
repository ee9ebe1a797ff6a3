//! `parasils simulate --tip-load-left/--tip-load-right`: the force columns,
//! checked by the balance of power from the CSV's own rate columns, the
//! paper's columns unchanged, loads with a procedure, a malformed load, and
//! a robot file with `[dynamics]` against the body's Newton-Euler.

mod common;

use common::files::demo;
use common::process::parasils;
use common::table::Table;

const FORCES: [&str; 12] = [
    "q1_force_n",
    "q2_force_n",
    "q3_force_n",
    "q4_force_n",
    "q5_force_n",
    "q6_force_n",
    "left_qs1_torque_nmm",
    "left_qs2_torque_nmm",
    "left_qs3_force_n",
    "right_qs1_torque_nmm",
    "right_qs2_torque_nmm",
    "right_qs3_force_n",
];

/// The rate column that goes with each force column, and the factor from
/// its unit to the force's (deg/s to rad/s for the rotary joints).
const RATES: [(&str, f64); 12] = {
    const DEG: f64 = core::f64::consts::PI / 180.0;
    [
        ("q1_rate_mm_s", 1.0),
        ("q2_rate_mm_s", 1.0),
        ("q3_rate_mm_s", 1.0),
        ("q4_rate_mm_s", 1.0),
        ("q5_rate_mm_s", 1.0),
        ("q6_rate_mm_s", 1.0),
        ("left_qs1_rate_deg_s", DEG),
        ("left_qs2_rate_deg_s", DEG),
        ("left_qs3_rate_mm_s", 1.0),
        ("right_qs1_rate_deg_s", DEG),
        ("right_qs2_rate_deg_s", DEG),
        ("right_qs3_rate_mm_s", 1.0),
    ]
};

/// The paper's turn holds both tips still, so the twelve actuators together
/// deliver no power: module 1's power to the platform is taken back by the
/// instrument modules, row by row, whatever the loads.
#[test]
fn the_twelve_actuators_balance_power_on_the_paper_turn() {
    let text = parasils(&[
        "simulate",
        "--tip-load-left",
        "5,-3,8",
        "--tip-load-right",
        "-2,4,10",
        "-o",
        "-",
    ])
    .run()
    .ok();
    let t = Table::parse(&text);
    // The 74 columns of every run (53, the four clearance columns, the
    // eight camera columns, the nine ports), then the forces.
    assert_eq!(t.header().len(), 74 + 14);
    assert_eq!(t.header()[74..86], FORCES.map(String::from));
    assert_eq!(
        t.header()[86..],
        ["left_tip_deflection_mm", "right_tip_deflection_mm"]
    );
    let forces = FORCES.map(|n| t.col(n));
    let rates = RATES.map(|(n, k)| t.col(n).into_iter().map(|v| v * k).collect::<Vec<_>>());
    let mut moving = 0;
    for k in 0..t.rows() {
        let terms: Vec<f64> = (0..12).map(|c| forces[c][k] * rates[c][k]).collect();
        let scale: f64 = terms.iter().map(|v| v.abs()).sum();
        let module1: f64 = terms[..6].iter().sum();
        let total: f64 = terms.iter().sum();
        assert!(total.abs() <= 1e-9 * scale, "row {k}: {total} of {scale}");
        if module1.abs() > 1.0 {
            moving += 1;
        }
    }
    // Module 1 does work on most rows: the balance is not 0 = 0.
    assert!(moving > 3000, "{moving}");
    // The paper's columns are the unloaded run's, digit for digit.
    let plain = Table::parse(&parasils(&["simulate", "-o", "-"]).run().ok());
    for name in plain.header() {
        assert_eq!(plain.text(name), t.text(name), "{name}");
    }
}

#[test]
fn loads_apply_to_a_procedure() {
    let text = parasils(&[
        "simulate",
        "--procedure",
        &demo(),
        "--rate",
        "100",
        "--tip-load-right",
        "0,0,-10",
        "-o",
        "-",
    ])
    .run()
    .ok();
    let t = Table::parse(&text);
    assert_eq!(t.header().len(), 74 + 12 + 14);
    assert_eq!(t.header()[86..98], FORCES.map(String::from));
    assert!(t.col("left_qs3_force_n").iter().all(|v| *v == 0.0));
    assert!(t.col("left_tip_deflection_mm").iter().all(|v| *v == 0.0));
    assert!(t.col("right_tip_deflection_mm").iter().all(|v| *v > 0.0));
    assert!(t.col("right_qs3_force_n").iter().any(|v| v.abs() > 1.0));
}

/// Statics and the springs are linear: twice the loads, twice every force
/// and both deflections.
#[test]
fn twice_the_loads_twice_the_forces_and_deflections() {
    let run = |left: &str, right: &str| {
        Table::parse(
            &parasils(&[
                "simulate",
                "--rate",
                "50",
                "--tip-load-left",
                left,
                "--tip-load-right",
                right,
                "-o",
                "-",
            ])
            .run()
            .ok(),
        )
    };
    let once = run("5,-3,8", "-2,4,10");
    let twice = run("10,-6,16", "-4,8,20");
    for name in FORCES
        .iter()
        .chain(&["left_tip_deflection_mm", "right_tip_deflection_mm"])
    {
        for (a, b) in once.col(name).iter().zip(twice.col(name)) {
            assert!(
                (2.0 * a - b).abs() <= 1e-12 * b.abs().max(1e-3),
                "{name}: {a} {b}"
            );
        }
    }
    assert!(once.col("left_tip_deflection_mm").iter().all(|d| *d > 0.0));
}

#[test]
fn a_malformed_load_names_its_flag() {
    let err = parasils(&["simulate", "--tip-load-left", "1,2", "-o", "-"])
        .run()
        .fails();
    assert!(err.contains("--tip-load-left"), "{err}");
    assert!(err.contains("expected 3"), "{err}");
}

#[test]
fn the_summary_and_the_check_give_each_actuator_s_peak_use_of_its_force_limit() {
    let dir = tempfile::tempdir().expect("tempdir");
    let text = parasils(&["simulate", "--rate", "100", "--tip-load-left", "0,0,-10"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(text.contains("force limits, peak use:"), "{text}");
    // The peak use of q1 is its largest force over the assumed 200 N.
    let table = Table::parse(
        &parasils(&[
            "simulate",
            "--rate",
            "100",
            "--tip-load-left",
            "0,0,-10",
            "-o",
            "-",
        ])
        .run()
        .ok(),
    );
    let peak = table
        .col("q1_force_n")
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(text.contains(&format!(" q1 {:.3}", peak / 200.0)), "{text}");
    let plain = parasils(&["simulate", "--rate", "100"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(!plain.contains("force limits"), "{plain}");
    let check = parasils(&[
        "simulate",
        "--procedure",
        &demo(),
        "--check",
        "--tip-load-right",
        "0,0,-10",
    ])
    .run()
    .ok();
    assert!(check.contains("force limits, peak use:"), "{check}");
}

/// `robots/dynamics.toml`.
fn dynamics_robot() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../robots/dynamics.toml").to_owned()
}

/// A robot file with `[dynamics]` writes the force columns without a tip
/// load, and its slider forces are the kinematics' Newton-Euler wrench of
/// the assumed body, computed here from the CSV's own pose, Euler rate and
/// acceleration columns (`P` and `phi` held by the paper's turn), through
/// the transposed Jacobian: within 1e-8 of the largest force, every row.
#[test]
fn a_robot_with_dynamics_feeds_forward_its_body_s_newton_euler_wrench() {
    use parasils::kin::{ParallelRobot, Payload, PlatformState, Pose, PoseRate};
    let robot = dynamics_robot();
    let t = Table::parse(
        &parasils(&["simulate", "--robot", &robot, "--rate", "200", "-o", "-"])
            .run()
            .ok(),
    );
    assert_eq!(t.header().len(), 74 + 14);
    assert_eq!(t.header()[74..86], FORCES.map(String::from));
    let col = |n: &str| t.col(n);
    let (x, y, z) = (col("x_mm"), col("y_mm"), col("z_mm"));
    let angles = ["psi_deg", "theta_deg", "phi_deg"].map(&col);
    let rates = ["psi_rate_deg_s", "theta_rate_deg_s"].map(&col);
    let accs = ["psi_acc_deg_s2", "theta_acc_deg_s2"].map(&col);
    let forces: Vec<Vec<f64>> = FORCES[..6].iter().map(|n| col(n)).collect();
    let module1 = ParallelRobot::<f64>::assumed();
    let body = Payload::<f64>::assumed();
    let (mut worst, mut inertial) = (0.0_f64, 0.0_f64);
    for k in 0..t.rows() {
        let r = |v: &[f64]| v[k].to_radians();
        let state = PlatformState {
            pose: Pose::new(
                x[k],
                y[k],
                z[k],
                r(&angles[0]),
                r(&angles[1]),
                r(&angles[2]),
            ),
            velocity: PoseRate::euler(r(&rates[0]), r(&rates[1])),
            acceleration: PoseRate::euler(r(&accs[0]), r(&accs[1])),
        };
        let frame = state.frame().expect("finite");
        let solution = module1.solve(&frame).expect("solves");
        let expected = module1
            .slider_forces(&frame, &solution, &body.moving_wrench(&frame))
            .expect("forces")
            .force
            .0;
        let weight_only = module1
            .slider_forces(&frame, &solution, &body.holding_wrench(&frame))
            .expect("forces")
            .force
            .0;
        let scale = expected.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for j in 0..6 {
            worst = worst.max((forces[j][k] - expected[j]).abs() / scale);
            inertial = inertial.max((expected[j] - weight_only[j]).abs());
        }
    }
    assert!(worst <= 1e-8, "{worst}");
    // The body's inertia shows: not the weight alone.
    assert!(inertial > 1e-3, "{inertial}");
    // Nothing on the tips: the modules hold nothing.
    assert!(t.col("left_qs3_force_n").iter().all(|v| *v == 0.0));
    // The summary gives the peak use of each force limit.
    let dir = tempfile::tempdir().expect("tempdir");
    let text = parasils(&["simulate", "--robot", &robot, "--rate", "100"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(text.contains("force limits, peak use:"), "{text}");
}
