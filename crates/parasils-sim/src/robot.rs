//! The robot a run uses, as one robot file gives it: the geometry (module 1
//! and both instrument modules, with their limits) and the margin
//! supervisor's thresholds (`[supervisor]`), and the bodies' sizes for the
//! clearance checks (`[bodies]`, assumed by default), the platform as one
//! rigid body (`[dynamics]`, none by default) and the actuators'
//! stiffness (`[stiffness]`, assumed by default).
//!
//! A robot file is read once, into one [`Robot`]
//! ([`robot_file::load_robot`](crate::robot_file::load_robot)), and that
//! value is what every front end passes on: the command line's `--robot`,
//! Python's `parasils.Robot` and `robot=` arguments, a procedure's `robot`
//! key. Nothing reads the file a second time for one of its tables.
//!
//! ```
//! use parasils::kin::{ActuatorStiffness, BodyGeometry, Payload, RobotGeometry};
//! use parasils_sim::Robot;
//!
//! let robot = Robot::paper();
//! assert_eq!(robot.geometry, RobotGeometry::paper());
//! assert!(robot.supervisor.is_empty());
//! ```

use parasils::kin::{ActuatorStiffness, BodyGeometry, Payload, RobotGeometry};

use crate::supervisor::SupervisorTable;

/// A whole robot file's content: the geometry, the supervisor's
/// thresholds the file sets (none given keeps the defaults) and the bodies'
/// sizes.
#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    /// Module 1 and both instrument modules, in library units (mm, rad).
    pub geometry: RobotGeometry<f64>,
    /// The `[supervisor]` table: the thresholds the file gives.
    pub supervisor: SupervisorTable,
    /// The `[bodies]` table: the shafts' and the endoscope's sizes (mm;
    /// default [`BodyGeometry::assumed`]).
    pub bodies: BodyGeometry<f64>,
    /// The `[dynamics]` table: the platform with its modules as one rigid
    /// body, its weight and inertia loading module 1 every sample; `None`
    /// without the table (no weight: tip loads alone).
    pub dynamics: Option<Payload<f64>>,
    /// The `[stiffness]` table: each actuator's stiffness for the tips'
    /// deflections (default [`ActuatorStiffness::assumed`]).
    pub stiffness: ActuatorStiffness<f64>,
}

impl Robot {
    /// The paper's robot (module 1 assumed), with the supervisor's default
    /// thresholds.
    pub fn paper() -> Self {
        Self::from(RobotGeometry::paper())
    }

    /// The paper's robot with the assumed platform body
    /// ([`Payload::assumed`]): what `robots/dynamics.toml` holds.
    pub fn paper_with_dynamics() -> Self {
        Self {
            dynamics: Some(Payload::assumed()),
            ..Self::paper()
        }
    }
}

impl Default for Robot {
    /// [`Robot::paper`].
    fn default() -> Self {
        Self::paper()
    }
}

impl From<RobotGeometry<f64>> for Robot {
    /// A geometry with the supervisor's default thresholds and the assumed bodies.
    fn from(geometry: RobotGeometry<f64>) -> Self {
        Self {
            geometry,
            supervisor: SupervisorTable::default(),
            bodies: BodyGeometry::assumed(),
            dynamics: None,
            stiffness: ActuatorStiffness::assumed(),
        }
    }
}
