//! Typed errors of the profile constructors and of the sampler.
//!
//! Messages write every number with up to 6 significant digits: plain
//! decimals from `1e-3` to `1e6`, exponent form (`1e-6`, `2.5e308`) beyond,
//! `NaN` and `inf` by name; a duration just below its minimum gets as many
//! more digits as it takes to read differently from the minimum.

use core::fmt;

use parasils_num::Num;

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
/// - [`InvalidLimit`](Self::InvalidLimit), [`NonFinitePosition`](Self::NonFinitePosition),
///   [`NonFiniteVelocity`](Self::NonFiniteVelocity): bad input, typically a unit
///   mix-up or an uninitialised value upstream. Reject the command; do not
///   retry with the same input.
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
    #[error("axis {axis}: {limit} = {} is not a positive finite number", Num::new(*value))]
    InvalidLimit {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// Which limit.
        limit: LimitKind,
        /// The value given, in position units/s, /s^2 or /s^3.
        value: f64,
    },
    /// The start or the goal position is infinite or NaN.
    #[error("axis {axis}: the {endpoint} position {} is not finite", Num::new(*value))]
    NonFinitePosition {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// Start or goal.
        endpoint: Endpoint,
        /// The value given, in position units.
        value: f64,
    },
    /// The start velocity of an online profile is infinite or NaN.
    #[error("axis {axis}: the start velocity {} is not finite", Num::new(*value))]
    NonFiniteVelocity {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// The value given, in position units/s.
        value: f64,
    },
    /// `goal - start` overflows the float type.
    #[error(
        "axis {axis}: the distance from {} to {} overflows the float type",
        Num::new(*start), Num::new(*goal)
    )]
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
        "axis {axis}: the profile over distance {} does not fit the float type with these limits",
        Num::new(*distance)
    )]
    OutOfRange {
        /// The axis index (`0` for a single-axis profile).
        axis: usize,
        /// `|goal - start|`, in position units.
        distance: f64,
    },
    /// An imposed duration is shorter than the minimum time, or not finite.
    #[error(
        "axis {axis}: the duration {} s is not finite or below the minimum {} s",
        Num::apart_from(*requested, *minimum), Num::new(*minimum)
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
    #[error("sampling rate {} Hz is not a positive finite number", Num::new(*value))]
    InvalidRate {
        /// The rate given, in Hz.
        value: f64,
    },
    /// `duration * rate` does not fit `usize`.
    #[error(
        "sampling {} s at {} Hz needs more samples than usize can count",
        Num::new(*duration), Num::new(*rate)
    )]
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
    if value.finite() {
        Ok(())
    } else {
        Err(Error::NonFinitePosition {
            axis,
            endpoint,
            value: value.to_f64(),
        })
    }
}

/// Checks one limit: positive and finite.
pub(crate) fn check_limit<T: Real>(axis: usize, limit: LimitKind, value: T) -> Result<(), Error> {
    if value.finite() && value > T::zero() {
        Ok(())
    } else {
        Err(Error::InvalidLimit {
            axis,
            limit,
            value: value.to_f64(),
        })
    }
}

/// Checks both ends and returns `(direction, distance)`: the direction is
/// `+1`, `-1` or `0` (zero distance), the distance is `|goal - start|`.
pub(crate) fn check_move<T: Real>(axis: usize, start: T, goal: T) -> Result<(T, T), Error> {
    check_position(axis, Endpoint::Start, start)?;
    check_position(axis, Endpoint::Goal, goal)?;
    let delta = goal - start;
    if !delta.finite() {
        return Err(Error::DistanceOverflow {
            axis,
            start: start.to_f64(),
            goal: goal.to_f64(),
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
        distance: distance.to_f64(),
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::string::ToString;

    use super::*;

    #[test]
    fn numbers_are_short() {
        let e = Error::InvalidLimit {
            axis: 1,
            limit: LimitKind::Velocity,
            value: 1e308,
        };
        assert_eq!(
            e.to_string(),
            "axis 1: v_max = 1e308 is not a positive finite number"
        );
        let e = Error::DistanceOverflow {
            axis: 0,
            start: -1.5e308,
            goal: 1.7e308,
        };
        assert_eq!(
            e.to_string(),
            "axis 0: the distance from -1.5e308 to 1.7e308 overflows the float type"
        );
        let e = Error::InvalidDuration {
            axis: 0,
            requested: 4.499_999_9,
            minimum: 4.5,
        };
        assert_eq!(
            e.to_string(),
            "axis 0: the duration 4.4999999 s is not finite or below the minimum 4.5 s"
        );
        let e = Error::InvalidRate { value: -0.0 };
        assert_eq!(
            e.to_string(),
            "sampling rate 0 Hz is not a positive finite number"
        );
        let e = Error::TooManySamples {
            duration: 4.5,
            rate: 1.234_567_8e20,
        };
        assert_eq!(
            e.to_string(),
            "sampling 4.5 s at 1.23457e20 Hz needs more samples than usize can count"
        );
        for (x, want) in [
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
            (0.000_99, "9.9e-4"),
            (0.001, "0.001"),
            (999_999.7, "1e6"),
            (-123.456_78, "-123.457"),
        ] {
            assert_eq!(Num::new(x).to_string(), want);
        }
    }
}
