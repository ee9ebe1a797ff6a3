//! The camera follows the tips: a view-centring law for the platform's
//! `(psi, theta)` while the instruments move (see `docs/model.md`, *The
//! camera follows the tips*).
//!
//! Each cycle the law is given the time and both tips (mm, fixed frame) and
//! returns the platform's `(psi, theta)` setpoint with its rates and
//! accelerations (`P` and `phi` held, as the paper requires once the
//! instruments are in). It looks at the midpoint of the tips in the image of
//! the camera at the current setpoint (`m = (u, v)`, its radius
//! `|m| = sqrt(u^2 + v^2)` in normalised image units) and moves through
//! three phases, with the dead zones and hysteresis of the autocamera work:
//!
//! | phase | the platform | leaves it when |
//! |---|---|---|
//! | `Idle` | holds | `|m| > outer_radius`, or a tip is near the edge |
//! | `Armed` | holds | the tips have been still for `dwell_s` (or at once, a tip near the edge): `Recentring`; `|m| <= inner_radius` again: `Idle` |
//! | `Recentring` | turns to the look-at of the midpoint | the turn has ended on its goal: `Idle` |
//!
//! A tip is *near the edge* when `max(|u|, |v|) > edge` or it is behind the
//! camera: the law then recentres at once, without the dwell, since waiting
//! would lose the tip from the picture. A recentring aims the view axis at
//! the midpoint in closed form ([`Camera::look_at`], the solution nearest
//! the current angles) and reaches it with the online time-optimal profile
//! ([`OnlineMulti`], both angles synchronised, within `limits`), replanned
//! from the current moving state when the look-at goal moves by more than
//! `retarget` (the tips moving while the camera turns). Between `inner_radius`
//! and `outer_radius` nothing starts (the hysteresis band): small motions of
//! the instruments never move the picture.
//!
//! `#![no_std]`, allocation-free, `f32` or `f64`; every error typed
//! ([`FollowError`]).
//!
//! ```
//! use parasils::follow::{Follow, FollowParams, FollowPhase};
//! use parasils::kin::nalgebra::Vector3;
//! use parasils::kin::{Camera, Pose};
//!
//! let pose = Pose::<f64>::paper_start();
//! let depth = 60.0;
//! let mut law = Follow::new(Camera::assumed(), FollowParams::assumed(), pose, depth)?;
//! // Tips far to one side of the view, held still: one is near the edge,
//! // so the law turns at once, until the midpoint is on the view axis.
//! let tips = [Vector3::new(40.0, 30.0, -640.0), Vector3::new(60.0, 30.0, -640.0)];
//! let mut t = 0.0;
//! let mut step = law.step(t, &tips)?;
//! assert_eq!(step.phase, FollowPhase::Recentring);
//! while t < 20.0 {
//!     t += 1e-3;
//!     step = law.step(t, &tips)?;
//! }
//! assert_eq!(step.phase, FollowPhase::Idle);
//! assert!(step.midpoint.u.abs() < 1e-9 && step.midpoint.v.abs() < 1e-9);
//! assert_eq!(step.angles[0].velocity, 0.0);
//! # Ok::<(), parasils::follow::FollowError>(())
//! ```

use crate::Real;
use crate::kin::nalgebra::Vector3;
use crate::kin::{Camera, CameraError, ImagePoint, PlatformFrame, PlatformState, Pose};
use crate::traj::{Limits, OnlineMulti, State, Synchronization};

/// The follow law's parameters. Radii and the edge are in normalised image
/// units (`u`, `v` run from -1 to +1 across the image).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowParams<T> {
    /// The inner dead zone's radius: a pending recentring is dropped when
    /// the midpoint comes back within it (**assumed** 0.1).
    pub inner_radius: T,
    /// The trigger zone's radius: the midpoint beyond it arms a recentring
    /// (**assumed** 0.3).
    pub outer_radius: T,
    /// A tip with `max(|u|, |v|)` beyond this recentres at once, without
    /// the dwell (**assumed** 0.6).
    pub edge: T,
    /// How long the tips must have been still before an armed recentring
    /// starts, s (**assumed** 0.25 s).
    pub dwell_s: T,
    /// A tip slower than this counts as still, mm/s (**assumed** 0.5 mm/s).
    pub still_mm_s: T,
    /// A recentring is replanned when its look-at goal moves by more than
    /// this in `psi` or `theta`, rad (**assumed** 1e-3 rad, 0.057 deg).
    pub retarget_rad: T,
    /// The platform's angular limits for `psi` and `theta`, rad/s and
    /// rad/s^2 (default the paper's 10 deg/s and 5 deg/s^2).
    pub limits: Limits<T>,
}

impl<T: Real> FollowParams<T> {
    /// The assumed defaults (see each field and `docs/model.md`).
    pub fn assumed() -> Self {
        Self {
            inner_radius: T::lit(0.1),
            outer_radius: T::lit(0.3),
            edge: T::lit(0.6),
            dwell_s: T::lit(0.25),
            still_mm_s: T::lit(0.5),
            retarget_rad: T::lit(1e-3),
            limits: Limits::new(
                T::lit(crate::paper::OMEGA_MAX_DEG_S.to_radians()),
                T::lit(crate::paper::EPS_MAX_DEG_S2.to_radians()),
            ),
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`FollowError::InvalidParameter`] naming the first that is not
    /// finite or out of its range: `0 <= inner_radius <= outer_radius`,
    /// `0 < edge`, `dwell_s >= 0`, `still_mm_s > 0`, `retarget_rad > 0`,
    /// positive limits.
    pub fn validate(&self) -> Result<(), FollowError> {
        let zero = T::zero();
        let checks = [
            (
                "inner_radius",
                self.inner_radius,
                self.inner_radius >= zero,
                "at least 0",
            ),
            (
                "outer_radius",
                self.outer_radius,
                self.outer_radius >= self.inner_radius,
                "at least inner_radius",
            ),
            ("edge", self.edge, self.edge > zero, "above 0"),
            ("dwell_s", self.dwell_s, self.dwell_s >= zero, "at least 0"),
            (
                "still_mm_s",
                self.still_mm_s,
                self.still_mm_s > zero,
                "above 0",
            ),
            (
                "retarget_rad",
                self.retarget_rad,
                self.retarget_rad > zero,
                "above 0",
            ),
            (
                "limits.v_max",
                self.limits.v_max,
                self.limits.v_max > zero,
                "above 0",
            ),
            (
                "limits.a_max",
                self.limits.a_max,
                self.limits.a_max > zero,
                "above 0",
            ),
        ];
        for (what, value, ok, why) in checks {
            if !(value.finite() && ok) {
                return Err(FollowError::InvalidParameter {
                    what,
                    value: value.to_f64(),
                    why,
                });
            }
        }
        Ok(())
    }
}

/// Where the law is (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FollowPhase {
    /// The platform holds; the midpoint is within the trigger zone.
    Idle,
    /// The midpoint left the trigger zone: the platform holds until the
    /// tips have been still for the dwell.
    Armed,
    /// The platform turns to aim the camera at the midpoint.
    Recentring,
}

/// Why the law cannot take a cycle.
///
/// # When this happens / how to handle it
/// A parameter or an input that is not finite is a caller's bug; a
/// [`FollowError::Camera`] means the midpoint cannot be looked at from this
/// port (behind the endoscope's tip, or at the gimbal's `cos theta = 0`):
/// hold the platform where the last cycle left it and tell the surgeon.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FollowError {
    /// A parameter out of its range.
    #[error("follow: {what} = {value} is not valid: {why}")]
    InvalidParameter {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The range it must be in.
        why: &'static str,
    },
    /// A NaN or an infinity among the inputs.
    #[error("follow: non-finite input: {what} = {value}")]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// A time before the last one given.
    #[error("follow: the time {t} s is before {last} s, the latest time given")]
    TimeReversed {
        /// The time given, s.
        t: f64,
        /// The latest time given before, s.
        last: f64,
    },
    /// The midpoint cannot be looked at (see [`CameraError`]).
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The recentring's profile cannot be planned.
    #[error(transparent)]
    Trajectory(#[from] crate::traj::Error),
}

/// What one cycle of the law gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowStep<T> {
    /// The setpoint of `[psi, theta]`, rad, with rates (rad/s) and
    /// accelerations (rad/s^2).
    pub angles: [State<T>; 2],
    /// The phase after this cycle.
    pub phase: FollowPhase,
    /// Where the midpoint of the tips falls in the image of the camera at
    /// the setpoint given (after this cycle's turn).
    pub midpoint: ImagePoint<T>,
    /// Whether a recentring was planned or replanned in this cycle.
    pub replanned: bool,
}

/// The follow law's state: the current setpoint and the recentring under
/// way (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Follow<T: Real> {
    camera: Camera<T>,
    params: FollowParams<T>,
    /// `P` and `phi` held; `psi`, `theta` where the law started.
    pose: Pose<T>,
    depth: T,
    /// The current setpoint.
    angles: [State<T>; 2],
    phase: FollowPhase,
    /// The recentring: its profile, its start time (s) and its goal (rad).
    turn: Option<(OnlineMulti<T, 2>, T, [T; 2])>,
    /// The last cycle's time (s) and tips.
    last: Option<(T, [Vector3<T>; 2])>,
    /// Since when both tips have been still, s.
    still_since: Option<T>,
}

fn finite<T: Real>(what: &'static str, v: T) -> Result<T, FollowError> {
    if v.finite() {
        Ok(v)
    } else {
        Err(FollowError::NonFinite {
            what,
            value: v.to_f64(),
        })
    }
}

impl<T: Real> Follow<T> {
    /// The law at rest at `pose` (its `P` and `phi` are held), the camera at
    /// the endoscope's `depth` (mm).
    ///
    /// # Errors
    /// [`FollowError::InvalidParameter`] for invalid parameters (or
    /// [`FollowError::Camera`] for an invalid camera),
    /// [`FollowError::NonFinite`] for a non-finite pose or depth.
    pub fn new(
        camera: Camera<T>,
        params: FollowParams<T>,
        pose: Pose<T>,
        depth: T,
    ) -> Result<Self, FollowError> {
        camera.validate()?;
        params.validate()?;
        for (what, v) in [
            ("pose.x", pose.x),
            ("pose.y", pose.y),
            ("pose.z", pose.z),
            ("pose.psi", pose.psi),
            ("pose.theta", pose.theta),
            ("pose.phi", pose.phi),
            ("depth", depth),
        ] {
            finite(what, v)?;
        }
        Ok(Self {
            camera,
            params,
            pose,
            depth,
            angles: [State::rest(pose.psi), State::rest(pose.theta)],
            phase: FollowPhase::Idle,
            turn: None,
            last: None,
            still_since: None,
        })
    }

    /// The same law taking over a turn under way: the profile `turn` of
    /// `[psi, theta]` (rad) started at `start` (s), as if it were a
    /// recentring this law had planned, its setpoint `turn`'s state at `t`
    /// (s). While `turn` has not ended at `t`, the law is `Recentring`, so
    /// that its next cycle aims at the tips' midpoint from that moving state
    /// (replanned unless `turn` already aims there); once it has ended, the
    /// law rests at its goal, `Idle`. For a controller that hands its
    /// motion to the law ([`OnlineController::follow`]).
    ///
    /// [`OnlineController::follow`]: crate::OnlineController::follow
    #[must_use]
    pub fn taking_over(mut self, t: T, turn: OnlineMulti<T, 2>, start: T) -> Self {
        let goal = turn.axes().each_ref().map(|a| a.target());
        if t - start >= turn.duration() {
            self.angles = goal.map(State::rest);
            self.phase = FollowPhase::Idle;
            self.turn = None;
        } else {
            self.angles = turn.sample(t - start);
            self.phase = FollowPhase::Recentring;
            self.turn = Some((turn, start, goal));
        }
        self
    }

    /// The recentring under way: its profile of `[psi, theta]` (rad, in s
    /// from its start) and its start time (s); `None` when the law holds.
    pub fn recentring(&self) -> Option<(&OnlineMulti<T, 2>, T)> {
        self.turn
            .as_ref()
            .map(|(profile, start, _)| (profile, *start))
    }

    /// Moves the law's clock origin to `origin` (s): every later time is
    /// given from there (see [`OnlineController::rebase`]).
    ///
    /// [`OnlineController::rebase`]: crate::OnlineController::rebase
    pub fn rebase(&mut self, origin: T) {
        if let Some((_, start, _)) = &mut self.turn {
            *start -= origin;
        }
        if let Some((last, _)) = &mut self.last {
            *last -= origin;
        }
        if let Some(since) = &mut self.still_since {
            *since -= origin;
        }
    }

    /// The law's parameters.
    pub fn params(&self) -> &FollowParams<T> {
        &self.params
    }

    /// The phase the last cycle left.
    pub fn phase(&self) -> FollowPhase {
        self.phase
    }

    /// The current setpoint of `[psi, theta]` (rad, with rates).
    pub fn angles(&self) -> [State<T>; 2] {
        self.angles
    }

    /// Whether the platform rests and no recentring is pending.
    pub fn is_idle(&self) -> bool {
        self.phase == FollowPhase::Idle
    }

    /// The platform's pose at the setpoint `angles`.
    fn pose_at(&self, angles: [T; 2]) -> Pose<T> {
        Pose {
            psi: angles[0],
            theta: angles[1],
            ..self.pose
        }
    }

    fn frame_at(&self, angles: [T; 2]) -> PlatformFrame<T> {
        PlatformFrame::new(&PlatformState::at_rest(self.pose_at(angles)))
    }

    /// One cycle at time `t` (s, never decreasing) with the tips at `tips`
    /// (`[left, right]`, mm, fixed frame): the platform's setpoint.
    ///
    /// # Errors
    /// [`FollowError::NonFinite`] for a non-finite time or tip,
    /// [`FollowError::TimeReversed`] for a time before the last one,
    /// [`FollowError::Camera`] when the midpoint cannot be looked at,
    /// [`FollowError::Trajectory`] when the turn cannot be planned. The
    /// state is unchanged by a cycle that fails.
    pub fn step(&mut self, t: T, tips: &[Vector3<T>; 2]) -> Result<FollowStep<T>, FollowError> {
        finite("t", t)?;
        for (what, v) in [
            ("left tip x", tips[0].x),
            ("left tip y", tips[0].y),
            ("left tip z", tips[0].z),
            ("right tip x", tips[1].x),
            ("right tip y", tips[1].y),
            ("right tip z", tips[1].z),
        ] {
            finite(what, v)?;
        }
        let mut still_since = self.still_since;
        match self.last {
            Some((last, _)) if t < last => {
                return Err(FollowError::TimeReversed {
                    t: t.to_f64(),
                    last: last.to_f64(),
                });
            }
            Some((last, before)) if t > last => {
                let dt = t - last;
                let moved = (tips[0] - before[0])
                    .norm()
                    .max((tips[1] - before[1]).norm());
                if moved > self.params.still_mm_s * dt {
                    still_since = None;
                } else if still_since.is_none() {
                    still_since = Some(last);
                }
            }
            Some(_) => {}
            // The first cycle: the law starts at rest, the tips taken as
            // still from here.
            None => still_since = Some(t),
        }
        let midpoint = (tips[0] + tips[1]) * T::lit(0.5);
        // Where the tips are at the setpoint the last cycle left.
        let held = self.angles.map(|a| a.position);
        let frame = self.frame_at(held);
        let seen = |p: &Vector3<T>| self.camera.project(&frame, self.depth, p);
        let near_edge = |s: ImagePoint<T>| {
            !s.in_front || s.u.abs().max(s.v.abs()) > self.params.edge || !s.u.finite()
        };
        let urgent = near_edge(seen(&tips[0])) || near_edge(seen(&tips[1]));
        let m = seen(&midpoint);
        let radius = if m.in_front {
            (m.u * m.u + m.v * m.v).sqrt()
        } else {
            T::lit(f64::INFINITY)
        };
        let outside = !(radius <= self.params.outer_radius);
        let mut phase = self.phase;
        if phase == FollowPhase::Idle && (outside || urgent) {
            phase = FollowPhase::Armed;
        }
        if phase == FollowPhase::Armed {
            let dwelt = still_since.is_some_and(|s| t - s >= self.params.dwell_s);
            if urgent || dwelt {
                phase = FollowPhase::Recentring;
            } else if radius <= self.params.inner_radius {
                phase = FollowPhase::Idle;
            }
        }
        let mut turn = self.turn;
        let mut replanned = false;
        let mut angles = self.angles;
        if phase == FollowPhase::Recentring {
            // Where the current turn has the platform now.
            let now = match &turn {
                Some((profile, t0, _)) => profile.sample(t - *t0),
                None => self.angles.map(|a| State::rest(a.position)),
            };
            let pose = self.pose_at(now.map(|a| a.position));
            let goal = self.camera.look_at(&pose, self.depth, &midpoint)?;
            let moved = |g: &[T; 2]| {
                (goal[0] - g[0]).abs().max((goal[1] - g[1]).abs()) > self.params.retarget_rad
            };
            if turn.as_ref().is_none_or(|(_, _, g)| moved(g)) {
                let start = now.map(|a| State {
                    acceleration: T::zero(),
                    ..a
                });
                let profile =
                    OnlineMulti::new(start, goal, [self.params.limits; 2], Synchronization::Phase)?;
                turn = Some((profile, t, goal));
                replanned = true;
                angles = profile.sample(T::zero());
            } else {
                angles = now;
            }
            if let Some((profile, t0, _)) = &turn
                && !replanned
                && t - *t0 >= profile.duration()
            {
                // On the goal, at rest: the recentring is over.
                angles = profile
                    .sample(profile.duration())
                    .map(|a| State::rest(a.position));
                turn = None;
                phase = FollowPhase::Idle;
            }
        }
        let after = angles.map(|a| a.position);
        let midpoint = if after == held {
            // The platform held: the image is the one already seen.
            m
        } else {
            self.camera
                .project(&self.frame_at(after), self.depth, &midpoint)
        };
        self.angles = angles;
        self.phase = phase;
        self.turn = turn;
        self.last = Some((t, *tips));
        self.still_since = still_since;
        Ok(FollowStep {
            angles,
            phase,
            midpoint,
            replanned,
        })
    }
}
