//! The online controller: the per-cycle loop of motion type 4 that accepts a
//! new goal or a stop at any cycle, while the platform moves.
//!
//! An [`OnlineController`] holds the kinematics ([`Controller`]), the two tips
//! it keeps still, the platform's fixed part of the pose (`P` and `phi`), the
//! `(psi, theta)` limits, a margin [`Supervisor`], and the active motion: an
//! [`OnlineMulti`] of `(psi, theta)` started at some instant of the
//! controller's clock. Its calls, each taking the time `t` in s on that clock
//! (any origin; never decreasing from one call to the next):
//!
//! | call | what it does |
//! |---|---|
//! | [`new`](OnlineController::new) | at rest at a pose; checks the supervisor's thresholds; seeds module 1's margin tracker (the one full SVD) here, outside the loop |
//! | [`command`](OnlineController::command)`(t, [psi, theta])` | replans from the state of the active motion at `t` to rest at the goal (rad), time-optimal, `Phase` synchronisation requested; returns the one used |
//! | [`command_look_at`](OnlineController::command_look_at)`(t, target)` | the goal that aims the camera's view axis through `target` (mm, fixed frame; [`Camera::look_at`](crate::kin::Camera::look_at) from the orientation at `t`, `phi` held), then as `command` |
//! | [`stop`](OnlineController::stop)`(t)` | the controlled stop from the state at `t`: both angles to rest together, on a straight line |
//! | [`tick`](OnlineController::tick)`(t)` | one cycle: the platform state at `t`, [`Controller::step`], the supervisor's verdict; returns a [`Setpoint`] |
//! | [`command_index`](OnlineController::command_index) | 0 for the first motion, +1 at each command and each stop (a stop the supervisor demanded included) |
//! | [`is_at_rest`](OnlineController::is_at_rest)`(t)` | whether the active motion has ended at `t` |
//! | [`rebase`](OnlineController::rebase)`(origin)` | moves the clock's origin (see *Time* below) |
//!
//! A command at `t` takes effect at `t`: the new motion starts from the old
//! one's position and velocity at `t` exactly (the online profiles' start
//! state is returned as given), so both are continuous across every command;
//! the acceleration may jump (the profiles are second order). At its first
//! instant a motion reports the acceleration 0, as every profile of
//! [`parasils_traj`] does at `t <= 0`. A loop that commands at a cycle calls
//! `command(t, ..)` and then `tick(t)` with the same `t`.
//!
//! # The supervisor
//! Every tick checks the cycle's margins with
//! [`Supervisor::check_ahead`]: warnings for margins below their warning
//! thresholds, and a stop demanded for a decreasing margin that would end
//! below its stop threshold if a controlled stop began now. The rates are
//! the change since the previous tick; the stop's duration is that of the
//! controlled stop from this cycle's velocities. A demanded stop is carried
//! out at once: the controlled stop is planned from this cycle's state (as
//! [`stop`](OnlineController::stop) would), the command index grows by one,
//! and [`kind`](OnlineController::kind) becomes
//! [`MotionKind::SupervisorStop`]; the setpoint returned is this cycle's,
//! computed before the stop (same position and velocity; the next cycle
//! follows the stop). While a stop is under way a demand changes nothing. A
//! new command after a stop is accepted as any other: if it heads back
//! towards the limit, the supervisor stops it again; if it leaves, the margin
//! grows and nothing is demanded.
//!
//! # Clearance
//! [`with_clearance`](OnlineController::with_clearance) gives the
//! controller the bodies ([`ClearanceWatch`]: the shafts' and the
//! endoscope's sizes, the endoscope's depth, the warning and stop
//! thresholds in mm). Every tick then computes the three surface gaps
//! ([`Bodies::clearance`], in [`Setpoint::clearance`]) and their rates and
//! bends from the previous ticks, and the supervisor demands the controlled
//! stop for a decreasing gap predicted to end below the stop threshold
//! ([`ClearanceThresholds::check_ahead`]); the stop is carried out as a
//! margin's. Without it, nothing of the clearance is computed.
//!
//! # Time
//! The controller only uses the time since the active motion's start,
//! `t - start`, computed in `T`. In `f32` the spacing of the values near
//! `t` is about `t * 1.2e-7`: 0.12 us at 1 s, but 0.24 ms after an hour and
//! 1 ms after about 2.3 hours, where a 1 kHz loop no longer sees its cycles
//! apart. A
//! long-running `f32` loop keeps its clock small with
//! [`rebase`](OnlineController::rebase) (for example at every command, or
//! every minute), or runs the controller in `f64`.
//!
//! # Errors and cost
//! Every call returns a typed [`Error`]: a NaN or infinite time
//! ([`Error::NonFiniteTime`]), a time before the latest one
//! ([`Error::TimeReversed`]), a NaN goal or invalid limits
//! ([`Error::Trajectory`]), a kinematics failure ([`Error::Kinematics`]:
//! the cycle's pose is out of reach or beyond a hard threshold). A failed
//! call changes nothing: the active motion goes on, and the loop decides
//! (hold the drives, or command a stop). Nothing allocates, panics or loops
//! without a fixed bound. A tick costs one [`Controller::step`], with module
//! 1's margin tracked from the previous cycle (the full decomposition was
//! done by `new`), plus the supervisor's arithmetic; a command or a stop adds
//! one two-axis online plan. In `f32` the tracked margin is certified only
//! while the parallel margin is above about 0.2 (with module 1's assumed
//! geometry): below, rounding leaves the tracker nothing to certify, and
//! every cycle takes the full decomposition again (see
//! [`MarginTracker`]), about twice a tracked
//! cycle's cost; `f64` tracks down to the hard threshold.
//!
//! ```
//! use parasils::{OnlineController, Supervisor};
//! use parasils::kin::{Controller, Pose, TipTargets};
//! use parasils::traj::{Limits, Synchronization};
//!
//! let p0 = Pose::<f64>::paper_start();
//! let mut online = OnlineController::new(
//!     Controller::paper(),
//!     TipTargets::paper(),
//!     p0,
//!     [Limits::paper(); 2], // 10 deg/s, 5 deg/s^2
//!     Supervisor::default(),
//! )?;
//! let deg = 1f64.to_radians();
//! // The paper's goal at t = 0, then psi +5 / theta +10 deg from P0 at 1.2 s.
//! online.command(0.0, [p0.psi + 15.0 * deg, p0.theta + 25.0 * deg])?;
//! let mut k = 0u32;
//! loop {
//!     let t = f64::from(k) / 1000.0;
//!     if k == 1200 {
//!         let sync = online.command(t, [p0.psi + 5.0 * deg, p0.theta + 10.0 * deg])?;
//!         assert_eq!(sync, Synchronization::Time); // the velocity is not along the new way
//!     }
//!     let cycle = online.tick(t)?;
//!     // cycle.step: module 1's actuators, both modules' joints, rates, margins
//!     assert!(cycle.warnings.is_empty() && cycle.stop.is_empty());
//!     if online.is_at_rest(t) {
//!         break;
//!     }
//!     k += 1;
//! }
//! assert_eq!(online.command_index(), 1);
//! # Ok::<(), parasils::Error>(())
//! ```

use crate::Real;
use crate::error::Error;
use crate::kin::nalgebra::Vector3;
use crate::kin::{
    Bodies, BodyGeometry, Clearance, ControlStep, Controller, MarginTracker, PlatformState, Pose,
    TipTargets,
};
use crate::reorientation::turned;
use crate::supervisor::{ClearanceThresholds, MarginSet, Margins, PairSet, Supervisor};
use crate::traj::{Limits, OnlineMulti, State, Synchronization};

/// What the active motion of an [`OnlineController`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MotionKind {
    /// Nothing commanded yet: at rest where [`OnlineController::new`] put it.
    #[default]
    Rest,
    /// A goal given by [`OnlineController::command`].
    Command,
    /// A controlled stop asked by [`OnlineController::stop`].
    Stop,
    /// A controlled stop the supervisor demanded (see the [module docs](self)).
    SupervisorStop,
}

impl MotionKind {
    /// Whether the motion is a controlled stop, asked or demanded.
    pub const fn is_stop(self) -> bool {
        matches!(self, MotionKind::Stop | MotionKind::SupervisorStop)
    }
}

/// Everything one cycle of [`OnlineController::tick`] computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setpoint<T: Real> {
    /// The cycle's time, s.
    pub t: T,
    /// The platform's pose, Euler rates and accelerations at `t`.
    pub state: PlatformState<T>,
    /// Module 1's actuators and both instrument modules' joints, with their
    /// rates, accelerations and margins.
    pub step: ControlStep<T>,
    /// The index of the motion this cycle belongs to (see
    /// [`OnlineController::command_index`]); a stop the supervisor demanded
    /// in this cycle counts from the next cycle.
    pub command: u32,
    /// What that motion is.
    pub kind: MotionKind,
    /// The supervised margins of this cycle.
    pub margins: Margins<T>,
    /// The margins below their warning thresholds.
    pub warnings: MarginSet,
    /// The margins that demanded a controlled stop in this cycle (empty when
    /// none did); it was carried out unless a stop was already under way.
    pub stop: MarginSet,
    /// The surface gaps between the bodies at this cycle, with the closest
    /// points of their axes (mm, fixed frame); `None` when the controller
    /// watches no clearance ([`OnlineController::with_clearance`]).
    pub clearance: Option<Clearance<T>>,
    /// The pairs whose gap is below the clearance warning threshold.
    pub clearance_warnings: PairSet,
    /// The pairs whose gap demanded a controlled stop in this cycle (carried
    /// out as a margin's is).
    pub clearance_stop: PairSet,
}

/// How far above the clearance stop threshold (mm) a command looks its
/// motion's first cycle ahead even when no gap is below the warning
/// threshold (see [`OnlineController::command`]).
pub const PROBE_BAND_MM: f64 = 1.0;

/// What the online controller needs to watch the clearance between the
/// instrument shafts and the endoscope ([`OnlineController::with_clearance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceWatch<T> {
    /// The bodies' sizes, mm.
    pub bodies: BodyGeometry<T>,
    /// The endoscope's insertion below `P` along `-Z'`, mm.
    pub endoscope_depth: T,
    /// The warning and stop thresholds on every gap, mm.
    pub thresholds: ClearanceThresholds<T>,
}

/// The clearance watched, and what the previous tick saw of it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Watched<T> {
    watch: ClearanceWatch<T>,
    /// The previous tick's gaps, mm.
    previous: Option<[T; 3]>,
    /// Their rates from the tick before, mm/s (`None` before two ticks).
    rates: Option<[T; 3]>,
    /// Their second derivatives along the path at the current speed,
    /// mm/s^2 (0 before three ticks).
    bends: [T; 3],
    /// The latest interval between two ticks, s.
    period: Option<T>,
    /// A command's time and the rates its motion starts with, looked ahead
    /// (see [`OnlineController::command`]): the tick at that time checks
    /// them instead of the rates of the motion before.
    probe: Option<(T, [T; 3])>,
}

/// The per-cycle controller of motion type 4 with online goals, stops and a
/// margin supervisor (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnlineController<T: Real> {
    controller: Controller<T>,
    /// Module 1's weakest direction from the previous cycle.
    tracker: MarginTracker<T>,
    tips: TipTargets<T>,
    /// `P` and `phi` (fixed), and the `(psi, theta)` of the start.
    pose: Pose<T>,
    limits: [Limits<T>; 2],
    supervisor: Supervisor<T>,
    motion: OnlineMulti<T, 2>,
    /// Where the active motion starts on the controller's clock, s.
    start: T,
    kind: MotionKind,
    /// Motions accepted (commands and stops).
    accepted: u32,
    /// The latest time given to any call, s.
    last: Option<T>,
    /// The previous tick's time and margins, and the rates from the tick before.
    previous: Option<(T, Margins<T>)>,
    rates: Margins<T>,
    /// The clearance watched, if any.
    clearance: Option<Watched<T>>,
    /// The endoscope's insertion below `P`, mm, for look-at commands.
    depth: Option<T>,
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
        })
    }

    /// The same controller with the endoscope inserted `depth` mm below
    /// `P` along `-Z'`: where its camera sits for
    /// [`command_look_at`](Self::command_look_at).
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

    /// The endoscope's depth the look-at commands use, mm (`None` when
    /// none was given).
    pub fn endoscope_depth(&self) -> Option<T> {
        self.depth
    }

    /// The same controller watching the clearance between the bodies of
    /// `watch`: every tick computes the three surface gaps
    /// ([`Bodies::clearance`]) and the supervisor demands a controlled stop
    /// for a decreasing gap that would end below the stop threshold
    /// ([`ClearanceThresholds::check_ahead`]), as it does for the margins.
    /// Called before the first tick (the gaps' rates start from the next
    /// tick).
    ///
    /// # Errors
    /// [`Error::InvalidClearanceThreshold`] for a threshold that is not
    /// finite or a warning below the stop one; [`Error::Kinematics`] for an
    /// invalid size or a non-finite depth (the bodies are placed once at
    /// the current pose to check them).
    pub fn with_clearance(mut self, watch: ClearanceWatch<T>) -> Result<Self, Error> {
        watch.thresholds.validate()?;
        let mut tracker = self.tracker;
        let t = self.last.unwrap_or(self.start);
        let step = self
            .controller
            .step(&self.state_at(t), &self.tips, &mut tracker)?;
        let gaps = self.gaps(&watch, &step)?;
        self.clearance = Some(Watched {
            watch,
            // Where it rests now: a first command looks ahead only near the
            // stop threshold (the rates start from two ticks).
            previous: Some(gap_array(&gaps)),
            rates: None,
            bends: [T::zero(); 3],
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

    /// The three gaps of `step` with the bodies of `watch`.
    fn gaps(
        &self,
        watch: &ClearanceWatch<T>,
        step: &ControlStep<T>,
    ) -> Result<Clearance<T>, Error> {
        let c = &self.controller;
        Ok(Bodies::at(
            &watch.bodies,
            &step.frame,
            &c.left,
            &step.left.q,
            &c.right,
            &step.right.q,
            watch.endoscope_depth,
        )?
        .clearance()?)
    }

    /// A new goal `[psi, theta]` (rad) accepted at `t` (s): replanned from
    /// the state of the active motion at `t` to rest at the goal,
    /// time-optimal, phase synchronisation requested (a straight line when
    /// the velocity points along the remaining way or the platform is at
    /// rest, else time synchronisation). Returns the synchronisation used.
    /// Watching the clearance with a gap near its stop threshold, it also
    /// takes the gaps' rates at the new motion's start one cycle ahead,
    /// through the kinematics, for the tick at `t` to check.
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
        if let Some(gaps) = w.previous
            && gaps.iter().all(|&g| g >= band)
        {
            return None;
        }
        let h = w.period.unwrap_or(T::lit(1e-3));
        let mut tracker = self.tracker;
        let mut gaps_at = |dt: T| {
            let state = self.platform(motion.sample(dt));
            let step = self
                .controller
                .step(&state, &self.tips, &mut tracker)
                .ok()?;
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
    /// zero duration.
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

    /// One control cycle at `t` (s): the platform state of the active motion
    /// at `t`, [`Controller::step`] for it, and the supervisor's verdict (a
    /// demanded stop is carried out from this cycle's state; see the
    /// [module docs](self)).
    ///
    /// # Errors
    /// [`Error::NonFiniteTime`], [`Error::TimeReversed`], or
    /// [`Error::Kinematics`] when the state cannot be solved; the controller
    /// is then unchanged.
    pub fn tick(&mut self, t: T) -> Result<Setpoint<T>, Error> {
        self.check_time(t)?;
        let angles = self.angles_at(t);
        let state = self.platform(angles);
        let step = self
            .controller
            .step(&state, &self.tips, &mut self.tracker)?;
        let margins = Margins::of(&step);
        let clearance = match &self.clearance {
            Some(w) => Some(self.gaps(&w.watch, &step)?),
            None => None,
        };
        let mut period = T::zero();
        if let Some((t_prev, m_prev)) = self.previous
            && t > t_prev
        {
            period = t - t_prev;
            let per_s = T::one() / period;
            for ((r, m), p) in self.rates.0.iter_mut().zip(margins.0).zip(m_prev.0) {
                *r = (m - p) * per_s;
            }
            if let (Some(w), Some(c)) = (&mut self.clearance, &clearance)
                && let Some(g_prev) = w.previous
            {
                w.update(&gap_array(c), &g_prev, per_s, &angles);
                w.period = Some(period);
            }
        }
        self.previous = Some((t, margins));
        if let (Some(w), Some(c)) = (&mut self.clearance, &clearance) {
            w.previous = Some(gap_array(c));
        }
        self.last = Some(t);
        let stop_time = self.stop_time(&angles);
        let verdict = self
            .supervisor
            .check_ahead(&margins, &self.rates, stop_time);
        let gap_verdict = match (&mut self.clearance, &clearance) {
            (Some(w), Some(c)) => {
                // At a command's own tick, the rates its motion starts with.
                let rates = match w.probe {
                    Some((t0, rates)) if t0 == t => rates,
                    _ => w.rates.unwrap_or([T::zero(); 3]),
                };
                w.probe = None;
                w.watch
                    .thresholds
                    .check_ahead(&gap_array(c), &rates, &w.bends, stop_time, period)
            }
            _ => Default::default(),
        };
        let setpoint = Setpoint {
            t,
            state,
            step,
            command: self.command_index(),
            kind: self.kind,
            margins,
            warnings: verdict.warnings,
            stop: verdict.stop,
            clearance,
            clearance_warnings: gap_verdict.warnings,
            clearance_stop: gap_verdict.stop,
        };
        // A gap's demand at a motion's first instant, still at rest, holds
        // the platform there (a stop of zero duration): the motion would
        // take it below the stop threshold.
        let holds = !gap_verdict.stop.is_empty() && !self.is_at_rest(t);
        if (!verdict.stop.is_empty() || !gap_verdict.stop.is_empty())
            && !self.kind.is_stop()
            && (stop_time > T::zero() || holds)
            && let Ok(motion) = OnlineMulti::stop(angles, self.limits)
        {
            self.begin(t, motion, MotionKind::SupervisorStop);
        }
        Ok(setpoint)
    }

    /// The index of the active motion: 0 for the first one (and before any),
    /// one more at each command and each stop after it, a stop the
    /// supervisor demanded included.
    pub fn command_index(&self) -> u32 {
        self.accepted.saturating_sub(1)
    }

    /// What the active motion is.
    pub fn kind(&self) -> MotionKind {
        self.kind
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

    /// The tips held still, mm, fixed frame.
    pub fn tips(&self) -> &TipTargets<T> {
        &self.tips
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
    /// [module docs](self), *Time*): rebase from time to time, for example
    /// to the current cycle, and count the cycles from 0 again.
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
        Ok(())
    }

    fn check_time(&self, t: T) -> Result<(), Error> {
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

    fn begin(&mut self, t: T, motion: OnlineMulti<T, 2>, kind: MotionKind) {
        self.motion = motion;
        self.start = t;
        self.kind = kind;
        self.accepted = self.accepted.saturating_add(1);
        self.last = Some(t);
    }

    fn angles_at(&self, t: T) -> [State<T>; 2] {
        self.motion.sample(t - self.start)
    }

    fn platform(&self, angles: [State<T>; 2]) -> PlatformState<T> {
        turned(&self.pose, angles)
    }

    /// How long the controlled stop from these velocities takes, s.
    fn stop_time(&self, angles: &[State<T>; 2]) -> T {
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
}

/// The three gaps of `c` in the order of [`ClearancePair::ALL`], mm.
///
/// [`ClearancePair::ALL`]: crate::kin::ClearancePair::ALL
fn gap_array<T: Real>(c: &Clearance<T>) -> [T; 3] {
    [
        c.left_right.gap,
        c.left_endoscope.gap,
        c.right_endoscope.gap,
    ]
}

impl<T: Real> Watched<T> {
    /// The rates from the gaps `now` and `before`, one cycle apart
    /// (`per_s` = 1 / the cycle, 1/s), and the bends from the change of the
    /// rates: a gap `g(t) = G(sigma(t))`, `sigma` the way travelled in
    /// `(psi, theta)`, has `g'' = G'' sigma'^2 + G' sigma''`; the bend is
    /// `G'' sigma'^2 = g'' - g' sigma'' / sigma'`, what `g''` would be at
    /// the current speed `sigma'` held constant (the motion's own
    /// acceleration `sigma''` taken out), 0 at rest.
    fn update(&mut self, now: &[T; 3], before: &[T; 3], per_s: T, angles: &[State<T>; 2]) {
        let [a, b] = angles;
        let speed = (a.velocity * a.velocity + b.velocity * b.velocity).sqrt();
        let along = if speed > T::zero() {
            (a.velocity * a.acceleration + b.velocity * b.acceleration) / (speed * speed)
        } else {
            T::zero()
        };
        let mut rates = [T::zero(); 3];
        for ((r, g), p) in rates.iter_mut().zip(now).zip(before) {
            *r = (*g - *p) * per_s;
        }
        if let Some(old) = self.rates {
            for ((bend, r), o) in self.bends.iter_mut().zip(rates).zip(old) {
                *bend = if speed > T::zero() {
                    (r - o) * per_s - r * along
                } else {
                    T::zero()
                };
            }
        }
        self.rates = Some(rates);
    }
}
