//! Property tests of multi-axis synchronisation (`docs/model.md`, *Trajectories*): phase stays
//! on the straight line, time gives one duration, none keeps each axis's own
//! profile; zero-distance and opposite-direction axes included.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact times are what these tests check"
)]

mod common;

use common::{
    Bounds, CASES, check_continuity, check_derivatives, check_ends, check_limits_and_path,
    log_uniform,
};
use parasils_traj::{
    DoubleS, JerkLimits, Limits, Multi, Profile, Real, Synchronization, Trapezoid,
};
use proptest::prelude::*;

const N: usize = 3;
const FRACTIONS: [f64; 7] = [0.07, 0.19, 0.33, 0.5, 0.66, 0.81, 0.93];

fn fail(e: parasils_traj::Error) -> TestCaseError {
    TestCaseError::fail(format!("{e}"))
}

/// Per-axis start and signed distance: a third of axes still, random signs.
fn moves() -> impl Strategy<Value = [(f64, f64); N]> {
    let one = (
        -1e2..1e2_f64,
        prop_oneof![1 => Just(0.0), 3 => log_uniform(-3.0, 3.0), 3 => log_uniform(-3.0, 3.0).prop_map(|d| -d)],
    );
    [one.clone(), one.clone(), one]
}

/// Per-axis limits: the same for all axes (the paper's case) or independent.
fn limits() -> impl Strategy<Value = [(f64, f64, f64); N]> {
    let one = (
        log_uniform(-2.0, 2.0),
        log_uniform(-2.0, 3.0),
        log_uniform(-1.0, 4.0),
    );
    prop_oneof![
        one.clone().prop_map(|l| [l; N]),
        [one.clone(), one.clone(), one],
    ]
}

fn split(m: [(f64, f64); N]) -> ([f64; N], [f64; N]) {
    (m.map(|(s, _)| s), m.map(|(s, d)| s + d))
}

fn trap_switches<T: Real>(p: &Trapezoid<T>) -> [T; 2] {
    [p.t_accel(), p.t_accel() + p.t_cruise()]
}

fn ds_switches<T: Real>(p: &DoubleS<T>) -> [T; 6] {
    let (tj, ta, tv) = (p.t_jerk(), p.t_accel(), p.t_cruise());
    [tj, ta - tj, ta, ta + tv, ta + tv + tj, p.duration() - tj]
}

/// Axis `i` is on the straight line: its normalised progress equals that of
/// the longest axis at every `t`, within the rounding of the positions.
fn check_straight_line<P: Profile<f64>>(m: &Multi<f64, N, P>) -> Result<(), TestCaseError> {
    let axes = m.axes();
    let Some(big) = axes
        .iter()
        .max_by(|a, b| a.distance().total_cmp(&b.distance()))
    else {
        return Ok(());
    };
    for k in 0..=40 {
        let t = m.duration() * f64::from(k) / 40.0;
        let s_ref = (big.position(t) - big.start()) / (big.goal() - big.start());
        for p in axes.iter().filter(|p| p.distance() > 0.0) {
            let s = (p.position(t) - p.start()) / (p.goal() - p.start());
            let tol =
                16.0 * f64::EPSILON * ((p.start().abs() + p.goal().abs()) / p.distance() + 1.0)
                    + 16.0 * f64::EPSILON * (big.start().abs() + big.goal().abs()) / big.distance();
            prop_assert!(
                (s - s_ref).abs() <= tol,
                "off the line by {} at t={} (tol {})",
                s - s_ref,
                t,
                tol
            );
        }
    }
    Ok(())
}

/// Still axes stay exactly still, with zero velocity and acceleration.
fn check_still<P: Profile<f64>>(m: &Multi<f64, N, P>) -> Result<(), TestCaseError> {
    for k in 0..=20 {
        let t = m.duration() * f64::from(k) / 20.0;
        for (p, s) in m.axes().iter().zip(m.sample(t)) {
            if p.distance() == 0.0 {
                prop_assert_eq!(s.position, p.start());
                prop_assert_eq!(s.velocity, 0.0);
                prop_assert_eq!(s.acceleration, 0.0);
            }
        }
    }
    let end = m.sample(m.duration());
    for (p, s) in m.axes().iter().zip(end) {
        prop_assert_eq!(s, parasils_traj::State::rest(p.goal()));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn trapezoid_sync(mv in moves(), lim in limits(), mode in 0..3u8) {
        let (start, goal) = split(mv);
        let lims = lim.map(|(v, a, _)| Limits::new(v, a));
        let sync = [Synchronization::Phase, Synchronization::Time, Synchronization::None][usize::from(mode)];
        let m = Multi::new(start, goal, lims, sync).map_err(fail)?;
        let own: Vec<Trapezoid<f64>> = (0..N)
            .map(|i| Trapezoid::new(start[i], goal[i], lims[i]))
            .collect::<Result<_, _>>()
            .map_err(fail)?;
        let t_max = own.iter().fold(0.0_f64, |x, p| x.max(p.duration()));
        let same_limits = lims.iter().all(|l| *l == lims[0]);
        check_still(&m)?;
        for (p, l) in m.axes().iter().zip(lims) {
            let sw = trap_switches(p);
            check_ends(p)?;
            check_limits_and_path(p, Bounds { v: l.v_max, a: l.a_max, j: None }, &sw, 32)?;
            check_continuity(p, &sw)?;
            if p.distance() > 0.0 {
                check_derivatives(p, &sw, 1e-6, &FRACTIONS, None)?;
            }
        }
        match sync {
            Synchronization::Phase => {
                check_straight_line(&m)?;
                prop_assert!(m.duration() >= t_max * (1.0 - 1e-14));
                if same_limits {
                    prop_assert!((m.duration() - t_max).abs() <= 1e-14 * t_max);
                }
                // Same phase times for every moving axis.
                let moving: Vec<_> = m.axes().iter().filter(|p| p.distance() > 0.0).collect();
                for w in moving.windows(2) {
                    prop_assert_eq!(w[0].t_accel(), w[1].t_accel());
                    prop_assert_eq!(w[0].t_cruise(), w[1].t_cruise());
                }
            }
            Synchronization::Time => {
                prop_assert_eq!(m.duration(), t_max);
                for ((p, o), l) in m.axes().iter().zip(&own).zip(lims) {
                    if p.distance() > 0.0 {
                        prop_assert_eq!(p.duration(), t_max);
                        prop_assert_eq!(p.peak_acceleration(), l.a_max);
                        prop_assert!(p.peak_velocity() <= o.peak_velocity());
                    }
                }
            }
            Synchronization::None => {
                prop_assert_eq!(m.duration(), t_max);
                prop_assert_eq!(&m.axes()[..], &own[..]);
            }
        }
    }

    #[test]
    fn double_s_sync(mv in moves(), lim in limits(), mode in 0..3u8) {
        let (start, goal) = split(mv);
        let lims = lim.map(|(v, a, j)| JerkLimits::new(v, a, j));
        let sync = [Synchronization::Phase, Synchronization::Time, Synchronization::None][usize::from(mode)];
        let m = Multi::double_s(start, goal, lims, sync).map_err(fail)?;
        let own: Vec<DoubleS<f64>> = (0..N)
            .map(|i| DoubleS::new(start[i], goal[i], lims[i]))
            .collect::<Result<_, _>>()
            .map_err(fail)?;
        let t_max = own.iter().fold(0.0_f64, |x, p| x.max(p.duration()));
        check_still(&m)?;
        for (p, l) in m.axes().iter().zip(lims) {
            let sw = ds_switches(p);
            check_ends(p)?;
            check_limits_and_path(p, Bounds { v: l.v_max, a: l.a_max, j: Some(l.j_max) }, &sw, 32)?;
            prop_assert!(p.peak_jerk() <= l.j_max * (1.0 + 1e-14));
            check_continuity(p, &sw)?;
            if p.distance() > 0.0 {
                check_derivatives(p, &sw, 1e-6, &FRACTIONS, Some(l.j_max))?;
            }
        }
        match sync {
            Synchronization::Phase => {
                check_straight_line(&m)?;
                prop_assert!(m.duration() >= t_max * (1.0 - 1e-14));
                if lims.iter().all(|l| *l == lims[0]) {
                    prop_assert!((m.duration() - t_max).abs() <= 1e-14 * t_max);
                }
            }
            Synchronization::Time => {
                prop_assert_eq!(m.duration(), t_max);
                for (p, l) in m.axes().iter().zip(lims) {
                    if p.distance() > 0.0 {
                        prop_assert_eq!(p.duration(), t_max);
                        prop_assert_eq!(p.peak_jerk(), l.j_max);
                    }
                }
            }
            Synchronization::None => {
                prop_assert_eq!(&m.axes()[..], &own[..]);
            }
        }
    }

    /// Phase synchronisation in f32 keeps the limits and the exact ends.
    #[test]
    fn f32_phase(s in proptest::array::uniform3(-10.0..10.0_f32), d in proptest::array::uniform3(-10.0..10.0_f32), v in 0.1..10.0_f32, a in 0.1..10.0_f32) {
        let goal = [s[0] + d[0], s[1] + d[1], s[2] + d[2]];
        let m = Multi::new(s, goal, [Limits::new(v, a); N], Synchronization::Phase).map_err(fail)?;
        for p in m.axes() {
            check_ends(p)?;
            check_limits_and_path(p, Bounds { v, a, j: None }, &trap_switches(p), 32)?;
        }
        let end = m.sample(m.duration());
        prop_assert_eq!(end.map(|x| x.position), goal);
    }
}

/// Regression: opposite directions with equal distances in phase mode are exact mirrors.
#[test]
fn opposite_directions_mirror_exactly() -> Result<(), parasils_traj::Error> {
    let m = Multi::new(
        [0.0_f64, 0.0],
        [3.0, -3.0],
        [Limits::new(1.0, 2.0); 2],
        Synchronization::Phase,
    )?;
    for k in 0..=30 {
        let [a, b] = m.sample(m.duration() * f64::from(k) / 30.0);
        assert_eq!(a.position, -b.position);
        assert_eq!(a.velocity, -b.velocity);
        assert_eq!(a.acceleration, -b.acceleration);
    }
    Ok(())
}

/// The default synchronisation is phase.
#[test]
fn default_is_phase() {
    assert_eq!(Synchronization::default(), Synchronization::Phase);
}
