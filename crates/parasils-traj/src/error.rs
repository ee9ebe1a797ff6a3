//! Typed errors of the profile constructors and of the sampler.

use core::fmt;

use crate::real::Real;

/// Which limit of an axis an [`Error::InvalidLimit`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LimitKind {
    /// The velocity limit `v_max` (position units/s).
    Velocity,
    /// The acceleration limit `a_max` (position units/s^2).
    Acceleration,
    /// The jerk limit `j_max` (position units/s^3).
    Jerk,
}

impl fmt::Display for LimitKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Velocity => "v_max",
            Self::Acceleration => "a_max",
            Self::Jerk => "j_max",
        })
    }
}

/// Which end of a motion an [`Error::NonFinitePosition`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Endpoint {
    /// The start position.
    Start,
    /// The goal position.
    Goal,
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Start => "start",
            Self::Goal => "goal",
        })
    }
}

/// Why a profile or a sampler could not be built.
///
/// Every variant names the axis (its index in the arrays given to
/// [`Multi`](crate::Multi); `0` for a single-axis profile) and the offending
/// value, widened to `f64`.
///
/// # When this happens / how to handle it
/// - [`InvalidLimit`](Self::InvalidLimit), [`NonFinitePosition`](Self::NonFinitePosition):
///   bad input, typically a unit mix-up or an uninitialised value upstream.
///   Reject the command; do not retry with the same input.
/// - [`DistanceOverflow`](Self::DistanceOverflow), [`OutOfRange`](Self::OutOfRange):
///   the numbers are finite but the profile does not fit the float type (for
///   example a distance of `1e30` at `1e-30` units/s in `f32`). Check units.
/// - [`InvalidDuration`](Self::InvalidDuration): a duration was imposed that the
///   limits cannot meet; use at least the `minimum` reported.
/// - [`InvalidRate`](Self::InvalidRate), [`TooManySamples`](Self::TooManySamples):
///   the sampling rate is not usable; pick a positive rate whose sample count fits `usize`.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A limit is zero, negative, infinite or NaN.
    #[error("axis {axis}: {limit} = {value} is not a positive finite number")]
    InvalidLimit {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// Which limit.
        limit: LimitKind,
        /// The value given, in position units/s, /s^2 or /s^3.
        value: f64,
    },
    /// The start or the goal position is infinite or NaN.
    #[error("axis {axis}: the {endpoint} position {value} is not finite")]
    NonFinitePosition {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// Start or goal.
        endpoint: Endpoint,
        /// The value given, in position units.
        value: f64,
    },
    /// `goal - start` overflows the float type.
    #[error("axis {axis}: the distance from {start} to {goal} overflows the float type")]
    DistanceOverflow {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// The start position, in position units.
        start: f64,
        /// The goal position, in position units.
        goal: f64,
    },
    /// The limits are valid but the profile's duration, a phase time or a
    /// peak overflows or underflows the float type.
    #[error(
        "axis {axis}: the profile over distance {distance} does not fit the float type with these limits"
    )]
    OutOfRange {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// `|goal - start|`, in position units.
        distance: f64,
    },
    /// An imposed duration is shorter than the minimum time, or not finite.
    #[error(
        "axis {axis}: the duration {requested} s is not finite or below the minimum {minimum} s"
    )]
    InvalidDuration {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// The duration asked for, in s.
        requested: f64,
        /// The minimum time of the axis under its limits, in s.
        minimum: f64,
    },
    /// A sampling rate is zero, negative, infinite or NaN.
    #[error("sampling rate {value} Hz is not a positive finite number")]
    InvalidRate {
        /// The rate given, in Hz.
        value: f64,
    },
    /// `duration * rate` does not fit `usize`.
    #[error("sampling {duration} s at {rate} Hz needs more samples than usize can count")]
    TooManySamples {
        /// The motion's duration, in s.
        duration: f64,
        /// The rate given, in Hz.
        rate: f64,
    },
}

/// Checks one end position.
pub(crate) fn check_position<T: Real>(
    axis: usize,
    endpoint: Endpoint,
    value: T,
) -> Result<(), Error> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::NonFinitePosition {
            axis,
            endpoint,
            value: value.widen(),
        })
    }
}

/// Checks one limit: positive and finite.
pub(crate) fn check_limit<T: Real>(axis: usize, limit: LimitKind, value: T) -> Result<(), Error> {
    if value.is_finite() && value > T::zero() {
        Ok(())
    } else {
        Err(Error::InvalidLimit {
            axis,
            limit,
            value: value.widen(),
        })
    }
}

/// Checks both ends and returns `(direction, distance)`: the direction is
/// `+1`, `-1` or `0` (zero distance), the distance is `|goal - start|`.
pub(crate) fn check_move<T: Real>(axis: usize, start: T, goal: T) -> Result<(T, T), Error> {
    check_position(axis, Endpoint::Start, start)?;
    check_position(axis, Endpoint::Goal, goal)?;
    let delta = goal - start;
    if !delta.is_finite() {
        return Err(Error::DistanceOverflow {
            axis,
            start: start.widen(),
            goal: goal.widen(),
        });
    }
    let dir = if delta > T::zero() {
        T::one()
    } else if delta < T::zero() {
        -T::one()
    } else {
        T::zero()
    };
    Ok((dir, delta.abs()))
}

/// The error for a profile that does not fit the float type.
pub(crate) fn out_of_range<T: Real>(axis: usize, distance: T) -> Error {
    Error::OutOfRange {
        axis,
        distance: distance.widen(),
    }
}
