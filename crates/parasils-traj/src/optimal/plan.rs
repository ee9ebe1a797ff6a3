//! The check of a solved schedule between its knots ([`certify`]) and the
//! whole plan ([`plan`]: the grid, the solve, the check), over the
//! [`Schedule`] and the solver: the one module that uses both.

use crate::real::Real;

use super::schedule::Schedule;
use super::solve::{fill_uniform, set_times, solve};
use super::types::{Certificate, Derivatives, Error, Knot, Path, RowLimits};

/// How many times [`certify`] solves again with lower speeds where it
/// found an excess, before it stretches the whole schedule instead.
pub const CERTIFY_PASSES: usize = 4;

/// Excesses up to this (relative, as a time stretch) are removed by the
/// final uniform stretch rather than by solving again.
const LOCAL_THRESHOLD: f64 = 1e-6;

/// The headroom the final stretch leaves below every limit, relative (and
/// at least 64 ulps): a law that uses a limit to the full is computed
/// again by whoever samples it (`s_ddot` times `q'`, the kinematics' own
/// rates), and that rounding must not take it over the limit.
const ROUNDING_HEADROOM: f64 = 1e-12;

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
/// `1 / stretch^2`), with a headroom of `1e-12` (or 64 ulps, the larger)
/// against the rounding of whoever samples the law: a limit used to the
/// full stays within it when recomputed.
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
    let headroom = T::lit(ROUNDING_HEADROOM).max(T::EPSILON * T::lit(64.0));
    let stretch = (worst * (T::one() + headroom)).max(T::one());
    if !stretch.finite() {
        return Err(Error::OutOfRange { index: 0 });
    }
    if stretch > T::one() {
        let f = T::one() / (stretch * stretch);
        for k in knots.iter_mut() {
            k.x *= f;
            k.u *= f;
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
                s: s.to_f64(),
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
