//! Module 1, the parallel robot, against independent truths: the check values
//! of `docs/model.md` (*Check values*), FK(IK) round trips, finite differences of the
//! actuators, the reorientation of the paper, the controller, and every error
//! path.

use nalgebra::{Vector3, Vector6};
use parasils_kin::error::{Error, ParallelSingularity};
use parasils_kin::instrument::Interval;
use parasils_kin::parallel::SymmetricLayout;
use parasils_kin::{
    Actuators, Branch, Controller, FkOptions, FkSolution, MarginTracker, ParallelGeometry,
    ParallelRobot, PlatformFrame, PlatformState, Pose, PoseRate, Real, RobotGeometry, TipTargets,
};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

mod common;
use common::reorientation;

/// `docs/model.md`, *Check values*: the actuators at `P0`, mm.
const Q_P0: [f64; 6] = [117.942, 151.459, 56.937, 89.428, 132.193, 77.441];
/// `docs/model.md`, *Check values*: every actuator at the symmetric pose, mm.
const Q_SYMMETRIC: f64 = 92.754;

fn symmetric_pose<T: Real>() -> Pose<T> {
    Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, -60.0)
}

fn to_f64<T: Real>(q: &Actuators<T>) -> [f64; 6] {
    q.0.map(|v| v.to_f64())
}

/// The robot with unlimited strokes, for the properties that test the
/// kinematics and not the (assumed) strokes.
fn unlimited() -> ParallelRobot<f64> {
    let mut g = ParallelGeometry::assumed();
    for guide in g.guides.iter_mut() {
        guide.stroke = Interval::new(f64::NEG_INFINITY, f64::INFINITY);
    }
    ParallelRobot::new(g).expect("valid geometry")
}

mod check_values {
    use super::*;

    fn check<T: Real>(tol: f64) {
        let robot = ParallelRobot::<T>::assumed();
        let q = to_f64(&robot.ik(&symmetric_pose()).expect("reachable"));
        for (j, qj) in q.iter().enumerate() {
            assert!(
                (qj - Q_SYMMETRIC).abs() < tol,
                "symmetric pose: q{} = {qj}",
                j + 1
            );
        }
        let q = to_f64(&robot.ik(&Pose::paper_start()).expect("reachable"));
        for j in 0..6 {
            assert!(
                (q[j] - Q_P0[j]).abs() < tol,
                "P0: q{} = {}, expected {}",
                j + 1,
                q[j],
                Q_P0[j]
            );
        }
    }

    #[test]
    fn symmetric_pose_and_p0_in_f64() {
        // The table prints three decimals.
        check::<f64>(5e-4);
    }

    #[test]
    fn symmetric_pose_and_p0_in_f32() {
        check::<f32>(6e-4);
    }

    #[test]
    fn symmetric_pose_is_exactly_symmetric() {
        let q = ParallelRobot::<f64>::assumed()
            .ik(&symmetric_pose())
            .expect("reachable");
        // 400 - sqrt(94400), from |r|^2 = 188100 and l^2 = 122500.
        let exact = 400.0 - 94_400f64.sqrt();
        for qj in q.0 {
            assert!((qj - exact).abs() < 1e-12, "{qj} vs {exact}");
        }
    }

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
    fn guide_directions_are_normalised() {
        let mut g = ParallelGeometry::<f64>::assumed();
        for guide in g.guides.iter_mut() {
            guide.direction *= 2.5;
        }
        let robot = ParallelRobot::new(g).expect("valid");
        assert!((robot.geometry().guides[3].direction.norm() - 1.0).abs() < 1e-15);
        let q = robot.ik(&Pose::paper_start()).expect("reachable");
        let q0 = ParallelRobot::<f64>::assumed()
            .ik(&Pose::paper_start())
            .expect("reachable");
        assert!((0..6).all(|j| (q[j] - q0[j]).abs() < 1e-12));
    }

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

/// A general motion: every platform coordinate a quadratic in `t`, so that
/// the rates at `t` are exactly known.
#[derive(Debug, Clone, Copy)]
struct Motion {
    pose: [f64; 6],
    rate: [f64; 6],
    acc: [f64; 6],
}

fn motion() -> impl Strategy<Value = Motion> {
    (
        prop::array::uniform6(-1.0f64..=1.0),
        prop::array::uniform6(-1.0f64..=1.0),
        prop::array::uniform6(-1.0f64..=1.0),
    )
        .prop_map(|(p, r, a)| {
            let p0 = Pose::<f64>::paper_start().to_array();
            let deg20 = 20f64.to_radians();
            Motion {
                pose: core::array::from_fn(|i| p0[i] + if i < 3 { 30.0 } else { deg20 } * p[i]),
                // Tens of mm/s and deg/s: the paper's order of magnitude and more;
                // the linear rates exercise Pdot (motion type 1).
                rate: core::array::from_fn(|i| if i < 3 { 50.0 } else { deg20 } * r[i]),
                acc: core::array::from_fn(|i| if i < 3 { 50.0 } else { deg20 } * a[i]),
            }
        })
}

impl Motion {
    fn state(&self, t: f64) -> PlatformState<f64> {
        let p: [f64; 6] =
            core::array::from_fn(|i| self.pose[i] + self.rate[i] * t + 0.5 * self.acc[i] * t * t);
        let v: [f64; 6] = core::array::from_fn(|i| self.rate[i] + self.acc[i] * t);
        let a = self.acc;
        PlatformState {
            pose: Pose::from_array(p),
            velocity: PoseRate::new(v[0], v[1], v[2], v[3], v[4], v[5]),
            acceleration: PoseRate::new(a[0], a[1], a[2], a[3], a[4], a[5]),
        }
    }
}

/// `|fd - analytic|_inf / max(|analytic|_inf, floor)` over the six actuators.
fn rel_err(fd: &[f64; 6], analytic: &Actuators<f64>, floor: f64) -> f64 {
    let err = (0..6).fold(0f64, |m, j| m.max((fd[j] - analytic[j]).abs()));
    err / analytic.amax().max(floor)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10_000))]

    #[test]
    fn rates_match_finite_differences(mo in motion()) {
        let robot = unlimited();
        // Five-point central differences (truncation O(h^4)), with a time
        // step shortened near a serial singularity, where the actuators'
        // higher derivatives grow as powers of 1 / margin: with the square of
        // the margin, so that the truncation error stays below the bound as
        // the margin shrinks (a margin of 0.046 gave 5e-8 with a linear
        // shortening).
        let Ok(margins) = robot.margins(&mo.state(0.0).pose) else {
            return Err(TestCaseError::reject("out of reach"));
        };
        let h = 1e-3 * (2.0 * margins.serial_min).min(1.0).powi(2);
        let solve = |k: f64| robot.solve_state(&mo.state(k * h));
        let (Ok(s0), Ok(p1), Ok(m1), Ok(p2), Ok(m2)) =
            (solve(0.0), solve(1.0), solve(-1.0), solve(2.0), solve(-2.0))
        else {
            return Err(TestCaseError::reject("out of reach"));
        };
        let d1 = |p2: f64, p1: f64, m1: f64, m2: f64| (-p2 + 8.0 * p1 - 8.0 * m1 + m2) / (12.0 * h);
        let qd_fd: [f64; 6] = core::array::from_fn(|j| d1(p2.q[j], p1.q[j], m1.q[j], m2.q[j]));
        let qdd_from_rates: [f64; 6] = core::array::from_fn(|j| {
            d1(p2.q_dot[j], p1.q_dot[j], m1.q_dot[j], m2.q_dot[j])
        });
        let qdd_fd: [f64; 6] = core::array::from_fn(|j| {
            (-p2.q[j] + 16.0 * p1.q[j] - 30.0 * s0.q[j] + 16.0 * m1.q[j] - m2.q[j])
                / (12.0 * h * h)
        });
        let e1 = rel_err(&qd_fd, &s0.q_dot, 1.0);
        let e2 = rel_err(&qdd_from_rates, &s0.q_ddot, 1.0);
        let e3 = rel_err(&qdd_fd, &s0.q_ddot, 1.0);
        prop_assert!(e1 < 1e-8, "qdot vs FD of q: relative error {e1}");
        prop_assert!(e2 < 1e-8, "qddot vs FD of qdot: relative error {e2}");
        // The second difference divides rounding of the positions by h^2:
        // (1 + 16 + 30 + 16 + 1) / 12 eps |q| / h^2 at most, which the
        // shortened step near a serial singularity makes larger than the
        // truncation error; the bound adds it to 1e-6.
        let q_max = s0.q.0.iter().fold(1.0_f64, |m, q| m.max(q.abs()));
        let rounding = 64.0 / 12.0 * f64::EPSILON * q_max / (h * h);
        prop_assert!(e3 < 1e-6 + rounding, "qddot vs second FD of q: relative error {e3} (rounding bound {rounding})");
        // rates() from the IK's actuators is the same computation as solve().
        let frame = mo.state(0.0).frame().expect("finite");
        let (qd, qdd) = robot.rates(&frame, &s0.q).expect("regular");
        prop_assert!(rel_err(&qd.0, &s0.q_dot, 1.0) < 1e-12);
        prop_assert!(rel_err(&qdd.0, &s0.q_ddot, 1.0) < 1e-12);
    }

    #[test]
    fn jacobian_maps_the_twist_to_the_actuator_rates(mo in motion()) {
        let robot = unlimited();
        let st = mo.state(0.0);
        let Ok(sol) = robot.solve_state(&st) else {
            return Err(TestCaseError::reject("out of reach"));
        };
        let frame = st.frame().expect("finite");
        let omega_fixed = frame.rotation * frame.omega;
        let l = robot.length_scale();
        let twist = Vector6::new(
            frame.velocity.x,
            frame.velocity.y,
            frame.velocity.z,
            l * omega_fixed.x,
            l * omega_fixed.y,
            l * omega_fixed.z,
        );
        let lhs = robot.jacobian(&st.pose).expect("reachable") * twist;
        for j in 0..6 {
            // Branch +1: e.u > 0, so e.u / l is the serial margin.
            let rhs = sol.margins.serial[j] * sol.q_dot[j];
            prop_assert!((lhs[j] - rhs).abs() < 1e-9 * (1.0 + rhs.abs()), "row {j}: {} vs {rhs}", lhs[j]);
        }
    }
}

#[test]
fn along_the_reorientation_f64() {
    let robot = ParallelRobot::<f64>::assumed();
    let (mut q_min, mut q_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut serial_min, mut parallel_min) = (f64::INFINITY, f64::INFINITY);
    let (mut pos_err, mut ang_err, mut max_it) = (0f64, 0f64, 0u32);
    let mut previous = reorientation::<f64>(0.0).pose;
    let mut previous_q: Option<Actuators<f64>> = None;
    let mut fd_err = 0f64;
    for k in 0..=4500 {
        let st = reorientation::<f64>(f64::from(k) / 1000.0);
        let sol = robot.solve_state(&st).expect("regular all along");
        let parallel = [sol.margins.parallel];
        let all = sol
            .q
            .0
            .iter()
            .chain(&sol.q_dot.0)
            .chain(&sol.q_ddot.0)
            .chain(&sol.margins.serial)
            .chain(&parallel);
        assert!(all.into_iter().all(|v| v.is_finite()), "at sample {k}");
        for qj in sol.q.0 {
            q_min = q_min.min(qj);
            q_max = q_max.max(qj);
        }
        serial_min = serial_min.min(sol.margins.serial_min);
        parallel_min = parallel_min.min(sol.margins.parallel);
        // FK from the actuators, seeded with the previous sample's pose.
        let fk = robot.fk(&sol.q, &previous).expect("converges");
        let d = Vector6::from(fk.pose.to_array()) - Vector6::from(st.pose.to_array());
        pos_err = pos_err.max(d.fixed_rows::<3>(0).amax());
        ang_err = ang_err.max(d.fixed_rows::<3>(3).amax());
        max_it = max_it.max(fk.iterations);
        previous = fk.pose;
        // The rates against a backward difference of the samples (1 ms).
        if let Some(q_prev) = previous_q {
            let prev = robot.solve_state(&reorientation(f64::from(k - 1) / 1000.0));
            let qd_prev = prev.expect("regular").q_dot;
            for j in 0..6 {
                let fd = (sol.q[j] - q_prev[j]) / 1e-3;
                let mid = 0.5 * (sol.q_dot[j] + qd_prev[j]);
                fd_err = fd_err.max((fd - mid).abs());
            }
        }
        previous_q = Some(sol.q);
    }
    println!(
        "reorientation: q in [{q_min:.3}, {q_max:.3}] mm, serial margin >= {serial_min:.4}, \
         parallel margin >= {parallel_min:.4}; FK seeded with the previous pose: \
         max error {pos_err:.3e} mm, {ang_err:.3e} rad, at most {max_it} iterations; \
         max |dq/dt (1 ms) - mean qdot| = {fd_err:.3e} mm/s"
    );
    // `docs/model.md`, *Module 1, the parallel robot*: roughly 50-210 mm,
    // away from both singularities.
    assert!(q_min > 40.0 && q_max < 220.0);
    assert!(serial_min > 0.5 && parallel_min > 0.1);
    assert!(pos_err < 1e-9 && ang_err < 1e-10);
    assert!(fd_err < 1e-4, "{fd_err}");
}

#[test]
fn along_the_reorientation_f32() {
    let robot = ParallelRobot::<f32>::assumed();
    let robot64 = ParallelRobot::<f64>::assumed();
    let mut previous = reorientation::<f32>(0.0).pose;
    let (mut q_err, mut pos_err, mut ang_err) = (0f64, 0f64, 0f64);
    for k in (0..=4500).step_by(10) {
        let t = f64::from(k) / 1000.0;
        let st = reorientation::<f32>(t);
        let sol = robot.solve_state(&st).expect("regular all along");
        let sol64 = robot64.solve_state(&reorientation(t)).expect("regular");
        for j in 0..6 {
            q_err = q_err.max((f64::from(sol.q[j]) - sol64.q[j]).abs());
        }
        assert!(sol.q_ddot.0.iter().all(|v| v.is_finite()));
        let fk = robot.fk(&sol.q, &previous).expect("converges in f32");
        let d: [f64; 6] = core::array::from_fn(|i| {
            f64::from(fk.pose.to_array()[i]) - f64::from(st.pose.to_array()[i])
        });
        pos_err = pos_err.max(d[..3].iter().fold(0f64, |m, v| m.max(v.abs())));
        ang_err = ang_err.max(d[3..].iter().fold(0f64, |m, v| m.max(v.abs())));
        previous = fk.pose;
    }
    println!(
        "f32 reorientation: |q - q_f64| <= {q_err:.3e} mm; FK off by {pos_err:.3e} mm, {ang_err:.3e} rad"
    );
    assert!(q_err < 1e-3, "{q_err}");
    assert!(pos_err < 2e-2 && ang_err < 1e-4, "{pos_err} {ang_err}");
}

mod controller {
    use super::*;

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
            let rel = (out.module1.margins.parallel - exact.margins.parallel).abs()
                / exact.margins.parallel;
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
        println!(
            "tracked margin, f32: largest relative difference {worst:.2e}, {full} of {n} full"
        );
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
        let st =
            PlatformState::at_rest(Pose::from_mm_deg(15.0, -450.0, -500.0, -15.0, 10.0, -60.0));
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
}

mod bad_inputs {
    use super::*;

    #[test]
    fn pose_out_of_reach_names_the_actuator() {
        let robot = ParallelRobot::<f64>::assumed();
        // Sideways by 450 mm towards -Y: leg 1's node (at Y = 150 mm in the
        // symmetric pose) is 386 mm from the lines of its guides (at Y = 200).
        let pose = Pose::from_mm_deg(0.0, -450.0, -500.0, 0.0, 0.0, -60.0);
        let e = robot.ik(&pose).expect_err("out of reach");
        match e {
            Error::LegOutOfReach {
                actuator: 1,
                discriminant,
            } => {
                // l^2 - |r_perp|^2 with r_perp = (-160, -500) mm.
                let expected = 350f64.powi(2) - 160f64.powi(2) - 500f64.powi(2);
                assert!((discriminant - expected).abs() < 1e-6, "{discriminant}");
            }
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().contains("actuator q1"), "{e}");
        // Towards +X: leg 1's node is 661 mm from q2's guide line (at X = -160 mm).
        let e = robot
            .ik(&Pose::from_mm_deg(500.0, 0.0, -500.0, 0.0, 0.0, -60.0))
            .expect_err("out of reach");
        assert!(
            matches!(e, Error::LegOutOfReach { actuator: 2, .. }),
            "{e:?}"
        );
        // margins(), solve() and the rates fail the same way, not with NaN.
        assert!(robot.margins(&pose).is_err());
        let frame = PlatformState::at_rest(pose).frame().expect("finite");
        assert!(matches!(
            robot.solve(&frame),
            Err(Error::LegOutOfReach { actuator: 1, .. })
        ));
    }

    #[test]
    fn actuator_beyond_its_stroke() {
        let robot = ParallelRobot::<f64>::assumed();
        // Raised by 100 mm from the symmetric pose: q = 300 - sqrt(94400) < 0.
        let pose = Pose::from_mm_deg(0.0, 0.0, -400.0, 0.0, 0.0, -60.0);
        let e = robot.ik(&pose).expect_err("beyond the stroke");
        match e {
            Error::ActuatorLimit {
                actuator: 1,
                value,
                min,
                max,
            } => {
                assert!((value - (300.0 - 94_400f64.sqrt())).abs() < 1e-9);
                assert!(min.abs() < 1e-15 && (max - 320.0).abs() < 1e-12);
            }
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().contains("q1 = -7.24583 mm"), "{e}");
        // solve() checks the strokes too; ik_unchecked() does not.
        let frame = PlatformState::at_rest(pose).frame().expect("finite");
        assert!(matches!(
            robot.solve(&frame),
            Err(Error::ActuatorLimit { actuator: 1, .. })
        ));
        assert!(robot.ik_unchecked(&pose).expect("in reach")[0] < 0.0);
        // The margin to the stroke is reported, negative.
        assert!(robot.margins(&pose).expect("in reach").stroke[0] < -7.0);
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

    #[test]
    fn non_finite_values_are_named() {
        let robot = ParallelRobot::<f64>::assumed();
        let mut pose = Pose::paper_start();
        pose.theta = f64::NAN;
        assert!(matches!(
            robot.ik(&pose),
            Err(Error::NonFinite {
                what: "pose.theta",
                ..
            })
        ));
        let q = robot.ik(&Pose::paper_start()).expect("reachable");
        let mut bad_q = q;
        bad_q.0[4] = f64::INFINITY;
        assert!(matches!(
            robot.fk(&bad_q, &Pose::paper_start()),
            Err(Error::NonFinite { what: "q5", .. })
        ));
        assert!(matches!(
            robot.fk(&q, &pose),
            Err(Error::NonFinite {
                what: "pose.theta",
                ..
            })
        ));
        let mut st = PlatformState::at_rest(Pose::paper_start());
        st.velocity.x = f64::NAN;
        assert!(matches!(
            robot.solve_state(&st),
            Err(Error::NonFinite {
                what: "velocity.x",
                ..
            })
        ));
        let frame = PlatformFrame::new(&PlatformState::at_rest(Pose::paper_start()));
        assert!(matches!(
            robot.rates(&frame, &bad_q),
            Err(Error::NonFinite { what: "q5", .. })
        ));
        assert!(robot.residual(&pose, &q).is_err());
        // A frame built without the check is refused, not turned into NaN.
        let mut st = PlatformState::at_rest(Pose::paper_start());
        st.acceleration.psi = f64::NAN;
        let unchecked = PlatformFrame::new(&st);
        assert!(matches!(
            robot.solve(&unchecked),
            Err(Error::NonFinite { what: "frame", .. })
        ));
        assert!(matches!(
            robot.rates(&unchecked, &q),
            Err(Error::NonFinite { what: "frame", .. })
        ));
    }

    #[test]
    fn invalid_geometries_are_named() {
        type Spoil = fn(&mut ParallelGeometry<f64>);
        let cases: [(Spoil, &str); 8] = [
            (
                |g| g.guides[2].direction = Vector3::zeros(),
                "module1.guides[2].direction",
            ),
            (
                |g| g.guides[5].link_length = -1.0,
                "module1.guides[5].link_length",
            ),
            (
                |g| g.guides[0].stroke = Interval::new(10.0, 0.0),
                "module1.guides[0].stroke",
            ),
            (
                |g| g.guides[1].point.y = f64::NAN,
                "module1.guides[1].point.y",
            ),
            (|g| g.nodes[2].z = f64::INFINITY, "module1.nodes[2].z"),
            (|g| g.nodes = [Vector3::zeros(); 3], "module1.nodes"),
            (|g| g.thresholds.serial = 0.0, "module1.thresholds.serial"),
            (|g| g.fk.max_iterations = 0, "module1.fk.max_iterations"),
        ];
        for (spoil, name) in cases {
            let mut g = ParallelGeometry::assumed();
            spoil(&mut g);
            match ParallelRobot::new(g) {
                Err(Error::InvalidParameter { what, .. } | Error::NonFinite { what, .. }) => {
                    assert_eq!(what, name);
                }
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}

#[test]
fn layout_builds_the_assumed_geometry() {
    let g = ParallelGeometry::<f64>::from_layout(&SymmetricLayout::assumed());
    assert!(!g.assumed);
    let a = ParallelGeometry::<f64>::assumed();
    for j in 0..6 {
        let (x, y) = (&g.guides[j], &a.guides[j]);
        assert!((x.point - y.point).norm() < 1e-12, "guide {j}");
        assert_eq!(
            (x.direction, x.link_length, x.branch, x.stroke),
            (y.direction, y.link_length, y.branch, y.stroke)
        );
    }
    for i in 0..3 {
        assert!((g.nodes[i] - a.nodes[i]).norm() < 1e-12, "node {i}");
    }
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
