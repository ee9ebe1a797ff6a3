//! The vocabulary of one axis, written once for the three one-axis profiles
//! (crate-private).
//!
//! - **Time** ([`instant`]): a NaN `t` or `t <= 0` is the start, `t >=
//!   duration` the end, both returned exactly as stored; in between, the
//!   phase that begins at a switch holds it (right-continuous).
//! - **An imposed duration** ([`check_duration`]): at least the minimum time,
//!   up to 8 float epsilons (relative) below it, and finite.
//! - **A ramp** ([`ramp`]): the distance covered from rest in `t` at a
//!   constant acceleration; the last phase of every profile is written
//!   from the goal with it, so that the goal is reached exactly.
//! - **A rest-to-rest shape** ([`Shape`]): the timing of a move over a
//!   positive distance in magnitudes (phase times, peaks), its minimum-time
//!   and stretched forms, its copy scaled in space; the trapezoid
//!   ([`Trapezoid`](crate::Trapezoid)) and the double S
//!   ([`DoubleS`](crate::DoubleS)) are two shapes.
//! - **A rest-to-rest axis** ([`Axis`]): a shape placed between a start and a
//!   goal, with the direction and the distance: its construction, its
//!   stretch to a duration and its state at `t`, shared by both shapes and
//!   by the synchronised builder ([`Multi`](crate::Multi)), which sees every
//!   profile through [`OneAxis`].
//!
//! The online profile ([`OnlineTrapezoid`](crate::OnlineTrapezoid)) starts
//! from a moving state, so it has no rest-to-rest shape, but it keeps the
//! same time, duration and ramp conventions from here.

use crate::error::{Error, check_move, out_of_range};
use crate::profile::{Profile, State};
use crate::real::Real;

/// Where an instant `t` (s) falls in a motion of a given duration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Instant<T> {
    /// `t <= 0` or NaN: the start state, exactly as stored.
    Start,
    /// `t >= duration`: the end at rest, exactly as stored.
    End,
    /// `0 < t < duration`.
    Inside(T),
}

/// Where `t` falls in `[0, duration]` (see [`Instant`]).
#[inline]
pub(crate) fn instant<T: Real>(t: T, duration: T) -> Instant<T> {
    if t.is_nan() || t <= T::zero() {
        Instant::Start
    } else if t >= duration {
        Instant::End
    } else {
        Instant::Inside(t)
    }
}

/// Checks that a profile whose minimum time is `minimum` (s) can last
/// `requested` (s): finite, and not below `minimum` by more than 8 float
/// epsilons (relative).
///
/// # Errors
/// [`Error::InvalidDuration`], naming `axis`.
pub(crate) fn check_duration<T: Real>(axis: usize, minimum: T, requested: T) -> Result<(), Error> {
    let tol = minimum * T::EPSILON * T::lit(8.0);
    if !requested.finite() || requested < minimum - tol {
        return Err(Error::InvalidDuration {
            axis,
            requested: requested.to_f64(),
            minimum: minimum.to_f64(),
        });
    }
    Ok(())
}

/// The distance covered from rest in `t` (s) at the constant acceleration
/// `a`, `a t^2 / 2`, signed as `a`.
#[inline]
pub(crate) fn ramp<T: Real>(a: T, t: T) -> T {
    T::lit(0.5) * (a * t) * t
}

/// The timing of a rest-to-rest move over a positive distance, in
/// magnitudes: an acceleration half of `t_accel`, a cruise at the peak
/// velocity for `t_cruise`, and the deceleration, the acceleration half
/// mirrored in time.
pub(crate) trait Shape<T: Real>: Copy {
    /// The limits the shape is planned under.
    type Limits: Copy;

    /// Checks every limit (positive and finite), naming `axis`.
    fn check_limits(limits: &Self::Limits, axis: usize) -> Result<(), Error>;
    /// Every limit infinite: where a minimum over axes starts.
    fn unbounded() -> Self::Limits;
    /// Lowers each limit of `line` to that of `limits` times `ratio` when
    /// smaller.
    fn tighten(line: &mut Self::Limits, limits: &Self::Limits, ratio: T);

    /// The minimum-time shape over `d > 0` under valid limits; `None` when
    /// it does not fit the float type.
    fn min_time(d: T, limits: Self::Limits) -> Option<Self>;
    /// The shape over `d > 0` lasting exactly `duration`, above the minimum
    /// time of `self` (the minimum-time shape over `d`), keeping the
    /// acceleration (and jerk) limit and lowering the cruise velocity;
    /// `None` when it does not fit the float type.
    fn with_duration(&self, d: T, limits: Self::Limits, duration: T) -> Option<Self>;
    /// This shape scaled by `k` in space (same phase times); `None` when `k`
    /// or a scaled peak is not a normal number (a subnormal one holds too few
    /// significant bits for the axis to end on its goal).
    fn scaled(&self, k: T) -> Option<Self>;
    /// The shape of an axis that stays still for `duration`: all zero but
    /// the cruise time and the duration.
    fn still(duration: T) -> Self;

    /// Total time, s.
    fn duration(&self) -> T;
    /// Duration of the acceleration half (equal to the deceleration's), s.
    fn t_accel(&self) -> T;
    /// Duration of the cruise, s.
    fn t_cruise(&self) -> T;
    /// The cruise velocity, units/s.
    fn peak_velocity(&self) -> T;
    /// Offset from the start, speed and acceleration at `t` in
    /// `[0, t_accel)` (all magnitudes).
    fn accel_half(&self, t: T) -> (T, T, T);
}

/// A rest-to-rest shape `S` placed between a start and a goal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Axis<T, S> {
    start: T,
    goal: T,
    /// +1, -1, or 0 for a zero distance.
    dir: T,
    distance: T,
    /// In magnitudes; [`Shape::still`] for a zero distance.
    shape: S,
}

impl<T: Real, S: Shape<T>> Axis<T, S> {
    /// The minimum-time axis from `start` to `goal` under `limits`.
    ///
    /// # Errors
    /// [`Error::InvalidLimit`], [`Error::NonFinitePosition`],
    /// [`Error::DistanceOverflow`] or [`Error::OutOfRange`], naming `axis`.
    pub(crate) fn new(axis: usize, start: T, goal: T, limits: S::Limits) -> Result<Self, Error> {
        S::check_limits(&limits, axis)?;
        let (dir, distance) = check_move(axis, start, goal)?;
        if dir == T::zero() {
            return Ok(Self::still(start, goal, T::zero()));
        }
        let shape = S::min_time(distance, limits).ok_or_else(|| out_of_range(axis, distance))?;
        Ok(Self {
            start,
            goal,
            dir,
            distance,
            shape,
        })
    }

    /// A zero-distance axis that stays still for `duration`.
    pub(crate) fn still(start: T, goal: T, duration: T) -> Self {
        Self {
            start,
            goal,
            dir: T::zero(),
            distance: T::zero(),
            shape: S::still(duration),
        }
    }

    /// This minimum-time axis stretched to `duration` (see [`Shape::with_duration`]).
    ///
    /// # Errors
    /// [`Error::InvalidDuration`] (see [`check_duration`]) or
    /// [`Error::OutOfRange`], naming `axis`.
    pub(crate) fn stretched(
        self,
        axis: usize,
        limits: S::Limits,
        duration: T,
    ) -> Result<Self, Error> {
        check_duration(axis, self.shape.duration(), duration)?;
        if self.dir == T::zero() {
            return Ok(Self::still(self.start, self.goal, duration.max(T::zero())));
        }
        if duration <= self.shape.duration() {
            return Ok(self);
        }
        let shape = self
            .shape
            .with_duration(self.distance, limits, duration)
            .ok_or_else(|| out_of_range(axis, self.distance))?;
        Ok(Self { shape, ..self })
    }

    /// This moving axis's share `k` of a shape planned over a longer
    /// distance (a straight line in joint space), or, for a still axis, the
    /// axis still for that shape's duration.
    ///
    /// # Errors
    /// [`Error::OutOfRange`], naming `axis`, when the share does not fit
    /// the float type ([`Shape::scaled`]).
    pub(crate) fn share(self, axis: usize, line: &S, k: T) -> Result<Self, Error> {
        if self.distance > T::zero() {
            let shape = line
                .scaled(k)
                .ok_or_else(|| out_of_range(axis, self.distance))?;
            Ok(Self { shape, ..self })
        } else {
            Ok(Self::still(self.start, self.goal, line.duration()))
        }
    }

    /// Start position, in position units.
    pub(crate) fn start(&self) -> T {
        self.start
    }

    /// Goal position, in position units.
    pub(crate) fn goal(&self) -> T {
        self.goal
    }

    /// `|goal - start|`, in position units.
    pub(crate) fn distance(&self) -> T {
        self.distance
    }

    /// Whether the axis moves (a non-zero distance).
    pub(crate) fn moves(&self) -> bool {
        self.dir != T::zero()
    }

    /// Direction: `+1`, `-1`, or `0` for a zero distance.
    pub(crate) fn direction(&self) -> T {
        self.dir
    }

    /// The shape, in magnitudes.
    pub(crate) fn shape(&self) -> &S {
        &self.shape
    }

    /// The state at `t` (s): the acceleration half from the start, the
    /// cruise, and the deceleration as the acceleration half mirrored in
    /// time and written from the goal, so that it is reached exactly. The
    /// speed is clamped to the peak velocity against rounding.
    pub(crate) fn sample(&self, t: T) -> State<T> {
        let s = &self.shape;
        let t = match instant(t, s.duration()) {
            Instant::Inside(t) if self.moves() => t,
            Instant::End => return State::rest(self.goal),
            _ => return State::rest(self.start),
        };
        let (t_a, v) = (s.t_accel(), s.peak_velocity());
        let (position, speed, accel) = if t < t_a {
            let (p, speed, a) = s.accel_half(t);
            (self.start + self.dir * p, speed, a)
        } else if t < t_a + s.t_cruise() {
            let p = T::lit(0.5) * v * t_a + v * (t - t_a);
            (self.start + self.dir * p, v, T::zero())
        } else {
            let (p, speed, a) = s.accel_half(s.duration() - t);
            (self.goal - self.dir * p, speed, -a)
        };
        State {
            position,
            velocity: self.dir * speed.min(v),
            acceleration: self.dir * accel,
        }
    }
}

/// A one-axis rest-to-rest profile as its [`Axis`]: what the synchronised
/// builder ([`Multi`](crate::Multi)) plans every profile type through.
pub(crate) trait OneAxis<T: Real>: Profile<T> {
    /// The profile's shape.
    type Shape: Shape<T>;
    /// The profile of an axis.
    fn from_axis(axis: Axis<T, Self::Shape>) -> Self;
}
