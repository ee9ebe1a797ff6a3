//! What can stop a simulation or a run, each error naming its subject.

use parasils::kin::{ClearancePair, LimitError};
use parasils::motions::Port;
use parasils_anatomy::{AnatomyError, Body};

use crate::timing::TimingError;

use crate::motion::{Inside, InsideRule, MotionName, refusal};
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
    /// A motion of a procedure breaks a rule the paper states for motions
    /// while anything is inside the patient (see [`InsideRule`]): refused
    /// while the procedure is planned, before any output.
    #[error("{motion}: {}", refusal(*rule, inside, *moved_mm, *turned_deg))]
    Inside {
        /// The motion (its index, type and name).
        motion: Box<MotionName>,
        /// The first rule it breaks (the incision point before the turn).
        rule: InsideRule,
        /// What is inside when it starts.
        inside: Inside,
        /// How far `P` would leave the incision point, mm (the largest
        /// distance over the motion's rows).
        moved_mm: f64,
        /// How far `phi` would turn from its value at the motion's start,
        /// deg (the largest over the motion's rows).
        turned_deg: f64,
    },
    /// The time-optimal law cannot be computed.
    #[error("time-optimal timing: {0}")]
    Timing(TimingError),
    /// The margin supervisor's thresholds are invalid (a stop threshold not
    /// above the solvers' hard one, a warning below its stop threshold).
    #[error("supervisor thresholds: {0}")]
    Supervisor(parasils::Error),
    /// Two bodies closer than the robot file's clearance stop threshold
    /// (`[supervisor]`'s `clearance_stop_mm`) at a sample of a planned run
    /// or a procedure: found while the run is planned, before any output.
    #[error(
        "{}clearance {pair} = {} mm is below the stop threshold {} mm, {} mm below the ports",
        AtTime(*t), Fixed(*gap_mm, 3), Shortest(*stop_mm), Fixed(*depth_mm, 1)
    )]
    Clearance {
        /// The sample's time, s.
        t: f64,
        /// The sample's index.
        sample: Option<usize>,
        /// Which two bodies.
        pair: ClearancePair,
        /// Their surface gap, mm (negative when they overlap).
        gap_mm: f64,
        /// The stop threshold, mm.
        stop_mm: f64,
        /// How deep the closest points are below the platform's port plane
        /// (`z' = 0`), mm: positive inside the patient, negative above the
        /// ports.
        depth_mm: f64,
    },
    /// A port (where a shaft or the endoscope crosses the skin) moved
    /// farther from where it was at its motion's start than the robot
    /// file's `[supervisor]` `port_motion_stop_mm`, at a sample of a planned
    /// run or a procedure: found while the run is planned, before any
    /// output.
    #[error(
        "{}the {} port moved {} mm from where it was at the motion's start, more than the limit {} mm",
        AtTime(*t), port.name(), Fixed(*displacement_mm, 3), Shortest(*stop_mm)
    )]
    PortMotion {
        /// The sample's time, s.
        t: f64,
        /// The sample's index.
        sample: Option<usize>,
        /// Which port: the left or right module's RCM, or the endoscope's.
        port: Port,
        /// How far it is from its position at the motion's start, mm
        /// (fixed frame).
        displacement_mm: f64,
        /// The limit, mm.
        stop_mm: f64,
    },
    /// A shaft or the endoscope closer to a forbidden region than the
    /// clearance stop threshold (`[supervisor]`'s `clearance_stop_mm`, 0.5
    /// mm by default) at a sample of a planned run or a procedure: found
    /// while the run is planned, before any output.
    #[error(
        "{}{body} is {} mm from the forbidden region {region:?}, below the stop threshold {} mm",
        AtTime(*t), Fixed(*gap_mm, 3), Shortest(*stop_mm)
    )]
    NoGo {
        /// The sample's time, s.
        t: f64,
        /// The sample's index.
        sample: Option<usize>,
        /// The region's name.
        region: String,
        /// Which body.
        body: Body,
        /// The gap, mm (negative inside the region).
        gap_mm: f64,
        /// The stop threshold, mm.
        stop_mm: f64,
    },
    /// A query of the anatomy failed at a sample (a body not finite).
    #[error("{}{error}", AtTime(*t))]
    Anatomy {
        /// The sample's time, s.
        t: f64,
        /// The sample's index.
        sample: Option<usize>,
        /// What failed (boxed: the variant stays small).
        error: Box<AnatomyError>,
    },
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
    /// The teleoperation core refused its setup or a cycle (an invalid
    /// parameter, a home pose the kinematics refuse, a clock that goes
    /// back).
    #[error("{}{error}", AtTime(*t))]
    Teleop {
        /// The cycle's time, s.
        t: f64,
        /// The cycle's index (`None` at the setup).
        sample: Option<usize>,
        /// What failed.
        error: parasils::teleop::TeleopError,
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
            SimulationError::Clearance {
                pair,
                gap_mm,
                stop_mm,
                depth_mm,
                ..
            } => format!(
                "clearance {pair} = {} mm is below the stop threshold {} mm, {} mm below the ports",
                Fixed(*gap_mm, 3),
                Shortest(*stop_mm),
                Fixed(*depth_mm, 1)
            ),
            SimulationError::PortMotion {
                port,
                displacement_mm,
                stop_mm,
                ..
            } => format!(
                "the {} port moved {} mm from where it was at the motion's start, more than the limit {} mm",
                port.name(),
                Fixed(*displacement_mm, 3),
                Shortest(*stop_mm)
            ),
            SimulationError::NoGo {
                region,
                body,
                gap_mm,
                stop_mm,
                ..
            } => format!(
                "{body} is {} mm from the forbidden region {region:?}, below the stop threshold {} mm",
                Fixed(*gap_mm, 3),
                Shortest(*stop_mm)
            ),
            SimulationError::Anatomy { error, .. } => error.to_string(),
            e => e.to_string(),
        }
    }

    /// The time of the failure, s from the start, when there is one.
    pub fn time_s(&self) -> Option<f64> {
        match self {
            SimulationError::Kinematics { t, .. }
            | SimulationError::Controller { t, .. }
            | SimulationError::ActuatorLimit { t, .. }
            | SimulationError::Clearance { t, .. }
            | SimulationError::PortMotion { t, .. } => Some(*t),
            SimulationError::NoGo { t, .. }
            | SimulationError::Anatomy { t, .. }
            | SimulationError::Teleop { t, .. } => Some(*t),
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
