//! Property tests of the online profiles (any state to rest, the controlled
//! stop), in f64 and f32, 10^5 cases per property: limits within 16 epsilons,
//! the target reached exactly and at rest, no overshoot where none is needed,
//! the duration never longer than braking to a full stop and then going
//! rest to rest, continuity at replans; and hand-derived cases.
#![allow(
    clippy::float_cmp,
    reason = "exact ends and exact start states are what these tests check"
)]

mod common;

use common::{c, log_uniform, near_zero};
use parasils_traj::{
    Error, LimitKind, Limits, Motion, OnlineMulti, OnlineTrapezoid, Real, State, Synchronization,
    Trapezoid,
};
use proptest::prelude::*;

/// Cases per property.
const CASES: u32 = 100_000;

fn fail(e: Error) -> TestCaseError {
    TestCaseError::fail(format!("{e}"))
}

fn moving<T: Real>(position: T, velocity: T) -> State<T> {
    State {
        position,
        velocity,
        acceleration: T::zero(),
    }
}

/// One axis's problem, drawn in f64 and converted to the type under test.
#[derive(Debug, Clone, Copy)]
struct Case {
    p0: f64,
    v0: f64,
    target: f64,
    v_max: f64,
    a_max: f64,
}

impl Case {
    fn start<T: Real>(&self) -> State<T> {
        moving(c(self.p0), c(self.v0))
    }
    fn target<T: Real>(&self) -> T {
        c(self.target)
    }
    fn limits<T: Real>(&self) -> Limits<T> {
        Limits::new(c(self.v_max), c(self.a_max))
    }
}

/// Random problems: positions in `-p..p`, distances `10^(lo..hi)`, limits
/// `10^(vl)`, `10^(al)`, velocities up to 1.5 `v_max` (and exactly 0 or
/// `+-v_max`), targets anywhere, on the start, or at or near the stopping point.
fn case(
    p: f64,
    lo: f64,
    hi: f64,
    vl: (f64, f64),
    al: (f64, f64),
) -> impl Strategy<Value = Case> + Clone {
    let factor = prop_oneof![
        1 => Just(0.0),
        1 => Just(1.0),
        1 => Just(-1.0),
        6 => -1.5..1.5_f64,
    ];
    let signed = (log_uniform(lo, hi), any::<bool>()).prop_map(|(d, n)| if n { -d } else { d });
    // 0: from p0; 1: from the stopping point, offset by `d`; 2: the stopping point times (1 + small).
    let target = prop_oneof![
        4 => (Just(0_u8), signed.clone()),
        1 => (Just(0_u8), Just(0.0)),
        2 => (Just(1_u8), signed),
        2 => (Just(2_u8), near_zero()),
    ];
    (
        -p..p,
        factor,
        target,
        log_uniform(vl.0, vl.1),
        log_uniform(al.0, al.1),
    )
        .prop_map(|(p0, f, (kind, off), v_max, a_max)| {
            let v0 = f * v_max;
            let stop = 0.5 * v0 * v0.abs() / a_max;
            let target = match kind {
                0 => p0 + off,
                1 => p0 + stop + off,
                _ => p0 + stop * (1.0 + off),
            };
            Case {
                p0,
                v0,
                target,
                v_max,
                a_max,
            }
        })
}

fn case_f64() -> impl Strategy<Value = Case> + Clone {
    case(1e2, -3.0, 3.0, (-2.0, 2.0), (-2.0, 3.0))
}

fn case_f32() -> impl Strategy<Value = Case> + Clone {
    case(10.0, -2.0, 2.0, (-1.0, 1.0), (-1.0, 2.0))
}

/// The rounding of positions of one axis: 16 eps of the largest position involved.
fn rounding<T: Real>(p0: T, v0: T, target: T, a_max: T) -> T {
    let stop = v0 * v0 / a_max;
    c::<T>(16.0) * T::EPSILON * (p0.abs() + target.abs() + stop)
}

/// How far a duration may move when the positions move by `delta`: the time
/// to cover `delta` at the slowest velocity the profile can be at when it
/// matters, `min(v_max, sqrt(a_max |gap|))`, `gap` the distance from the
/// stopping point to the target (at least `delta`).
fn time_slack<T: Real>(delta: T, gap: T, lim: Limits<T>) -> T {
    if delta == T::zero() {
        return T::zero();
    }
    let v = lim.v_max.min((lim.a_max * gap.abs().max(delta)).sqrt());
    c::<T>(4.0) * delta / v
}

/// Times in `(0, T)`: a grid of `m` points, the switches and their neighbours.
fn times<T: Real>(t_end: T, switches: &[T], m: usize) -> Vec<T> {
    let mut v: Vec<T> = (1..m)
        .map(|k| t_end * T::from_index(k) / T::from_index(m))
        .collect();
    let nudge = t_end * T::EPSILON * c(4.0);
    for &s in switches {
        for t in [s - nudge, s, s + nudge] {
            if t > T::zero() && t < t_end {
                v.push(t);
            }
        }
    }
    v.sort_by(|x, y| x.partial_cmp(y).unwrap_or(core::cmp::Ordering::Equal));
    v
}

/// The conventions at the ends, the limits, continuity at the switches and at
/// the end, and (when `monotone`) a position that never goes back.
fn check_profile<T: Real>(
    p: &OnlineTrapezoid<T>,
    lim: Limits<T>,
    monotone: bool,
) -> Result<(), TestCaseError> {
    let (p0, v0, target, t_end) = (p.start(), p.start_velocity(), p.target(), p.duration());
    let start = moving(p0, v0);
    prop_assert_eq!(p.sample(T::zero()), start);
    prop_assert_eq!(p.sample(-T::one()), start);
    prop_assert_eq!(p.sample(T::lit(f64::NAN)), start);
    prop_assert_eq!(p.sample(t_end), State::rest(target));
    prop_assert_eq!(p.sample(t_end + t_end + T::one()), State::rest(target));
    prop_assert_eq!(p.sample(T::INFINITY), State::rest(target));
    prop_assert!(t_end.is_finite() && t_end >= T::zero());

    let rel = T::one() + c::<T>(16.0) * T::EPSILON;
    // The rounding of the positions met: 16 eps of the largest.
    let tol_p = rounding(p0, v0, target, lim.a_max)
        + c::<T>(16.0) * T::EPSILON * p.peak_velocity() * t_end;
    let (lo, hi) = (p0.min(target), p0.max(target));
    let dir = (target - p0).signum();
    let braking = v0.abs() > lim.v_max;
    let mut prev = moving(p0, v0);
    let mut prev_t = T::zero();
    for t in times(t_end, &p.switches(), 24) {
        let s = p.sample(t);
        prop_assert!(
            s.position.is_finite() && s.velocity.is_finite() && s.acceleration.is_finite()
        );
        prop_assert!(
            s.acceleration.abs() <= lim.a_max * rel,
            "a {:?} > {:?} at {:?}",
            s.acceleration,
            lim.a_max,
            t
        );
        let v_bound = if braking && t < p.t_first() {
            v0.abs()
        } else {
            lim.v_max
        };
        prop_assert!(
            s.velocity.abs() <= v_bound * rel,
            "v {:?} > {:?} at {:?}",
            s.velocity,
            v_bound,
            t
        );
        // Continuity: the position moves by what the velocities explain.
        let dt = t - prev_t;
        let expect = prev.position + T::lit(0.5) * (prev.velocity + s.velocity) * dt;
        let tol_step = tol_p + lim.a_max * dt * dt;
        prop_assert!(
            (s.position - expect).abs() <= tol_step,
            "position jumps from {:?} to {:?} over {:?} s at {:?}",
            prev.position,
            s.position,
            dt,
            t
        );
        // Rounding of `v0 + a t`.
        let tol_v = c::<T>(16.0) * T::EPSILON * (v0.abs() + lim.v_max + lim.a_max * t);
        prop_assert!(
            (s.velocity - prev.velocity).abs() <= lim.a_max * dt * rel + tol_v,
            "velocity jumps from {:?} to {:?} at {:?}",
            prev.velocity,
            s.velocity,
            t
        );
        if monotone {
            prop_assert!(
                s.position >= lo - tol_p && s.position <= hi + tol_p,
                "overshoot: {:?} at {:?}",
                s.position,
                t
            );
            prop_assert!(
                (s.position - prev.position) * dir >= -tol_p,
                "goes back: {:?} after {:?} at {:?}",
                s.position,
                prev.position,
                t
            );
        }
        prev = s;
        prev_t = t;
    }
    // The last phase ends on the target at rest.
    let dt = t_end - prev_t;
    prop_assert!(
        (target - prev.position - T::lit(0.5) * prev.velocity * dt).abs()
            <= tol_p + lim.a_max * dt * dt
    );
    prop_assert!(
        prev.velocity.abs() <= lim.a_max * dt * rel + c::<T>(16.0) * T::EPSILON * lim.v_max
    );
    Ok(())
}

/// True when `v0` points towards the target (or is zero) and the target is
/// beyond the stopping point: no overshoot is needed.
fn needs_no_overshoot<T: Real>(p0: T, v0: T, target: T, lim: Limits<T>) -> bool {
    let d = target - p0;
    let stop = T::lit(0.5) * v0 * v0 / lim.a_max;
    v0 * d >= T::zero() && d.abs() >= stop
}

/// The minimum time, written independently of the implementation (from the
/// rest-to-rest trapezoid): the axis either passes through rest at its
/// stopping point (moving away, or the target before the stopping point), or
/// is the tail of a rest-to-rest profile from a virtual start, or brakes to
/// `v_max` and cruises. Also returns the upper bound of the requirements,
/// braking to rest then rest-to-rest.
fn reference<T: Real>(p0: T, v0: T, target: T, lim: Limits<T>) -> Result<(T, T), TestCaseError> {
    let half = T::lit(0.5);
    let (vm, am) = (lim.v_max, lim.a_max);
    let t_brake = v0.abs() / am;
    let stop = p0 + half * v0 * v0.abs() / am;
    let bound = t_brake + Trapezoid::new(stop, target, lim).map_err(fail)?.duration();
    let d = target - p0;
    let exact = if needs_no_overshoot(p0, v0, target, lim) {
        if v0.abs() <= vm {
            let virtual_start = p0 - half * v0 * v0.abs() / am;
            Trapezoid::new(virtual_start, target, lim)
                .map_err(fail)?
                .duration()
                - t_brake
        } else {
            t_brake + (d.abs() - half * v0 * v0 / am) / vm
        }
    } else {
        bound
    };
    Ok((exact, bound))
}

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
                tol_t = tol_t + c::<T>(4.0) * rel * m.duration();
            }
        }
    }
    for (i, k) in ks.iter().enumerate() {
        let l = shares[i];
        let (x, g) = (s[i], target[i]);
        let delta = rounding(x.position, x.velocity, g, l.a_max)
            + rounding(k.start::<T>().position, k.start::<T>().velocity, g, l.a_max);
        let gap = g - (x.position + T::lit(0.5) * x.velocity * x.velocity.abs() / l.a_max);
        tol_t = tol_t + time_slack(delta, gap, l);
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
            tol = tol + time_slack(delta, gap, limits[i]);
        }
        tol = tol + c::<T>(64.0) * T::EPSILON * longest;
        prop_assert!(
            (m.duration() - longest).abs() <= tol,
            "line {:?} vs slowest axis {:?}",
            m.duration(),
            longest
        );
    }
    Ok(())
}

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

/// Any f64 bit pattern (NaN, infinities, subnormals included), or a
/// moderate value so that valid problems are drawn too.
fn anything() -> impl Strategy<Value = f64> {
    prop_oneof![any::<f64>(), -1e3..1e3_f64]
}

/// Limits shared by every axis, or drawn for each.
fn group<const N: usize>(
    one: impl Strategy<Value = Case> + Clone,
) -> impl Strategy<Value = [Case; N]> {
    (proptest::array::uniform::<_, N>(one), any::<bool>()).prop_map(|(mut ks, same)| {
        if same {
            let (v, a) = (ks[0].v_max, ks[0].a_max);
            for k in &mut ks {
                k.v_max = v;
                k.a_max = a;
            }
        }
        ks
    })
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

    #[test]
    fn f64_stop(ks in group::<3>(case_f64())) {
        check_stop::<f64, 3>(&ks)?;
    }

    #[test]
    fn f32_stop(ks in group::<3>(case_f32())) {
        check_stop::<f32, 3>(&ks)?;
    }

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
