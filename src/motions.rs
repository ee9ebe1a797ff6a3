//! The paper's four motion types as planned, rest-to-rest motions, each
//! sampled into what [`Controller::step_commanded`] takes.
//!
//! | type | [`Motion`] | what moves | the profile |
//! |---|---|---|---|
//! | 1 | [`Positioning`] | module 1 takes the platform along a straight line in pose space; the instrument joints are held, so the tips ride along | `(x, y, z, psi, theta, phi)` on one phase-synchronised trapezoid |
//! | 2 | [`Insertion`] | one instrument's `qs3`, or the endoscope's depth: the tip moves on the tool's axis through its port | a trapezoid in `qs3` (or the depth) |
//! | 3 | [`Manipulation`] | one tip, or both, on a straight line in the fixed frame, the platform still; the joints from the closed-form IK at every sample | a trapezoid in arc length (both tips phase-synchronised) |
//! | 4 | [`Reorientation`] | the platform turns in `(psi, theta)`; both tips held | as [`Reorientation`] |
//!
//! Each motion starts from a [`RobotState`] (the platform's pose, both
//! modules' joints, the endoscope's depth): the state where the previous one
//! ended. [`Motion::sample`] gives, at any time, a [`MotionSample`]: the
//! platform's state and each module's command (its tip, or its joints) with
//! rates and accelerations from the profile, in closed form. The assembly
//! modes are the controller's, kept from motion to motion.
//!
//! Units as in the libraries: mm, rad, s. Everything is `no_std`,
//! allocation-free and generic over `f32`/`f64`.
//!
//! ```
//! use parasils::kin::{Controller, Joints, MarginTracker, Pose};
//! use parasils::motions::{Insertion, Motion, Port, RobotState};
//! use parasils::traj::Limits;
//!
//! let controller = Controller::<f64>::paper();
//! let start = RobotState {
//!     pose: Pose::paper_start(),
//!     joints: [Joints::from_deg_mm(3.0, -10.0, 120.0), Joints::from_deg_mm(-3.0, 10.0, 120.0)],
//!     endoscope_depth: 0.0,
//! };
//! // The left instrument 30 mm deeper, at most 20 mm/s and 20 mm/s^2.
//! let insert = Motion::Insert(Insertion::new(&start, Port::Left, 30.0, Limits::new(20.0, 20.0))?);
//! let end = insert.sample(insert.duration());
//! let out = controller.step_commanded(&end.platform, &end.left, &end.right, &mut MarginTracker::new())?;
//! assert_eq!(out.left.q.qs3, 150.0);
//! assert_eq!(out.left.q.qs1, start.joints[0].qs1);
//! # Ok::<(), parasils::Error>(())
//! ```
//!
//! [`Controller::step_commanded`]: crate::kin::Controller::step_commanded

use crate::Real;
use crate::kin::nalgebra::Vector3;
use crate::kin::{JointMotion, Joints, ModuleCommand, PlatformState, Pose, PoseRate, TipMotion};
use crate::reorientation::{Reorientation, turned};
use crate::traj::{
    Limits, Motion as Profile, Multi, OnlineMulti, OnlineTrapezoid, State, Synchronization,
    Trapezoid,
};

/// A profile planned from rest (`R`) or from a moving state (`O`, an online
/// profile: after a motion cut short, the next one starts where it was, at
/// its speed).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Planned<R, O> {
    Rest(R),
    Online(O),
}

impl<R, O> Planned<R, O> {
    fn duration<T: Real>(&self) -> T
    where
        R: Profile<T>,
        O: Profile<T>,
    {
        match self {
            Planned::Rest(p) => p.duration(),
            Planned::Online(p) => p.duration(),
        }
    }

    fn sample<T: Real>(&self, t: T) -> R::Output
    where
        R: Profile<T>,
        O: Profile<T, Output = R::Output>,
    {
        match self {
            Planned::Rest(p) => p.sample(t),
            Planned::Online(p) => p.sample(t),
        }
    }
}

/// A motion's own coordinates at an instant, with their rates: what a motion
/// cut short hands to the next one ([`Motion::moving_at`]).
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

/// Motion type 1: the platform from its pose to `goal` on a straight line in
/// pose space, the six coordinates on one phase-synchronised trapezoid; the
/// instrument joints and the endoscope's depth held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Positioning<T: Real> {
    start: RobotState<T>,
    profile: Planned<Multi<T, 6>, OnlineMulti<T, 6>>,
}

impl<T: Real> Positioning<T> {
    /// Plans the straight line from `start.pose` to `goal`: `x, y, z` each
    /// within `linear` (mm/s, mm/s^2), `psi, theta, phi` each within
    /// `angular` (rad/s, rad/s^2); the slowest coordinate sets the timing
    /// and the others follow it in phase, so that the pose stays on the
    /// segment.
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for a non-finite goal or invalid limits.
    pub fn new(
        start: &RobotState<T>,
        goal: Pose<T>,
        linear: Limits<T>,
        angular: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let limits = [linear, linear, linear, angular, angular, angular];
        let profile = Multi::new(
            start.pose.to_array(),
            goal.to_array(),
            limits,
            Synchronization::Phase,
        )?;
        Ok(Self {
            start: *start,
            profile: Planned::Rest(profile),
        })
    }

    /// Plans the platform from the moving `pose` (a positioning cut short)
    /// to rest at `goal`, time-optimal under the same limits: on the straight
    /// line when the velocity points along the remaining displacement, each
    /// coordinate arriving together otherwise (see `parasils_traj::online`).
    /// `start` holds the joints and the endoscope.
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for a non-finite state or goal, or invalid
    /// limits.
    pub fn from_moving(
        start: &RobotState<T>,
        pose: [State<T>; 6],
        goal: Pose<T>,
        linear: Limits<T>,
        angular: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let limits = [linear, linear, linear, angular, angular, angular];
        let profile = OnlineMulti::new(pose, goal.to_array(), limits, Synchronization::Phase)?;
        Ok(Self {
            start: *start,
            profile: Planned::Online(profile),
        })
    }

    /// The controlled stop of the platform moving as `pose`: the six
    /// coordinates to rest together, each decelerating uniformly, so that
    /// the path keeps its direction.
    ///
    /// # Errors
    /// As [`Positioning::from_moving`].
    pub fn stop(
        start: &RobotState<T>,
        pose: [State<T>; 6],
        linear: Limits<T>,
        angular: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let limits = [linear, linear, linear, angular, angular, angular];
        Ok(Self {
            start: *start,
            profile: Planned::Online(OnlineMulti::stop(pose, limits)?),
        })
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.profile.duration()
    }

    fn sample(&self, t: T) -> MotionSample<T> {
        let s = self.profile.sample(t);
        let pose = Pose::from_array(s.map(|a| a.position));
        let [vx, vy, vz, vpsi, vtheta, vphi] = s.map(|a| a.velocity);
        let [ax, ay, az, apsi, atheta, aphi] = s.map(|a| a.acceleration);
        held(
            &self.start,
            PlatformState {
                pose,
                velocity: PoseRate::new(vx, vy, vz, vpsi, vtheta, vphi),
                acceleration: PoseRate::new(ax, ay, az, apsi, atheta, aphi),
            },
        )
    }
}

/// The platform in `platform`, both modules' joints and the endoscope held
/// at `start`.
fn held<T: Real>(start: &RobotState<T>, platform: PlatformState<T>) -> MotionSample<T> {
    let [l, r] = start.joints;
    MotionSample {
        platform,
        left: ModuleCommand::Joints(JointMotion::held(l)),
        right: ModuleCommand::Joints(JointMotion::held(r)),
        endoscope: State::rest(start.endoscope_depth),
    }
}

/// Motion type 2: one instrument's `qs3`, or the endoscope's depth, by a
/// signed `depth` (mm, positive inwards) on a trapezoid; the platform and
/// every other joint still, so that the tip moves on a straight line through
/// its port.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Insertion<T: Real> {
    start: RobotState<T>,
    port: Port,
    profile: Planned<Trapezoid<T>, OnlineTrapezoid<T>>,
}

impl<T: Real> Insertion<T> {
    /// Plans the insertion of `port` by `depth` mm within `limits` (mm/s,
    /// mm/s^2). Limits on `qs3` and on the endoscope's range are the
    /// controller's to check, at every sample.
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for a non-finite depth or invalid limits.
    pub fn new(
        start: &RobotState<T>,
        port: Port,
        depth: T,
        limits: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let from = match port {
            Port::Left => start.joints[0].qs3,
            Port::Right => start.joints[1].qs3,
            Port::Endoscope => start.endoscope_depth,
        };
        let profile = Trapezoid::new(from, from + depth, limits)?;
        Ok(Self {
            start: *start,
            port,
            profile: Planned::Rest(profile),
        })
    }

    /// Plans `port` from its moving `qs3` (or depth) `state` (an insertion cut
    /// short) to rest `depth` mm beyond where it is, time-optimal under
    /// `limits`.
    ///
    /// # Errors
    /// As [`Insertion::new`].
    pub fn from_moving(
        start: &RobotState<T>,
        port: Port,
        state: State<T>,
        depth: T,
        limits: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let profile = OnlineTrapezoid::new(state, state.position + depth, limits)?;
        Ok(Self {
            start: *start,
            port,
            profile: Planned::Online(profile),
        })
    }

    /// The controlled stop of `port` moving as `state`: to rest at `a_max`.
    ///
    /// # Errors
    /// As [`Insertion::new`].
    pub fn stop(
        start: &RobotState<T>,
        port: Port,
        state: State<T>,
        limits: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        Ok(Self {
            start: *start,
            port,
            profile: Planned::Online(OnlineTrapezoid::stop(state, limits)?),
        })
    }

    /// What moves.
    pub fn port(&self) -> Port {
        self.port
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.profile.duration()
    }

    fn sample(&self, t: T) -> MotionSample<T> {
        let s = self.profile.sample(t);
        let mut out = held(&self.start, PlatformState::at_rest(self.start.pose));
        let zero = T::zero();
        let driven = |q: Joints<T>| {
            ModuleCommand::Joints(JointMotion {
                q: Joints::new(q.qs1, q.qs2, s.position),
                q_dot: Joints::new(zero, zero, s.velocity),
                q_ddot: Joints::new(zero, zero, s.acceleration),
            })
        };
        match self.port {
            Port::Left => out.left = driven(self.start.joints[0]),
            Port::Right => out.right = driven(self.start.joints[1]),
            Port::Endoscope => out.endoscope = s,
        }
        out
    }
}

/// Motion type 3: one tip or both from where they are to targets in the
/// fixed frame, each on a straight line, on trapezoids in arc length
/// phase-synchronised with each other; the platform still. A tip without a
/// target is held still.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Manipulation<T: Real> {
    start: RobotState<T>,
    from: [Vector3<T>; 2],
    /// Each tip's displacement, mm (zero for a tip held).
    delta: [Vector3<T>; 2],
    /// Each tip's target, mm (`from` for a tip held): where it ends, exactly.
    to: [Vector3<T>; 2],
    /// Each tip's path length, mm.
    length: [T; 2],
    /// From rest: the arc lengths, from 0 to `length`; from a moving state:
    /// `x, y, z` of both tips.
    profile: Planned<Multi<T, 2>, OnlineMulti<T, 6>>,
}

impl<T: Real> Manipulation<T> {
    /// Plans the tips from `from` (`[left, right]`, mm, fixed frame: where
    /// the start joints put them) to `to` (`None` for a tip held), each arc
    /// length within `limits` (mm/s, mm/s^2).
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for non-finite targets or invalid limits.
    pub fn new(
        start: &RobotState<T>,
        from: [Vector3<T>; 2],
        to: [Option<Vector3<T>>; 2],
        limits: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let to = [0, 1].map(|i| to[i].unwrap_or(from[i]));
        let delta = [to[0] - from[0], to[1] - from[1]];
        let length = delta.map(|d| d.norm());
        let profile = Multi::new([T::zero(); 2], length, [limits; 2], Synchronization::Phase)?;
        Ok(Self {
            start: *start,
            from,
            delta,
            to,
            length,
            profile: Planned::Rest(profile),
        })
    }

    /// Plans both tips from their moving `tips` (a manipulation cut short;
    /// `x, y, z` of the left tip, then the right) to rest at `to` (`None`:
    /// where the tip is now), time-optimal under `limits` on each
    /// coordinate: a straight line when the velocity points along the
    /// remaining displacement, each coordinate arriving together otherwise.
    ///
    /// # Errors
    /// As [`Manipulation::new`].
    pub fn from_moving(
        start: &RobotState<T>,
        tips: [State<T>; 6],
        to: [Option<Vector3<T>>; 2],
        limits: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let now = |i: usize| {
            Vector3::from_fn(|k, _| tips.get(3 * i + k).map_or(T::zero(), |s| s.position))
        };
        let goal = [0, 1].map(|i| to[i].unwrap_or_else(|| now(i)));
        let target: [T; 6] = core::array::from_fn(|k| goal[k / 3][k % 3]);
        Self::online(
            start,
            tips,
            OnlineMulti::new(tips, target, [limits; 6], Synchronization::Phase)?,
        )
    }

    /// The controlled stop of both tips moving as `tips`: every coordinate
    /// to rest together, decelerating uniformly, so that each tip keeps its
    /// direction.
    ///
    /// # Errors
    /// As [`Manipulation::new`].
    pub fn stop(
        start: &RobotState<T>,
        tips: [State<T>; 6],
        limits: Limits<T>,
    ) -> Result<Self, crate::traj::Error> {
        Self::online(start, tips, OnlineMulti::stop(tips, [limits; 6])?)
    }

    fn online(
        start: &RobotState<T>,
        tips: [State<T>; 6],
        profile: OnlineMulti<T, 6>,
    ) -> Result<Self, crate::traj::Error> {
        let end = profile.sample(profile.duration());
        let at = |s: &[State<T>; 6], i: usize| {
            Vector3::from_fn(|k, _| s.get(3 * i + k).map_or(T::zero(), |a| a.position))
        };
        let from = [at(&tips, 0), at(&tips, 1)];
        let to = [at(&end, 0), at(&end, 1)];
        let delta = [to[0] - from[0], to[1] - from[1]];
        Ok(Self {
            start: *start,
            from,
            delta,
            to,
            length: delta.map(|d| d.norm()),
            profile: Planned::Online(profile),
        })
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.profile.duration()
    }

    /// Both tips' `x, y, z` with their rates at `t` (left first).
    fn tips_at(&self, t: T) -> [State<T>; 6] {
        match &self.profile {
            Planned::Online(p) => p.sample(t),
            Planned::Rest(p) => {
                let [l, r] = p.sample(t);
                let [a, b] = [self.tip(0, &l), self.tip(1, &r)];
                core::array::from_fn(|k| {
                    let m = if k < 3 { &a } else { &b };
                    let i = k % 3;
                    State {
                        position: m.position[i],
                        velocity: m.velocity[i],
                        acceleration: m.acceleration[i],
                    }
                })
            }
        }
    }

    /// Each tip's path length, `[left, right]`, mm.
    pub fn length(&self) -> [T; 2] {
        self.length
    }

    /// Tip `i`'s position, velocity and acceleration at arc-length state
    /// `s`: `from + delta (s / length)`, on the segment whatever the
    /// rounding of `s`, and the target itself at the end (`s = length`).
    fn tip(&self, i: usize, s: &State<T>) -> TipMotion<T> {
        let (from, delta, to, length) = match (
            self.from.get(i),
            self.delta.get(i),
            self.to.get(i),
            self.length.get(i),
        ) {
            (Some(f), Some(d), Some(to), Some(l)) => (*f, *d, *to, *l),
            _ => return TipMotion::still(Vector3::zeros()),
        };
        if !(length > T::zero()) {
            return TipMotion::still(from);
        }
        let u = delta / length;
        TipMotion {
            position: if s.position >= length {
                to
            } else {
                from + delta * (s.position / length)
            },
            velocity: u * s.velocity,
            acceleration: u * s.acceleration,
        }
    }

    fn sample(&self, t: T) -> MotionSample<T> {
        let mut out = held(&self.start, PlatformState::at_rest(self.start.pose));
        match &self.profile {
            Planned::Rest(p) => {
                let [l, r] = p.sample(t);
                if self.length[0] > T::zero() {
                    out.left = ModuleCommand::Tip(self.tip(0, &l));
                }
                if self.length[1] > T::zero() {
                    out.right = ModuleCommand::Tip(self.tip(1, &r));
                }
            }
            Planned::Online(p) => {
                let s = p.sample(t);
                let tip = |i: usize| {
                    let v = |f: fn(&State<T>) -> T| {
                        Vector3::from_fn(|k, _| s.get(3 * i + k).map_or(T::zero(), f))
                    };
                    ModuleCommand::Tip(TipMotion {
                        position: v(|a| a.position),
                        velocity: v(|a| a.velocity),
                        acceleration: v(|a| a.acceleration),
                    })
                };
                out.left = tip(0);
                out.right = tip(1);
            }
        }
        out
    }
}

/// Motion type 4 as a procedure plans it: the turn, from rest
/// ([`Reorientation`]) or from a moving `(psi, theta)` (a turn cut short),
/// with the tips it holds and the endoscope's depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turning<T: Real> {
    start: Pose<T>,
    profile: Planned<Reorientation<T>, OnlineMulti<T, 2>>,
    tips: [Vector3<T>; 2],
    depth: T,
}

impl<T: Real> Turning<T> {
    /// The turn `reorientation`, holding `tips` (`[left, right]`, mm, fixed
    /// frame), the endoscope at `depth` (mm).
    pub fn new(reorientation: Reorientation<T>, tips: [Vector3<T>; 2], depth: T) -> Self {
        Self {
            start: *reorientation.start(),
            profile: Planned::Rest(reorientation),
            tips,
            depth,
        }
    }

    /// The turn from the moving `angles` (`psi`, `theta`, rad, with their
    /// rates) at `pose` to rest at `goal` (rad), time-optimal under
    /// `limits`, as the online controller replans (see
    /// [`OnlineController`](crate::OnlineController)).
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for a non-finite state or goal, or invalid
    /// limits.
    pub fn from_moving(
        pose: Pose<T>,
        angles: [State<T>; 2],
        goal: [T; 2],
        limits: Limits<T>,
        tips: [Vector3<T>; 2],
        depth: T,
    ) -> Result<Self, crate::traj::Error> {
        let profile = OnlineMulti::new(angles, goal, [limits; 2], Synchronization::Phase)?;
        Ok(Self {
            start: pose,
            profile: Planned::Online(profile),
            tips,
            depth,
        })
    }

    /// The controlled stop of the turn moving as `angles`.
    ///
    /// # Errors
    /// As [`Turning::from_moving`].
    pub fn stop(
        pose: Pose<T>,
        angles: [State<T>; 2],
        limits: Limits<T>,
        tips: [Vector3<T>; 2],
        depth: T,
    ) -> Result<Self, crate::traj::Error> {
        Ok(Self {
            start: pose,
            profile: Planned::Online(OnlineMulti::stop(angles, [limits; 2])?),
            tips,
            depth,
        })
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        match &self.profile {
            Planned::Rest(r) => r.duration(),
            Planned::Online(p) => p.duration(),
        }
    }

    fn angles(&self, t: T) -> [State<T>; 2] {
        match &self.profile {
            Planned::Rest(r) => r.profile().sample(t),
            Planned::Online(p) => p.sample(t),
        }
    }

    fn sample(&self, t: T) -> MotionSample<T> {
        let [left, right] = self.tips;
        MotionSample {
            platform: turned(&self.start, self.angles(t)),
            left: ModuleCommand::still(left),
            right: ModuleCommand::still(right),
            endoscope: State::rest(self.depth),
        }
    }
}

/// One planned motion of any type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion<T: Real> {
    /// Type 1.
    Position(Positioning<T>),
    /// Type 2.
    Insert(Insertion<T>),
    /// Type 3.
    Manipulate(Manipulation<T>),
    /// Type 4.
    Reorient(Turning<T>),
}

impl<T: Real> Motion<T> {
    /// Its type.
    pub fn motion_type(&self) -> MotionType {
        match self {
            Motion::Position(_) => MotionType::Position,
            Motion::Insert(_) => MotionType::Insert,
            Motion::Manipulate(_) => MotionType::Manipulate,
            Motion::Reorient(_) => MotionType::Reorient,
        }
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        match self {
            Motion::Position(m) => m.duration(),
            Motion::Insert(m) => m.duration(),
            Motion::Manipulate(m) => m.duration(),
            Motion::Reorient(m) => m.duration(),
        }
    }

    /// The motion at `t` (s from its start): at rest at its start for
    /// `t <= 0` and at its end for `t >= duration`.
    pub fn sample(&self, t: T) -> MotionSample<T> {
        match self {
            Motion::Position(m) => m.sample(t),
            Motion::Insert(m) => m.sample(t),
            Motion::Manipulate(m) => m.sample(t),
            Motion::Reorient(m) => m.sample(t),
        }
    }

    /// The motion's own coordinates and their rates at `t`: what the next
    /// motion starts from when this one is cut short at `t`.
    pub fn moving_at(&self, t: T) -> Moving<T> {
        match self {
            Motion::Position(m) => Moving::Pose(m.profile.sample(t)),
            Motion::Insert(m) => Moving::Depth(m.port, m.profile.sample(t)),
            Motion::Manipulate(m) => Moving::Tips(m.tips_at(t)),
            Motion::Reorient(m) => Moving::Angles(m.angles(t)),
        }
    }
}

impl<T: Real> crate::traj::Motion<T> for Motion<T> {
    type Output = MotionSample<T>;

    fn duration(&self) -> T {
        Motion::duration(self)
    }

    fn sample(&self, t: T) -> MotionSample<T> {
        Motion::sample(self, t)
    }
}
