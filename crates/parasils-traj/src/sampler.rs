//! Fixed-rate sampling of a motion, without allocation, ending on the goal.
//!
//! Convention: sample `k` is at `t_k = k / rate` (computed as such, never by
//! accumulating a period), for `k = 0, 1, ..., n`, where `n` is the smallest
//! integer with `n / rate >= T` (`T` the duration). So:
//! - when `T` is a multiple of the period, the last sample is at `T` exactly:
//!   4.5 s at 1 kHz gives `n = 4500`, 4501 samples `t = 0, 0.001, ..., 4.5`;
//! - otherwise the last sample is at the first period after `T`, where the
//!   motion already rests at its goal: 3.4641 s at 1 kHz gives `n = 3465`,
//!   3466 samples, the last at 3.465 s;
//! - a zero-duration motion gives one sample, at `t = 0`.
//!
//! The last sample's state is always the end state exactly (goal position,
//! zero velocity and acceleration), even when `n / rate` falls short of `T` by
//! rounding: `T * rate` within 64 float epsilons (relative) of an integer is
//! taken as that integer, so rounding never adds a sample.

use core::iter::FusedIterator;

use crate::error::Error;
use crate::profile::Motion;
use crate::real::Real;

/// One sample: its index, its time and the motion's state then.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Sample<T, S> {
    /// Index `k` of the sample, from 0.
    pub index: usize,
    /// Time `k / rate`, in s from the start of the motion.
    pub time: T,
    /// The state at `time`: a [`State`](crate::State) or one per axis.
    pub state: S,
}

/// An iterator over a motion sampled at a fixed rate; see the module docs.
///
/// ```
/// use parasils_traj::{Limits, Motion, Multi, Synchronization};
/// let deg = core::f64::consts::PI / 180.0;
/// let m = Multi::new([-15.0 * deg, 10.0 * deg], [0.0, 35.0 * deg], [Limits::paper(); 2], Synchronization::Phase)?;
/// let samples = m.sampler(1000.0)?;
/// assert_eq!(samples.len(), 4501);
/// let last = samples.last().ok_or(parasils_traj::Error::InvalidRate { value: 0.0 })?;
/// assert_eq!(last.time, 4.5);
/// assert_eq!([last.state[0].position, last.state[1].position], [0.0, 35.0 * deg]);
/// # Ok::<(), parasils_traj::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Sampler<T, M> {
    motion: M,
    rate: T,
    /// Next index from the front.
    front: usize,
    /// One past the last index still to yield from the back.
    back: usize,
    /// `n + 1`, the number of samples.
    count: usize,
}

/// A whole number `n >= 0` as a `usize`; `None` when it does not fit.
fn count_of(n: f64) -> Option<usize> {
    // `usize::MAX + 1` is a power of two, exact in `f64` (the sum rounds to
    // it for a 64-bit `usize`), so the cast below is exact.
    #[allow(clippy::cast_precision_loss)]
    let end = usize::MAX as f64 + 1.0;
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    (n >= 0.0 && n < end).then_some(n as usize)
}

impl<T: Real, M: Motion<T>> Sampler<T, M> {
    /// Samples `motion` at `rate` (Hz).
    ///
    /// # Errors
    /// [`Error::InvalidRate`] when `rate` is not positive and finite,
    /// [`Error::TooManySamples`] when the sample count does not fit `usize`.
    pub fn new(motion: M, rate: T) -> Result<Self, Error> {
        if !(rate.finite() && rate > T::zero()) {
            return Err(Error::InvalidRate {
                value: rate.to_f64(),
            });
        }
        let duration = motion.duration();
        let too_many = Error::TooManySamples {
            duration: duration.to_f64(),
            rate: rate.to_f64(),
        };
        let x = duration.max(T::zero()) * rate;
        if !x.finite() {
            return Err(too_many);
        }
        let floor = x.floor();
        let n = if x - floor <= x * T::EPSILON * T::lit(64.0) {
            floor
        } else {
            floor + T::one()
        };
        let count = count_of(n.to_f64())
            .and_then(|n| n.checked_add(1))
            .ok_or(too_many)?;
        Ok(Self {
            motion,
            rate,
            front: 0,
            back: count,
            count,
        })
    }

    /// The sampling rate, in Hz.
    #[must_use]
    pub fn rate(&self) -> T {
        self.rate
    }

    /// The total number of samples `n + 1`, consumed or not.
    #[must_use]
    pub fn sample_count(&self) -> usize {
        self.count
    }

    /// The motion sampled.
    #[must_use]
    pub fn motion(&self) -> &M {
        &self.motion
    }

    fn at(&self, k: usize) -> Sample<T, M::Output> {
        let time = T::from_index(k) / self.rate;
        let state = if k + 1 >= self.count {
            self.motion.sample(self.motion.duration())
        } else {
            self.motion.sample(time)
        };
        Sample {
            index: k,
            time,
            state,
        }
    }
}

impl<T: Real, M: Motion<T>> Iterator for Sampler<T, M> {
    type Item = Sample<T, M::Output>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.front >= self.back {
            return None;
        }
        let k = self.front;
        self.front += 1;
        Some(self.at(k))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.back.saturating_sub(self.front);
        (n, Some(n))
    }

    fn last(mut self) -> Option<Self::Item> {
        self.next_back()
    }

    fn nth(&mut self, n: usize) -> Option<Self::Item> {
        self.front = self.front.saturating_add(n).min(self.back);
        self.next()
    }
}

impl<T: Real, M: Motion<T>> DoubleEndedIterator for Sampler<T, M> {
    fn next_back(&mut self) -> Option<Self::Item> {
        if self.front >= self.back {
            return None;
        }
        self.back -= 1;
        Some(self.at(self.back))
    }
}

impl<T: Real, M: Motion<T>> ExactSizeIterator for Sampler<T, M> {}
impl<T: Real, M: Motion<T>> FusedIterator for Sampler<T, M> {}
