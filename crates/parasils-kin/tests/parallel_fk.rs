//! Module 1's forward kinematics: from `P0`'s check values back to `P0`,
//! FK(IK(pose)) round trips near `P0` and over a wider box (with the
//! convergence statistics on a fixed seed), and the FK's error paths (the
//! Euler angles' singularity, a parallel singularity, too few iterations,
//! no solution, another branch).

use nalgebra::{Vector3, Vector6};
use parasils_kin::error::{Error, ParallelSingularity};
use parasils_kin::{
    Actuators, Branch, FkOptions, FkSolution, ParallelGeometry, ParallelRobot, Pose,
};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

mod common;
use common::module1::{Q_P0, symmetric_pose};

#[test]
fn fk_at_p0_from_the_symmetric_pose() {
    let robot = ParallelRobot::<f64>::assumed();
    let q = Actuators::new(Q_P0);
    // The table's rounded values: the pose is P0 to within their rounding.
    let fk = robot.fk(&q, &symmetric_pose()).expect("converges");
    let p = fk.pose;
    let p0 = Pose::<f64>::paper_start();
    assert!((p.position() - p0.position()).norm() < 5e-3, "{p:?}");
    for (a, b) in [(p.psi, p0.psi), (p.theta, p0.theta), (p.phi, p0.phi)] {
        assert!((a - b).abs() < 5e-5, "{p:?}");
    }
    assert!(fk.residual <= 1e-13 && fk.iterations <= 10, "{fk:?}");
}

/// A pose near `P0` and a starting guess near the pose: offsets as fractions
/// of the bounds, position and angles separately.
#[derive(Debug, Clone, Copy)]
struct FkCase {
    pose: [f64; 6],
    guess: [f64; 6],
}

/// A vector of `[-1, 1]^3` inside the unit ball.
fn in_ball() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-1.0f64..=1.0)
        .prop_map(Vector3::from)
        .prop_filter("inside the unit ball", |v| v.norm() <= 1.0)
}

/// `P0 + (dp, da)` as an array (mm, rad).
fn offset(base: &[f64; 6], dp: Vector3<f64>, da: Vector3<f64>) -> [f64; 6] {
    core::array::from_fn(|i| base[i] + if i < 3 { dp[i] } else { da[i - 3] })
}

/// The acceptance check's cases: the pose within 30 mm and 20 deg of `P0`
/// (the position offset's norm, the Euler angles' offset's norm), the guess
/// within 20 mm and 10 deg of the pose (the same norms).
fn fk_case() -> impl Strategy<Value = FkCase> {
    (in_ball(), in_ball(), in_ball(), in_ball()).prop_map(|(p, a, gp, ga)| {
        let pose = offset(
            &Pose::<f64>::paper_start().to_array(),
            p * 30.0,
            a * 20f64.to_radians(),
        );
        FkCase {
            pose,
            guess: offset(&pose, gp * 20.0, ga * 10f64.to_radians()),
        }
    })
}

/// The box reading, wider: every pose coordinate up to 30 mm or 20 deg from
/// `P0`, every guess coordinate up to 20 mm or 10 deg from the pose. Its
/// corners (34.6 deg from `P0`, guesses 17 deg away) reach within 10 deg of
/// parallel singularities.
fn fk_case_box() -> impl Strategy<Value = FkCase> {
    (
        prop::array::uniform6(-1.0f64..=1.0),
        prop::array::uniform6(-1.0f64..=1.0),
    )
        .prop_map(|(p, g)| {
            let p0 = Pose::<f64>::paper_start().to_array();
            let deg = |x: f64| x.to_radians();
            let pose: [f64; 6] =
                core::array::from_fn(|i| p0[i] + p[i] * if i < 3 { 30.0 } else { deg(20.0) });
            FkCase {
                pose,
                guess: core::array::from_fn(|i| {
                    pose[i] + g[i] * if i < 3 { 20.0 } else { deg(10.0) }
                }),
            }
        })
}

/// A forward kinematics' result with its position (mm) and angle (rad) errors.
type FkOutcome = Result<(FkSolution<f64>, f64, f64), Error>;

/// FK(IK(pose)) from the case's guess: `None` when the IK refuses the pose
/// (a stroke end), else the FK's result, with the position error (mm) and
/// the angle error (rad) of a converged one.
fn fk_round_trip(robot: &ParallelRobot<f64>, c: &FkCase) -> Option<(Actuators<f64>, FkOutcome)> {
    let q = robot.ik(&Pose::from_array(c.pose)).ok()?;
    let out = robot.fk(&q, &Pose::from_array(c.guess)).map(|fk| {
        let d = Vector6::from(fk.pose.to_array()) - Vector6::from(c.pose);
        (fk, d.fixed_rows::<3>(0).amax(), d.fixed_rows::<3>(3).amax())
    });
    Some((q, out))
}

/// The smallest parallel margin on the straight segment from the guess to
/// the pose (21 points), 0 where a point is out of reach.
fn segment_margin(robot: &ParallelRobot<f64>, c: &FkCase) -> f64 {
    (0..=20).fold(f64::INFINITY, |m, k| {
        let t = f64::from(k) / 20.0;
        let x = Pose::from_array(core::array::from_fn(|i| {
            c.guess[i] + t * (c.pose[i] - c.guess[i])
        }));
        m.min(robot.margins(&x).map_or(0.0, |mg| mg.parallel))
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 10_000,
        max_global_rejects: 100_000,
        ..ProptestConfig::default()
    })]

    #[test]
    fn fk_inverts_ik(c in fk_case()) {
        let robot = ParallelRobot::assumed();
        let Some((_, out)) = fk_round_trip(&robot, &c) else {
            return Err(TestCaseError::reject("outside the strokes"));
        };
        let (fk, pos, ang) = out.map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert!(pos < 1e-9, "position off by {pos} mm");
        prop_assert!(ang < 1e-10, "angles off by {ang} rad");
        prop_assert!(fk.residual <= 1e-13);
    }

    /// Over the wider box (per coordinate: corners up to 35 deg from P0,
    /// guesses up to 17 deg away) the pose and the guess may lie in different
    /// assembly modes, separated by a parallel singularity that no local
    /// method sees: FK may then find another genuine solution or fail, but
    /// whatever it returns satisfies the constraints, never garbage. How often
    /// it recovers the pose is asserted on a fixed seed in
    /// `fk_convergence_statistics`.
    #[test]
    fn fk_over_the_box_returns_a_solution_or_an_error(c in fk_case_box()) {
        let robot = ParallelRobot::assumed();
        let Some((q, out)) = fk_round_trip(&robot, &c) else {
            return Err(TestCaseError::reject("outside the strokes"));
        };
        if let Ok((fk, _, _)) = out {
            prop_assert!(robot.residual(&fk.pose, &q).expect("finite") < 1e-12);
            prop_assert!(fk.pose.to_array().iter().all(|v| v.is_finite()));
        }
    }
}

/// The acceptance property over 10^4 cases (a fixed seed), with the
/// statistics the report quotes (run with `--nocapture` to see them), and
/// the box reading's share of other assembly modes.
#[test]
fn fk_convergence_statistics() {
    let robot = ParallelRobot::assumed();
    let mut runner = TestRunner::deterministic();
    let (mut n, mut rejected) = (0u32, 0u32);
    let (mut pos_max, mut ang_max, mut res_max) = (0f64, 0f64, 0f64);
    let mut histogram = [0u32; 13];
    let strategy = fk_case();
    while n < 10_000 {
        let c = strategy.new_tree(&mut runner).expect("a case").current();
        let Some((_, out)) = fk_round_trip(&robot, &c) else {
            rejected += 1;
            continue;
        };
        let (fk, pos, ang) = out.expect("converges");
        n += 1;
        pos_max = pos_max.max(pos);
        ang_max = ang_max.max(ang);
        res_max = res_max.max(fk.residual);
        histogram[(fk.iterations as usize).min(12)] += 1;
    }
    println!(
        "FK(IK(pose)) over {n} poses ({rejected} outside the strokes): \
         max error {pos_max:.3e} mm, {ang_max:.3e} rad, max residual {res_max:.3e}; \
         iterations [0, 1, ..., 11, >= 12]: {histogram:?}"
    );
    assert!(pos_max < 1e-9 && ang_max < 1e-10);
    let strategy = fk_case_box();
    let (mut n, mut other, mut failed, mut max_it) = (0u32, 0u32, 0u32, 0u32);
    // The largest parallel margin along the guess-to-pose segment among the
    // cases that found another solution.
    let mut worst_segment = 0f64;
    while n < 10_000 {
        let c = strategy.new_tree(&mut runner).expect("a case").current();
        let Some((_, out)) = fk_round_trip(&robot, &c) else {
            continue;
        };
        n += 1;
        match out {
            Ok((fk, pos, ang)) => {
                max_it = max_it.max(fk.iterations);
                if pos > 1e-9 || ang > 1e-10 {
                    other += 1;
                    worst_segment = worst_segment.max(segment_margin(&robot, &c));
                }
            }
            Err(_) => failed += 1,
        }
    }
    println!(
        "box reading over {n} poses: {other} other assembly modes, {failed} failures, \
         at most {max_it} iterations; largest segment margin among the others {worst_segment:.4}"
    );
    // Measured on this seed: 12 of 10^4 (0.12%), each with a parallel margin
    // below 0.0064 somewhere on the straight path from the guess to the
    // pose. (Other seeds have shown rare cases above 0.01: the segment is
    // only a proxy for the path Newton takes.)
    assert!(
        other + failed <= n / 500,
        "{other} other modes and {failed} failures in {n}"
    );
    assert!(worst_segment < 0.01, "{worst_segment}");
}

#[test]
fn euler_singular_guess() {
    let robot = ParallelRobot::<f64>::assumed();
    let q = robot.ik(&Pose::paper_start()).expect("reachable");
    let guess = Pose::from_mm_deg(15.0, 20.0, -500.0, -15.0, 90.0, -60.0);
    match robot.fk(&q, &guess) {
        Err(Error::SingularJacobian {
            kind: ParallelSingularity::EulerAngles,
            iteration: 0,
            margin,
            ..
        }) => assert!(margin < 1e-15),
        other => panic!("{other:?}"),
    }
    let guess = Pose::from_mm_deg(15.0, 20.0, -500.0, -15.0, -90.0, -60.0);
    let e = robot.fk(&q, &guess).expect_err("singular");
    assert!(e.to_string().contains("theta = +-90 deg"), "{e}");
}

#[test]
fn parallel_singular_geometry() {
    // All three nodes at one point: locked actuators leave the platform
    // free to turn about it, a parallel singularity everywhere.
    let mut g = ParallelGeometry::<f64>::assumed();
    g.nodes = [Vector3::new(0.0, 0.0, 100.0); 3];
    let robot = ParallelRobot::new(g).expect("valid geometry");
    let pose = Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, 0.0);
    let m = robot.margins(&pose).expect("in reach");
    assert!(m.parallel < 1e-12, "{m:?}");
    let q = robot.ik(&pose).expect("in reach");
    let guess = Pose::from_mm_deg(1.0, 0.0, -500.0, 0.0, 0.0, 0.0);
    match robot.fk(&q, &guess) {
        Err(Error::SingularJacobian {
            kind: ParallelSingularity::Parallel,
            iteration: 0,
            margin,
            threshold,
        }) => assert!(margin < threshold),
        other => panic!("{other:?}"),
    }
}

#[test]
fn fk_without_enough_iterations() {
    let robot = ParallelRobot::<f64>::assumed();
    let q = robot.ik(&Pose::paper_start()).expect("reachable");
    let options = FkOptions {
        tolerance: 1e-13,
        max_iterations: 2,
    };
    match robot.fk_with(&q, &symmetric_pose(), &options) {
        Err(Error::NoConvergence {
            iterations: 2,
            residual,
        }) => assert!(residual > 1e-13 && residual.is_finite()),
        other => panic!("{other:?}"),
    }
    let bad = FkOptions {
        tolerance: f64::NAN,
        max_iterations: 5,
    };
    assert!(matches!(
        robot.fk_with(&q, &symmetric_pose(), &bad),
        Err(Error::InvalidParameter { .. })
    ));
}

#[test]
fn fk_far_from_any_solution_fails_cleanly() {
    let robot = ParallelRobot::<f64>::assumed();
    // Actuators no pose can satisfy (q1 and q2 far apart on a narrow leg).
    let q = Actuators::new([0.0, 320.0, 0.0, 320.0, 0.0, 320.0]);
    let e = robot.fk(&q, &symmetric_pose()).expect_err("no pose");
    assert!(
        matches!(
            e,
            Error::NoConvergence { .. }
                | Error::SingularJacobian { .. }
                | Error::BranchMismatch { .. }
        ),
        "{e:?}"
    );
    if let Error::NoConvergence { residual, .. } = e {
        assert!(!residual.is_nan());
    }
}

#[test]
fn fk_reports_another_branch() {
    let robot = ParallelRobot::<f64>::assumed();
    let q = robot.ik(&Pose::paper_start()).expect("reachable");
    let mut g = ParallelGeometry::<f64>::assumed();
    g.guides[3].branch = Branch::Minus;
    let other = ParallelRobot::new(g).expect("valid");
    assert!(matches!(
        other.fk(&q, &Pose::paper_start()),
        Err(Error::BranchMismatch { actuator: 4 })
    ));
}
