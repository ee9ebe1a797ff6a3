//! One geometry per motion type: what a motion moves and where the robot is
//! for any value of the motion's own coordinates, with the timing left
//! apart.
//!
//! A [`Geometry`] is a start [`RobotState`] and a target. Every motion of
//! the paper's four types is described by its own coordinates ([`Moving`]):
//! the pose's six for type 1, the inserted `qs3` or depth for type 2, both
//! tips' `x, y, z` for type 3, `(psi, theta)` for type 4.
//! [`Geometry::at`] is the one map from those coordinates (with their rates
//! and accelerations) to what the controller takes ([`MotionSample`]), and
//! [`Geometry::along`] is the straight line from the start to the target in
//! those coordinates, `s in [0, 1]`. A timing then only says how the
//! coordinates move in time:
//!
//! | timing | the coordinates at `t` |
//! |---|---|
//! | a synchronised trapezoid from rest ([`Motion`](crate::motions::Motion)) | each coordinate's profile, in phase, so on the straight line |
//! | the jerk-limited double S ([`Motion::jerk_limited`](crate::motions::Motion::jerk_limited)) | `along(s(t))`, `s(t)` a double S from 0 to 1 |
//! | the time-optimal schedule (`parasils-sim`'s optimal timing over [`MotionPath`](crate::path::MotionPath)) | `along(s(t))`, `s(t)` from the solver |
//! | an online profile from a moving state (a motion cut short, a stop) | each coordinate's online profile, arriving together |
//!
//! and every one of them reaches the robot through [`Geometry::at`].
//!
//! ```
//! use parasils::geometry::{Geometry, Moving, Port, RobotState};
//! use parasils::kin::{Joints, ModuleCommand, Pose};
//!
//! let start = RobotState {
//!     pose: Pose::<f64>::paper_start(),
//!     joints: [Joints::from_deg_mm(3.0, -10.0, 120.0), Joints::from_deg_mm(-3.0, 10.0, 120.0)],
//!     endoscope_depth: 0.0,
//! };
//! // The left instrument 30 mm deeper: halfway along, moving with s_dot = 2 /s,
//! // so qs3 at 135 mm and 60 mm/s.
//! let insert = Geometry::insertion(&start, Port::Left, 30.0);
//! let half = insert.along(0.5, 2.0, 0.0);
//! let Moving::Depth(Port::Left, qs3) = half else { unreachable!() };
//! assert_eq!((qs3.position, qs3.velocity), (135.0, 60.0));
//! let ModuleCommand::Joints(left) = insert.at(&half).left else { unreachable!() };
//! assert_eq!((left.q.qs3, left.q_dot.qs3, left.q.qs1), (135.0, 60.0, start.joints[0].qs1));
//! ```

use crate::Real;
use crate::kin::nalgebra::Vector3;
use crate::kin::{
    Controller, JointMotion, Joints, MarginTracker, ModuleCommand, PlatformState, Pose, PoseRate,
    TipMotion, TipTargets,
};
use crate::reorientation::turned;
use crate::traj::{JerkLimits, State};

/// The paper's motion types, numbered as in its section 2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MotionType {
    /// 1: the platform positioned outside the patient.
    Position = 1,
    /// 2: an instrument or the endoscope inserted along its axis.
    Insert = 2,
    /// 3: an instrument tip moved.
    Manipulate = 3,
    /// 4: the endoscope reoriented, both tips held.
    Reorient = 4,
}

impl MotionType {
    /// The type's number, 1 to 4.
    pub const fn number(self) -> u8 {
        self as u8
    }

    /// The name procedures use: `"position"`, `"insert"`, `"manipulate"`,
    /// `"reorient"`.
    pub const fn name(self) -> &'static str {
        match self {
            MotionType::Position => "position",
            MotionType::Insert => "insert",
            MotionType::Manipulate => "manipulate",
            MotionType::Reorient => "reorient",
        }
    }
}

/// What an insertion moves along its own axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Port {
    /// The left instrument (`qs3`).
    Left,
    /// The right instrument (`qs3`).
    Right,
    /// The endoscope (its depth).
    Endoscope,
}

impl Port {
    /// `"left"`, `"right"` or `"endoscope"`.
    pub const fn name(self) -> &'static str {
        match self {
            Port::Left => "left",
            Port::Right => "right",
            Port::Endoscope => "endoscope",
        }
    }
}

/// The robot's state between motions: at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotState<T> {
    /// The platform's pose, mm and rad.
    pub pose: Pose<T>,
    /// Both instrument modules' joints, `[left, right]` (rad, rad, mm).
    pub joints: [Joints<T>; 2],
    /// The endoscope's insertion depth, mm (0 at its port, positive inwards).
    pub endoscope_depth: T,
}

impl<T: Real> RobotState<T> {
    /// The robot at rest at `pose` with its tips at `tips` and the
    /// endoscope at `endoscope_depth` (mm): both modules' joints from
    /// `controller`'s inverse kinematics, in its assembly modes.
    ///
    /// # Errors
    /// The kinematics' error when the pose or a tip cannot be solved.
    pub fn solved(
        controller: &Controller<T>,
        pose: Pose<T>,
        tips: &TipTargets<T>,
        endoscope_depth: T,
    ) -> Result<Self, crate::kin::Error> {
        let step = controller.step(
            &PlatformState::at_rest(pose),
            tips,
            &mut MarginTracker::new(),
        )?;
        Ok(Self {
            pose,
            joints: [step.left.q, step.right.q],
            endoscope_depth,
        })
    }
}

/// One instant of a motion: what the controller is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionSample<T: Real> {
    /// The platform's pose, rates and accelerations.
    pub platform: PlatformState<T>,
    /// The left module's command.
    pub left: ModuleCommand<T>,
    /// The right module's command.
    pub right: ModuleCommand<T>,
    /// The endoscope's depth (mm), with its rate and acceleration.
    pub endoscope: State<T>,
}

/// A motion's own coordinates at an instant, with their rates: what
/// [`Geometry::at`] maps to the robot, and what a motion cut short hands to
/// the next one ([`Motion::moving_at`](crate::motions::Motion::moving_at)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Moving<T> {
    /// Type 1: `x, y, z` (mm), `psi, theta, phi` (rad).
    Pose([State<T>; 6]),
    /// Type 2: what is inserted, and its `qs3` (or depth), mm.
    Depth(Port, State<T>),
    /// Type 3: both tips, `x, y, z` each, mm, fixed frame (left first).
    Tips([State<T>; 6]),
    /// Type 4: `psi, theta`, rad.
    Angles([State<T>; 2]),
}

impl<T: Real> Moving<T> {
    /// Whether every coordinate is at rest (zero velocity).
    pub fn at_rest(&self) -> bool {
        let still = |s: &[State<T>]| s.iter().all(|a| a.velocity == T::zero());
        match self {
            Moving::Pose(s) | Moving::Tips(s) => still(s),
            Moving::Depth(_, s) => still(core::slice::from_ref(s)),
            Moving::Angles(s) => still(s),
        }
    }
}

/// What a motion moves: each type by its target, so that `s = 1` is the
/// target itself, not a sum that rounding could leave short of it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind<T: Real> {
    /// Type 1: the pose to `(x, y, z, psi, theta, phi)` (mm, rad).
    Position([T; 6]),
    /// Type 2: `qs3` of a module, or the endoscope's depth, by `depth` mm.
    Insert(Port, T),
    /// Type 3: the tips from `from` to `to` (mm, fixed frame); a tip that is
    /// not `driven` keeps its joints.
    Manipulate {
        from: [Vector3<T>; 2],
        to: [Vector3<T>; 2],
        driven: [bool; 2],
    },
    /// Type 4: `(psi, theta)` to `goal` (rad), the tips held.
    Reorient { goal: [T; 2], tips: [Vector3<T>; 2] },
}

/// One motion of the paper's four types as geometry: the start, the target,
/// and the map from the motion's own coordinates to the robot (see the
/// module's documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry<T: Real> {
    start: RobotState<T>,
    kind: Kind<T>,
}

/// The point `s` of the way from `from` to `to`: `from + s (to - from)`,
/// and `to` itself from `s = 1` on.
fn lerp<T: Real>(from: T, to: T, s: T) -> T {
    if s >= T::one() {
        to
    } else {
        from + s * (to - from)
    }
}

/// Tip `i`'s command (0 left, 1 right) from type 3's coordinates.
fn tip_command<T: Real>(c: &[State<T>; 6], i: usize) -> ModuleCommand<T> {
    let v = |f: fn(&State<T>) -> T| Vector3::from_fn(|k, _| c.get(3 * i + k).map_or(T::zero(), f));
    ModuleCommand::Tip(TipMotion {
        position: v(|a| a.position),
        velocity: v(|a| a.velocity),
        acceleration: v(|a| a.acceleration),
    })
}

/// The largest magnitude in `d` (0 for none).
fn largest<T: Real>(d: &[T]) -> T {
    d.iter().fold(T::zero(), |m, &x| {
        let x = if x < T::zero() { -x } else { x };
        if x > m { x } else { m }
    })
}

impl<T: Real> Geometry<T> {
    /// Type 1: the platform from `start.pose` to `goal` on the straight line
    /// in pose space, the instrument joints and the endoscope held.
    pub fn positioning(start: &RobotState<T>, goal: Pose<T>) -> Self {
        Self {
            start: *start,
            kind: Kind::Position(goal.to_array()),
        }
    }

    /// Type 2: `port`'s `qs3` (or the endoscope's depth) by `depth` mm
    /// (positive inwards), everything else held.
    pub fn insertion(start: &RobotState<T>, port: Port, depth: T) -> Self {
        Self {
            start: *start,
            kind: Kind::Insert(port, depth),
        }
    }

    /// Type 3: the tips from `from` (`[left, right]`, mm, fixed frame: where
    /// the start joints put them) to `to` (`None`: held) on straight lines,
    /// the platform still. A tip that does not move keeps its joints.
    pub fn manipulation(
        start: &RobotState<T>,
        from: [Vector3<T>; 2],
        to: [Option<Vector3<T>>; 2],
    ) -> Self {
        let to = [0, 1].map(|i| to[i].unwrap_or(from[i]));
        let driven = [from[0] != to[0], from[1] != to[1]];
        Self::manipulation_driven(start, from, to, driven)
    }

    /// Type 3 with the tips that are commanded by position named: a motion
    /// from a moving state commands both, since a tip may move on the way
    /// even when it ends where it started.
    pub(crate) fn manipulation_driven(
        start: &RobotState<T>,
        from: [Vector3<T>; 2],
        to: [Vector3<T>; 2],
        driven: [bool; 2],
    ) -> Self {
        Self {
            start: *start,
            kind: Kind::Manipulate { from, to, driven },
        }
    }

    /// Type 4: `(psi, theta)` from `start.pose`'s to `goal` (rad), the tips
    /// held at `tips` (`[left, right]`, mm, fixed frame); `start.joints` are
    /// not used (the tips are).
    pub fn turning(start: &RobotState<T>, goal: [T; 2], tips: [Vector3<T>; 2]) -> Self {
        Self {
            start: *start,
            kind: Kind::Reorient { goal, tips },
        }
    }

    /// A manipulation's tips at the start and at the target (`[left,
    /// right]`, mm); a turn's held tips twice; zeros for types 1 and 2.
    pub(crate) fn tips_line(&self) -> ([Vector3<T>; 2], [Vector3<T>; 2]) {
        match &self.kind {
            Kind::Manipulate { from, to, .. } => (*from, *to),
            Kind::Reorient { tips, .. } => (*tips, *tips),
            _ => ([Vector3::zeros(); 2], [Vector3::zeros(); 2]),
        }
    }

    /// The motion's type.
    pub fn motion_type(&self) -> MotionType {
        match self.kind {
            Kind::Position(_) => MotionType::Position,
            Kind::Insert(..) => MotionType::Insert,
            Kind::Manipulate { .. } => MotionType::Manipulate,
            Kind::Reorient { .. } => MotionType::Reorient,
        }
    }

    /// The state it starts from.
    pub fn start(&self) -> &RobotState<T> {
        &self.start
    }

    /// What an insertion moves (`None` for the other types).
    pub fn port(&self) -> Option<Port> {
        match self.kind {
            Kind::Insert(port, _) => Some(port),
            _ => None,
        }
    }

    /// The inserted coordinate's value at the start: `qs3` of the module,
    /// or the endoscope's depth, mm.
    fn depth_from(&self, port: Port) -> T {
        match port {
            Port::Left => self.start.joints[0].qs3,
            Port::Right => self.start.joints[1].qs3,
            Port::Endoscope => self.start.endoscope_depth,
        }
    }

    /// The motion's own coordinates on the straight line from the start to
    /// the target at `s` (`s = 1` the target exactly), moving with path
    /// speed `s_dot` (1/s) and path acceleration `s_ddot` (1/s^2).
    pub fn along(&self, s: T, s_dot: T, s_ddot: T) -> Moving<T> {
        let along = |from: T, to: T| {
            let by = to - from;
            State {
                position: lerp(from, to, s),
                velocity: s_dot * by,
                acceleration: s_ddot * by,
            }
        };
        match &self.kind {
            Kind::Position(goal) => {
                let p = self.start.pose.to_array();
                Moving::Pose(core::array::from_fn(|k| along(p[k], goal[k])))
            }
            Kind::Insert(port, depth) => {
                let from = self.depth_from(*port);
                Moving::Depth(*port, along(from, from + *depth))
            }
            Kind::Manipulate { from, to, .. } => Moving::Tips(core::array::from_fn(|k| {
                let (i, c) = (k / 3, k % 3);
                along(from[i][c], to[i][c])
            })),
            Kind::Reorient { goal, .. } => {
                let p = &self.start.pose;
                Moving::Angles([along(p.psi, goal[0]), along(p.theta, goal[1])])
            }
        }
    }

    /// The robot for the motion's own `coordinates`: the one map every
    /// timing goes through. Coordinates of another motion type than this
    /// geometry's leave the robot at its start.
    pub fn at(&self, coordinates: &Moving<T>) -> MotionSample<T> {
        let start = &self.start;
        let [l, r] = start.joints;
        let mut out = MotionSample {
            platform: PlatformState::at_rest(start.pose),
            left: ModuleCommand::Joints(JointMotion::held(l)),
            right: ModuleCommand::Joints(JointMotion::held(r)),
            endoscope: State::rest(start.endoscope_depth),
        };
        match (&self.kind, coordinates) {
            (Kind::Position(_), Moving::Pose(c)) => {
                let [vx, vy, vz, vpsi, vtheta, vphi] = c.map(|a| a.velocity);
                let [ax, ay, az, apsi, atheta, aphi] = c.map(|a| a.acceleration);
                out.platform = PlatformState {
                    pose: Pose::from_array(c.map(|a| a.position)),
                    velocity: PoseRate::new(vx, vy, vz, vpsi, vtheta, vphi),
                    acceleration: PoseRate::new(ax, ay, az, apsi, atheta, aphi),
                };
            }
            (Kind::Insert(port, _), Moving::Depth(moved, a)) if port == moved => {
                let zero = T::zero();
                let driven = |q: Joints<T>| {
                    ModuleCommand::Joints(JointMotion {
                        q: Joints::new(q.qs1, q.qs2, a.position),
                        q_dot: Joints::new(zero, zero, a.velocity),
                        q_ddot: Joints::new(zero, zero, a.acceleration),
                    })
                };
                match port {
                    Port::Left => out.left = driven(l),
                    Port::Right => out.right = driven(r),
                    Port::Endoscope => out.endoscope = *a,
                }
            }
            (Kind::Manipulate { driven, .. }, Moving::Tips(c)) => {
                if driven[0] {
                    out.left = tip_command(c, 0);
                }
                if driven[1] {
                    out.right = tip_command(c, 1);
                }
            }
            (Kind::Reorient { tips, .. }, Moving::Angles(a)) => {
                out.platform = turned(&start.pose, *a);
                out.left = ModuleCommand::still(tips[0]);
                out.right = ModuleCommand::still(tips[1]);
            }
            _ => {}
        }
        out
    }

    /// A type-3 motion seen by a camera that follows the tips: the tips at
    /// `coordinates`, both commanded by position in the fixed frame (a tip
    /// the motion does not drive is held where it is, not by its joints),
    /// while the platform turns to `angles` (`[psi, theta]`, rad, with rates
    /// and accelerations; `P` and `phi` of the start held), so both modules
    /// compensate the turn. For any other geometry, or coordinates of
    /// another type, the same as [`Geometry::at`].
    pub fn followed(&self, coordinates: &Moving<T>, angles: [State<T>; 2]) -> MotionSample<T> {
        let mut out = self.at(coordinates);
        if let (Kind::Manipulate { .. }, Moving::Tips(c)) = (&self.kind, coordinates) {
            out.platform = turned(&self.start.pose, angles);
            out.left = tip_command(c, 0);
            out.right = tip_command(c, 1);
        }
        out
    }

    /// The robot at `s` of the straight line, moving with `s_dot` and
    /// `s_ddot`: `at(along(s, s_dot, s_ddot))`.
    pub fn sample(&self, s: T, s_dot: T, s_ddot: T) -> MotionSample<T> {
        self.at(&self.along(s, s_dot, s_ddot))
    }

    /// How far each of the motion's own coordinates moves over the whole
    /// line (`d/ds` of each), as the limits read them: `[linear, angular]`
    /// groups, each the displacements its limit applies to (mm; rad).
    fn displacements(&self) -> ([T; 6], usize, [T; 3], usize) {
        let zero = T::zero();
        let mut linear = [zero; 6];
        let mut angular = [zero; 3];
        let (nl, na) = match &self.kind {
            Kind::Position(goal) => {
                let p = self.start.pose.to_array();
                for k in 0..3 {
                    linear[k] = goal[k] - p[k];
                    angular[k] = goal[k + 3] - p[k + 3];
                }
                (3, 3)
            }
            Kind::Insert(_, d) => {
                linear[0] = *d;
                (1, 0)
            }
            Kind::Manipulate { from, to, .. } => {
                linear[0] = (to[0] - from[0]).norm();
                linear[1] = (to[1] - from[1]).norm();
                (2, 0)
            }
            Kind::Reorient { goal, .. } => {
                angular[0] = goal[0] - self.start.pose.psi;
                angular[1] = goal[1] - self.start.pose.theta;
                (0, 2)
            }
        };
        (linear, nl, angular, na)
    }

    /// Whether nothing moves along it (a displacement of zero).
    pub fn is_still(&self) -> bool {
        let (linear, nl, angular, na) = self.displacements();
        largest(&linear[..nl]) == T::zero() && largest(&angular[..na]) == T::zero()
    }

    /// The motion's own two rows of a path (see
    /// [`MotionPath`](crate::path::MotionPath)): their derivatives in `s`.
    pub fn own_rates(&self) -> [T; 2] {
        let (linear, nl, angular, na) = self.displacements();
        match &self.kind {
            Kind::Position(_) => [largest(&linear[..nl]), largest(&angular[..na])],
            Kind::Insert(_, d) => [*d, T::zero()],
            Kind::Manipulate { .. } => [linear[0], linear[1]],
            Kind::Reorient { .. } => [angular[0], angular[1]],
        }
    }

    /// The limits of a law in `s` that keeps every coordinate within its
    /// own: `linear` for the lengths (mm), `angular` for the angles (rad);
    /// each limit of `s` is the smallest over the coordinates that move of
    /// the coordinate's limit over its displacement. `None` when nothing
    /// moves.
    pub fn path_limits(
        &self,
        linear: JerkLimits<T>,
        angular: JerkLimits<T>,
    ) -> Option<JerkLimits<T>> {
        let (l, nl, a, na) = self.displacements();
        let mut out: Option<JerkLimits<T>> = None;
        let groups = [(&l[..nl], linear), (&a[..na], angular)];
        for (displacements, limits) in groups {
            for &d in displacements {
                let d = if d < T::zero() { -d } else { d };
                if !(d > T::zero()) {
                    continue;
                }
                let scaled = JerkLimits::new(limits.v_max / d, limits.a_max / d, limits.j_max / d);
                out = Some(match out {
                    None => scaled,
                    Some(o) => JerkLimits::new(
                        scaled.v_max.min(o.v_max),
                        scaled.a_max.min(o.a_max),
                        scaled.j_max.min(o.j_max),
                    ),
                });
            }
        }
        out
    }
}
