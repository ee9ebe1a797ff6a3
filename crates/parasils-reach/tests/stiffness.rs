//! The stiffness map: each feasible cell's tip deflections against the
//! kinematics' `tip_deflection` called here on the controller's own step,
//! and that deflection against the springs given way by hand: the
//! actuators moved by their forces over their stiffnesses, the tip found
//! by the forward kinematics (module 1's Newton solve, then the module's
//! own), central differences in the size of the load.

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{
    ActuatorStiffness, Actuators, Controller, Joints, Loads, MarginTracker, PlatformState, Pose,
    Side,
};
use parasils_reach::{ReachError, ReachMap, ReachOptions, csv};
use parasils_sim::Scenario;

const LOAD_N: [f64; 3] = [3.0, -4.0, -10.0];

fn options() -> ReachOptions {
    ReachOptions {
        psi_range_deg: [-45.0, 45.0],
        theta_range_deg: [-45.0, 45.0],
        step_deg: 5.0,
        line: false,
        threads: 1,
        deflection_load_n: Some(LOAD_N),
    }
}

/// The controller's step at rest at `(dpsi, dtheta)` deg from the paper's
/// start, the paper's tips held.
fn step_at(
    controller: &Controller<f64>,
    dpsi: f64,
    dtheta: f64,
) -> (parasils::kin::ControlStep<f64>, Pose<f64>) {
    let scenario = Scenario::paper();
    let start = scenario.start();
    let pose = Pose {
        psi: start.psi + dpsi.to_radians(),
        theta: start.theta + dtheta.to_radians(),
        ..start
    };
    let step = controller
        .step(
            &PlatformState::at_rest(pose),
            &scenario.tips(),
            &mut MarginTracker::new(),
        )
        .expect("feasible");
    (step, pose)
}

#[test]
fn each_cell_is_the_kinematics_tip_deflection() {
    let map = ReachMap::compute(&Scenario::paper(), &options()).expect("map");
    let controller = Controller::<f64>::paper();
    let stiffness = ActuatorStiffness::assumed();
    let load = Vector3::from(LOAD_N);
    let (mut checked, mut infeasible) = (0, 0);
    let (mut least, mut most) = (f64::INFINITY, 0.0_f64);
    for (i, cell) in map.cells.iter().enumerate() {
        let Some(d) = cell.deflection_mm else {
            assert!(!cell.feasible, "a feasible cell without its deflection");
            infeasible += 1;
            continue;
        };
        assert!(cell.feasible);
        let [dpsi, dtheta] = map.increments_deg(i);
        let (step, _) = step_at(&controller, dpsi, dtheta);
        for (side, value) in [(Side::Left, d[0]), (Side::Right, d[1])] {
            let direct = controller
                .tip_deflection(&step, side, &-load, &stiffness)
                .expect("deflects")
                .norm();
            assert!(
                (value - direct).abs() <= 1e-12 * direct,
                "{dpsi} {dtheta} {side:?}: {value} vs {direct}"
            );
            least = least.min(value);
            most = most.max(value);
        }
        checked += 1;
    }
    assert!(checked > 50, "{checked}");
    assert!(infeasible > 0, "the grid reaches past the workspace");
    // The map tells stiff from soft: the deflection varies over the grid.
    assert!(most > 1.2 * least, "{least} {most}");
    // The CSV: two more columns, empty where infeasible.
    let mut out = Vec::new();
    csv::write(&map, &mut out).expect("writes");
    let text = String::from_utf8(out).expect("utf-8");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header[header.len() - 2..], csv::DEFLECTION);
    for (line, cell) in lines.zip(&map.cells) {
        let fields: Vec<&str> = line.split(',').collect();
        let last: Vec<&str> = fields[fields.len() - 2..].to_vec();
        match cell.deflection_mm {
            Some(d) => {
                assert_eq!(last[0].parse::<f64>().ok(), Some(d[0]));
                assert_eq!(last[1].parse::<f64>().ok(), Some(d[1]));
            }
            None => assert_eq!(last, ["", ""]),
        }
    }
    // Without a load: no deflection, no extra columns.
    let plain = ReachMap::compute(
        &Scenario::paper(),
        &ReachOptions {
            deflection_load_n: None,
            ..options()
        },
    )
    .expect("map");
    assert!(plain.cells.iter().all(|c| c.deflection_mm.is_none()));
    let feasible = |m: &ReachMap| m.cells.iter().map(|c| c.feasible).collect::<Vec<_>>();
    assert_eq!(feasible(&plain), feasible(&map));
}

/// The tip of `side` (mm, fixed frame) with module 1's actuators at `q`
/// (its pose by the forward kinematics from `guess`) and the module's
/// joints at `qs`.
fn tip_of(
    controller: &Controller<f64>,
    side: Side,
    q: &Actuators<f64>,
    qs: &Joints<f64>,
    guess: &Pose<f64>,
) -> Vector3<f64> {
    let pose = controller.module1.fk(q, guess).expect("assembles").pose;
    let frame = PlatformState::at_rest(pose).frame().expect("finite");
    let module = match side {
        Side::Left => &controller.left,
        Side::Right => &controller.right,
    };
    frame.to_fixed(&module.fk_platform(qs))
}

/// The springs given way by hand: the tip pressing with `F` is held by the
/// actuators' forces `tau` (`Controller::forces`); the tissue's push `-F`
/// compresses each spring by `tau_k / k_k` against its force, so the
/// actuators sit at `q - tau / k`, and the forward kinematics put the tip
/// there. Scaled by `c` and differenced centrally, that is the deflection
/// per unit of the load, to 1e-7.
#[test]
fn the_deflection_is_the_springs_given_way_through_the_forward_kinematics() {
    let controller = Controller::<f64>::paper();
    // Soft springs of different stiffness each, so that no two terms are alike.
    let stiffness = ActuatorStiffness {
        stiffness: [
            150.0, 180.0, 210.0, 240.0, 170.0, 260.0, 1.5e5, 2.5e5, 40.0, 1.8e5, 2.2e5, 60.0,
        ],
    };
    let force = Vector3::from(LOAD_N);
    for (dpsi, dtheta) in [(0.0, 0.0), (10.0, 15.0), (-15.0, 25.0)] {
        let (step, pose) = step_at(&controller, dpsi, dtheta);
        for side in [Side::Left, Side::Right] {
            let (left, right) = match side {
                Side::Left => (force, Vector3::zeros()),
                Side::Right => (Vector3::zeros(), force),
            };
            let tau = controller
                .forces(&step, &Loads::tips(left, right))
                .expect("forces")
                .to_array();
            let k = &stiffness.stiffness;
            let (qs, base) = match side {
                Side::Left => (step.left.q, 6),
                Side::Right => (step.right.q, 9),
            };
            let at = |c: f64| {
                let q = Actuators(core::array::from_fn(|j| {
                    step.module1.q[j] - c * tau[j] / k[j]
                }));
                let give = |i: usize| c * tau[base + i] / k[base + i];
                let qs = Joints::new(qs.qs1 - give(0), qs.qs2 - give(1), qs.qs3 - give(2));
                tip_of(&controller, side, &q, &qs, &pose)
            };
            let c = 1e-3;
            let by_hand = (at(c) - at(-c)) / (2.0 * c);
            let deflection = controller
                .tip_deflection(&step, side, &-force, &stiffness)
                .expect("deflects");
            let error = (by_hand - deflection).norm() / deflection.norm();
            assert!(error <= 1e-7, "{dpsi} {dtheta} {side:?}: {error:e}");
            // Pressed by the tissue, the tip gives way towards it.
            assert!(deflection.dot(&force) < 0.0);
        }
    }
}

#[test]
fn a_non_finite_load_is_refused() {
    let e = ReachMap::compute(
        &Scenario::paper(),
        &ReachOptions {
            deflection_load_n: Some([0.0, f64::NAN, 1.0]),
            ..options()
        },
    )
    .expect_err("refused");
    assert!(matches!(e, ReachError::DeflectionLoad { .. }), "{e}");
    assert!(e.to_string().contains("deflection load"), "{e}");
}
