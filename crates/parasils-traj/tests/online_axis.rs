//! Property tests of the online profile of one axis (any state to rest,
//! and its stop), in f64 and f32, 10^5 cases per property: limits within 16
//! epsilons, the target reached exactly and at rest, no overshoot where none
//! is needed, the duration never longer than braking to a full stop and then
//! going rest to rest, continuity at replans; any input an error or finite
//! samples; hand-derived cases and the errors.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact start states are what these tests check"
)]

mod common;
mod online_common;

use common::c;
use online_common::{
    CASES, Case, anything, case_f32, case_f64, check_profile, fail, moving, needs_no_overshoot,
    reference, rounding, time_slack,
};
use parasils_traj::{
    Error, LimitKind, Limits, OnlineMulti, OnlineTrapezoid, Real, State, Synchronization,
};
use proptest::prelude::*;

/// Every single-axis check; returns the profile.
fn check_single<T: Real>(k: &Case) -> Result<OnlineTrapezoid<T>, TestCaseError> {
    let (start, target, lim) = (k.start::<T>(), k.target::<T>(), k.limits::<T>());
    let p = OnlineTrapezoid::new(start, target, lim).map_err(fail)?;
    let (p0, v0) = (start.position, start.velocity);
    let monotone = needs_no_overshoot(p0, v0, target, lim);
    check_profile(&p, lim, monotone)?;
    if monotone {
        prop_assert!(!p.reverses() || v0 == T::zero());
    }
    let (exact, bound) = reference(p0, v0, target, lim)?;
    let delta = rounding(p0, v0, target, lim.a_max);
    let gap = target - (p0 + T::lit(0.5) * v0 * v0.abs() / lim.a_max);
    let tol = c::<T>(64.0) * T::EPSILON * bound + time_slack(delta, gap, lim);
    prop_assert!(
        p.duration() <= bound + tol,
        "duration {:?} > brake and rest to rest {:?}",
        p.duration(),
        bound
    );
    prop_assert!(
        (p.duration() - exact).abs() <= tol,
        "duration {:?} vs {:?} (tol {:?})",
        p.duration(),
        exact,
        tol
    );
    Ok(p)
}

/// Replanning at `t` from the profile's own state gives the same state at
/// `t` and the same remaining motion.
fn check_replan<T: Real>(k: &Case, frac: f64) -> Result<(), TestCaseError> {
    let (start, target, lim) = (k.start::<T>(), k.target::<T>(), k.limits::<T>());
    let p = OnlineTrapezoid::new(start, target, lim).map_err(fail)?;
    let [s1, s2] = p.switches();
    let mut at = vec![p.duration() * c(frac), s1, s2];
    at.retain(|t| *t > T::zero() && *t < p.duration());
    for t in at {
        let s = p.sample(t);
        let q = OnlineTrapezoid::new(s, target, lim).map_err(fail)?;
        let q0 = q.sample(T::zero());
        prop_assert_eq!((q0.position, q0.velocity), (s.position, s.velocity));
        check_profile(&q, lim, false)?;
        let delta = rounding(s.position, s.velocity, target, lim.a_max)
            + rounding(start.position, start.velocity, target, lim.a_max);
        let gap = target - (s.position + T::lit(0.5) * s.velocity * s.velocity.abs() / lim.a_max);
        let tol_t = c::<T>(64.0) * T::EPSILON * p.duration() + time_slack(delta, gap, lim);
        let rest = p.duration() - t;
        prop_assert!(
            (q.duration() - rest).abs() <= tol_t,
            "replanned at {:?}: {:?} s left vs {:?} (tol {:?})",
            t,
            q.duration(),
            rest,
            tol_t
        );
        for f in [0.25, 0.5, 0.75] {
            let u = rest * c(f);
            let (a, b) = (q.sample(u), p.sample(t + u));
            let tol = delta + c::<T>(2.0) * lim.v_max.max(s.velocity.abs()) * tol_t;
            prop_assert!(
                (a.position - b.position).abs() <= tol,
                "replanned path {:?} vs {:?} at {:?} + {:?}",
                a.position,
                b.position,
                t,
                u
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]
    #[test]
    fn f64_single(k in case_f64()) {
        check_single::<f64>(&k)?;
    }

    #[test]
    fn f32_single(k in case_f32()) {
        check_single::<f32>(&k)?;
    }

    #[test]
    fn f64_replan(k in case_f64(), frac in 0.0..1.0_f64) {
        check_replan::<f64>(&k, frac)?;
    }

    #[test]
    fn f32_replan(k in case_f32(), frac in 0.0..1.0_f64) {
        check_replan::<f32>(&k, frac)?;
    }

}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]
    /// Any bit pattern in, an error or a profile whose samples are finite out.
    #[test]
    fn never_nan_or_panic(p0 in anything(), v0 in anything(), g in anything(),
                          v in anything(), a in anything(), t in anything()) {
        let start = moving(p0, v0);
        let lim = Limits::new(v, a);
        let built = [
            OnlineTrapezoid::new(start, g, lim),
            OnlineTrapezoid::stop(start, lim),
            OnlineTrapezoid::with_duration(start, g, lim, t),
        ];
        for p in built.into_iter().flatten() {
            for x in [t, p.duration() * 0.5, p.duration() * 0.999, p.duration()] {
                let s = p.sample(x);
                prop_assert!(s.position.is_finite() && s.velocity.is_finite()
                    && s.acceleration.is_finite());
            }
        }
        let m = OnlineMulti::new([start, moving(g, p0)], [g, v0], [lim, Limits::new(a, v)],
                                 Synchronization::Phase);
        if let Ok(m) = m {
            for s in m.sample(t * 1e-3).iter().chain(&m.sample(m.duration() * 0.5)) {
                prop_assert!(s.position.is_finite() && s.velocity.is_finite()
                    && s.acceleration.is_finite());
            }
        }
    }
}

#[test]
fn hand_derived_cases() -> Result<(), Error> {
    let lim = Limits::new(2.0_f64, 1.0);
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    // From rest: accelerate 2 s (2 units), cruise 3 s (6 units), decelerate 2 s.
    let p = OnlineTrapezoid::new(State::rest(0.0), 10.0, lim)?;
    assert!(close(p.duration(), 7.0) && close(p.t_first(), 2.0) && close(p.t_cruise(), 3.0));
    assert_eq!(p.cruise_velocity(), 2.0);
    // v0 = 3 > v_max = 2: brake 1 s (2.5 units), cruise 2.75 s (5.5 units), decelerate 2 s.
    let p = OnlineTrapezoid::new(moving(0.0, 3.0), 10.0, lim)?;
    assert!(close(p.duration(), 5.75) && close(p.t_first(), 1.0) && close(p.t_cruise(), 2.75));
    assert_eq!(p.first_acceleration(), -1.0);
    assert_eq!(p.sample(0.5).velocity, 2.5);
    // v0 = 2 towards a target 1 unit ahead: stop after 2 units (2 s), come
    // back 1 unit as a triangle peaking at -1 (2 s).
    let p = OnlineTrapezoid::new(moving(0.0, 2.0), 1.0, lim)?;
    assert!(close(p.duration(), 4.0) && close(p.cruise_velocity(), -1.0) && p.reverses());
    assert!(close(p.sample(2.0).position, 2.0) && close(p.sample(2.0).velocity, 0.0));
    // Moving away at 1: stop 0.5 unit behind (1 s), then 2.5 units as a
    // triangle, 2 sqrt(2.5) s.
    let p = OnlineTrapezoid::new(moving(0.0, -1.0), 2.0, lim)?;
    assert!(close(p.duration(), 1.0 + 2.0 * 2.5_f64.sqrt()));
    // The target exactly at the stopping point: brake only, 2 s.
    let p = OnlineTrapezoid::new(moving(0.0, 2.0), 2.0, lim)?;
    assert!(close(p.duration(), 2.0) && !p.reverses());
    assert_eq!(
        p.sample(1.0),
        State {
            position: 1.5,
            velocity: 1.0,
            acceleration: -1.0
        }
    );
    // On the target but moving at 1: out 0.5 unit (1 s) and back (2 sqrt(0.5) s).
    let p = OnlineTrapezoid::new(moving(0.0, 1.0), 0.0, lim)?;
    assert!(close(p.duration(), 1.0 + 2.0 * 0.5_f64.sqrt()));
    // Far enough beyond the stopping point at v_max: cruise straight away.
    let p = OnlineTrapezoid::new(moving(0.0, 2.0), 10.0, lim)?;
    assert!(close(p.duration(), 6.0) && p.t_first() == 0.0 && close(p.t_cruise(), 4.0));
    // At rest on the target: nothing to do.
    let p = OnlineTrapezoid::new(State::rest(3.0), 3.0, lim)?;
    assert_eq!(p.duration(), 0.0);
    assert_eq!(p.sample(1.0), State::rest(3.0));
    Ok(())
}

#[test]
fn errors_name_the_axis_and_value() {
    let lim = Limits::new(1.0_f64, 1.0);
    assert!(matches!(
        OnlineTrapezoid::new(moving(0.0, f64::NAN), 1.0, lim),
        Err(Error::NonFiniteVelocity { axis: 0, value }) if value.is_nan()
    ));
    assert!(matches!(
        OnlineTrapezoid::new(moving(0.0, f64::INFINITY), 1.0, lim),
        Err(Error::NonFiniteVelocity { axis: 0, value }) if value == f64::INFINITY
    ));
    assert!(matches!(
        OnlineTrapezoid::new(moving(0.0, 1.0), f64::NAN, lim),
        Err(Error::NonFinitePosition {
            endpoint: parasils_traj::Endpoint::Goal,
            ..
        })
    ));
    assert!(matches!(
        OnlineTrapezoid::new(moving(f64::NEG_INFINITY, 1.0), 0.0, lim),
        Err(Error::NonFinitePosition {
            endpoint: parasils_traj::Endpoint::Start,
            ..
        })
    ));
    assert_eq!(
        OnlineTrapezoid::new(moving(0.0, 1.0), 1.0, Limits::new(0.0, 1.0)),
        Err(Error::InvalidLimit {
            axis: 0,
            limit: LimitKind::Velocity,
            value: 0.0
        })
    );
    assert!(matches!(
        OnlineTrapezoid::stop(moving(0.0, 1.0), Limits::new(1.0, -1.0)),
        Err(Error::InvalidLimit {
            limit: LimitKind::Acceleration,
            ..
        })
    ));
    assert!(matches!(
        OnlineTrapezoid::new(moving(-f64::MAX, 0.0), f64::MAX, lim),
        Err(Error::DistanceOverflow { .. })
    ));
    assert!(matches!(
        OnlineTrapezoid::new(moving(0.0_f32, 0.0), 1e30, Limits::new(1e-30, 1.0)),
        Err(Error::OutOfRange { .. })
    ));
    assert!(matches!(
        OnlineTrapezoid::with_duration(moving(0.0, 0.0), 10.0, Limits::new(2.0, 1.0), 6.0),
        Err(Error::InvalidDuration { minimum, .. }) if (minimum - 7.0).abs() < 1e-12
    ));
    let r = OnlineMulti::new(
        [moving(0.0, 0.0), moving(0.0, f64::NAN)],
        [1.0, 1.0],
        [lim; 2],
        Synchronization::Time,
    );
    assert!(matches!(r, Err(Error::NonFiniteVelocity { axis: 1, .. })));
    let r = OnlineMulti::stop(
        [moving(0.0, 1.0), moving(0.0, 1.0)],
        [lim, Limits::new(1.0, 0.0)],
    );
    assert!(matches!(r, Err(Error::InvalidLimit { axis: 1, .. })));
    let e = OnlineTrapezoid::new(moving(0.0, f64::INFINITY), 1.0, lim).err();
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some("axis 0: the start velocity inf is not finite")
    );
}
