//! The per-cycle call with module 1: a step holds module 1's own solution,
//! the controller built from the paper's geometry is the paper's, and a
//! step or a geometry it cannot take is refused with a typed error.

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
