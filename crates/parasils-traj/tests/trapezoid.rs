//! Property tests of the single-axis trapezoidal profile, in f64 and f32,
//! over wide random inputs and near the triangular/trapezoidal switch.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact times are what these tests check"
)]

mod common;

use common::{
    Bounds, CASES, c, check_continuity, check_derivatives, check_ends, check_limits_and_path,
    log_uniform, near_zero,
};
use parasils_traj::{DoubleS, JerkLimits, Limits, Real, Trapezoid};
use proptest::prelude::*;

/// Points where finite differences are taken, as fractions of the duration.
const FRACTIONS: [f64; 9] = [0.05, 0.13, 0.27, 0.38, 0.5, 0.61, 0.74, 0.86, 0.95];

fn fail(e: parasils_traj::Error) -> TestCaseError {
    TestCaseError::fail(format!("{e}"))
}

fn switches<T: Real>(p: &Trapezoid<T>) -> [T; 2] {
    [p.t_accel(), p.t_accel() + p.t_cruise()]
}

/// Every check on one profile; `h_rel` is the finite-difference step relative to T.
fn check_all<T: Real>(
    start: T,
    goal: T,
    lim: Limits<T>,
    h_rel: T,
) -> Result<Trapezoid<T>, TestCaseError> {
    let p = Trapezoid::new(start, goal, lim).map_err(fail)?;
    let sw = switches(&p);
    check_ends(&p)?;
    check_limits_and_path(
        &p,
        Bounds {
            v: lim.v_max,
            a: lim.a_max,
            j: None,
        },
        &sw,
        64,
    )?;
    check_continuity(&p, &sw)?;
    check_derivatives(&p, &sw, h_rel, &FRACTIONS, None)?;
    // Duration against the textbook formula, written with products (the code uses ratios).
    let d = p.distance();
    let expected = if d * lim.a_max < lim.v_max * lim.v_max {
        c::<T>(2.0) * (d / lim.a_max).sqrt()
    } else {
        d / lim.v_max + lim.v_max / lim.a_max
    };
    let rel = c::<T>(8.0) * T::EPSILON;
    prop_assert!(
        (p.duration() - expected).abs() <= rel * expected,
        "duration {:?} vs {:?}",
        p.duration(),
        expected
    );
    prop_assert!(p.t_accel() + p.t_cruise() + p.t_decel() <= p.duration() * (T::one() + rel));
    // The acceleration phase reaches the peak velocity.
    prop_assert!(
        (p.peak_acceleration() * p.t_accel() - p.peak_velocity()).abs() <= rel * p.peak_velocity()
    );
    prop_assert_eq!(p.is_triangular(), p.t_cruise() == T::zero());
    Ok(p)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    /// Wide random inputs in f64, both directions.
    #[test]
    fn f64_random(start in -1e3..1e3_f64, d in log_uniform(-3.0, 3.0), neg in any::<bool>(),
                  v in log_uniform(-2.0, 2.0), a in log_uniform(-2.0, 3.0)) {
        let goal = if neg { start - d } else { start + d };
        check_all(start, goal, Limits::new(v, a), 1e-6)?;
    }

    /// Near the switch: `v_max = sqrt(d a_max) (1 + delta)`, `|delta|` from 1e-16 to 1e-2, and 0.
    #[test]
    fn f64_near_switch(start in -1e2..1e2_f64, d in log_uniform(-3.0, 3.0), a in log_uniform(-2.0, 3.0),
                       delta in near_zero(), neg in any::<bool>()) {
        let goal = if neg { start - d } else { start + d };
        let d = (goal - start).abs(); // the distance the profile sees
        let v = (d * a).sqrt() * (1.0 + delta);
        let p = check_all(start, goal, Limits::new(v, a), 1e-6)?;
        // Both formulas agree at the switch: T = 2 sqrt(d / a) within the perturbation.
        let t_switch = 2.0 * (d / a).sqrt();
        prop_assert!((p.duration() - t_switch).abs() <= (delta.abs() * 2.0 + 1e-14) * t_switch);
    }

    /// Wide random inputs in f32.
    #[test]
    fn f32_random(start in -10.0..10.0_f32, d in log_uniform(-2.0, 2.0), neg in any::<bool>(),
                  v in log_uniform(-1.0, 1.0), a in log_uniform(-1.0, 2.0)) {
        let d = d as f32;
        let goal = if neg { start - d } else { start + d };
        check_all(start, goal, Limits::new(v as f32, a as f32), 1e-3)?;
    }

    /// Near the switch in f32.
    #[test]
    fn f32_near_switch(start in -10.0..10.0_f32, d in log_uniform(-2.0, 2.0), a in log_uniform(-1.0, 2.0),
                       delta in near_zero()) {
        let goal = start + d as f32;
        let d = f64::from(goal - start);
        let v = ((d * a).sqrt() * (1.0 + delta)) as f32;
        check_all(start, goal, Limits::new(v, a as f32), 1e-3)?;
    }

    /// The f32 profiles follow the f64 ones: the budget stated in the crate docs,
    /// `4 f32::EPSILON` of `|start| + |goal| + distance` in position and of the
    /// duration in time (measured: 1.6 and 1.6 epsilons over 1e5 random cases).
    #[test]
    fn f32_error_budget(start in -10.0..10.0_f32, d in log_uniform(-2.0, 2.0), v in log_uniform(-1.0, 1.0),
                        a in log_uniform(-1.0, 2.0), j in log_uniform(-1.0, 3.0), delta in near_zero(),
                        near in any::<bool>()) {
        let v = if near { (d * a).sqrt() * (1.0 + delta) } else { v };
        let (d32, v32, a32, j32) = (d as f32, v as f32, a as f32, j as f32);
        let goal = start + d32;
        let (s64, g64) = (f64::from(start), f64::from(goal));
        let budget = 4.0 * f64::from(f32::EPSILON);
        let big = s64.abs() + g64.abs() + (g64 - s64).abs();
        let p32 = Trapezoid::new(start, goal, Limits::new(v32, a32)).map_err(fail)?;
        let p64 = Trapezoid::new(s64, g64, Limits::new(f64::from(v32), f64::from(a32))).map_err(fail)?;
        let q32 = DoubleS::new(start, goal, JerkLimits::new(v32, a32, j32)).map_err(fail)?;
        let q64 = DoubleS::new(s64, g64, JerkLimits::new(f64::from(v32), f64::from(a32), f64::from(j32))).map_err(fail)?;
        prop_assert!((f64::from(p32.duration()) - p64.duration()).abs() <= budget * p64.duration());
        prop_assert!((f64::from(q32.duration()) - q64.duration()).abs() <= budget * q64.duration());
        for k in 0..=50 {
            let t = p64.duration() * f64::from(k) / 50.0;
            let (x, y) = (p32.sample(t as f32), p64.sample(t));
            prop_assert!((f64::from(x.position) - y.position).abs() <= budget * big,
                "trapezoid f32 {} vs f64 {} at t={}", x.position, y.position, t);
            let t = q64.duration() * f64::from(k) / 50.0;
            let (x, y) = (q32.sample(t as f32), q64.sample(t));
            prop_assert!((f64::from(x.position) - y.position).abs() <= budget * big,
                "double-S f32 {} vs f64 {} at t={}", x.position, y.position, t);
        }
    }

    /// `with_duration`: exact duration, keeps a_max, lowers the velocity, stays within limits.
    #[test]
    fn f64_with_duration(start in -1e2..1e2_f64, d in log_uniform(-3.0, 3.0), v in log_uniform(-2.0, 2.0),
                         a in log_uniform(-2.0, 3.0), stretch in prop_oneof![Just(0.0), log_uniform(-12.0, 1.0)]) {
        let lim = Limits::new(v, a);
        let own = Trapezoid::new(start, start + d, lim).map_err(fail)?;
        let t = own.duration() * (1.0 + stretch);
        let p = Trapezoid::with_duration(start, start + d, lim, t).map_err(fail)?;
        prop_assert_eq!(p.duration(), if stretch == 0.0 { own.duration() } else { t });
        prop_assert_eq!(p.peak_acceleration(), a);
        prop_assert!(p.peak_velocity() <= own.peak_velocity());
        let sw = switches(&p);
        check_ends(&p)?;
        check_limits_and_path(&p, Bounds { v, a, j: None }, &sw, 64)?;
        check_continuity(&p, &sw)?;
        check_derivatives(&p, &sw, 1e-6, &FRACTIONS, None)?;
    }
}

/// Regression guard: huge but finite limits and distances must not give NaN
/// (the product `d * a_max` overflows where the ratio form does not).
#[test]
fn extreme_magnitudes_stay_finite() {
    for (d, v, a) in [
        (1e300, 1e300, 1e300),
        (1e-300, 1e-300, 1e-300),
        (1.0, 1e300, 1e300),
        (1e200, 1e200, 1e200),
        (1e-200, 1e200, 1e-200),
    ] {
        match Trapezoid::new(0.0_f64, d, Limits::new(v, a)) {
            Ok(p) => {
                for k in 0..=20 {
                    let s = p.sample(p.duration() * f64::from(k) / 20.0);
                    assert!(
                        s.position.is_finite()
                            && s.velocity.is_finite()
                            && s.acceleration.is_finite()
                    );
                }
                assert_eq!(p.sample(p.duration()).position, d);
            }
            Err(e) => assert!(matches!(e, parasils_traj::Error::OutOfRange { .. }), "{e}"),
        }
    }
}

/// Errors display the axis, the limit and the value.
#[test]
fn error_messages_name_the_value() {
    let e = Trapezoid::new(0.0_f64, 1.0, Limits::new(1.0, -2.0)).err();
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some("axis 0: a_max = -2 is not a positive finite number")
    );
    let e = Trapezoid::new(0.0_f64, f64::INFINITY, Limits::new(1.0, 2.0)).err();
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some("axis 0: the goal position inf is not finite")
    );
}
