//! The controller's nominal commands along a motion: what the nominal model
//! sends to the twelve actuators at every sample, and where it believes the
//! platform and the tips are.

use nalgebra::Vector3;
use parasils_kin::{Joints, Pose, RobotGeometry};
use parasils_sim::{Scenario, Simulation, SimulationError};

/// One sample of the commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command {
    /// The time from the motion's start, s.
    pub t_s: f64,
    /// Module 1's actuators `q1..q6` as commanded (encoder readings), mm.
    pub q_mm: [f64; 6],
    /// The left module's joints.
    pub left: Joints<f64>,
    /// The right module's joints.
    pub right: Joints<f64>,
    /// The platform pose the nominal model commands.
    pub pose: Pose<f64>,
    /// The left tip the nominal model commands (its forward kinematics at
    /// the commanded joints and pose), mm, fixed frame.
    pub tip_left_mm: Vector3<f64>,
    /// The right tip, likewise.
    pub tip_right_mm: Vector3<f64>,
}

/// The commands of a whole motion, with the nominal robot that computed
/// them.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    robot: RobotGeometry<f64>,
    commands: Vec<Command>,
}

impl Trace {
    /// Runs `scenario` (the paper's reorientation, a procedure...) through
    /// the simulation and keeps its commands.
    ///
    /// # Errors
    /// The simulation's own: an invalid scenario, or a sample where the
    /// nominal robot itself fails.
    pub fn from_scenario(scenario: Scenario) -> Result<Self, SimulationError> {
        let robot = scenario.robot;
        let sim = Simulation::new(scenario)?;
        let commands = sim
            .samples()
            .map(|record| {
                record.map(|r| {
                    let joints = |q: [f64; 3]| Joints::new(q[0], q[1], q[2]);
                    Command {
                        t_s: r.t,
                        q_mm: r.module1.q,
                        left: joints(r.left.q),
                        right: joints(r.right.q),
                        pose: Pose::from_array(r.pose),
                        tip_left_mm: r.left.tip,
                        tip_right_mm: r.right.tip,
                    }
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { robot, commands })
    }

    /// The nominal robot.
    pub fn robot(&self) -> &RobotGeometry<f64> {
        &self.robot
    }

    /// The commands, in time order.
    pub fn commands(&self) -> &[Command] {
        &self.commands
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.commands.len()
    }

    /// `true` when there is no sample.
    pub fn is_empty(&self) -> bool {
        self.commands.is_empty()
    }
}
