//! Motion type 4 timed for the actuators' limits: the path's derivatives
//! against finite differences, the paper's trapezoid against the assumed
//! limits, and the time-optimal law through the controller.

use parasils::Reorientation;
use parasils::geometry::RobotState;
use parasils::kin::{
    ACTUATOR_COUNT, Actuator, ActuatorLimits, ControlStep, Controller, LimitError, MarginTracker,
    Pose, RateKind, TipTargets, step_positions, step_rates,
};
use parasils::path::{MotionPath, PATH_ROWS, row_limits};
use parasils::traj::Limits;
use parasils::traj::Motion;
use parasils::traj::optimal::{self, Knot, Schedule};
use proptest::prelude::*;

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// The turn by `increment` (rad) from `pose`, tips held at `tips`.
fn turn(
    pose: Pose<f64>,
    increment: [f64; 2],
    tips: &TipTargets<f64>,
) -> core::result::Result<MotionPath<f64>, parasils::kin::Error> {
    let c = Controller::paper();
    let start = RobotState::solved(&c, pose, tips, 0.0)?;
    let goal = [pose.psi + increment[0], pose.theta + increment[1]];
    Ok(MotionPath::turning(
        &c,
        &start,
        goal,
        [tips.left, tips.right],
    ))
}

fn paper_path() -> MotionPath<f64> {
    turn(
        Pose::paper_start(),
        [15f64.to_radians(), 25f64.to_radians()],
        &TipTargets::paper(),
    )
    .expect("the paper's start is in reach")
}

/// The largest `|rate| / limit` of each actuator over a run of control steps.
fn peaks(steps: &[ControlStep<f64>], limits: &ActuatorLimits<f64>) -> ([f64; 12], [f64; 12]) {
    let mut pv = [0.0_f64; 12];
    let mut pa = [0.0_f64; 12];
    for step in steps {
        let (v, a) = limits.usage(step);
        for k in 0..ACTUATOR_COUNT {
            pv[k] = pv[k].max(v[k]);
            pa[k] = pa[k].max(a[k]);
        }
    }
    (pv, pa)
}

fn trapezoid_steps() -> Result<Vec<ControlStep<f64>>> {
    let c = Controller::paper();
    let mut tracker = MarginTracker::new();
    let tips = TipTargets::paper();
    let mut out = Vec::new();
    for sample in Reorientation::<f64>::paper()?.sampler(1000.0)? {
        out.push(c.step(&sample.state, &tips, &mut tracker)?);
    }
    Ok(out)
}

/// The optimal schedule's states at `rate_hz` through the controller.
fn optimal_steps(
    path: &MotionPath<f64>,
    schedule: &Schedule<'_, f64, PATH_ROWS>,
    rate_hz: f64,
) -> Result<Vec<(f64, ControlStep<f64>)>> {
    let c = Controller::paper();
    let mut tracker = MarginTracker::new();
    let mut out = Vec::new();
    for sample in schedule.sampler(rate_hz)? {
        let st = sample.state;
        let at = path.sample(st.position, st.velocity, st.acceleration);
        let step = c.step_commanded(&at.platform, &at.left, &at.right, &mut tracker)?;
        out.push((sample.time, step));
    }
    Ok(out)
}

#[test]
fn path_derivatives_match_finite_differences_of_the_positions() -> Result {
    let path = paper_path();
    let h = 1e-4;
    // The path is defined on [0, 1] (its end is the target exactly): at
    // s = 1 the differences are one-sided, of second order like the
    // central ones.
    for s in [0.0, 0.1, 0.37, 0.5, 0.81, 1.0] {
        let p = path.point(s)?;
        let q = |x: f64| path.point(x).map(|p| p.q);
        let (d1s, d2s): ([f64; ACTUATOR_COUNT], [f64; ACTUATOR_COUNT]) = if s + h > 1.0 {
            let (a, b, c) = (q(s - h)?, q(s - 2.0 * h)?, q(s - 3.0 * h)?);
            (
                core::array::from_fn(|k| (3.0 * p.q[k] - 4.0 * a[k] + b[k]) / (2.0 * h)),
                core::array::from_fn(|k| (2.0 * p.q[k] - 5.0 * a[k] + 4.0 * b[k] - c[k]) / (h * h)),
            )
        } else {
            let (m, pl) = (q(s - h)?, q(s + h)?);
            (
                core::array::from_fn(|k| (pl[k] - m[k]) / (2.0 * h)),
                core::array::from_fn(|k| (pl[k] - 2.0 * p.q[k] + m[k]) / (h * h)),
            )
        };
        for k in 0..ACTUATOR_COUNT {
            let (d1, d2) = (d1s[k], d2s[k]);
            let scale1 = p.q_s.iter().fold(1e-3_f64, |a, b| a.max(b.abs()));
            let scale2 = p.q_ss.iter().fold(1e-3_f64, |a, b| a.max(b.abs()));
            assert!(
                (d1 - p.q_s[k]).abs() < 1e-6 * scale1,
                "{} at s = {s}: q' = {} vs {d1}",
                Actuator::ALL[k],
                p.q_s[k]
            );
            assert!(
                (d2 - p.q_ss[k]).abs() < 1e-4 * scale2,
                "{} at s = {s}: q'' = {} vs {d2}",
                Actuator::ALL[k],
                p.q_ss[k]
            );
        }
    }
    Ok(())
}

#[test]
fn paper_trapezoid_stays_within_the_assumed_limits() -> Result {
    let limits = ActuatorLimits::assumed();
    let steps = trapezoid_steps()?;
    for s in &steps {
        limits.check(s)?;
    }
    let (pv, pa) = peaks(&steps, &limits);
    for k in 0..ACTUATOR_COUNT {
        println!(
            "{:>12}: velocity {:.4}, acceleration {:.4} of the limit",
            Actuator::ALL[k].to_string(),
            pv[k],
            pa[k]
        );
    }
    Ok(())
}

#[test]
fn paper_optimal_law_is_feasible_at_1_khz_and_faster_than_the_trapezoid() -> Result {
    let path = paper_path();
    let actuators = ActuatorLimits::assumed();
    let limits = row_limits(&actuators, None);
    let mut knots = vec![Knot::default(); 1000];
    let (schedule, cert) = optimal::plan(&path, &limits, &mut knots, 10)?;
    println!("duration {} s, certificate {cert:?}", schedule.duration());
    for ph in schedule.phases(&limits) {
        println!(
            "{ph} usage {} ({})",
            ph.usage,
            Actuator::from_index(ph.row).map_or("angle".into(), |a| a.to_string())
        );
    }
    let steps = optimal_steps(&path, &schedule, 1000.0)?;
    let mut worst = 0.0_f64;
    for (_, s) in &steps {
        let (v, a) = actuators.usage(s);
        worst = worst.max(v.iter().chain(&a).fold(0.0, |m, x| m.max(*x)));
    }
    println!("worst use at 1 kHz {worst}");
    assert!(worst <= 1.0 + 1e-9, "worst use {worst}");
    assert!(schedule.duration() < 4.5);
    Ok(())
}

/// The worst use of any actuator limit over a run.
fn worst_use(steps: &[(f64, ControlStep<f64>)], limits: &ActuatorLimits<f64>) -> f64 {
    let mut worst = 0.0_f64;
    for (_, s) in steps {
        let (v, a) = limits.usage(s);
        worst = worst.max(v.iter().chain(&a).fold(0.0, |m, x| m.max(*x)));
    }
    worst
}

#[test]
fn optimal_law_holds_the_tips_stays_on_the_line_and_rests_at_both_ends() -> Result {
    let path = paper_path();
    let limits = row_limits(&ActuatorLimits::assumed(), None);
    let mut knots = vec![Knot::default(); 1000];
    let (schedule, _) = optimal::plan(&path, &limits, &mut knots, 10)?;
    let rate = 1000.0;
    let steps = optimal_steps(&path, &schedule, rate)?;
    let c = Controller::<f64>::paper();
    let tips = TipTargets::paper();
    let p0 = Pose::<f64>::paper_start();
    let (dpsi, dtheta): (f64, f64) = (15f64.to_radians(), 25f64.to_radians());
    for (_, s) in &steps {
        let left = s.frame.to_fixed(&c.left.fk_platform(&s.left.q));
        let right = s.frame.to_fixed(&c.right.fk_platform(&s.right.q));
        assert!((left - tips.left).norm() < 1e-9 && (right - tips.right).norm() < 1e-9);
    }
    // The platform's Euler angles along the run, from the schedule.
    for sample in schedule.sampler(rate)? {
        let st = path
            .sample(
                sample.state.position,
                sample.state.velocity,
                sample.state.acceleration,
            )
            .platform;
        let a = (st.pose.psi - p0.psi) / dpsi;
        let b = (st.pose.theta - p0.theta) / dtheta;
        assert!((a - b).abs() < 1e-12, "off the line at t = {}", sample.time);
        assert_eq!(
            (st.pose.x, st.pose.y, st.pose.z, st.pose.phi),
            (p0.x, p0.y, p0.z, p0.phi)
        );
    }
    // At rest at both ends, and every actuator too.
    let (first, last) = (&steps[0].1, &steps[steps.len() - 1].1);
    for step in [first, last] {
        let (v, _) = step_rates(step);
        assert!(v.iter().all(|x| *x == 0.0), "{v:?}");
    }
    // The rate columns against finite differences of the positions (central,
    // at 1 kHz): within the acceleration limit times the sample period.
    let dt = 1.0 / rate;
    for w in steps.windows(3) {
        let (q0, q2) = (step_positions(&w[0].1), step_positions(&w[2].1));
        let (v1, _) = step_rates(&w[1].1);
        let h = w[2].0 - w[0].0;
        for k in 0..ACTUATOR_COUNT {
            let fd = (q2[k] - q0[k]) / h;
            let tol = ActuatorLimits::<f64>::assumed().acceleration[k] * dt * 1.01;
            assert!(
                (fd - v1[k]).abs() <= tol,
                "{} at t = {}: {} vs {fd}",
                Actuator::ALL[k],
                w[1].0,
                v1[k]
            );
        }
    }
    Ok(())
}

#[test]
fn a_limit_set_the_trapezoid_exceeds_gives_a_slower_feasible_optimal_run() -> Result {
    // The trapezoid drives q6 at 35.7 mm/s at most: a 20 mm/s limit stops it.
    let mut limits = ActuatorLimits::assumed();
    for v in &mut limits.velocity[..6] {
        *v = 20.0;
    }
    let err = trapezoid_steps()?
        .iter()
        .find_map(|s| limits.check(s).err())
        .ok_or("the trapezoid should exceed 20 mm/s")?;
    assert!(
        matches!(
            err,
            LimitError::Exceeded {
                kind: RateKind::Velocity,
                limit: 20.0,
                actuator: Actuator::Module1(5 | 6),
                ..
            }
        ),
        "{err}"
    );
    let path = paper_path();
    let rows = row_limits(&limits, None);
    let mut knots = vec![Knot::default(); 1000];
    let (schedule, _) = optimal::plan(&path, &rows, &mut knots, 10)?;
    let steps = optimal_steps(&path, &schedule, 1000.0)?;
    let worst = worst_use(&steps, &limits);
    assert!(worst <= 1.0 + 1e-9, "worst use {worst}");
    assert!(schedule.duration() > 4.5, "{} s", schedule.duration());
    Ok(())
}

#[test]
fn with_only_the_angular_limits_the_optimal_law_is_the_paper_trapezoid() -> Result {
    // Each Euler angle within 10 deg/s and 5 deg/s^2, actuators unlimited: on
    // the straight line theta (25 deg) binds, and the fastest law is its
    // trapezoid, 4.5 s.
    let path = paper_path();
    let deg = 1f64.to_radians();
    let rows = row_limits(
        &ActuatorLimits::unlimited(),
        Some([Limits::new(10.0 * deg, 5.0 * deg); 2]),
    );
    for n in [100, 1000] {
        let mut knots = vec![Knot::default(); n];
        let (schedule, cert) = optimal::plan(&path, &rows, &mut knots, 10)?;
        let t = schedule.duration();
        assert!(
            t >= 4.5 * (1.0 - 1e-12) && t <= 4.5 * (1.0 + 2.0 / n as f64),
            "{n} knots: {t} s"
        );
        assert_eq!(cert.passes, 0);
        let phases: Vec<_> = schedule.phases(&rows).collect();
        assert!(
            phases.iter().all(|p| p.row == PATH_ROWS - 1),
            "theta binds throughout"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn random_turns_and_limits_are_feasible_and_at_rest_at_both_ends(
        start in (-25.0..-5.0f64, 0.0..20.0f64),
        turn in (-20.0..20.0f64, -20.0..30.0f64),
        tip in prop::array::uniform3(-15.0..15.0f64),
        scale in prop::array::uniform2(0.2..3.0f64),
    ) {
        prop_assume!(turn.0.abs() + turn.1.abs() > 2.0);
        let mut pose = Pose::paper_start();
        pose.psi = start.0.to_radians();
        pose.theta = start.1.to_radians();
        let mut tips = TipTargets::paper();
        tips.left += parasils::kin::nalgebra::Vector3::from(tip);
        let path = self::turn(pose, [turn.0.to_radians(), turn.1.to_radians()], &tips);
        // Starts out of reach are not this test's subject.
        prop_assume!(path.is_ok());
        let path = path.map_err(|e| TestCaseError::fail(e.to_string()))?;
        let mut limits = ActuatorLimits::assumed();
        for v in &mut limits.velocity { *v *= scale[0]; }
        for a in &mut limits.acceleration { *a *= scale[1]; }
        let rows = row_limits(&limits, None);
        let mut knots = vec![Knot::default(); 300];
        let planned = optimal::plan(&path, &rows, &mut knots, 10);
        // Turns that leave the workspace are not this test's subject.
        prop_assume!(planned.is_ok());
        let schedule = Schedule::view(&knots);
        let t = schedule.duration();
        // 10 times denser than the knots in s.
        for w in knots.windows(2) {
            for j in 0..=10 {
                let s = w[0].s + (w[1].s - w[0].s) * f64::from(j) / 10.0;
                let x = if j == 10 { w[1].x() } else { w[0].x() + 2.0 * w[0].s_ddot() * (s - w[0].s) };
                let p = path.point(s).map_err(|e| TestCaseError::fail(e.to_string()))?;
                for k in 0..ACTUATOR_COUNT {
                    let v = (p.q_s[k] * x.sqrt()).abs() / limits.velocity[k];
                    let a = (p.q_s[k] * w[0].s_ddot() + p.q_ss[k] * x).abs() / limits.acceleration[k];
                    prop_assert!(v <= 1.0 + 1e-9 && a <= 1.0 + 1e-9, "{} at s = {}: {} {}", Actuator::ALL[k], s, v, a);
                }
            }
        }
        // At 1 kHz through the controller (which also watches module 1's
        // parallel margin, which the path does not: turns that come too
        // close to a parallel singularity are not this test's subject).
        let steps = optimal_steps(&path, &schedule, 1000.0);
        prop_assume!(steps.is_ok());
        let steps = steps.map_err(|e| TestCaseError::fail(e.to_string()))?;
        let worst = worst_use(&steps, &limits);
        prop_assert!(worst <= 1.0 + 1e-9, "worst use {}", worst);
        prop_assert!(worst >= 1.0 - 1e-2, "some limit binds: {}", worst);
        let end = schedule.state(t);
        prop_assert_eq!((end.position, end.velocity), (1.0, 0.0));
    }
}
