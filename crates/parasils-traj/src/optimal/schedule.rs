//! The solved schedule `s(t)`: sampling, phases, and the check between
//! knots with its correction.

use crate::error::LimitKind;
use crate::profile::{Motion, State};
use crate::real::Real;

use super::solve::{fill_uniform, set_times, solve};
use super::types::{Certificate, Derivatives, Error, Knot, Path, Phase, RowLimits};

/// A solved schedule: `s(t)` piecewise with constant `s_ddot` between
/// knots, at rest at both ends. A view of the knots [`solve`] wrote.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Schedule<'a, T, const M: usize> {
    knots: &'a [Knot<T, M>],
}

impl<'a, T: Real, const M: usize> Schedule<'a, T, M> {
    /// The schedule last solved into `knots` (by [`solve`] or [`plan`]).
    /// Knots never solved read as a motion of zero duration.
    pub fn view(knots: &'a [Knot<T, M>]) -> Self {
        Self { knots }
    }

    /// The knots, with their `x`, `s_ddot` and `t`.
    pub fn knots(&self) -> &'a [Knot<T, M>] {
        self.knots
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.knots.last().map_or_else(T::zero, |k| k.t)
    }

    /// `(s, s_dot, s_ddot)` at `t` (s) as a [`State`]: the start at rest for
    /// `t <= 0` (and NaN), the end at rest for `t >= duration`; `s_ddot` is
    /// that of the interval that begins at `t` (right-continuous).
    pub fn state(&self, t: T) -> State<T> {
        let (Some(first), Some(last)) = (self.knots.first(), self.knots.last()) else {
            return State::rest(T::zero());
        };
        if !(t > T::zero()) {
            return State::rest(first.s);
        }
        if t >= last.t {
            return State::rest(last.s);
        }
        let p = self.knots.partition_point(|k| k.t <= t);
        let (Some(k0), Some(k1)) = (self.knots.get(p.wrapping_sub(1)), self.knots.get(p)) else {
            return State::rest(last.s);
        };
        let tau = t - k0.t;
        let v0 = k0.x.sqrt();
        let s = (k0.s + tau * (v0 + T::lit(0.5) * k0.u * tau))
            .max(k0.s)
            .min(k1.s);
        let s_dot = (v0 + k0.u * tau).max(T::zero());
        State {
            position: s,
            velocity: s_dot,
            acceleration: k0.u,
        }
    }

    /// The phases of the schedule: the stretches of intervals over which
    /// the same row's same limit is the most used (see [`Phase`]).
    pub fn phases(&self, limits: &'a [RowLimits<T>; M]) -> Phases<'a, T, M> {
        Phases {
            knots: self.knots,
            limits,
            next: 0,
        }
    }
}

impl<T: Real, const M: usize> Motion<T> for Schedule<'_, T, M> {
    type Output = State<T>;

    fn duration(&self) -> T {
        Schedule::duration(self)
    }

    fn sample(&self, t: T) -> State<T> {
        self.state(t)
    }
}

/// The use of every limit at one point: `x = s_dot^2`, `u = s_ddot`, as
/// the largest `(|q' s_dot| / v_max, row)` and `(|q' u + q'' x| / a_max, row)`.
pub(crate) fn usage<T: Real, const M: usize>(
    d: &Derivatives<T, M>,
    limits: &[RowLimits<T>; M],
    x: T,
    u: T,
) -> [(T, usize); 2] {
    let v = x.max(T::zero()).sqrt();
    let (mut vel, mut acc) = ((T::zero(), 0), (T::zero(), 0));
    for (j, ((l, &q1), &q2)) in limits.iter().zip(&d.first).zip(&d.second).enumerate() {
        let rv = (q1 * v).abs() / l.velocity;
        let ra = (q1 * u + q2 * x).abs() / l.acceleration;
        if rv > vel.0 {
            vel = (rv, j);
        }
        if ra > acc.0 {
            acc = (ra, j);
        }
    }
    [vel, acc]
}

/// The most used limit on interval `k0 -> k1` (at both ends), and its use.
fn interval_binding<T: Real, const M: usize>(
    k0: &Knot<T, M>,
    k1: &Knot<T, M>,
    limits: &[RowLimits<T>; M],
) -> (usize, LimitKind, T) {
    let mut best = (0, LimitKind::Acceleration, T::zero());
    for (d, x) in [(&k0.derivatives, k0.x), (&k1.derivatives, k1.x)] {
        let [(rv, jv), (ra, ja)] = usage(d, limits, x, k0.u);
        if rv > best.2 {
            best = (jv, LimitKind::Velocity, rv);
        }
        if ra > best.2 {
            best = (ja, LimitKind::Acceleration, ra);
        }
    }
    best
}

/// The phases of a [`Schedule`], in time order.
#[derive(Debug, Clone)]
pub struct Phases<'a, T, const M: usize> {
    knots: &'a [Knot<T, M>],
    limits: &'a [RowLimits<T>; M],
    next: usize,
}

impl<T: Real, const M: usize> Iterator for Phases<'_, T, M> {
    type Item = Phase<T>;

    fn next(&mut self) -> Option<Phase<T>> {
        let first = self.next;
        let k0 = self.knots.get(first)?;
        let k1 = self.knots.get(first + 1)?;
        let (row, limit, mut usage) = interval_binding(k0, k1, self.limits);
        let mut end = first + 1;
        // Extend while this limit stays the most used (within rounding of
        // the best, so that two nearly equal limits do not flicker).
        while let (Some(a), Some(b)) = (self.knots.get(end), self.knots.get(end + 1)) {
            let (r, l, u) = interval_binding(a, b, self.limits);
            if (r, l) != (row, limit) {
                let [(rv, jv), (ra, ja)] = usage_pair(a, b, self.limits);
                let ours = match limit {
                    LimitKind::Velocity if jv == row => rv,
                    LimitKind::Acceleration if ja == row => ra,
                    _ => T::zero(),
                };
                if ours < u * (T::one() - T::lit(1e-6)) {
                    break;
                }
            }
            usage = usage.max(u);
            end += 1;
        }
        self.next = end;
        let last = self.knots.get(end)?;
        Some(Phase {
            row,
            limit,
            first_knot: first,
            last_knot: end,
            start_t: k0.t,
            end_t: last.t,
            usage,
        })
    }
}

fn usage_pair<T: Real, const M: usize>(
    k0: &Knot<T, M>,
    k1: &Knot<T, M>,
    limits: &[RowLimits<T>; M],
) -> [(T, usize); 2] {
    let [a0, b0] = usage(&k0.derivatives, limits, k0.x, k0.u);
    let [a1, b1] = usage(&k1.derivatives, limits, k1.x, k0.u);
    [
        if a1.0 > a0.0 { a1 } else { a0 },
        if b1.0 > b0.0 { b1 } else { b0 },
    ]
}

/// How many times [`certify`] solves again with lower speeds where it
/// found an excess, before it stretches the whole schedule instead.
pub const CERTIFY_PASSES: usize = 4;

/// Excesses up to this (relative, as a time stretch) are removed by the
/// final uniform stretch rather than by solving again.
const LOCAL_THRESHOLD: f64 = 1e-6;

/// Checks a solved schedule between its knots and makes it safe there.
///
/// On every interval, at `checks` evenly spaced points (both ends
/// included, `checks >= 2` sub-intervals), the path's derivatives are
/// evaluated and every limit's use computed with the interval's `x(s)`
/// (linear in `s`) and `s_ddot`. Between two check points a use can exceed
/// the larger of its two values; the parabola through three neighbouring
/// check points estimates by how much (where it is concave and peaks
/// between them), and that excess is counted twice.
///
/// Where an interval's worst use `r` (as a time stretch) is above
/// `1 + 1e-6`, the speed at both its knots is capped at `x / r^2` and the
/// schedule solved again ([`solve`]), up to [`CERTIFY_PASSES`] times; what
/// remains above 1 is removed by one uniform time stretch of the whole
/// schedule (velocities scale by `1 / stretch`, accelerations by
/// `1 / stretch^2`).
///
/// # Errors
/// [`Error::TooFewChecks`], [`Error::Path`], [`Error::OutOfRange`].
pub fn certify<T: Real, P: Path<T, M>, const M: usize>(
    path: &P,
    limits: &[RowLimits<T>; M],
    knots: &mut [Knot<T, M>],
    checks: usize,
) -> Result<Certificate<T>, Error<P::Error>> {
    if checks < 2 {
        return Err(Error::TooFewChecks { count: checks });
    }
    let mut evaluated = 0;
    let mut passes = 0;
    let mut first = None;
    let worst = loop {
        let cap = passes < CERTIFY_PASSES;
        let worst = check_pass(path, limits, knots, checks, cap, &mut evaluated)?;
        first.get_or_insert(worst);
        if !cap || !(worst > T::one() + T::lit(LOCAL_THRESHOLD)) {
            break worst;
        }
        passes += 1;
        solve(limits, knots).map_err(Error::widen)?;
    };
    let stretch = worst.max(T::one());
    if !stretch.is_finite() {
        return Err(Error::OutOfRange { index: 0 });
    }
    if stretch > T::one() {
        let f = T::one() / (stretch * stretch);
        for k in knots.iter_mut() {
            k.x = k.x * f;
            k.u = k.u * f;
        }
        set_times(knots).map_err(Error::widen)?;
    }
    Ok(Certificate {
        worst: first.unwrap_or(worst),
        passes,
        stretch,
        checks: evaluated,
    })
}

/// One pass of [`certify`]'s check: the worst use over all intervals; with
/// `cap`, the knots of each interval above the threshold get their cap.
fn check_pass<T: Real, P: Path<T, M>, const M: usize>(
    path: &P,
    limits: &[RowLimits<T>; M],
    knots: &mut [Knot<T, M>],
    checks: usize,
    cap: bool,
    evaluated: &mut usize,
) -> Result<T, Error<P::Error>> {
    let mut worst = T::zero();
    let step = T::one() / T::from_index(checks);
    let threshold = T::one() + T::lit(LOCAL_THRESHOLD);
    for i in 0..knots.len().saturating_sub(1) {
        let (head, tail) = knots.split_at_mut(i + 1);
        let (Some(k0), Some(k1)) = (head.last_mut(), tail.first_mut()) else {
            continue;
        };
        let r = interval_worst(path, limits, k0, k1, checks, step, evaluated)?;
        if cap && r > threshold {
            let f = T::one() / (r * r);
            k0.x_cap = k0.x_cap.min(k0.x * f);
            k1.x_cap = k1.x_cap.min(k1.x * f);
        }
        worst = worst.max(r);
    }
    Ok(worst)
}

/// The worst use on one interval, at its check points and between them.
fn interval_worst<T: Real, P: Path<T, M>, const M: usize>(
    path: &P,
    limits: &[RowLimits<T>; M],
    k0: &Knot<T, M>,
    k1: &Knot<T, M>,
    checks: usize,
    step: T,
    evaluated: &mut usize,
) -> Result<T, Error<P::Error>> {
    let h = k1.s - k0.s;
    let mut worst = T::zero();
    // The uses at the last two points: [velocity; M], [acceleration; M].
    let mut before: Option<([T; M], [T; M])> = None;
    let mut prev: Option<([T; M], [T; M])> = None;
    for j in 0..=checks {
        let (s, d) = if j == 0 {
            (k0.s, k0.derivatives)
        } else if j == checks {
            (k1.s, k1.derivatives)
        } else {
            let s = k0.s + h * T::from_index(j) * step;
            let d = path.derivatives(s).map_err(|error| Error::Path {
                s: s.widen(),
                error,
            })?;
            *evaluated += 1;
            (s, d)
        };
        let x = if j == checks {
            k1.x
        } else {
            (k0.x + k0.u * T::lit(2.0) * (s - k0.s)).max(T::zero())
        };
        let now = uses(&d, limits, x, k0.u);
        for (rv, ra) in now.0.iter().zip(&now.1) {
            worst = worst.max(*rv).max(ra.sqrt());
        }
        // Between the previous points and this one, from the parabola
        // through the last three.
        if let (Some(b), Some(p)) = (&before, &prev) {
            for (bs, (ps, ns), accel) in
                [(&b.0, (&p.0, &now.0), false), (&b.1, (&p.1, &now.1), true)]
            {
                for ((&gb, &gp), &gn) in bs.iter().zip(ps).zip(ns) {
                    let top = between(gb, gp, gn);
                    worst = worst.max(if accel { top.sqrt() } else { top });
                }
            }
        }
        before = prev;
        prev = Some(now);
    }
    Ok(worst)
}

/// An upper estimate of a smooth function's largest value between three
/// evenly spaced samples `gb, gp, gn`: the parabola through them peaks
/// inside when it is concave with its vertex between the outer two; that
/// excess over the largest sample is counted twice.
fn between<T: Real>(gb: T, gp: T, gn: T) -> T {
    let top = gb.max(gp).max(gn);
    let curvature = gn - gp * T::lit(2.0) + gb;
    let slope = (gn - gb) * T::lit(0.5);
    if !(curvature < T::zero()) {
        return top;
    }
    // g(tau) = gp + slope tau + curvature tau^2 / 2, tau in [-1, 1].
    let vertex = -slope / curvature;
    if !(vertex.abs() < T::one()) {
        return top;
    }
    let peak = gp - slope * slope / (curvature * T::lit(2.0));
    top + (peak - top).max(T::zero()) * T::lit(2.0)
}

/// Every row's velocity and acceleration use at one point.
fn uses<T: Real, const M: usize>(
    d: &Derivatives<T, M>,
    limits: &[RowLimits<T>; M],
    x: T,
    u: T,
) -> ([T; M], [T; M]) {
    let v = x.max(T::zero()).sqrt();
    let mut rv = [T::zero(); M];
    let mut ra = [T::zero(); M];
    let rows = limits
        .iter()
        .zip(d.first.iter().zip(&d.second))
        .zip(rv.iter_mut().zip(ra.iter_mut()));
    for ((l, (&q1, &q2)), (v_use, a_use)) in rows {
        *v_use = (q1 * v).abs() / l.velocity;
        *a_use = (q1 * u + q2 * x).abs() / l.acceleration;
    }
    (rv, ra)
}

/// What [`plan`] returns: the schedule and what its check found and did.
pub type Planned<'a, T, const M: usize> = (Schedule<'a, T, M>, Certificate<T>);

/// The whole plan: `knots.len()` knots evenly on `[0, 1]` ([`fill_uniform`]),
/// the optimal schedule on them ([`solve`]), checked and made safe at
/// `checks` points per interval ([`certify`]).
///
/// # Errors
/// Those of the three steps.
pub fn plan<'a, T: Real, P: Path<T, M>, const M: usize>(
    path: &P,
    limits: &[RowLimits<T>; M],
    knots: &'a mut [Knot<T, M>],
    checks: usize,
) -> Result<Planned<'a, T, M>, Error<P::Error>> {
    fill_uniform(path, knots)?;
    solve(limits, knots).map_err(Error::widen)?;
    let certificate = certify(path, limits, knots, checks)?;
    Ok((Schedule::view(knots), certificate))
}
