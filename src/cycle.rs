//! Motions on the control cycle: every planned motion lasts a whole number
//! of periods, so that it starts and ends on a sample.
//!
//! A timing law planned from rest lasts `T` s, rarely a multiple of the
//! control period `dt = 1 / rate`. [`Stretch`] places it on the cycle: `N`
//! is the smallest whole number of periods with `N dt >= T` (the rule of
//! [`parasils_traj::sampler`]: `T * rate` within 64 float epsilons of an
//! integer counts as that integer), the motion lasts `T' = N dt`, and the
//! law is read at the scaled time
//!
//! ```text
//! s(t) = law(t T / T'),  velocity * (T / T'),  acceleration * (T / T')^2.
//! ```
//!
//! This is a time scaling of the same law, not a re-solve: the path is the
//! same point for point, its speed is multiplied by `r = T / T' <= 1` and its
//! acceleration by `r^2 <= 1` (`d/dt law(r t) = r law'(r t)`). Every
//! velocity and acceleration of the robot is linear in the path's velocity
//! and acceleration once the pose is fixed (the Euler accelerations enter
//! linearly, the rates squared), so each actuator's velocity is scaled by
//! `r` and its acceleration by `r^2` at the same pose: every symmetric limit
//! that held still holds, and the stretch costs at most one period. A
//! re-solve for `T'` would be as valid but law-specific; the scaling serves
//! every law at once (trapezoid, time-optimal, any other) and keeps the
//! planned law's shape, which the summary reports beside the stretched
//! duration.
//!
//! A law that starts moving (an online profile from a motion cut short)
//! cannot be scaled without changing its initial velocity; [`Stretch::padded`]
//! keeps it as it is and holds its end until the next whole period
//! (`r = 1`, at rest on its target from `T` to `T'`).
//!
//! [`OnCycle`] is a motion so placed, itself a
//! [`Motion`]: sample `j` (at `t = j dt`) is the law at
//! `j dt r`, and sample `N` is the law's end state itself (its target, at
//! rest), never a float sum that could fall short of it.
//!
//! ```
//! use parasils::Reorientation;
//! use parasils::cycle::OnCycle;
//! use parasils::traj::{Limits, Synchronization};
//!
//! // psi by 20 deg at 10 deg/s, 5 deg/s^2: 20/10 + 10/5 = 4 s, a whole
//! // number of periods.
//! let deg = core::f64::consts::PI / 180.0;
//! let start = parasils::kin::Pose::paper_start();
//! let turn = Reorientation::new(
//!     start,
//!     [start.psi + 20.0 * deg, start.theta + 7.0 * deg],
//!     [Limits::new(10.0 * deg, 5.0 * deg); 2],
//!     Synchronization::Phase,
//! )?;
//! let on_cycle = OnCycle::new(turn, 1000.0)?;
//! assert_eq!(on_cycle.stretch().periods(), 4000);
//! assert_eq!(on_cycle.stretch().ratio(), 1.0);
//! // 12 deg at 7 deg/s: 12/7 + 7/5 = 3.1142857... s, stretched to 3.115 s.
//! let turn = Reorientation::new(
//!     start,
//!     [start.psi + 12.0 * deg, start.theta],
//!     [Limits::new(7.0 * deg, 5.0 * deg); 2],
//!     Synchronization::Phase,
//! )?;
//! let on_cycle = OnCycle::new(turn, 1000.0)?;
//! assert_eq!(on_cycle.stretch().periods(), 3115);
//! let end = on_cycle.at_sample(3115);
//! assert_eq!(end.pose.psi, start.psi + 12.0 * deg);
//! assert_eq!(end.velocity.psi, 0.0);
//! # Ok::<(), parasils::traj::Error>(())
//! ```

use crate::Real;
use crate::geometry::{MotionSample, Moving};
use crate::kin::nalgebra::ComplexField;
use crate::kin::{ModuleCommand, PlatformState, PoseRate};
use crate::traj::{Error, Motion, State};

/// What a time scaling by `r` does to a motion's output: velocities times
/// `r`, accelerations times `r^2`, positions unchanged.
pub trait TimeScaled<T> {
    /// The same instant of the motion run `ratio` times as fast.
    #[must_use]
    fn time_scaled(self, ratio: T) -> Self;
}

impl<T: Real> TimeScaled<T> for State<T> {
    fn time_scaled(self, r: T) -> Self {
        State {
            position: self.position,
            velocity: self.velocity * r,
            acceleration: self.acceleration * (r * r),
        }
    }
}

impl<T: Real, S: TimeScaled<T>, const N: usize> TimeScaled<T> for [S; N] {
    fn time_scaled(self, r: T) -> Self {
        self.map(|s| s.time_scaled(r))
    }
}

fn scaled_rate<T: Real>(v: PoseRate<T>, r: T) -> PoseRate<T> {
    PoseRate::new(v.x * r, v.y * r, v.z * r, v.psi * r, v.theta * r, v.phi * r)
}

impl<T: Real> TimeScaled<T> for PlatformState<T> {
    fn time_scaled(self, r: T) -> Self {
        PlatformState {
            pose: self.pose,
            velocity: scaled_rate(self.velocity, r),
            acceleration: scaled_rate(self.acceleration, r * r),
        }
    }
}

impl<T: Real> TimeScaled<T> for ModuleCommand<T> {
    fn time_scaled(self, r: T) -> Self {
        match self {
            ModuleCommand::Tip(mut tip) => {
                tip.velocity *= r;
                tip.acceleration *= r * r;
                ModuleCommand::Tip(tip)
            }
            ModuleCommand::Joints(mut j) => {
                let r2 = r * r;
                j.q_dot.qs1 *= r;
                j.q_dot.qs2 *= r;
                j.q_dot.qs3 *= r;
                j.q_ddot.qs1 *= r2;
                j.q_ddot.qs2 *= r2;
                j.q_ddot.qs3 *= r2;
                ModuleCommand::Joints(j)
            }
        }
    }
}

impl<T: Real> TimeScaled<T> for MotionSample<T> {
    fn time_scaled(self, r: T) -> Self {
        MotionSample {
            platform: self.platform.time_scaled(r),
            left: self.left.time_scaled(r),
            right: self.right.time_scaled(r),
            endoscope: self.endoscope.time_scaled(r),
        }
    }
}

impl<T: Real> TimeScaled<T> for Moving<T> {
    fn time_scaled(self, r: T) -> Self {
        match self {
            Moving::Pose(s) => Moving::Pose(s.time_scaled(r)),
            Moving::Depth(port, s) => Moving::Depth(port, s.time_scaled(r)),
            Moving::Tips(s) => Moving::Tips(s.time_scaled(r)),
            Moving::Angles(s) => Moving::Angles(s.time_scaled(r)),
        }
    }
}

/// A law of `planned` s placed on a cycle of `rate` Hz: `periods` whole
/// periods, read at `t * ratio` (see the module's documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch<T> {
    planned: T,
    rate: T,
    periods: usize,
    ratio: T,
}

impl<T: Real> Stretch<T> {
    /// The law of `planned_s` s stretched to the next whole number of
    /// periods at `rate_hz`, by a time scaling (`ratio = T / T'`; exactly 1
    /// when `T` already is a whole number of periods).
    ///
    /// # Errors
    /// [`Error::InvalidRate`] for a rate that is not positive and finite,
    /// [`Error::TooManySamples`] for a duration that is negative, not
    /// finite, or too long to count in periods.
    pub fn new(planned_s: T, rate_hz: T) -> Result<Self, Error> {
        let (periods, x) = Self::count(planned_s, rate_hz)?;
        let n = <T as crate::traj::Real>::from_index(periods);
        let ratio = if periods == 0 || !(n > x) {
            T::one()
        } else {
            x / n
        };
        Ok(Self {
            planned: planned_s,
            rate: rate_hz,
            periods,
            ratio,
        })
    }

    /// The law of `planned_s` s held at its end until the next whole period
    /// (`ratio = 1`): for a law that starts moving, which a time scaling
    /// would change.
    ///
    /// # Errors
    /// As [`Stretch::new`].
    pub fn padded(planned_s: T, rate_hz: T) -> Result<Self, Error> {
        let (periods, _) = Self::count(planned_s, rate_hz)?;
        Ok(Self {
            planned: planned_s,
            rate: rate_hz,
            periods,
            ratio: T::one(),
        })
    }

    /// `N`, the smallest whole number of periods not shorter than `planned`
    /// (the sampler's rule), and `planned * rate`.
    fn count(planned: T, rate: T) -> Result<(usize, T), Error> {
        if !(rate.finite() && rate > T::zero()) {
            return Err(Error::InvalidRate {
                value: rate.to_f64(),
            });
        }
        let too_many = Error::TooManySamples {
            duration: planned.to_f64(),
            rate: rate.to_f64(),
        };
        let x = planned * rate;
        if !(x.finite() && x >= T::zero()) {
            return Err(too_many);
        }
        let floor = ComplexField::floor(x);
        let slack = x * <T as crate::kin::Real>::EPSILON * <T as crate::kin::Real>::lit(64.0);
        let n = if x - floor <= slack {
            floor
        } else {
            floor + T::one()
        };
        let n = n.to_f64();
        // Whole numbers up to 2^53 convert exactly; beyond, nothing is sampled.
        if n > 9.007_199_254_740_992e15 {
            return Err(too_many);
        }
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a whole number in [0, 2^53]"
        )]
        let n = n as usize;
        Ok((n, x))
    }

    /// The law's own duration `T`, s.
    pub fn planned(&self) -> T {
        self.planned
    }

    /// The stretched duration `T' = N / rate`, s.
    pub fn duration(&self) -> T {
        <T as crate::traj::Real>::from_index(self.periods) / self.rate
    }

    /// `N`, the whole number of periods the motion lasts.
    pub fn periods(&self) -> usize {
        self.periods
    }

    /// `r = T / T'` (1 when not scaled).
    pub fn ratio(&self) -> T {
        self.ratio
    }

    /// The rate, Hz.
    pub fn rate(&self) -> T {
        self.rate
    }

    /// The law's time at sample `j` (`t = j / rate`): `t r`, and exactly
    /// `T` from sample `N` on.
    pub fn law_time(&self, j: usize) -> T {
        if j >= self.periods {
            self.planned
        } else {
            <T as crate::traj::Real>::from_index(j) / self.rate * self.ratio
        }
    }
}

/// A motion on the control cycle: `motion` read through a [`Stretch`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnCycle<M, T> {
    motion: M,
    stretch: Stretch<T>,
}

impl<T: Real, M: Motion<T>> OnCycle<M, T>
where
    M::Output: TimeScaled<T>,
{
    /// `motion` (planned from rest) stretched to the next whole number of
    /// periods at `rate_hz` ([`Stretch::new`]).
    ///
    /// # Errors
    /// As [`Stretch::new`].
    pub fn new(motion: M, rate_hz: T) -> Result<Self, Error> {
        let stretch = Stretch::new(motion.duration(), rate_hz)?;
        Ok(Self { motion, stretch })
    }

    /// `motion` (starting moving) held at its end until the next whole
    /// period ([`Stretch::padded`]).
    ///
    /// # Errors
    /// As [`Stretch::new`].
    pub fn padded(motion: M, rate_hz: T) -> Result<Self, Error> {
        let stretch = Stretch::padded(motion.duration(), rate_hz)?;
        Ok(Self { motion, stretch })
    }

    /// The motion as planned.
    pub fn motion(&self) -> &M {
        &self.motion
    }

    /// How it is placed on the cycle.
    pub fn stretch(&self) -> &Stretch<T> {
        &self.stretch
    }

    /// Sample `j`, at `t = j / rate`: the law at `t r`, scaled; from sample
    /// `N` on, the law's end state itself.
    pub fn at_sample(&self, j: usize) -> M::Output {
        let tau = self.stretch.law_time(j);
        if j >= self.stretch.periods {
            self.motion.sample(tau)
        } else {
            self.motion.sample(tau).time_scaled(self.stretch.ratio)
        }
    }
}

impl<T: Real, M: Motion<T>> Motion<T> for OnCycle<M, T>
where
    M::Output: TimeScaled<T>,
{
    type Output = M::Output;

    fn duration(&self) -> T {
        self.stretch.duration()
    }

    /// The motion at `t` (s): the law at `t r`, scaled, and its end state
    /// from `T'` on.
    fn sample(&self, t: T) -> M::Output {
        if t >= self.stretch.duration() {
            return self.motion.sample(self.stretch.planned);
        }
        let tau = t * self.stretch.ratio;
        self.motion.sample(tau).time_scaled(self.stretch.ratio)
    }
}

#[cfg(test)]
mod tests {
    use super::{Stretch, TimeScaled};
    use crate::traj::{Error, State};

    #[test]
    fn periods_follow_the_sampler_s_rule() {
        // 1.2345 s at 1 kHz: 1235 periods, r = 1.2345 / 1.235.
        let s = Stretch::new(1.2345_f64, 1000.0).expect("valid");
        assert_eq!(s.periods(), 1235);
        assert_eq!(s.duration(), 1.235);
        assert!((s.ratio() - 1.2345 / 1.235).abs() < 1e-15);
        // The law's time at the last sample is its duration itself.
        assert_eq!(s.law_time(1235), 1.2345);
        assert_eq!(s.law_time(0), 0.0);
        // 4.5 s: whole already, not scaled at all.
        let s = Stretch::new(4.5_f64, 1000.0).expect("valid");
        assert_eq!((s.periods(), s.ratio()), (4500, 1.0));
        // Within 64 epsilons above a whole number: that number, unscaled.
        let s = Stretch::new(3.0_f64 * (1.0 + 8.0 * f64::EPSILON), 1000.0).expect("valid");
        assert_eq!((s.periods(), s.ratio()), (3000, 1.0));
        // No time: one sample.
        let s = Stretch::new(0.0_f64, 1000.0).expect("valid");
        assert_eq!((s.periods(), s.ratio(), s.duration()), (0, 1.0, 0.0));
        // f32 as well: 0.0125 s at 1 kHz, 13 periods.
        let s = Stretch::new(0.0125_f32, 1000.0).expect("valid");
        assert_eq!(s.periods(), 13);
        assert!((s.ratio() - 12.5 / 13.0).abs() < 1e-6);
    }

    #[test]
    fn padded_keeps_the_law_and_rests_after_it() {
        let s = Stretch::padded(1.2345_f64, 1000.0).expect("valid");
        assert_eq!((s.periods(), s.ratio()), (1235, 1.0));
        assert_eq!(s.law_time(1234), 1.234);
        assert_eq!(s.law_time(1235), 1.2345);
    }

    #[test]
    fn invalid_rates_and_durations_are_errors() {
        for rate in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                Stretch::new(1.0, rate),
                Err(Error::InvalidRate { .. })
            ));
        }
        for t in [-1.0, f64::NAN, f64::INFINITY, 1e300] {
            assert!(matches!(
                Stretch::new(t, 1e10),
                Err(Error::TooManySamples { .. })
            ));
        }
    }

    #[test]
    fn a_time_scaling_scales_rates_by_r_and_accelerations_by_r_squared() {
        let s = State {
            position: 2.0_f64,
            velocity: 3.0,
            acceleration: -4.0,
        }
        .time_scaled(0.5);
        assert_eq!((s.position, s.velocity, s.acceleration), (2.0, 1.5, -1.0));
    }
}
