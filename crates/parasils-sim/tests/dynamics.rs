//! The robot file's `[dynamics]` and `[stiffness]`: the committed
//! `robots/dynamics.toml`, round trips, errors that name their key, and
//! runs whose actuator forces hold the platform's weight and move its
//! inertia: gravity at rest checked by hand, every sample of the paper's
//! turn against the kinematics' Newton-Euler on the record's own state.

use std::path::PathBuf;

use nalgebra::{Matrix3, Vector3};
use parasils::kin::{
    ActuatorStiffness, Controller, ParallelRobot, Payload, PlatformState, Pose, RobotGeometry, Side,
};
use parasils_sim::robot_file::{self, RobotFileError};
use parasils_sim::{Record, Robot, Run, Scenario, Turn, columns};

fn dynamics_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots/dynamics.toml")
}

#[path = "common/turn.rs"]
mod turn;
use turn::turn_state;

fn records(scenario: Scenario) -> Vec<Record> {
    turn::records(scenario).1
}

fn with_robot(robot: Robot) -> Scenario {
    Scenario {
        robot: robot.geometry,
        dynamics: robot.dynamics,
        stiffness: robot.stiffness,
        ..Scenario::paper()
    }
}

#[test]
fn the_committed_dynamics_file_is_the_paper_robot_with_the_assumed_body() {
    let expected = robot_file::robot_to_toml_string(&Robot::paper_with_dynamics()).expect("writes");
    let committed = std::fs::read_to_string(dynamics_path()).expect("robots/dynamics.toml");
    assert_eq!(
        committed, expected,
        "regenerate robots/dynamics.toml:\n{expected}"
    );
    let robot = robot_file::load_robot(dynamics_path()).expect("reads");
    assert_eq!(robot.geometry, RobotGeometry::paper());
    assert_eq!(robot.dynamics, Some(Payload::assumed()));
    assert!(committed.contains("ASSUMED"));
    // The assumed cylinder's moments by hand: 6 kg, r 150 mm, h 200 mm.
    let i = Payload::<f64>::assumed().inertia;
    assert_eq!(i[(2, 2)], 6.0 * 150.0 * 150.0 / 2.0);
    assert_eq!(i[(0, 0)], 6.0 * (3.0 * 22_500.0 + 40_000.0) / 12.0);
}

const DYNAMICS: &str = "
[dynamics]
platform_mass_kg = 2.5
platform_com_mm = [1.0, -2.0, 30.0]
platform_inertia_kg_mm2 = [[3000.0, 10.0, -5.0], [10.0, 2500.0, 0.0], [-5.0, 0.0, 4000.0]]

[stiffness]
slider_n_mm = [100.0, 110.0, 120.0, 130.0, 140.0, 150.0]
right_qs3_n_mm = 25.0
";

fn default_text() -> String {
    robot_file::to_toml_string(&RobotGeometry::paper()).expect("writes")
}

#[test]
fn the_tables_read_with_their_defaults_and_write_back() {
    let robot = robot_file::parse_robot(&(default_text() + DYNAMICS)).expect("valid");
    let p = robot.dynamics.expect("a body");
    assert_eq!(p.mass, 2.5);
    assert_eq!(p.com, Vector3::new(1.0, -2.0, 30.0));
    assert_eq!(p.inertia[(0, 1)], 10.0);
    assert_eq!(p.inertia[(2, 0)], -5.0);
    // Gravity not given: standard, along -Z.
    assert_eq!(p.gravity, Vector3::new(0.0, 0.0, -9810.0));
    let k = robot.stiffness.stiffness;
    assert_eq!(k[..6], [100.0, 110.0, 120.0, 130.0, 140.0, 150.0]);
    assert_eq!(k[11], 25.0);
    // Not given: assumed.
    assert_eq!(k[6], ActuatorStiffness::<f64>::QS12_NMM_RAD);
    assert_eq!(k[8], ActuatorStiffness::<f64>::QS3_N_MM);
    let text = robot_file::robot_to_toml_string(&robot).expect("writes");
    assert_eq!(robot_file::parse_robot(&text).expect("reads back"), robot);
    // Without the tables: no body, the assumed springs.
    let plain = robot_file::parse_robot(&default_text()).expect("valid");
    assert_eq!(plain.dynamics, None);
    assert_eq!(plain.stiffness, ActuatorStiffness::assumed());
}

/// The error of `table` appended to the default file: its message, and
/// its key and line when it has them.
fn error_of(table: &str) -> (String, Option<String>, Option<usize>) {
    let text = default_text() + table;
    let err = robot_file::parse_robot(&text).expect_err("invalid");
    let message = err.to_string();
    match err {
        RobotFileError::Parse { key, line, .. } | RobotFileError::Invalid { key, line, .. } => {
            (message, key.map(String::from), line)
        }
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn a_wrong_value_names_its_key_and_line() {
    let first_line = default_text().lines().count() + 3;
    let bad = |key: &str, value: &str| {
        DYNAMICS.replace(&format!("{key} = "), &format!("{key} = {value} #"))
    };
    let cases = [
        ("platform_mass_kg", "-1.0", "a finite number >= 0", 0),
        (
            "platform_com_mm",
            "[0.0, nan, 0.0]",
            "three finite numbers",
            1,
        ),
        (
            "slider_n_mm",
            "[100.0, 0.0, 1.0, 1.0, 1.0, 1.0]",
            "six finite numbers > 0",
            5,
        ),
        ("right_qs3_n_mm", "-25.0", "a finite number > 0", 6),
    ];
    for (key, value, expected, offset) in cases {
        let (message, at, line) = error_of(&bad(key, value));
        assert!(message.contains(expected), "{key}: {message}");
        assert_eq!(at.as_deref(), Some(key), "{message}");
        assert_eq!(line, Some(first_line + offset), "{key}: {message}");
    }
    // An unknown key, a missing key.
    let (message, ..) = error_of(&DYNAMICS.replace("platform_mass_kg", "platform_mass"));
    assert!(message.contains("platform_mass"), "{message}");
    let (message, ..) = error_of("\n[dynamics]\nplatform_mass_kg = 1.0\n");
    assert!(message.contains("platform_com_mm"), "{message}");
}

#[test]
fn an_impossible_inertia_is_refused_naming_it() {
    let cases = [
        // Not symmetric.
        (
            "[[3000.0, 10.0, -5.0], [11.0, 2500.0, 0.0], [-5.0, 0.0, 4000.0]]",
            "not symmetric",
        ),
        // A negative principal moment.
        (
            "[[3000.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 4000.0]]",
            "negative",
        ),
        // 1 + 1 < 3: no body has these.
        (
            "[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]]",
            "above the sum",
        ),
    ];
    let first_line = default_text().lines().count() + 5;
    for (matrix, expected) in cases {
        let table = DYNAMICS.replace(
            "[[3000.0, 10.0, -5.0], [10.0, 2500.0, 0.0], [-5.0, 0.0, 4000.0]]",
            matrix,
        );
        let (message, key, line) = error_of(&table);
        assert!(message.contains(expected), "{message}");
        assert!(message.contains("platform_inertia_kg_mm2"), "{message}");
        assert_eq!(key.as_deref(), Some("[dynamics] platform_inertia_kg_mm2"));
        assert_eq!(line, Some(first_line));
    }
}

/// A payload of `mass` kg on the platform's axis at the symmetric pose
/// (`P` on the axis of the guides, `phi = -60` deg, no tilt): by the
/// symmetry of the three legs each slider carries a sixth of the weight,
/// pushed up against its guide (`u = -Z`): `tau_j = -M g / 6` by hand.
#[test]
fn gravity_at_rest_on_the_symmetric_pose_is_shared_by_six() {
    let start = [0.0, 0.0, -500.0, 0.0, 0.0, -60.0];
    let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, -60.0);
    // The tips straight below each port, 150 mm.
    let controller = Controller::<f64>::paper();
    let frame = PlatformState::at_rest(pose).frame().expect("finite");
    let tip = |side: Side| {
        let module = match side {
            Side::Left => &controller.left,
            Side::Right => &controller.right,
        };
        let port = frame.to_fixed(&module.geometry().rcm);
        (port - Vector3::new(0.0, 0.0, 150.0)).into()
    };
    let mass = 4.0;
    let payload = Payload::new(mass, Vector3::new(0.0, 0.0, 80.0))
        .with_inertia(Matrix3::from_diagonal(&Vector3::new(1e4, 2e4, 3e4)));
    let scenario = Scenario {
        start_mm_deg: start,
        tip_left_mm: tip(Side::Left),
        tip_right_mm: Some(tip(Side::Right)),
        dynamics: Some(payload),
        run: Run::turn(Turn {
            psi_deg: 0.0,
            theta_deg: 0.0,
            ..Turn::paper()
        }),
        ..Scenario::paper()
    };
    assert_eq!(columns::csv_columns_of(&scenario).len(), 74 + 14);
    let records = records(scenario);
    assert!(!records.is_empty());
    let each = -mass * 9.81 / 6.0;
    for r in &records {
        for (j, tau) in r.forces.module1.iter().enumerate() {
            assert!(
                (tau - each).abs() <= 1e-12 * each.abs(),
                "q{}: {tau} vs {each}",
                j + 1
            );
        }
        // No tip load: the modules hold nothing and give nothing.
        assert_eq!(r.forces.left, [0.0; 3]);
        assert_eq!(r.forces.right, [0.0; 3]);
        assert_eq!(r.forces.deflection, [0.0; 2]);
    }
}

/// Every sample of the paper's turn with the assumed body: the slider
/// forces are the kinematics' Newton-Euler wrench for the record's own
/// pose, Euler rates and accelerations, through the transposed Jacobian;
/// the inertia matters (the forces differ from the weight's alone).
#[test]
fn a_run_with_dynamics_moves_the_body_by_newton_euler() {
    let robot = Robot::paper_with_dynamics();
    let payload = robot.dynamics.expect("a body");
    let records = records(with_robot(robot));
    let module1 = ParallelRobot::<f64>::assumed();
    let (mut worst, mut inertial) = (0.0f64, 0.0f64);
    for r in &records {
        let state = turn_state(r, true);
        let frame = state.frame().expect("finite");
        let solution = module1.solve(&frame).expect("solves");
        let moving = module1
            .slider_forces(&frame, &solution, &payload.moving_wrench(&frame))
            .expect("forces");
        let holding = module1
            .slider_forces(&frame, &solution, &payload.holding_wrench(&frame))
            .expect("forces");
        let scale = moving.force.0.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for j in 0..6 {
            worst = worst.max((r.forces.module1[j] - moving.force.0[j]).abs() / scale);
            inertial = inertial.max((moving.force.0[j] - holding.force.0[j]).abs());
        }
    }
    assert!(worst <= 1e-12, "{worst}");
    // The turn's accelerations move the forces by more than a millinewton.
    assert!(inertial > 1e-3, "{inertial}");
}

/// The robot file's stiffness reaches the deflection columns: every spring
/// twice as stiff, every deflection half (the springs are in series, each
/// giving `tau / k`).
#[test]
fn twice_the_stiffness_half_the_deflection() {
    let loaded = |stiffness| Scenario {
        tip_load_left_n: Some([4.0, -6.0, 9.0]),
        tip_load_right_n: Some([-3.0, 2.5, -12.0]),
        stiffness,
        ..Scenario::paper()
    };
    let soft = ActuatorStiffness::assumed();
    let stiff = ActuatorStiffness {
        stiffness: soft.stiffness.map(|k| 2.0 * k),
    };
    let (a, b) = (records(loaded(soft)), records(loaded(stiff)));
    for (a, b) in a.iter().zip(&b).step_by(97) {
        for s in 0..2 {
            let (da, db) = (a.forces.deflection[s], b.forces.deflection[s]);
            assert!(da > 0.0);
            assert!((db - da / 2.0).abs() <= 1e-12 * da, "{da} {db}");
        }
        assert_eq!(a.forces.module1, b.forces.module1);
    }
}
