//! Property tests of the controlled stop of several axes, in f64 and f32,
//! 10^5 cases per property: every axis at rest at the same instant, the lead
//! at its limit, each decelerating uniformly along its start velocity.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact start states are what these tests check"
)]

mod common;
mod online_common;

use common::c;
use online_common::{CASES, Case, case_f32, case_f64, fail, group};
use parasils_traj::{OnlineMulti, Real, State, Synchronization};
use proptest::prelude::*;

/// The controlled stop: every axis at rest at the same instant, the lead at
/// its limit, each decelerating uniformly (a straight line along `v0`).
fn check_stop<T: Real, const N: usize>(ks: &[Case; N]) -> Result<(), TestCaseError> {
    let start = ks.map(|k| k.start::<T>());
    let limits = ks.map(|k| k.limits::<T>());
    let m = OnlineMulti::stop(start, limits).map_err(fail)?;
    prop_assert_eq!(m.synchronization(), Synchronization::Phase);
    let t_stop = start
        .iter()
        .zip(&limits)
        .fold(T::zero(), |a, (s, l)| a.max(s.velocity.abs() / l.a_max));
    prop_assert_eq!(m.duration(), t_stop);
    let rel = T::one() + c::<T>(16.0) * T::EPSILON;
    for (i, p) in m.axes().iter().enumerate() {
        if start[i].velocity != T::zero() {
            prop_assert_eq!(p.duration(), t_stop);
        }
        prop_assert_eq!(p.sample(t_stop), State::rest(p.target()));
        let stop_at = start[i].position + T::lit(0.5) * start[i].velocity * t_stop;
        prop_assert!(
            (p.target() - stop_at).abs()
                <= c::<T>(4.0) * T::EPSILON * (start[i].position.abs() + p.target().abs())
        );
    }
    if let Some(l) = m.lead() {
        let a = m.axes()[l].first_acceleration().abs();
        prop_assert!((a - limits[l].a_max).abs() <= c::<T>(16.0) * T::EPSILON * limits[l].a_max);
    }
    if t_stop == T::zero() {
        return Ok(());
    }
    for k in 1..16 {
        let t = t_stop * T::from_index(k) / c(16.0);
        let s = m.sample(t);
        // The common progress g(t) = t - t^2 / (2 T).
        let g = t - t * t / (t_stop + t_stop);
        for i in 0..N {
            prop_assert!(s[i].acceleration.abs() <= limits[i].a_max * rel);
            prop_assert!(s[i].velocity * start[i].velocity >= T::zero(), "reverses");
            let along = start[i].position + start[i].velocity * g;
            let tol = c::<T>(16.0)
                * T::EPSILON
                * (start[i].position.abs() + (start[i].velocity * t_stop).abs());
            prop_assert!(
                (s[i].position - along).abs() <= tol,
                "axis {} off the line at {:?}: {:?} vs {:?}",
                i,
                t,
                s[i].position,
                along
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]
    #[test]
    fn f64_stop(ks in group::<3>(case_f64())) {
        check_stop::<f64, 3>(&ks)?;
    }

    #[test]
    fn f32_stop(ks in group::<3>(case_f32())) {
        check_stop::<f32, 3>(&ks)?;
    }

}
