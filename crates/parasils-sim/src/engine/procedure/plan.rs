//! A procedure planned: its motions one after the other on one time line
//! of samples, each on the control cycle, each from the state the previous
//! one ended in.

use std::borrow::Cow;

use parasils::kin::{Controller, JointMotion, MarginTracker, ModuleCommand, PlatformState};
use parasils::motions::{Motion, MotionSample, MotionType, Moving, RobotState};
use parasils::traj::{State, Synchronization};
use parasils::{Stretch, TimeScaled};

use super::follow;
use super::inside;
use super::motion::{Continue, continued, optimal_plan, plan, tips_of};
use crate::engine::error::SimulationError;
use crate::motion::{CameraMode, Inside, MotionGoal, MotionLimits, MotionName};
use crate::scenario::{Motions, Scenario, Timeline, Timing};
use crate::timing::OptimalMotion;
use parasils_io::Shortest;

/// One motion placed on the procedure's time line, on the control cycle.
///
/// Its rows are at its own `t = 0, dt, ..., L dt` (`dt = 1 / rate`), the
/// first at its start and, unless it is cut short, the last one at rest
/// exactly on its target; the next motion's first row is the next cycle's.
/// A motion cut short by its `until_s` owns the rows `0, ..., L - 1`: the
/// motion that continues it starts at row `L`, from its moving state there.
#[derive(Debug, Clone)]
pub struct PlannedMotion {
    /// The motion, from the state the previous one ended in.
    pub motion: Motion<f64>,
    /// When it starts, s from the procedure's start: `first_sample / rate`.
    pub start_s: f64,
    /// How long it lasts on the time line, s: `L / rate`, its stretched
    /// duration, or its `until_s` rounded up to a whole period (cut short
    /// before its end, or resting after it).
    pub length_s: f64,
    /// The index of its first row in the procedure's samples.
    pub first_sample: usize,
    /// `L`, its length in periods (see [`PlannedMotion`]).
    pub periods: usize,
    /// Whether its `until_s` cuts it short (its last row is not at rest).
    pub cut: bool,
    /// Its law on the control cycle: the planned and the stretched duration.
    pub stretch: Stretch<f64>,
    /// How messages and outputs name it.
    pub name: MotionName,
    /// The time-optimal law that times it instead of `motion`'s profile,
    /// under `--timing optimal` (`motion` then gives its type and path).
    pub optimal: Option<OptimalMotion>,
    /// What is inside the patient when it starts, and the incision point.
    pub inside: Inside,
    /// A type-3 motion whose camera follows the tips: the platform's
    /// `[psi, theta]` (rad, with rates and accelerations) at each of its
    /// rows, from the follow law stepped over them while planning; its
    /// rows run past the tips' arrival until the camera has settled.
    pub follow: Option<Vec<[State<f64>; 2]>>,
}

impl PlannedMotion {
    /// Its duration on the control cycle (stretched), s.
    pub fn duration(&self) -> f64 {
        self.stretch.duration()
    }

    /// Its law's own duration (as planned, before the stretch), s.
    pub fn planned_s(&self) -> f64 {
        self.stretch.planned()
    }

    /// The law at its own time `tau` (s), unscaled.
    fn law(&self, tau: f64) -> MotionSample<f64> {
        match &self.optimal {
            Some(o) => o.sample_at(tau),
            None => self.motion.sample(tau),
        }
    }

    /// Its row `j` (at its own `t = j / rate`): the law at the scaled time,
    /// and, from its stretched end on, the law's end state itself.
    pub fn sample_index(&self, j: usize) -> MotionSample<f64> {
        if let Some(rows) = &self.follow {
            let last = rows.len().saturating_sub(1);
            if let Some(angles) = rows.get(j.min(last)) {
                return self
                    .motion
                    .geometry()
                    .followed(&self.moving_at_row(j), *angles);
            }
        }
        let tau = self.stretch.law_time(j);
        if j >= self.stretch.periods() {
            self.law(tau)
        } else {
            self.law(tau).time_scaled(self.stretch.ratio())
        }
    }

    /// The motion at `t` (s from its start), on the control cycle.
    pub fn sample(&self, t: f64) -> MotionSample<f64> {
        if self.follow.is_some() {
            let row = (t * self.stretch.rate()).round().max(0.0);
            #[allow(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "non-negative, capped at the motion's last row"
            )]
            let j = row.min(self.periods as f64) as usize;
            return self.sample_index(j);
        }
        if t >= self.stretch.duration() {
            return self.law(self.stretch.planned());
        }
        let r = self.stretch.ratio();
        self.law(t * r).time_scaled(r)
    }

    /// Its own coordinates and their rates at row `j`, on the control
    /// cycle: what a motion continuing it starts from.
    pub fn moving_at_row(&self, j: usize) -> Moving<f64> {
        let tau = self.stretch.law_time(j);
        let m = self.motion.moving_at(tau);
        if j >= self.stretch.periods() {
            m
        } else {
            m.time_scaled(self.stretch.ratio())
        }
    }

    /// The index of the next motion's first row: one cycle after this
    /// one's last row, or, cut short, the row this one stops at.
    fn next_sample(&self) -> usize {
        if self.cut {
            self.first_sample + self.periods
        } else {
            self.first_sample + self.periods + 1
        }
    }
}

/// The planned procedure: every motion, and where each starts.
#[derive(Debug, Clone)]
pub struct ProcedurePlan {
    /// The motions in order.
    pub motions: Vec<PlannedMotion>,
    /// The state at the start (joints from the IK of the start tips).
    pub start: RobotState<f64>,
    /// The control rate, Hz.
    pub rate_hz: f64,
    /// Whether messages name the motion an error is in (a procedure's), or
    /// give the error alone (the single turn of a run without motions of its
    /// own, as the paper's).
    named: bool,
    /// The last row's index.
    last_sample: usize,
    /// Why planning stopped early: the end of the last motion could not be
    /// solved, so that no later motion can start. The samples up to that end
    /// are still planned, so that a run finds the first one that fails.
    failure: Option<SimulationError>,
}

impl ProcedurePlan {
    /// Plans every motion of `scenario` in order, each on the control cycle
    /// (see [`PlannedMotion`]); the end of each (solved by `controller`) is
    /// the start of the next, or, for a motion cut short by its `until_s`,
    /// its moving state there.
    ///
    /// # Errors
    /// [`SimulationError::Motion`] naming the motion whose profile cannot be
    /// planned or that cannot follow the one before;
    /// [`SimulationError::Inside`] naming the first motion that would move
    /// the incision point or turn about the endoscope's axis while anything
    /// is inside the patient; [`SimulationError::Kinematics`]
    /// at `t = 0` when the start cannot be solved;
    /// [`SimulationError::Trajectory`] for a rate that is not positive and
    /// finite.
    pub fn new(
        scenario: &Scenario,
        timeline: &Timeline,
        controller: &Controller<f64>,
    ) -> Result<Self, SimulationError> {
        let rate = scenario.rate_hz;
        // The paper's turn is a timeline of one reorientation, with its own
        // synchronisation and, under the optimal timing, its angular limits
        // binding when they were given.
        let (specs, sync, named) = match &timeline.motions {
            Motions::Turn(turn) => {
                let angular = timeline.timing == (Timing::Optimal { angular: true });
                (Cow::Owned(vec![turn.motion(angular)]), turn.sync, false)
            }
            Motions::Procedure(m) => (Cow::Borrowed(m.as_slice()), Synchronization::Phase, true),
        };
        Stretch::new(0.0, rate).map_err(SimulationError::Trajectory)?;
        let solver = *controller;
        let camera = &controller.endoscope.camera;
        let mut tracker = MarginTracker::new();
        let tips = scenario.tips();
        let start_pose = scenario.start();
        let at_start = |error| SimulationError::Kinematics {
            t: 0.0,
            sample: Some(0),
            error,
        };
        let first = solver
            .step(&PlatformState::at_rest(start_pose), &tips, &mut tracker)
            .map_err(at_start)?;
        solver
            .endoscope
            .check(scenario.endoscope_depth_mm)
            .map_err(at_start)?;
        let start = RobotState {
            pose: start_pose,
            joints: [first.left.q, first.right.q],
            endoscope_depth: scenario.endoscope_depth_mm,
        };
        let mut state = start;
        // The tips the next motion starts from: the scenario's own at the
        // start, then where each motion's end joints put them.
        let mut held = [tips.left, tips.right];
        let mut inside_now = inside::at_start(&start);
        let mut next_sample = 0usize;
        let mut motions: Vec<PlannedMotion> = Vec::with_capacity(specs.len());
        // The previous motion's moving state when it was cut short, with
        // its limits (a stop decelerates at them).
        let mut moving: Option<(Moving<f64>, MotionLimits)> = None;
        let count = specs.len();
        for (index, spec) in specs.iter().enumerate() {
            let previous = motions.last().map(|m| m.name.motion_type);
            let motion_type = spec.motion_type().or(previous);
            let mut name = MotionName {
                index,
                motion_type: motion_type.unwrap_or(MotionType::Reorient),
                stop: spec.motion_type().is_none(),
                name: spec.name.clone(),
            };
            let fail = |name: &MotionName, t_motion: f64, error: SimulationError| {
                in_motion(named, name, t_motion, error)
            };
            let order =
                |name: &MotionName, why: String| fail(name, 0.0, SimulationError::Procedure(why));
            if name.stop && motions.is_empty() {
                return Err(order(
                    &name,
                    String::from("a stop needs a motion before it to stop"),
                ));
            }
            // A law that starts moving keeps its start: held at its end
            // until the next whole period instead of stretched.
            let mut from_moving = false;
            let motion = match (&spec.goal, moving) {
                (goal, Some((m, limits))) if !m.at_rest() || *goal == MotionGoal::Stop => {
                    from_moving = !m.at_rest();
                    continued(camera, &state, held, spec, m, limits).map_err(|e| match e {
                        Continue::Trajectory(e) => fail(&name, 0.0, SimulationError::Trajectory(e)),
                        Continue::Mismatch(why) => order(&name, why),
                    })?
                }
                (MotionGoal::Stop, _) => {
                    // The motion before ended at rest: a stop of no length.
                    let last = motions.last().map(|m| m.moving_at_row(m.periods));
                    let m = last.ok_or_else(|| order(&name, String::from("nothing to stop")))?;
                    continued(camera, &state, held, spec, m, spec.limits).map_err(|e| match e {
                        Continue::Trajectory(e) => fail(&name, 0.0, SimulationError::Trajectory(e)),
                        Continue::Mismatch(why) => order(&name, why),
                    })?
                }
                _ => plan(camera, &state, held, spec, sync).map_err(|e| match e {
                    Continue::Trajectory(e) => fail(&name, 0.0, SimulationError::Trajectory(e)),
                    Continue::Mismatch(why) => order(&name, why),
                })?,
            };
            name.motion_type = motion.motion_type();
            let optimal = match timeline.timing {
                // A motion that gives a jerk limit keeps its double S.
                Timing::Optimal { .. } if spec.limits.jerk().is_none() => {
                    optimal_plan(controller, &state, held, spec)
                        .map_err(|e| fail(&name, 0.0, SimulationError::Timing(e)))?
                }
                Timing::Optimal { .. } | Timing::Trapezoid => None,
            };
            let planned = optimal.as_ref().map_or(motion.duration(), |o| o.duration());
            let stretch = if from_moving {
                Stretch::padded(planned, rate)
            } else {
                Stretch::new(planned, rate)
            }
            .map_err(|e| fail(&name, 0.0, SimulationError::Trajectory(e)))?;
            let periods = match spec.until_s {
                Some(until) => Stretch::padded(until, rate)
                    .map_err(|e| fail(&name, 0.0, SimulationError::Trajectory(e)))?
                    .periods(),
                None => stretch.periods(),
            };
            let cut = periods < stretch.periods();
            let (length, duration) = (periods as f64 / rate, stretch.duration());
            if cut && optimal.is_some() {
                return Err(order(
                    &name,
                    format!(
                        "until_s = {} s cuts the motion short (it lasts {} s): the time-optimal timing plans motions from rest to rest",
                        Shortest(length),
                        Shortest(duration)
                    ),
                ));
            }
            if cut && index + 1 == count {
                return Err(order(
                    &name,
                    format!(
                        "until_s = {} s cuts the last motion short (it lasts {} s): add the motion that follows, or a stop",
                        Shortest(length),
                        Shortest(duration)
                    ),
                ));
            }
            let mut placed = PlannedMotion {
                motion,
                start_s: next_sample as f64 / rate,
                length_s: length,
                first_sample: next_sample,
                periods,
                cut,
                stretch,
                name,
                optimal,
                inside: inside_now,
                follow: None,
            };
            if spec.camera == CameraMode::Follow {
                if placed.optimal.is_some() || from_moving {
                    return Err(order(
                        &placed.name,
                        String::from(
                            "camera = \"follow\" needs a motion planned from rest by its own profile (not the time-optimal timing, not the continuation of a motion cut short)",
                        ),
                    ));
                }
                let rows = follow::setpoints(
                    camera,
                    &state,
                    &spec.limits,
                    rate,
                    placed.stretch.periods(),
                    |j| placed.moving_at_row(j),
                )
                .map_err(|e| match e {
                    follow::FollowFailure::Law(t, error) => fail(
                        &placed.name,
                        t,
                        SimulationError::Procedure(format!(
                            "the camera cannot follow the tips at t = {} s of the motion: {error}",
                            Shortest(t)
                        )),
                    ),
                    follow::FollowFailure::Unsettled => order(
                        &placed.name,
                        format!(
                            "the camera following the tips had not settled {} s after they stopped",
                            Shortest(follow::SETTLE_LIMIT_S)
                        ),
                    ),
                })?;
                placed.periods = rows.len().saturating_sub(1);
                placed.length_s = placed.periods as f64 / rate;
                placed.follow = Some(rows);
            }
            let periods = placed.periods;
            let length = placed.length_s;
            inside::check_motion(
                &inside_now,
                &placed.name,
                &state.pose,
                (0..=periods).map(|j| placed.sample_index(j).platform.pose),
            )?;
            let end = placed.sample_index(periods);
            let out =
                match solver.step_commanded(&end.platform, &end.left, &end.right, &mut tracker) {
                    Ok(out) => out,
                    Err(error) => {
                        let failure = fail(
                            &placed.name,
                            length,
                            SimulationError::Kinematics {
                                t: placed.start_s + length,
                                sample: None,
                                error,
                            },
                        );
                        let last_sample = placed.first_sample + periods;
                        motions.push(placed);
                        return Ok(Self {
                            motions,
                            start,
                            rate_hz: rate,
                            named,
                            last_sample,
                            failure: Some(failure),
                        });
                    }
                };
            state = RobotState {
                pose: end.platform.pose,
                joints: [out.left.q, out.right.q],
                endoscope_depth: end.endoscope.position,
            };
            held = tips_of(controller, &state.pose, &state.joints);
            let inserted = match &placed.motion {
                Motion::Insert(i) => Some(i.port()),
                _ => None,
            };
            inside_now = inside::after(&inside_now, inserted, &state, &start);
            moving = cut.then(|| (placed.moving_at_row(periods), spec.limits));
            next_sample = placed.next_sample();
            motions.push(placed);
        }
        let last_sample = motions.last().map_or(0, |m| m.first_sample + m.periods);
        Ok(Self {
            motions,
            start,
            rate_hz: rate,
            named,
            last_sample,
            failure: None,
        })
    }

    /// `error` in motion `m` at `t_motion` (s from its start): named after
    /// the motion in a procedure, alone for a single turn.
    pub(crate) fn in_motion(
        &self,
        m: usize,
        t_motion: f64,
        error: SimulationError,
    ) -> SimulationError {
        let name = self.motions.get(m).map_or_else(
            || MotionName {
                index: m,
                motion_type: MotionType::Reorient,
                stop: false,
                name: None,
            },
            |p| p.name.clone(),
        );
        in_motion(self.named, &name, t_motion, error)
    }

    /// Why planning stopped before the last motion, if it did (see
    /// [`Simulation::new`](crate::engine::Simulation::new), which runs the samples
    /// first to name the first that fails).
    pub fn failure(&self) -> Option<&SimulationError> {
        self.failure.as_ref()
    }

    /// The whole procedure's duration, s: its last row's time.
    pub fn duration(&self) -> f64 {
        self.last_sample as f64 / self.rate_hz
    }

    /// The number of rows, `t = k / rate` for `k = 0..n`.
    pub fn sample_count(&self) -> usize {
        self.last_sample + 1
    }

    /// The motion under way at row `k` (at `t = k / rate`) and its sample
    /// there.
    pub fn sample_index(&self, k: usize) -> (usize, MotionSample<f64>) {
        let i = self.motion_at(k);
        match self.motions.get(i) {
            Some(m) => (i, m.sample_index(k.saturating_sub(m.first_sample))),
            // No motion: never planned (a procedure has at least one).
            None => (0, held_at(&self.start)),
        }
    }

    /// The motion under way at `t` (s from the procedure's start, read as
    /// the nearest row) and its sample there.
    pub fn sample_at(&self, t: f64) -> (usize, MotionSample<f64>) {
        self.sample_index(self.row(t))
    }

    /// The index of the motion under way at `t` (s, read as the nearest
    /// row): the last one whose first row is at or before it.
    pub fn index_at(&self, t: f64) -> usize {
        self.motion_at(self.row(t))
    }

    fn motion_at(&self, k: usize) -> usize {
        self.motions
            .partition_point(|m| m.first_sample <= k)
            .saturating_sub(1)
    }

    /// The row nearest `t` (s), within the plan.
    fn row(&self, t: f64) -> usize {
        let x = (t * self.rate_hz).round();
        if x > 0.0 {
            #[allow(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "positive, capped at the last row"
            )]
            let k = x.min(self.last_sample as f64) as usize;
            k
        } else {
            0
        }
    }
}

impl parasils::traj::Motion<f64> for ProcedurePlan {
    type Output = (usize, MotionSample<f64>);

    fn duration(&self) -> f64 {
        ProcedurePlan::duration(self)
    }

    fn sample(&self, t: f64) -> Self::Output {
        self.sample_at(t)
    }
}

/// `error` in the motion `name` at `t_motion` (s from its start), when
/// motions are `named`; otherwise `error` itself.
fn in_motion(
    named: bool,
    name: &MotionName,
    t_motion: f64,
    error: SimulationError,
) -> SimulationError {
    if named {
        SimulationError::Motion {
            motion: Box::new(name.clone()),
            t_motion,
            error: Box::new(error),
        }
    } else {
        error
    }
}

/// The robot at rest in `state`.
fn held_at(state: &RobotState<f64>) -> MotionSample<f64> {
    MotionSample {
        platform: PlatformState::at_rest(state.pose),
        left: ModuleCommand::Joints(JointMotion::held(state.joints[0])),
        right: ModuleCommand::Joints(JointMotion::held(state.joints[1])),
        endoscope: parasils::traj::State::rest(state.endoscope_depth),
    }
}
