//! The inputs and the typed errors of the time-optimal solver.

use core::convert::Infallible;
use core::fmt;

use parasils_num::Num;

use crate::error::LimitKind;
use crate::real::Real;

/// The limits of one row (one actuator, or any quantity `q_j(s)` along the
/// path): `|q_j' s_dot| <= velocity` and `|q_j' s_ddot + q_j'' s_dot^2| <=
/// acceleration`, in the row's units per s and per s^2. `+inf` means no
/// limit; every limit must be positive (not NaN).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RowLimits<T> {
    /// The velocity maximum, row units/s.
    pub velocity: T,
    /// The acceleration maximum, row units/s^2.
    pub acceleration: T,
}

impl<T: Real> RowLimits<T> {
    /// The limits `velocity` (units/s) and `acceleration` (units/s^2).
    pub fn new(velocity: T, acceleration: T) -> Self {
        Self {
            velocity,
            acceleration,
        }
    }

    /// No limit (both `+inf`): the row is not constrained.
    pub fn unlimited() -> Self {
        Self::new(T::INFINITY, T::INFINITY)
    }
}

/// The path's first and second derivatives with respect to the path
/// parameter `s`, one per row: `first[j] = dq_j/ds`, `second[j] = d^2q_j/ds^2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Derivatives<T, const M: usize> {
    /// `q'(s)`, row units.
    pub first: [T; M],
    /// `q''(s)`, row units.
    pub second: [T; M],
}

impl<T: Real, const M: usize> Default for Derivatives<T, M> {
    fn default() -> Self {
        Self {
            first: [T::zero(); M],
            second: [T::zero(); M],
        }
    }
}

impl<T: Real, const M: usize> Derivatives<T, M> {
    /// The velocity limit curve here: the largest `x = s_dot^2` with
    /// `|q_j' s_dot| <= v_j` for every row, `min_j (v_j / q_j')^2`
    /// (`+inf` when no row moves or every velocity is unlimited).
    pub fn velocity_limit(&self, limits: &[RowLimits<T>; M]) -> T {
        let mut x = T::INFINITY;
        for (d, lim) in self.first.iter().zip(limits) {
            if *d != T::zero() {
                let r = lim.velocity / d.abs();
                x = x.min(r * r);
            }
        }
        x
    }

    /// The acceleration limit curve here: the largest `x = s_dot^2` at
    /// which some path acceleration `u` keeps `|q_j' u + q_j'' x| <= a_j` for
    /// every row (`+inf` when no such bound exists). Each row bounds `u`
    /// between two lines in `x`; the curve is where the highest lower line
    /// meets the lowest upper one, found over every pair of rows.
    pub fn acceleration_limit(&self, limits: &[RowLimits<T>; M]) -> T {
        let mut x = T::INFINITY;
        // Row j's band, when q_j' != 0: u in [b x - w, b x + w].
        let bands: [Option<(T, T)>; M] = core::array::from_fn(|j| {
            let (d, dd, a) = (self.first[j], self.second[j], limits[j].acceleration);
            (d != T::zero() && a != T::INFINITY).then(|| (a / d.abs(), -dd / d))
        });
        for ((d, dd), lim) in self.first.iter().zip(&self.second).zip(limits) {
            if *d == T::zero() && *dd != T::zero() {
                // No u in the row: |q_j'' x| <= a_j alone.
                x = x.min(lim.acceleration / dd.abs());
            }
        }
        for (w_lo, b_lo) in bands.iter().flatten() {
            for (w_hi, b_hi) in bands.iter().flatten() {
                // b_lo x - w_lo <= b_hi x + w_hi.
                let slope = *b_lo - *b_hi;
                if slope > T::zero() {
                    x = x.min((*w_lo + *w_hi) / slope);
                }
            }
        }
        x
    }
}

/// A geometric path with `M` constrained rows: its derivatives at any `s`
/// of `[0, 1]`, from the path's own closed form (never differenced).
pub trait Path<T: Real, const M: usize> {
    /// Why the path cannot be evaluated at some `s` (out of reach, ...).
    type Error;

    /// `q'(s)` and `q''(s)`.
    ///
    /// # Errors
    /// The path's own, when `s` is not on a valid part of it.
    fn derivatives(&self, s: T) -> Result<Derivatives<T, M>, Self::Error>;
}

impl<T: Real, const M: usize, P: Path<T, M> + ?Sized> Path<T, M> for &P {
    type Error = P::Error;
    fn derivatives(&self, s: T) -> Result<Derivatives<T, M>, Self::Error> {
        (**self).derivatives(s)
    }
}

/// One grid point of the solver: the caller's `s` and the path's
/// derivatives there, and what the solver computes (the squared path speed
/// `x = s_dot^2`, the path acceleration `u = s_ddot` of the interval that
/// starts here, the time `t`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knot<T, const M: usize> {
    /// The path parameter.
    pub s: T,
    /// `q'(s)`, `q''(s)`.
    pub derivatives: Derivatives<T, M>,
    /// The largest admissible `x`: the velocity limit curve, then the
    /// controllable set's upper end.
    pub(crate) x_max: T,
    /// An extra bound on `x` set by [`certify`](super::certify) where the
    /// limits were exceeded between knots (`+inf` at first).
    pub(crate) x_cap: T,
    pub(crate) x: T,
    pub(crate) u: T,
    pub(crate) t: T,
}

impl<T: Real, const M: usize> Default for Knot<T, M> {
    fn default() -> Self {
        Self::new(T::zero(), Derivatives::default())
    }
}

impl<T: Real, const M: usize> Knot<T, M> {
    /// A knot at `s` with the path's derivatives there.
    pub fn new(s: T, derivatives: Derivatives<T, M>) -> Self {
        Self {
            s,
            derivatives,
            x_max: T::zero(),
            x_cap: T::INFINITY,
            x: T::zero(),
            u: T::zero(),
            t: T::zero(),
        }
    }

    /// `s_dot^2` at this knot (1/s^2).
    pub fn x(&self) -> T {
        self.x
    }

    /// `s_dot` at this knot (1/s).
    pub fn s_dot(&self) -> T {
        self.x.sqrt()
    }

    /// `s_ddot` (1/s^2) on the interval that starts at this knot (0 at the last knot).
    pub fn s_ddot(&self) -> T {
        self.u
    }

    /// The time at which the schedule passes this knot, s.
    pub fn t(&self) -> T {
        self.t
    }

    /// The largest `s_dot^2` the limits admit here from which a stop at the
    /// path's end is still possible (the controllable set's upper end).
    pub fn x_max(&self) -> T {
        self.x_max
    }
}

/// Why a time-optimal schedule could not be computed. `E` is the path's own
/// error ([`Path::Error`]); [`solve`](super::solve), which evaluates no
/// path, returns `Error<Infallible>`.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error<E = Infallible> {
    /// Fewer than two knots.
    #[error("time-optimal timing: {count} knots, at least 2 are needed")]
    TooFewKnots {
        /// The number of knots given.
        count: usize,
    },
    /// A knot's `s` is not finite or not above the previous knot's.
    #[error("time-optimal timing: knot {index}: s = {} is not finite or not above the previous knot's", Num::new(*s))]
    Grid {
        /// The knot.
        index: usize,
        /// Its `s`.
        s: f64,
    },
    /// A limit that is zero, negative or NaN.
    #[error("time-optimal timing: row {row}: {kind} = {} is not a positive number", Num::new(*value))]
    InvalidLimit {
        /// The row.
        row: usize,
        /// Velocity or acceleration.
        kind: LimitKind,
        /// The value given.
        value: f64,
    },
    /// A path derivative that is NaN or infinite.
    #[error("time-optimal timing: knot {index}: row {row}: a path derivative is {}", Num::new(*value))]
    NonFiniteDerivative {
        /// The knot.
        index: usize,
        /// The row.
        row: usize,
        /// The value.
        value: f64,
    },
    /// No limit bounds the path speed near this knot (the path moves no
    /// limited row there): the fastest motion would take no time.
    #[error("time-optimal timing: knot {index}: no limit bounds the path speed there")]
    Unconstrained {
        /// The knot.
        index: usize,
    },
    /// The schedule's numbers overflow or underflow the float type.
    #[error("time-optimal timing: knot {index}: the schedule does not fit the float type")]
    OutOfRange {
        /// The knot.
        index: usize,
    },
    /// Fewer than 2 check points per interval were asked for.
    #[error("time-optimal timing: {count} check points per interval, at least 2 are needed")]
    TooFewChecks {
        /// The number asked for.
        count: usize,
    },
    /// The path could not be evaluated.
    #[error("time-optimal timing: the path at s = {}: {error}", Num::new(*s))]
    Path {
        /// Where.
        s: f64,
        /// The path's own error.
        error: E,
    },
}

impl<E> Error<E> {
    /// The path's error with where it happened (`Err((s, error))`), or the
    /// solver's own error.
    pub fn split(self) -> Result<Error, (f64, E)> {
        Ok(match self {
            Error::TooFewKnots { count } => Error::TooFewKnots { count },
            Error::Grid { index, s } => Error::Grid { index, s },
            Error::InvalidLimit { row, kind, value } => Error::InvalidLimit { row, kind, value },
            Error::NonFiniteDerivative { index, row, value } => {
                Error::NonFiniteDerivative { index, row, value }
            }
            Error::Unconstrained { index } => Error::Unconstrained { index },
            Error::OutOfRange { index } => Error::OutOfRange { index },
            Error::TooFewChecks { count } => Error::TooFewChecks { count },
            Error::Path { s, error } => return Err((s, error)),
        })
    }
}

impl Error<Infallible> {
    /// The same error as that of a path with error type `E` (a solver error
    /// carries no path error).
    pub fn widen<E>(self) -> Error<E> {
        match self {
            Error::TooFewKnots { count } => Error::TooFewKnots { count },
            Error::Grid { index, s } => Error::Grid { index, s },
            Error::InvalidLimit { row, kind, value } => Error::InvalidLimit { row, kind, value },
            Error::NonFiniteDerivative { index, row, value } => {
                Error::NonFiniteDerivative { index, row, value }
            }
            Error::Unconstrained { index } => Error::Unconstrained { index },
            Error::OutOfRange { index } => Error::OutOfRange { index },
            Error::TooFewChecks { count } => Error::TooFewChecks { count },
            Error::Path { error, .. } => match error {},
        }
    }
}

/// What limits a stretch of the schedule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phase<T> {
    /// The row whose limit binds.
    pub row: usize,
    /// Which of its limits: velocity or acceleration.
    pub limit: LimitKind,
    /// The first knot of the phase.
    pub first_knot: usize,
    /// The knot where it ends.
    pub last_knot: usize,
    /// When it starts, s.
    pub start_t: T,
    /// When it ends, s.
    pub end_t: T,
    /// The largest fraction of the binding limit used in the phase (1 when it binds).
    pub usage: T,
}

impl<T: Real> fmt::Display for Phase<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} s to {} s: row {} {}",
            Num::new(self.start_t.to_f64()),
            Num::new(self.end_t.to_f64()),
            self.row,
            match self.limit {
                LimitKind::Velocity => "velocity",
                _ => "acceleration",
            }
        )
    }
}

/// What [`certify`](super::certify) found and did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Certificate<T> {
    /// The worst use of any limit found on the check points of the solved
    /// schedule, before any correction, as a time stretch:
    /// `max(|v| / v_max, sqrt(|a| / a_max))`, the estimated excess between
    /// check points included.
    pub worst: T,
    /// How many times the schedule was solved again with lower speeds where
    /// the check points found an excess.
    pub passes: usize,
    /// The uniform factor the time was finally stretched by (1: none).
    pub stretch: T,
    /// How many check points were evaluated on the path.
    pub checks: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limit_curves_by_hand() {
        // Row 0: u in [-1 - x, 1 - x]; row 1: u in [-1 + x, 1 + x]: they
        // meet while -1 + x <= 1 - x, so up to x = 1.
        let d = Derivatives {
            first: [1.0_f64, 1.0],
            second: [1.0, -1.0],
        };
        let limits = [RowLimits::new(2.0, 1.0), RowLimits::new(3.0, 1.0)];
        assert_eq!(d.acceleration_limit(&limits), 1.0);
        assert_eq!(d.velocity_limit(&limits), 4.0);
        // One row alone always has a u (its band is never empty).
        let one = Derivatives {
            first: [2.0_f64],
            second: [1.0],
        };
        assert_eq!(
            one.acceleration_limit(&[RowLimits::new(1.0, 1.0)]),
            f64::INFINITY
        );
        // A row that does not move but curves: |q''| x <= a.
        let still = Derivatives {
            first: [0.0_f64, 1.0],
            second: [4.0, 0.0],
        };
        let limits = [RowLimits::new(1.0, 2.0), RowLimits::new(1.0, 1.0)];
        assert_eq!(still.acceleration_limit(&limits), 0.5);
        assert_eq!(still.velocity_limit(&limits), 1.0);
    }

    #[test]
    fn the_acceleration_curve_is_where_the_bands_stop_meeting() {
        // Pseudo-random rows; at the curve's x (slightly below) the highest
        // lower bound on u is under the lowest upper one, slightly above it
        // is not.
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            let d = Derivatives::<f64, 5> {
                first: core::array::from_fn(|_| next()),
                second: core::array::from_fn(|_| 3.0 * next()),
            };
            let limits: [RowLimits<f64>; 5] =
                core::array::from_fn(|_| RowLimits::new(1.0, 0.1 + next().abs()));
            let x_a = d.acceleration_limit(&limits);
            let gap = |x: f64| {
                let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
                for ((a, b), lim) in d.first.iter().zip(&d.second).zip(&limits) {
                    let c = lim.acceleration;
                    let (u1, u2) = ((-c - b * x) / a, (c - b * x) / a);
                    lo = lo.max(u1.min(u2));
                    hi = hi.min(u1.max(u2));
                }
                hi - lo
            };
            if x_a.finite() {
                assert!(gap(x_a * (1.0 - 1e-9)) >= 0.0, "{d:?}");
                assert!(gap(x_a * (1.0 + 1e-6)) < 0.0, "{d:?}");
            } else {
                assert!(gap(1e12) >= 0.0);
            }
        }
    }
}
