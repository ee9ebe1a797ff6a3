//! Module 1's margins and singularities: the margins at `P0`, the serial
//! margin's threshold, the parallel singularity refused by the per-cycle
//! call, and the tracked parallel margin against the full decomposition
//! (along the paper's motion in `f64` and `f32`, across jumps, through a
//! near-double singular value and up to a singularity).

use nalgebra::Vector6;
use parasils_kin::error::Error;
use parasils_kin::instrument::Interval;
use parasils_kin::{
    Controller, MarginTracker, ParallelGeometry, ParallelRobot, PlatformState, Pose, TipTargets,
};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

mod common;
use common::motion::reorientation;

#[test]
fn margins_at_p0() {
    let m = ParallelRobot::<f64>::assumed()
        .margins(&Pose::paper_start())
        .expect("reachable");
    // Links within about 40 deg of their guides, and far from a parallel singularity.
    assert!(m.serial_min > 0.75 && m.serial_min <= 1.0, "{m:?}");
    assert!(m.parallel > 0.1 && m.parallel < 1.5, "{m:?}");
    assert!(m.stroke.iter().all(|&s| s > 50.0), "{m:?}");
}

#[test]
fn serial_margin_below_its_threshold() {
    let mut g = ParallelGeometry::<f64>::assumed();
    g.thresholds.serial = 0.95;
    let robot = ParallelRobot::new(g).expect("valid");
    let e = robot.ik(&Pose::paper_start()).expect_err("below 0.95");
    match e {
        Error::SerialSingular {
            actuator,
            margin,
            threshold,
        } => {
            assert!((1..=6).contains(&actuator));
            assert!(margin < 0.95 && (threshold - 0.95).abs() < 1e-15);
        }
        other => panic!("{other:?}"),
    }
    let frame = PlatformState::at_rest(Pose::paper_start())
        .frame()
        .expect("finite");
    let q = ParallelRobot::<f64>::assumed()
        .ik(&Pose::paper_start())
        .expect("ok");
    assert!(matches!(
        robot.rates(&frame, &q),
        Err(Error::SerialSingular { .. })
    ));
}

/// The per-cycle call refuses a pose next to a parallel singularity: the
/// assumed geometry has one near `psi = -15 deg, theta = 49.7 deg` (found
/// along `parasils simulate --psi 0 --theta 60`), where the IK alone is fine.
#[test]
fn solve_refuses_a_pose_next_to_a_parallel_singularity() {
    use parasils_kin::frame::{PlatformState, Pose};
    use parasils_kin::parallel::ParallelRobot;
    let robot = ParallelRobot::<f64>::assumed();
    let near = Pose::from_mm_deg(15.0, 20.0, -500.0, -15.0, 49.7, -60.0);
    assert!(robot.ik(&near).is_ok());
    let margin = robot.margins(&near).expect("reachable").parallel;
    assert!(margin < 1e-2, "margin {margin}");
    match robot.solve_state(&PlatformState::at_rest(near)) {
        Err(parasils_kin::Error::ParallelSingular {
            margin: m,
            threshold,
        }) => {
            assert!((m - margin).abs() < 1e-15);
            assert!((threshold - 1e-2).abs() < 1e-18);
        }
        other => panic!("{other:?}"),
    }
    // Farther away it solves.
    let far = Pose::from_mm_deg(15.0, 20.0, -500.0, -15.0, 40.0, -60.0);
    assert!(robot.solve_state(&PlatformState::at_rest(far)).is_ok());
}

/// The paper's reorientation at 1 kHz: every tracked margin is the full
/// decomposition's (`robot.margins`) to rounding, only the first cycle
/// takes the full decomposition, and the rest of module 1's solution is
/// the same bit for bit.
#[test]
fn tracked_margin_along_the_paper_motion() {
    let controller = Controller::<f64>::paper();
    let mut tracker = MarginTracker::new();
    let tips = TipTargets::paper();
    let mut worst = 0f64;
    for k in 0..=4500 {
        let st = reorientation::<f64>(k as f64 * 1e-3);
        let out = controller.step(&st, &tips, &mut tracker).expect("regular");
        let exact = controller.module1.solve_state(&st).expect("regular");
        let rel =
            (out.module1.margins.parallel - exact.margins.parallel).abs() / exact.margins.parallel;
        worst = worst.max(rel);
        assert_eq!(
            (out.module1.q, out.module1.q_dot, out.module1.q_ddot),
            (exact.q, exact.q_dot, exact.q_ddot)
        );
        assert_eq!(out.module1.margins.serial, exact.margins.serial);
    }
    println!("tracked margin, f64: largest relative difference {worst:.2e}");
    assert!(worst < 1e-14, "{worst:e}");
    assert_eq!(tracker.counts(), (4501, 1));
    // The direction is a unit right singular vector: |J x| = margin.
    let st = reorientation::<f64>(4.5);
    let x = tracker.weakest().expect("tracked");
    let j = controller.module1.jacobian(&st.pose).expect("reachable");
    let jx = j * Vector6::from(x);
    let m = controller
        .module1
        .margins(&st.pose)
        .expect("reachable")
        .parallel;
    assert!((Vector6::from(x).norm() - 1.0).abs() < 1e-14);
    assert!((jx.norm() - m).abs() < 1e-13, "{} vs {m}", jx.norm());
}

/// The same in `f32`, against the `f64` margin: within the certified
/// `f32` tolerance, without falling back more than a few times.
#[test]
fn tracked_margin_along_the_paper_motion_f32() {
    let controller = Controller::<f32>::paper();
    let mut tracker = MarginTracker::new();
    let exact = ParallelRobot::<f64>::assumed();
    let tips = TipTargets::paper();
    let mut worst = 0f64;
    for k in 0..=4500 {
        let t = k as f64 * 1e-3;
        let out = controller
            .step(&reorientation::<f32>(t), &tips, &mut tracker)
            .expect("regular");
        let m = exact
            .margins(&reorientation::<f64>(t).pose)
            .expect("regular")
            .parallel;
        worst = worst.max((f64::from(out.module1.margins.parallel) - m).abs() / m);
    }
    let (n, full) = tracker.counts();
    println!("tracked margin, f32: largest relative difference {worst:.2e}, {full} of {n} full");
    assert!(worst < 1e-5, "{worst:e}");
    assert!(full <= 5, "{full}");
}

/// Margins tracked across jumps (random poses one after the other, no
/// continuity), through the near-double smallest singular value of the
/// symmetric pose, and up to the parallel singularity near
/// `theta = 49.7 deg`: always within the certified tolerance of the full
/// decomposition, the fallback taken where the direction does not carry.
#[test]
fn tracked_margin_certified_anywhere() {
    let mut g = ParallelGeometry::<f64>::assumed();
    g.thresholds.parallel_command = 1e-12;
    for guide in g.guides.iter_mut() {
        guide.stroke = Interval::new(f64::NEG_INFINITY, f64::INFINITY);
    }
    let robot = ParallelRobot::new(g).expect("valid");
    let tol = MarginTracker::<f64>::TOLERANCE_F64 / 2.0;
    let check = |tracker: &mut MarginTracker<f64>, pose: &Pose<f64>| -> Option<f64> {
        let exact = robot.margins(pose).ok()?.parallel;
        let frame = PlatformState::at_rest(*pose).frame().expect("finite");
        match robot.solve_tracking(&frame, tracker) {
            Ok(s) => {
                let rel = (s.margins.parallel - exact).abs() / exact;
                assert!(rel <= tol, "{pose:?}: {rel:e}");
                Some(rel)
            }
            Err(e) => panic!("{pose:?}: {e}"),
        }
    };
    // Jumps.
    let mut tracker = MarginTracker::new();
    let mut runner = TestRunner::deterministic();
    let strategy = (
        -60.0..60.0f64,
        -60.0..60.0f64,
        -560.0..-440.0f64,
        -30.0..30.0f64,
        -30.0..30.0f64,
        -90.0..-30.0f64,
    );
    let mut checked = 0;
    for _ in 0..2000 {
        let (x, y, z, a, b, c) = strategy.new_tree(&mut runner).expect("tree").current();
        let pose = Pose::from_mm_deg(x, y, z, a, b, c);
        checked += usize::from(check(&mut tracker, &pose).is_some());
    }
    let (n, full) = tracker.counts();
    assert!(checked > 1000 && n == checked as u64, "{checked} {n}");
    assert!(full > n / 2, "jumps mostly fall back: {full} of {n}");
    // Through the symmetric pose, 0.01 deg of phi per cycle.
    let mut tracker = MarginTracker::new();
    for k in 0..=2000 {
        let phi = -70.0 + 0.01 * f64::from(k);
        let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, phi);
        check(&mut tracker, &pose).expect("in reach");
    }
    assert!(tracker.counts().1 <= 20, "{:?}", tracker.counts());
    // Up to the singularity, 0.001 deg of theta per cycle.
    let mut tracker = MarginTracker::new();
    let mut smallest = f64::INFINITY;
    for k in 0..=10_000 {
        let theta = 45.0 + 1e-3 * f64::from(k);
        let pose = Pose::from_mm_deg(15.0, 20.0, -500.0, -15.0, theta, -60.0);
        if let Ok(m) = robot.margins(&pose) {
            smallest = smallest.min(m.parallel);
            check(&mut tracker, &pose);
        }
    }
    println!(
        "to the singularity: smallest margin {smallest:e}, {:?}",
        tracker.counts()
    );
    assert!(smallest < 1e-4, "{smallest}");
}

/// Rows of a reach map's grid: 0.5 deg of `psi` from one call to the next,
/// hundreds of control cycles' worth, where last call's direction alone
/// seldom certifies. Two steps of inverse iteration from it recover the
/// weakest direction without the full decomposition: every margin within
/// the certified tolerance of the full decomposition, and the full one
/// taken for the first margin of each row only.
#[test]
fn tracked_margin_across_grid_steps() {
    let robot = ParallelRobot::<f64>::assumed();
    let tol = MarginTracker::<f64>::TOLERANCE_F64 / 2.0;
    let (mut worst, mut margins, mut fulls) = (0f64, 0u64, 0u64);
    for row in 0..21 {
        let theta = -20.0 + 2.0 * f64::from(row);
        let mut tracker = MarginTracker::new();
        for col in 0..81 {
            let psi = -20.0 + 0.5 * f64::from(col);
            let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, psi, theta, -60.0);
            let Ok(exact) = robot.margins(&pose) else {
                continue;
            };
            let frame = PlatformState::at_rest(pose).frame().expect("finite");
            let s = robot
                .solve_tracking(&frame, &mut tracker)
                .expect("solvable");
            let rel = (s.margins.parallel - exact.parallel).abs() / exact.parallel;
            assert!(rel <= tol, "psi {psi}, theta {theta}: {rel:e}");
            worst = worst.max(rel);
        }
        let (n, full) = tracker.counts();
        margins += n;
        fulls += full;
    }
    println!("grid steps: {fulls} full of {margins}, largest relative difference {worst:.2e}");
    assert!(margins > 1500, "{margins}");
    assert!(fulls <= 21 + margins / 100, "{fulls} of {margins}");
}

/// A tracker started from a neighbour's direction (a grid step of 0.5 deg
/// away, scaled by 3) takes no full decomposition and gives the SVD's
/// margin within the certified tolerance; a direction of zero length or
/// with a NaN starts as a new tracker (its first margin the full one).
#[test]
fn tracker_from_a_neighbours_direction() {
    let robot = ParallelRobot::<f64>::assumed();
    let tol = MarginTracker::<f64>::TOLERANCE_F64 / 2.0;
    let at = |psi: f64, theta: f64| {
        let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, psi, theta, -60.0);
        (pose, PlatformState::at_rest(pose).frame().expect("finite"))
    };
    let mut checked = 0;
    for (psi, theta) in [(0.0, 0.0), (-10.0, 5.0), (12.0, -8.0), (15.0, 15.0)] {
        let (_, here) = at(psi, theta);
        let mut neighbour = MarginTracker::new();
        robot
            .solve_tracking(&here, &mut neighbour)
            .expect("solvable");
        let x = neighbour.weakest().expect("a direction");
        let (pose, next) = at(psi + 0.5, theta + 0.5);
        let exact = robot.margins(&pose).expect("in reach").parallel;
        let mut seeded = MarginTracker::from_direction(x.map(|v| 3.0 * v));
        let norm: f64 = seeded
            .weakest()
            .expect("seeded")
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt();
        assert!((norm - 1.0).abs() < 1e-15, "{norm}");
        let s = robot.solve_tracking(&next, &mut seeded).expect("solvable");
        assert!(
            (s.margins.parallel - exact).abs() / exact <= tol,
            "{psi}, {theta}"
        );
        assert_eq!(seeded.counts(), (1, 0), "{psi}, {theta}");
        checked += 1;
    }
    assert_eq!(checked, 4);
    for bad in [
        [0.0; 6],
        [f64::NAN, 1.0, 0.0, 0.0, 0.0, 0.0],
        [f64::INFINITY; 6],
    ] {
        let mut t = MarginTracker::from_direction(bad);
        assert_eq!(t.weakest(), None);
        let (_, frame) = at(0.0, 0.0);
        robot.solve_tracking(&frame, &mut t).expect("solvable");
        assert_eq!(t.counts(), (1, 1));
    }
}
