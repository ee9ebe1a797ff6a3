//! The smallest gap between two capsules over a whole interval of time, not
//! only at samples: a lower bound from how fast the gap can change, refined
//! by bisection where it is loose.
//!
//! # The argument
//!
//! **The gap is Lipschitz in the axes' ends.** A point of a segment is a
//! convex combination of its ends, `a(s) = (1 - s) a0 + s a1`; if the ends
//! move with velocities `v0`, `v1`, the point moves with `(1 - s) v0 + s v1`,
//! no faster than `max(|v0|, |v1|)`. The distance between two segments is
//! the minimum over their points of `|a(s) - b(t)|`, and a minimum of
//! functions that each change no faster than `V_a + V_b` changes no faster
//! either. So the surface gap `g` (the distance less both radii) satisfies
//! `|dg/dt| <= V_a + V_b`, with `V` the larger speed of a body's two ends.
//!
//! **The ends' speed from the rates.** Every axis here is
//! `x(lambda) = O + lambda u` for `lambda` between `-d` and `L - d`: the
//! port `O` (the module's RCM `P + R rcm`, or `P` for the endoscope), the
//! unit direction `u` of the tool (`R R_tool e_z`) or of the endoscope
//! (`R e_z`), the depth `d` (`qs3`, or the endoscope's insertion) and the
//! length `L`. Differentiating an end,
//! `v = O' - d' u + lambda u'`, with `|O'| <= |P'| + |omega| |rcm|` and
//! `|u'| <= |omega| + |qs1'| + |qs2'|` (the tool's rotation relative to the
//! platform is `R_Y(alpha) R_X(qs1) R_Y(qs2) R_X(beta)`, whose angular
//! velocity is `qs1'` about one unit axis plus `qs2'` about another), so
//!
//! `|v| <= |P'| + |omega| |rcm| + |d'| + max(d, |L - d|) (|omega| + |qs1'| + |qs2'|)`
//!
//! ([`AxisState::end_speed`]; the endoscope has `rcm = 0` and no tool
//! rates).
//!
//! **Over an interval.** Between two instants `dt` apart, a rate `r` whose
//! own rate is at most `A` is at most `(|r0| + |r1| + A dt) / 2` (it cannot
//! climb from either end faster than `A`; the two cones meet there), and
//! the depth is at most `(d0 + d1 + D dt) / 2` with `D` that bound of
//! `|d'|` ([`AxisState::end_speed_over`]). The bounds `A` are the caller's
//! ([`AxisAccelerations`]): see `docs/model.md`, *Clearance*, for where the
//! simulation takes them and what they assume.
//!
//! **The smallest gap.** With `|dg/dt| <= G` on `[t0, t1]`,
//! `g(t) >= max(g0 - G (t - t0), g1 - G (t1 - t))`, whose lowest point is
//! `(g0 + g1 - G dt) / 2` ([`gap_lower_bound`]). Where that is more than a
//! tolerance below the smallest gap seen so far, [`certify`] evaluates the
//! true gap at the midpoint and bounds both halves, down to a depth cap.
//! When every interval's bound is within the tolerance of the smallest gap
//! evaluated, the true minimum lies between the two: the certificate is
//! within the tolerance of the truth and never above it.
//!
//! ```
//! use parasils_kin::{AxisAccelerations, AxisState, Probe, certify, gap_lower_bound};
//!
//! // Two gaps of 1 mm, 0.1 s apart, changing at most 4 mm/s: the gap can
//! // dip to 0.8 mm half way.
//! assert!((gap_lower_bound(1.0_f64, 1.0, 4.0, 0.1) - 0.8).abs() < 1e-15);
//!
//! // A shaft sliding in at 10 mm/s towards a still one: the gap is
//! // `5 - 10 |t - 0.5|`, sampled only at 0 and 1 s (0 mm at each end) and
//! // 5 mm at its peak; the lowest is 0 at the ends.
//! let still = AxisState { depth: 0.0, length: 0.0, ..AxisState::default() };
//! let moving = AxisState { depth_rate: 10.0, ..still };
//! let probe = |t: f64| -> Result<Probe<f64>, ()> {
//!     Ok(Probe { gap: 5.0 - 10.0 * (t - 0.5f64).abs(), axes: [moving, still] })
//! };
//! let acc = [AxisAccelerations::default(); 2];
//! let c = certify((0.0, probe(0.0)?), (1.0, probe(1.0)?), f64::INFINITY, &acc, 1e-3, 20, probe)?;
//! assert_eq!(c.sampled, 0.0);
//! assert!(c.certified <= 0.0 && c.certified > -1e-3 && c.converged);
//! # Ok::<(), ()>(())
//! ```

use crate::real::Real;

/// What bounds how fast the ends of one body's axis move, at one instant:
/// the axis is `O + lambda u`, `lambda` from `-depth` to `length - depth`
/// (see the [module](self)). Every field is a magnitude (at least 0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisState<T> {
    /// `|P'|`, the platform's speed, mm/s.
    pub platform_speed: T,
    /// `|omega|`, the platform's angular speed, rad/s.
    pub omega: T,
    /// `|rcm|`, the port's distance from `P` in the platform frame, mm (0
    /// for the endoscope).
    pub port_offset: T,
    /// `d`: `qs3` of a shaft, or the endoscope's insertion depth, mm.
    pub depth: T,
    /// `|d'|`, mm/s.
    pub depth_rate: T,
    /// `|qs1'| + |qs2'|`, the tool's angular speed relative to the platform
    /// at most, rad/s (0 for the endoscope).
    pub tilt_rate: T,
    /// `L`, the axis' length, mm.
    pub length: T,
}

/// Bounds on how fast the rates of an [`AxisState`] change over the
/// interval certified (each at least 0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisAccelerations<T> {
    /// Of `|P'|`: `|P''|` at most, mm/s^2.
    pub platform: T,
    /// Of `|omega|`: `|alpha|` at most, rad/s^2.
    pub omega: T,
    /// Of `|d'|`: `|d''|` at most, mm/s^2.
    pub depth: T,
    /// Of `|qs1'| + |qs2'|`: `|qs1''| + |qs2''|` at most, rad/s^2.
    pub tilt: T,
}

/// `max(|r0|, |r1|, (|r0| + |r1| + a dt) / 2)`: the largest a rate can be
/// between two instants `dt` apart where it is `r0` and `r1`, when it
/// changes no faster than `a`.
pub fn rate_over<T: Real>(r0: T, r1: T, a: T, dt: T) -> T {
    let (r0, r1) = (r0.abs(), r1.abs());
    let cones = (r0 + r1 + a.abs() * dt.abs()) * T::lit(0.5);
    r0.max(r1).max(cones)
}

impl<T: Real> AxisState<T> {
    /// The larger speed of the axis' two ends, mm/s:
    /// `|P'| + |omega| |rcm| + |d'| + max(d, |L - d|) (|omega| + tilt rate)`.
    pub fn end_speed(&self) -> T {
        let reach = self.depth.abs().max((self.length - self.depth).abs());
        self.platform_speed.abs()
            + self.omega.abs() * self.port_offset.abs()
            + self.depth_rate.abs()
            + reach * (self.omega.abs() + self.tilt_rate.abs())
    }

    /// A bound on [`AxisState::end_speed`] over the whole interval between
    /// `a` and `b`, `dt` s apart, each rate bounded by [`rate_over`] with
    /// the accelerations `acc`, and the depth by its rate's bound.
    pub fn end_speed_over(a: &Self, b: &Self, acc: &AxisAccelerations<T>, dt: T) -> T {
        let half = T::lit(0.5);
        let depth_rate = rate_over(a.depth_rate, b.depth_rate, acc.depth, dt);
        let swing = depth_rate * dt.abs();
        let deepest = (a.depth + b.depth + swing) * half;
        let shallowest = (a.depth + b.depth - swing) * half;
        let reach = deepest
            .abs()
            .max(shallowest.abs())
            .max((a.length - shallowest).abs())
            .max((a.length - deepest).abs());
        let omega = rate_over(a.omega, b.omega, acc.omega, dt);
        rate_over(a.platform_speed, b.platform_speed, acc.platform, dt)
            + omega * a.port_offset.abs().max(b.port_offset.abs())
            + depth_rate
            + reach * (omega + rate_over(a.tilt_rate, b.tilt_rate, acc.tilt, dt))
    }
}

/// The lowest the gap can be between two instants `dt` apart where it is
/// `g0` and `g1`, if it changes no faster than `rate` (mm/s):
/// `min(g0, g1, (g0 + g1 - rate dt) / 2)`, mm.
pub fn gap_lower_bound<T: Real>(g0: T, g1: T, rate: T, dt: T) -> T {
    let cones = (g0 + g1 - rate.abs() * dt.abs()) * T::lit(0.5);
    cones.min(g0).min(g1)
}

/// The gap of a pair of bodies at one instant and the two axes' states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe<T> {
    /// The surface gap, mm.
    pub gap: T,
    /// The two bodies' axes.
    pub axes: [AxisState<T>; 2],
}

/// What [`certify`] found over an interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Certificate<T> {
    /// The smallest gap known (`known`, the ends and every midpoint), mm:
    /// the true minimum over the interval and wherever `known` was found is
    /// at most this.
    pub sampled: T,
    /// A lower bound of the gap over the whole interval, mm: the true
    /// minimum is at least this.
    pub certified: T,
    /// How many midpoints were evaluated.
    pub evaluations: u32,
    /// Whether every piece was certified within the tolerance of
    /// `sampled` (`false`: the depth cap stopped a refinement).
    pub converged: bool,
}

/// A lower bound of a gap over `[t0, t1]` (s), from its probes `p0`, `p1`
/// at the ends, refined by bisection: a piece whose bound
/// ([`gap_lower_bound`] with the rate from [`AxisState::end_speed_over`] of
/// both axes) is more than `tolerance` (mm) below the smallest gap known
/// (`known`, the smallest found elsewhere, `INFINITY` if none, and every
/// gap evaluated here) is split at its midpoint, evaluated by `probe`, down
/// to `max_depth` halvings. The first error of `probe` is returned as is.
#[allow(clippy::too_many_arguments)]
pub fn certify<T: Real, E>(
    (t0, p0): (T, Probe<T>),
    (t1, p1): (T, Probe<T>),
    known: T,
    acc: &[AxisAccelerations<T>; 2],
    tolerance: T,
    max_depth: u32,
    mut probe: impl FnMut(T) -> Result<Probe<T>, E>,
) -> Result<Certificate<T>, E> {
    let mut c = Certificate {
        sampled: p0.gap.min(p1.gap).min(known),
        certified: p0.gap.min(p1.gap),
        evaluations: 0,
        converged: true,
    };
    let piece = Piece {
        t0,
        p0,
        t1,
        p1,
        depth: 0,
    };
    c.certified = refine(&piece, acc, tolerance, max_depth, &mut probe, &mut c)?;
    Ok(c)
}

/// One piece of the interval under refinement.
struct Piece<T> {
    t0: T,
    p0: Probe<T>,
    t1: T,
    p1: Probe<T>,
    depth: u32,
}

fn refine<T: Real, E>(
    piece: &Piece<T>,
    acc: &[AxisAccelerations<T>; 2],
    tolerance: T,
    max_depth: u32,
    probe: &mut impl FnMut(T) -> Result<Probe<T>, E>,
    c: &mut Certificate<T>,
) -> Result<T, E> {
    let Piece { t0, p0, t1, p1, .. } = *piece;
    let dt = t1 - t0;
    let rate = AxisState::end_speed_over(&p0.axes[0], &p1.axes[0], &acc[0], dt)
        + AxisState::end_speed_over(&p0.axes[1], &p1.axes[1], &acc[1], dt);
    let bound = gap_lower_bound(p0.gap, p1.gap, rate, dt);
    // `!(>=)`: a NaN bound is never taken as certified.
    if !(bound < c.sampled - tolerance) {
        return Ok(bound);
    }
    if piece.depth >= max_depth {
        c.converged = false;
        return Ok(bound);
    }
    let tm = t0 + dt * T::lit(0.5);
    let pm = probe(tm)?;
    c.evaluations = c.evaluations.saturating_add(1);
    c.sampled = c.sampled.min(pm.gap);
    let depth = piece.depth + 1;
    let left = refine(
        &Piece {
            t0,
            p0,
            t1: tm,
            p1: pm,
            depth,
        },
        acc,
        tolerance,
        max_depth,
        probe,
        c,
    )?;
    let right = refine(
        &Piece {
            t0: tm,
            p0: pm,
            t1,
            p1,
            depth,
        },
        acc,
        tolerance,
        max_depth,
        probe,
        c,
    )?;
    Ok(left.min(right))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cones_meet_where_both_ends_allow() {
        // From 2 and 1 mm, at 10 mm/s over 0.3 s: (2 + 1 - 3) / 2 = 0.
        assert!(gap_lower_bound(2.0_f64, 1.0, 10.0, 0.3).abs() < 1e-15);
        // A slow rate: never above the smaller end.
        assert_eq!(gap_lower_bound(2.0, 1.0, 0.0, 0.3), 1.0);
        // A rate from 1 to 3 with |r'| <= 10 over 0.2 s peaks at 3 (the
        // cones meet at (1 + 3 + 2) / 2 = 3).
        assert_eq!(rate_over(1.0, -3.0, 10.0, 0.2), 3.0);
        assert!((rate_over(1.0_f64, 1.0, 10.0, 0.2) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn an_end_speed_is_what_the_formula_says() {
        // |P'| 1, |omega| 0.5 at 10 mm from P, qs3 = 100 of 400 (reach
        // 300), d' 2, tilt 0.1: 1 + 5 + 2 + 300 (0.5 + 0.1) = 188.
        let s = AxisState {
            platform_speed: 1.0_f64,
            omega: 0.5,
            port_offset: 10.0,
            depth: 100.0,
            depth_rate: -2.0,
            tilt_rate: 0.1,
            length: 400.0,
        };
        assert!((s.end_speed() - 188.0).abs() < 1e-12);
        // Over a zero interval, the larger of the two instants.
        let t = AxisState { omega: 0.7, ..s };
        let acc = AxisAccelerations::default();
        assert_eq!(AxisState::end_speed_over(&s, &t, &acc, 0.0), t.end_speed());
    }

    /// The speed bound against the true speed of an axis turning about its
    /// port, by finite differences of its far end.
    #[test]
    fn the_speed_bounds_a_turning_axis() {
        let (omega, length, depth) = (0.8_f64, 400.0_f64, 150.0_f64);
        let far = |t: f64| {
            let a = omega * t;
            let l = length - depth;
            [10.0 + l * a.sin(), 0.0, l * a.cos()]
        };
        let h = 1e-6;
        let (a, b) = (far(0.3), far(0.3 + h));
        let speed = ((b[0] - a[0]).powi(2) + (b[2] - a[2]).powi(2)).sqrt() / h;
        let s = AxisState {
            depth,
            length,
            tilt_rate: omega,
            ..AxisState::default()
        };
        assert!((speed - (length - depth) * omega).abs() < 1e-3, "{speed}");
        assert!(s.end_speed() >= speed - 1e-3);
    }

    #[test]
    fn a_dip_between_samples_is_found() {
        // A gap 1 mm at both ends and -0.5 in the middle (a V at 6 mm/s
        // over 0.5 s), the axes' state allowing 6 mm/s.
        let axis = AxisState {
            depth_rate: 3.0,
            ..AxisState::default()
        };
        let probe = |t: f64| -> Result<Probe<f64>, ()> {
            Ok(Probe {
                gap: -0.5 + 6.0 * (t - 0.25).abs(),
                axes: [axis; 2],
            })
        };
        let acc = [AxisAccelerations::default(); 2];
        let c = certify(
            (0.0, probe(0.0).expect("the probe never fails")),
            (0.5, probe(0.5).expect("the probe never fails")),
            f64::INFINITY,
            &acc,
            1e-3,
            30,
            probe,
        )
        .expect("the probe never fails");
        assert!(c.converged);
        assert!(c.certified <= -0.5 && c.certified > -0.5 - 1e-3, "{c:?}");
        assert_eq!(c.sampled, -0.5);
        // Capped at no refinement, the bound still holds but is loose.
        let c = certify(
            (0.0, probe(0.0).expect("the probe never fails")),
            (0.5, probe(0.5).expect("the probe never fails")),
            f64::INFINITY,
            &acc,
            1e-3,
            0,
            probe,
        )
        .expect("the probe never fails");
        assert!(!c.converged && c.certified <= -0.5, "{c:?}");
        assert_eq!(c.sampled, 1.0);
    }

    #[test]
    fn a_smaller_gap_known_elsewhere_spares_the_refinement() {
        // The same V, but a gap of -1 mm known from another interval: the
        // bound -0.5 is not below it, so nothing is evaluated.
        let axis = AxisState {
            depth_rate: 3.0,
            ..AxisState::default()
        };
        let probe = |t: f64| -> Result<Probe<f64>, ()> {
            Ok(Probe {
                gap: -0.5 + 6.0 * (t - 0.25).abs(),
                axes: [axis; 2],
            })
        };
        let acc = [AxisAccelerations::default(); 2];
        let c = certify(
            (0.0, probe(0.0).expect("the probe never fails")),
            (0.5, probe(0.5).expect("the probe never fails")),
            -1.0,
            &acc,
            1e-3,
            30,
            probe,
        )
        .expect("the probe never fails");
        assert_eq!((c.evaluations, c.sampled), (0, -1.0));
        assert!(c.certified <= -0.5 && c.converged, "{c:?}");
    }

    #[test]
    fn a_nan_gap_is_never_certified() {
        let probe = |_: f64| -> Result<Probe<f64>, ()> {
            Ok(Probe {
                gap: f64::NAN,
                axes: [AxisState::default(); 2],
            })
        };
        let acc = [AxisAccelerations::default(); 2];
        let c = certify(
            (0.0, probe(0.0).expect("the probe never fails")),
            (1.0, probe(1.0).expect("the probe never fails")),
            f64::INFINITY,
            &acc,
            1e-3,
            3,
            probe,
        )
        .expect("the probe never fails");
        assert!(!(c.certified >= 0.0));
    }
}
