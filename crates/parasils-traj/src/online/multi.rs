//! Several axes from their current states to rest, synchronised, and the
//! controlled stop (see the [module docs](super)).

use super::axis::{OnlineTrapezoid, check_start};
use crate::error::Error;
use crate::profile::{Motion, State};
use crate::real::Real;
use crate::sync::Synchronization;
use crate::trapezoid::Limits;

/// `N` axes from their current states to rest at their targets, synchronised
/// (see the [module docs](super)): the online counterpart of [`Multi`](crate::Multi).
///
/// Time is in s from the common start; the group's duration is the longest
/// axis duration, and each axis rests at its target after its own end.
///
/// ```
/// use parasils_traj::{Limits, OnlineMulti, State, Synchronization};
/// let limits = [Limits::new(2.0_f64, 1.0); 2];
/// let moving = |p, v| State { position: p, velocity: v, acceleration: 0.0 };
/// // Velocity along the displacement: the straight line is kept.
/// let line = OnlineMulti::new([moving(0.0, 1.0), moving(0.0, 0.5)], [4.0, 2.0], limits, Synchronization::Phase)?;
/// assert_eq!(line.synchronization(), Synchronization::Phase);
/// // Velocity across it: phase is not possible, time synchronisation is used.
/// let turn = OnlineMulti::new([moving(0.0, 0.0), moving(0.0, 1.0)], [4.0, 0.0], limits, Synchronization::Phase)?;
/// assert_eq!(turn.synchronization(), Synchronization::Time);
/// let [a, b] = turn.axes();
/// assert_eq!(a.duration(), b.duration());
/// // The controlled stop: both axes at rest together, on a straight line.
/// let stop = OnlineMulti::stop(turn.sample(1.0), limits)?;
/// assert_eq!(stop.synchronization(), Synchronization::Phase);
/// # Ok::<(), parasils_traj::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnlineMulti<T, const N: usize> {
    axes: [OnlineTrapezoid<T>; N],
    duration: T,
    sync: Synchronization,
    lead: Option<usize>,
}

/// The first axis with the largest value, if any is positive.
fn first_max<T: Real>(values: impl Iterator<Item = T>) -> Option<(usize, T)> {
    let mut best: Option<(usize, T)> = None;
    for (i, x) in values.enumerate() {
        if x > T::zero() && best.is_none_or(|(_, b)| x > b) {
            best = Some((i, x));
        }
    }
    best
}

impl<T: Real, const N: usize> OnlineMulti<T, N> {
    /// `N` axes from `start` (position and velocity of each; accelerations
    /// are not used) to rest at `target` under per-axis `limits`, synchronised
    /// as `sync` asks: `Phase` falls back to `Time` when the velocity is not
    /// parallel to the displacement; [`synchronization`](Self::synchronization)
    /// reports which was used.
    ///
    /// # Errors
    /// The first invalid axis's [`Error`] (`InvalidLimit`, `NonFinitePosition`,
    /// `NonFiniteVelocity`, `DistanceOverflow`, `OutOfRange`), with its index.
    pub fn new(
        start: [State<T>; N],
        target: [T; N],
        limits: [Limits<T>; N],
        sync: Synchronization,
    ) -> Result<Self, Error> {
        let mut own = [OnlineTrapezoid::at_rest(T::zero(), T::zero(), T::zero()); N];
        for (i, (((p, s), g), l)) in own
            .iter_mut()
            .zip(start)
            .zip(target)
            .zip(limits)
            .enumerate()
        {
            *p = OnlineTrapezoid::new_axis(i, s, g, l)?;
        }
        let lead = first_max(own.iter().map(OnlineTrapezoid::duration));
        let Some((lead_axis, t_max)) = lead else {
            // Every axis rests on its target.
            return Ok(Self::group(own, sync, None));
        };
        let mut axes = own;
        let phase = sync == Synchronization::Phase && Self::line(&mut axes, &own, start, limits);
        let used = if phase {
            Synchronization::Phase
        } else if sync == Synchronization::None {
            Synchronization::None
        } else {
            for (i, ((ax, p), l)) in axes.iter_mut().zip(own).zip(limits).enumerate() {
                *ax = p.stretched(i, l, t_max)?;
            }
            Synchronization::Time
        };
        Ok(Self::group(axes, used, Some(lead_axis)))
    }

    /// The controlled stop: every axis to rest at the same instant
    /// `T = max_i |v0_i| / a_max_i`, each decelerating uniformly, so that the
    /// path keeps its direction; reported as [`Synchronization::Phase`]. The
    /// targets are where the axes stop; `v_max` is not used.
    ///
    /// # Errors
    /// The first invalid axis's [`Error`] (`InvalidLimit`, `NonFinitePosition`,
    /// `NonFiniteVelocity`, `OutOfRange`), with its index.
    pub fn stop(start: [State<T>; N], limits: [Limits<T>; N]) -> Result<Self, Error> {
        for (i, (s, l)) in start.iter().zip(&limits).enumerate() {
            l.check(i)?;
            check_start(i, *s)?;
        }
        let lead = first_max(
            start
                .iter()
                .zip(&limits)
                .map(|(s, l)| s.velocity.abs() / l.a_max),
        );
        let t = lead.map_or(T::zero(), |(_, t)| t);
        let mut axes = [OnlineTrapezoid::at_rest(T::zero(), T::zero(), T::zero()); N];
        for (i, (ax, s)) in axes.iter_mut().zip(start).enumerate() {
            *ax = OnlineTrapezoid::stopping(i, s, limits[i].a_max, t)?;
        }
        Ok(Self::group(
            axes,
            Synchronization::Phase,
            lead.map(|(i, _)| i),
        ))
    }

    fn group(axes: [OnlineTrapezoid<T>; N], sync: Synchronization, lead: Option<usize>) -> Self {
        let duration = axes.iter().fold(T::zero(), |m, p| m.max(p.duration()));
        Self {
            axes,
            duration,
            sync,
            lead,
        }
    }

    /// The straight line, when the velocity is parallel to the displacement
    /// and within every `v_max`: fills `axes` and returns `true`, or returns
    /// `false` (also when the line does not fit the float type) and leaves them.
    fn line(
        axes: &mut [OnlineTrapezoid<T>; N],
        own: &[OnlineTrapezoid<T>; N],
        start: [State<T>; N],
        limits: [Limits<T>; N],
    ) -> bool {
        let eps = T::EPSILON;
        let delta = own.each_ref().map(|p| p.target - p.start);
        // The rounding of each axis's positions, in position units.
        let round = own
            .each_ref()
            .map(|p| T::lit(4.0) * eps * (p.start.abs() + p.target.abs()));
        let (k, big, w0, l) = if let Some((l, big)) = first_max(delta.iter().map(|d| d.abs())) {
            let k = delta.map(|d| d / big);
            (k, big, k[l] * start[l].velocity, l)
        } else if let Some((l, w0)) = first_max(start.iter().map(|s| s.velocity.abs())) {
            // At the targets but moving: the line along the velocity.
            (start.map(|s| s.velocity / w0), T::zero(), w0, l)
        } else {
            return false; // not reached: some axis moves
        };
        let fast = start
            .iter()
            .zip(&limits)
            .any(|(s, l)| !(s.velocity.abs() <= l.v_max * (T::one() + T::lit(64.0) * eps)));
        if fast {
            return false;
        }
        for (i, (s, ki)) in start.iter().zip(k).enumerate() {
            let along = ki * w0;
            let m = s.velocity.abs() + along.abs();
            let slack = if big > T::zero() {
                w0.abs() * (round[i] + ki.abs() * round[l]) / big
            } else {
                T::zero()
            };
            let tol = (T::lit(64.0) * eps * m + slack).min(m / T::lit(1024.0));
            if !((s.velocity - along).abs() <= tol) {
                return false;
            }
        }
        // The line's limits, then each axis within its share of them.
        let mut v = T::INFINITY;
        let mut a = T::INFINITY;
        for (ki, li) in k.iter().zip(&limits) {
            if *ki != T::zero() {
                v = v.min(li.v_max / ki.abs());
                a = a.min(li.a_max / ki.abs());
            }
        }
        let mut scaled = limits;
        let mut line = *own;
        let mut t_line = T::zero();
        for (i, ((ax, ki), s)) in line.iter_mut().zip(k).zip(start).enumerate() {
            let share = Limits::new(v * ki.abs(), a * ki.abs());
            let usable = [share.v_max, share.a_max]
                .iter()
                .all(|x| x.finite() && *x > T::zero());
            if ki != T::zero() && usable {
                scaled[i] = share;
                match OnlineTrapezoid::new_axis(i, s, own[i].target, share) {
                    Ok(p) => *ax = p,
                    Err(_) => return false,
                }
            }
            t_line = t_line.max(ax.duration);
        }
        for (i, (ax, l)) in line.iter_mut().zip(scaled).enumerate() {
            match ax.stretched(i, l, t_line) {
                Ok(p) => *ax = p,
                Err(_) => return false,
            }
        }
        *axes = line;
        true
    }

    /// Duration of the group, in s: the longest axis duration.
    #[must_use]
    pub fn duration(&self) -> T {
        self.duration
    }

    /// The per-axis profiles, in the order given.
    #[must_use]
    pub fn axes(&self) -> &[OnlineTrapezoid<T>; N] {
        &self.axes
    }

    /// The profile of axis `i`, or `None` when `i >= N`.
    #[must_use]
    pub fn axis(&self, i: usize) -> Option<&OnlineTrapezoid<T>> {
        self.axes.get(i)
    }

    /// The synchronisation used: the one asked for, except `Phase` that fell
    /// back to `Time` (velocity not parallel to the displacement, or an axis
    /// faster than its `v_max`); `Phase` for a controlled stop.
    #[must_use]
    pub fn synchronization(&self) -> Synchronization {
        self.sync
    }

    /// The axis with the longest minimum time on its own (for a stop: the
    /// longest stopping time; the first one on a tie), or `None` when no
    /// axis moves.
    #[must_use]
    pub fn lead(&self) -> Option<usize> {
        self.lead
    }

    /// The state of every axis at `t` (s), each by its own profile's conventions.
    #[must_use]
    pub fn sample(&self, t: T) -> [State<T>; N] {
        self.axes.each_ref().map(|p| p.sample(t))
    }
}

impl<T: Real, const N: usize> Motion<T> for OnlineMulti<T, N> {
    type Output = [State<T>; N];
    fn duration(&self) -> T {
        self.duration
    }
    fn sample(&self, t: T) -> [State<T>; N] {
        OnlineMulti::sample(self, t)
    }
}
