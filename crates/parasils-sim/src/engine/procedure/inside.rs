//! Inside or outside the patient: the state before each motion of a
//! procedure ([`Inside`]) carried from motion to motion, and the rules the
//! paper states for motions while anything is inside ([`InsideRule`]).
//!
//! The state (docs/model.md, *Inside or outside the patient*):
//! - the endoscope is inside while its depth is above 0 mm;
//! - an instrument is inside once an insertion (type 2) of it has ended
//!   deeper (`qs3`) than at the procedure's start, and outside again once
//!   an insertion of it ends at most at that start depth; other motions do
//!   not change whether it is inside;
//! - at the start, everything is outside but the endoscope when its depth
//!   is above 0 mm;
//! - the incision point is `P` (the platform's origin, the endoscope's
//!   remote centre of motion) when the first insertion begins, or at the
//!   start when the endoscope starts inside; it is forgotten once
//!   everything is outside again.
//!
//! While anything is inside, no motion may move `P` off the incision point,
//! nor change `phi` (the turn about the endoscope's axis, which would twist
//! the port at the skin). Each motion is checked at every row it owns on
//! the control cycle, before any output.

use parasils::kin::Pose;
use parasils::motions::{Port, RobotState};

use crate::engine::error::SimulationError;
use crate::motion::{Inside, InsideRule, MOVE_TOLERANCE_MM, MotionName, TURN_TOLERANCE_DEG};

/// A depth counts as inside when it is beyond its outside value by more
/// than this, mm: the rounding of a depth brought back by the opposite
/// insertion is far below it.
const DEPTH_TOLERANCE_MM: f64 = 1e-6;

/// The state at a procedure's start: everything outside but the endoscope
/// when its depth is above 0 mm, whose incision is then `P` at the start.
pub(crate) fn at_start(start: &RobotState<f64>) -> Inside {
    let endoscope = start.endoscope_depth > DEPTH_TOLERANCE_MM;
    Inside {
        endoscope,
        left: false,
        right: false,
        incision_mm: endoscope.then(|| position(&start.pose)),
    }
}

/// The state after a motion that started in `before` and ended in `end`:
/// `inserted` is the port it inserted (a type-2 motion), `start` the
/// procedure's start state. The incision point is kept while anything is
/// inside; a new one is `P` at `end` (an insertion does not move `P`, so it
/// is `P` where the insertion began).
pub(crate) fn after(
    before: &Inside,
    inserted: Option<Port>,
    end: &RobotState<f64>,
    start: &RobotState<f64>,
) -> Inside {
    let deeper = |k: usize| match (end.joints.get(k), start.joints.get(k)) {
        (Some(now), Some(then)) => now.qs3 > then.qs3 + DEPTH_TOLERANCE_MM,
        _ => false,
    };
    let mut next = Inside {
        endoscope: end.endoscope_depth > DEPTH_TOLERANCE_MM,
        ..*before
    };
    match inserted {
        Some(Port::Left) => next.left = deeper(0),
        Some(Port::Right) => next.right = deeper(1),
        Some(Port::Endoscope) | None => {}
    }
    next.incision_mm = if next.any() {
        before.incision_mm.or_else(|| Some(position(&end.pose)))
    } else {
        None
    };
    next
}

/// The check of a motion named `name` that starts in `inside` at the pose
/// `from` and whose platform goes through `poses` (every row it owns):
/// while anything is inside, `P` stays on the incision point and `phi` on
/// its value at the motion's start.
///
/// # Errors
/// [`SimulationError::Inside`] naming the motion, the first rule broken
/// (the incision point before the turn) and the largest distance of `P`
/// from the incision point (mm) and turn of `phi` (deg) over the motion.
pub(crate) fn check_motion(
    inside: &Inside,
    name: &MotionName,
    from: &Pose<f64>,
    poses: impl IntoIterator<Item = Pose<f64>>,
) -> Result<(), SimulationError> {
    if !inside.any() {
        return Ok(());
    }
    let incision = inside.incision_mm.unwrap_or_else(|| position(from));
    let (mut moved_mm, mut turned_deg) = (0.0_f64, 0.0_f64);
    for pose in poses {
        let p = position(&pose);
        let d = ((p[0] - incision[0]).powi(2)
            + (p[1] - incision[1]).powi(2)
            + (p[2] - incision[2]).powi(2))
        .sqrt();
        // A NaN counts as the largest, and stays.
        if d > moved_mm || d.is_nan() {
            moved_mm = d;
        }
        let t = (pose.phi - from.phi).to_degrees().abs();
        if t > turned_deg || t.is_nan() {
            turned_deg = t;
        }
    }
    let rule = if moved_mm > MOVE_TOLERANCE_MM || moved_mm.is_nan() {
        InsideRule::MovesIncision
    } else if turned_deg > TURN_TOLERANCE_DEG || turned_deg.is_nan() {
        InsideRule::TurnsAboutAxis
    } else {
        return Ok(());
    };
    Err(SimulationError::Inside {
        motion: Box::new(name.clone()),
        rule,
        inside: *inside,
        moved_mm,
        turned_deg,
    })
}

/// `P`, mm.
fn position(pose: &Pose<f64>) -> [f64; 3] {
    [pose.x, pose.y, pose.z]
}
