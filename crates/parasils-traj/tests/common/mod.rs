//! Shared checks for the property tests: generic over the float type, with
//! tolerances derived from the float epsilon and the sizes involved.
#![allow(dead_code)]

use parasils_traj::{Profile, Real, State};
use proptest::prelude::*;

/// Number of cases per property (a whole run of the crate's tests takes about a second).
pub const CASES: u32 = 10_000;

/// `10^e` for `e` uniform in `lo..hi`: log-uniform magnitudes.
pub fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    (lo..hi).prop_map(|e| 10f64.powf(e))
}

/// A relative offset near 0: exactly 0, or `+-10^e` with `e` in `-16..-2`.
pub fn near_zero() -> impl Strategy<Value = f64> + Clone {
    prop_oneof![
        1 => Just(0.0),
        6 => (-16.0..-2.0_f64, any::<bool>()).prop_map(|(e, neg)| if neg { -10f64.powf(e) } else { 10f64.powf(e) }),
    ]
}

/// The limits one axis must respect, as magnitudes; `jerk` is optional.
#[derive(Debug, Clone, Copy)]
pub struct Bounds<T> {
    pub v: T,
    pub a: T,
    pub j: Option<T>,
}

/// Converts an f64 to the float type under test.
pub fn c<T: Real>(x: f64) -> T {
    T::lit(x)
}

/// Position scale of a profile: `|start| + |goal| + distance`.
pub fn scale<T: Real, P: Profile<T>>(p: &P) -> T {
    p.start().abs() + p.goal().abs() + p.distance()
}

/// The exact-end and outside-the-motion conventions.
pub fn check_ends<T: Real, P: Profile<T>>(p: &P) -> Result<(), TestCaseError> {
    let t_end = p.duration();
    prop_assert_eq!(p.sample(T::zero()), State::rest(p.start()));
    prop_assert_eq!(p.sample(-T::one()), State::rest(p.start()));
    prop_assert_eq!(p.sample(T::lit(f64::NAN)), State::rest(p.start()));
    prop_assert_eq!(p.sample(t_end), State::rest(p.goal()));
    prop_assert_eq!(p.sample(t_end + t_end + T::one()), State::rest(p.goal()));
    prop_assert_eq!(p.sample(T::INFINITY), State::rest(p.goal()));
    Ok(())
}

/// Limits, monotonic progress, no overshoot and finiteness on a grid of
/// `m` points plus the given switch instants and their neighbours.
pub fn check_limits_and_path<T: Real, P: Profile<T>>(
    p: &P,
    b: Bounds<T>,
    switches: &[T],
    m: usize,
) -> Result<(), TestCaseError> {
    let rel = c::<T>(16.0) * T::EPSILON;
    let big = scale(p);
    let tol_p = c::<T>(8.0) * T::EPSILON * big;
    let (lo, hi) = (p.start().min(p.goal()), p.start().max(p.goal()));
    let dir = (p.goal() - p.start()).signum();
    let mut times = grid_times(p.duration(), switches, m);
    times.sort_by(|x, y| x.partial_cmp(y).unwrap_or(core::cmp::Ordering::Equal));
    let mut prev = p.start();
    for &t in &times {
        let s = p.sample(t);
        prop_assert!(
            s.position.is_finite() && s.velocity.is_finite() && s.acceleration.is_finite()
        );
        prop_assert!(
            s.velocity.abs() <= b.v * (T::one() + rel),
            "v {:?} > {:?} at t={:?}",
            s.velocity,
            b.v,
            t
        );
        prop_assert!(
            s.acceleration.abs() <= b.a * (T::one() + rel),
            "a {:?} > {:?} at t={:?}",
            s.acceleration,
            b.a,
            t
        );
        prop_assert!(
            s.position >= lo - tol_p && s.position <= hi + tol_p,
            "overshoot {:?} at {:?}",
            s.position,
            t
        );
        if p.distance() > T::zero() {
            prop_assert!(
                (s.position - prev) * dir >= -tol_p,
                "goes back: {:?} after {:?} at t={:?}",
                s.position,
                prev,
                t
            );
            prop_assert!(
                s.velocity * dir >= T::zero(),
                "velocity against the motion at {:?}",
                t
            );
        }
        prev = s.position;
    }
    Ok(())
}

/// Grid times in `(0, T)`, the switches, and one ulp-ish either side.
fn grid_times<T: Real>(t_end: T, switches: &[T], m: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(m + 3 * switches.len());
    for k in 1..m {
        v.push(t_end * T::from_index(k) / T::from_index(m));
    }
    let nudge = t_end * T::EPSILON * c(4.0);
    for &s in switches {
        for t in [s - nudge, s, s + nudge] {
            if t > T::zero() && t < t_end {
                v.push(t);
            }
        }
    }
    v
}

/// Position continuity across each switch instant: the jump between just
/// before and at the switch is at most what the velocity explains plus rounding.
pub fn check_continuity<T: Real, P: Profile<T>>(
    p: &P,
    switches: &[T],
) -> Result<(), TestCaseError> {
    let big = scale(p);
    let nudge = p.duration() * T::EPSILON * c(4.0);
    for &s in switches {
        if !(s > T::zero() && s < p.duration()) {
            continue;
        }
        let (x, y) = (p.sample(s - nudge), p.sample(s));
        let tol = c::<T>(16.0) * T::EPSILON * big + p.peak_velocity() * nudge * c(2.0);
        prop_assert!(
            (x.position - y.position).abs() <= tol,
            "position jumps by {:?} at switch {:?}",
            y.position - x.position,
            s
        );
        let tol_v =
            c::<T>(16.0) * T::EPSILON * p.peak_velocity() + p.peak_acceleration() * nudge * c(2.0);
        prop_assert!(
            (x.velocity - y.velocity).abs() <= tol_v,
            "velocity jumps at switch {:?}",
            s
        );
    }
    Ok(())
}

/// Central finite differences at points at least `2h` from every switch:
/// velocity is the derivative of position and acceleration that of velocity.
/// `jerk_term` bounds the truncation error of the position difference
/// (`j h^2 / 6` for a cubic, 0 for a quadratic).
pub fn check_derivatives<T: Real, P: Profile<T>>(
    p: &P,
    switches: &[T],
    h_rel: T,
    fractions: &[f64],
    jerk: Option<T>,
) -> Result<(), TestCaseError> {
    let t_end = p.duration();
    if p.distance() == T::zero() || t_end == T::zero() {
        return Ok(()); // nothing moves (e.g. a distance below one ulp of the start)
    }
    let h = t_end * h_rel;
    let big = scale(p);
    let eps = T::EPSILON;
    let mut checked = 0;
    for &f in fractions {
        let t = t_end * c(f);
        let near = switches
            .iter()
            .chain([T::zero(), t_end].iter())
            .any(|&s| (t - s).abs() < h + h);
        if near {
            continue;
        }
        let (m, z, pl) = (p.sample(t - h), p.sample(t), p.sample(t + h));
        let two_h = h + h;
        let dp = (pl.position - m.position) / two_h;
        let trunc = jerk.map_or(T::zero(), |j| j * h * h / c(6.0));
        // Rounding of positions, and of times (`T - t` and the like, `eps T` each).
        let tol_v = c::<T>(8.0) * eps * (big + t_end * p.peak_velocity()) / h + trunc;
        prop_assert!(
            (dp - z.velocity).abs() <= tol_v,
            "dp/dt {:?} vs v {:?} at t={:?} (tol {:?})",
            dp,
            z.velocity,
            t,
            tol_v
        );
        let dv = (pl.velocity - m.velocity) / two_h;
        let tol_a = c::<T>(8.0) * eps * (p.peak_velocity() + t_end * p.peak_acceleration()) / h;
        prop_assert!(
            (dv - z.acceleration).abs() <= tol_a,
            "dv/dt {:?} vs a {:?} at t={:?} (tol {:?})",
            dv,
            z.acceleration,
            t,
            tol_a
        );
        checked += 1;
    }
    let _ = checked;
    Ok(())
}
