//! The engine's unit tests.

use super::*;
use crate::record::Record;
use crate::scenario::{Run, Scenario, Turn};

/// The paper's scenario turned by `psi_deg`, `theta_deg` at `rate_hz`.
fn turn(psi_deg: f64, theta_deg: f64, rate_hz: f64) -> Scenario {
    Scenario {
        rate_hz,
        run: Run::turn(Turn {
            psi_deg,
            theta_deg,
            ..Turn::paper()
        }),
        ..Scenario::paper()
    }
}

#[test]
fn the_paper_run_holds_the_tips_and_starts_on_the_user_s_degrees() {
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    assert_eq!(sim.sample_count(), 4501);
    assert_eq!(sim.duration(), 4.5);
    let mut first = None;
    let mut last = None;
    let mut worst = 0.0f64;
    let mut n = 0;
    sim.run(&mut |r: &Record| {
        first.get_or_insert(*r);
        last = Some(*r);
        worst = worst.max(r.left.tip_err).max(r.right.tip_err);
        n += 1;
        Ok::<(), core::convert::Infallible>(())
    })
    .expect("runs");
    assert_eq!(n, 4501);
    assert!(worst < 1e-9, "{worst}");
    let (first, last) = (first.expect("records"), last.expect("records"));
    assert_eq!(first.angles_deg, [-15.0, 10.0, -60.0]);
    assert_eq!(last.index, 4500);
    assert_eq!(last.t, 4.5);
    assert!(last.angles_deg[0].abs() < 1e-12);
    assert!((last.angles_deg[1] - 35.0).abs() < 1e-12);
    assert_eq!(last.angles_deg[2], -60.0);
}

#[test]
fn errors_name_their_subject_and_time_once() {
    // Within the assumed actuator limits, q4 is first too fast (4.6 s): the
    // turn streams, so the run stops at that sample.
    let fast = Simulation::new(turn(-60.0, 0.0, 100.0))
        .expect("plans")
        .run(&mut |_: &Record| Ok::<(), core::convert::Infallible>(()))
        .expect_err("q4 too fast");
    assert_eq!(
        fast.to_string(),
        "at t = 4.600 s: module 1 q4: velocity 50.1196 mm/s is beyond its limit 50 mm/s"
    );
    // Without them, it leaves its stroke (6.4 s).
    let mut robot = parasils::kin::RobotGeometry::paper();
    robot.limits = parasils::kin::ActuatorLimits::unlimited();
    let e = Simulation::new(Scenario {
        robot,
        ..turn(-60.0, 0.0, 100.0)
    })
    .expect("plans")
    .run(&mut |_: &Record| Ok::<(), core::convert::Infallible>(()))
    .expect_err("q4 leaves its stroke");
    let text = e.to_string();
    assert!(
        text.starts_with("at t = 6.400 s: module 1: actuator q4"),
        "{text}"
    );
    assert_eq!(text.matches("module 1").count(), 1, "{text}");
    match e {
        RunError::Simulation(SimulationError::Kinematics { t, sample, .. }) => {
            assert_eq!(sample.map(|k| k as f64 / 100.0), Some(t));
        }
        other => panic!("{other:?}"),
    }
    let e = Simulation::new(Scenario {
        tip_right_mm: Some([f64::NAN, 0.0, 0.0]),
        ..Scenario::paper()
    })
    .expect_err("not finite");
    assert!(matches!(
        e,
        SimulationError::Kinematics { sample: None, .. }
    ));
    let e = Simulation::new(Scenario {
        run: Run::turn(Turn {
            omega_max_deg_s: 0.0,
            ..Turn::paper()
        }),
        ..Scenario::paper()
    })
    .expect_err("no velocity");
    assert!(e.to_string().starts_with("trajectory: "), "{e}");
}
