//! Closed intervals: joint limits and actuator strokes.

use crate::real::Real;

/// A closed interval `[min, max]` in the unit of the quantity it bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Interval<T> {
    /// Lower bound.
    pub min: T,
    /// Upper bound.
    pub max: T,
}

impl<T: Real> Interval<T> {
    /// `[min, max]`.
    pub const fn new(min: T, max: T) -> Self {
        Self { min, max }
    }

    /// The signed distance inside the interval: positive inside (to the
    /// nearer bound), negative outside (by how much it is exceeded).
    pub fn margin(&self, value: T) -> T {
        (value - self.min).min(self.max - value)
    }
}
