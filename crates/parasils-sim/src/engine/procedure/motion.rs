//! One motion of a timeline, built from the state the one before ended
//! in: from rest ([`plan`]), continuing a motion cut short while it moved
//! ([`continued`]), or timed as fast as the actuators allow
//! ([`optimal_plan`]).

use nalgebra::Vector3;
use parasils::Geometry;
use parasils::kin::{Camera, Controller, Joints, Pose};
use parasils::motions::{
    Insertion, Manipulation, Motion, MotionType, Moving, Port, Positioning, RobotState, Turning,
};
use parasils::traj::Synchronization;

use crate::motion::{LookAt, MotionGoal, MotionLimits, MotionSpec, turn_goal_rad};
use crate::timing::{MotionPath, OptimalMotion, TimingError, TimingOptions};

/// The tips where `joints` put them with the platform at `pose`, mm, fixed
/// frame (`[left, right]`).
pub(super) fn tips_of(
    controller: &Controller<f64>,
    pose: &Pose<f64>,
    joints: &[Joints<f64>; 2],
) -> [Vector3<f64>; 2] {
    let r = pose.rotation();
    let p = pose.position();
    [
        r * controller.left.fk_platform(&joints[0]) + p,
        r * controller.right.fk_platform(&joints[1]) + p,
    ]
}

/// The motion `spec` from `state`, at rest, the tips at `held` (`[left,
/// right]`, mm, fixed frame); a reorientation's two angles timed together
/// by `sync`.
pub(super) fn plan(
    camera: &Camera<f64>,
    state: &RobotState<f64>,
    held: [Vector3<f64>; 2],
    spec: &MotionSpec,
    sync: Synchronization,
) -> Result<Motion<f64>, Continue> {
    if let (Some([linear, angular]), Some(geometry)) =
        (spec.limits.jerk(), geometry_of(camera, state, held, spec)?)
    {
        return Ok(Motion::jerk_limited(geometry, linear, angular)?);
    }
    let (linear, angular) = (spec.limits.linear(), spec.limits.angular());
    Ok(match spec.goal {
        MotionGoal::Position { pose_mm_deg: p } => Motion::Position(Positioning::new(
            state,
            Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]),
            linear,
            angular,
        )?),
        MotionGoal::Insert { port, depth_mm } => {
            Motion::Insert(Insertion::new(state, port, depth_mm, linear)?)
        }
        MotionGoal::Manipulate {
            tip_left_mm,
            tip_right_mm,
        } => Motion::Manipulate(Manipulation::new(
            state,
            held,
            [
                tip_left_mm.map(Vector3::from),
                tip_right_mm.map(Vector3::from),
            ],
            linear,
        )?),
        MotionGoal::Stop => {
            return Err(Continue::Mismatch(String::from(
                "nothing to stop: the motion before is at rest",
            )));
        }
        MotionGoal::Reorient {
            psi_deg,
            theta_deg,
            absolute,
        } => {
            let goal = turn_goal_rad(
                psi_deg,
                theta_deg,
                absolute,
                [state.pose.psi, state.pose.theta],
            );
            Motion::Reorient(Turning::new(state, goal, [angular; 2], sync, held)?)
        }
        MotionGoal::LookAt { target } => Motion::Reorient(Turning::new(
            state,
            look_goal(camera, state, held, &target)?,
            [angular; 2],
            sync,
            held,
        )?),
    })
}

/// The `[psi, theta]` (rad) that aim `camera` at `target` from `state`,
/// the tips at `held`.
fn look_goal(
    camera: &Camera<f64>,
    state: &RobotState<f64>,
    held: [Vector3<f64>; 2],
    target: &LookAt,
) -> Result<[f64; 2], Continue> {
    let point = Vector3::from(target.point([held[0].into(), held[1].into()]));
    camera
        .look_at(&state.pose, state.endoscope_depth, &point)
        .map_err(|e| Continue::Mismatch(format!("look-at: {e}")))
}

/// The geometry of the motion `spec` from `state`, the tips at `held`
/// (`None` for a stop): what the double S and the optimal timing time.
fn geometry_of(
    camera: &Camera<f64>,
    state: &RobotState<f64>,
    held: [Vector3<f64>; 2],
    spec: &MotionSpec,
) -> Result<Option<Geometry<f64>>, Continue> {
    Ok(Some(match spec.goal {
        MotionGoal::Position { pose_mm_deg: p } => {
            Geometry::positioning(state, Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]))
        }
        MotionGoal::Insert { port, depth_mm } => Geometry::insertion(state, port, depth_mm),
        MotionGoal::Manipulate {
            tip_left_mm,
            tip_right_mm,
        } => Geometry::manipulation(
            state,
            held,
            [
                tip_left_mm.map(Vector3::from),
                tip_right_mm.map(Vector3::from),
            ],
        ),
        MotionGoal::Reorient {
            psi_deg,
            theta_deg,
            absolute,
        } => {
            let from = [state.pose.psi, state.pose.theta];
            let goal = turn_goal_rad(psi_deg, theta_deg, absolute, from);
            Geometry::turning(state, goal, held)
        }
        MotionGoal::LookAt { target } => {
            Geometry::turning(state, look_goal(camera, state, held, &target)?, held)
        }
        MotionGoal::Stop => return Ok(None),
    }))
}

/// The motion `spec` from `state`, at rest, timed to be as fast as the
/// robot's actuator limits allow (see [`OptimalMotion`]): its own limits
/// bind as well where the procedure states them, and always for the
/// endoscope's depth, which no actuator moves. A stop keeps its profile
/// (`None`): it only ever stops a motion that ended at rest, in no time,
/// since the optimal timing cuts no motion short.
pub(super) fn optimal_plan(
    controller: &Controller<f64>,
    state: &RobotState<f64>,
    held: [Vector3<f64>; 2],
    spec: &MotionSpec,
) -> Result<Option<OptimalMotion>, TimingError> {
    let (linear, angular) = (spec.limits.linear(), spec.limits.angular());
    let [linear_stated, angular_stated] = spec.stated;
    let stated_linear = linear_stated.then_some(linear);
    let stated_angular = angular_stated.then_some(angular);
    // The motion was planned from rest before (plan): its geometry exists.
    let Ok(Some(geometry)) = geometry_of(&controller.endoscope.camera, state, held, spec) else {
        return Ok(None);
    };
    let own = match spec.goal {
        MotionGoal::Insert { port, .. } => [
            (linear_stated || port == Port::Endoscope).then_some(linear),
            None,
        ],
        MotionGoal::Manipulate { .. } => [stated_linear; 2],
        MotionGoal::Reorient { .. } | MotionGoal::LookAt { .. } => [stated_angular; 2],
        MotionGoal::Position { .. } | MotionGoal::Stop => [stated_linear, stated_angular],
    };
    let path = MotionPath::new(controller, geometry);
    OptimalMotion::plan(path, &controller.limits, own, &TimingOptions::default()).map(Some)
}

/// Why a motion cannot continue the one before.
pub(super) enum Continue {
    /// The profile cannot be planned.
    Trajectory(parasils::traj::Error),
    /// The motion cannot follow the one before, and why.
    Mismatch(String),
}

impl From<parasils::traj::Error> for Continue {
    fn from(e: parasils::traj::Error) -> Self {
        Continue::Trajectory(e)
    }
}

/// The motion `spec` from the moving state `m` of the motion before (cut
/// short): a stop of it, or a motion of the same type replanned from it.
/// A stop decelerates at the limits of the motion it stops (`stopped`)
/// unless it gives limits of its own.
pub(super) fn continued(
    camera: &Camera<f64>,
    state: &RobotState<f64>,
    held: [Vector3<f64>; 2],
    spec: &MotionSpec,
    m: Moving<f64>,
    stopped: MotionLimits,
) -> Result<Motion<f64>, Continue> {
    if spec.limits.jerk().is_some() {
        return Err(Continue::Mismatch(String::from(
            "the motion before was cut short while moving (its until_s): the motion continuing it is timed by the online profile from that moving state, which takes no jerk limit (jerk_mm_s3, jerk_deg_s3 time motions from rest)",
        )));
    }
    let l = if spec.goal == MotionGoal::Stop && spec.limits == MotionLimits::default() {
        stopped
    } else {
        spec.limits
    };
    let (linear, angular) = (l.linear(), l.angular());
    Ok(match (spec.goal, m) {
        (MotionGoal::Stop, Moving::Pose(s)) => {
            Motion::Position(Positioning::stop(state, s, linear, angular)?)
        }
        (MotionGoal::Stop, Moving::Depth(port, s)) => {
            Motion::Insert(Insertion::stop(state, port, s, linear)?)
        }
        (MotionGoal::Stop, Moving::Tips(s)) => {
            Motion::Manipulate(Manipulation::stop(state, s, linear)?)
        }
        (MotionGoal::Stop, Moving::Angles(a)) => {
            Motion::Reorient(Turning::stop(state, a, angular, held)?)
        }
        (MotionGoal::Position { pose_mm_deg: p }, Moving::Pose(s)) => {
            Motion::Position(Positioning::from_moving(
                state,
                s,
                Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]),
                linear,
                angular,
            )?)
        }
        (MotionGoal::Insert { port, depth_mm }, Moving::Depth(moving, s)) if port == moving => {
            Motion::Insert(Insertion::from_moving(state, port, s, depth_mm, linear)?)
        }
        (
            MotionGoal::Manipulate {
                tip_left_mm,
                tip_right_mm,
            },
            Moving::Tips(s),
        ) => Motion::Manipulate(Manipulation::from_moving(
            state,
            s,
            [
                tip_left_mm.map(Vector3::from),
                tip_right_mm.map(Vector3::from),
            ],
            linear,
        )?),
        (
            MotionGoal::Reorient {
                psi_deg,
                theta_deg,
                absolute,
            },
            Moving::Angles(a),
        ) => {
            let goal = turn_goal_rad(psi_deg, theta_deg, absolute, [a[0].position, a[1].position]);
            Motion::Reorient(Turning::from_moving(state, a, goal, angular, held)?)
        }
        (MotionGoal::LookAt { target }, Moving::Angles(a)) => {
            let goal = look_goal(camera, state, held, &target)?;
            Motion::Reorient(Turning::from_moving(state, a, goal, angular, held)?)
        }
        (goal, m) => {
            let was = match m {
                Moving::Pose(_) => "position",
                Moving::Depth(Port::Left, _) => "insert (left)",
                Moving::Depth(Port::Right, _) => "insert (right)",
                Moving::Depth(Port::Endoscope, _) => "insert (endoscope)",
                Moving::Tips(_) => "manipulate",
                Moving::Angles(_) => "reorient",
            };
            let is = match goal {
                MotionGoal::Insert { port, .. } => format!("insert ({})", port.name()),
                g => String::from(g.motion_type().map_or("stop", MotionType::name)),
            };
            return Err(Continue::Mismatch(format!(
                "the motion before was cut short while moving (its until_s): only a stop or another {was:?} motion can start from its moving state, not {is:?}"
            )));
        }
    })
}
