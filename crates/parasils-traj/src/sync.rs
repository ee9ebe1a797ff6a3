//! Several axes moving together: `phase`, `time` and `none` synchronisation
//! (`docs/model.md`, *Trajectories*).
//!
//! - [`Synchronization::Phase`] (default): a straight line in joint space.
//!   All axes share one normalised profile and its phase times; axis `i` is
//!   the copy scaled by `d_i / D` (`D` the longest distance), so that
//!   `(p_i(t) - start_i) / (goal_i - start_i)` is the same for every moving
//!   axis at every `t`. The normalised limits are `min_i v_max_i D / d_i` and
//!   `min_i a_max_i D / d_i` (and `j_max` alike for [`DoubleS`]): the fastest
//!   straight line that keeps every axis within its own limits. When all axes
//!   share the same limits (the paper's case), this is exactly the model's wording:
//!   the axis with the longest minimum time sets the timing and the others are
//!   scaled copies of its profile. When the axes have different limits, the
//!   straight line can take longer than every single axis alone (one axis
//!   binds the velocity, another the acceleration).
//! - [`Synchronization::Time`]: every axis lasts the longest minimum time
//!   `T`; each other axis keeps its acceleration (and jerk) limit and lowers
//!   its cruise velocity so as to arrive at `T`, in closed form for the
//!   trapezoid ([`Trapezoid::with_duration`]).
//! - [`Synchronization::None`]: each axis on its own minimum-time profile;
//!   the group's duration is the longest.
//!
//! Zero-distance axes stay still (zero velocity and acceleration) and never
//! divide anything; axes may move in opposite directions.

use crate::axis::{Axis, OneAxis, Shape};
use crate::double_s::{DoubleS, JerkLimits};
use crate::error::{Error, out_of_range};
use crate::profile::{Motion, Profile, State};
use crate::real::Real;
use crate::trapezoid::{Limits, Trapezoid};

/// How the axes of a [`Multi`] are timed together (`docs/model.md`,
/// *Trajectories*).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Synchronization {
    /// Straight line in joint space; the slowest axis sets the timing (default).
    #[default]
    Phase,
    /// Same duration for all; the others lower their cruise velocity.
    Time,
    /// Each axis on its own minimum-time profile.
    None,
}

/// `N` axes moving together from `start` to `goal`, synchronised.
///
/// `P` is the per-axis profile: [`Trapezoid`] (built by [`Multi::new`]) or
/// [`DoubleS`] (built by [`Multi::double_s`]). Each axis keeps its own units.
/// Time is in s from the common start; the group's duration is the longest
/// axis duration, and each axis rests at its goal after its own end.
///
/// ```
/// use parasils_traj::{Limits, Multi, Synchronization};
/// // Opposite directions and a still axis, phase-synchronised.
/// let m = Multi::new([0.0_f64, 0.0, 2.0], [4.0, -2.0, 2.0], [Limits::new(1.0, 1.0); 3], Synchronization::Phase)?;
/// assert_eq!(m.lead(), Some(0));
/// let [a, b, c] = m.sample(m.duration() / 3.0);
/// assert!((a.position + 2.0 * b.position).abs() < 1e-12); // on the straight line
/// assert_eq!(c.position, 2.0);
/// # Ok::<(), parasils_traj::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Multi<T, const N: usize, P = Trapezoid<T>> {
    axes: [P; N],
    duration: T,
    sync: Synchronization,
    lead: Option<usize>,
}

/// Index of the first longest duration among moving axes, and that duration.
fn longest<T: Real>(durations: impl Iterator<Item = (T, bool)>) -> (Option<usize>, T) {
    let mut best = (None, T::zero());
    for (i, (d, moving)) in durations.enumerate() {
        if moving && (best.0.is_none() || d > best.1) {
            best = (Some(i), d);
        }
    }
    best
}

/// The straight line's distance `D = max_i d_i` and limits, each
/// `min_i limit_i D / d_i` over the moving axes.
fn line_limits<T: Real, S: Shape<T>>(axes: &[Axis<T, S>], limits: &[S::Limits]) -> (T, S::Limits) {
    let big = axes.iter().fold(T::zero(), |m, p| m.max(p.distance()));
    let mut line = S::unbounded();
    for (p, l) in axes.iter().zip(limits) {
        if p.distance() > T::zero() {
            let ratio = big / p.distance(); // >= 1, may be +inf but never NaN
            S::tighten(&mut line, l, ratio);
        }
    }
    (big, line)
}

/// The one construction of a [`Multi`], whatever its profile type: each
/// axis on its own, then synchronised as `sync` asks.
fn build<T: Real, const N: usize, P: OneAxis<T>>(
    start: [T; N],
    goal: [T; N],
    limits: [<P::Shape as Shape<T>>::Limits; N],
    sync: Synchronization,
) -> Result<Multi<T, N, P>, Error> {
    let mut own = [Axis::<T, P::Shape>::still(T::zero(), T::zero(), T::zero()); N];
    for (i, (((p, s), g), l)) in own.iter_mut().zip(start).zip(goal).zip(limits).enumerate() {
        *p = Axis::new(i, s, g, l)?;
    }
    let (lead, t_max) = longest(own.iter().map(|p| (p.shape().duration(), p.moves())));
    let mut axes = own;
    if let Some(lead_axis) = lead {
        match sync {
            Synchronization::None => {}
            Synchronization::Phase => {
                let (big, line) = line_limits(&own, &limits);
                let shape =
                    P::Shape::min_time(big, line).ok_or_else(|| out_of_range(lead_axis, big))?;
                for (i, ax) in axes.iter_mut().enumerate() {
                    *ax = ax.share(i, &shape, ax.distance() / big)?;
                }
            }
            Synchronization::Time => {
                for (i, (ax, l)) in axes.iter_mut().zip(limits).enumerate() {
                    *ax = ax.stretched(i, l, t_max)?;
                }
            }
        }
    }
    let duration = axes
        .iter()
        .fold(T::zero(), |m, p| m.max(p.shape().duration()));
    Ok(Multi {
        axes: axes.map(P::from_axis),
        duration,
        sync,
        lead,
    })
}

impl<T: Real, const N: usize> Multi<T, N, Trapezoid<T>> {
    /// `N` trapezoidal axes from `start` to `goal` (position units per axis)
    /// under per-axis `limits`, synchronised by `sync`.
    ///
    /// # Errors
    /// The first invalid axis's [`Error`] (`InvalidLimit`, `NonFinitePosition`,
    /// `DistanceOverflow`, `OutOfRange`), with its index.
    pub fn new(
        start: [T; N],
        goal: [T; N],
        limits: [Limits<T>; N],
        sync: Synchronization,
    ) -> Result<Self, Error> {
        build(start, goal, limits, sync)
    }
}

impl<T: Real, const N: usize> Multi<T, N, DoubleS<T>> {
    /// `N` jerk-limited axes, as [`Multi::new`]. All three synchronisations
    /// are supported: `Phase` scales one normalised double-S (velocity,
    /// acceleration and jerk by `d_i / D`); `Time` keeps each axis's `a_max`
    /// and `j_max` and lowers its cruise velocity (closed form when `a_max` is
    /// reached, bisection on the jerk time otherwise).
    ///
    /// # Errors
    /// As [`Multi::new`].
    pub fn double_s(
        start: [T; N],
        goal: [T; N],
        limits: [JerkLimits<T>; N],
        sync: Synchronization,
    ) -> Result<Self, Error> {
        build(start, goal, limits, sync)
    }
}

impl<T: Real, const N: usize, P: Profile<T>> Multi<T, N, P> {
    /// Duration of the group, in s: the longest axis duration.
    #[must_use]
    pub fn duration(&self) -> T {
        self.duration
    }

    /// The per-axis profiles, in the order given.
    #[must_use]
    pub fn axes(&self) -> &[P; N] {
        &self.axes
    }

    /// The profile of axis `i`, or `None` when `i >= N`.
    #[must_use]
    pub fn axis(&self, i: usize) -> Option<&P> {
        self.axes.get(i)
    }

    /// The synchronisation used.
    #[must_use]
    pub fn synchronization(&self) -> Synchronization {
        self.sync
    }

    /// The axis with the longest minimum time (the first one on a tie), or
    /// `None` when no axis moves.
    #[must_use]
    pub fn lead(&self) -> Option<usize> {
        self.lead
    }

    /// The state of every axis at `t` (s); each axis follows its own profile's
    /// conventions (start before 0, goal after its end, right-continuous
    /// acceleration, 0 outside the motion).
    #[must_use]
    pub fn sample(&self, t: T) -> [State<T>; N] {
        self.axes.each_ref().map(|p| p.sample(t))
    }
}

impl<T: Real, const N: usize, P: Profile<T>> Motion<T> for Multi<T, N, P> {
    type Output = [State<T>; N];
    fn duration(&self) -> T {
        self.duration
    }
    fn sample(&self, t: T) -> [State<T>; N] {
        Multi::sample(self, t)
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp, reason = "exactness is what these tests check")]
mod tests {
    use super::*;

    #[test]
    fn all_still() -> Result<(), Error> {
        let m = Multi::new(
            [1.0_f64, 2.0],
            [1.0, 2.0],
            [Limits::new(1.0, 1.0); 2],
            Synchronization::Phase,
        )?;
        assert_eq!(m.duration(), 0.0);
        assert_eq!(m.lead(), None);
        assert_eq!(m.sample(0.5), [State::rest(1.0), State::rest(2.0)]);
        Ok(())
    }

    #[test]
    fn a_share_too_small_for_normal_numbers_is_out_of_range() {
        // Axis 1 moves 1e-300 of axis 0's distance: its scaled velocity and
        // acceleration (about 1e-300) are still normal numbers in f64; at
        // 1e-312 of it they are subnormal, and refused.
        let ok = Multi::new(
            [0.0_f64, 0.0],
            [100.0, 1e-298],
            [Limits::new(1.0, 1.0); 2],
            Synchronization::Phase,
        );
        assert!(ok.is_ok(), "{ok:?}");
        let r = Multi::new(
            [0.0_f64, 0.0],
            [100.0, 1e-310],
            [Limits::new(1.0, 1.0); 2],
            Synchronization::Phase,
        );
        assert!(matches!(r, Err(Error::OutOfRange { axis: 1, .. })), "{r:?}");
        let r = Multi::double_s(
            [0.0_f64, 0.0],
            [100.0, 1e-310],
            [JerkLimits::new(1.0, 1.0, 1.0); 2],
            Synchronization::Phase,
        );
        assert!(matches!(r, Err(Error::OutOfRange { axis: 1, .. })), "{r:?}");
        // No synchronisation keeps the axis's own shape: no scaling.
        let r = Multi::new(
            [0.0_f64, 0.0],
            [100.0, 1e-310],
            [Limits::new(1.0, 1.0); 2],
            Synchronization::None,
        );
        assert!(r.is_ok(), "{r:?}");
        // Time synchronisation lowers its cruise velocity to about 1e-311,
        // subnormal too: refused alike.
        let r = Multi::new(
            [0.0_f64, 0.0],
            [100.0, 1e-310],
            [Limits::new(1.0, 1.0); 2],
            Synchronization::Time,
        );
        assert!(matches!(r, Err(Error::OutOfRange { axis: 1, .. })), "{r:?}");
    }

    #[test]
    fn errors_carry_the_axis() {
        let r = Multi::new(
            [0.0_f64, 0.0],
            [1.0, 1.0],
            [Limits::new(1.0, 1.0), Limits::new(1.0, 0.0)],
            Synchronization::Phase,
        );
        assert!(matches!(r, Err(Error::InvalidLimit { axis: 1, .. })));
    }

    #[test]
    fn phase_with_different_limits_respects_each_axis() -> Result<(), Error> {
        // Axis 0 binds velocity, axis 1 acceleration: the line is slower than both.
        let m = Multi::new(
            [0.0_f64, 0.0],
            [1.0, 1.0],
            [Limits::new(0.5, 100.0), Limits::new(100.0, 0.5)],
            Synchronization::Phase,
        )?;
        let [a, b] = m.axes();
        assert!(a.peak_velocity() <= 0.5 && b.peak_acceleration() <= 0.5);
        let t0 = Trapezoid::new(0.0_f64, 1.0, Limits::new(0.5, 100.0))?.duration();
        let t1 = Trapezoid::new(0.0_f64, 1.0, Limits::new(100.0, 0.5))?.duration();
        assert!(m.duration() > t0.max(t1));
        Ok(())
    }

    #[test]
    fn time_synchronising_an_axis_whose_time_scale_overflows_is_out_of_range() {
        // The fuzzer's case (f32): axis 1's a_max is subnormal; stretched to
        // axis 0's 4.9e22 s, its d / a_max overflows. It used to come back
        // with an acceleration time of 1.2e35 s in a plan of 4.9e22 s, at
        // 1854 times its distance from the start; now it is out of range
        // (its subnormal a_max alone refuses it).
        let r = Multi::new(
            [0.0_f32, 3.1568e-41],
            [8.137_419_4e23, 1.000_000_1],
            [
                Limits::new(16.498_047, 0.019_836_426),
                Limits::new(0.000_186_920_84, 1.560_925e-39),
            ],
            Synchronization::Time,
        );
        assert!(matches!(r, Err(Error::OutOfRange { axis: 1, .. })), "{r:?}");
    }

    #[test]
    fn time_synchronised_double_s_with_a_tiny_jerk_reaches_its_goal() -> Result<(), Error> {
        // The fuzzer's case (f64): axis 1 lasts 1.46e158 s; axis 0, 1e154
        // long with j_max = 1e-154, is stretched to it. `2 d / j_max`
        // overflowed in the bound of the bisection for the jerk time, which
        // then ran out of halvings far above the root: a cruise velocity
        // 1e4 times too high, the axis 4e156 past its goal of 1e154.
        let m = Multi::double_s(
            [-3.458_736_359_466_021_7e19_f64, 3.903_190_409_522_057e-33],
            [1e154, 14601.0],
            [
                JerkLimits::new(0.894_104_003_906_25, 0.000_610_351_562_5, 1e-154),
                JerkLimits::new(1e-154, 1e-154, 1e-154),
            ],
            Synchronization::Time,
        )?;
        let [a0, _] = m.axes();
        for k in 0..=32 {
            let t = m.duration() * f64::from(k) / 32.0;
            let p = a0.sample(t).position;
            assert!(
                (-3.5e19..=1e154 * (1.0 + 1e-12)).contains(&p),
                "{p:e} at {t:e}"
            );
        }
        Ok(())
    }

    #[test]
    fn a_subnormal_share_is_out_of_range_even_with_normal_scaled_limits() {
        // The fuzzer's case (f64): axis 0 moves 2.2e-16, axis 1 2.5e307 at
        // limits of 1e154, so axis 0's share is 9e-324, a subnormal number
        // 10 % off; its scaled limits (1e-169) are normal numbers, and it
        // ended 2.7 % past its goal. The share itself must be normal.
        let r = Multi::double_s(
            [2.220_446_049_250_313e-16_f64, -2.461_661_297_927_25e307],
            [1e-154, 1e-154],
            [
                JerkLimits::new(3.6875, 1e154, 1e154),
                JerkLimits::new(1e154, 1e154, 1e154),
            ],
            Synchronization::Phase,
        );
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
        let r = Multi::new(
            [2.220_446_049_250_313e-16_f64, -2.461_661_297_927_25e307],
            [1e-154, 1e-154],
            [Limits::new(3.6875, 1e154), Limits::new(1e154, 1e154)],
            Synchronization::Phase,
        );
        assert!(matches!(r, Err(Error::OutOfRange { axis: 0, .. })), "{r:?}");
    }

    #[test]
    fn time_synchronising_an_axis_at_subnormal_limits_is_out_of_range() {
        // The fuzzer's case (f32): both axes at v_max = a_max = 1.4e-45,
        // the smallest subnormal number. Axis 1, stretched to axis 0's
        // 8.4e6 s, needed a cruise velocity of 7.8e-46, which rounds to
        // 1.4e-45: it ended past its goal by 9 % of its distance.
        let r = Multi::new(
            [1.175_494_4e-38_f32, 6.553_657e-39],
            [0.0, 1e-45],
            [Limits::new(1e-45, 1e-45); 2],
            Synchronization::Time,
        );
        assert!(matches!(r, Err(Error::OutOfRange { .. })), "{r:?}");
    }
}
