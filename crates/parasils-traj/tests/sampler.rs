//! The fixed-rate sampler: `k / rate` times, `n = ceil(T rate)` up to rounding,
//! the last sample exactly the end state.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact times are what these tests check"
)]

mod common;

use common::{CASES, log_uniform};
use parasils_traj::{Error, Limits, Motion, Multi, Sampler, State, Synchronization, Trapezoid};
use proptest::prelude::*;

fn fail(e: Error) -> TestCaseError {
    TestCaseError::fail(format!("{e}"))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn f64_grid_and_exact_end(d in log_uniform(-3.0, 2.0), v in log_uniform(-1.0, 1.0),
                              a in log_uniform(-1.0, 1.0), rate in log_uniform(0.0, 3.0)) {
        let p = Trapezoid::new(1.0, 1.0 + d, Limits::new(v, a)).map_err(fail)?;
        let s = p.sampler(rate).map_err(fail)?;
        let n = s.len() - 1;
        let t_end = p.duration();
        // n / rate reaches T (up to the stated rounding), (n - 1) / rate does not.
        prop_assert!(n as f64 / rate >= t_end * (1.0 - 128.0 * f64::EPSILON));
        prop_assert!(n == 0 || ((n - 1) as f64) / rate < t_end);
        let mut count = 0;
        let mut last = None;
        for (k, x) in s.enumerate() {
            prop_assert_eq!(x.index, k);
            prop_assert_eq!(x.time, k as f64 / rate); // computed, not accumulated
            if k < n {
                prop_assert_eq!(x.state, p.sample(x.time));
            }
            count += 1;
            last = Some(x);
        }
        prop_assert_eq!(count, n + 1);
        let last = last.ok_or_else(|| TestCaseError::fail("no sample"))?;
        prop_assert_eq!(last.state, State::rest(p.goal()));
    }

    /// Both ends of the iterator agree; nth skips exactly.
    #[test]
    fn double_ended(d in log_uniform(-1.0, 1.0), rate in 1.0..200.0_f64, skip in 0usize..50) {
        let p = Trapezoid::new(0.0, d, Limits::new(1.0, 1.0)).map_err(fail)?;
        let fwd: Vec<_> = p.sampler(rate).map_err(fail)?.collect();
        let mut back: Vec<_> = p.sampler(rate).map_err(fail)?.rev().collect();
        back.reverse();
        prop_assert_eq!(&fwd, &back);
        let mut s = p.sampler(rate).map_err(fail)?;
        prop_assert_eq!(s.nth(skip), fwd.get(skip).copied());
    }

    #[test]
    fn f32_exact_end(d in 0.01..100.0_f32, rate in 1.0..2000.0_f32) {
        let p = Trapezoid::new(-3.0_f32, -3.0 - d, Limits::new(2.0, 1.5)).map_err(fail)?;
        let s = p.sampler(rate).map_err(fail)?;
        let n = s.len() - 1;
        prop_assert!(n == 0 || ((n - 1) as f32) / rate < p.duration());
        let last = s.last().ok_or_else(|| TestCaseError::fail("no sample"))?;
        prop_assert_eq!(last.index, n);
        prop_assert_eq!(last.state, State::rest(p.goal()));
    }
}

#[test]
fn zero_duration_gives_one_sample_at_the_goal() -> Result<(), Error> {
    let p = Trapezoid::new(2.0_f64, 2.0, Limits::new(1.0, 1.0))?;
    let v: Vec<_> = p.sampler(1000.0)?.collect();
    assert_eq!(v.len(), 1);
    assert_eq!(
        (v[0].index, v[0].time, v[0].state),
        (0, 0.0, State::rest(2.0))
    );
    Ok(())
}

#[test]
fn a_duration_off_the_grid_ends_at_the_next_period() -> Result<(), Error> {
    // 2 sqrt(3) s = 3.4641 s at 1 kHz: 3466 samples, the last at 3.465 s on the goal.
    let p = Trapezoid::new(0.0_f64, 15.0, Limits::new(10.0, 5.0))?;
    let s = Sampler::new(p, 1000.0)?;
    assert_eq!(s.len(), 3466);
    let last = s.last().ok_or(Error::InvalidRate { value: 0.0 })?;
    assert_eq!(last.time, 3.465);
    assert_eq!(last.state, State::rest(15.0));
    Ok(())
}

#[test]
fn rounding_does_not_add_a_sample() -> Result<(), Error> {
    // 0.1 + 0.2 != 0.3 in f64; a duration that is a multiple of the period up to
    // rounding gives n = T * rate exactly.
    let p = Trapezoid::with_duration(0.0_f64, 0.01, Limits::new(1.0, 1.0), 0.1 + 0.2)?;
    assert!(p.duration() > 0.3 && p.duration() * 10.0 > 3.0);
    let s = p.sampler(10.0)?;
    assert_eq!(s.len(), 4);
    let last = s.last().ok_or(Error::InvalidRate { value: 0.0 })?;
    assert_eq!((last.time, last.state), (0.3, State::rest(0.01)));
    Ok(())
}

#[test]
fn bad_rates_are_errors() -> Result<(), Error> {
    let p = Trapezoid::new(0.0_f64, 1.0, Limits::new(1.0, 1.0))?;
    for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(p.sampler(r), Err(Error::InvalidRate { .. })));
    }
    assert!(matches!(
        p.sampler(1e300),
        Err(Error::TooManySamples { .. })
    ));
    Ok(())
}

#[test]
fn multi_axis_sampling_by_reference() -> Result<(), Error> {
    let m = Multi::new(
        [0.0_f64, 1.0],
        [1.0, 0.0],
        [Limits::new(1.0, 1.0); 2],
        Synchronization::Time,
    )?;
    let s = (&m).sampler(100.0)?;
    assert_eq!(s.sample_count(), s.len());
    let last = s.last().ok_or(Error::InvalidRate { value: 0.0 })?;
    assert_eq!(last.state, [State::rest(1.0), State::rest(0.0)]);
    Ok(())
}
