//! From a trajectory to the controller: motion type 4, the endoscope
//! reorientation, as a sequence of platform states.
//!
//! A [`Reorientation`] is a start pose and a synchronised two-axis profile of
//! `(psi, theta)`; `P` and `phi` stay at the start. [`Reorientation::state_at`]
//! gives the [`PlatformState`] (pose, Euler rates, Euler accelerations) at any
//! time, which is exactly what [`Controller::step`](crate::kin::Controller::step)
//! takes; [`Reorientation::sampler`] yields those states at a fixed rate,
//! `t_k = k / rate`, the last one exactly at the goal (see
//! [`parasils_traj::sampler`]).
//!
//! Everything is `no_std`, allocation-free and generic over `f32`/`f64`: the
//! firmware, the simulation engine, the benchmarks and the tests all step the
//! controller through this one bridge.
//!
//! ```
//! use parasils::Reorientation;
//! use parasils::kin::{Controller, MarginTracker, TipTargets};
//!
//! let motion = Reorientation::<f64>::paper()?;
//! assert_eq!(motion.duration(), 4.5);
//! let controller = Controller::paper();
//! let mut tracker = MarginTracker::new();
//! let tips = TipTargets::paper();
//! let mut drift = 0.0_f64;
//! for sample in motion.sampler(1000.0)? {
//!     let out = controller.step(&sample.state, &tips, &mut tracker)?;
//!     let tip = out.frame.to_fixed(&controller.left.fk_platform(&out.left.q));
//!     drift = drift.max((tip - tips.left).norm());
//! }
//! assert!(drift < 1e-9); // mm: the left tip held still along the whole turn
//! # Ok::<(), parasils::Error>(())
//! ```

use crate::Real;
use crate::kin::{PlatformState, Pose};
use crate::paper;
use crate::traj::{Limits, Motion, Multi, Sampler, State, Synchronization};

/// Motion type 4: the platform turns in `(psi, theta)` from a start pose along
/// a synchronised rest-to-rest profile; `P` and `phi` stay still.
///
/// Units as in the libraries: mm, rad, s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reorientation<T: Real> {
    start: Pose<T>,
    motion: Multi<T, 2>,
}

impl<T: Real> Reorientation<T> {
    /// Plans the turn from `start` to the final angles `goal = [psi, theta]`
    /// (rad), each angle within its `limits` (rad/s, rad/s^2), the two timed
    /// together as `sync` says.
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for non-finite angles or invalid limits.
    pub fn new(
        start: Pose<T>,
        goal: [T; 2],
        limits: [Limits<T>; 2],
        sync: Synchronization,
    ) -> Result<Self, crate::traj::Error> {
        let motion = Multi::new([start.psi, start.theta], goal, limits, sync)?;
        Ok(Self { start, motion })
    }

    /// The paper's reorientation ([`crate::paper`]): from
    /// [`Pose::paper_start`], `psi` +15 deg and `theta` +25 deg, 10 deg/s and
    /// 5 deg/s^2, phase-synchronised; 4.5 s.
    ///
    /// # Errors
    /// None in practice (the paper's numbers are valid); the planner's
    /// `Result` is passed on rather than unwrapped, so that no panic path is
    /// linked into firmware.
    pub fn paper() -> Result<Self, crate::traj::Error> {
        let start = Pose::<T>::paper_start();
        let rad = |deg: f64| <T as crate::kin::Real>::lit(deg.to_radians());
        Self::new(
            start,
            [
                start.psi + rad(paper::PSI_DEG),
                start.theta + rad(paper::THETA_DEG),
            ],
            [Limits::new(rad(paper::OMEGA_MAX_DEG_S), rad(paper::EPS_MAX_DEG_S2)); 2],
            Synchronization::Phase,
        )
    }

    /// The platform's pose at `t = 0`.
    pub fn start(&self) -> &Pose<T> {
        &self.start
    }

    /// The final `[psi, theta]`, rad.
    pub fn goal(&self) -> [T; 2] {
        let [psi, theta] = self.motion.sample(self.motion.duration());
        [psi.position, theta.position]
    }

    /// The `(psi, theta)` profile.
    pub fn profile(&self) -> &Multi<T, 2> {
        &self.motion
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.motion.duration()
    }

    /// The platform's state at `t` (s): at rest at the start for `t <= 0`, at
    /// rest at the goal for `t >= duration`.
    pub fn state_at(&self, t: T) -> PlatformState<T> {
        self.platform_state(self.motion.sample(t))
    }

    /// The states at `t_k = k / rate_hz`, `k = 0..=n`, the last exactly at
    /// the goal (see [`parasils_traj::sampler`]): each item's `state` is the
    /// [`PlatformState`] and its `time` is `t_k`.
    ///
    /// # Errors
    /// [`parasils_traj::Error::InvalidRate`] for a rate that is not positive
    /// and finite, [`parasils_traj::Error::TooManySamples`] when the count
    /// does not fit `usize`.
    pub fn sampler(self, rate_hz: T) -> Result<Sampler<T, Self>, crate::traj::Error> {
        Sampler::new(self, rate_hz)
    }

    fn platform_state(&self, angles: [State<T>; 2]) -> PlatformState<T> {
        turned(&self.start, angles)
    }
}

/// The platform at `start` turned to the `(psi, theta)` of `angles`, with
/// their rates and accelerations: motion type 4's state (`P` and `phi` of
/// `start`, at rest). The one place a profile sample becomes a
/// [`PlatformState`]; the [`OnlineController`](crate::OnlineController)
/// uses it too.
pub(crate) fn turned<T: Real>(start: &Pose<T>, [psi, theta]: [State<T>; 2]) -> PlatformState<T> {
    let mut pose = *start;
    pose.psi = psi.position;
    pose.theta = theta.position;
    PlatformState::reorientation(
        pose,
        [psi.velocity, theta.velocity],
        [psi.acceleration, theta.acceleration],
    )
}

impl<T: Real> Motion<T> for Reorientation<T> {
    type Output = PlatformState<T>;

    fn duration(&self) -> T {
        self.motion.duration()
    }

    fn sample(&self, t: T) -> PlatformState<T> {
        self.state_at(t)
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp, reason = "exactness is what these tests check")]
mod tests {
    use super::*;

    #[test]
    fn paper_turn_starts_and_ends_at_rest_on_its_poses() -> Result<(), crate::traj::Error> {
        let m = Reorientation::<f64>::paper()?;
        let p0 = Pose::<f64>::paper_start();
        assert_eq!(m.state_at(0.0), PlatformState::at_rest(p0));
        let end = m.state_at(4.5);
        assert_eq!(end.pose.psi, p0.psi + 15f64.to_radians(), "psi at the goal");
        assert_eq!(end.pose.theta, p0.theta + 25f64.to_radians());
        assert_eq!(
            (end.pose.x, end.pose.y, end.pose.z, end.pose.phi),
            (p0.x, p0.y, p0.z, p0.phi)
        );
        assert_eq!(end.velocity.psi, 0.0);
        assert_eq!(end.acceleration.theta, 0.0);
        assert_eq!(m.goal(), [end.pose.psi, end.pose.theta]);
        Ok(())
    }

    #[test]
    fn mid_turn_state_is_the_profile_on_the_start_pose() -> Result<(), crate::traj::Error> {
        // t = 1 s: both angles accelerating (theta at 5 deg/s^2, psi at 3).
        let m = Reorientation::<f64>::paper()?;
        let s = m.state_at(1.0);
        let [psi, theta] = m.profile().sample(1.0);
        assert_eq!((s.pose.psi, s.pose.theta), (psi.position, theta.position));
        assert_eq!(
            (s.velocity.psi, s.velocity.theta),
            (psi.velocity, theta.velocity)
        );
        assert_eq!(
            (s.acceleration.psi, s.acceleration.theta),
            (psi.acceleration, theta.acceleration)
        );
        assert_eq!(
            (s.velocity.phi, s.velocity.x, s.acceleration.z),
            (0.0, 0.0, 0.0)
        );
        assert!((theta.acceleration.to_degrees() - 5.0).abs() < 1e-12);
        assert!((psi.acceleration.to_degrees() - 3.0).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn sampler_yields_4501_states_ending_on_the_goal() -> Result<(), crate::traj::Error> {
        let m = Reorientation::<f32>::paper()?;
        let samples = m.sampler(1000.0)?;
        assert_eq!(samples.len(), 4501);
        let last = samples
            .last()
            .ok_or(crate::traj::Error::InvalidRate { value: 0.0 })?;
        assert_eq!(last.state, m.state_at(m.duration()));
        assert_eq!(last.state.velocity.psi, 0.0);
        Ok(())
    }
}
