//! The trapezoidal velocity profile of one axis (`docs/model.md`,
//! *Trajectories*), triangular
//! when the distance is too short to reach the velocity limit.
//!
//! With distance `d = |goal - start|` and limits `v_max`, `a_max`:
//! - trapezoidal when `d * a_max > v_max^2`: accelerate at `a_max` for
//!   `t_a = v_max / a_max`, cruise at `v_max` for `t_c = d / v_max - v_max / a_max`,
//!   decelerate for `t_a`; duration `T = d / v_max + v_max / a_max`;
//! - triangular when `d * a_max <= v_max^2`: peak velocity `sqrt(d * a_max)`,
//!   `t_a = sqrt(d / a_max)`, `t_c = 0`, `T = 2 sqrt(d / a_max)`.
//!
//! The two formulas agree at the switch `d * a_max = v_max^2`. The comparison
//! is made as `d / v_max < v_max / a_max`, which neither overflows nor
//! underflows where the product form would.

use crate::axis::{Axis, OneAxis, Shape, ramp};
use crate::error::{Error, LimitKind, check_limit};
use crate::profile::{Motion, Profile, State};
use crate::real::Real;

/// Velocity and acceleration limits of one axis (magnitudes, both directions).
///
/// Units: `v_max` in position units/s, `a_max` in position units/s^2 (e.g.
/// rad/s and rad/s^2, or mm/s and mm/s^2). Both must be positive and finite;
/// this is checked when a profile is built, with the axis index in the error.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Limits<T> {
    /// Largest `|velocity|`, in position units/s.
    pub v_max: T,
    /// Largest `|acceleration|`, in position units/s^2.
    pub a_max: T,
}

impl<T: Real> Limits<T> {
    /// Limits from `v_max` (units/s) and `a_max` (units/s^2).
    #[must_use]
    pub const fn new(v_max: T, a_max: T) -> Self {
        Self { v_max, a_max }
    }

    /// The paper's platform limits in radians: `omega_max = 10 deg/s`,
    /// `epsilon_max = 5 deg/s^2`.
    ///
    /// ```
    /// let l = parasils_traj::Limits::<f64>::paper();
    /// assert!((l.v_max.to_degrees() - 10.0).abs() < 1e-12);
    /// assert!((l.a_max.to_degrees() - 5.0).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn paper() -> Self {
        let deg = core::f64::consts::PI / 180.0;
        Self::new(T::lit(10.0 * deg), T::lit(5.0 * deg))
    }

    /// Checks both limits, reporting `axis` in the error.
    pub(crate) fn check(&self, axis: usize) -> Result<(), Error> {
        check_limit(axis, LimitKind::Velocity, self.v_max)?;
        check_limit(axis, LimitKind::Acceleration, self.a_max)
    }
}

/// The timing of a trapezoid over a positive distance: peaks and phase times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrapShape<T> {
    /// Peak (cruise) velocity, units/s.
    v: T,
    /// Acceleration magnitude, units/s^2.
    a: T,
    /// Acceleration time (= deceleration time), s.
    t_a: T,
    /// Cruise time, s.
    t_c: T,
    /// Total time, s.
    duration: T,
}

impl<T: Real> TrapShape<T> {
    /// The shape with these peaks and phase times; `None` when one does not
    /// fit the float type: not finite, or a peak not a normal number. A
    /// subnormal peak holds too few significant bits for the axis to end on
    /// its goal (a cruise velocity lowered to 7.8e-46 in `f32` rounds to
    /// 1.4e-45, nearly twice as fast), as for a scaled shape
    /// ([`Shape::scaled`]).
    fn checked(v: T, a: T, t_a: T, t_c: T, duration: T) -> Option<Self> {
        let finite = [v, a, t_a, t_c, duration].iter().all(|x| x.finite());
        let normal = v.is_normal() && a.is_normal();
        let positive = v > T::zero() && a > T::zero() && t_a > T::zero();
        (finite && normal && positive).then_some(Self {
            v,
            a,
            t_a,
            t_c,
            duration,
        })
    }
}

impl<T: Real> Shape<T> for TrapShape<T> {
    type Limits = Limits<T>;

    fn check_limits(limits: &Limits<T>, axis: usize) -> Result<(), Error> {
        limits.check(axis)
    }

    fn unbounded() -> Limits<T> {
        Limits::new(T::INFINITY, T::INFINITY)
    }

    fn tighten(line: &mut Limits<T>, limits: &Limits<T>, ratio: T) {
        line.v_max = line.v_max.min(limits.v_max * ratio);
        line.a_max = line.a_max.min(limits.a_max * ratio);
    }

    /// Trapezoidal when `d / v_max >= v_max / a_max`, else triangular (module docs).
    fn min_time(d: T, limits: Limits<T>) -> Option<Self> {
        let (v_max, a_max) = (limits.v_max, limits.a_max);
        let x = d / v_max; // time to cover d at v_max
        let y = v_max / a_max; // time to reach v_max
        let (v, t_a, t_c) = if x < y {
            // Triangular: t_a = sqrt(d / a_max) = sqrt(x * y), without overflow.
            let t_a = x.sqrt() * y.sqrt();
            ((d / t_a).min(v_max), t_a, T::zero())
        } else {
            (v_max, y, x - y)
        };
        Self::checked(v, a_max, t_a, t_c, t_a + t_a + t_c)
    }

    /// `time` synchronisation (`docs/model.md`, *Trajectories*): `d = v (T -
    /// v / a)` gives `v = 2 d / (T + sqrt(T^2 - 4 d / a))`, the root that
    /// leaves a non-negative cruise, written without cancellation.
    fn with_duration(&self, d: T, limits: Limits<T>, duration: T) -> Option<Self> {
        let two = T::lit(2.0);
        let r = two * (d / limits.a_max).sqrt(); // minimum time without a velocity limit
        if !r.finite() {
            // `d / a_max` overflows (a long distance against a small `a_max`): the cruise
            // velocity below would come from a NaN, a plan that does not
            // last `duration` nor stay on its segment. Out of range.
            return None;
        }
        let root = (duration - r).max(T::zero()).sqrt() * (duration + r).sqrt();
        let v = (d / (T::lit(0.5) * (duration + root))).min(limits.v_max);
        let t_a = v / limits.a_max;
        let t_c = (duration - two * t_a).max(T::zero());
        Self::checked(v, limits.a_max, t_a, t_c, duration)
    }

    /// A share `k` of 9e-324 in `f64` is 2 ulps, 10 % off: refused.
    fn scaled(&self, k: T) -> Option<Self> {
        let shape = Self {
            v: self.v * k,
            a: self.a * k,
            ..*self
        };
        (k.is_normal() && shape.v.is_normal() && shape.a.is_normal()).then_some(shape)
    }

    fn still(duration: T) -> Self {
        let z = T::zero();
        Self {
            v: z,
            a: z,
            t_a: z,
            t_c: duration,
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
        self.t_c
    }

    fn peak_velocity(&self) -> T {
        self.v
    }

    fn accel_half(&self, t: T) -> (T, T, T) {
        (ramp(self.a, t), self.a * t, self.a)
    }
}

/// A rest-to-rest trapezoidal (or triangular) velocity profile of one axis.
///
/// Time `t` is in s from the start of the motion. Position is in the units of
/// the axis, velocity in units/s, acceleration in units/s^2. The profile is
/// analytic at every `t`:
/// - `t <= 0` (or NaN): the start at rest, `t >= duration()`: the goal at rest,
///   both returned exactly as given;
/// - at a switch instant the acceleration is that of the phase that begins
///   (right-continuous), and it is exactly 0 for `t <= 0` and `t >= duration()`;
/// - a motion towards a smaller position is the mirror image (negative
///   velocity while cruising); a zero-distance motion stays still.
///
/// ```
/// use parasils_traj::{Limits, Trapezoid};
/// // The paper's psi axis: 15 deg at 10 deg/s and 5 deg/s^2 is triangular.
/// let psi = Trapezoid::new(0.0, 15.0, Limits::new(10.0, 5.0))?;
/// assert!(psi.is_triangular());
/// assert!((psi.duration() - 2.0 * 3.0_f64.sqrt()).abs() < 1e-12);
/// assert_eq!(psi.sample(psi.duration()).position, 15.0);
/// // The acceleration is right-continuous: at t_accel the deceleration begins.
/// assert_eq!(psi.sample(psi.t_accel()).acceleration, -5.0);
/// # Ok::<(), parasils_traj::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trapezoid<T>(Axis<T, TrapShape<T>>);

impl<T: Real> Trapezoid<T> {
    /// The minimum-time profile from `start` to `goal` (position units) under `limits`.
    ///
    /// # Errors
    /// [`Error::NonFinitePosition`], [`Error::InvalidLimit`],
    /// [`Error::DistanceOverflow`] or [`Error::OutOfRange`], with axis `0`.
    pub fn new(start: T, goal: T, limits: Limits<T>) -> Result<Self, Error> {
        Axis::new(0, start, goal, limits).map(Self)
    }

    /// The profile from `start` to `goal` that lasts `duration` (s) exactly,
    /// keeping `a_max` and lowering the cruise velocity (the single-axis form
    /// of [`Synchronization::Time`](crate::Synchronization::Time)).
    ///
    /// A `duration` below the minimum time by no more than 8 float epsilons
    /// (relative) gives the minimum-time profile. A zero-distance motion
    /// stays still for `duration`.
    ///
    /// ```
    /// use parasils_traj::{Limits, Trapezoid};
    /// let slow = Trapezoid::with_duration(0.0_f64, 15.0, Limits::new(10.0, 5.0), 4.5)?;
    /// assert!((slow.duration() - 4.5).abs() < 1e-12);
    /// assert_eq!(slow.peak_acceleration(), 5.0);
    /// assert!(slow.peak_velocity() < 10.0);
    /// # Ok::<(), parasils_traj::Error>(())
    /// ```
    ///
    /// # Errors
    /// As [`Trapezoid::new`], and [`Error::InvalidDuration`] when `duration`
    /// is not finite or shorter than the minimum time.
    pub fn with_duration(start: T, goal: T, limits: Limits<T>, duration: T) -> Result<Self, Error> {
        let own = Axis::new(0, start, goal, limits)?;
        own.stretched(0, limits, duration).map(Self)
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
        self.0.shape().duration
    }

    /// Duration of the acceleration phase, in s (0 for a zero distance).
    #[must_use]
    pub fn t_accel(&self) -> T {
        self.0.shape().t_a
    }

    /// Duration of the constant-velocity phase, in s (0 when triangular).
    #[must_use]
    pub fn t_cruise(&self) -> T {
        self.0.shape().t_c
    }

    /// Duration of the deceleration phase, in s (equal to [`t_accel`](Self::t_accel)).
    #[must_use]
    pub fn t_decel(&self) -> T {
        self.0.shape().t_a
    }

    /// Largest `|velocity|` reached, in units/s (`v_max`, or `sqrt(d a_max)` when triangular).
    #[must_use]
    pub fn peak_velocity(&self) -> T {
        self.0.shape().v
    }

    /// `|acceleration|` of the acceleration and deceleration phases, in units/s^2.
    #[must_use]
    pub fn peak_acceleration(&self) -> T {
        self.0.shape().a
    }

    /// True when the profile has no constant-velocity phase (a moving axis
    /// with `t_cruise() == 0`): for a minimum-time profile, when
    /// `d * a_max <= v_max^2`, the switch itself included.
    #[must_use]
    pub fn is_triangular(&self) -> bool {
        self.0.moves() && self.0.shape().t_c <= T::zero()
    }

    /// The state at `t` (s). See the type docs for the conventions.
    #[must_use]
    pub fn sample(&self, t: T) -> State<T> {
        self.0.sample(t)
    }
}

impl<T: Real> OneAxis<T> for Trapezoid<T> {
    type Shape = TrapShape<T>;
    fn from_axis(axis: Axis<T, TrapShape<T>>) -> Self {
        Self(axis)
    }
}

impl<T: Real> Motion<T> for Trapezoid<T> {
    type Output = State<T>;
    fn duration(&self) -> T {
        Trapezoid::duration(self)
    }
    fn sample(&self, t: T) -> State<T> {
        self.0.sample(t)
    }
}

impl<T: Real> Profile<T> for Trapezoid<T> {
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
        Trapezoid::peak_velocity(self)
    }
    fn peak_acceleration(&self) -> T {
        Trapezoid::peak_acceleration(self)
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp, reason = "exactness is what these tests check")]
mod tests {
    use super::*;

    #[test]
    fn paper_psi_is_triangular() -> Result<(), Error> {
        let p = Trapezoid::new(-15.0_f64, 0.0, Limits::new(10.0, 5.0))?;
        assert!(p.is_triangular());
        assert!((p.duration() - 2.0 * 3.0_f64.sqrt()).abs() < 1e-12);
        assert!((p.peak_velocity() - 75.0_f64.sqrt()).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn paper_theta_is_trapezoidal() -> Result<(), Error> {
        let p = Trapezoid::new(10.0_f64, 35.0, Limits::new(10.0, 5.0))?;
        assert!(!p.is_triangular());
        assert!((p.duration() - 4.5).abs() < 1e-12);
        assert!((p.t_accel() - 2.0).abs() < 1e-12);
        assert!((p.t_cruise() - 0.5).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn acceleration_is_right_continuous_and_zero_outside() -> Result<(), Error> {
        let p = Trapezoid::new(0.0_f64, 25.0, Limits::new(10.0, 5.0))?;
        assert_eq!(p.sample(0.0).acceleration, 0.0);
        assert_eq!(p.sample(-1.0).acceleration, 0.0);
        assert_eq!(p.sample(1e-9).acceleration, 5.0);
        assert_eq!(p.sample(p.t_accel()).acceleration, 0.0);
        assert_eq!(p.sample(p.t_accel() + p.t_cruise()).acceleration, -5.0);
        assert_eq!(p.sample(p.duration()).acceleration, 0.0);
        Ok(())
    }

    #[test]
    fn negative_direction_is_the_mirror() -> Result<(), Error> {
        let up = Trapezoid::new(0.0_f64, 3.0, Limits::new(2.0, 1.0))?;
        let down = Trapezoid::new(0.0_f64, -3.0, Limits::new(2.0, 1.0))?;
        for i in 0..=100 {
            let t = f64::from(i) * 0.05;
            let (u, d) = (up.sample(t), down.sample(t));
            assert_eq!(u.position, -d.position);
            assert_eq!(u.velocity, -d.velocity);
            assert_eq!(u.acceleration, -d.acceleration);
        }
        Ok(())
    }

    #[test]
    fn zero_distance_stays_still() -> Result<(), Error> {
        let p = Trapezoid::new(1.5_f64, 1.5, Limits::new(2.0, 1.0))?;
        assert_eq!(p.duration(), 0.0);
        assert!(!p.is_triangular());
        for t in [-1.0, 0.0, 1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(p.sample(t), State::rest(1.5));
        }
        Ok(())
    }

    #[test]
    fn nan_time_is_the_start() -> Result<(), Error> {
        let p = Trapezoid::new(1.0_f64, 2.0, Limits::new(2.0, 1.0))?;
        assert_eq!(p.sample(f64::NAN), State::rest(1.0));
        assert_eq!(p.sample(f64::NEG_INFINITY), State::rest(1.0));
        assert_eq!(p.sample(f64::INFINITY), State::rest(2.0));
        Ok(())
    }

    #[test]
    fn errors_name_axis_limit_and_value() {
        assert_eq!(
            Trapezoid::new(0.0_f64, 1.0, Limits::new(-1.0, 1.0)),
            Err(Error::InvalidLimit {
                axis: 0,
                limit: LimitKind::Velocity,
                value: -1.0
            })
        );
        assert!(matches!(
            Trapezoid::new(0.0_f64, 1.0, Limits::new(1.0, f64::INFINITY)),
            Err(Error::InvalidLimit {
                limit: LimitKind::Acceleration,
                ..
            })
        ));
        assert!(matches!(
            Trapezoid::new(f64::NAN, 1.0, Limits::new(1.0, 1.0)),
            Err(Error::NonFinitePosition { .. })
        ));
        assert!(matches!(
            Trapezoid::new(-f64::MAX, f64::MAX, Limits::new(1.0, 1.0)),
            Err(Error::DistanceOverflow { .. })
        ));
        assert!(matches!(
            Trapezoid::new(0.0_f32, 1e30, Limits::new(1e-30, 1.0)),
            Err(Error::OutOfRange { .. })
        ));
    }

    #[test]
    fn with_duration_rejects_too_short() {
        let r = Trapezoid::with_duration(0.0_f64, 25.0, Limits::new(10.0, 5.0), 4.0);
        assert!(
            matches!(r, Err(Error::InvalidDuration { minimum, .. }) if (minimum - 4.5).abs() < 1e-12)
        );
    }

    #[test]
    fn a_stretch_whose_time_scale_overflows_is_out_of_range() -> Result<(), Error> {
        // f32: the minimum time (2e20 s) fits, but stretching it needs
        // d / a_max = 1e40, past f32's largest number. The plan is refused
        // rather than built from a NaN (the fuzzer's case, with a subnormal
        // a_max, lasted 4.9e22 s with an acceleration time of 1.2e35 s).
        let l = Limits::new(1e10_f32, 1e-10);
        let own = Trapezoid::new(0.0_f32, 1e30, l)?;
        let r = Trapezoid::with_duration(0.0_f32, 1e30, l, own.duration() * 2.0);
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
        Ok(())
    }

    #[test]
    fn a_stretch_that_lowers_the_velocity_to_a_subnormal_number_is_out_of_range() {
        // The fuzzer's case (f32): 2.5e-38 stretched to 16705 s needs a
        // cruise velocity of 1.5e-42, a subnormal number of 10 significant
        // bits; the plan ended 1.4e-42 past its goal (6e-5 of the distance).
        let l = Limits::new(6.600_68e-40_f32, 570.625);
        let r = Trapezoid::with_duration(0.0_f32, 2.516_292_6e-38, l, 16705.0);
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
        // Its own (given) velocity limit is subnormal too: refused alike.
        let r = Trapezoid::new(0.0_f32, 2.516_292_6e-38, l);
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
    }
}
