//! The simulation engine: the trajectory, sampled at a fixed rate, through the
//! controller's per-cycle call, one [`Sample`] at a time.
//!
//! Nothing is integrated: every sample is computed from the trajectory's
//! analytic state at its time, so the tips' drift is the kinematics' rounding
//! only. Samples stream to a [`Sink`]; memory stays flat however long the run.

use parasils_kin::{AssemblyMode, Controller, Instrument, PlatformState, Pose, TipTargets};
use parasils_traj::{Limits, Multi, Sampler};

use crate::sample::{ModuleSample, Sample, Sink};
use crate::scenario::Scenario;

/// What can stop a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimulationError {
    /// The robot's geometry is invalid.
    #[error("robot geometry: {0}")]
    Geometry(parasils_kin::Error),
    /// The trajectory cannot be built (limits, angles or rate invalid).
    #[error("trajectory: {0}")]
    Trajectory(parasils_traj::Error),
    /// The kinematics failed at a sample: unreachable tip, singularity, limit.
    #[error("at t = {t:.3} s: {error}")]
    Kinematics {
        /// The sample's time, s.
        t: f64,
        /// What failed.
        error: parasils_kin::Error,
    },
}

/// A simulation's failure: the engine's, or the sink's.
#[derive(Debug, thiserror::Error)]
pub enum RunError<E> {
    /// The engine failed.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// The sink failed (for instance, an I/O error while writing).
    #[error("writing the output: {0}")]
    Sink(E),
}

/// A scenario, ready to run.
#[derive(Debug, Clone)]
pub struct Simulation {
    scenario: Scenario,
    controller: Controller<f64>,
    tips: TipTargets<f64>,
    sampler: Sampler<f64, Multi<f64, 2>>,
}

impl Simulation {
    /// Validates the scenario and plans the trajectory.
    pub fn new(scenario: Scenario) -> Result<Self, SimulationError> {
        let controller =
            Controller::from_geometry(&scenario.robot).map_err(SimulationError::Geometry)?;
        let limits = Limits::new(scenario.omega_max, scenario.eps_max);
        let motion = Multi::new(
            [scenario.start.psi, scenario.start.theta],
            scenario.goal(),
            [limits; 2],
            scenario.sync,
        )
        .map_err(SimulationError::Trajectory)?;
        let sampler =
            Sampler::new(motion, scenario.rate_hz).map_err(SimulationError::Trajectory)?;
        let tips = scenario.tips();
        for (what, v) in [("left tip", tips.left), ("right tip", tips.right)] {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(SimulationError::Kinematics {
                    t: 0.0,
                    error: parasils_kin::Error::NonFinite {
                        what,
                        value: v
                            .iter()
                            .copied()
                            .find(|x| !x.is_finite())
                            .unwrap_or(f64::NAN),
                    },
                });
            }
        }
        Ok(Self {
            scenario,
            controller,
            tips,
            sampler,
        })
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The tips held still, mm, fixed frame.
    pub fn tips(&self) -> &TipTargets<f64> {
        &self.tips
    }

    /// The controller (geometry of every module).
    pub fn controller(&self) -> &Controller<f64> {
        &self.controller
    }

    /// The motion's duration, s.
    pub fn duration(&self) -> f64 {
        self.sampler.motion().duration()
    }

    /// The number of samples: `t = k / rate` for `k = 0..n`, the last one at
    /// the end of the motion (see `parasils_traj::sampler`).
    pub fn sample_count(&self) -> usize {
        self.sampler.sample_count()
    }

    /// The samples, computed one at a time. Each call starts the
    /// controller afresh (module 1's margin tracked from the first sample).
    pub fn samples(&self) -> impl Iterator<Item = Result<Sample, SimulationError>> + '_ {
        let mut controller = self.controller;
        self.sampler.clone().map(move |s| {
            let [psi, theta] = s.state;
            let mut pose = self.scenario.start;
            pose.psi = psi.position;
            pose.theta = theta.position;
            let state = PlatformState::reorientation(
                pose,
                [psi.velocity, theta.velocity],
                [psi.acceleration, theta.acceleration],
            );
            self.sample_at(&mut controller, s.time, &state)
        })
    }

    fn sample_at(
        &self,
        controller: &mut Controller<f64>,
        t: f64,
        state: &PlatformState<f64>,
    ) -> Result<Sample, SimulationError> {
        let out = controller
            .step(state, &self.tips)
            .map_err(|error| SimulationError::Kinematics { t, error })?;
        let module = |m: &Instrument<f64>,
                      sol: &parasils_kin::InstrumentSolution<f64>,
                      mode: AssemblyMode,
                      target: nalgebra::Vector3<f64>| {
            // The tip by forward kinematics from the joints, placed with the
            // step's own platform frame (the rotation `Instrument::tip` would
            // evaluate again from the Euler angles, the same numbers): `q`
            // and the frame are finite, the step checked them.
            let tip = out.frame.to_fixed(&m.tip_platform(&sol.q));
            // `cos qs2` signed: `|cos qs2|` from the step's margins, positive
            // in mode A and negative in mode B (the IK keeps the mode).
            let cos_qs2 = match mode {
                AssemblyMode::A => sol.margins.cos_qs2,
                AssemblyMode::B => -sol.margins.cos_qs2,
            };
            ModuleSample {
                q: sol.q.to_array(),
                q_dot: sol.q_dot.to_array(),
                q_ddot: sol.q_ddot.to_array(),
                cos_qs2,
                tip,
                tip_err: (tip - target).norm(),
            }
        };
        let p: &Pose<f64> = &state.pose;
        let m1 = &out.module1;
        Ok(Sample {
            t,
            pose: p.to_array(),
            euler_rate: [state.velocity.psi, state.velocity.theta, state.velocity.phi],
            euler_acc: [
                state.acceleration.psi,
                state.acceleration.theta,
                state.acceleration.phi,
            ],
            q: m1.q.to_array(),
            q_dot: m1.q_dot.to_array(),
            q_ddot: m1.q_ddot.to_array(),
            serial_margin: m1.margins.serial_min,
            parallel_margin: m1.margins.parallel,
            left: module(
                &self.controller.left,
                &out.left,
                self.controller.modes[0],
                self.tips.left,
            ),
            right: module(
                &self.controller.right,
                &out.right,
                self.controller.modes[1],
                self.tips.right,
            ),
        })
    }

    /// Runs the whole motion into `sink`, sample by sample; stops at the first
    /// failure.
    pub fn run<S: Sink>(&self, sink: &mut S) -> Result<(), RunError<S::Error>> {
        for sample in self.samples() {
            sink.push(&sample?).map_err(RunError::Sink)?;
        }
        Ok(())
    }
}
