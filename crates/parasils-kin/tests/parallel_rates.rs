//! Module 1's rates and Jacobian: the actuators' velocities and
//! accelerations against finite differences of the IK over general motions,
//! the Jacobian mapping the platform's twist to the actuators' rates, and
//! the paper's reorientation (the actuators' range, FK back to every pose,
//! the rates against the samples' differences) in `f64` and `f32`.

use nalgebra::Vector6;
use parasils_kin::{Actuators, ParallelRobot, PlatformState, Pose, PoseRate};
use proptest::prelude::*;

mod common;
use common::module1::unlimited;
use common::motion::reorientation;

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
