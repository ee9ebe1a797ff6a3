//! The engine: a [`Scenario`] planned and sampled at a fixed rate through
//! the controller's per-cycle call, one [`Record`] at a time.
//!
//! Two paths, one loop shape:
//! - **Without commands** (the paper's run), the reorientation is planned
//!   rest to rest as a [`Reorientation`] (or its time-optimal law),
//!   stretched onto the control cycle ([`OnCycle`]: a whole number of
//!   periods, the last sample at rest exactly on the goal), and each
//!   sample's state goes through [`Controller::step`]. The paper's 4.5 s at
//!   1 kHz already is a whole number of periods: its records are those of
//!   every earlier release, to the last bit.
//! - **With commands** (retargets, a stop; see [`Command`]), the run is an
//!   [`OnlineController`] loop, as a robot's controller runs it: the
//!   reorientation is commanded at `t = 0`, and each command at the first
//!   sample at or after its time, replanned from the state of that sample
//!   (position and velocity continuous; the acceleration may jump, and is 0
//!   at the sample a motion starts on, as at the start of every profile).
//!   The run ends at the first sample at which every command has taken
//!   effect and the last motion is at rest. The controller's margin
//!   [`Supervisor`] watches every cycle and stops the platform before a
//!   margin reaches its hard threshold (a [`CommandKind::SupervisorStop`]),
//!   where the rest-to-rest path would fail there with an error.
//!
//! Nothing is integrated: every record is computed from the trajectory's
//! analytic state at its time, so the tips' drift is the kinematics' rounding
//! only. Records stream to a [`Sink`] in [`Simulation::run`], the one loop
//! that the command line and the Python bindings both run; memory stays flat
//! however long the run.

use nalgebra::Vector3;
use parasils::kin::{
    AssemblyMode, ControlStep, Controller, Instrument, InstrumentSolution, PlatformState,
    TipTargets,
};
use parasils::kin::{LimitError, MarginTracker};
use parasils::supervisor::{MarginSet, Margins};
use parasils::traj::Sampler;
use parasils::{MotionKind, OnCycle, OnlineController, Reorientation, Supervisor};
use procedure::{ProcedureCheck, ProcedurePlan};

use crate::scenario::Timing;
use crate::timing::{OptimalReorientation, TimingError, TimingOptions};

use crate::motion::MotionName;
use crate::record::{InstrumentRecord, Module1Record, Record};
use crate::scenario::{Command, CommandKind, Scenario};
use crate::sink::Sink;
use parasils_io::{AtTime, Fixed, Shortest};

/// What can stop a simulation.
///
/// Each message names its subject once: the robot's geometry, the
/// trajectory, the commands, or the sample's time followed by the
/// kinematics' own message (which names the module).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// The robot's geometry is invalid.
    #[error("robot geometry: {0}")]
    Geometry(parasils::kin::Error),
    /// The trajectory cannot be planned or sampled (limits, angles or rate
    /// invalid).
    #[error("trajectory: {0}")]
    Trajectory(parasils::traj::Error),
    /// The kinematics failed at a sample (unreachable tip, singularity,
    /// limit), or a tip target is not finite (at `t = 0`, before any sample).
    #[error("{}{error}", AtTime(*t))]
    Kinematics {
        /// The sample's time, s.
        t: f64,
        /// The sample's index; `None` when no sample was computed.
        sample: Option<usize>,
        /// What failed.
        error: parasils::kin::Error,
    },
    /// The retargets or the stop cannot be scheduled.
    #[error("commands: {0}")]
    Commands(CommandError),
    /// A motion of a procedure failed: which one, when inside it, and what
    /// failed (the error's own time is from the procedure's start).
    #[error(
        "{motion}, {} s into it{}: {}",
        Fixed(*t_motion, 3),
        error.time_s().map(|t| format!(" (t = {} s)", Fixed(t, 3))).unwrap_or_default(),
        error.without_time()
    )]
    Motion {
        /// The motion.
        motion: Box<MotionName>,
        /// The time inside it, s.
        t_motion: f64,
        /// What failed.
        error: Box<SimulationError>,
    },
    /// A procedure's motions do not follow each other (a stop with nothing
    /// to stop, a motion of another type after one cut short while moving).
    #[error("{0}")]
    Procedure(String),
    /// An actuator's velocity or acceleration beyond its limit at a sample.
    #[error("{}{error}", AtTime(*t))]
    ActuatorLimit {
        /// The sample's time, s.
        t: f64,
        /// The sample's index.
        sample: Option<usize>,
        /// Which actuator, the value and the limit.
        error: LimitError,
    },
    /// The time-optimal law cannot be computed.
    #[error("time-optimal timing: {0}")]
    Timing(TimingError),
    /// An option that does not apply to this run.
    #[error("{0}")]
    Unsupported(&'static str),
    /// The margin supervisor's thresholds are invalid (a stop threshold not
    /// above the solvers' hard one, a warning below its stop threshold).
    #[error("supervisor thresholds: {0}")]
    Supervisor(parasils::Error),
    /// The online controller refused a call for another reason than the
    /// kinematics or the trajectory (for instance, a supervisor threshold).
    #[error("{}{error}", AtTime(*t))]
    Controller {
        /// The sample's time, s.
        t: f64,
        /// The sample's index.
        sample: Option<usize>,
        /// What failed.
        error: parasils::Error,
    },
}

impl SimulationError {
    /// The message without its leading time (for errors placed in a
    /// motion, which give the time inside it).
    fn without_time(&self) -> String {
        match self {
            SimulationError::Kinematics { error, .. } => error.to_string(),
            SimulationError::Controller { error, .. } => error.to_string(),
            SimulationError::ActuatorLimit { error, .. } => error.to_string(),
            e => e.to_string(),
        }
    }

    /// The time of the failure, s from the start, when there is one.
    pub fn time_s(&self) -> Option<f64> {
        match self {
            SimulationError::Kinematics { t, .. }
            | SimulationError::Controller { t, .. }
            | SimulationError::ActuatorLimit { t, .. } => Some(*t),
            SimulationError::Motion { error, .. } => error.time_s(),
            _ => None,
        }
    }
}

/// A command as the errors name it: `the reorientation`, `retarget 2` (the
/// second given, counting from 1), `the stop`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CommandName {
    /// The scenario's reorientation.
    Reorientation,
    /// The retarget given in this place, from 1.
    Retarget(usize),
    /// The stop.
    Stop,
}

impl core::fmt::Display for CommandName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CommandName::Reorientation => f.write_str("the reorientation"),
            CommandName::Retarget(n) => write!(f, "retarget {n}"),
            CommandName::Stop => f.write_str("the stop"),
        }
    }
}

/// Why the commands of a scenario cannot be scheduled.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CommandError {
    /// Retargets and stops change the paper's reorientation while it runs;
    /// a procedure plans its motions in full instead.
    #[error("retargets and stops apply to a single reorientation, not to a procedure's motions")]
    InProcedure,
    /// A time or an angle is NaN or infinite.
    #[error("{command}: {what} = {} is not a finite number", Shortest(*value))]
    NonFinite {
        /// The command.
        command: CommandName,
        /// `"t"`, `"psi"` or `"theta"`.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A time is negative.
    #[error("{command}: t = {} s is before the start (t = 0)", Shortest(*t))]
    BeforeStart {
        /// The command.
        command: CommandName,
        /// Its time, s.
        t: f64,
    },
    /// The retargets are not given in time order.
    #[error(
        "{command} at t = {} s comes before {previous} at t = {} s: give the retargets in time order",
        Shortest(*t),
        Shortest(*previous_t)
    )]
    OutOfOrder {
        /// The retarget out of order.
        command: CommandName,
        /// Its time, s.
        t: f64,
        /// The retarget given before it.
        previous: CommandName,
        /// That one's time, s.
        previous_t: f64,
    },
    /// Two commands take effect at the same sample: the first would never
    /// be active, and the output could not show it.
    #[error(
        "{command} at t = {} s takes effect at the same sample as {previous} at t = {} s (t = {} s at {} Hz): give each command a sample of its own",
        Shortest(*t),
        Shortest(*previous_t),
        Shortest(*sample_t),
        Shortest(*rate)
    )]
    SameSample {
        /// The later command.
        command: CommandName,
        /// Its time, s.
        t: f64,
        /// The command before it.
        previous: CommandName,
        /// That one's time, s.
        previous_t: f64,
        /// The sample's time, s.
        sample_t: f64,
        /// The sampling rate, Hz.
        rate: f64,
    },
}

/// A run's failure: the engine's, or the sink's.
#[derive(Debug, thiserror::Error)]
pub enum RunError<E> {
    /// The engine failed.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// The sink failed (for instance, an I/O error while writing); its
    /// message says what it was writing.
    #[error("{0}")]
    Sink(E),
}

/// A command with the sample it takes effect at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scheduled {
    /// The command as given.
    pub command: Command,
    /// Its goal `[psi, theta]` as final angles, rad; `None` for the stop.
    pub goal_rad: Option<[f64; 2]>,
    /// The first sample at or after its time: where it takes effect.
    pub sample: usize,
    /// That sample's time, `sample / rate`, s.
    pub t_s: f64,
}

/// How the samples are computed.
#[derive(Debug, Clone)]
#[allow(
    clippy::large_enum_variant,
    reason = "one per simulation, never in a collection"
)]
enum Plan {
    /// Without commands: the rest-to-rest reorientation.
    Rest(Sampler<f64, OnCycle<Reorientation<f64>, f64>>),
    /// With commands: the online controller, at rest at the start, and the
    /// sampling rate.
    Online(OnlineController<f64>, f64),
    /// A procedure: its motions on one time line.
    Procedure(Sampler<f64, ProcedurePlan>),
    /// Without commands, timed to the actuators' limits.
    Optimal(Sampler<f64, OnCycle<OptimalReorientation, f64>>),
}

/// What a record says besides the kinematics: the command and motion it
/// belongs to, the supervisor's warnings, the endoscope.
#[derive(Debug, Clone, Copy)]
struct Context {
    command: u32,
    kind: CommandKind,
    warnings: MarginSet,
    motion: u32,
    motion_type: u8,
    endoscope_depth: f64,
    endoscope_tip: Vector3<f64>,
}

impl Context {
    /// A run without a procedure: motion 0, of type 4.
    fn command(command: u32, kind: CommandKind, warnings: MarginSet) -> Self {
        Self {
            command,
            kind,
            warnings,
            motion: 0,
            motion_type: 4,
            endoscope_depth: 0.0,
            endoscope_tip: Vector3::zeros(),
        }
    }
}

/// A scenario, validated and planned, ready to run.
#[derive(Debug, Clone)]
pub struct Simulation {
    scenario: Scenario,
    controller: Controller<f64>,
    tips: TipTargets<f64>,
    plan: Plan,
    schedule: Vec<Scheduled>,
    count: usize,
    duration: f64,
    /// The start's Euler angles, deg (the user's) and rad.
    start_deg: [f64; 3],
    start_rad: [f64; 3],
    /// The margin supervisor whose warnings a procedure's records carry.
    supervisor: Supervisor<f64>,
    /// A procedure's check, made in [`Simulation::new`].
    check: Option<ProcedureCheck>,
}

/// The supervisor of `scenario` on `controller`: [`supervisor_for`] with the
/// thresholds the robot file sets, validated.
fn scenario_supervisor(
    scenario: &Scenario,
    controller: &Controller<f64>,
) -> Result<Supervisor<f64>, SimulationError> {
    let s = scenario.supervisor.apply(supervisor_for(controller));
    s.validate(&Margins::hard(controller))
        .map_err(SimulationError::Supervisor)?;
    Ok(s)
}

/// The supervisor of `controller`: [`Supervisor::default`], each stop
/// threshold raised to at least 3 times the solvers' hard one and each
/// warning threshold to at least 10 times, so that a robot file with higher
/// hard thresholds than the paper's robot keeps the same proportions.
fn supervisor_for(controller: &Controller<f64>) -> Supervisor<f64> {
    let hard = Margins::hard(controller);
    let mut s = Supervisor::<f64>::default();
    for (k, h) in hard.0.iter().enumerate() {
        if let (Some(stop), Some(warn)) = (s.stop.0.get_mut(k), s.warn.0.get_mut(k)) {
            *stop = stop.max(3.0 * h);
            *warn = warn.max(10.0 * h);
        }
    }
    s
}

/// The first sample index `k >= from` whose time `k / rate` satisfies
/// `ready` (monotone: false, then true), starting the search near `guess`
/// s; `None` when it does not fit `usize`.
fn first_sample(rate: f64, from: usize, guess: f64, ready: impl Fn(f64) -> bool) -> Option<usize> {
    let x = (guess * rate).ceil();
    // From 2^53 on, not every index is an f64 of its own: refuse them.
    if !(x.is_finite() && x < 9.007_199_254_740_992e15) {
        return None;
    }
    // In range: checked just above (and `max(0)`).
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let mut k = (x.max(0.0) as usize).max(from);
    let time = |k: usize| k as f64 / rate;
    // The guess is within a sample or two of the answer (rounding): a few
    // steps back, then forward until `ready` holds (a step or two in
    // practice; `ready` is true from the guess's time on, up to rounding).
    for _ in 0..4 {
        if k > from && ready(time(k - 1)) {
            k -= 1;
        }
    }
    while !ready(time(k)) {
        k = k.checked_add(1)?;
    }
    Some(k)
}

/// The kinematics' error of an online call at sample `k`, time `t`.
fn online_error(error: parasils::Error, t: f64, k: usize) -> SimulationError {
    match error {
        parasils::Error::Kinematics(error) => SimulationError::Kinematics {
            t,
            sample: Some(k),
            error,
        },
        parasils::Error::Trajectory(e) => SimulationError::Trajectory(e),
        error => SimulationError::Controller {
            t,
            sample: Some(k),
            error,
        },
    }
}

impl Simulation {
    /// Validates the scenario and plans the trajectory: through
    /// [`Reorientation::new`] without commands; with commands, through an
    /// [`OnlineController`] given every command at its sample (the kinematics
    /// solved once, at the start pose), which tells the run's length.
    ///
    /// # Errors
    /// [`SimulationError::Geometry`] for an invalid robot,
    /// [`SimulationError::Trajectory`] for angles, limits or a rate that
    /// cannot be planned, [`SimulationError::Kinematics`] for a non-finite
    /// tip target (or, with commands, a start pose that cannot be solved),
    /// [`SimulationError::Commands`] for commands that cannot be scheduled.
    pub fn new(scenario: Scenario) -> Result<Self, SimulationError> {
        let controller =
            Controller::from_geometry(&scenario.robot).map_err(SimulationError::Geometry)?;
        let start = scenario.start();
        let reorientation = Reorientation::new(
            start,
            scenario.goal_rad(),
            [scenario.limits(); 2],
            scenario.sync,
        )
        .map_err(SimulationError::Trajectory)?;
        let tips = scenario.tips();
        for (what, v) in [("left tip", tips.left), ("right tip", tips.right)] {
            if let Some(value) = v.iter().copied().find(|x| !x.is_finite()) {
                return Err(SimulationError::Kinematics {
                    t: 0.0,
                    sample: None,
                    error: parasils::kin::Error::NonFinite { what, value },
                });
            }
        }
        let procedure = !scenario.motions.is_empty();
        let (plan, schedule, count, duration) = if procedure {
            if scenario.has_commands() {
                return Err(SimulationError::Commands(CommandError::InProcedure));
            }
            let plan = ProcedurePlan::new(&scenario, &controller)?;
            let duration = plan.duration();
            let sampler =
                Sampler::new(plan, scenario.rate_hz).map_err(SimulationError::Trajectory)?;
            let schedule = vec![Scheduled {
                command: scenario.commands()[0],
                goal_rad: None,
                sample: 0,
                t_s: 0.0,
            }];
            (
                Plan::Procedure(sampler.clone()),
                schedule,
                sampler.sample_count(),
                duration,
            )
        } else if let Timing::Optimal { angular } = scenario.timing {
            if scenario.has_commands() {
                return Err(SimulationError::Unsupported(
                    "the time-optimal timing plans one reorientation from rest to rest: it does not take retargets or a stop",
                ));
            }
            let options = TimingOptions {
                angular: angular.then(|| [scenario.limits(); 2]),
                ..TimingOptions::default()
            };
            let plan = OptimalReorientation::plan(
                &controller,
                start,
                scenario.goal_rad(),
                tips,
                &controller.limits,
                &options,
            )
            .map_err(SimulationError::Timing)?;
            let plan = OnCycle::new(plan, scenario.rate_hz).map_err(SimulationError::Trajectory)?;
            let duration = plan.stretch().duration();
            let sampler =
                Sampler::new(plan, scenario.rate_hz).map_err(SimulationError::Trajectory)?;
            let schedule = vec![Scheduled {
                command: scenario.commands()[0],
                goal_rad: Some(scenario.goal_rad()),
                sample: 0,
                t_s: 0.0,
            }];
            let count = sampler.sample_count();
            (Plan::Optimal(sampler), schedule, count, duration)
        } else if scenario.has_commands() {
            Self::plan_online(&scenario, controller, tips)?
        } else {
            let turn = OnCycle::new(reorientation, scenario.rate_hz)
                .map_err(SimulationError::Trajectory)?;
            let duration = turn.stretch().duration();
            let sampler =
                Sampler::new(turn, scenario.rate_hz).map_err(SimulationError::Trajectory)?;
            let schedule = vec![Scheduled {
                command: scenario.commands()[0],
                goal_rad: Some(scenario.goal_rad()),
                sample: 0,
                t_s: 0.0,
            }];
            let count = sampler.sample_count();
            (Plan::Rest(sampler), schedule, count, duration)
        };
        let [_, _, _, psi, theta, phi] = scenario.start_mm_deg;
        let mut sim = Self {
            start_deg: [psi, theta, phi],
            start_rad: [start.psi, start.theta, start.phi],
            supervisor: scenario_supervisor(&scenario, &controller)?,
            scenario,
            controller,
            tips,
            plan,
            schedule,
            count,
            duration,
            check: None,
        };
        if let Plan::Procedure(sampler) = &sim.plan {
            // Plan, then check, then write: every sample computed once here,
            // so that a failure is known before the first byte of output.
            let mut check = ProcedureCheck::new(sampler.motion());
            let mut run = ProcedureRun::new(sampler.clone(), controller);
            while let Some(r) = run.next(&sim) {
                let (record, margins) = r?;
                check.push(&record, &margins, &sim.supervisor, &controller.limits);
            }
            if let Some(e) = sampler.motion().failure() {
                return Err(e.clone());
            }
            sim.check = Some(check);
        }
        Ok(sim)
    }

    /// A procedure's check (per motion: duration, peak rates, smallest
    /// margins; the supervisor's warnings), made before any output; `None`
    /// for a run without motions.
    pub fn procedure_check(&self) -> Option<&ProcedureCheck> {
        self.check.as_ref()
    }

    /// The time-optimal law, for a run timed with [`Timing::Optimal`].
    pub fn optimal(&self) -> Option<&OptimalReorientation> {
        match &self.plan {
            Plan::Optimal(sampler) => Some(sampler.motion().motion()),
            _ => None,
        }
    }

    /// A procedure's plan; `None` for a run without motions.
    pub fn procedure(&self) -> Option<&ProcedurePlan> {
        match &self.plan {
            Plan::Procedure(sampler) => Some(sampler.motion()),
            _ => None,
        }
    }

    /// The margin supervisor whose thresholds a procedure's warnings use.
    pub fn supervisor(&self) -> &Supervisor<f64> {
        &self.supervisor
    }

    /// The online plan: the commands validated and scheduled, the
    /// controller at rest at the start, the planned sample count and the
    /// time the last motion comes to rest.
    fn plan_online(
        scenario: &Scenario,
        controller: Controller<f64>,
        tips: TipTargets<f64>,
    ) -> Result<(Plan, Vec<Scheduled>, usize, f64), SimulationError> {
        let rate = scenario.rate_hz;
        if !(rate.is_finite() && rate > 0.0) {
            return Err(SimulationError::Trajectory(
                parasils::traj::Error::InvalidRate { value: rate },
            ));
        }
        let schedule = schedule(scenario)?;
        let online = OnlineController::new(
            controller,
            tips,
            scenario.start(),
            [scenario.limits(); 2],
            scenario_supervisor(scenario, &controller)?,
        )
        .map_err(|e| online_error(e, 0.0, 0))?;
        // The run planned: every command at its sample, no cycle run (the
        // supervisor, which needs the kinematics, can only end it sooner
        // or start a later command from rest).
        let mut dry = online;
        for s in &schedule {
            apply(&mut dry, s, scenario).map_err(|e| online_error(e, s.t_s, s.sample))?;
        }
        let too_many = |duration: f64| {
            SimulationError::Trajectory(parasils::traj::Error::TooManySamples { duration, rate })
        };
        let last = schedule.last().map_or(0, |s| s.sample);
        let end = dry.motion_end();
        let n = first_sample(rate, last, end, |t| dry.is_at_rest(t)).ok_or(too_many(end))?;
        let count = n.checked_add(1).ok_or(too_many(end))?;
        Ok((Plan::Online(online, rate), schedule, count, end))
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// Whether module 1's geometry is the assumed one (not the real robot's).
    pub fn module1_assumed(&self) -> bool {
        self.scenario.robot.module1.assumed
    }

    /// The tips held still, mm, fixed frame.
    pub fn tips(&self) -> &TipTargets<f64> {
        &self.tips
    }

    /// The controller (the geometry of every module).
    pub fn controller(&self) -> &Controller<f64> {
        &self.controller
    }

    /// The commands with the samples they take effect at: the reorientation
    /// at sample 0, then, in a run with commands, each retarget and the stop
    /// in time order.
    pub fn schedule(&self) -> &[Scheduled] {
        &self.schedule
    }

    /// The motion's duration, s: the reorientation's; with commands, the
    /// time the last motion comes to rest as planned (a stop demanded by
    /// the supervisor can change it).
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The number of records: `t = k / rate` for `k = 0..n`, the last one at
    /// the end of the motion (see `parasils_traj::sampler`); with commands,
    /// the first sample at which every command has taken effect and the last
    /// motion is at rest, as planned (a stop demanded by the supervisor can
    /// change it).
    pub fn sample_count(&self) -> usize {
        self.count
    }

    /// The records, computed one at a time. Each call starts the controller
    /// afresh (module 1's margin tracked from the first sample).
    pub fn samples(&self) -> Records<'_> {
        let inner = match &self.plan {
            Plan::Rest(sampler) => Inner::Rest {
                sampler: sampler.clone(),
                tracker: MarginTracker::new(),
            },
            Plan::Procedure(sampler) => {
                Inner::Procedure(ProcedureRun::new(sampler.clone(), self.controller))
            }
            Plan::Optimal(sampler) => Inner::Optimal {
                sampler: sampler.clone(),
                tracker: MarginTracker::new(),
            },
            Plan::Online(online, rate) => Inner::Online(OnlineRun {
                controller: *online,
                rate: *rate,
                next: 0,
                pending: 0,
                kind: CommandKind::Reorient,
                done: false,
            }),
        };
        Records { sim: self, inner }
    }

    /// Runs the whole motion into `sink`, record by record; stops at the
    /// first failure.
    ///
    /// # Errors
    /// [`RunError::Simulation`] when the kinematics fail at a sample,
    /// [`RunError::Sink`] when the sink does.
    pub fn run<S: Sink + ?Sized>(&self, sink: &mut S) -> Result<(), RunError<S::Error>> {
        for record in self.samples() {
            sink.push(&record?).map_err(RunError::Sink)?;
        }
        Ok(())
    }

    /// The record of sample `index` at `t`: the platform `state` and the
    /// controller's `out` for it, the tips commanded `targets`, in `context`.
    fn record(
        &self,
        index: usize,
        t: f64,
        state: &PlatformState<f64>,
        out: &ControlStep<f64>,
        targets: &TipTargets<f64>,
        context: Context,
    ) -> Record {
        let module = |m: &Instrument<f64>,
                      sol: &InstrumentSolution<f64>,
                      mode: AssemblyMode,
                      target: Vector3<f64>| {
            // The tip by forward kinematics from the joints, placed with the
            // step's own platform frame (the rotation `Instrument::fk` would
            // evaluate again from the Euler angles, the same numbers): `q`
            // and the frame are finite, the step checked them.
            let tip = out.frame.to_fixed(&m.fk_platform(&sol.q));
            // `cos qs2` signed: `|cos qs2|` from the step's margins, positive
            // in mode A and negative in mode B (the IK keeps the mode).
            let cos_qs2 = match mode {
                AssemblyMode::A => sol.margins.cos_qs2,
                AssemblyMode::B => -sol.margins.cos_qs2,
            };
            InstrumentRecord {
                q: sol.q.to_array(),
                q_dot: sol.q_dot.to_array(),
                q_ddot: sol.q_ddot.to_array(),
                cos_qs2,
                tip,
                tip_err: (tip - target).norm(),
            }
        };
        let p = &state.pose;
        let m1 = &out.module1;
        Record {
            index,
            t,
            pose: p.to_array(),
            angles_deg: Record::degrees_from_start(
                [p.psi, p.theta, p.phi],
                self.start_deg,
                self.start_rad,
            ),
            euler_dot: [state.velocity.psi, state.velocity.theta, state.velocity.phi],
            euler_ddot: [
                state.acceleration.psi,
                state.acceleration.theta,
                state.acceleration.phi,
            ],
            module1: Module1Record {
                q: m1.q.to_array(),
                q_dot: m1.q_dot.to_array(),
                q_ddot: m1.q_ddot.to_array(),
                serial_margin: m1.margins.serial_min,
                parallel_margin: m1.margins.parallel,
            },
            left: module(
                &self.controller.left,
                &out.left,
                self.controller.modes[0],
                targets.left,
            ),
            right: module(
                &self.controller.right,
                &out.right,
                self.controller.modes[1],
                targets.right,
            ),
            command: context.command,
            kind: context.kind,
            warnings: context.warnings,
            motion: context.motion,
            motion_type: context.motion_type,
            endoscope_depth: context.endoscope_depth,
            endoscope_tip: context.endoscope_tip,
        }
    }
}

/// The commands of `scenario`, validated, with their samples.
fn schedule(scenario: &Scenario) -> Result<Vec<Scheduled>, SimulationError> {
    let fail = SimulationError::Commands;
    let finite = |command, what, value: f64| {
        if value.is_finite() {
            Ok(())
        } else {
            Err(fail(CommandError::NonFinite {
                command,
                what,
                value,
            }))
        }
    };
    let mut previous: Option<(CommandName, f64)> = None;
    for (k, r) in scenario.retargets.iter().enumerate() {
        let name = CommandName::Retarget(k + 1);
        finite(name, "t", r.t_s)?;
        finite(name, "psi", r.psi_deg)?;
        finite(name, "theta", r.theta_deg)?;
        if r.t_s < 0.0 {
            return Err(fail(CommandError::BeforeStart {
                command: name,
                t: r.t_s,
            }));
        }
        if let Some((p, t)) = previous
            && r.t_s < t
        {
            return Err(fail(CommandError::OutOfOrder {
                command: name,
                t: r.t_s,
                previous: p,
                previous_t: t,
            }));
        }
        previous = Some((name, r.t_s));
    }
    if let Some(t) = scenario.stop_at_s {
        finite(CommandName::Stop, "t", t)?;
        if t < 0.0 {
            return Err(fail(CommandError::BeforeStart {
                command: CommandName::Stop,
                t,
            }));
        }
    }
    let rate = scenario.rate_hz;
    let mut out: Vec<Scheduled> = Vec::with_capacity(scenario.retargets.len() + 2);
    let mut retargets = 0;
    let mut names = Vec::with_capacity(out.capacity());
    for command in scenario.commands() {
        let name = match command.kind {
            CommandKind::Reorient => CommandName::Reorientation,
            CommandKind::Retarget => {
                retargets += 1;
                CommandName::Retarget(retargets)
            }
            _ => CommandName::Stop,
        };
        let from = out.last().map_or(0, |s| s.sample);
        let sample = first_sample(rate, from, command.t_s, |t| t >= command.t_s).ok_or(
            SimulationError::Trajectory(parasils::traj::Error::TooManySamples {
                duration: command.t_s,
                rate,
            }),
        )?;
        let t_s = sample as f64 / rate;
        if let (Some(p), Some(&pname)) = (out.last(), names.last())
            && p.sample == sample
        {
            return Err(fail(CommandError::SameSample {
                command: name,
                t: command.t_s,
                previous: pname,
                previous_t: p.command.t_s,
                sample_t: t_s,
                rate,
            }));
        }
        names.push(name);
        out.push(Scheduled {
            command,
            goal_rad: command.goal_deg.map(|g| scenario.angles_rad(g)),
            sample,
            t_s,
        });
    }
    Ok(out)
}

/// Gives `s`'s command to `online` at its sample's time.
fn apply(
    online: &mut OnlineController<f64>,
    s: &Scheduled,
    scenario: &Scenario,
) -> Result<(), parasils::Error> {
    match s.goal_rad {
        Some(goal) => online
            .command_synchronized(s.t_s, goal, scenario.sync)
            .map(|_| ()),
        None => online.stop(s.t_s),
    }
}

/// The records of a [`Simulation`], computed one at a time
/// ([`Simulation::samples`]).
#[derive(Debug)]
pub struct Records<'a> {
    sim: &'a Simulation,
    inner: Inner,
}

#[derive(Debug)]
#[allow(
    clippy::large_enum_variant,
    reason = "one per run, never in a collection"
)]
enum Inner {
    Rest {
        sampler: Sampler<f64, OnCycle<Reorientation<f64>, f64>>,
        tracker: MarginTracker<f64>,
    },
    Online(OnlineRun),
    Procedure(ProcedureRun),
    Optimal {
        sampler: Sampler<f64, OnCycle<OptimalReorientation, f64>>,
        tracker: MarginTracker<f64>,
    },
}

/// The record of a planned reorientation's sample `k` at `t` in `state`:
/// the controller's step, checked against the actuators' limits.
fn planned_record(
    sim: &Simulation,
    tracker: &mut MarginTracker<f64>,
    k: usize,
    t: f64,
    state: &PlatformState<f64>,
) -> Result<Record, SimulationError> {
    let controller = &sim.controller;
    let out = controller
        .step(state, &sim.tips, tracker)
        .map_err(|error| SimulationError::Kinematics {
            t,
            sample: Some(k),
            error,
        })?;
    check_limits(controller, &out, t, k)?;
    Ok(sim.record(
        k,
        t,
        state,
        &out,
        &sim.tips,
        Context::command(0, CommandKind::Reorient, MarginSet::EMPTY),
    ))
}

/// `step` against the actuators' limits of `controller`.
fn check_limits(
    controller: &Controller<f64>,
    step: &ControlStep<f64>,
    t: f64,
    k: usize,
) -> Result<(), SimulationError> {
    controller
        .limits
        .check(step)
        .map_err(|error| SimulationError::ActuatorLimit {
            t,
            sample: Some(k),
            error,
        })
}

/// A procedure's run under way.
#[derive(Debug)]
struct ProcedureRun {
    sampler: Sampler<f64, ProcedurePlan>,
    controller: Controller<f64>,
    tracker: MarginTracker<f64>,
    done: bool,
}

impl ProcedureRun {
    fn new(sampler: Sampler<f64, ProcedurePlan>, controller: Controller<f64>) -> Self {
        Self {
            sampler,
            controller,
            tracker: MarginTracker::new(),
            done: false,
        }
    }

    /// The next record with its margins; after a failure, nothing more.
    fn next(
        &mut self,
        sim: &Simulation,
    ) -> Option<Result<(Record, Margins<f64>), SimulationError>> {
        if self.done {
            return None;
        }
        let s = self.sampler.next()?;
        let (t, k) = (s.time, s.index);
        let (m, sample) = s.state;
        let plan = self.sampler.motion();
        let planned = plan.motions.get(m);
        let in_motion = |error: SimulationError| SimulationError::Motion {
            motion: Box::new(planned.map_or_else(
                || crate::motion::MotionName {
                    index: m,
                    motion_type: parasils::motions::MotionType::Reorient,
                    stop: false,
                    name: None,
                },
                |p| p.name.clone(),
            )),
            t_motion: t - planned.map_or(0.0, |p| p.start_s),
            error: Box::new(error),
        };
        let fail = |error| {
            in_motion(SimulationError::Kinematics {
                t,
                sample: Some(k),
                error,
            })
        };
        let result = (|| {
            let out = self
                .controller
                .step_commanded(
                    &sample.platform,
                    &sample.left,
                    &sample.right,
                    &mut self.tracker,
                )
                .map_err(fail)?;
            let endoscope_tip = self
                .controller
                .endoscope
                .tip(&out.frame, sample.endoscope.position)
                .map_err(fail)?;
            self.controller.limits.check(&out).map_err(|error| {
                in_motion(SimulationError::ActuatorLimit {
                    t,
                    sample: Some(k),
                    error,
                })
            })?;
            let margins = Margins::of(&out);
            let targets = procedure::commanded_tips(&self.controller, &sample, &out.frame);
            let motion_type = plan
                .motions
                .get(m)
                .map_or(4, |p| p.motion.motion_type().number());
            let context = Context {
                command: 0,
                kind: CommandKind::Reorient,
                warnings: sim.supervisor.check(&margins).warnings,
                motion: u32::try_from(m).unwrap_or(u32::MAX),
                motion_type,
                endoscope_depth: sample.endoscope.position,
                endoscope_tip,
            };
            let record = sim.record(k, t, &sample.platform, &out, &targets, context);
            Ok((record, margins))
        })();
        if result.is_err() {
            self.done = true;
        }
        Some(result)
    }
}

/// An online run under way.
#[derive(Debug)]
struct OnlineRun {
    controller: OnlineController<f64>,
    rate: f64,
    /// The next sample's index.
    next: usize,
    /// The next scheduled command to give.
    pending: usize,
    /// What the active command is.
    kind: CommandKind,
    /// Whether the last record has been given (or a failure).
    done: bool,
}

impl Iterator for Records<'_> {
    type Item = Result<Record, SimulationError>;

    fn next(&mut self) -> Option<Self::Item> {
        let sim = self.sim;
        match &mut self.inner {
            Inner::Rest { sampler, tracker } => {
                let s = sampler.next()?;
                Some(planned_record(sim, tracker, s.index, s.time, &s.state))
            }
            Inner::Optimal { sampler, tracker } => {
                let s = sampler.next()?;
                Some(planned_record(sim, tracker, s.index, s.time, &s.state))
            }
            Inner::Procedure(run) => run.next(sim).map(|r| r.map(|(record, _)| record)),
            Inner::Online(run) => {
                if run.done {
                    return None;
                }
                let r = run.step(sim);
                if r.is_err() {
                    run.done = true;
                }
                Some(r)
            }
        }
    }
}

impl OnlineRun {
    /// The next sample: the commands due at it given, then one cycle.
    fn step(&mut self, sim: &Simulation) -> Result<Record, SimulationError> {
        let k = self.next;
        let t = k as f64 / self.rate;
        while let Some(s) = sim.schedule.get(self.pending).filter(|s| s.sample <= k) {
            apply(&mut self.controller, s, &sim.scenario).map_err(|e| online_error(e, t, k))?;
            self.kind = s.command.kind;
            self.pending += 1;
        }
        let cycle = self.controller.tick(t).map_err(|e| online_error(e, t, k))?;
        check_limits(self.controller.controller(), &cycle.step, t, k)?;
        if cycle.kind == MotionKind::SupervisorStop {
            self.kind = CommandKind::SupervisorStop;
        }
        let record = sim.record(
            k,
            t,
            &cycle.state,
            &cycle.step,
            &sim.tips,
            Context::command(cycle.command, self.kind, cycle.warnings),
        );
        let finished = self.pending >= sim.schedule.len() && self.controller.is_at_rest(t);
        match k.checked_add(1) {
            Some(next) if !finished => self.next = next,
            _ => self.done = true,
        }
        Ok(record)
    }
}

pub mod procedure;
#[cfg(test)]
mod tests;
