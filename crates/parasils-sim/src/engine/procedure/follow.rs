//! A type-3 motion with `camera = "follow"`: the follow law stepped on the
//! control cycle over the motion's tips, once, while the procedure is
//! planned. The law has state (its phase, its recentring, how long the tips
//! have been still), so its setpoints are not a function of time alone: they
//! are computed in order, row by row, and kept with the motion (two angles
//! with their rates and accelerations, 48 bytes a row), so that every later
//! reading of the motion (the check, the run, the end state the next motion
//! starts from) sees the same platform.

use nalgebra::Vector3;
use parasils::kin::Camera;
use parasils::motions::Moving;
use parasils::traj::State;
use parasils::{Follow, FollowParams};

use crate::motion::MotionLimits;
use parasils::motions::RobotState;

/// How long the camera may take to settle once the tips have stopped, s:
/// past it, the motion is refused (a law that keeps turning would otherwise
/// never hand over to the next motion).
pub(super) const SETTLE_LIMIT_S: f64 = 60.0;

/// Why the law could not follow the motion.
pub(super) enum FollowFailure {
    /// The law failed at the motion's own time `t` (s).
    Law(f64, parasils::FollowError),
    /// The camera was still turning [`SETTLE_LIMIT_S`] after the tips
    /// stopped.
    Unsettled,
}

/// The law's `[psi, theta]` setpoints at rows `0, 1, ...` of a motion that
/// starts at rest in `state`, the tips at row `j` given by `tips_at(j)`
/// (`None` past the motion's own rows is not expected: the motion's last
/// row holds), at `rate` (Hz): until the tips have stopped (from row
/// `periods` on) and the law is idle.
pub(super) fn setpoints(
    camera: &Camera<f64>,
    state: &RobotState<f64>,
    limits: &MotionLimits,
    rate: f64,
    periods: usize,
    tips_at: impl Fn(usize) -> Moving<f64>,
) -> Result<Vec<[State<f64>; 2]>, FollowFailure> {
    let params = FollowParams {
        limits: limits.angular(),
        ..FollowParams::assumed()
    };
    let mut law = Follow::new(*camera, params, state.pose, state.endoscope_depth)
        .map_err(|e| FollowFailure::Law(0.0, e))?;
    #[allow(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a positive rate times a minute, far below usize::MAX"
    )]
    let cap = periods.saturating_add((SETTLE_LIMIT_S * rate).ceil() as usize);
    let mut rows = Vec::with_capacity(periods + 1);
    for j in 0..=cap {
        let t = j as f64 / rate;
        let tips = match tips_at(j) {
            Moving::Tips(c) => {
                [0, 3].map(|i| Vector3::new(c[i].position, c[i + 1].position, c[i + 2].position))
            }
            // Not a manipulation: the platform holds.
            _ => return Ok(vec![law.angles(); periods + 1]),
        };
        let step = law.step(t, &tips).map_err(|e| FollowFailure::Law(t, e))?;
        rows.push(step.angles);
        if j >= periods && law.is_idle() {
            return Ok(rows);
        }
    }
    Err(FollowFailure::Unsettled)
}
