//! The robot a run uses, as one robot file gives it: the geometry (module 1
//! and both instrument modules, with their limits) and the margin
//! supervisor's thresholds (`[supervisor]`).
//!
//! A robot file is read once, into one [`Robot`]
//! ([`robot_file::load_robot`](crate::robot_file::load_robot)), and that
//! value is what every front end passes on: the command line's `--robot`,
//! Python's `parasils.Robot` and `robot=` arguments, a procedure's `robot`
//! key. Nothing reads the file a second time for one of its tables.
//!
//! ```
//! use parasils::kin::RobotGeometry;
//! use parasils_sim::Robot;
//!
//! let robot = Robot::paper();
//! assert_eq!(robot.geometry, RobotGeometry::paper());
//! assert!(robot.supervisor.is_empty());
//! ```

use parasils::kin::RobotGeometry;

use crate::supervisor::SupervisorTable;

/// A whole robot file's content: the geometry and the supervisor's
/// thresholds the file sets (none given keeps the defaults).
#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    /// Module 1 and both instrument modules, in library units (mm, rad).
    pub geometry: RobotGeometry<f64>,
    /// The `[supervisor]` table: the thresholds the file gives.
    pub supervisor: SupervisorTable,
}

impl Robot {
    /// The paper's robot (module 1 assumed), with the supervisor's default
    /// thresholds.
    pub fn paper() -> Self {
        Self::from(RobotGeometry::paper())
    }
}

impl Default for Robot {
    /// [`Robot::paper`].
    fn default() -> Self {
        Self::paper()
    }
}

impl From<RobotGeometry<f64>> for Robot {
    /// A geometry with the supervisor's default thresholds.
    fn from(geometry: RobotGeometry<f64>) -> Self {
        Self {
            geometry,
            supervisor: SupervisorTable::default(),
        }
    }
}
