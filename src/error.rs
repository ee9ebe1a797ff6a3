//! The error of a motion run through the controller: the planner's or the
//! kinematics'.

/// What can fail when a trajectory drives the controller.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The kinematics failed (see [`parasils_kin::Error`]).
    #[error(transparent)]
    Kinematics(#[from] crate::kin::Error),
    /// The trajectory cannot be planned or sampled (see [`parasils_traj::Error`]).
    #[error(transparent)]
    Trajectory(#[from] crate::traj::Error),
}
