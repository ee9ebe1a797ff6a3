//! What one cycle of the online controller reports ([`Setpoint`]), and what
//! kind of motion it belongs to ([`MotionKind`]).

use crate::Real;
use crate::follow::FollowPhase;
use crate::kin::{Clearance, ControlStep, PlatformState, TipTargets};
use crate::regions::NearestRegion;
use crate::supervisor::{MarginSet, Margins, PairSet};

/// What the active motion of an [`OnlineController`] is.
///
/// [`OnlineController`]: crate::OnlineController
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MotionKind {
    /// Nothing commanded yet: at rest where [`OnlineController::new`] put it.
    ///
    /// [`OnlineController::new`]: crate::OnlineController::new
    #[default]
    Rest,
    /// A goal given by [`OnlineController::command`].
    ///
    /// [`OnlineController::command`]: crate::OnlineController::command
    Command,
    /// A controlled stop asked by [`OnlineController::stop`].
    ///
    /// [`OnlineController::stop`]: crate::OnlineController::stop
    Stop,
    /// A controlled stop the supervisor demanded (see the [module
    /// docs](crate::online)).
    SupervisorStop,
    /// The camera follows the tips ([`OnlineController::follow`]): the
    /// follow law's recentrings, or its rest between them.
    ///
    /// [`OnlineController::follow`]: crate::OnlineController::follow
    Follow,
}

impl MotionKind {
    /// Whether the motion is a controlled stop, asked or demanded.
    pub const fn is_stop(self) -> bool {
        matches!(self, MotionKind::Stop | MotionKind::SupervisorStop)
    }
}

/// Everything one cycle of [`OnlineController::tick`] computed.
///
/// [`OnlineController::tick`]: crate::OnlineController::tick
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setpoint<T: Real> {
    /// The cycle's time, s.
    pub t: T,
    /// The platform's pose, Euler rates and accelerations at `t`.
    pub state: PlatformState<T>,
    /// Module 1's actuators and both instrument modules' joints, with their
    /// rates, accelerations and margins.
    pub step: ControlStep<T>,
    /// The tips this cycle puts the instruments at, mm, fixed frame (those
    /// of the latest [`set_tips`] or [`move_tips`], or of `new`).
    ///
    /// [`set_tips`]: crate::OnlineController::set_tips
    /// [`move_tips`]: crate::OnlineController::move_tips
    pub tips: TipTargets<T>,
    /// The index of the motion this cycle belongs to (see
    /// [`OnlineController::command_index`]); a stop the supervisor demanded
    /// in this cycle counts from the next cycle.
    ///
    /// [`OnlineController::command_index`]: crate::OnlineController::command_index
    pub command: u32,
    /// What that motion is.
    pub kind: MotionKind,
    /// The follow law's phase after this cycle while the camera follows the
    /// tips (`None` otherwise).
    pub follow: Option<FollowPhase>,
    /// The supervised margins of this cycle.
    pub margins: Margins<T>,
    /// The margins below their warning thresholds.
    pub warnings: MarginSet,
    /// The margins that demanded a controlled stop in this cycle (empty when
    /// none did); it was carried out unless a stop was already under way.
    pub stop: MarginSet,
    /// The surface gaps between the bodies at this cycle, with the closest
    /// points of their axes (mm, fixed frame); `None` when the controller
    /// watches no clearance ([`OnlineController::with_clearance`]).
    ///
    /// [`OnlineController::with_clearance`]: crate::OnlineController::with_clearance
    pub clearance: Option<Clearance<T>>,
    /// The pairs whose gap is below the clearance warning threshold.
    pub clearance_warnings: PairSet,
    /// The pairs whose gap demanded a controlled stop in this cycle (carried
    /// out as a margin's is).
    pub clearance_stop: PairSet,
    /// The smallest gap from the in-body parts to the forbidden regions and
    /// which region ([`OnlineController::tick_with`]); `None` without
    /// regions, or while no body is inside.
    ///
    /// [`OnlineController::tick_with`]: crate::OnlineController::tick_with
    pub region: Option<NearestRegion<T>>,
    /// That gap is below the clearance warning threshold.
    pub region_warning: bool,
    /// That gap demanded a controlled stop in this cycle (carried out as a
    /// margin's is).
    pub region_stop: bool,
}
