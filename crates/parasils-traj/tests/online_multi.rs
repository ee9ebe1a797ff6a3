//! Property tests of the online profiles of several axes, synchronised, in
//! f64 and f32, 10^5 cases per property: time synchronisation (one
//! duration, the longest minimum time), phase kept as a straight line when
//! the velocity allows it and falling back to time otherwise, replans of the
//! group from its own state; hand-derived groups and stops, the sampler.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact start states are what these tests check"
)]

mod common;
mod online_common;

use common::{c, log_uniform};
use online_common::{
    CASES, Case, case_f32, case_f64, check_profile, fail, group, moving, needs_no_overshoot,
    rounding, time_slack,
};
use parasils_traj::{
    Error, Limits, Motion, OnlineMulti, OnlineTrapezoid, Real, State, Synchronization,
};
use proptest::prelude::*;

/// Time synchronisation of `N` axes: one duration, the longest minimum time,
/// each axis within its limits, no overshoot where none is needed.
fn check_time<T: Real, const N: usize>(
    ks: &[Case; N],
    sync: Synchronization,
) -> Result<OnlineMulti<T, N>, TestCaseError> {
    let start = ks.map(|k| k.start::<T>());
    let target = ks.map(|k| k.target::<T>());
    let limits = ks.map(|k| k.limits::<T>());
    let m = OnlineMulti::new(start, target, limits, sync).map_err(fail)?;
    let own: Vec<T> = ks
        .iter()
        .map(|k| OnlineTrapezoid::new(k.start::<T>(), k.target::<T>(), k.limits::<T>()))
        .map(|p| p.map(|p| p.duration()))
        .collect::<Result<_, _>>()
        .map_err(fail)?;
    let longest = own.iter().fold(T::zero(), |a, b| a.max(*b));
    let line = m.synchronization() == Synchronization::Phase;
    if line {
        // Parallel by chance (at rest, typically): the straight line, no
        // faster than the slowest axis (tested further in `check_phase`).
        prop_assert!(m.duration() >= longest * (T::one() - c::<T>(16.0) * T::EPSILON));
    } else {
        prop_assert_eq!(m.duration(), longest);
    }
    if m.synchronization() == Synchronization::Time {
        prop_assert!(m.axes().iter().all(|p| p.duration() == longest));
    }
    for (p, k) in m.axes().iter().zip(ks) {
        let (s, g, l) = (k.start::<T>(), k.target::<T>(), k.limits::<T>());
        check_profile(
            p,
            l,
            !line && needs_no_overshoot(s.position, s.velocity, g, l),
        )?;
    }
    Ok(m)
}

/// Replanning a group at `t` from its own state, with the same request.
fn check_multi_replan<T: Real, const N: usize>(
    m: &OnlineMulti<T, N>,
    ks: &[Case; N],
    frac: f64,
) -> Result<(), TestCaseError> {
    let t = m.duration() * c(frac);
    if !(t > T::zero() && t < m.duration()) {
        return Ok(());
    }
    let target = ks.map(|k| k.target::<T>());
    let limits = ks.map(|k| k.limits::<T>());
    let s = m.sample(t);
    let q = OnlineMulti::new(s, target, limits, m.synchronization()).map_err(fail)?;
    for (a, b) in q.sample(T::zero()).iter().zip(&s) {
        prop_assert_eq!((a.position, a.velocity), (b.position, b.velocity));
    }
    if q.synchronization() != m.synchronization() {
        return Ok(());
    }
    // Along a line, each axis moves under its share of the line's limits:
    // its rounding is worth that much more time.
    let disp: [T; N] = core::array::from_fn(|i| target[i] - s[i].position);
    let shares = if q.synchronization() == Synchronization::Phase {
        line_shares(disp, limits)
    } else {
        limits
    };
    let mut tol_t = c::<T>(64.0) * T::EPSILON * m.duration();
    if q.synchronization() == Synchronization::Phase {
        // The line's shares come from the remaining displacements, each
        // known only to the rounding of its two ends: a short displacement
        // far from 0 gives its axis a share known to
        // `eps (|x| + |g|) / |g - x|` relative, and the line's scaled
        // limits, so its duration, move by as much.
        for i in 0..N {
            let d = disp[i].abs();
            if d > T::zero() {
                let rel = T::EPSILON * (s[i].position.abs() + target[i].abs()) / d;
                tol_t += c::<T>(4.0) * rel * m.duration();
            }
        }
    }
    for (i, k) in ks.iter().enumerate() {
        let l = shares[i];
        let (x, g) = (s[i], target[i]);
        let delta = rounding(x.position, x.velocity, g, l.a_max)
            + rounding(k.start::<T>().position, k.start::<T>().velocity, g, l.a_max);
        let gap = g - (x.position + T::lit(0.5) * x.velocity * x.velocity.abs() / l.a_max);
        tol_t += time_slack(delta, gap, l);
    }
    let rest = m.duration() - t;
    prop_assert!(
        (q.duration() - rest).abs() <= tol_t,
        "replanned group at {:?}: {:?} s left vs {:?} (tol {:?})",
        t,
        q.duration(),
        rest,
        tol_t
    );
    Ok(())
}

/// The line's limits scaled to each axis (`k_i = |d_i| / max |d|`): the
/// fastest straight line within every axis's limits; an axis that does not
/// move keeps its own.
fn line_shares<T: Real, const N: usize>(disp: [T; N], limits: [Limits<T>; N]) -> [Limits<T>; N] {
    let big = disp.iter().fold(T::zero(), |a, d| a.max(d.abs()));
    let (mut v, mut a) = (T::INFINITY, T::INFINITY);
    for (d, l) in disp.iter().zip(&limits) {
        if *d != T::zero() {
            v = v.min(l.v_max * big / d.abs());
            a = a.min(l.a_max * big / d.abs());
        }
    }
    core::array::from_fn(|i| {
        let k = disp[i].abs() / big;
        if k > T::zero() {
            Limits::new(v * k, a * k)
        } else {
            limits[i]
        }
    })
}

/// A straight line: every moving axis's progress `(p_i - p0_i) / d_i` equals
/// the longest axis's, within the rounding of positions.
fn check_line<T: Real, const N: usize>(
    m: &OnlineMulti<T, N>,
    disp: [T; N],
) -> Result<(), TestCaseError> {
    let axes = m.axes();
    let Some(l) = (0..N).max_by(|&i, &j| {
        disp[i]
            .abs()
            .partial_cmp(&disp[j].abs())
            .unwrap_or(core::cmp::Ordering::Equal)
    }) else {
        return Ok(());
    };
    if disp[l] == T::zero() {
        return Ok(());
    }
    for k in 0..=16 {
        let t = m.duration() * T::from_index(k) / c(16.0);
        let s = m.sample(t);
        let lead = (s[l].position - axes[l].start()) / disp[l];
        for i in (0..N).filter(|&i| disp[i] != T::zero()) {
            let x = (s[i].position - axes[i].start()) / disp[i];
            let tol = c::<T>(64.0)
                * T::EPSILON
                * (T::one() + lead.abs())
                * (T::one()
                    + (axes[i].start().abs() + axes[i].target().abs()) / disp[i].abs()
                    + (axes[l].start().abs() + axes[l].target().abs()) / disp[l].abs());
            prop_assert!(
                (x - lead).abs() <= tol,
                "axis {} at {:?} off the line: {:?} vs {:?}",
                i,
                t,
                x,
                lead
            );
        }
    }
    Ok(())
}

/// Velocities along the displacement (`v0_i = lambda d_i`): phase is kept.
fn check_phase<T: Real, const N: usize>(
    ks: &[Case; N],
    lambda: f64,
    frac: f64,
) -> Result<(), TestCaseError> {
    // Parallel in the type under test: from its own displacement.
    let start = ks.map(|k| {
        let p0 = c::<T>(k.p0);
        moving(p0, c::<T>(lambda) * (k.target::<T>() - p0))
    });
    let target = ks.map(|k| k.target::<T>());
    let limits = ks.map(|k| k.limits::<T>());
    let m = OnlineMulti::new(start, target, limits, Synchronization::Phase).map_err(fail)?;
    let fast = start
        .iter()
        .zip(&limits)
        .any(|(s, l)| s.velocity.abs() > l.v_max * (T::one() + c::<T>(64.0) * T::EPSILON));
    if fast {
        // An axis above its limit brakes at its own a_max: not a line.
        prop_assert_eq!(m.synchronization(), Synchronization::Time);
        return Ok(());
    }
    prop_assert_eq!(m.synchronization(), Synchronization::Phase);
    let disp: [T; N] = core::array::from_fn(|i| target[i] - start[i].position);
    // No overshoot is needed when none is under the axis's share of the line.
    let shares = line_shares(disp, limits);
    for (i, p) in m.axes().iter().enumerate() {
        let monotone = disp[i] != T::zero()
            && needs_no_overshoot(start[i].position, start[i].velocity, target[i], shares[i]);
        check_profile(p, limits[i], monotone)?;
    }
    check_line(&m, disp)?;
    check_multi_replan(&m, ks, frac)?;
    // With one set of limits the line takes the slowest axis's minimum time.
    if ks
        .iter()
        .all(|k| k.v_max == ks[0].v_max && k.a_max == ks[0].a_max)
    {
        let mut longest = T::zero();
        let mut tol = T::zero();
        for i in 0..N {
            let own = OnlineTrapezoid::new(start[i], target[i], limits[i]).map_err(fail)?;
            longest = longest.max(own.duration());
            let delta = rounding(
                start[i].position,
                start[i].velocity,
                target[i],
                limits[i].a_max,
            );
            let gap = target[i]
                - (start[i].position
                    + T::lit(0.5) * start[i].velocity * start[i].velocity.abs() / limits[i].a_max);
            tol += time_slack(delta, gap, limits[i]);
        }
        tol += c::<T>(64.0) * T::EPSILON * longest;
        prop_assert!(
            (m.duration() - longest).abs() <= tol,
            "line {:?} vs slowest axis {:?}",
            m.duration(),
            longest
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]
    #[test]
    fn f64_time_sync(ks in group::<2>(case_f64()), frac in 0.0..1.0_f64) {
        let m = check_time::<f64, 2>(&ks, Synchronization::Time)?;
        prop_assert_eq!(m.synchronization(), Synchronization::Time);
        check_multi_replan(&m, &ks, frac)?;
    }

    #[test]
    fn f32_time_sync(ks in group::<2>(case_f32()), frac in 0.0..1.0_f64) {
        let m = check_time::<f32, 2>(&ks, Synchronization::Time)?;
        prop_assert_eq!(m.synchronization(), Synchronization::Time);
        check_multi_replan(&m, &ks, frac)?;
    }

    /// Phase asked for with random velocities: time is used (and reported)
    /// unless the velocity happens to be parallel.
    #[test]
    fn f64_phase_falls_back(ks in group::<3>(case_f64()), frac in 0.0..1.0_f64) {
        let m = check_time::<f64, 3>(&ks, Synchronization::Phase)?;
        check_multi_replan(&m, &ks, frac)?;
    }

    #[test]
    fn f32_phase_falls_back(ks in group::<3>(case_f32()), frac in 0.0..1.0_f64) {
        let m = check_time::<f32, 3>(&ks, Synchronization::Phase)?;
        check_multi_replan(&m, &ks, frac)?;
    }

    #[test]
    fn f64_phase_line(ks in group::<3>(case_f64()),
                      lambda in prop_oneof![Just(0.0), -3.0..3.0_f64, log_uniform(-3.0, 1.0)],
        frac in 0.0..1.0_f64) {
        check_phase::<f64, 3>(&ks, lambda, frac)?;
    }

    #[test]
    fn f32_phase_line(ks in group::<3>(case_f32()),
                      lambda in prop_oneof![Just(0.0), -3.0..3.0_f64, log_uniform(-3.0, 1.0)],
        frac in 0.0..1.0_f64) {
        check_phase::<f32, 3>(&ks, lambda, frac)?;
    }

}

#[test]
fn hand_derived_groups() -> Result<(), Error> {
    let lim = [Limits::new(2.0_f64, 1.0); 2];
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    // Axis 0 from rest over 10 units (7 s); axis 1 on its target moving at 1,
    // out and back in 1 + sqrt(2) s alone, stretched to 7 s.
    let m = OnlineMulti::new(
        [State::rest(0.0), moving(0.0, 1.0)],
        [10.0, 0.0],
        lim,
        Synchronization::Phase,
    )?;
    assert_eq!(m.synchronization(), Synchronization::Time);
    assert_eq!(m.lead(), Some(0));
    assert_eq!(m.duration(), 7.0);
    let [a, b] = m.axes();
    assert_eq!(a.duration(), 7.0);
    assert_eq!(b.duration(), 7.0);
    assert_eq!(b.first_acceleration().abs(), 1.0);
    // Axis 1 goes out 0.5 + its cruise and comes back: a peak below v_max.
    assert!(b.reverses() && b.cruise_velocity() < 0.0 && b.cruise_velocity() > -2.0);
    assert_eq!(m.sample(7.0), [State::rest(10.0), State::rest(0.0)]);
    // Time synchronisation where the slower cruise is reached by braking:
    // axis 1 at 2 towards a target 4 units ahead (2 s to stop + 1 s cruise
    // at 2 alone) must last 7 s: brake to v, cruise, stop:
    // 2 + v (7 - 2) = 4 gives v = 0.4.
    let m = OnlineMulti::new(
        [State::rest(0.0), moving(0.0, 2.0)],
        [10.0, 4.0],
        lim,
        Synchronization::Time,
    )?;
    let b = &m.axes()[1];
    assert!(close(b.cruise_velocity(), 0.4) && close(b.t_first(), 1.6) && close(b.t_cruise(), 5.0));
    assert_eq!(b.first_acceleration(), -1.0);
    // A velocity along the displacement keeps the straight line, here at
    // axis 0's limits (axis 1 moves half as far).
    let m = OnlineMulti::new(
        [moving(0.0, 1.0), moving(1.0, 0.5)],
        [10.0, 6.0],
        lim,
        Synchronization::Phase,
    )?;
    assert_eq!(m.synchronization(), Synchronization::Phase);
    let own = OnlineTrapezoid::new(moving(0.0, 1.0), 10.0, lim[0])?;
    assert!(close(m.duration(), own.duration()));
    for t in [0.5, 2.0, 4.0, 6.0] {
        let [x, y] = m.sample(t);
        assert!(close(y.position - 1.0, 0.5 * x.position));
        assert!(close(y.velocity, 0.5 * x.velocity));
    }
    // The controlled stop: axis 0 at 2 stops in 2 s at 1 unit/s^2, axis 1 at
    // 1 decelerates at 0.5 to stop at the same instant.
    let m = OnlineMulti::stop([moving(0.0, 2.0), moving(5.0, -1.0)], lim)?;
    assert_eq!(m.duration(), 2.0);
    let [a, b] = m.axes();
    assert_eq!(
        (a.first_acceleration(), b.first_acceleration()),
        (-1.0, 0.5)
    );
    assert_eq!((a.target(), b.target()), (2.0, 4.0));
    assert_eq!(m.sample(2.0), [State::rest(2.0), State::rest(4.0)]);
    // No synchronisation: each axis on its own minimum time.
    let m = OnlineMulti::new(
        [State::rest(0.0), moving(0.0, 2.0)],
        [10.0, 4.0],
        lim,
        Synchronization::None,
    )?;
    assert_eq!(m.synchronization(), Synchronization::None);
    assert_eq!(m.duration(), 7.0);
    assert!(close(m.axes()[1].duration(), 3.0));
    // A stop from rest takes no time.
    let m = OnlineMulti::stop([State::rest(1.0), State::rest(2.0)], lim)?;
    assert_eq!((m.duration(), m.lead()), (0.0, None));
    Ok(())
}

#[test]
fn sampler_ends_on_the_targets() -> Result<(), Error> {
    let m = OnlineMulti::new(
        [moving(0.0_f64, 1.5), moving(0.0, -0.5)],
        [1.0, 2.0],
        [Limits::new(2.0, 1.0); 2],
        Synchronization::Time,
    )?;
    let samples = m.sampler(1000.0)?;
    let first = samples
        .clone()
        .next()
        .ok_or(Error::InvalidRate { value: 0.0 })?;
    assert_eq!(first.state[0], moving(0.0, 1.5));
    let last = samples.last().ok_or(Error::InvalidRate { value: 0.0 })?;
    assert_eq!(last.state, [State::rest(1.0), State::rest(2.0)]);
    Ok(())
}

/// A line whose lead axis brakes nearly all the way (`h` small) and is
/// stretched by an ulp or two of time to the line's duration: in f32 the
/// accelerating root of the stretched plan fell below `u0`, so the cruise
/// (from `v0`, no first phase) and the last phase (from the root) differed by
/// 2.2e-4 units/s at their switch. Found by `f32_phase_line`.
#[test]
fn stretched_near_the_decelerating_case() -> Result<(), TestCaseError> {
    let ks = [
        Case {
            p0: 0.0,
            v0: 3.508_154_745_974_545,
            target: 16.288_625_698_882_64,
            v_max: 4.816_128_197_338_387,
            a_max: 0.377_783_551_209_847_2,
        },
        Case {
            p0: 0.0,
            v0: 0.0,
            target: 1.0,
            v_max: 1.0,
            a_max: 1.0,
        },
        Case {
            p0: 0.0,
            v0: -2.525_572_474_297_82,
            target: -4.560_004_233_367_136,
            v_max: 2.525_572_474_297_82,
            a_max: 5.477_155_869_777_102,
        },
    ];
    let lambda = 0.215_227_295_723_215_75;
    check_phase::<f32, 3>(&ks, lambda, 0.0)?;
    check_phase::<f64, 3>(&ks, lambda, 0.0)?;
    // The lead axis: the last phase starts from the cruise velocity.
    let start = ks.map(|k| moving(0.0_f32, c::<f32>(lambda) * k.target::<f32>()));
    let target = ks.map(|k| k.target::<f32>());
    let limits = ks.map(|k| k.limits::<f32>());
    let m = OnlineMulti::new(start, target, limits, Synchronization::Phase).map_err(fail)?;
    prop_assert_eq!(m.synchronization(), Synchronization::Phase);
    let p = &m.axes()[0];
    let end_of_cruise = -p.last_acceleration() * p.t_last();
    prop_assert!(
        (end_of_cruise - p.cruise_velocity()).abs()
            <= 4.0 * f32::EPSILON * p.cruise_velocity().abs(),
        "cruise {:?}, last phase from {:?}",
        p.cruise_velocity(),
        end_of_cruise
    );
    Ok(())
}
