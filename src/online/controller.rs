//! The online controller's state, its construction and what it reports
//! between cycles; its commands and its cycle are its siblings
//! (`command`, `tick`).

use super::setpoint::MotionKind;
use super::watch::{ClearanceWatch, GapTrack, Watched, gap_array};
use crate::Real;
use crate::error::Error;
use crate::follow::{Follow, FollowPhase};
use crate::kin::{
    Bodies, Clearance, ControlStep, Controller, MarginTracker, ModuleCommand, PlatformState, Pose,
    TipMotion, TipTargets,
};
use crate::reorientation::turned;
use crate::supervisor::{Margins, Supervisor};
use crate::traj::{Limits, OnlineMulti, State, Synchronization};

/// The largest move of a tip (mm, fixed frame) one
/// [`set_tips`](OnlineController::set_tips) or
/// [`move_tips`](OnlineController::move_tips) accepts by default: 1 mm, a
/// tip at 1 m/s on a 1 kHz loop (**assumed**; change it with
/// [`with_max_tip_step`](OnlineController::with_max_tip_step)).
pub const MAX_TIP_STEP_MM: f64 = 1.0;

/// The per-cycle controller of motion type 4 with online goals, stops, tips
/// that move, a camera that follows them, and a supervisor (see the [module
/// docs](crate::online)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnlineController<T: Real> {
    pub(super) controller: Controller<T>,
    /// Module 1's weakest direction from the previous cycle.
    pub(super) tracker: MarginTracker<T>,
    /// The tips' positions, mm, fixed frame.
    pub(super) tips: TipTargets<T>,
    /// The tips with their velocities and accelerations, fixed frame.
    pub(super) tip_motion: [TipMotion<T>; 2],
    /// The largest move of a tip one call accepts, mm.
    pub(super) max_tip_step: T,
    /// `P` and `phi` (fixed), and the `(psi, theta)` of the start.
    pub(super) pose: Pose<T>,
    pub(super) limits: [Limits<T>; 2],
    pub(super) supervisor: Supervisor<T>,
    pub(super) motion: OnlineMulti<T, 2>,
    /// Where the active motion starts on the controller's clock, s.
    pub(super) start: T,
    pub(super) kind: MotionKind,
    /// Motions accepted (commands, stops, follow modes).
    pub(super) accepted: u32,
    /// The latest time given to any call, s.
    pub(super) last: Option<T>,
    /// The previous tick's time and margins, and the rates from the tick before.
    pub(super) previous: Option<(T, Margins<T>)>,
    pub(super) rates: Margins<T>,
    /// The clearance watched, if any.
    pub(super) clearance: Option<Watched<T>>,
    /// The endoscope's insertion below `P`, mm, for look-at commands and
    /// the follow law.
    pub(super) depth: Option<T>,
    /// The follow law while the camera follows the tips.
    pub(super) follow: Option<Follow<T>>,
}

impl<T: Real> OnlineController<T> {
    /// At rest at `pose` (mm, rad), holding `tips` still, with the
    /// `[psi, theta]` `limits` (rad/s, rad/s^2) and the margin `supervisor`.
    ///
    /// Solves the kinematics at `pose` once: it must be reachable, and this
    /// is the full singular value decomposition that seeds module 1's margin
    /// tracker, so that no cycle of the loop needs one.
    ///
    /// # Errors
    /// [`Error::InvalidThreshold`] for a supervisor threshold not above the
    /// solvers' hard one ([`Supervisor::validate`]); [`Error::Trajectory`]
    /// for invalid limits or a non-finite angle; [`Error::Kinematics`] when
    /// `pose` cannot be solved.
    pub fn new(
        controller: Controller<T>,
        tips: TipTargets<T>,
        pose: Pose<T>,
        limits: [Limits<T>; 2],
        supervisor: Supervisor<T>,
    ) -> Result<Self, Error> {
        supervisor.validate(&Margins::hard(&controller))?;
        let angles = [pose.psi, pose.theta];
        let motion = OnlineMulti::new(
            angles.map(State::rest),
            angles,
            limits,
            Synchronization::Phase,
        )?;
        let mut tracker = MarginTracker::new();
        controller.step(&PlatformState::at_rest(pose), &tips, &mut tracker)?;
        Ok(Self {
            controller,
            tracker,
            tips,
            tip_motion: [TipMotion::still(tips.left), TipMotion::still(tips.right)],
            max_tip_step: T::lit(MAX_TIP_STEP_MM),
            pose,
            limits,
            supervisor,
            motion,
            start: T::zero(),
            kind: MotionKind::Rest,
            accepted: 0,
            last: None,
            previous: None,
            rates: Margins::splat(T::zero()),
            clearance: None,
            depth: None,
            follow: None,
        })
    }

    /// The same controller with the endoscope inserted `depth` mm below
    /// `P` along `-Z'`: where its camera sits for
    /// [`command_look_at`](Self::command_look_at) and
    /// [`follow`](Self::follow).
    /// [`with_clearance`](Self::with_clearance) sets it too, from
    /// [`ClearanceWatch::endoscope_depth`].
    ///
    /// # Errors
    /// [`Error::Kinematics`] (`InvalidParameter "endoscope.depth"`) for a
    /// depth that is not finite or outside the endoscope's range.
    pub fn with_endoscope_depth(mut self, depth: T) -> Result<Self, Error> {
        let range = self.controller.endoscope.depth;
        if !(depth.finite() && depth >= range.min && depth <= range.max) {
            return Err(crate::kin::Error::InvalidParameter {
                what: "endoscope.depth",
                value: depth.to_f64(),
            }
            .into());
        }
        self.depth = Some(depth);
        Ok(self)
    }

    /// The same controller accepting tips that move by at most `max_mm`
    /// (mm, fixed frame) in one [`set_tips`](Self::set_tips) or
    /// [`move_tips`](Self::move_tips) (default [`MAX_TIP_STEP_MM`]).
    ///
    /// # Errors
    /// [`Error::Kinematics`] (`InvalidParameter "online.max_tip_step_mm"`)
    /// for a step that is not finite and above 0.
    pub fn with_max_tip_step(mut self, max_mm: T) -> Result<Self, Error> {
        if !(max_mm.finite() && max_mm > T::zero()) {
            return Err(crate::kin::Error::InvalidParameter {
                what: "online.max_tip_step_mm",
                value: max_mm.to_f64(),
            }
            .into());
        }
        self.max_tip_step = max_mm;
        Ok(self)
    }

    /// The endoscope's depth the look-at commands and the follow law use,
    /// mm (`None` when none was given).
    pub fn endoscope_depth(&self) -> Option<T> {
        self.depth
    }

    /// The same controller watching the clearance between the bodies of
    /// `watch`: every tick computes the three surface gaps
    /// ([`Bodies::clearance`]) and the supervisor demands a controlled stop
    /// for a decreasing gap that would end below the stop threshold
    /// ([`ClearanceThresholds::check_ahead`]), as it does for the margins;
    /// [`tick_with`](Self::tick_with) does the same for the gap to
    /// forbidden regions. Called before the first tick (the gaps' rates
    /// start from the next tick).
    ///
    /// # Errors
    /// [`Error::InvalidClearanceThreshold`] for a threshold that is not
    /// finite or a warning below the stop one; [`Error::Kinematics`] for an
    /// invalid size or a non-finite depth (the bodies are placed once at
    /// the current pose to check them).
    ///
    /// [`ClearanceThresholds::check_ahead`]: crate::supervisor::ClearanceThresholds::check_ahead
    pub fn with_clearance(mut self, watch: ClearanceWatch<T>) -> Result<Self, Error> {
        watch.thresholds.validate()?;
        let mut tracker = self.tracker;
        let t = self.last.unwrap_or(self.start);
        let step = self.solve(&self.state_at(t), &mut tracker)?;
        let gaps = self.gaps(&watch, &step)?;
        let mut pairs = GapTrack::new();
        // Where it rests now: a first command looks ahead only near the
        // stop threshold (the rates start from two ticks).
        pairs.previous = Some(gap_array(&gaps));
        self.clearance = Some(Watched {
            watch,
            pairs,
            regions: [GapTrack::new(); 3],
            period: None,
            probe: None,
        });
        self.depth = Some(watch.endoscope_depth);
        Ok(self)
    }

    /// The clearance watched (`None` when none is).
    pub fn clearance_watch(&self) -> Option<&ClearanceWatch<T>> {
        self.clearance.as_ref().map(|w| &w.watch)
    }

    /// The index of the active motion: 0 for the first one (and before any),
    /// one more at each command, each stop and each start of the follow
    /// mode after it, a stop the supervisor demanded included (the follow
    /// law's own recentrings do not count).
    pub fn command_index(&self) -> u32 {
        self.accepted.saturating_sub(1)
    }

    /// What the active motion is.
    pub fn kind(&self) -> MotionKind {
        self.kind
    }

    /// The follow law's phase while the camera follows the tips (`None`
    /// otherwise; see [`follow`](Self::follow)).
    pub fn follow_phase(&self) -> Option<FollowPhase> {
        self.follow.as_ref().map(Follow::phase)
    }

    /// The follow law while the camera follows the tips.
    pub fn follow_law(&self) -> Option<&Follow<T>> {
        self.follow.as_ref()
    }

    /// Whether the active motion has ended at `t` (s): the platform rests at
    /// its goal. `false` for a NaN `t`.
    pub fn is_at_rest(&self, t: T) -> bool {
        t - self.start >= self.motion.duration()
    }

    /// The platform's state at `t` (s) along the active motion: its start
    /// state before it begins, its goal at rest after it ends.
    pub fn state_at(&self, t: T) -> PlatformState<T> {
        self.platform(self.angles_at(t))
    }

    /// The active motion of `[psi, theta]`, in s from
    /// [`motion_start`](Self::motion_start).
    pub fn motion(&self) -> &OnlineMulti<T, 2> {
        &self.motion
    }

    /// When the active motion started on the controller's clock, s.
    pub fn motion_start(&self) -> T {
        self.start
    }

    /// When the active motion ends on the controller's clock, s.
    pub fn motion_end(&self) -> T {
        self.start + self.motion.duration()
    }

    /// The goal `[psi, theta]` of the active motion, rad: where it rests.
    pub fn goal(&self) -> [T; 2] {
        self.motion.axes().each_ref().map(|a| a.target())
    }

    /// The synchronisation the active motion uses.
    pub fn synchronization(&self) -> Synchronization {
        self.motion.synchronization()
    }

    /// The kinematics.
    pub fn controller(&self) -> &Controller<T> {
        &self.controller
    }

    /// Module 1's weakest direction from the previous cycle, and how many
    /// margins took the full decomposition (see
    /// [`MarginTracker`]).
    pub fn margin_tracker(&self) -> &MarginTracker<T> {
        &self.tracker
    }

    /// The tips the next cycles put the instruments at, mm, fixed frame.
    pub fn tips(&self) -> &TipTargets<T> {
        &self.tips
    }

    /// The tips with their velocities (mm/s) and accelerations (mm/s^2),
    /// fixed frame, `[left, right]`.
    pub fn tip_motion(&self) -> &[TipMotion<T>; 2] {
        &self.tip_motion
    }

    /// The largest move of a tip one call accepts, mm.
    pub fn max_tip_step(&self) -> T {
        self.max_tip_step
    }

    /// The `[psi, theta]` limits, rad/s and rad/s^2.
    pub fn limits(&self) -> &[Limits<T>; 2] {
        &self.limits
    }

    /// The margin supervisor.
    pub fn supervisor(&self) -> &Supervisor<T> {
        &self.supervisor
    }

    /// The latest time given to any call, s (`None` before the first).
    pub fn last_time(&self) -> Option<T> {
        self.last
    }

    /// Moves the clock's origin to `origin` (s, a time on the clock so far):
    /// every later call gives its time from there, so that `t - origin`
    /// becomes `t`. For a long-running `f32` loop (see the
    /// [module docs](crate::online), *Time*): rebase from time to time, for
    /// example to the current cycle, and count the cycles from 0 again (the
    /// follow law's clock moves with it).
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`] for a NaN or infinite `origin`; the
    /// controller is then unchanged.
    pub fn rebase(&mut self, origin: T) -> Result<(), Error> {
        if !origin.finite() {
            return Err(Error::NonFiniteTime {
                value: origin.to_f64(),
            });
        }
        self.start -= origin;
        self.last = self.last.map(|t| t - origin);
        self.previous = self.previous.map(|(t, m)| (t - origin, m));
        if let Some(w) = &mut self.clearance
            && let Some((t, rates)) = w.probe
        {
            w.probe = Some((t - origin, rates));
        }
        if let Some(law) = &mut self.follow {
            law.rebase(origin);
        }
        Ok(())
    }

    pub(super) fn check_time(&self, t: T) -> Result<(), Error> {
        if !t.finite() {
            return Err(Error::NonFiniteTime { value: t.to_f64() });
        }
        match self.last {
            Some(last) if t < last => Err(Error::TimeReversed {
                t: t.to_f64(),
                last: last.to_f64(),
            }),
            _ => Ok(()),
        }
    }

    /// A new active motion from `t`, accepted (a command, a stop, a stop
    /// the supervisor demanded): the follow mode ends.
    pub(super) fn begin(&mut self, t: T, motion: OnlineMulti<T, 2>, kind: MotionKind) {
        self.motion = motion;
        self.start = t;
        self.kind = kind;
        self.accepted = self.accepted.saturating_add(1);
        self.last = Some(t);
        self.follow = None;
    }

    pub(super) fn angles_at(&self, t: T) -> [State<T>; 2] {
        self.motion.sample(t - self.start)
    }

    pub(super) fn platform(&self, angles: [State<T>; 2]) -> PlatformState<T> {
        turned(&self.pose, angles)
    }

    /// The kinematics of one cycle at `state` with the tips as set.
    ///
    /// The kinematics' own error, converted by the caller, which keeps
    /// the step in this `Result` until it moves into the setpoint: a
    /// conversion here would move the step out of one `Result` into
    /// another on every cycle.
    pub(super) fn solve(
        &self,
        state: &PlatformState<T>,
        tracker: &mut MarginTracker<T>,
    ) -> Result<ControlStep<T>, crate::kin::Error> {
        self.controller.step_commanded(
            state,
            &ModuleCommand::Tip(self.tip_motion[0]),
            &ModuleCommand::Tip(self.tip_motion[1]),
            tracker,
        )
    }

    /// How long the controlled stop from these velocities takes, s.
    pub(super) fn stop_time(&self, angles: &[State<T>; 2]) -> T {
        let mut longest = T::zero();
        for (s, l) in angles.iter().zip(&self.limits) {
            let v = s.velocity;
            let t = if v < T::zero() { -v } else { v } / l.a_max;
            if t > longest {
                longest = t;
            }
        }
        longest
    }

    /// The bodies of `watch` at `step`.
    pub(super) fn bodies(
        &self,
        watch: &ClearanceWatch<T>,
        step: &ControlStep<T>,
    ) -> Result<Bodies<T>, Error> {
        let c = &self.controller;
        Ok(Bodies::at(
            &watch.bodies,
            &step.frame,
            &c.left,
            &step.left.q,
            &c.right,
            &step.right.q,
            watch.endoscope_depth,
        )?)
    }

    /// The three gaps of `step` with the bodies of `watch`.
    pub(super) fn gaps(
        &self,
        watch: &ClearanceWatch<T>,
        step: &ControlStep<T>,
    ) -> Result<Clearance<T>, Error> {
        Ok(self.bodies(watch, step)?.clearance()?)
    }
}
