//! A procedure planned: its motions one after the other on one time line,
//! each from the state the previous one ended in, each lasting a whole
//! number of periods (`plan`), each built from where the one before ended
//! (`motion`), what is inside the patient before each and
//! the rules for motions while anything is (`inside`), and the checks made
//! before any output (`check`; see
//! [`Simulation::new`](crate::engine::Simulation::new)).

mod check;
mod follow;
mod inside;
mod motion;
mod plan;

pub(crate) use check::commanded_tips;
pub use check::{CameraCheck, MotionCheck, ProcedureCheck, Warning};
pub use plan::{PlannedMotion, ProcedurePlan};
