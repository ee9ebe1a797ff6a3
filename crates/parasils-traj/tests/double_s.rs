//! Property tests of the jerk-limited profile: limits on velocity,
//! acceleration and jerk, never shorter than the trapezoid, exact ends,
//! derivatives, near every boundary of the case analysis.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact times are what these tests check"
)]

mod common;

use common::{
    Bounds, CASES, c, check_continuity, check_derivatives, check_ends, check_limits_and_path,
    log_uniform, near_zero,
};
use parasils_traj::{DoubleS, JerkLimits, Real, Trapezoid};
use proptest::prelude::*;

const FRACTIONS: [f64; 9] = [0.04, 0.11, 0.23, 0.37, 0.5, 0.63, 0.77, 0.89, 0.96];

fn switches<T: Real>(p: &DoubleS<T>) -> [T; 7] {
    let (tj, ta, tv) = (p.t_jerk(), p.t_accel(), p.t_cruise());
    [
        tj,
        ta - tj,
        ta,
        ta + tv,
        ta + tv + tj,
        p.duration() - tj,
        p.duration(),
    ]
}

fn fail(e: parasils_traj::Error) -> TestCaseError {
    TestCaseError::fail(format!("{e}"))
}

fn check_all<T: Real>(
    start: T,
    goal: T,
    lim: JerkLimits<T>,
    h_rel: T,
) -> Result<DoubleS<T>, TestCaseError> {
    let p = DoubleS::new(start, goal, lim).map_err(fail)?;
    check_profile(&p, lim, h_rel)?;
    // Never shorter than the trapezoid with the same v_max and a_max.
    let trap = Trapezoid::new(start, goal, lim.limits()).map_err(fail)?;
    let rel = c::<T>(8.0) * T::EPSILON;
    prop_assert!(
        p.duration() >= trap.duration() * (T::one() - rel),
        "double-S {:?} shorter than trapezoid {:?}",
        p.duration(),
        trap.duration()
    );
    Ok(p)
}

fn check_profile<T: Real>(
    p: &DoubleS<T>,
    lim: JerkLimits<T>,
    h_rel: T,
) -> Result<(), TestCaseError> {
    let sw = switches(p);
    check_ends(p)?;
    let bounds = Bounds {
        v: lim.v_max,
        a: lim.a_max,
        j: Some(lim.j_max),
    };
    check_limits_and_path(p, bounds, &sw, 64)?;
    check_continuity(p, &sw)?;
    check_derivatives(p, &sw, h_rel, &FRACTIONS, Some(lim.j_max))?;
    let rel = c::<T>(16.0) * T::EPSILON;
    prop_assert!(p.peak_jerk() <= lim.j_max * (T::one() + rel));
    prop_assert!(p.peak_acceleration() <= lim.a_max * (T::one() + rel));
    prop_assert!(p.peak_velocity() <= lim.v_max * (T::one() + rel));
    // Jerk: bounded, and the derivative of the acceleration away from switches.
    let h = p.duration() * h_rel;
    for &f in &FRACTIONS {
        let t = p.duration() * c(f);
        let j = p.jerk(t);
        prop_assert!(j.abs() <= lim.j_max * (T::one() + rel));
        if sw
            .iter()
            .chain([T::zero()].iter())
            .all(|&s| (t - s).abs() > h + h)
        {
            let da = (p.sample(t + h).acceleration - p.sample(t - h).acceleration) / (h + h);
            let tol =
                c::<T>(8.0) * T::EPSILON * (p.peak_acceleration() + p.duration() * p.peak_jerk())
                    / h;
            prop_assert!(
                (da - j).abs() <= tol,
                "da/dt {:?} vs jerk {:?} at {:?}",
                da,
                j,
                t
            );
        }
    }
    // Distance consistency: the phases cover the distance.
    let d_back = p.peak_velocity() * (p.t_accel() + p.t_cruise());
    prop_assert!((d_back - p.distance()).abs() <= c::<T>(64.0) * T::EPSILON * p.distance());
    Ok(())
}

/// Parameters near each boundary of the case analysis.
/// mode 0: random; 1: `v j = a^2` (a reached or not at v_max);
/// 2: `d = v t_a(v)` (v reached or not); 3: `d = 2 a^3 / j^2` (a reached or not, v large).
/// `wide` spans 6 decades of distance (f64), otherwise 4 (f32).
fn params(wide: bool) -> impl Strategy<Value = (f64, f64, f64, f64)> {
    let e = if wide { 1.0 } else { 0.5 };
    (
        0..4u8,
        log_uniform(-3.0 * e, 3.0 * e),
        log_uniform(-2.0 * e, 2.0 * e),
        log_uniform(-2.0 * e, 3.0 * e),
        log_uniform(-2.0 * e, 4.0 * e),
        near_zero(),
    )
        .prop_map(|(mode, d, v, a, j, delta)| match mode {
            1 => (d, a * a / j * (1.0 + delta), a, j),
            2 => {
                let t_a = if v / a >= a / j {
                    a / j + v / a
                } else {
                    2.0 * (v / j).sqrt()
                };
                (v * t_a * (1.0 + delta), v, a, j)
            }
            3 => (2.0 * a * a * a / (j * j) * (1.0 + delta), 1e6, a, j),
            _ => (d, v, a, j),
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn f64_random_and_boundaries(start in -1e2..1e2_f64, (d, v, a, j) in params(true), neg in any::<bool>()) {
        let goal = if neg { start - d } else { start + d };
        check_all(start, goal, JerkLimits::new(v, a, j), 1e-6)?;
    }

    #[test]
    fn f32_random_and_boundaries(start in -10.0..10.0_f32, (d, v, a, j) in params(false), neg in any::<bool>()) {
        let d = d as f32;
        let goal = if neg { start - d } else { start + d };
        check_all(start, goal, JerkLimits::new(v as f32, a as f32, j as f32), 1e-3)?;
    }

    /// `with_duration`: exact duration, same jerk, within limits, both branches (a reached or not).
    #[test]
    fn f64_with_duration(start in -1e2..1e2_f64, (d, v, a, j) in params(true),
                         stretch in prop_oneof![Just(0.0), log_uniform(-12.0, 1.5)]) {
        let lim = JerkLimits::new(v, a, j);
        let own = DoubleS::new(start, start + d, lim).map_err(fail)?;
        let t = own.duration() * (1.0 + stretch);
        let p = DoubleS::with_duration(start, start + d, lim, t).map_err(fail)?;
        prop_assert_eq!(p.duration(), if stretch == 0.0 { own.duration() } else { t });
        prop_assert!(p.peak_velocity() <= own.peak_velocity() * (1.0 + 1e-12));
        check_profile(&p, lim, 1e-6)?;
    }
}

/// With a very large jerk limit, the double-S tends to the trapezoid.
#[test]
fn large_jerk_tends_to_the_trapezoid() -> Result<(), parasils_traj::Error> {
    for d in [0.5, 2.0, 25.0] {
        let trap = Trapezoid::new(0.0_f64, d, parasils_traj::Limits::new(10.0, 5.0))?;
        let ds = DoubleS::new(0.0_f64, d, JerkLimits::new(10.0, 5.0, 1e9))?;
        assert!((ds.duration() - trap.duration()).abs() < 1e-8 * trap.duration().max(1.0));
        for k in 1..20 {
            let t = trap.duration() * f64::from(k) / 20.0;
            assert!((ds.sample(t).position - trap.sample(t).position).abs() < 1e-7 * d);
        }
    }
    Ok(())
}
