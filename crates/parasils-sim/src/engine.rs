//! The engine: a [`Scenario`] planned into a [`Reorientation`], sampled at a
//! fixed rate through the controller's per-cycle call, one [`Record`] at a
//! time.
//!
//! Nothing is integrated: every record is computed from the trajectory's
//! analytic state at its time, so the tips' drift is the kinematics' rounding
//! only. Records stream to a [`Sink`] in [`Simulation::run`], the one loop
//! that the command line and the Python bindings both run; memory stays flat
//! however long the run.

use nalgebra::Vector3;
use parasils::Reorientation;
use parasils::kin::{
    AssemblyMode, Controller, Instrument, InstrumentSolution, PlatformState, TipTargets,
};
use parasils::traj::{Sample, Sampler};

use crate::numbers::AtTime;
use crate::record::{InstrumentRecord, Module1Record, Record};
use crate::scenario::Scenario;
use crate::sink::Sink;

/// What can stop a simulation.
///
/// Each message names its subject once: the robot's geometry, the
/// trajectory, or the sample's time followed by the kinematics' own message
/// (which names the module).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
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

/// A scenario, validated and planned, ready to run.
#[derive(Debug, Clone)]
pub struct Simulation {
    scenario: Scenario,
    controller: Controller<f64>,
    tips: TipTargets<f64>,
    sampler: Sampler<f64, Reorientation<f64>>,
    /// The start's Euler angles, deg (the user's) and rad.
    start_deg: [f64; 3],
    start_rad: [f64; 3],
}

impl Simulation {
    /// Validates the scenario and plans the trajectory through
    /// [`Reorientation::new`].
    ///
    /// # Errors
    /// [`SimulationError::Geometry`] for an invalid robot,
    /// [`SimulationError::Trajectory`] for angles, limits or a rate that
    /// cannot be planned, [`SimulationError::Kinematics`] for a non-finite
    /// tip target.
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
        let sampler = reorientation
            .sampler(scenario.rate_hz)
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
        let [_, _, _, psi, theta, phi] = scenario.start_mm_deg;
        Ok(Self {
            start_deg: [psi, theta, phi],
            start_rad: [start.psi, start.theta, start.phi],
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

    /// The motion's duration, s.
    pub fn duration(&self) -> f64 {
        parasils::traj::Motion::duration(self.sampler.motion())
    }

    /// The number of records: `t = k / rate` for `k = 0..n`, the last one at
    /// the end of the motion (see `parasils_traj::sampler`).
    pub fn sample_count(&self) -> usize {
        self.sampler.sample_count()
    }

    /// The records, computed one at a time. Each call starts the controller
    /// afresh (module 1's margin tracked from the first sample).
    pub fn samples(&self) -> impl Iterator<Item = Result<Record, SimulationError>> + '_ {
        let mut controller = self.controller;
        self.sampler
            .clone()
            .map(move |s| self.record(&mut controller, &s))
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

    fn record(
        &self,
        controller: &mut Controller<f64>,
        sample: &Sample<f64, PlatformState<f64>>,
    ) -> Result<Record, SimulationError> {
        let (t, state) = (sample.time, &sample.state);
        let out =
            controller
                .step(state, &self.tips)
                .map_err(|error| SimulationError::Kinematics {
                    t,
                    sample: Some(sample.index),
                    error,
                })?;
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
        Ok(Record {
            index: sample.index,
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_run_holds_the_tips_and_starts_on_the_user_s_degrees() {
        let sim = Simulation::new(Scenario::paper()).expect("valid");
        assert_eq!(sim.sample_count(), 4501);
        assert_eq!(sim.duration(), 4.5);
        let mut first = None;
        let mut last = None;
        let mut worst = 0.0f64;
        let mut n = 0;
        sim.run(&mut |r: &Record| {
            first.get_or_insert(*r);
            last = Some(*r);
            worst = worst.max(r.left.tip_err).max(r.right.tip_err);
            n += 1;
            Ok::<(), core::convert::Infallible>(())
        })
        .expect("runs");
        assert_eq!(n, 4501);
        assert!(worst < 1e-9, "{worst}");
        let (first, last) = (first.expect("records"), last.expect("records"));
        assert_eq!(first.angles_deg, [-15.0, 10.0, -60.0]);
        assert_eq!(last.index, 4500);
        assert_eq!(last.t, 4.5);
        assert!(last.angles_deg[0].abs() < 1e-12);
        assert!((last.angles_deg[1] - 35.0).abs() < 1e-12);
        assert_eq!(last.angles_deg[2], -60.0);
    }

    #[test]
    fn errors_name_their_subject_and_time_once() {
        let e = Simulation::new(Scenario {
            psi_deg: -60.0,
            theta_deg: 0.0,
            rate_hz: 100.0,
            ..Scenario::paper()
        })
        .expect("plans")
        .run(&mut |_: &Record| Ok::<(), core::convert::Infallible>(()))
        .expect_err("q4 leaves its stroke");
        let text = e.to_string();
        assert!(
            text.starts_with("at t = 6.400 s: module 1: actuator q4"),
            "{text}"
        );
        assert_eq!(text.matches("module 1").count(), 1, "{text}");
        match e {
            RunError::Simulation(SimulationError::Kinematics { t, sample, .. }) => {
                assert_eq!(sample.map(|k| k as f64 / 100.0), Some(t));
            }
            other => panic!("{other:?}"),
        }
        let e = Simulation::new(Scenario {
            tip_right_mm: Some([f64::NAN, 0.0, 0.0]),
            ..Scenario::paper()
        })
        .expect_err("not finite");
        assert!(matches!(
            e,
            SimulationError::Kinematics { sample: None, .. }
        ));
        let e = Simulation::new(Scenario {
            omega_max_deg_s: 0.0,
            ..Scenario::paper()
        })
        .expect_err("no velocity");
        assert!(e.to_string().starts_with("trajectory: "), "{e}");
    }
}
