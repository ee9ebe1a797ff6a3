//! The solved schedule `s(t)`: sampling, phases, and the check between
//! knots with its correction.

use crate::error::LimitKind;
use crate::profile::{Motion, State};
use crate::real::Real;

use super::types::{Derivatives, Knot, Phase, RowLimits};

/// A solved schedule: `s(t)` piecewise with constant `s_ddot` between
/// knots, at rest at both ends. A view of the knots [`solve`](super::solve) wrote.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Schedule<'a, T, const M: usize> {
    knots: &'a [Knot<T, M>],
}

impl<'a, T: Real, const M: usize> Schedule<'a, T, M> {
    /// The schedule last solved into `knots` (by [`solve`](super::solve) or [`plan`](super::plan)).
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
