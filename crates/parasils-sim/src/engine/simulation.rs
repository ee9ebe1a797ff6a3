//! [`Simulation`]: a scenario validated and planned, before any record: a
//! planned run's timeline (one path, whatever its motions), or an online
//! run's commands on the sample grid.

use super::procedure::{ProcedureCheck, ProcedurePlan};
use nalgebra::{Matrix3, Vector3};
use parasils::kin::{
    AssemblyMode, Camera, ControlStep, Controller, ImagePoint, Instrument, InstrumentSolution,
    PlatformFrame, PlatformState, TipTargets,
};
use parasils::supervisor::ClearanceThresholds;
use parasils::supervisor::{MarginSet, Margins};
use parasils::traj::{Sampler, Synchronization};
use parasils::{ClearanceWatch, OnlineController, Reorientation, Supervisor};

use crate::motion::{MotionGoal, MotionSpec};
use crate::record::{
    CameraRecord, ClearanceRecord, ForceRecord, InstrumentRecord, Module1Record, Record,
};
use crate::scenario::{CommandKind, Online, Run, Scenario};
use crate::sink::Sink;
use crate::timing::OptimalMotion;

use super::error::{RunError, SimulationError};
use super::records::{Inner, OnlineRun, ProcedureRun, Records};
use super::schedule::{Scheduled, apply, first_sample, schedule};

/// How the samples are computed.
#[derive(Debug, Clone)]
#[allow(
    clippy::large_enum_variant,
    reason = "one per simulation, never in a collection"
)]
pub(super) enum Plan {
    /// A planned timeline (the paper's turn, a procedure): its motions on
    /// one time line of samples, and, for a procedure, the check of every
    /// sample made before any output.
    Planned(Sampler<f64, ProcedurePlan>, Option<ProcedureCheck>),
    /// With commands: the online controller, at rest at the start, and the
    /// sampling rate.
    Online(OnlineController<f64>, f64),
}

/// What a record says besides the kinematics: the command and motion it
/// belongs to, the supervisor's warnings, the endoscope.
#[derive(Debug, Clone, Copy)]
pub(super) struct Context {
    pub(super) command: u32,
    pub(super) kind: CommandKind,
    pub(super) warnings: MarginSet,
    pub(super) motion: u32,
    pub(super) motion_type: u8,
    pub(super) endoscope_depth: f64,
    pub(super) endoscope_tip: Vector3<f64>,
}

impl Context {
    /// A run without a procedure: motion 0, of type 4.
    pub(super) fn command(command: u32, kind: CommandKind, warnings: MarginSet) -> Self {
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
    pub(super) scenario: Scenario,
    pub(super) controller: Controller<f64>,
    pub(super) tips: TipTargets<f64>,
    pub(super) plan: Plan,
    pub(super) schedule: Vec<Scheduled>,
    pub(super) count: usize,
    pub(super) duration: f64,
    /// The start's Euler angles, deg (the user's) and rad.
    pub(super) start_deg: [f64; 3],
    pub(super) start_rad: [f64; 3],
    /// The platform's rotation at the start: the camera's roll is measured
    /// from it.
    pub(super) start_rotation: Matrix3<f64>,
    /// The margin supervisor whose warnings a planned run's records carry.
    pub(super) supervisor: Supervisor<f64>,
}

/// The supervisor of `scenario` on `controller`: [`supervisor_for`] with the
/// thresholds the robot file sets, validated.
pub(super) fn scenario_supervisor(
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
pub(super) fn supervisor_for(controller: &Controller<f64>) -> Supervisor<f64> {
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

/// The kinematics' error of an online call at sample `k`, time `t`.
pub(super) fn online_error(error: parasils::Error, t: f64, k: usize) -> SimulationError {
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
    /// Validates the scenario and plans it: a planned [`Timeline`](crate::Timeline)
    /// motion by motion ([`ProcedurePlan`]), a procedure's every sample then
    /// computed and checked once before any output ([`ProcedureCheck`]); an
    /// online run
    /// through an [`OnlineController`] given every command at its sample
    /// (the kinematics solved once, at the start pose), which tells the
    /// run's length.
    ///
    /// # Errors
    /// [`SimulationError::Geometry`] for an invalid robot,
    /// [`SimulationError::Trajectory`] for angles, limits or a rate that
    /// cannot be planned, [`SimulationError::Kinematics`] for a non-finite
    /// tip target or a start that cannot be solved,
    /// [`SimulationError::Commands`] for commands that cannot be scheduled;
    /// in a procedure, [`SimulationError::Motion`] naming the motion whose
    /// planning or sample fails.
    pub fn new(scenario: Scenario) -> Result<Self, SimulationError> {
        let controller =
            Controller::from_geometry(&scenario.robot).map_err(SimulationError::Geometry)?;
        let start = scenario.start();
        if let Some(turn) = scenario.turn() {
            // The turn's angles and limits, checked before anything is
            // solved (as the paper's run always has).
            Reorientation::new(start, turn.goal_rad(&start), [turn.limits(); 2], turn.sync)
                .map_err(SimulationError::Trajectory)?;
        }
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
        let (plan, schedule, count, duration) = match &scenario.run {
            Run::Planned(timeline) => {
                let plan = ProcedurePlan::new(&scenario, timeline, &controller)?;
                let duration = plan.duration();
                let sampler =
                    Sampler::new(plan, scenario.rate_hz).map_err(SimulationError::Trajectory)?;
                let schedule = vec![Scheduled {
                    command: scenario.commands()[0],
                    goal_rad: scenario.turn().map(|_| scenario.goal_rad()),
                    sample: 0,
                    t_s: 0.0,
                }];
                let count = sampler.sample_count();
                // A procedure's check is made below, once the simulation can
                // make records.
                let plan = Plan::Planned(sampler, None);
                (plan, schedule, count, duration)
            }
            Run::Online(online) => Self::plan_online(&scenario, online, controller, tips)?,
        };
        let [_, _, _, psi, theta, phi] = scenario.start_mm_deg;
        let mut sim = Self {
            start_deg: [psi, theta, phi],
            start_rad: [start.psi, start.theta, start.phi],
            start_rotation: start.rotation(),
            supervisor: scenario_supervisor(&scenario, &controller)?,
            scenario,
            controller,
            tips,
            plan,
            schedule,
            count,
            duration,
        };
        if let Plan::Planned(sampler, _) = &sim.plan
            && (sim.scenario.is_procedure() || sim.scenario.anatomy.is_some())
        {
            // A procedure: plan, then check, then write; every sample
            // computed once here, so that a failure is known before the
            // first byte of output and `--check` can report it. The single
            // turn streams instead (a failure ends its run at that sample),
            // so that a run too long to write is refused before any sample
            // is computed.
            let sampler = sampler.clone();
            let mut check = ProcedureCheck::new(sampler.motion(), &controller.endoscope.camera);
            if let Some(anatomy) = &sim.scenario.anatomy {
                check.no_go_regions = anatomy.regions.iter().map(|r| r.name.clone()).collect();
            }
            let mut run = ProcedureRun::new(sampler.clone(), controller);
            while let Some(r) = run.next(&sim) {
                let (record, margins) = r?;
                check.push(&record, &margins, &sim.supervisor, &controller.limits);
                check.push_no_go(&record, run.no_go.as_ref());
            }
            if let Some(e) = sampler.motion().failure() {
                return Err(e.clone());
            }
            // The single turn is checked ahead only for its anatomy, so
            // that entering a forbidden region fails before any output; it
            // keeps no procedure table.
            if let Plan::Planned(_, c) = &mut sim.plan
                && sim.scenario.is_procedure()
            {
                *c = Some(check);
            }
        }
        Ok(sim)
    }

    /// The check of a procedure (per motion: duration, peak rates, smallest
    /// margins; the supervisor's warnings), made before any output; `None`
    /// for the single turn, which streams, and for an online run.
    pub fn procedure_check(&self) -> Option<&ProcedureCheck> {
        match &self.plan {
            Plan::Planned(_, check) => check.as_ref(),
            Plan::Online(..) => None,
        }
    }

    /// The time-optimal law of the single turn, for a run timed with
    /// [`Timing::Optimal`](crate::Timing::Optimal) (a procedure's motions
    /// have theirs in [`Simulation::timeline`]).
    pub fn optimal(&self) -> Option<&OptimalMotion> {
        if self.scenario.is_procedure() {
            return None;
        }
        self.timeline()?.motions.first()?.optimal.as_ref()
    }

    /// A procedure's plan; `None` for the single turn and an online run
    /// (see [`Simulation::timeline`] for every planned run's).
    pub fn procedure(&self) -> Option<&ProcedurePlan> {
        self.timeline().filter(|_| self.scenario.is_procedure())
    }

    /// The plan of a planned run, motion by motion (one motion for the
    /// single turn); `None` for an online run.
    pub fn timeline(&self) -> Option<&ProcedurePlan> {
        match &self.plan {
            Plan::Planned(sampler, _) => Some(sampler.motion()),
            Plan::Online(..) => None,
        }
    }

    /// The margin supervisor whose thresholds a planned run's warnings use.
    pub fn supervisor(&self) -> &Supervisor<f64> {
        &self.supervisor
    }

    /// The online plan: the commands validated and scheduled, the
    /// controller at rest at the start, the planned sample count and the
    /// time the last motion comes to rest.
    fn plan_online(
        scenario: &Scenario,
        run: &Online,
        controller: Controller<f64>,
        tips: TipTargets<f64>,
    ) -> Result<(Plan, Vec<Scheduled>, usize, f64), SimulationError> {
        let rate = scenario.rate_hz;
        if !(rate.is_finite() && rate > 0.0) {
            return Err(SimulationError::Trajectory(
                parasils::traj::Error::InvalidRate { value: rate },
            ));
        }
        let schedule = schedule(scenario, run)?;
        let online = OnlineController::new(
            controller,
            tips,
            scenario.start(),
            [run.turn.limits(); 2],
            scenario_supervisor(scenario, &controller)?,
        )
        .and_then(|online| match scenario.supervisor.clearance() {
            // The robot file's clearance thresholds: the controller stops
            // ahead of the stop threshold, as it does for the margins.
            Some([warn, stop]) => online.with_clearance(ClearanceWatch {
                bodies: scenario.bodies,
                endoscope_depth: scenario.endoscope_depth_mm,
                thresholds: ClearanceThresholds { warn, stop },
            }),
            None => Ok(online),
        })
        .map_err(|e| online_error(e, 0.0, 0))?;
        // The run planned: every command at its sample, no cycle run (the
        // supervisor, which needs the kinematics, can only end it sooner
        // or start a later command from rest).
        let mut dry = online;
        for s in &schedule {
            apply(&mut dry, s, run.turn.sync).map_err(|e| online_error(e, s.t_s, s.sample))?;
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
            Plan::Planned(sampler, _) => {
                Inner::Planned(ProcedureRun::new(sampler.clone(), self.controller))
            }
            Plan::Online(online, rate) => Inner::Online(OnlineRun {
                controller: *online,
                sync: self
                    .scenario
                    .turn()
                    .map_or(Synchronization::Phase, |t| t.sync),
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
    pub(super) fn record(
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
            // Filled in by the caller (`records::with_clearance`), which can fail.
            clearance: ClearanceRecord::default(),
            ports: [
                out.frame.to_fixed(&self.controller.left.geometry().rcm),
                out.frame.to_fixed(&self.controller.right.geometry().rcm),
                out.frame.position,
            ],
            forces: ForceRecord::default(),
            camera: self.camera(&out.frame, context, targets),
            // Likewise (`records::with_no_go`).
            no_go_clearance_mm: f64::INFINITY,
            // Filled in by a teleoperation run (`teleop::TeleopRun`).
            teleop: crate::record::TeleopRecord::default(),
        }
    }

    /// The point the camera is to look at in `context`, the tips
    /// commanded at `targets`, mm, fixed frame: the look-at motion's under
    /// way (a procedure's) or the run's turn's, else the tips' midpoint.
    fn aim_target(&self, context: Context, targets: &TipTargets<f64>) -> Vector3<f64> {
        let motion = usize::try_from(context.motion).unwrap_or(usize::MAX);
        let look = match self.scenario.motions().get(motion) {
            Some(MotionSpec {
                goal: MotionGoal::LookAt { target },
                ..
            }) => Some(*target),
            _ => self.scenario.turn().and_then(|t| t.look_at),
        };
        look.map_or_else(
            || (targets.left + targets.right) * 0.5,
            |l| Vector3::from(l.point([targets.left.into(), targets.right.into()])),
        )
    }

    /// What the camera on `frame` sees in `context`, the tips commanded at
    /// `targets` (see `docs/model.md`, *What the camera sees*).
    fn camera(
        &self,
        frame: &PlatformFrame<f64>,
        context: Context,
        targets: &TipTargets<f64>,
    ) -> CameraRecord {
        let camera: &Camera<f64> = &self.controller.endoscope.camera;
        let depth = context.endoscope_depth;
        // A tip in the camera's own plane (`z = 0` exactly) has no image
        // coordinates: 0, and not ahead, rather than an infinity.
        let [left, right] = [targets.left, targets.right].map(|p| {
            let seen = camera.project(frame, depth, &p);
            if seen.u.is_finite() && seen.v.is_finite() {
                seen
            } else {
                ImagePoint {
                    u: 0.0,
                    v: 0.0,
                    in_front: false,
                }
            }
        });
        CameraRecord {
            tips: [[left.u, left.v], [right.u, right.v]],
            ahead: [left.in_front, right.in_front],
            in_view: [left.in_view(), right.in_view()],
            aim_error: camera.aim_error(frame, depth, &self.aim_target(context, targets)),
            roll: camera.roll(&self.start_rotation, &frame.rotation),
        }
    }
}
