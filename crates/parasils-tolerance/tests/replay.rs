//! The study's replay (module 1 by the chord method from the nominal
//! Jacobians, [`ReplayPlan`]) against the reference replay (Newton's method
//! from the previous pose at every sample, [`replay`]), over random
//! perturbed robots: the same deviations within 1e-9 mm (and 1e-9 deg), the
//! same failures.

use parasils_sim::Scenario;
use parasils_tolerance::{
    Deviation, Distribution, Family, ReplayFailure, ReplayPlan, Spec, Study, Trace, replay,
};

fn paper_trace(rate_hz: f64) -> Trace {
    let mut scenario = Scenario::paper();
    scenario.rate_hz = rate_hz;
    Trace::from_scenario(scenario).expect("the paper's motion")
}

/// The largest difference of the four columns between the two replays of
/// samples `samples` of `study`; panics on a failure of one and not the
/// other, or on failures at different samples.
fn largest_difference(study: &Study, samples: core::ops::Range<u64>) -> (f64, usize) {
    let plan = study.plan();
    let mut worst: f64 = 0.0;
    let mut failed = 0;
    for i in samples {
        let robot = study.robot(i);
        let reference: Result<Deviation, ReplayFailure> = replay(&robot, study.trace());
        let fast = plan.replay(&robot);
        match (reference, fast) {
            (Ok(a), Ok(b)) => {
                for (x, y) in [
                    (a.left_tip_dev_mm, b.left_tip_dev_mm),
                    (a.right_tip_dev_mm, b.right_tip_dev_mm),
                    (a.pose_position_err_mm, b.pose_position_err_mm),
                    (a.pose_rotation_err_deg, b.pose_rotation_err_deg),
                ] {
                    worst = worst.max((x - y).abs());
                }
            }
            (Err(a), Err(b)) => {
                assert_eq!(a.index, b.index, "robot {i}: {a} / {b}");
                failed += 1;
            }
            (a, b) => panic!("robot {i}: the reference {a:?}, the plan {b:?}"),
        }
    }
    (worst, failed)
}

#[test]
fn the_chord_replay_agrees_with_newtons_within_a_nanometre() {
    // The default tolerances along the paper's turn at 100 Hz (the
    // benchmark's study), 200 random robots.
    let study = Study::new(Spec::default(), paper_trace(100.0), 2024).expect("valid");
    assert_eq!(study.plan().newton_samples(), 0);
    let (worst, failed) = largest_difference(&study, 0..200);
    assert_eq!(failed, 0);
    eprintln!("default tolerances: largest difference {worst:e}");
    assert!(worst < 1e-9, "{worst:e}");
    // Three times wider: larger perturbations, a slower chord.
    let wide = Study::new(Spec::default().scaled(3.0), paper_trace(50.0), 7).expect("valid");
    let (worst, failed) = largest_difference(&wide, 0..60);
    assert_eq!(failed, 0);
    eprintln!("three times wider: largest difference {worst:e}");
    assert!(worst < 1e-9, "{worst:e}");
}

#[test]
fn robots_that_cannot_be_followed_fail_as_in_the_reference() {
    // Encoder offsets of up to 250 mm (as in the study's tests): the chord
    // does not contract, Newton's method takes over and fails where the
    // reference does.
    let spec = Spec::none().with(
        Family::EncoderOffset,
        Some(Distribution::Uniform { half_width: 250.0 }),
    );
    let study = Study::new(spec, paper_trace(10.0), 4).expect("valid");
    let (worst, failed) = largest_difference(&study, 0..48);
    assert!(failed > 0 && failed < 48, "{failed}");
    assert!(worst < 1e-9, "{worst:e}");
}

#[test]
fn a_plan_keeps_the_trace_it_was_made_from() {
    let trace = paper_trace(10.0);
    let plan = ReplayPlan::new(trace.clone());
    assert_eq!(plan.trace(), &trace);
    // The nominal robot on its own commands: no deviation.
    let d = plan.replay(trace.robot()).expect("followed");
    assert!(
        d.tip_dev_mm() < 1e-9 && d.pose_rotation_err_deg < 1e-9,
        "{d:?}"
    );
}
