//! The paper's four motion types timed: each a [`Geometry`] (what moves,
//! written once in [`crate::geometry`]) and a law for its own coordinates,
//! sampled into what [`Controller::step_commanded`] takes.
//!
//! | type | [`Motion`] | what moves | the law from rest |
//! |---|---|---|---|
//! | 1 | [`Positioning`] | module 1 takes the platform along a straight line in pose space; the instrument joints are held, so the tips ride along | `(x, y, z, psi, theta, phi)` on one phase-synchronised trapezoid |
//! | 2 | [`Insertion`] | one instrument's `qs3`, or the endoscope's depth: the tip moves on the tool's axis through its port | a trapezoid in `qs3` (or the depth) |
//! | 3 | [`Manipulation`] | one tip, or both, on a straight line in the fixed frame, the platform still; the joints from the closed-form IK at every sample | a trapezoid in arc length (both tips phase-synchronised) |
//! | 4 | [`Turning`] | the platform turns in `(psi, theta)`; both tips held | as [`Reorientation`] |
//!
//! Each motion starts from a [`RobotState`] (the platform's pose, both
//! modules' joints, the endoscope's depth): the state where the previous one
//! ended. Besides the law from rest in the table, a motion may be planned
//! from a moving state (`from_moving`, `stop`: each coordinate's online
//! profile) or timed by the jerk-limited double S along its line
//! ([`Motion::jerk_limited`]). [`Motion::sample`] gives, at any time, a
//! [`MotionSample`]: the law's coordinates through [`Geometry::at`], the
//! platform's state and each module's command (its tip, or its joints) with
//! rates and accelerations in closed form. The assembly modes are the
//! controller's, kept from motion to motion.
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
use crate::geometry::Geometry;
pub use crate::geometry::{MotionSample, MotionType, Moving, Port, RobotState};
use crate::kin::nalgebra::Vector3;
use crate::kin::{Pose, TipMotion};
use crate::reorientation::Reorientation;
use crate::traj::{
    DoubleS, JerkLimits, Limits, Motion as Profile, Multi, OnlineMulti, OnlineTrapezoid, State,
    Synchronization, Trapezoid,
};

/// How a motion's own coordinates move in time: a profile planned from rest
/// (`R`), an online profile from a moving state (`O`: after a motion cut
/// short, the next one starts where it was, at its speed), or a law `s(t)`
/// along the geometry's straight line (the jerk-limited double S).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Law<T, R, O> {
    Rest(R),
    Online(O),
    Path(DoubleS<T>),
}

impl<T: Real, R: Profile<T>, O: Profile<T>> Law<T, R, O> {
    fn duration(&self) -> T {
        match self {
            Law::Rest(p) => p.duration(),
            Law::Online(p) => p.duration(),
            Law::Path(p) => p.duration(),
        }
    }
}

/// The coordinates of `law` at `t`: `rest` or `online` read a profile's
/// sample, a path law is the geometry's straight line at `s(t)`.
fn coordinates<T: Real, R: Profile<T>, O: Profile<T>>(
    law: &Law<T, R, O>,
    geometry: &Geometry<T>,
    t: T,
    rest: impl FnOnce(R::Output) -> Moving<T>,
    online: impl FnOnce(O::Output) -> Moving<T>,
) -> Moving<T> {
    match law {
        Law::Rest(p) => rest(p.sample(t)),
        Law::Online(p) => online(p.sample(t)),
        Law::Path(p) => {
            let s = p.sample(t);
            geometry.along(s.position, s.velocity, s.acceleration)
        }
    }
}

/// Motion type 1: the platform from its pose to `goal` on a straight line in
/// pose space, the six coordinates on one phase-synchronised trapezoid; the
/// instrument joints and the endoscope's depth held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Positioning<T: Real> {
    geometry: Geometry<T>,
    law: Law<T, Multi<T, 6>, OnlineMulti<T, 6>>,
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
            geometry: Geometry::positioning(start, goal),
            law: Law::Rest(profile),
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
            geometry: Geometry::positioning(start, goal),
            law: Law::Online(profile),
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
        let profile = OnlineMulti::stop(pose, limits)?;
        let end = Pose::from_array(profile.sample(profile.duration()).map(|a| a.position));
        Ok(Self {
            geometry: Geometry::positioning(start, end),
            law: Law::Online(profile),
        })
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.law.duration()
    }

    fn moving(&self, t: T) -> Moving<T> {
        coordinates(&self.law, &self.geometry, t, Moving::Pose, Moving::Pose)
    }
}

/// Motion type 2: one instrument's `qs3`, or the endoscope's depth, by a
/// signed `depth` (mm, positive inwards) on a trapezoid; the platform and
/// every other joint still, so that the tip moves on a straight line through
/// its port.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Insertion<T: Real> {
    geometry: Geometry<T>,
    port: Port,
    law: Law<T, Trapezoid<T>, OnlineTrapezoid<T>>,
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
            geometry: Geometry::insertion(start, port, depth),
            port,
            law: Law::Rest(profile),
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
            geometry: Geometry::insertion(start, port, depth),
            port,
            law: Law::Online(profile),
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
        let profile = OnlineTrapezoid::stop(state, limits)?;
        let by = profile.sample(profile.duration()).position - state.position;
        Ok(Self {
            geometry: Geometry::insertion(start, port, by),
            port,
            law: Law::Online(profile),
        })
    }

    /// What moves.
    pub fn port(&self) -> Port {
        self.port
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.law.duration()
    }

    fn moving(&self, t: T) -> Moving<T> {
        let port = self.port;
        coordinates(
            &self.law,
            &self.geometry,
            t,
            |s| Moving::Depth(port, s),
            |s| Moving::Depth(port, s),
        )
    }
}

/// Motion type 3: one tip or both from where they are to targets in the
/// fixed frame, each on a straight line, on trapezoids in arc length
/// phase-synchronised with each other; the platform still. A tip without a
/// target is held still.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Manipulation<T: Real> {
    /// Where the tips start and end (exactly), and which are driven.
    geometry: Geometry<T>,
    /// Each tip's displacement, mm (zero for a tip held), kept for the
    /// samples.
    delta: [Vector3<T>; 2],
    /// Each tip's path length, mm, kept for the samples.
    length: [T; 2],
    /// From rest: the arc lengths, from 0 to `length`; from a moving state:
    /// `x, y, z` of both tips.
    law: Law<T, Multi<T, 2>, OnlineMulti<T, 6>>,
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
        let geometry = Geometry::manipulation(start, from, to);
        let (_, length) = Self::lines(&geometry);
        let profile = Multi::new([T::zero(); 2], length, [limits; 2], Synchronization::Phase)?;
        Ok(Self::on(geometry, Law::Rest(profile)))
    }

    /// Each tip's displacement and path length along `geometry`.
    fn lines(geometry: &Geometry<T>) -> ([Vector3<T>; 2], [T; 2]) {
        let (from, to) = geometry.tips_line();
        let delta = [to[0] - from[0], to[1] - from[1]];
        (delta, delta.map(|d| d.norm()))
    }

    /// The tips along `geometry`, timed by `law`.
    fn on(geometry: Geometry<T>, law: Law<T, Multi<T, 2>, OnlineMulti<T, 6>>) -> Self {
        let (delta, length) = Self::lines(&geometry);
        Self {
            geometry,
            delta,
            length,
            law,
        }
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

    /// From a moving state both tips are commanded by position: a tip may
    /// move on the way even where it ends where it started.
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
        let geometry = Geometry::manipulation_driven(start, from, to, [true; 2]);
        Ok(Self::on(geometry, Law::Online(profile)))
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.law.duration()
    }

    /// Both tips' `x, y, z` with their rates at `t` (left first).
    fn moving(&self, t: T) -> Moving<T> {
        let rest = |[l, r]: [State<T>; 2]| {
            let [a, b] = [self.tip(0, &l), self.tip(1, &r)];
            Moving::Tips(core::array::from_fn(|k| {
                let m = if k < 3 { &a } else { &b };
                let i = k % 3;
                State {
                    position: m.position[i],
                    velocity: m.velocity[i],
                    acceleration: m.acceleration[i],
                }
            }))
        };
        coordinates(&self.law, &self.geometry, t, rest, Moving::Tips)
    }

    /// Each tip's path length, `[left, right]`, mm.
    pub fn length(&self) -> [T; 2] {
        self.length
    }

    /// Tip `i`'s position, velocity and acceleration at arc-length state
    /// `s`: `from + delta (s / length)`, on the segment whatever the
    /// rounding of `s`, and the target itself at the end (`s = length`).
    fn tip(&self, i: usize, s: &State<T>) -> TipMotion<T> {
        let (from, to) = self.geometry.tips_line();
        let (from, delta, to, length) = match (
            from.get(i),
            self.delta.get(i),
            to.get(i),
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
}

/// Motion type 4 as a procedure plans it: the turn, from rest
/// ([`Reorientation`]) or from a moving `(psi, theta)` (a turn cut short),
/// with the tips it holds; the endoscope's depth is the start's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turning<T: Real> {
    geometry: Geometry<T>,
    law: Law<T, Reorientation<T>, OnlineMulti<T, 2>>,
}

impl<T: Real> Turning<T> {
    /// The turn of `start.pose` to `goal` (`[psi, theta]`, rad), each angle
    /// within `limits` (rad/s, rad/s^2), the two timed together as `sync`
    /// says, holding `tips` (`[left, right]`, mm, fixed frame).
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for non-finite angles or invalid limits.
    pub fn new(
        start: &RobotState<T>,
        goal: [T; 2],
        limits: [Limits<T>; 2],
        sync: Synchronization,
        tips: [Vector3<T>; 2],
    ) -> Result<Self, crate::traj::Error> {
        let turn = Reorientation::new(start.pose, goal, limits, sync)?;
        Ok(Self {
            geometry: Geometry::turning(start, goal, tips),
            law: Law::Rest(turn),
        })
    }

    /// The turn from the moving `angles` (`psi`, `theta`, rad, with their
    /// rates) at `start` to rest at `goal` (rad), time-optimal under
    /// `limits`, as the online controller replans (see
    /// [`OnlineController`](crate::OnlineController)).
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for a non-finite state or goal, or invalid
    /// limits.
    pub fn from_moving(
        start: &RobotState<T>,
        angles: [State<T>; 2],
        goal: [T; 2],
        limits: Limits<T>,
        tips: [Vector3<T>; 2],
    ) -> Result<Self, crate::traj::Error> {
        let profile = OnlineMulti::new(angles, goal, [limits; 2], Synchronization::Phase)?;
        Ok(Self {
            geometry: Geometry::turning(start, goal, tips),
            law: Law::Online(profile),
        })
    }

    /// The controlled stop of the turn moving as `angles`.
    ///
    /// # Errors
    /// As [`Turning::from_moving`].
    pub fn stop(
        start: &RobotState<T>,
        angles: [State<T>; 2],
        limits: Limits<T>,
        tips: [Vector3<T>; 2],
    ) -> Result<Self, crate::traj::Error> {
        let profile = OnlineMulti::stop(angles, [limits; 2])?;
        let goal = profile.sample(profile.duration()).map(|a| a.position);
        Ok(Self {
            geometry: Geometry::turning(start, goal, tips),
            law: Law::Online(profile),
        })
    }

    /// The duration, s.
    pub fn duration(&self) -> T {
        self.law.duration()
    }

    fn moving(&self, t: T) -> Moving<T> {
        let rest = |s: crate::kin::PlatformState<T>| {
            Moving::Angles([
                State {
                    position: s.pose.psi,
                    velocity: s.velocity.psi,
                    acceleration: s.acceleration.psi,
                },
                State {
                    position: s.pose.theta,
                    velocity: s.velocity.theta,
                    acceleration: s.acceleration.theta,
                },
            ])
        };
        coordinates(&self.law, &self.geometry, t, rest, Moving::Angles)
    }
}

/// One planned motion of any type: its [`Geometry`] and how its coordinates
/// move in time.
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
    /// The motion along `geometry`'s straight line timed by the
    /// jerk-limited double S from rest to rest: `s(t)` from 0 to 1 within
    /// the limits of `s` that keep every coordinate within its own
    /// ([`Geometry::path_limits`]: `linear` for lengths, mm/s, mm/s^2,
    /// mm/s^3; `angular` for angles, rad/s, rad/s^2, rad/s^3). Velocity and
    /// acceleration are continuous, the jerk bounded.
    ///
    /// ```
    /// use parasils::geometry::{Geometry, Port, RobotState};
    /// use parasils::kin::{Joints, Pose};
    /// use parasils::motions::Motion;
    /// use parasils::traj::JerkLimits;
    ///
    /// let start = RobotState {
    ///     pose: Pose::<f64>::paper_start(),
    ///     joints: [Joints::from_deg_mm(3.0, -10.0, 120.0), Joints::from_deg_mm(-3.0, 10.0, 120.0)],
    ///     endoscope_depth: 0.0,
    /// };
    /// // 30 mm at most 20 mm/s, 20 mm/s^2, 40 mm/s^3.
    /// let linear = JerkLimits::new(20.0, 20.0, 40.0);
    /// let angular = JerkLimits::new(0.2, 0.1, 0.2);
    /// let m = Motion::jerk_limited(Geometry::insertion(&start, Port::Left, 30.0), linear, angular)?;
    /// // Hand-derived: v_max is reached (a^2/j = 10 mm/s < 20), t_j = a/j = 0.5 s,
    /// // t_a = v/a + t_j = 1.5 s, cruise (30 - 20 * 1.5) / 20 = 0 s: 3 s in all.
    /// assert!((m.duration() - 3.0).abs() < 1e-12);
    /// let end = m.moving_at(m.duration());
    /// assert!(end.at_rest());
    /// # Ok::<(), parasils::traj::Error>(())
    /// ```
    ///
    /// # Errors
    /// A [`parasils_traj::Error`] for limits that are not positive and
    /// finite, or a path that cannot be timed.
    pub fn jerk_limited(
        geometry: Geometry<T>,
        linear: JerkLimits<T>,
        angular: JerkLimits<T>,
    ) -> Result<Self, crate::traj::Error> {
        let zero = T::zero();
        // The limits as given, checked by the profile's own validation.
        DoubleS::new(zero, zero, linear)?;
        DoubleS::new(zero, zero, angular)?;
        let path = match geometry.path_limits(linear, angular) {
            Some(limits) => DoubleS::new(zero, T::one(), limits)?,
            None => DoubleS::new(zero, zero, linear)?,
        };
        Ok(match geometry.motion_type() {
            MotionType::Position => Motion::Position(Positioning {
                geometry,
                law: Law::Path(path),
            }),
            MotionType::Insert => Motion::Insert(Insertion {
                geometry,
                port: geometry.port().unwrap_or(Port::Endoscope),
                law: Law::Path(path),
            }),
            MotionType::Manipulate => {
                Motion::Manipulate(Manipulation::on(geometry, Law::Path(path)))
            }
            MotionType::Reorient => Motion::Reorient(Turning {
                geometry,
                law: Law::Path(path),
            }),
        })
    }

    /// Its type.
    pub fn motion_type(&self) -> MotionType {
        self.geometry().motion_type()
    }

    /// Its geometry: the start, the target, the map from its coordinates
    /// to the robot.
    pub fn geometry(&self) -> &Geometry<T> {
        match self {
            Motion::Position(m) => &m.geometry,
            Motion::Insert(m) => &m.geometry,
            Motion::Manipulate(m) => &m.geometry,
            Motion::Reorient(m) => &m.geometry,
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
    /// `t <= 0` and at its end for `t >= duration`. Its coordinates at `t`
    /// through its geometry's one map ([`Geometry::at`]).
    pub fn sample(&self, t: T) -> MotionSample<T> {
        self.geometry().at(&self.moving_at(t))
    }

    /// The motion's own coordinates and their rates at `t`: what the next
    /// motion starts from when this one is cut short at `t`.
    pub fn moving_at(&self, t: T) -> Moving<T> {
        match self {
            Motion::Position(m) => m.moving(t),
            Motion::Insert(m) => m.moving(t),
            Motion::Manipulate(m) => m.moving(t),
            Motion::Reorient(m) => m.moving(t),
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
