//! The error of a motion run through the controller: the planner's, the
//! kinematics', or the online controller's own.

use crate::follow::FollowError;
use crate::kin::Side;
use crate::margin::Margin;
use crate::regions::RegionQueryError;

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
    /// A look-at command has no solution (see [`parasils_kin::CameraError`]):
    /// the target is behind the port, out of the view's reach with this
    /// `phi`, or needs the gimbal's `theta = +-90 deg`.
    #[error(transparent)]
    Camera(#[from] crate::kin::CameraError),
    /// A look-at command was given to an
    /// [`OnlineController`](crate::OnlineController) that knows no
    /// endoscope depth (give it with
    /// [`with_endoscope_depth`](crate::OnlineController::with_endoscope_depth)
    /// or [`with_clearance`](crate::OnlineController::with_clearance)).
    #[error(
        "a look-at command needs the endoscope's depth, and the online controller was given none"
    )]
    NoEndoscopeDepth,
    /// A time given to the [`OnlineController`](crate::OnlineController) is
    /// infinite or NaN.
    #[error("the time {value} s is not finite")]
    NonFiniteTime {
        /// The time given, s.
        value: f64,
    },
    /// A time given to the [`OnlineController`](crate::OnlineController) is
    /// earlier than one it was given before: its clock never runs backwards.
    #[error("the time {t} s is before {last} s, the latest time given")]
    TimeReversed {
        /// The time given, s.
        t: f64,
        /// The latest time given before, s.
        last: f64,
    },
    /// A threshold of a [`Supervisor`](crate::supervisor::Supervisor) is not
    /// finite or not above the one it must exceed (a stop threshold the
    /// solvers' hard one, a warning threshold the stop one).
    #[error(
        "the supervisor's {what} threshold of {margin} is {value}: it must be finite and above {min}"
    )]
    InvalidThreshold {
        /// `"stop"` or `"warning"`.
        what: &'static str,
        /// Which margin.
        margin: Margin,
        /// The threshold given, in the margin's unit.
        value: f64,
        /// What it must exceed (a warning threshold may equal it).
        min: f64,
    },
    /// A clearance threshold of the supervisor
    /// ([`ClearanceThresholds`](crate::supervisor::ClearanceThresholds)) is
    /// not finite, or the warning threshold is below the stop one.
    #[error(
        "the supervisor's clearance {what} threshold is {value} mm: it must be finite and at least {min} mm"
    )]
    InvalidClearanceThreshold {
        /// `"stop"` or `"warning"`.
        what: &'static str,
        /// The threshold given, mm.
        value: f64,
        /// What it must reach (`-inf` for the stop threshold: only finite).
        min: f64,
    },
    /// A tip given to the [`OnlineController`](crate::OnlineController)
    /// ([`set_tips`](crate::OnlineController::set_tips),
    /// [`move_tips`](crate::OnlineController::move_tips)) is further from
    /// the tip held so far than the largest step it accepts in one call.
    #[error(
        "the {side} tip would move {step_mm} mm in one call, more than the largest step of {max_mm} mm"
    )]
    TipStep {
        /// Which tip.
        side: Side,
        /// How far it would move, mm.
        step_mm: f64,
        /// The largest step accepted, mm.
        max_mm: f64,
    },
    /// The follow law cannot take a cycle or its parameters are invalid
    /// (see [`FollowError`]).
    #[error(transparent)]
    Follow(#[from] FollowError),
    /// A forbidden region's gap could not be computed (see
    /// [`RegionQueryError`]).
    #[error(transparent)]
    Region(#[from] RegionQueryError),
    /// Forbidden regions were given to an
    /// [`OnlineController`](crate::OnlineController) that knows no bodies'
    /// sizes (give them with
    /// [`with_clearance`](crate::OnlineController::with_clearance)).
    #[error(
        "forbidden regions need the bodies' sizes, and the online controller watches no clearance"
    )]
    NoClearanceWatch,
}
