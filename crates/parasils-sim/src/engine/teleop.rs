//! A teleoperation run: the teleoperation core ([`parasils::teleop::Teleop`])
//! stepped at the control rate, one [`Record`] per cycle, from what each
//! device holds at that cycle: a recorded session ([`Replay`]) or live
//! devices (the caller polls them and calls [`TeleopRun::step`]).
//!
//! Every input is stamped with the current cycle's time: a recording holds
//! each device's row until the device's next row, and a live device is read
//! every cycle, so neither goes silent for the core's timeout (a recording's
//! gaps between rows are holds, not silences).

use nalgebra::Vector3;
use parasils::kin::{PlatformState, PoseRate, TipTargets};
use parasils::supervisor::ClearanceThresholds;
use parasils::teleop::{
    CameraCommand, CameraInput, Command, HandCommand, HandInput, Inputs, Teleop, TeleopParams,
};
use parasils_device::{Held, Recording};

use crate::record::{Record, TeleopRecord};
use crate::scenario::Scenario;
use crate::sink::Sink;

use super::error::{RunError, SimulationError};
use super::records::{bodies_of, clearance_of, forces, no_go_of};
use super::simulation::{Context, Simulation};

/// The default time a replay runs on after the recording's last row, s:
/// long enough for a tip at its speed limit to stop at its acceleration
/// limit and the filter to settle.
pub const SETTLE_S: f64 = 1.0;

/// A teleoperation run under way: the core at the scenario's start pose,
/// tips and endoscope depth, with the robot file's supervisor thresholds
/// and clearance watch, stepped once per [`TeleopRun::step`].
#[derive(Debug)]
pub struct TeleopRun {
    sim: Simulation,
    teleop: Teleop<f64>,
    rate_hz: f64,
    next: usize,
    /// The previous cycle's `[psi, theta]` rates, rad/s (the Euler
    /// accelerations are their change per period).
    last_rates: [f64; 2],
}

impl TeleopRun {
    /// The core for `scenario` (its robot, start pose, tips, endoscope
    /// depth, camera, supervisor and clearance thresholds, rate) with the
    /// mapping `params`, DISABLED at rest.
    ///
    /// # Errors
    /// The scenario's own errors ([`Simulation::new`]), and
    /// [`SimulationError::Teleop`] when the core refuses its setup.
    pub fn new(scenario: Scenario, params: TeleopParams<f64>) -> Result<Self, SimulationError> {
        let rate_hz = scenario.rate_hz;
        let sim = Simulation::new(scenario)?;
        let setup = |error| SimulationError::Teleop {
            t: 0.0,
            sample: None,
            error,
        };
        let scenario = &sim.scenario;
        let mut teleop = Teleop::new(
            sim.controller,
            scenario.start(),
            sim.tips,
            scenario.endoscope_depth_mm,
            params,
        )
        .and_then(|t| t.with_supervisor(sim.supervisor))
        .and_then(|t| t.with_camera(sim.controller.endoscope.camera))
        .map_err(setup)?;
        if let Some([warn, stop]) = scenario.supervisor.clearance() {
            teleop = teleop
                .with_clearance(scenario.bodies, ClearanceThresholds { warn, stop })
                .map_err(setup)?;
        }
        Ok(Self {
            sim,
            teleop,
            rate_hz,
            next: 0,
            last_rates: [0.0; 2],
        })
    }

    /// The scenario this run was made from.
    pub fn scenario(&self) -> &Scenario {
        &self.sim.scenario
    }

    /// The simulation the records are made with (the scenario's robot,
    /// camera and supervisor; for the summary).
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// The control rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        self.rate_hz
    }

    /// The time of the next cycle, `k / rate`, s.
    pub fn next_time_s(&self) -> f64 {
        self.next as f64 / self.rate_hz
    }

    /// The core, as it is after the last cycle.
    pub fn teleop(&self) -> &Teleop<f64> {
        &self.teleop
    }

    /// Starts a planned move of the core ([`Teleop::start_move`]: look at a
    /// point or the tips, move to a pose, home) from the last cycle's
    /// setpoint; the next [`step`](Self::step) is its first cycle.
    ///
    /// # Errors
    /// [`parasils::teleop::MoveRefused`]: not ENABLED, a non-finite goal, a
    /// point the view cannot aim at; the core is then unchanged.
    pub fn start_move(
        &mut self,
        goal: parasils::teleop::Goal<f64>,
    ) -> Result<(), parasils::teleop::MoveRefused> {
        self.teleop.start_move(goal)
    }

    /// One cycle at [`TeleopRun::next_time_s`]: each device holding `held`
    /// (`[left, right, camera]`, stamped now), `command` given; its record.
    ///
    /// # Errors
    /// [`SimulationError::Teleop`] when the core refuses the cycle,
    /// [`SimulationError::Kinematics`] when the record's gaps or forces
    /// cannot be computed, [`SimulationError::ActuatorLimit`] for a tip load
    /// beyond an actuator's force limit.
    pub fn step(
        &mut self,
        held: [Held; 3],
        command: Option<Command>,
    ) -> Result<Record, SimulationError> {
        let k = self.next;
        let t = self.next_time_s();
        let dt = 1.0 / self.rate_hz;
        let [left, right, camera] = held;
        let hand = |h: Held| HandInput {
            command: HandCommand::Rate(h.axes),
            buttons: h.buttons,
            stamp_s: t,
        };
        let inputs = Inputs {
            left: hand(left),
            right: hand(right),
            camera: CameraInput {
                command: CameraCommand::Rate(camera.axes),
                buttons: camera.buttons,
                stamp_s: t,
            },
            command,
        };
        let cycle = self
            .teleop
            .step(t, &inputs)
            .map_err(|error| SimulationError::Teleop {
                t,
                sample: Some(k),
                error,
            })?;
        let [psi, theta] = cycle.angles;
        let [psi_dot, theta_dot] = cycle.angle_rates;
        let [last_psi, last_theta] = self.last_rates;
        self.last_rates = cycle.angle_rates;
        let rates = |psi, theta| PoseRate {
            psi,
            theta,
            ..PoseRate::zero()
        };
        let pose = self.teleop.pose();
        let state = PlatformState {
            pose: parasils::kin::Pose { psi, theta, ..pose },
            velocity: rates(psi_dot, theta_dot),
            acceleration: if k == 0 {
                rates(0.0, 0.0)
            } else {
                rates((psi_dot - last_psi) / dt, (theta_dot - last_theta) / dt)
            },
        };
        let [a, b] = cycle.tips;
        let targets = TipTargets { left: a, right: b };
        let depth = self.sim.scenario.endoscope_depth_mm;
        let context = Context {
            endoscope_depth: depth,
            endoscope_tip: Vector3::zeros(),
            ..Context::command(
                0,
                crate::scenario::CommandKind::Reorient,
                Default::default(),
            )
        };
        let mut record = self
            .sim
            .record(k, t, &state, &cycle.step, &targets, context);
        let controller = self.teleop.controller();
        let kinematics = |error| SimulationError::Kinematics {
            t,
            sample: Some(k),
            error,
        };
        let bodies = bodies_of(&self.sim, controller, &cycle.step, depth).map_err(kinematics)?;
        record.clearance = clearance_of(&bodies, &cycle.step).map_err(kinematics)?.0;
        record.forces = forces(&self.sim.scenario, controller, &cycle.step, t, k)?;
        // Recorded, not failed on, as in an online run.
        let no_go = no_go_of(&self.sim, &bodies, &cycle.step, depth, t, k)?;
        if let Some(min) = no_go
            .as_ref()
            .and_then(parasils_anatomy::NoGoClearance::min)
        {
            record.no_go_clearance_mm = min.gap_mm;
        }
        record.warnings = self.sim.supervisor.check(&cycle.margins).warnings;
        record.teleop = TeleopRecord {
            axes: held.map(|h| h.axes),
            buttons: held.map(|h| h.buttons),
            command,
            state: cycle.state,
            hold: cycle.hold,
            fault: cycle.fault,
            hands: cycle.hands,
        };
        self.next = k.saturating_add(1);
        Ok(record)
    }
}

/// A recorded session replayed through a [`TeleopRun`]: one cycle per
/// period from `t = 0` to the recording's last row plus a settle time,
/// each cycle given what each device holds (its rows at or before the
/// cycle's time) and the next command due (one per cycle: two commands at
/// one instant take effect at consecutive cycles, in the file's order).
#[derive(Debug)]
pub struct Replay {
    run: TeleopRun,
    recording: Recording,
    settle_s: f64,
}

impl Replay {
    /// `recording` replayed on `scenario` with `params`, running on for
    /// `settle_s` after its last row ([`SETTLE_S`] is the usual choice).
    ///
    /// # Errors
    /// Those of [`TeleopRun::new`]; [`SimulationError::Teleop`] for a
    /// settle time that is negative or not finite.
    pub fn new(
        scenario: Scenario,
        params: TeleopParams<f64>,
        recording: Recording,
        settle_s: f64,
    ) -> Result<Self, SimulationError> {
        if !(settle_s.is_finite() && settle_s >= 0.0) {
            return Err(SimulationError::Teleop {
                t: 0.0,
                sample: None,
                error: parasils::teleop::TeleopError::InvalidParameter {
                    what: "settle_s",
                    value: settle_s,
                },
            });
        }
        Ok(Self {
            run: TeleopRun::new(scenario, params)?,
            recording,
            settle_s,
        })
    }

    /// The scenario replayed on.
    pub fn scenario(&self) -> &Scenario {
        self.run.scenario()
    }

    /// The run's simulation ([`TeleopRun::simulation`]).
    pub fn simulation(&self) -> &Simulation {
        self.run.simulation()
    }

    /// The number of cycles: from `t = 0` to the last row plus the settle
    /// time, both included.
    pub fn cycle_count(&self) -> usize {
        let end = (self.recording.end_s() + self.settle_s) * self.run.rate_hz;
        // A few ulps below a whole number of periods still counts it.
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a finite, non-negative count of periods"
        )]
        let n = (end + 1e-9).floor() as usize;
        n.saturating_add(1)
    }

    /// Runs the whole replay into `sink`, cycle by cycle; stops at the
    /// first failure.
    ///
    /// # Errors
    /// [`RunError::Simulation`] when a cycle fails, [`RunError::Sink`]
    /// when the sink does.
    pub fn run<S: Sink + ?Sized>(self, sink: &mut S) -> Result<(), RunError<S::Error>> {
        let count = self.cycle_count();
        let Self {
            mut run, recording, ..
        } = self;
        let mut player = recording.player();
        let mut pending = std::collections::VecDeque::new();
        for _ in 0..count {
            let t = run.next_time_s();
            // The commands due now, one per cycle: rows of one instant give
            // theirs at consecutive cycles, in the recording's order.
            pending.extend(player.advance(t));
            let record = run.step(player.held(), pending.pop_front())?;
            sink.push(&record).map_err(RunError::Sink)?;
        }
        Ok(())
    }
}
