//! The discretised problem and its two passes: the controllable sets
//! backwards from rest at the end, then the greedy forward pass from rest
//! at the start (reachability analysis).

use crate::error::LimitKind;
use crate::real::Real;

use super::schedule::Schedule;
use super::types::{Derivatives, Error, Knot, Path, RowLimits};

/// A line `u = a + b x` in the `(x, u)` plane of one interval.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Line<T> {
    pub(crate) a: T,
    pub(crate) b: T,
}

/// One interval `[s_i, s_{i+1}]` with a constant `u`: every row's
/// acceleration constraint at both ends, as bands `|u - d x| <= c` in the
/// start's `x` (at the end, `x_{i+1} = x + 2 h u`), and the bound on `x`
/// alone from rows whose band does not involve `u`. Set up in place for
/// each interval in turn; at each end, the first `len` entries are the
/// bands (a row without one, or unlimited, takes none).
pub(crate) struct Interval<T, const M: usize> {
    c: [[T; M]; 2],
    d: [[T; M]; 2],
    len: [usize; 2],
    /// The largest `x` at the start: the velocity limit curve and the
    /// `x`-only rows.
    pub(crate) x_hi: T,
    /// `2 (s_{i+1} - s_i)`.
    pub(crate) two_h: T,
}

impl<T: Real, const M: usize> Interval<T, M> {
    pub(crate) fn empty() -> Self {
        Self {
            c: [[T::INFINITY; M]; 2],
            d: [[T::zero(); M]; 2],
            len: [0; 2],
            x_hi: T::zero(),
            two_h: T::one(),
        }
    }

    /// The bands of the interval `k0 -> k1`.
    pub(crate) fn set(
        &mut self,
        k0: &Knot<T, M>,
        k1: &Knot<T, M>,
        limits: &[RowLimits<T>; M],
        index: usize,
    ) -> Result<(), Error> {
        let two_h = (k1.s - k0.s) * T::lit(2.0);
        let mut x_hi = k0.x_max;
        let mut finite = true;
        let (d0, d1) = (&k0.derivatives, &k1.derivatives);
        let mut len = [0; 2];
        let rows = limits
            .iter()
            .zip(d0.first.iter().zip(&d0.second))
            .zip(d1.first.iter().zip(&d1.second));
        for ((lim, (&a0, &b0)), (&a1, &b1)) in rows {
            let gamma = lim.acceleration;
            if gamma == T::INFINITY {
                // An unlimited row bounds nothing.
                continue;
            }
            for (end, (alpha, beta)) in [(a0, b0), (a1 + two_h * b1, b1)].into_iter().enumerate() {
                if alpha == T::zero() {
                    // No band in u: a bound on x alone.
                    x_hi = x_hi.min(gamma / beta.abs());
                } else {
                    let inv = T::one() / alpha;
                    let (c, d) = (gamma * inv.abs(), -beta * inv);
                    finite &= c.finite() & d.finite();
                    let k = len[end];
                    if let (Some(cj), Some(dj)) = (self.c[end].get_mut(k), self.d[end].get_mut(k)) {
                        (*cj, *dj) = (c, d);
                        len[end] = k + 1;
                    }
                }
            }
        }
        self.len = len;
        if !finite {
            return Err(Error::OutOfRange { index });
        }
        self.x_hi = x_hi;
        self.two_h = two_h;
        Ok(())
    }

    /// The upper envelope of `u` at `x` (the next knot's `x` kept within
    /// `[0, k_next]`), as the forward pass needs it.
    fn upper(&self, x: T, k_next: T) -> T {
        let mut up = (k_next - x) / self.two_h;
        for ((cs, ds), &n) in self.c.iter().zip(&self.d).zip(&self.len) {
            for (&c, &d) in cs.iter().zip(ds).take(n) {
                up = up.min(d * x + c);
            }
        }
        up
    }

    /// The lines that make the upper and the lower envelope of `u` at `x`
    /// (the next knot's `x` kept within `[0, k_next]`), with the envelopes'
    /// values there.
    fn active(&self, x: T, k_next: T) -> (Line<T>, Line<T>, T, T) {
        let inv = T::one() / self.two_h;
        let mut up = Line {
            a: k_next * inv,
            b: -inv,
        };
        let mut lo = Line {
            a: T::zero(),
            b: -inv,
        };
        let (mut up_v, mut lo_v) = ((k_next - x) * inv, -x * inv);
        for ((cs, ds), &n) in self.c.iter().zip(&self.d).zip(&self.len) {
            for (&c, &d) in cs.iter().zip(ds).take(n) {
                let mid = d * x;
                let v = mid + c;
                if v < up_v {
                    (up, up_v) = (Line { a: c, b: d }, v);
                }
                let v = mid - c;
                if v > lo_v {
                    (lo, lo_v) = (Line { a: -c, b: d }, v);
                }
            }
        }
        (up, lo, up_v, lo_v)
    }

    /// The largest `x` in `[0, x_start]` at which some `u` satisfies every
    /// band and keeps the next `x` within `[0, k_next]`. The gap between the
    /// upper and the lower envelope is concave and piecewise linear, and not
    /// negative at 0; from `x_start` down, each step goes to the root of the
    /// active pieces' line, which is never below the answer (Newton's method
    /// on a concave function, finite).
    pub(crate) fn max_feasible(&self, x_start: T, k_next: T) -> T {
        let mut x = x_start;
        for _ in 0..4 * M + 16 {
            let (up, lo, up_v, lo_v) = self.active(x, k_next);
            if up_v >= lo_v {
                return x;
            }
            let slope = up.b - lo.b;
            let gap0 = up.a - lo.a;
            if !(slope < T::zero()) || !(gap0 >= T::zero()) {
                return T::zero();
            }
            let y = (gap0 / -slope).max(T::zero());
            if !(y < x) {
                return x;
            }
            x = y;
        }
        x
    }
}

/// Puts `knots.len()` knots evenly on `[0, 1]` (`s_k = k / (n - 1)`, the
/// last exactly 1) and evaluates the path's derivatives there.
///
/// # Errors
/// [`Error::TooFewKnots`] for fewer than 2, [`Error::Path`] where the path
/// cannot be evaluated.
pub fn fill_uniform<T: Real, P: Path<T, M>, const M: usize>(
    path: &P,
    knots: &mut [Knot<T, M>],
) -> Result<(), Error<P::Error>> {
    let n = knots.len();
    if n < 2 {
        return Err(Error::TooFewKnots { count: n });
    }
    let last = T::from_index(n - 1);
    for (k, knot) in knots.iter_mut().enumerate() {
        let s = if k + 1 == n {
            T::one()
        } else {
            T::from_index(k) / last
        };
        let derivatives: Derivatives<T, M> = path.derivatives(s).map_err(|error| Error::Path {
            s: s.to_f64(),
            error,
        })?;
        *knot = Knot::new(s, derivatives);
    }
    Ok(())
}

fn validate<T: Real, const M: usize>(
    limits: &[RowLimits<T>; M],
    knots: &[Knot<T, M>],
) -> Result<(), Error> {
    if knots.len() < 2 {
        return Err(Error::TooFewKnots { count: knots.len() });
    }
    for (row, l) in limits.iter().enumerate() {
        for (kind, value) in [
            (LimitKind::Velocity, l.velocity),
            (LimitKind::Acceleration, l.acceleration),
        ] {
            if !(value > T::zero()) {
                return Err(Error::InvalidLimit {
                    row,
                    kind,
                    value: value.to_f64(),
                });
            }
        }
    }
    let mut previous = -T::INFINITY;
    for (index, k) in knots.iter().enumerate() {
        if !(k.s.finite() && k.s > previous) {
            return Err(Error::Grid {
                index,
                s: k.s.to_f64(),
            });
        }
        previous = k.s;
        let d = &k.derivatives;
        for (row, &value) in d.first.iter().chain(&d.second).enumerate() {
            if !value.finite() {
                return Err(Error::NonFiniteDerivative {
                    index,
                    row: row % M.max(1),
                    value: value.to_f64(),
                });
            }
        }
    }
    Ok(())
}

/// The time-optimal rest-to-rest schedule over the knots the caller filled
/// (`s` increasing, the path's derivatives at each), within `limits`: the
/// acceleration constraints hold at both ends of every interval (with the
/// interval's constant `s_ddot`), the velocity constraints at every knot.
/// Writes `x`, `s_ddot` and `t` into the knots; no allocation.
///
/// The check between knots and the correction is [`certify`](super::certify);
/// [`plan`](super::plan) does both.
///
/// # Errors
/// Invalid input ([`Error::TooFewKnots`], [`Error::Grid`],
/// [`Error::InvalidLimit`], [`Error::NonFiniteDerivative`]), a path no limit
/// bounds ([`Error::Unconstrained`]), or numbers that do not fit the float
/// type ([`Error::OutOfRange`]).
pub fn solve<'a, T: Real, const M: usize>(
    limits: &[RowLimits<T>; M],
    knots: &'a mut [Knot<T, M>],
) -> Result<Schedule<'a, T, M>, Error> {
    validate(limits, knots)?;
    // The velocity limit curve.
    // min_j (v_j / |q_j'|)^2 as 1 / (max_j |q_j'| / v_j)^2: one division
    // per knot (an unlimited row's 1 / v_j is 0).
    let huge = T::MAX.sqrt();
    let mut inv_v = [T::zero(); M];
    for (w, l) in inv_v.iter_mut().zip(limits) {
        *w = T::one() / l.velocity;
    }
    for k in knots.iter_mut() {
        let mut w = T::zero();
        for (&q1, &iv) in k.derivatives.first.iter().zip(&inv_v) {
            w = w.max(q1.abs() * iv);
        }
        let x = huge.min(k.x_cap).min(T::one() / (w * w));
        (k.x_max, k.x, k.u, k.t) = (x, T::zero(), T::zero(), T::zero());
    }
    // Backward: the controllable sets [0, x_max], from rest at the end.
    let n = knots.len();
    let mut iv = Interval::empty();
    if let Some(last) = knots.last_mut() {
        last.x_max = T::zero();
    }
    for i in (0..n - 1).rev() {
        let (head, tail) = knots.split_at_mut(i + 1);
        let (Some(k0), Some(k1)) = (head.last_mut(), tail.first()) else {
            continue;
        };
        iv.set(k0, k1, limits, i)?;
        let x = iv.max_feasible(iv.x_hi, k1.x_max);
        if !(x < huge) {
            return Err(Error::Unconstrained { index: i });
        }
        k0.x_max = x;
    }
    // Forward: from rest, the largest s_ddot that stays controllable.
    for i in 0..n - 1 {
        let (head, tail) = knots.split_at_mut(i + 1);
        let (Some(k0), Some(k1)) = (head.last_mut(), tail.first_mut()) else {
            continue;
        };
        let x0 = k0.x.min(k0.x_max);
        let two_h = (k1.s - k0.s) * T::lit(2.0);
        let up = match forward_u(k0, k1, limits, two_h, x0, k1.x_max) {
            Some(u) => u,
            None => {
                iv.set(k0, k1, limits, i)?;
                iv.upper(x0, k1.x_max)
            }
        };
        let x1 = (x0 + two_h * up).max(T::zero()).min(k1.x_max);
        k0.x = x0;
        k0.u = (x1 - x0) / two_h;
        k1.x = x1;
    }
    if let Some(last) = knots.last_mut() {
        (last.x, last.u) = (T::zero(), T::zero());
    }
    set_times(knots)?;
    Ok(Schedule::view(knots))
}

/// The forward pass's largest `u` on the interval `k0 -> k1` (`two_h =
/// 2 (s_1 - s_0)`) from `x0`: the least of `(k_next - x0) / two_h` and of
/// every band's upper line at `x0`, `(gamma - sign(alpha) beta x0) /
/// |alpha|` (the bands of [`Interval::set`], which the backward pass has
/// already set up and checked on this interval), compared by
/// cross-multiplying so that only the least is divided. `None` where a
/// product does not fit the float type: the caller then sets the bands up.
fn forward_u<T: Real, const M: usize>(
    k0: &Knot<T, M>,
    k1: &Knot<T, M>,
    limits: &[RowLimits<T>; M],
    two_h: T,
    x0: T,
    k_next: T,
) -> Option<T> {
    let (mut num, mut den) = (k_next - x0, two_h);
    let mut finite = true;
    let (d0, d1) = (&k0.derivatives, &k1.derivatives);
    let rows = limits
        .iter()
        .zip(d0.first.iter().zip(&d0.second))
        .zip(d1.first.iter().zip(&d1.second));
    for ((lim, (&a0, &b0)), (&a1, &b1)) in rows {
        let gamma = lim.acceleration;
        if gamma == T::INFINITY {
            continue;
        }
        for (alpha, beta) in [(a0, b0), (a1 + two_h * b1, b1)] {
            if alpha == T::zero() {
                continue;
            }
            let m = alpha.abs();
            let n = if alpha > T::zero() {
                gamma - beta * x0
            } else {
                gamma + beta * x0
            };
            let (left, right) = (n * den, num * m);
            finite &= left.finite() & right.finite();
            if left < right {
                (num, den) = (n, m);
            }
        }
    }
    let up = num / den;
    (finite && up.finite()).then_some(up)
}

/// The time at each knot: `dt = 2 h / (s_dot_i + s_dot_{i+1})` on each interval.
pub(crate) fn set_times<T: Real, const M: usize>(knots: &mut [Knot<T, M>]) -> Result<(), Error> {
    let mut t = T::zero();
    let mut previous: Option<(T, T)> = None;
    for (index, k) in knots.iter_mut().enumerate() {
        if let Some((s, v)) = previous {
            let dt = (k.s - s) * T::lit(2.0) / (v + k.x.sqrt());
            t += dt;
            if !(t.finite() && dt > T::zero()) {
                return Err(Error::OutOfRange { index });
            }
        }
        k.t = t;
        previous = Some((k.s, k.x.sqrt()));
    }
    Ok(())
}
