//! What every profile offers: the state at a time, the duration, the ends.

use crate::error::Error;
use crate::real::Real;
use crate::sampler::Sampler;

/// The state of one axis at one instant.
///
/// Units are those of the axis: position in its units (e.g. rad or mm),
/// velocity in units/s, acceleration in units/s^2. Signs follow the axis: a
/// motion towards a smaller position has negative velocity while it cruises.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct State<T> {
    /// Position, in position units of the axis.
    pub position: T,
    /// Velocity, in position units/s.
    pub velocity: T,
    /// Acceleration, in position units/s^2.
    pub acceleration: T,
}

impl<T: Real> State<T> {
    /// At rest at `position`: zero velocity and acceleration.
    #[must_use]
    pub fn rest(position: T) -> Self {
        Self {
            position,
            velocity: T::zero(),
            acceleration: T::zero(),
        }
    }
}

/// Anything that moves over `[0, duration]` and can be sampled at any time:
/// single-axis profiles ([`Trapezoid`](crate::Trapezoid), [`DoubleS`](crate::DoubleS))
/// and synchronised groups ([`Multi`](crate::Multi)).
///
/// Time is in seconds, measured from the start of the motion. For `t <= 0`
/// (and for a NaN `t`) the state is the start state (at rest for the rest-to-rest profiles), for `t >= duration()`
/// the goal at rest, both returned exactly as stored.
pub trait Motion<T: Real> {
    /// What a sample holds: a [`State`] for one axis, `[State<T>; N]` for `N` axes.
    type Output;

    /// Duration of the motion, in s.
    fn duration(&self) -> T;

    /// The state at time `t` (s); see the trait docs for `t` outside `[0, duration]`.
    fn sample(&self, t: T) -> Self::Output;

    /// A fixed-rate sampler over the whole motion, `rate` in Hz; see [`Sampler`].
    ///
    /// # Errors
    /// [`Error::InvalidRate`] or [`Error::TooManySamples`], as [`Sampler::new`].
    fn sampler(self, rate: T) -> Result<Sampler<T, Self>, Error>
    where
        Self: Sized,
    {
        Sampler::new(self, rate)
    }
}

impl<T: Real, M: Motion<T> + ?Sized> Motion<T> for &M {
    type Output = M::Output;
    fn duration(&self) -> T {
        (**self).duration()
    }
    fn sample(&self, t: T) -> Self::Output {
        (**self).sample(t)
    }
}

/// A rest-to-rest motion of one axis, implemented by [`Trapezoid`](crate::Trapezoid)
/// and [`DoubleS`](crate::DoubleS), so that code can take either.
///
/// ```
/// use parasils_traj::{DoubleS, JerkLimits, Limits, Profile, Trapezoid};
/// fn halfway<P: Profile<f64>>(p: &P) -> f64 {
///     p.position(p.duration() / 2.0)
/// }
/// let trap = Trapezoid::new(0.0, 1.0, Limits::new(1.0, 1.0))?;
/// let ds = DoubleS::new(0.0, 1.0, JerkLimits::new(1.0, 1.0, 10.0))?;
/// // Both profiles are symmetric in time: halfway in time is halfway in space.
/// assert!((halfway(&trap) - 0.5).abs() < 1e-12);
/// assert!((halfway(&ds) - 0.5).abs() < 1e-12);
/// # Ok::<(), parasils_traj::Error>(())
/// ```
pub trait Profile<T: Real>: Motion<T, Output = State<T>> {
    /// Start position, in position units.
    fn start(&self) -> T;
    /// Goal position, in position units.
    fn goal(&self) -> T;
    /// `|goal - start|`, in position units.
    fn distance(&self) -> T;
    /// Largest `|velocity|` over the motion, in units/s.
    fn peak_velocity(&self) -> T;
    /// Largest `|acceleration|` over the motion, in units/s^2.
    fn peak_acceleration(&self) -> T;

    /// Position at `t` (s), in position units.
    fn position(&self, t: T) -> T {
        self.sample(t).position
    }
    /// Velocity at `t` (s), in units/s.
    fn velocity(&self, t: T) -> T {
        self.sample(t).velocity
    }
    /// Acceleration at `t` (s), in units/s^2 (right-continuous, 0 for `t <= 0` and `t >= duration`).
    fn acceleration(&self, t: T) -> T {
        self.sample(t).acceleration
    }
}
