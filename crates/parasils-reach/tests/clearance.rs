//! The clearance among the reach map's constraints: with the robot file's
//! clearance thresholds, a cell where two bodies are closer than the stop
//! threshold is unreachable, limited by `clearance.<pair>`; without them
//! the map is unchanged.
//!
//! The right tip is moved by `(60, -40, 40)` mm from the paper's mirror,
//! so that the shafts clear each other near the start (with the mirror
//! their axes intersect at the start, and every cell would be limited);
//! what the paper's turn then runs into is the left shaft against the
//! endoscope (1.287 mm at the start, -1.373 mm at the paper's goal).

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{
    Bodies, BodyGeometry, ClearancePair, Controller, MarginTracker, PlatformState, TipTargets,
};
use parasils_reach::{Checker, Constraint, ReachMap, ReachOptions};
use parasils_sim::Scenario;

fn scenario(stop_mm: Option<f64>) -> Scenario {
    let right = TipTargets::<f64>::paper().right + Vector3::new(60.0, -40.0, 40.0);
    let mut s = Scenario {
        tip_right_mm: Some([right.x, right.y, right.z]),
        ..Scenario::paper()
    };
    s.supervisor.clearance_stop_mm = stop_mm;
    s
}

/// The three gaps at `(dpsi, dtheta)` (deg from the start), straight from
/// the controller's joints and the kinematics' bodies: the map's verdict
/// must follow them.
fn gaps(s: &Scenario, dpsi: f64, dtheta: f64) -> Option<[f64; 3]> {
    let controller = Controller::from_geometry(&s.robot).ok()?;
    let mut pose = s.start();
    pose.psi += dpsi.to_radians();
    pose.theta += dtheta.to_radians();
    let step = controller
        .step(
            &PlatformState::at_rest(pose),
            &s.tips(),
            &mut MarginTracker::new(),
        )
        .ok()?;
    let c = Bodies::at(
        &BodyGeometry::assumed(),
        &step.frame,
        &controller.left,
        &step.left.q,
        &controller.right,
        &step.right.q,
        0.0,
    )
    .ok()?
    .clearance()
    .ok()?;
    Some([
        c.left_right.gap,
        c.left_endoscope.gap,
        c.right_endoscope.gap,
    ])
}

#[test]
fn the_codes_name_the_pairs() {
    for (pair, code) in ClearancePair::ALL.into_iter().zip([
        "clearance.left_right",
        "clearance.left_endoscope",
        "clearance.right_endoscope",
    ]) {
        assert_eq!(Constraint::Clearance(pair).code(), code);
        assert_eq!(
            Constraint::from_code(code),
            Some(Constraint::Clearance(pair))
        );
    }
}

#[test]
fn the_paper_goal_is_limited_by_the_left_shaft_against_the_endoscope() {
    let s = scenario(Some(0.5));
    let mut checker = Checker::new(&s).expect("valid");
    let goal = checker.check(15f64.to_radians(), 25f64.to_radians());
    assert_eq!(
        goal.limiting,
        Constraint::Clearance(ClearancePair::LeftEndoscope)
    );
    // Normalised by the two radii (2.5 + 5 mm): (-1.373 - 0.5) / 7.5.
    let truth = gaps(&s, 15.0, 25.0).expect("solves")[1];
    assert!(
        (goal.margin - (truth - 0.5) / 7.5).abs() < 1e-12,
        "{}",
        goal.margin
    );
    assert!(goal.margin < -0.24);
    assert!(!checker.feasible(15f64.to_radians(), 25f64.to_radians()));
    // The start is feasible, its nearest constraint that gap.
    let start = checker.check(0.0, 0.0);
    assert!(start.feasible());
    assert_eq!(
        start.nearest,
        Constraint::Clearance(ClearancePair::LeftEndoscope)
    );
    assert!(
        (start.margin - (1.287_408_026_688_18 - 0.5) / 7.5).abs() < 1e-9,
        "{}",
        start.margin
    );
    // Without the robot file's thresholds, the goal is feasible.
    let mut free = Checker::new(&scenario(None)).expect("valid");
    assert!(
        free.check(15f64.to_radians(), 25f64.to_radians())
            .feasible()
    );
}

#[test]
fn every_cell_follows_the_gaps() {
    let options = ReachOptions {
        psi_range_deg: [-20.0, 20.0],
        theta_range_deg: [-30.0, 30.0],
        step_deg: 2.5,
        line: false,
        threads: 1,
        deflection_load_n: None,
    };
    let s = scenario(Some(0.5));
    let map = ReachMap::compute(&s, &options).expect("map");
    let free = ReachMap::compute(&scenario(None), &options).expect("map");
    let mut limited = 0;
    for (k, (cell, other)) in map.cells.iter().zip(&free.cells).enumerate() {
        let (c, r) = (k % map.psi.count, k / map.psi.count);
        let (dpsi, dtheta) = (map.psi.value_deg(c), map.theta.value_deg(r));
        match gaps(&s, dpsi, dtheta) {
            Some(g) if other.feasible => {
                let below = g.iter().position(|&x| x < 0.5);
                assert_eq!(cell.feasible, below.is_none(), "({dpsi}, {dtheta}): {g:?}");
                if let Some(i) = below {
                    assert_eq!(cell.limiting, Constraint::Clearance(ClearancePair::ALL[i]));
                    limited += 1;
                }
            }
            // The kinematics fail: the same constraint with or without
            // the clearance.
            _ => assert_eq!(cell.limiting, other.limiting),
        }
    }
    assert!(limited > 10, "{limited}");
    assert!(
        map.cells.iter().filter(|c| c.reachable).count()
            < free.cells.iter().filter(|c| c.reachable).count()
    );
}
