//! The jerk-limited ("double-S", seven-phase) rest-to-rest profile of one axis.
//!
//! The acceleration is a trapezoid (or a triangle) in time, the jerk is
//! piecewise constant in `{+j_max, 0, -j_max}`. Notation, for distance `d`:
//! - `t_j`: duration of each jerk phase; peak acceleration `a_p = j_max t_j`;
//! - `t_a`: duration of the whole acceleration (and of the deceleration):
//!   jerk `+j` for `t_j`, constant `a_p` for `t_a - 2 t_j`, jerk `-j` for `t_j`;
//!   peak velocity `v_p = a_p (t_a - t_j)`;
//! - `t_v`: cruise at `v_p`; duration `T = 2 t_a + t_v` and `d = v_p (t_a + t_v)`.
//!
//! The minimum-time case analysis, in closed form:
//! 1. `v_max` reached (`t_v = d / v_max - t_a >= 0`), with `t_j = a_max / j_max`,
//!    `t_a = t_j + v_max / a_max` when `v_max j_max >= a_max^2` (`a_max` reached),
//!    else `t_j = sqrt(v_max / j_max)`, `t_a = 2 t_j`;
//! 2. otherwise `t_v = 0` and, when `d >= 2 a_max^3 / j_max^2`, `a_max` is reached:
//!    `t_j = a_max / j_max`, `t_a = (t_j + sqrt(t_j^2 + 4 d / a_max)) / 2`;
//! 3. otherwise neither: `t_j = cbrt(d / (2 j_max))`, `t_a = 2 t_j`.

use crate::axis::{Axis, Instant, OneAxis, Shape, instant};
use crate::error::{Error, LimitKind, check_limit};
use crate::profile::{Motion, Profile, State};
use crate::real::Real;
use crate::trapezoid::Limits;

/// Velocity, acceleration and jerk limits of one axis (magnitudes).
///
/// Units: `v_max` in position units/s, `a_max` in units/s^2, `j_max` in
/// units/s^3. All must be positive and finite (checked when a profile is built).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JerkLimits<T> {
    /// Largest `|velocity|`, in position units/s.
    pub v_max: T,
    /// Largest `|acceleration|`, in position units/s^2.
    pub a_max: T,
    /// Largest `|jerk|`, in position units/s^3.
    pub j_max: T,
}

impl<T: Real> JerkLimits<T> {
    /// Limits from `v_max` (units/s), `a_max` (units/s^2) and `j_max` (units/s^3).
    #[must_use]
    pub const fn new(v_max: T, a_max: T, j_max: T) -> Self {
        Self {
            v_max,
            a_max,
            j_max,
        }
    }

    /// Trapezoid limits plus a jerk limit `j_max` (units/s^3).
    #[must_use]
    pub const fn from_limits(limits: Limits<T>, j_max: T) -> Self {
        Self::new(limits.v_max, limits.a_max, j_max)
    }

    /// The velocity and acceleration limits alone.
    #[must_use]
    pub const fn limits(&self) -> Limits<T> {
        Limits::new(self.v_max, self.a_max)
    }

    /// Checks the three limits, reporting `axis` in the error.
    pub(crate) fn check(&self, axis: usize) -> Result<(), Error> {
        check_limit(axis, LimitKind::Velocity, self.v_max)?;
        check_limit(axis, LimitKind::Acceleration, self.a_max)?;
        check_limit(axis, LimitKind::Jerk, self.j_max)
    }
}

/// The timing of a double-S over a positive distance (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SShape<T> {
    t_j: T,
    t_a: T,
    t_v: T,
    j: T,
    a_p: T,
    v_p: T,
    duration: T,
}

impl<T: Real> SShape<T> {
    /// The shape with these phase times and peaks; `None` when one does not
    /// fit the float type: not finite, or (the jerk time, the jerk and the
    /// peaks) not a normal number. A subnormal one holds too few significant
    /// bits for the profile to keep its limits and end on its goal (a jerk
    /// time of 8e-42 s in `f32` made `a_p = j t_j` 8e-5 above `a_max`), as
    /// for a scaled shape ([`SShape::scaled`]).
    fn checked(t_j: T, t_a: T, t_v: T, j: T, a_p: T, v_p: T) -> Option<Self> {
        let duration = t_a + t_a + t_v;
        let all = [t_j, t_a, t_v, j, a_p, v_p, duration];
        let finite = all.iter().all(|x| x.finite());
        let normal = [t_j, j, a_p, v_p].iter().all(|x| x.is_normal());
        let positive = t_j > T::zero() && j > T::zero() && a_p > T::zero() && v_p > T::zero();
        (finite && normal && positive).then_some(Self {
            t_j,
            t_a,
            t_v,
            j,
            a_p,
            v_p,
            duration,
        })
    }
}

impl<T: Real> Shape<T> for SShape<T> {
    type Limits = JerkLimits<T>;

    fn check_limits(limits: &JerkLimits<T>, axis: usize) -> Result<(), Error> {
        limits.check(axis)
    }

    fn unbounded() -> JerkLimits<T> {
        JerkLimits::new(T::INFINITY, T::INFINITY, T::INFINITY)
    }

    fn tighten(line: &mut JerkLimits<T>, limits: &JerkLimits<T>, ratio: T) {
        line.v_max = line.v_max.min(limits.v_max * ratio);
        line.a_max = line.a_max.min(limits.a_max * ratio);
        line.j_max = line.j_max.min(limits.j_max * ratio);
    }

    /// The three cases of the module docs.
    fn min_time(d: T, lim: JerkLimits<T>) -> Option<Self> {
        let (v, a, j) = (lim.v_max, lim.a_max, lim.j_max);
        let two = T::lit(2.0);
        let half = T::lit(0.5);
        // Case 1: v_max reached.
        let (t_j, t_a) = if v / a >= a / j {
            (a / j, a / j + v / a)
        } else {
            let t_j = (v / j).sqrt();
            (t_j, t_j + t_j)
        };
        let t_v = d / v - t_a;
        if t_v >= T::zero() {
            return Self::checked(t_j, t_a, t_v, j, j * t_j, v);
        }
        // Case 2: v_max not reached, a_max reached.
        let t_j = a / j;
        let t_a = half * (t_j + (t_j * t_j + T::lit(4.0) * (d / a)).sqrt());
        if t_a >= two * t_j {
            return Self::checked(t_j, t_a, T::zero(), j, a, a * (t_a - t_j));
        }
        // Case 3: neither reached: d = 2 j t_j^3.
        let t_j = (d / (two * j)).cbrt();
        let a_p = j * t_j;
        Self::checked(t_j, t_j + t_j, T::zero(), j, a_p, a_p * t_j)
    }

    /// With `T(v) = d / v + t_a(v)` decreasing in the cruise velocity `v` up to
    /// the minimum-time peak velocity: when `a_max` is reached (`v >= a_max^2 /
    /// j_max`), `T` is a quadratic in `v`, solved in closed form; otherwise `2
    /// t_j^3 - T t_j^2 + d / j_max = 0`, solved by bisection on `(0, min(T / 4,
    /// sqrt(2 d / (j_max T)))]` (at most 256 halvings).
    fn with_duration(&self, d: T, lim: JerkLimits<T>, duration: T) -> Option<Self> {
        let own_v_p = self.v_p;
        let (v_max, a, j) = (lim.v_max, lim.a_max, lim.j_max);
        let two = T::lit(2.0);
        let half = T::lit(0.5);
        let w_c = a / j; // jerk time when a_max is reached
        let v_c = a * w_c; // lowest cruise velocity that reaches a_max
        let reaches_a = v_c < own_v_p && duration < d / v_c + two * w_c;
        let (t_j, t_a, a_p) = if reaches_a {
            // v^2 / a - (T - w_c) v + d = 0, smaller root.
            let b = duration - w_c;
            let r = two * (d / a).sqrt();
            if !r.finite() {
                // `d / a_max` overflows: out of range, as for the trapezoid.
                return None;
            }
            let root = (b - r).max(T::zero()).sqrt() * (b + r).max(T::zero()).sqrt();
            let v = (d / (half * (b + root))).min(v_max);
            (w_c, w_c + v / a, a)
        } else {
            let c = d / j;
            let f = |w: T| (two * w - duration) * w * w + c;
            // On (0, T / 4], 2 w - T <= -T / 2, so f < 0 past sqrt(2 c / T):
            // the root is below that bound, which keeps the bisection within
            // its halvings however long T is next to the minimum time.
            // The bound is `sqrt(2 c / T)`, in an order that does not
            // overflow where `2 c` would (a distance of 1e154 against a jerk
            // of 1e-154 in f64: the bound came out infinite and the bisection
            // ran out of halvings from T / 4, 1e6 times above the root).
            let bound = (two * (d / duration) / j).sqrt();
            let (mut lo, mut hi) = (T::zero(), (duration * T::lit(0.25)).min(bound));
            let mut converged = false;
            for _ in 0..256 {
                let mid = half * (lo + hi);
                if mid <= lo || mid >= hi {
                    converged = true;
                    break;
                }
                if f(mid) > T::zero() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            if !converged {
                // Out of halvings far from the root: the numbers of this
                // stretch do not fit the float type.
                return None;
            }
            let w = hi.min(w_c);
            (w, w + w, j * w)
        };
        let v_p = (a_p * (t_a - t_j)).min(v_max);
        let t_v = (duration - two * t_a).max(T::zero());
        let mut shape = Self::checked(t_j, t_a, t_v, j, a_p, v_p)?;
        shape.duration = duration;
        Some(shape)
    }

    /// A subnormal jerk, acceleration or velocity is refused.
    fn scaled(&self, k: T) -> Option<Self> {
        let shape = Self {
            j: self.j * k,
            a_p: self.a_p * k,
            v_p: self.v_p * k,
            ..*self
        };
        [k, shape.j, shape.a_p, shape.v_p]
            .iter()
            .all(|x| x.is_normal())
            .then_some(shape)
    }

    fn still(duration: T) -> Self {
        let z = T::zero();
        Self {
            t_j: z,
            t_a: z,
            t_v: duration,
            j: z,
            a_p: z,
            v_p: z,
            duration,
        }
    }

    fn duration(&self) -> T {
        self.duration
    }

    fn t_accel(&self) -> T {
        self.t_a
    }

    fn t_cruise(&self) -> T {
        self.t_v
    }

    fn peak_velocity(&self) -> T {
        self.v_p
    }

    /// The jerk phase, the constant acceleration, the jerk phase back to
    /// the cruise.
    fn accel_half(&self, t: T) -> (T, T, T) {
        let half = T::lit(0.5);
        let sixth = T::one() / T::lit(6.0);
        if t < self.t_j {
            let a = (self.j * t).min(self.a_p);
            (a * t * t * sixth, half * a * t, a)
        } else if t < self.t_a - self.t_j {
            let s = half * self.a_p * t * (t - self.t_j) + self.a_p * self.t_j * self.t_j * sixth;
            (s, self.a_p * (t - half * self.t_j), self.a_p)
        } else {
            // sigma may exceed t_j by the rounding of `t_a - t`: clamp the acceleration.
            let sigma = (self.t_a - t).max(T::zero());
            let a = (self.j * sigma).min(self.a_p);
            let s = half * self.v_p * self.t_a - self.v_p * sigma + a * sigma * sigma * sixth;
            (s, self.v_p - half * a * sigma, a)
        }
    }
}

/// A rest-to-rest jerk-limited (double-S, seven-phase) profile of one axis,
/// with the same interface and conventions as [`Trapezoid`](crate::Trapezoid).
///
/// Units: position in the units of the axis, velocity units/s, acceleration
/// units/s^2, jerk units/s^3, time s from the start of the motion. The
/// acceleration is continuous; it is 0 for `t <= 0` and `t >= duration()`.
/// The jerk ([`DoubleS::jerk`]) is right-continuous at its switch instants.
///
/// ```
/// use parasils_traj::{DoubleS, JerkLimits, Trapezoid};
/// let limits = JerkLimits::new(10.0_f64, 5.0, 20.0);
/// let smooth = DoubleS::new(0.0, 25.0, limits)?;
/// let trap = Trapezoid::new(0.0, 25.0, limits.limits())?;
/// // The jerk limit costs a_max / j_max = 0.25 s here.
/// assert!((smooth.duration() - (trap.duration() + 0.25)).abs() < 1e-12);
/// assert_eq!(smooth.sample(smooth.duration()).position, 25.0);
/// # Ok::<(), parasils_traj::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoubleS<T>(Axis<T, SShape<T>>);

impl<T: Real> DoubleS<T> {
    /// The minimum-time jerk-limited profile from `start` to `goal` (position units).
    ///
    /// # Errors
    /// [`Error::NonFinitePosition`], [`Error::InvalidLimit`],
    /// [`Error::DistanceOverflow`] or [`Error::OutOfRange`], with axis `0`.
    pub fn new(start: T, goal: T, limits: JerkLimits<T>) -> Result<Self, Error> {
        Axis::new(0, start, goal, limits).map(Self)
    }

    /// The profile lasting `duration` (s) exactly, keeping `a_max` and `j_max`
    /// and lowering the cruise velocity. A `duration` below the minimum time
    /// by no more than 8 float epsilons (relative) gives the minimum-time profile.
    ///
    /// # Errors
    /// As [`DoubleS::new`], and [`Error::InvalidDuration`] when `duration` is
    /// not finite or shorter than the minimum time.
    pub fn with_duration(
        start: T,
        goal: T,
        limits: JerkLimits<T>,
        duration: T,
    ) -> Result<Self, Error> {
        let own = Axis::new(0, start, goal, limits)?;
        own.stretched(0, limits, duration).map(Self)
    }

    /// The shape, in magnitudes.
    fn s(&self) -> &SShape<T> {
        self.0.shape()
    }

    /// Start position, in position units.
    #[must_use]
    pub fn start(&self) -> T {
        self.0.start()
    }

    /// Goal position, in position units.
    #[must_use]
    pub fn goal(&self) -> T {
        self.0.goal()
    }

    /// `|goal - start|`, in position units.
    #[must_use]
    pub fn distance(&self) -> T {
        self.0.distance()
    }

    /// Duration of the motion, in s: `t_accel + t_cruise + t_decel`.
    #[must_use]
    pub fn duration(&self) -> T {
        self.s().duration
    }

    /// Duration of each of the four constant-jerk phases, in s.
    #[must_use]
    pub fn t_jerk(&self) -> T {
        self.s().t_j
    }

    /// Duration of the whole acceleration (three phases), in s.
    #[must_use]
    pub fn t_accel(&self) -> T {
        self.s().t_a
    }

    /// Duration of the constant-velocity phase, in s.
    #[must_use]
    pub fn t_cruise(&self) -> T {
        self.s().t_v
    }

    /// Duration of the whole deceleration (three phases), in s; equals [`t_accel`](Self::t_accel).
    #[must_use]
    pub fn t_decel(&self) -> T {
        self.s().t_a
    }

    /// Largest `|velocity|`, in units/s.
    #[must_use]
    pub fn peak_velocity(&self) -> T {
        self.s().v_p
    }

    /// Largest `|acceleration|`, in units/s^2.
    #[must_use]
    pub fn peak_acceleration(&self) -> T {
        self.s().a_p
    }

    /// `|jerk|` of the jerk phases, in units/s^3.
    #[must_use]
    pub fn peak_jerk(&self) -> T {
        self.s().j
    }

    /// True when the profile has a constant-velocity phase (`t_cruise() > 0`).
    #[must_use]
    pub fn has_cruise(&self) -> bool {
        self.0.moves() && self.s().t_v > T::zero()
    }

    /// True when the acceleration has a constant phase (`t_accel() > 2 t_jerk()`).
    #[must_use]
    pub fn has_constant_acceleration(&self) -> bool {
        self.0.moves() && self.s().t_a > self.s().t_j + self.s().t_j
    }

    /// The state at `t` (s); conventions as [`Trapezoid::sample`](crate::Trapezoid::sample).
    #[must_use]
    pub fn sample(&self, t: T) -> State<T> {
        self.0.sample(t)
    }

    /// Jerk at `t` (s), in units/s^3: `+-j` or 0, right-continuous at the
    /// switch instants, 0 for `t <= 0` and `t >= duration()`.
    #[must_use]
    pub fn jerk(&self, t: T) -> T {
        let s = self.s();
        let t = match instant(t, s.duration) {
            Instant::Inside(t) if self.0.moves() => t,
            _ => return T::zero(),
        };
        let decel = s.t_a + s.t_v;
        let j = if t < s.t_j {
            s.j
        } else if t < s.t_a - s.t_j {
            T::zero()
        } else if t < s.t_a {
            -s.j
        } else if t < decel {
            T::zero()
        } else if t < decel + s.t_j {
            -s.j
        } else if t < s.duration - s.t_j {
            T::zero()
        } else {
            s.j
        };
        self.0.direction() * j
    }
}

impl<T: Real> OneAxis<T> for DoubleS<T> {
    type Shape = SShape<T>;
    fn from_axis(axis: Axis<T, SShape<T>>) -> Self {
        Self(axis)
    }
}

impl<T: Real> Motion<T> for DoubleS<T> {
    type Output = State<T>;
    fn duration(&self) -> T {
        self.s().duration
    }
    fn sample(&self, t: T) -> State<T> {
        self.0.sample(t)
    }
}

impl<T: Real> Profile<T> for DoubleS<T> {
    fn start(&self) -> T {
        self.0.start()
    }
    fn goal(&self) -> T {
        self.0.goal()
    }
    fn distance(&self) -> T {
        self.0.distance()
    }
    fn peak_velocity(&self) -> T {
        self.s().v_p
    }
    fn peak_acceleration(&self) -> T {
        self.s().a_p
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp, reason = "exactness is what these tests check")]
mod tests {
    use super::*;

    /// One case per branch of the analysis; the durations are hand-computed.
    #[test]
    fn the_three_cases() -> Result<(), Error> {
        // Case 1, a reached: T = d/v + v/a + a/j = 2.5 + 2 + 0.25.
        let p = DoubleS::new(0.0_f64, 25.0, JerkLimits::new(10.0, 5.0, 20.0))?;
        assert!(p.has_cruise() && p.has_constant_acceleration());
        assert!((p.duration() - 4.75).abs() < 1e-12);
        // Case 1, a not reached: t_j = sqrt(v/j) = 1, T = d/v + 2 t_j = 10 + 2.
        let p = DoubleS::new(0.0_f64, 10.0, JerkLimits::new(1.0, 5.0, 1.0))?;
        assert!(p.has_cruise() && !p.has_constant_acceleration());
        assert!((p.duration() - 12.0).abs() < 1e-12);
        // Case 2: t_j = 0.5, t_a = (0.5 + sqrt(0.25 + 4 * 3 / 1)) / 2 = 2, T = 4.
        let p = DoubleS::new(0.0_f64, 3.0, JerkLimits::new(100.0, 1.0, 2.0))?;
        assert!(!p.has_cruise() && p.has_constant_acceleration());
        assert!((p.duration() - 4.0).abs() < 1e-12);
        // Case 3: d = 2 j t_j^3 with t_j = 1: T = 4 t_j.
        let p = DoubleS::new(0.0_f64, 2.0, JerkLimits::new(100.0, 100.0, 1.0))?;
        assert!(!p.has_cruise() && !p.has_constant_acceleration());
        assert!((p.duration() - 4.0).abs() < 1e-12);
        assert!((p.peak_acceleration() - 1.0).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn jerk_is_right_continuous() -> Result<(), Error> {
        let p = DoubleS::new(0.0_f64, 25.0, JerkLimits::new(10.0, 5.0, 20.0))?;
        assert_eq!(p.jerk(0.0), 0.0);
        assert_eq!(p.jerk(1e-12), 20.0);
        assert_eq!(p.jerk(p.t_jerk()), 0.0);
        assert_eq!(p.jerk(p.t_accel() - p.t_jerk()), -20.0);
        assert_eq!(p.jerk(p.t_accel()), 0.0);
        assert_eq!(p.jerk(p.t_accel() + p.t_cruise()), -20.0);
        assert_eq!(p.jerk(p.duration()), 0.0);
        Ok(())
    }

    #[test]
    fn with_duration_both_branches() -> Result<(), Error> {
        let lim = JerkLimits::new(10.0_f64, 5.0, 20.0);
        for (d, t) in [(25.0, 6.0), (25.0, 60.0), (1.0, 2.0), (1.0, 50.0)] {
            let own = DoubleS::new(0.0, d, lim)?;
            assert!(t > own.duration());
            let p = DoubleS::with_duration(0.0, d, lim, t)?;
            assert_eq!(p.duration(), t);
            let s = *p.s();
            let d_back = s.v_p * (s.t_a + s.t_v);
            assert!((d_back - d).abs() < 1e-9 * d, "{d} {t}: {d_back}");
            assert!(p.peak_acceleration() <= 5.0 && p.peak_velocity() <= 10.0);
        }
        Ok(())
    }

    #[test]
    fn a_stretch_whose_time_scale_overflows_is_out_of_range() -> Result<(), Error> {
        // f32, a_max reached: the minimum time (2e20 s) fits, but the
        // stretched shape needs d / a_max = 1e40, past f32's largest
        // number: refused, as for the trapezoid.
        let l = JerkLimits::new(1e10_f32, 1e-10, 1.0);
        let own = DoubleS::new(0.0_f32, 1e30, l)?;
        let r = DoubleS::with_duration(0.0_f32, 1e30, l, own.duration() * 2.0);
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
        Ok(())
    }

    #[test]
    fn a_subnormal_jerk_time_is_out_of_range() {
        // The fuzzer's case (f32): a_max = 9.1834e-41 (subnormal) with
        // j_max = 11: the jerk time a_max / j_max = 8.3e-42 s rounds to a
        // few significant bits, and the profile reported (and reached) a
        // peak acceleration j t_j 8e-5 above a_max. Refused instead.
        let l = JerkLimits::new(1e-19_f32, 9.1834e-41, 11.042_969);
        let r = DoubleS::new(1e19_f32, 1.0, l);
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
    }
}
