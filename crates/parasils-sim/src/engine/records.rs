//! The records of a simulation, computed one at a time: a planned
//! timeline's (the paper's turn, a procedure) and an online run's samples
//! through the controller's step.

use super::procedure::ProcedurePlan;
use nalgebra::Vector3;
use parasils::kin::MarginTracker;
use parasils::kin::{Bodies, ClearancePair, ControlStep, Controller, Loads, Payload, Side};
use parasils::supervisor::Margins;
use parasils::traj::{Sampler, Synchronization};
use parasils::{MotionKind, OnlineController};

use crate::record::{ClearanceRecord, ForceRecord, Record};
use crate::scenario::{CommandKind, Scenario};
use parasils_anatomy::{InBody, NoGoClearance};

use super::error::SimulationError;
use super::schedule::apply;
use super::simulation::{Context, Simulation, online_error};

/// The records of a [`Simulation`], computed one at a time
/// ([`Simulation::samples`]).
#[derive(Debug)]
pub struct Records<'a> {
    pub(super) sim: &'a Simulation,
    pub(super) inner: Inner,
}

#[derive(Debug)]
#[allow(
    clippy::large_enum_variant,
    reason = "one per run, never in a collection"
)]
pub(super) enum Inner {
    Planned(ProcedureRun),
    Online(OnlineRun),
}

/// The three bodies at `step` (the shafts at its joints, the endoscope at
/// `depth` mm), from the scenario's sizes: built once per sample, and
/// measured against each other ([`clearance_of`]) and against the
/// forbidden regions ([`no_go_of`]).
pub(super) fn bodies_of(
    sim: &Simulation,
    controller: &Controller<f64>,
    step: &ControlStep<f64>,
    depth: f64,
) -> Result<Bodies<f64>, parasils::kin::Error> {
    Bodies::at(
        &sim.scenario.bodies,
        &step.frame,
        &controller.left,
        &step.left.q,
        &controller.right,
        &step.right.q,
        depth,
    )
}

/// The three surface gaps between `bodies` (those of `step`), and the
/// depth below the ports (mm, `-z'` of the platform frame) of the smallest
/// gap's closest points.
pub(super) fn clearance_of(
    bodies: &Bodies<f64>,
    step: &ControlStep<f64>,
) -> Result<(ClearanceRecord, ClearancePair, f64), parasils::kin::Error> {
    let gaps = bodies.clearance()?;
    let (pair, _) = gaps.min();
    let axes = &gaps.get(pair).axes;
    let middle = (axes.point_a + axes.point_b) * 0.5;
    let below = -step.frame.to_platform(&middle).z;
    Ok((
        ClearanceRecord {
            left_right: gaps.left_right.gap,
            left_endoscope: gaps.left_endoscope.gap,
            right_endoscope: gaps.right_endoscope.gap,
        },
        pair,
        below,
    ))
}

/// `record` with the clearance of `bodies`, the sample's
/// ([`clearance_of`]); a failure is the sample's kinematics error, and a
/// gap below the robot file's clearance stop threshold (when it gives one)
/// is [`SimulationError::Clearance`].
pub(super) fn with_clearance(
    sim: &Simulation,
    bodies: &Bodies<f64>,
    step: &ControlStep<f64>,
    mut record: Record,
) -> Result<Record, SimulationError> {
    let (t, sample) = (record.t, Some(record.index));
    let (clearance, pair, depth_mm) = clearance_of(bodies, step)
        .map_err(|error| SimulationError::Kinematics { t, sample, error })?;
    record.clearance = clearance;
    if let Some([_, stop_mm]) = sim.scenario.supervisor.clearance() {
        let gap_mm = clearance.min();
        if !(gap_mm >= stop_mm) {
            return Err(SimulationError::Clearance {
                t,
                sample,
                pair,
                gap_mm,
                stop_mm,
                depth_mm,
            });
        }
    }
    Ok(record)
}

/// The gaps of the in-body parts of `bodies` (those of `step`, the
/// endoscope at `depth` mm) to the scenario's forbidden regions; `None`
/// without an anatomy.
pub(super) fn no_go_of(
    sim: &Simulation,
    bodies: &Bodies<f64>,
    step: &ControlStep<f64>,
    depth: f64,
    t: f64,
    k: usize,
) -> Result<Option<NoGoClearance>, SimulationError> {
    let Some(anatomy) = &sim.scenario.anatomy else {
        return Ok(None);
    };
    let inside = InBody::of(bodies, step.left.q.qs3, step.right.q.qs3, depth);
    anatomy
        .clearance(&inside)
        .map(Some)
        .map_err(|error| SimulationError::Anatomy {
            t,
            sample: Some(k),
            error: Box::new(error),
        })
}

/// `record` with its smallest gap to a forbidden region ([`no_go_of`]),
/// and the gaps to each; a gap below the stop threshold
/// ([`SupervisorTable::no_go_stop_mm`](crate::SupervisorTable::no_go_stop_mm))
/// is [`SimulationError::NoGo`], naming the region and the body.
pub(super) fn with_no_go(
    sim: &Simulation,
    bodies: &Bodies<f64>,
    step: &ControlStep<f64>,
    depth: f64,
    mut record: Record,
) -> Result<(Record, Option<NoGoClearance>), SimulationError> {
    let (t, k) = (record.t, record.index);
    let no_go = no_go_of(sim, bodies, step, depth, t, k)?;
    let smallest = no_go.as_ref().and_then(NoGoClearance::min);
    if let (Some(anatomy), Some(min)) = (&sim.scenario.anatomy, smallest) {
        record.no_go_clearance_mm = min.gap_mm;
        let stop_mm = sim.scenario.supervisor.no_go_stop_mm();
        if let (Some(body), Some(region)) = (min.body, anatomy.regions.get(min.region))
            && !(min.gap_mm >= stop_mm)
        {
            return Err(SimulationError::NoGo {
                t,
                sample: Some(k),
                region: region.name.clone(),
                body,
                gap_mm: min.gap_mm,
                stop_mm,
            });
        }
    }
    Ok((record, no_go))
}

/// What `scenario` has its actuators hold (`None` without forces,
/// [`Scenario::has_forces`]): its tip loads and its platform's body, the
/// endoscope's tip unloaded.
fn loads(scenario: &Scenario) -> Option<Loads<f64>> {
    let (left, right) = (scenario.tip_load_left_n, scenario.tip_load_right_n);
    scenario.has_forces().then(|| Loads {
        payload: scenario.dynamics.unwrap_or_else(Payload::none),
        ..Loads::tips(
            Vector3::from(left.unwrap_or_default()),
            Vector3::from(right.unwrap_or_default()),
        )
    })
}

/// Every actuator's force in `step` holding `scenario`'s tip loads and
/// moving its platform's body (`parasils_kin::statics`; the step's frame
/// carries the platform's closed-form angular velocity and acceleration),
/// checked against the actuators' force limits; zero without forces.
pub(super) fn forces(
    scenario: &Scenario,
    controller: &Controller<f64>,
    step: &ControlStep<f64>,
    t: f64,
    k: usize,
) -> Result<ForceRecord, SimulationError> {
    let Some(loads) = loads(scenario) else {
        return Ok(ForceRecord::default());
    };
    let f = controller
        .forces(step, &loads)
        .map_err(|error| SimulationError::Kinematics {
            t,
            sample: Some(k),
            error,
        })?;
    let stiffness = &scenario.stiffness;
    let deflection = [(Side::Left, loads.left), (Side::Right, loads.right)].map(|(side, load)| {
        controller
            .tip_deflection(step, side, &-load, stiffness)
            .map(|d| d.norm())
    });
    let [left_d, right_d] = deflection;
    let record = ForceRecord {
        module1: f.module1.force.0,
        left: f.left.to_array(),
        right: f.right.to_array(),
        deflection: [
            left_d.map_err(|error| kinematics(error, t, k))?,
            right_d.map_err(|error| kinematics(error, t, k))?,
        ],
    };
    controller
        .limits
        .check_forces(&f.to_array())
        .map_err(|error| SimulationError::ActuatorLimit {
            t,
            sample: Some(k),
            error,
        })?;
    Ok(record)
}

fn kinematics(error: parasils::kin::Error, t: f64, k: usize) -> SimulationError {
    SimulationError::Kinematics {
        t,
        sample: Some(k),
        error,
    }
}

/// `step` against the actuators' limits of `controller`.
pub(super) fn check_limits(
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
pub(super) struct ProcedureRun {
    pub(super) sampler: Sampler<f64, ProcedurePlan>,
    pub(super) controller: Controller<f64>,
    pub(super) tracker: MarginTracker<f64>,
    pub(super) done: bool,
    /// The motion under way and its ports at its first record, for the
    /// supervisor's `port_motion_stop_mm`.
    pub(super) port_start: Option<(usize, [Vector3<f64>; 3])>,
    /// The last sample's gaps to each forbidden region (`None` without an
    /// anatomy), for the procedure's check.
    pub(super) no_go: Option<NoGoClearance>,
}

impl ProcedureRun {
    pub(super) fn new(sampler: Sampler<f64, ProcedurePlan>, controller: Controller<f64>) -> Self {
        Self {
            sampler,
            controller,
            tracker: MarginTracker::new(),
            done: false,
            port_start: None,
            no_go: None,
        }
    }

    /// The next record with its margins; after a failure, nothing more.
    pub(super) fn next(
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
        let t_motion = t - plan.motions.get(m).map_or(0.0, |p| p.start_s);
        let in_motion = |error: SimulationError| plan.in_motion(m, t_motion, error);
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
            let targets = super::procedure::commanded_tips(&self.controller, &sample, &out.frame);
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
            let mut record = sim.record(k, t, &sample.platform, &out, &targets, context);
            record.forces =
                forces(&sim.scenario, &self.controller, &out, t, k).map_err(in_motion)?;
            let depth = sample.endoscope.position;
            let bodies = bodies_of(sim, &self.controller, &out, depth).map_err(fail)?;
            let record = with_clearance(sim, &bodies, &out, record).map_err(in_motion)?;
            check_ports(sim, &mut self.port_start, m, &record).map_err(in_motion)?;
            let (record, no_go) =
                with_no_go(sim, &bodies, &out, depth, record).map_err(in_motion)?;
            Ok((record, margins, no_go))
        })();
        match result {
            Ok((record, margins, no_go)) => {
                self.no_go = no_go;
                Some(Ok((record, margins)))
            }
            Err(e) => {
                self.done = true;
                Some(Err(e))
            }
        }
    }
}

/// `record` against the robot file's `port_motion_stop_mm` (when it gives
/// one): each port's distance from where it was at the first record of
/// motion `m` (`start` keeps that, and moves on with `m`).
fn check_ports(
    sim: &Simulation,
    start: &mut Option<(usize, [Vector3<f64>; 3])>,
    m: usize,
    record: &Record,
) -> Result<(), SimulationError> {
    let Some(stop_mm) = sim.scenario.supervisor.port_motion_stop_mm else {
        return Ok(());
    };
    let from = match start {
        Some((k, from)) if *k == m => *from,
        _ => {
            *start = Some((m, record.ports));
            record.ports
        }
    };
    for ((port, now), from) in Record::PORTS.iter().zip(&record.ports).zip(&from) {
        let displacement_mm = (now - from).norm();
        if !(displacement_mm <= stop_mm) {
            return Err(SimulationError::PortMotion {
                t: record.t,
                sample: Some(record.index),
                port: *port,
                displacement_mm,
                stop_mm,
            });
        }
    }
    Ok(())
}

/// An online run under way.
#[derive(Debug)]
pub(super) struct OnlineRun {
    pub(super) controller: OnlineController<f64>,
    /// How the turn's and the retargets' two angles are timed together.
    pub(super) sync: Synchronization,
    pub(super) rate: f64,
    /// The next sample's index.
    pub(super) next: usize,
    /// The next scheduled command to give.
    pub(super) pending: usize,
    /// What the active command is.
    pub(super) kind: CommandKind,
    /// Whether the last record has been given (or a failure).
    pub(super) done: bool,
}

impl Iterator for Records<'_> {
    type Item = Result<Record, SimulationError>;

    fn next(&mut self) -> Option<Self::Item> {
        let sim = self.sim;
        match &mut self.inner {
            Inner::Planned(run) => run.next(sim).map(|r| r.map(|(record, _)| record)),
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
    pub(super) fn step(&mut self, sim: &Simulation) -> Result<Record, SimulationError> {
        let k = self.next;
        let t = k as f64 / self.rate;
        while let Some(s) = sim.schedule.get(self.pending).filter(|s| s.sample <= k) {
            apply(&mut self.controller, s, self.sync).map_err(|e| online_error(e, t, k))?;
            self.kind = s.command.kind;
            self.pending += 1;
        }
        // With an anatomy and the robot file's clearance thresholds, the
        // controller also stops ahead of the forbidden regions.
        let cycle = match (&sim.scenario.anatomy, sim.scenario.supervisor.clearance()) {
            (Some(anatomy), Some(_)) => self.controller.tick_with(t, &**anatomy),
            _ => self.controller.tick(t),
        }
        .map_err(|e| online_error(e, t, k))?;
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
            Context {
                // The camera sits at the scenario's depth.
                endoscope_depth: sim.scenario.endoscope_depth_mm,
                ..Context::command(cycle.command, self.kind, cycle.warnings)
            },
        );
        // Recorded, not failed on: when the robot file gives clearance
        // thresholds, the online controller watches the gaps and stops
        // ahead of the stop threshold (its supervisor stop), as it does for
        // the margins, so a run of commands holds instead of failing
        // mid-run.
        let mut record = record;
        let depth = sim.scenario.endoscope_depth_mm;
        let bodies = bodies_of(sim, self.controller.controller(), &cycle.step, depth)
            .map_err(|error| kinematics(error, t, k))?;
        record.clearance = clearance_of(&bodies, &cycle.step)
            .map_err(|error| kinematics(error, t, k))?
            .0;
        record.forces = forces(
            &sim.scenario,
            self.controller.controller(),
            &cycle.step,
            t,
            k,
        )?;
        // Recorded, not enforced, like the gaps between the bodies.
        let no_go = no_go_of(sim, &bodies, &cycle.step, depth, t, k)?;
        if let Some(min) = no_go.as_ref().and_then(NoGoClearance::min) {
            record.no_go_clearance_mm = min.gap_mm;
        }
        let finished = self.pending >= sim.schedule.len() && self.controller.is_at_rest(t);
        match k.checked_add(1) {
            Some(next) if !finished => self.next = next,
            _ => self.done = true,
        }
        Ok(record)
    }
}
