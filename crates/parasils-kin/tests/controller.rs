//! The per-cycle call with module 1: a step holds module 1's own solution,
//! the controller built from the paper's geometry is the paper's, and a
//! step or a geometry it cannot take is refused with a typed error, and the
//! static step (`step_at_rest`) is the step of a platform at rest.

use parasils_kin::error::Error;
use parasils_kin::{Controller, MarginTracker, PlatformState, Pose, RobotGeometry, TipTargets};

mod common;
use common::motion::reorientation;

#[test]
fn step_includes_module_1() {
    let controller = Controller::<f64>::paper();
    let st = reorientation::<f64>(2.0);
    let out = controller
        .step(&st, &TipTargets::paper(), &mut MarginTracker::new())
        .expect("regular");
    let alone = controller.module1.solve_state(&st).expect("regular");
    assert_eq!(out.module1, alone);
    assert!(out.module1.q_dot.amax() > 1.0, "moving");
}

#[test]
fn from_the_paper_geometry_is_the_paper_controller() {
    let c = Controller::<f64>::from_geometry(&RobotGeometry::paper()).expect("valid");
    assert_eq!(c, Controller::paper());
    assert_eq!(c.geometry(), RobotGeometry::paper());
    assert!(c.geometry().module1.assumed);
}

#[test]
fn step_refuses_a_pose_out_of_module_1_reach() {
    let controller = Controller::<f64>::paper();
    let st = PlatformState::at_rest(Pose::from_mm_deg(15.0, -450.0, -500.0, -15.0, 10.0, -60.0));
    assert!(matches!(
        controller.step(&st, &TipTargets::paper(), &mut MarginTracker::new()),
        Err(Error::LegOutOfReach { .. })
    ));
}

#[test]
fn from_geometry_rejects_swapped_sides() {
    let mut g = RobotGeometry::<f64>::paper();
    core::mem::swap(&mut g.left, &mut g.right);
    assert!(matches!(
        Controller::from_geometry(&g),
        Err(Error::InvalidParameter {
            what: "robot.left.side",
            ..
        })
    ));
}

/// `step_at_rest` against `step` of a state at rest, each with its own
/// tracker fed the same poses in the same order, over a grid of
/// orientations wide enough to reach every kind of refusal: the same
/// result or the same error, every number equal (the rates `step`
/// evaluates are zero at rest, as `step_at_rest` sets them).
fn at_rest_agrees<T: parasils_kin::Real>(start: Pose<T>) -> [usize; 2] {
    let controller = Controller::<T>::paper();
    let tips = TipTargets::<T>::paper();
    let (mut a, mut b) = (MarginTracker::new(), MarginTracker::new());
    let mut counts = [0; 2];
    for i in -20..=20 {
        for j in -20..=20 {
            let pose = Pose {
                psi: start.psi + T::lit((f64::from(i) * 3.0).to_radians()),
                theta: start.theta + T::lit((f64::from(j) * 3.0).to_radians()),
                ..start
            };
            let full = controller.step(&PlatformState::at_rest(pose), &tips, &mut a);
            let rest = controller.step_at_rest(&pose, &tips, &mut b);
            match (&full, &rest) {
                (Ok(f), Ok(r)) => {
                    assert_eq!(f, r, "at {i}, {j}");
                    assert_eq!(r.module1.q_dot.amax(), T::zero());
                    counts[0] += 1;
                }
                (Err(f), Err(r)) => {
                    assert_eq!(f, r, "at {i}, {j}");
                    counts[1] += 1;
                }
                _ => panic!("at {i}, {j}: {full:?} against {rest:?}"),
            }
        }
    }
    counts
}

#[test]
fn step_at_rest_is_step_with_the_platform_at_rest() {
    let counts = at_rest_agrees(Pose::<f64>::paper_start());
    assert!(counts[0] > 100 && counts[1] > 100, "{counts:?}");
    let counts = at_rest_agrees(Pose::<f32>::paper_start());
    assert!(counts[0] > 100 && counts[1] > 100, "{counts:?}");
}

#[test]
fn step_at_rest_names_a_non_finite_input() {
    let controller = Controller::<f64>::paper();
    let mut tracker = MarginTracker::new();
    let mut pose = Pose::paper_start();
    pose.theta = f64::NAN;
    let tips = TipTargets::paper();
    assert!(matches!(
        controller.step_at_rest(&pose, &tips, &mut tracker),
        Err(Error::NonFinite { .. })
    ));
    let mut tips = TipTargets::paper();
    tips.right.y = f64::INFINITY;
    assert!(matches!(
        controller.step_at_rest(&Pose::paper_start(), &tips, &mut tracker),
        Err(Error::NonFinite {
            what: "tips.right.y",
            ..
        })
    ));
}
