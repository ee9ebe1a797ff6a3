//! What the online controller accepts between cycles: goals (angles or a
//! point to look at), stops, the tips it holds, and the follow mode.

use super::controller::OnlineController;
use super::setpoint::MotionKind;
use super::watch::{PROBE_BAND_MM, gap_array};
use crate::Real;
use crate::error::Error;
use crate::follow::{Follow, FollowParams};
use crate::kin::nalgebra::Vector3;
use crate::kin::{ModuleCommand, Pose, Side, TipMotion, TipTargets};
use crate::traj::{Limits, OnlineMulti, Synchronization};

/// The names of a tip's numbers in errors, `[position, velocity,
/// acceleration]` then `x, y, z`.
const TIP_NUMBERS: [[[&str; 3]; 3]; 2] = [
    [
        ["tips.left.x", "tips.left.y", "tips.left.z"],
        ["tips.left.vx", "tips.left.vy", "tips.left.vz"],
        ["tips.left.ax", "tips.left.ay", "tips.left.az"],
    ],
    [
        ["tips.right.x", "tips.right.y", "tips.right.z"],
        ["tips.right.vx", "tips.right.vy", "tips.right.vz"],
        ["tips.right.ax", "tips.right.ay", "tips.right.az"],
    ],
];

impl<T: Real> OnlineController<T> {
    /// A new goal `[psi, theta]` (rad) accepted at `t` (s): replanned from
    /// the state of the active motion at `t` to rest at the goal,
    /// time-optimal, phase synchronisation requested (a straight line when
    /// the velocity points along the remaining way or the platform is at
    /// rest, else time synchronisation). Ends the follow mode. Returns the
    /// synchronisation used. Watching the clearance with a gap near its
    /// stop threshold, it also takes the gaps' rates at the new motion's
    /// start one cycle ahead, through the kinematics, for the tick at `t`
    /// to check.
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`], [`Error::TimeReversed`], or
    /// [`Error::Trajectory`] for a non-finite goal; the controller is then
    /// unchanged.
    pub fn command(&mut self, t: T, goal: [T; 2]) -> Result<Synchronization, Error> {
        self.command_synchronized(t, goal, Synchronization::Phase)
    }

    /// A goal that aims the camera at `target` (mm, fixed frame), accepted
    /// at `t` (s): [`Camera::look_at`] of the controller's endoscope camera
    /// ([`Controller::endoscope`]), at the endoscope's depth, from the
    /// orientation of the active motion at `t` (`phi` held; the solution
    /// nearest that orientation), then exactly [`command`](Self::command)
    /// with the resulting `[psi, theta]`. When the motion ends, the view
    /// axis passes through `target`; the tips are held as in every command.
    /// Returns the synchronisation used.
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`], [`Error::TimeReversed`];
    /// [`Error::NoEndoscopeDepth`] when no depth was given
    /// ([`with_endoscope_depth`](Self::with_endoscope_depth),
    /// [`with_clearance`](Self::with_clearance)); [`Error::Camera`] when no
    /// turn aims at the target (behind the endoscope's tip, unreachable
    /// with this `phi`, `theta = +-90 deg`) or for a non-finite target; as
    /// [`command`](Self::command) for the plan. The controller is then
    /// unchanged.
    ///
    /// [`Camera::look_at`]: crate::kin::Camera::look_at
    /// [`Controller::endoscope`]: crate::kin::Controller::endoscope
    pub fn command_look_at(&mut self, t: T, target: Vector3<T>) -> Result<Synchronization, Error> {
        self.check_time(t)?;
        let depth = self.depth.ok_or(Error::NoEndoscopeDepth)?;
        let [psi, theta] = self.angles_at(t);
        let now = Pose {
            psi: psi.position,
            theta: theta.position,
            ..self.pose
        };
        let goal = self
            .controller
            .endoscope
            .camera
            .look_at(&now, depth, &target)?;
        self.command(t, goal)
    }

    /// [`command`](Self::command) with the synchronisation `sync` requested
    /// (`Phase` falls back to `Time` when the velocity is not along the way;
    /// see [`OnlineMulti::new`]).
    ///
    /// # Errors
    /// As [`command`](Self::command).
    pub fn command_synchronized(
        &mut self,
        t: T,
        goal: [T; 2],
        sync: Synchronization,
    ) -> Result<Synchronization, Error> {
        self.check_time(t)?;
        let motion = OnlineMulti::new(self.angles_at(t), goal, self.limits, sync)?;
        let probe = self.probe(&motion);
        self.begin(t, motion, MotionKind::Command);
        if let Some(w) = &mut self.clearance {
            w.probe = probe.map(|rates| (t, rates));
        }
        Ok(motion.synchronization())
    }

    /// The gaps' rates at the start of `motion`, looked ahead one cycle:
    /// the gaps at its start and one tick interval later (1 ms before any
    /// interval is known), through the kinematics. The rates of the ticks
    /// are measured over the cycle before, so at a command they are the old
    /// motion's, and from rest they are 0: a command from a rest just above
    /// the stop threshold would move a cycle inwards before any rate showed
    /// it. A cycle's motion moves a gap by micrometres, so the look-ahead
    /// (two kinematics steps, as much as two cycles) is taken only when the
    /// latest tick had a gap below the warning threshold or within
    /// [`PROBE_BAND_MM`] of the stop threshold. `None` otherwise, when the
    /// clearance is not watched, or when either instant cannot be solved
    /// (the ticks then report it).
    fn probe(&self, motion: &OnlineMulti<T, 2>) -> Option<[T; 3]> {
        let w = self.clearance.as_ref()?;
        let near = T::lit(PROBE_BAND_MM) + w.watch.thresholds.stop;
        let band = if w.watch.thresholds.warn > near {
            w.watch.thresholds.warn
        } else {
            near
        };
        if let Some(gaps) = w.pairs.previous
            && gaps.iter().all(|&g| g >= band)
        {
            return None;
        }
        let h = w.period.unwrap_or(T::lit(1e-3));
        let mut tracker = self.tracker;
        let mut gaps_at = |dt: T| {
            let state = self.platform(motion.sample(dt));
            let step = self.solve(&state, &mut tracker).ok()?;
            self.gaps(&w.watch, &step).ok().map(|c| gap_array(&c))
        };
        let (now, later) = (gaps_at(T::zero())?, gaps_at(h)?);
        let mut rates = [T::zero(); 3];
        for ((r, a), b) in rates.iter_mut().zip(now).zip(later) {
            *r = (b - a) / h;
        }
        Some(rates)
    }

    /// The controlled stop from the state at `t` (s): both angles to rest at
    /// the same instant, the one needing longer at its deceleration limit,
    /// on a straight line (see [`OnlineMulti::stop`]). At rest, a stop of
    /// zero duration. Ends the follow mode.
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`] or [`Error::TimeReversed`]; the controller is
    /// then unchanged.
    pub fn stop(&mut self, t: T) -> Result<(), Error> {
        self.check_time(t)?;
        let motion = OnlineMulti::stop(self.angles_at(t), self.limits)?;
        self.begin(t, motion, MotionKind::Stop);
        Ok(())
    }

    /// The tips held still at `tips` (mm, fixed frame) from `t` (s) on:
    /// [`move_tips`](Self::move_tips) with both velocities and
    /// accelerations 0.
    ///
    /// # Errors
    /// As [`move_tips`](Self::move_tips).
    pub fn set_tips(&mut self, t: T, tips: TipTargets<T>) -> Result<(), Error> {
        self.move_tips(
            t,
            [TipMotion::still(tips.left), TipMotion::still(tips.right)],
        )
    }

    /// The tips `[left, right]` (positions mm, velocities mm/s,
    /// accelerations mm/s^2, all in the fixed frame) that the ticks from
    /// `t` (s) on put the instruments at, whatever the platform does: each
    /// cycle solves both modules for these tips under the cycle's moving
    /// platform ([`Controller::step_commanded`]), so a tip stays exactly
    /// where it is commanded while the platform turns (its rates include
    /// the velocity given here). The active motion of the platform goes on.
    ///
    /// Checked before anything changes: every number finite; neither tip
    /// moved by more than [`max_tip_step`](Self::max_tip_step) from the
    /// tip held so far (a larger move is the caller's bug, or a sensor's
    /// leap: refused, never taken silently in one cycle); both modules
    /// solvable for the new tips at the platform's state at `t` (within
    /// reach, no joint beyond its limit).
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`], [`Error::TimeReversed`];
    /// [`Error::Kinematics`] (`NonFinite` naming the number, such as
    /// `"tips.right.vy"`) for a non-finite number; [`Error::TipStep`] for a
    /// move beyond the largest step; [`Error::Kinematics`] when a module
    /// cannot reach its new tip at the current pose. The controller is then
    /// unchanged.
    ///
    /// [`Controller::step_commanded`]: crate::kin::Controller::step_commanded
    pub fn move_tips(&mut self, t: T, tips: [TipMotion<T>; 2]) -> Result<(), Error> {
        self.check_time(t)?;
        for ((tip, names), (side, held)) in tips.iter().zip(&TIP_NUMBERS).zip([
            (Side::Left, &self.tips.left),
            (Side::Right, &self.tips.right),
        ]) {
            for (v, names) in [&tip.position, &tip.velocity, &tip.acceleration]
                .into_iter()
                .zip(names)
            {
                for (&x, &what) in v.iter().zip(names) {
                    if !x.finite() {
                        return Err(crate::kin::Error::NonFinite {
                            what,
                            value: x.to_f64(),
                        }
                        .into());
                    }
                }
            }
            let step = (tip.position - held).norm();
            if !(step <= self.max_tip_step) {
                return Err(Error::TipStep {
                    side,
                    step_mm: step.to_f64(),
                    max_mm: self.max_tip_step.to_f64(),
                });
            }
        }
        let mut tracker = self.tracker;
        self.controller.step_commanded(
            &self.state_at(t),
            &ModuleCommand::Tip(tips[0]),
            &ModuleCommand::Tip(tips[1]),
            &mut tracker,
        )?;
        self.tip_motion = tips;
        self.tips = TipTargets {
            left: tips[0].position,
            right: tips[1].position,
        };
        self.last = Some(t);
        Ok(())
    }

    /// The camera follows the tips from `t` (s) on: every tick runs the
    /// follow law ([`Follow`], with `params`) on the tips as set, and each
    /// recentring it plans becomes the active motion (the look-at of the
    /// tips' midpoint, reached time-optimally from the moving state), with
    /// the supervisor and the clearance guard in force as for every motion.
    /// The recentrings move within the lower of `params.limits` and the
    /// controller's own `[psi, theta]` limits. A motion under way is taken
    /// over as a recentring (the law's next cycle aims at the midpoint from
    /// that moving state); at rest, the law starts idle.
    ///
    /// The follow mode ends with a [`command`](Self::command) (or a look-at
    /// command), a [`stop`](Self::stop), or a stop the supervisor demands
    /// (the platform stops; following again is the caller's decision). Its
    /// phase is [`follow_phase`](Self::follow_phase) and each
    /// [`Setpoint::follow`](crate::Setpoint::follow).
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`], [`Error::TimeReversed`];
    /// [`Error::NoEndoscopeDepth`] without the endoscope's depth;
    /// [`Error::Follow`] for invalid parameters. The controller is then
    /// unchanged.
    pub fn follow(&mut self, t: T, params: FollowParams<T>) -> Result<(), Error> {
        self.check_time(t)?;
        let depth = self.depth.ok_or(Error::NoEndoscopeDepth)?;
        let lower = |a: T, b: T| if b < a { b } else { a };
        let [psi, theta] = self.limits;
        let limits = Limits {
            v_max: lower(params.limits.v_max, lower(psi.v_max, theta.v_max)),
            a_max: lower(params.limits.a_max, lower(psi.a_max, theta.a_max)),
        };
        let law = Follow::new(
            self.controller.endoscope.camera,
            FollowParams { limits, ..params },
            self.pose,
            depth,
        )?
        .taking_over(t, self.motion, self.start);
        self.follow = Some(law);
        self.kind = MotionKind::Follow;
        self.accepted = self.accepted.saturating_add(1);
        self.last = Some(t);
        Ok(())
    }
}
