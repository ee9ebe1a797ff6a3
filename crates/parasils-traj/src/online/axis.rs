//! One axis from its current state to rest at a target, and its stop (see
//! the [module docs](super)).

use crate::axis::{Instant, check_duration, instant, ramp};
use crate::error::{Endpoint, Error, check_move, check_position, out_of_range};
use crate::profile::{Motion, State};
use crate::real::Real;
use crate::trapezoid::Limits;

/// A plan in the units of one axis's limits (time `v_max / a_max`, velocity
/// `v_max`): the approach direction, the signs and the phase times.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Normalised<T> {
    /// Direction of the final approach: `+1`, `-1`, or `0` when nothing moves.
    sigma: T,
    /// Sign of the first phase's acceleration relative to `sigma`.
    first: T,
    /// `|v_c| / v_max`.
    peak: T,
    t1: T,
    t2: T,
    t3: T,
}

impl<T: Real> Normalised<T> {
    pub(super) fn still(t2: T) -> Self {
        Self {
            sigma: T::zero(),
            first: T::zero(),
            peak: T::zero(),
            t1: T::zero(),
            t2,
            t3: T::zero(),
        }
    }

    /// The approach direction, `u0 = s u` and `h = |e|`; `None` when the axis
    /// is at rest on its target. A moving axis whose target is within
    /// `slack` of its stopping point takes it as the stopping point.
    pub(super) fn approach(n: Problem<T>) -> Option<(T, T, T)> {
        let (x, u) = (n.x, n.u);
        let e = x - T::lit(0.5) * u * u.abs();
        let e = if e.abs() <= n.slack && u != T::zero() {
            T::zero()
        } else {
            e
        };
        let sigma = if e > T::zero() {
            T::one()
        } else if e < T::zero() {
            -T::one()
        } else if u > T::zero() {
            T::one()
        } else if u < T::zero() {
            -T::one()
        } else {
            return None;
        };
        Some((sigma, sigma * u, e.abs()))
    }

    /// The minimum-time plan over `x` from `u` (see the module docs).
    pub(super) fn min_time(n: Problem<T>) -> Self {
        let Some((sigma, u0, h)) = Self::approach(n) else {
            return Self::still(T::zero());
        };
        let one = T::one();
        let (first, peak, t1, t2, t3) = if u0 > one {
            (-one, one, u0 - one, h, one)
        } else {
            let q = if u0 > T::zero() { h + u0 * u0 } else { h };
            if q >= one {
                (one, one, one - u0, q - one, one)
            } else {
                let peak = q.sqrt();
                let t1 = if u0 > T::zero() {
                    h / (peak + u0)
                } else {
                    peak - u0
                };
                (one, peak, t1, T::zero(), peak)
            }
        };
        Self {
            sigma,
            first,
            peak,
            t1,
            t2,
            t3,
        }
    }

    /// The plan over `x` from `u` lasting `theta`, at least the minimum time
    /// (see the module docs).
    pub(super) fn with_duration(n: Problem<T>, theta: T) -> Self {
        let Some((sigma, u0, h)) = Self::approach(n) else {
            return Self::still(theta.max(T::zero()));
        };
        let (one, two) = (T::one(), T::lit(2.0));
        if h == T::zero() {
            // The target is the stopping point: brake, then wait there.
            return Self {
                sigma,
                first: -one,
                peak: T::zero(),
                t1: u0,
                t2: (theta - u0).max(T::zero()),
                t3: T::zero(),
            };
        }
        let rest = theta - u0;
        if u0 > one || (u0 > T::zero() && h <= u0 * rest) {
            // Decelerate to a slower cruise.
            let peak = (if h < rest { h / rest } else { one }).min(u0);
            return Self {
                sigma,
                first: -one,
                peak,
                t1: u0 - peak,
                t2: rest.max(T::zero()),
                t3: peak,
            };
        }
        // Accelerate to the smaller root of v^2 - b v + q = 0.
        let q = if u0 > T::zero() { h + u0 * u0 } else { h };
        let b = theta + u0;
        let sq = q.sqrt();
        let root = (b - two * sq).max(T::zero()).sqrt() * (b + two * sq).sqrt();
        let den = b + root;
        // In exact arithmetic the root exceeds `u0` here (the polynomial is
        // `h - u0 (theta - u0) > 0` at `u0`, below its vertex `b / 2`). Near the
        // boundary with the decelerating case the branch test and the root are
        // both decided by rounding (`h` and `theta - u0` are differences of
        // nearly equal numbers, and the root moves as the square root of
        // `b - 2 sq`), so the computed root can fall below `u0`: there is then
        // no first phase and the cruise is `u0` itself, which the last phase
        // must start from (a lower peak would leave a velocity jump at the
        // switch). Cruising at `u0` is the decelerating case at its boundary.
        let peak = if den > T::zero() {
            (two * q / den).min(sq)
        } else {
            sq
        }
        .max(u0)
        .min(one);
        let t1 = (peak - u0).max(T::zero());
        Self {
            sigma,
            first: one,
            peak,
            t1,
            t2: (theta - t1 - peak).max(T::zero()),
            t3: peak,
        }
    }
}

/// One axis's problem in the units of its limits (see the module docs).
#[derive(Debug, Clone, Copy)]
struct Problem<T> {
    /// `target - p0`, in `v_max^2 / a_max`.
    x: T,
    /// `v0`, in `v_max`.
    u: T,
    /// The rounding of the positions and of the stopping distance, as `x`.
    slack: T,
    /// The time unit `v_max / a_max`, in s.
    tau: T,
}

impl<T: Real> Problem<T> {
    /// The problem from `p0` and `v0` to `target`; `None` when it does not
    /// fit the float type.
    pub(super) fn new(p0: T, v0: T, target: T, limits: Limits<T>) -> Option<Self> {
        let tau = limits.v_max / limits.a_max;
        let scale = |y: T| (y / limits.v_max) / tau;
        let x = scale(target - p0);
        let u = v0 / limits.v_max;
        // 4 eps of |p0| + |target| and of the stopping distance u^2 / 2, twice.
        let big = scale(p0.abs().max(target.abs()));
        let slack = T::lit(4.0) * T::EPSILON * (big + big + u * u);
        let ok = tau.finite() && tau > T::zero() && x.finite() && u.finite();
        ok.then_some(Self { x, u, slack, tau })
    }
}

/// A normalised plan in the units of the axis: `(a1, t1, v_c, t2, a3, t3)`.
fn phases<T: Real>(n: Normalised<T>, limits: Limits<T>, tau: T) -> [T; 6] {
    let vc = if n.peak >= T::one() {
        limits.v_max
    } else {
        n.peak * limits.v_max
    };
    [
        n.sigma * n.first * limits.a_max,
        n.t1 * tau,
        n.sigma * vc,
        n.t2 * tau,
        -n.sigma * limits.a_max,
        n.t3 * tau,
    ]
}

/// Checks the limits, a start state and a target; returns `|target - p0|`.
fn check_axis<T: Real>(
    axis: usize,
    start: State<T>,
    target: T,
    limits: Limits<T>,
) -> Result<T, Error> {
    limits.check(axis)?;
    check_start(axis, start)?;
    check_move(axis, start.position, target).map(|(_, distance)| distance)
}

/// Checks the position and velocity of a start state.
pub(super) fn check_start<T: Real>(axis: usize, start: State<T>) -> Result<(), Error> {
    check_position(axis, Endpoint::Start, start.position)?;
    if start.velocity.finite() {
        Ok(())
    } else {
        Err(Error::NonFiniteVelocity {
            axis,
            value: start.velocity.to_f64(),
        })
    }
}

/// The profile of one axis from any state `(p0, v0)` to rest at a target,
/// time-optimal under [`Limits`] (see the [module docs](super) for the cases
/// and the conventions).
///
/// Time `t` is in s from the start of the motion; positions in the units of
/// the axis, velocities in units/s, accelerations in units/s^2. The profile
/// is analytic at every `t`: the start state for `t <= 0` (zero acceleration),
/// the target at rest for `t >= duration()`, both exactly as given.
///
/// ```
/// use parasils_traj::{Limits, OnlineTrapezoid, State};
/// let limits = Limits::new(2.0_f64, 1.0);
/// // From rest: the trapezoid, 10 units at 2 units/s and 1 unit/s^2.
/// let p = OnlineTrapezoid::new(State::rest(0.0), 10.0, limits)?;
/// assert!((p.duration() - 7.0).abs() < 1e-12);
/// // Moving at 3 units/s, above v_max: brake to 2 first, then as before.
/// let fast = OnlineTrapezoid::new(State { position: 0.0, velocity: 3.0, acceleration: 0.0 }, 10.0, limits)?;
/// assert!((fast.duration() - 5.75).abs() < 1e-12);
/// assert_eq!(fast.sample(0.5).acceleration, -1.0);
/// // Moving at 2 units/s with the target 1 unit ahead: overshoot and come back.
/// let back = OnlineTrapezoid::new(State { position: 0.0, velocity: 2.0, acceleration: 0.0 }, 1.0, limits)?;
/// assert!((back.duration() - 4.0).abs() < 1e-12);
/// assert!(back.reverses());
/// assert_eq!(back.sample(back.duration()), State::rest(1.0));
/// # Ok::<(), parasils_traj::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnlineTrapezoid<T> {
    pub(super) start: T,
    pub(super) v0: T,
    pub(super) target: T,
    /// Acceleration of the first phase, units/s^2 (signed).
    pub(super) a1: T,
    pub(super) t1: T,
    /// Position at the end of the first phase.
    pub(super) p1: T,
    /// Cruise velocity, units/s (signed).
    pub(super) vc: T,
    /// `t1 + t2`: the start of the last phase.
    pub(super) t12: T,
    /// Acceleration of the last phase, units/s^2 (signed).
    pub(super) a3: T,
    pub(super) duration: T,
}

impl<T: Real> OnlineTrapezoid<T> {
    /// The minimum-time profile from `start` (its position and velocity; its
    /// acceleration is not used) to rest at `target` under `limits`.
    ///
    /// # Errors
    /// [`Error::InvalidLimit`], [`Error::NonFinitePosition`] (start or goal),
    /// [`Error::NonFiniteVelocity`], [`Error::DistanceOverflow`] or
    /// [`Error::OutOfRange`], with axis `0`.
    pub fn new(start: State<T>, target: T, limits: Limits<T>) -> Result<Self, Error> {
        Self::new_axis(0, start, target, limits)
    }

    /// The profile from `start` to rest at `target` that lasts `duration`
    /// (s) exactly, keeping `a_max` and lowering the cruise velocity (the
    /// single-axis form of time synchronisation; see the [module docs](super)).
    /// A `duration` below the minimum time by no more than 8 float epsilons
    /// (relative) gives the minimum-time profile.
    ///
    /// ```
    /// use parasils_traj::{Limits, OnlineTrapezoid, State};
    /// let start = State { position: 0.0_f64, velocity: 1.0, acceleration: 0.0 };
    /// let p = OnlineTrapezoid::with_duration(start, 4.0, Limits::new(2.0, 1.0), 6.0)?;
    /// assert_eq!(p.duration(), 6.0);
    /// assert!(p.cruise_velocity() < 2.0);
    /// # Ok::<(), parasils_traj::Error>(())
    /// ```
    ///
    /// # Errors
    /// As [`OnlineTrapezoid::new`], and [`Error::InvalidDuration`] when
    /// `duration` is not finite or shorter than the minimum time.
    pub fn with_duration(
        start: State<T>,
        target: T,
        limits: Limits<T>,
        duration: T,
    ) -> Result<Self, Error> {
        let own = Self::new_axis(0, start, target, limits)?;
        own.stretched(0, limits, duration)
    }

    /// The controlled stop of one axis: from `start` to rest as fast as
    /// `a_max` allows, wherever that is (the target is the stopping point
    /// `p0 + v0 |v0| / (2 a_max)`). `v_max` is not used.
    ///
    /// ```
    /// use parasils_traj::{Limits, OnlineTrapezoid, State};
    /// let start = State { position: 1.0_f64, velocity: -2.0, acceleration: 0.0 };
    /// let p = OnlineTrapezoid::stop(start, Limits::new(2.0, 4.0))?;
    /// assert_eq!(p.duration(), 0.5);
    /// assert_eq!(p.target(), 0.5);
    /// # Ok::<(), parasils_traj::Error>(())
    /// ```
    ///
    /// # Errors
    /// [`Error::InvalidLimit`], [`Error::NonFinitePosition`],
    /// [`Error::NonFiniteVelocity`] or [`Error::OutOfRange`], with axis `0`.
    pub fn stop(start: State<T>, limits: Limits<T>) -> Result<Self, Error> {
        limits.check(0)?;
        check_start(0, start)?;
        let t = start.velocity.abs() / limits.a_max;
        Self::stopping(0, start, limits.a_max, t)
    }

    /// [`OnlineTrapezoid::new`] reporting `axis` in errors.
    pub(super) fn new_axis(
        axis: usize,
        start: State<T>,
        target: T,
        limits: Limits<T>,
    ) -> Result<Self, Error> {
        let d = check_axis(axis, start, target, limits)?;
        let n = Problem::new(start.position, start.velocity, target, limits)
            .ok_or_else(|| out_of_range(axis, d))?;
        let plan = Normalised::min_time(n);
        Self::from_phases(axis, start, target, phases(plan, limits, n.tau), None)
    }

    /// This (minimum-time) profile stretched to `duration` under `limits`.
    pub(super) fn stretched(
        self,
        axis: usize,
        limits: Limits<T>,
        duration: T,
    ) -> Result<Self, Error> {
        check_duration(axis, self.duration, duration)?;
        if duration <= self.duration {
            return Ok(self);
        }
        let d = self.target - self.start;
        let n = Problem::new(self.start, self.v0, self.target, limits)
            .ok_or_else(|| out_of_range(axis, d.abs()))?;
        let plan = Normalised::with_duration(n, duration / n.tau);
        let start = State {
            position: self.start,
            velocity: self.v0,
            acceleration: T::zero(),
        };
        Self::from_phases(
            axis,
            start,
            self.target,
            phases(plan, limits, n.tau),
            Some(duration),
        )
    }

    /// Uniform deceleration from `start` to rest in `t` (s), at most `a_max`.
    pub(super) fn stopping(axis: usize, start: State<T>, a_max: T, t: T) -> Result<Self, Error> {
        let (p0, v0) = (start.position, start.velocity);
        let range = || out_of_range(axis, (v0 * t).abs());
        if !t.finite() {
            return Err(range());
        }
        if v0 == T::zero() {
            return Ok(Self::at_rest(p0, v0, T::zero()));
        }
        // A moving axis whose braking time underflows (a speed far below
        // a_max times the smallest time the float type holds): no profile of
        // this type ends at rest.
        if !(t > T::zero()) {
            return Err(range());
        }
        let target = p0 + T::lit(0.5) * v0 * t;
        if !target.finite() {
            return Err(range());
        }
        // |v0| / t <= a_max as t >= |v0| / a_max, up to rounding.
        let a1 = (-(v0 / t)).max(-a_max).min(a_max);
        let p = [a1, t, T::zero(), T::zero(), T::zero(), T::zero()];
        Self::from_phases(axis, start, target, p, None)
    }

    /// An axis at `p0` with velocity `v0` (only for `t <= 0`) and still for `duration`.
    pub(super) fn at_rest(p0: T, v0: T, duration: T) -> Self {
        Self {
            start: p0,
            v0,
            target: p0,
            a1: T::zero(),
            t1: T::zero(),
            p1: p0,
            vc: T::zero(),
            t12: duration,
            a3: T::zero(),
            duration,
        }
    }

    /// The profile from its phases `[a1, t1, v_c, t2, a3, t3]`; `duration`
    /// overrides `t1 + t2 + t3` (it then sets the cruise time).
    pub(super) fn from_phases(
        axis: usize,
        start: State<T>,
        target: T,
        [a1, t1, vc, t2, a3, t3]: [T; 6],
        duration: Option<T>,
    ) -> Result<Self, Error> {
        let (p0, v0) = (start.position, start.velocity);
        let (t12, duration) = match duration {
            Some(total) => (t1.max(total - t3).min(total), total),
            None => (t1 + t2, t1 + t2 + t3),
        };
        // With no first phase the cruise starts from v0 itself.
        let vc = if t1 > T::zero() { vc } else { v0 };
        let p1 = p0 + t1 * (v0 + T::lit(0.5) * a1 * t1);
        let reach = p1 + vc * (t12 - t1);
        // Where a first phase that brakes through rest turns back: the
        // farthest position of the whole plan, which `p1` (back near the
        // start) does not show. It overflowed from f64::MAX at 1e154/s.
        let turn = if v0 * a1 < T::zero() {
            p0 + T::lit(0.5) * v0 * (-v0 / a1).min(t1)
        } else {
            p0
        };
        let finite = [
            a1,
            t1,
            p1,
            vc,
            t12,
            a3,
            duration,
            reach,
            turn,
            v0 * t1,
            vc * t3,
        ]
        .iter()
        .all(|x| x.finite());
        if !finite {
            return Err(out_of_range(axis, (target - p0).abs()));
        }
        // Phase times that all underflow to 0 (limits so large that the
        // motion takes less than the smallest time the float type holds)
        // leave an axis that is not already resting on its target with no
        // motion to get there.
        if !(duration > T::zero()) && (p0 != target || v0 != T::zero()) {
            return Err(out_of_range(axis, (target - p0).abs()));
        }
        Ok(Self {
            start: p0,
            v0,
            target,
            a1,
            t1,
            p1,
            vc,
            t12,
            a3,
            duration,
        })
    }

    /// Start position, in position units.
    #[must_use]
    pub fn start(&self) -> T {
        self.start
    }

    /// Start velocity, in units/s.
    #[must_use]
    pub fn start_velocity(&self) -> T {
        self.v0
    }

    /// The target, where the axis rests at the end (position units).
    #[must_use]
    pub fn target(&self) -> T {
        self.target
    }

    /// Duration of the motion, in s.
    #[must_use]
    pub fn duration(&self) -> T {
        self.duration
    }

    /// Duration of the first phase (from `v0` to the cruise velocity), in s.
    #[must_use]
    pub fn t_first(&self) -> T {
        self.t1
    }

    /// Duration of the cruise, in s.
    #[must_use]
    pub fn t_cruise(&self) -> T {
        self.t12 - self.t1
    }

    /// Duration of the last phase (from the cruise velocity to rest), in s.
    #[must_use]
    pub fn t_last(&self) -> T {
        self.duration - self.t12
    }

    /// The two switch instants, `t_first` and `t_first + t_cruise` (s).
    #[must_use]
    pub fn switches(&self) -> [T; 2] {
        [self.t1, self.t12]
    }

    /// Cruise velocity, in units/s (signed; `|v_c| <= v_max`).
    #[must_use]
    pub fn cruise_velocity(&self) -> T {
        self.vc
    }

    /// Acceleration of the first phase, in units/s^2 (signed).
    #[must_use]
    pub fn first_acceleration(&self) -> T {
        self.a1
    }

    /// Acceleration of the last phase, in units/s^2 (signed).
    #[must_use]
    pub fn last_acceleration(&self) -> T {
        if self.t12 < self.duration {
            self.a3
        } else {
            T::zero()
        }
    }

    /// Largest `|velocity|` over the motion, in units/s: `max(|v0|, |v_c|)`.
    #[must_use]
    pub fn peak_velocity(&self) -> T {
        self.v0.abs().max(self.vc.abs())
    }

    /// Largest `|acceleration|` over the motion, in units/s^2.
    #[must_use]
    pub fn peak_acceleration(&self) -> T {
        let first = if self.t1 > T::zero() {
            self.a1.abs()
        } else {
            T::zero()
        };
        first.max(self.last_acceleration().abs())
    }

    /// True when the velocity changes sign during the motion: the axis moves
    /// away from the target at first, or overshoots it and comes back.
    #[must_use]
    pub fn reverses(&self) -> bool {
        self.v0 * self.vc < T::zero()
    }

    /// The state at `t` (s). See the [module docs](super) for the conventions.
    #[must_use]
    pub fn sample(&self, t: T) -> State<T> {
        let t = match instant(t, self.duration) {
            Instant::Start => {
                return State {
                    position: self.start,
                    velocity: self.v0,
                    acceleration: T::zero(),
                };
            }
            Instant::End => return State::rest(self.target),
            Instant::Inside(t) => t,
        };
        let half = T::lit(0.5);
        if t < self.t1 {
            let (lo, hi) = (self.v0.min(self.vc), self.v0.max(self.vc));
            State {
                position: self.start + t * (self.v0 + half * self.a1 * t),
                velocity: (self.v0 + self.a1 * t).max(lo).min(hi),
                acceleration: self.a1,
            }
        } else if t < self.t12 {
            State {
                position: self.p1 + self.vc * (t - self.t1),
                velocity: self.vc,
                acceleration: T::zero(),
            }
        } else {
            // The last phase, written from the target so that it is reached exactly.
            let tau = self.duration - t;
            let speed = self.vc.abs();
            State {
                position: self.target + ramp(self.a3, tau),
                velocity: (-self.a3 * tau).max(-speed).min(speed),
                acceleration: self.a3,
            }
        }
    }
}

impl<T: Real> Motion<T> for OnlineTrapezoid<T> {
    type Output = State<T>;
    fn duration(&self) -> T {
        self.duration
    }
    fn sample(&self, t: T) -> State<T> {
        OnlineTrapezoid::sample(self, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_past_the_largest_float_is_out_of_range() {
        // The fuzzer's case (f64): from f64::MAX at 1e154/s away from the
        // target, braking at 15163 turns back 3e303 further: past the
        // largest float. The plan used to sample an infinite position.
        let start = State {
            position: f64::MAX,
            velocity: 1e154,
            acceleration: 1e154,
        };
        let r = OnlineTrapezoid::new(start, 315.0, Limits::new(1e154, 15163.0));
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
        // Towards the target it fits.
        let start = State {
            velocity: -1e154,
            ..start
        };
        assert!(OnlineTrapezoid::new(start, 315.0, Limits::new(1e154, 15163.0)).is_ok());
    }
}
