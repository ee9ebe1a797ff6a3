//! Motion type 4 as a geometric path, for time-optimal timing: `s in [0, 1]`
//! turns the platform from its start pose along the straight line
//! `(psi, theta) = (psi_0 + s dpsi, theta_0 + s dtheta)`, `P` and `phi`
//! still, both tips held.
//!
//! Along the path, each actuator is a function `q(s)`. Its derivatives come
//! from the controller's own cycle ([`Controller::step_commanded`], the same
//! call a control loop makes, with a fresh margin tracker): the platform
//! state at `s` with `s_dot = 1`, `s_ddot = 0` (Euler rates
//! `(dpsi, dtheta)`, no Euler acceleration) gives actuator velocities
//! `q'(s)` and accelerations `q''(s)`, since `q_dot = q' s_dot` and
//! `q_ddot = q' s_ddot + q'' s_dot^2`. No finite difference, no spline, and
//! no second copy of the cycle: a point of the path is what the controller
//! accepts (strokes, joint limits, singularity thresholds, the parallel
//! margin included).
//!
//! The path has [`PATH_ROWS`] rows for the solver
//! ([`parasils_traj::optimal`]): the twelve actuators in the order of
//! [`Actuator::ALL`](crate::kin::Actuator::ALL), then `psi` and `theta`
//! themselves (rad), so that the paper's angular limits can bind too when
//! asked ([`row_limits`]).
//!
//! ```
//! use parasils::kin::{ActuatorLimits, Controller, Pose, TipTargets};
//! use parasils::path::{ReorientationPath, row_limits};
//! use parasils::traj::optimal::{self, Knot};
//!
//! let deg = core::f64::consts::PI / 180.0;
//! let path = ReorientationPath::new(
//!     &Controller::paper(),
//!     Pose::paper_start(),
//!     [15.0 * deg, 25.0 * deg],
//!     TipTargets::paper(),
//! );
//! let limits = row_limits(&ActuatorLimits::assumed(), None);
//! let mut knots = vec![Knot::default(); 1000];
//! let (schedule, _) = optimal::plan(&path, &limits, &mut knots, 10)?;
//! // Faster than the paper's 4.5 s trapezoid under the assumed limits.
//! assert!(schedule.duration() < 4.5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::Real;
use crate::kin::nalgebra::Vector3;
use crate::kin::{
    ACTUATOR_COUNT, ActuatorLimits, ControlStep, Controller, JointMotion, Joints, MarginTracker,
    ModuleCommand, PlatformState, Pose, PoseRate, TipMotion, TipTargets, step_positions,
    step_rates,
};
use crate::motions::{MotionSample, MotionType, Port, RobotState};
use crate::reorientation::turned;
use crate::traj::optimal::{Derivatives, Path, RowLimits};
use crate::traj::{Limits, State};

/// The rows of a reorientation path: twelve actuators, then `psi`, `theta`.
pub const PATH_ROWS: usize = ACTUATOR_COUNT + 2;

/// The actuators along the path at one `s`: positions, and their first and
/// second derivatives with respect to `s`, in the order of
/// [`Actuator::ALL`](crate::kin::Actuator::ALL) (mm and rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint<T> {
    /// `q(s)`.
    pub q: [T; ACTUATOR_COUNT],
    /// `q'(s)`.
    pub q_s: [T; ACTUATOR_COUNT],
    /// `q''(s)`.
    pub q_ss: [T; ACTUATOR_COUNT],
}

impl<T: Real> PathPoint<T> {
    /// The actuators of the controller's step at `s` moving with `s_dot = 1`,
    /// `s_ddot = 0`: their rates are `q'(s)`, their accelerations `q''(s)`.
    fn of(step: &ControlStep<T>) -> Self {
        let (q_s, q_ss) = step_rates(step);
        Self {
            q: step_positions(step),
            q_s,
            q_ss,
        }
    }

    /// As the solver takes them: the twelve actuators' `q'`, `q''`, and the
    /// motion's own two rows' `q'` (linear in `s`: no `q''`).
    fn derivatives(&self, own: [T; 2]) -> Derivatives<T, PATH_ROWS> {
        let mut first = [T::zero(); PATH_ROWS];
        let mut second = [T::zero(); PATH_ROWS];
        first[..ACTUATOR_COUNT].copy_from_slice(&self.q_s);
        second[..ACTUATOR_COUNT].copy_from_slice(&self.q_ss);
        let [.., a, b] = &mut first;
        (*a, *b) = (own[0], own[1]);
        Derivatives { first, second }
    }
}

/// Motion type 4's straight turn as a path `s in [0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReorientationPath<T: Real> {
    controller: Controller<T>,
    start: Pose<T>,
    increment: [T; 2],
    tips: TipTargets<T>,
}

impl<T: Real> ReorientationPath<T> {
    /// The turn by `increment = [dpsi, dtheta]` (rad) from `start`, tips held
    /// at `tips`, on `controller`'s robot and assembly modes.
    pub fn new(
        controller: &Controller<T>,
        start: Pose<T>,
        increment: [T; 2],
        tips: TipTargets<T>,
    ) -> Self {
        Self {
            controller: *controller,
            start,
            increment,
            tips,
        }
    }

    /// The start pose.
    pub fn start(&self) -> &Pose<T> {
        &self.start
    }

    /// `[dpsi, dtheta]`, rad.
    pub fn increment(&self) -> [T; 2] {
        self.increment
    }

    /// The tips held.
    pub fn tips(&self) -> &TipTargets<T> {
        &self.tips
    }

    /// The platform at `s` moving with path speed `s_dot` (1/s) and path
    /// acceleration `s_ddot` (1/s^2): what the controller steps through.
    pub fn state(&self, s: T, s_dot: T, s_ddot: T) -> PlatformState<T> {
        let [dpsi, dtheta] = self.increment;
        let mut pose = self.start;
        pose.psi = self.start.psi + s * dpsi;
        pose.theta = self.start.theta + s * dtheta;
        PlatformState::reorientation(
            pose,
            [dpsi * s_dot, dtheta * s_dot],
            [dpsi * s_ddot, dtheta * s_ddot],
        )
    }

    /// The actuators and their derivatives in `s` at `s`.
    ///
    /// # Errors
    /// The kinematics' error where the path leaves the robot's workspace: a
    /// leg out of reach, a serial singularity, a stroke or joint limit, a tip
    /// out of reach, an instrument singularity, a non-finite number.
    pub fn point(&self, s: T) -> Result<PathPoint<T>, crate::kin::Error> {
        let state = self.state(s, T::one(), T::zero());
        let step = self
            .controller
            .step(&state, &self.tips, &mut MarginTracker::new())?;
        Ok(PathPoint::of(&step))
    }
}

impl<T: Real> Path<T, PATH_ROWS> for ReorientationPath<T> {
    type Error = crate::kin::Error;

    fn derivatives(&self, s: T) -> Result<Derivatives<T, PATH_ROWS>, crate::kin::Error> {
        Ok(self.point(s)?.derivatives(self.increment))
    }
}

/// The solver's limits for a reorientation path: the actuators' (mm, rad
/// per s and s^2), and, when `angular` is given, `psi`'s and `theta`'s
/// (`[psi, theta]`, rad/s and rad/s^2, each axis on its own, as the
/// trapezoid reads them); without it the angles are not limited.
pub fn row_limits<T: Real>(
    actuators: &ActuatorLimits<T>,
    angular: Option<[Limits<T>; 2]>,
) -> [RowLimits<T>; PATH_ROWS] {
    let mut rows = [RowLimits::unlimited(); PATH_ROWS];
    for (row, (&v, &a)) in rows
        .iter_mut()
        .zip(actuators.velocity.iter().zip(&actuators.acceleration))
    {
        *row = RowLimits::new(v, a);
    }
    if let Some([psi, theta]) = angular {
        let [.., r_psi, r_theta] = &mut rows;
        *r_psi = RowLimits::new(psi.v_max, psi.a_max);
        *r_theta = RowLimits::new(theta.v_max, theta.a_max);
    }
    rows
}

/// What a [`MotionPath`] moves: each type by its target, so that `s = 1`
/// is the target itself, not a sum that rounding could leave short of it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Geometry<T: Real> {
    /// Type 1: the pose to `(x, y, z, psi, theta, phi)` (mm, rad).
    Position([T; 6]),
    /// Type 2: `qs3` of a module, or the endoscope's depth, by `depth` mm.
    Insert(Port, T),
    /// Type 3: the tips from `from` to `to` (mm, fixed frame).
    Manipulate {
        from: [Vector3<T>; 2],
        to: [Vector3<T>; 2],
    },
    /// Type 4: `(psi, theta)` to `goal` (rad), the tips held.
    Reorient { goal: [T; 2], tips: [Vector3<T>; 2] },
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

/// The displacement of a [`MotionPath`]'s own coordinates over the path.
enum Delta<T: Real> {
    Position([T; 6]),
    Insert(T),
    Manipulate([Vector3<T>; 2]),
    Reorient([T; 2]),
}

/// Any of the paper's four motion types from rest to rest as a geometric
/// path `s in [0, 1]`, for time-optimal timing: the same straight line its
/// [`Motion`](crate::motions::Motion) follows, with the time law left open.
///
/// Rows 0 to 11 are the twelve actuators, as in [`ReorientationPath`]; rows
/// 12 and 13 are the motion's own coordinates, so that the limits a
/// procedure states for the motion can bind as well:
///
/// | type | row 12 | row 13 |
/// |---|---|---|
/// | 1 | `max(\|dx\|, \|dy\|, \|dz\|)`, mm | `max(\|dpsi\|, \|dtheta\|, \|dphi\|)`, rad |
/// | 2 | `qs3` or the endoscope's depth, mm | none (zero) |
/// | 3 | the left tip's arc length, mm | the right tip's, mm |
/// | 4 | `psi`, rad | `theta`, rad |
///
/// Each is linear in `s`, so a linear and an angular limit bind type 1 as
/// its trapezoid reads them: each axis on its own, the largest displacement
/// first.
///
/// ```
/// use parasils::kin::{ActuatorLimits, Controller, Joints, Pose};
/// use parasils::motions::{Port, RobotState};
/// use parasils::path::{MotionPath, row_limits};
/// use parasils::traj::optimal::{self, Knot};
///
/// let controller = Controller::<f64>::paper();
/// let start = RobotState {
///     pose: Pose::paper_start(),
///     joints: [Joints::from_deg_mm(3.0, -10.0, 120.0), Joints::from_deg_mm(-3.0, 10.0, 120.0)],
///     endoscope_depth: 0.0,
/// };
/// // The left instrument 30 mm deeper: only its qs3 moves, so only qs3's
/// // limits (60 mm/s, 60 mm/s^2 assumed) bind: sqrt(4 d / a) = sqrt(2) s.
/// let path = MotionPath::insertion(&controller, &start, Port::Left, 30.0);
/// let limits = row_limits(&ActuatorLimits::assumed(), None);
/// let mut knots = vec![Knot::default(); 201];
/// let (schedule, _) = optimal::plan(&path, &limits, &mut knots, 10)?;
/// assert!((schedule.duration() - 2f64.sqrt()).abs() < 1e-9, "{}", schedule.duration());
/// let end = path.sample(1.0, 0.0, 0.0);
/// assert_eq!(end.left, parasils::kin::ModuleCommand::Joints(parasils::kin::JointMotion::held(
///     Joints::from_deg_mm(3.0, -10.0, 150.0),
/// )));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionPath<T: Real> {
    controller: Controller<T>,
    start: RobotState<T>,
    geometry: Geometry<T>,
}

impl<T: Real> MotionPath<T> {
    fn on(controller: &Controller<T>, start: &RobotState<T>, geometry: Geometry<T>) -> Self {
        Self {
            controller: *controller,
            start: *start,
            geometry,
        }
    }

    /// Type 1: the platform from `start.pose` to `goal` on the straight
    /// line in pose space, the instrument joints and the endoscope held.
    pub fn positioning(controller: &Controller<T>, start: &RobotState<T>, goal: Pose<T>) -> Self {
        Self::on(controller, start, Geometry::Position(goal.to_array()))
    }

    /// Type 2: `port`'s `qs3` (or the endoscope's depth) by `depth` mm,
    /// everything else held.
    pub fn insertion(
        controller: &Controller<T>,
        start: &RobotState<T>,
        port: Port,
        depth: T,
    ) -> Self {
        Self::on(controller, start, Geometry::Insert(port, depth))
    }

    /// Type 3: the tips from `from` (`[left, right]`, mm, fixed frame:
    /// where the start joints put them) to `to` (`None`: held) on straight
    /// lines, the platform still; both arrive together.
    pub fn manipulation(
        controller: &Controller<T>,
        start: &RobotState<T>,
        from: [Vector3<T>; 2],
        to: [Option<Vector3<T>>; 2],
    ) -> Self {
        let to = [0, 1].map(|i| to[i].unwrap_or(from[i]));
        Self::on(controller, start, Geometry::Manipulate { from, to })
    }

    /// Type 4: `(psi, theta)` from `start.pose`'s to `goal` (rad), the tips
    /// held at `tips` (`[left, right]`, mm, fixed frame).
    pub fn turning(
        controller: &Controller<T>,
        start: &RobotState<T>,
        goal: [T; 2],
        tips: [Vector3<T>; 2],
    ) -> Self {
        Self::on(controller, start, Geometry::Reorient { goal, tips })
    }

    /// The displacement of the motion's coordinates along the whole path
    /// (`d q / d s` of each): the pose's six, the inserted depth, each tip's
    /// `x, y, z`, `(psi, theta)`.
    fn delta(&self) -> Delta<T> {
        let p = self.start.pose.to_array();
        match &self.geometry {
            Geometry::Position(goal) => Delta::Position(core::array::from_fn(|k| goal[k] - p[k])),
            Geometry::Insert(_, d) => Delta::Insert(*d),
            Geometry::Manipulate { from, to } => {
                Delta::Manipulate([to[0] - from[0], to[1] - from[1]])
            }
            Geometry::Reorient { goal, .. } => Delta::Reorient([
                goal[0] - self.start.pose.psi,
                goal[1] - self.start.pose.theta,
            ]),
        }
    }

    /// The motion's type.
    pub fn motion_type(&self) -> MotionType {
        match self.geometry {
            Geometry::Position(_) => MotionType::Position,
            Geometry::Insert(..) => MotionType::Insert,
            Geometry::Manipulate { .. } => MotionType::Manipulate,
            Geometry::Reorient { .. } => MotionType::Reorient,
        }
    }

    /// The state it starts from.
    pub fn start(&self) -> &RobotState<T> {
        &self.start
    }

    /// Whether nothing moves along it (a displacement of zero): it takes no
    /// time.
    pub fn is_still(&self) -> bool {
        let zero = T::zero();
        match self.delta() {
            Delta::Position(d) => d.iter().all(|&x| x == zero),
            Delta::Insert(d) => d == zero,
            Delta::Manipulate(delta) => delta.iter().all(|d| d.iter().all(|&x| x == zero)),
            Delta::Reorient(increment) => increment.iter().all(|&x| x == zero),
        }
    }

    /// The motion's own coordinates' derivatives in `s` (rows 12 and 13,
    /// see [`MotionPath`]).
    pub fn own_rates(&self) -> [T; 2] {
        let zero = T::zero();
        let largest = |d: &[T]| {
            d.iter().fold(zero, |m, &x| {
                let x = if x < zero { -x } else { x };
                if x > m { x } else { m }
            })
        };
        match self.delta() {
            Delta::Position(d) => [largest(&d[..3]), largest(&d[3..])],
            Delta::Insert(d) => [d, zero],
            Delta::Manipulate(delta) => delta.map(|d| d.norm()),
            Delta::Reorient(increment) => increment,
        }
    }

    /// The robot at `s` moving with path speed `s_dot` (1/s) and path
    /// acceleration `s_ddot` (1/s^2): what
    /// [`Controller::step_commanded`] takes, as
    /// [`Motion::sample`](crate::motions::Motion::sample) gives it.
    pub fn sample(&self, s: T, s_dot: T, s_ddot: T) -> MotionSample<T> {
        let start = &self.start;
        let [l, r] = start.joints;
        let mut out = MotionSample {
            platform: PlatformState::at_rest(start.pose),
            left: ModuleCommand::Joints(JointMotion::held(l)),
            right: ModuleCommand::Joints(JointMotion::held(r)),
            endoscope: State::rest(start.endoscope_depth),
        };
        let along = |from: T, to: T| {
            let by = to - from;
            State {
                position: lerp(from, to, s),
                velocity: s_dot * by,
                acceleration: s_ddot * by,
            }
        };
        match &self.geometry {
            Geometry::Position(goal) => {
                let p = start.pose.to_array();
                let c: [State<T>; 6] = core::array::from_fn(|k| along(p[k], goal[k]));
                out.platform = PlatformState {
                    pose: Pose::from_array(c.map(|a| a.position)),
                    velocity: PoseRate::new(
                        c[0].velocity,
                        c[1].velocity,
                        c[2].velocity,
                        c[3].velocity,
                        c[4].velocity,
                        c[5].velocity,
                    ),
                    acceleration: PoseRate::new(
                        c[0].acceleration,
                        c[1].acceleration,
                        c[2].acceleration,
                        c[3].acceleration,
                        c[4].acceleration,
                        c[5].acceleration,
                    ),
                };
            }
            Geometry::Insert(port, depth) => {
                let driven = |q: Joints<T>| {
                    let a = along(q.qs3, q.qs3 + *depth);
                    let zero = T::zero();
                    ModuleCommand::Joints(JointMotion {
                        q: Joints::new(q.qs1, q.qs2, a.position),
                        q_dot: Joints::new(zero, zero, a.velocity),
                        q_ddot: Joints::new(zero, zero, a.acceleration),
                    })
                };
                match port {
                    Port::Left => out.left = driven(l),
                    Port::Right => out.right = driven(r),
                    Port::Endoscope => {
                        out.endoscope =
                            along(start.endoscope_depth, start.endoscope_depth + *depth);
                    }
                }
            }
            Geometry::Manipulate { from, to } => {
                let tip = |i: usize| {
                    let delta = to[i] - from[i];
                    ModuleCommand::Tip(TipMotion {
                        position: Vector3::from_fn(|k, _| lerp(from[i][k], to[i][k], s)),
                        velocity: delta * s_dot,
                        acceleration: delta * s_ddot,
                    })
                };
                if from[0] != to[0] {
                    out.left = tip(0);
                }
                if from[1] != to[1] {
                    out.right = tip(1);
                }
            }
            Geometry::Reorient { goal, tips } => {
                let p = &start.pose;
                out.platform = turned(p, [along(p.psi, goal[0]), along(p.theta, goal[1])]);
                out.left = ModuleCommand::still(tips[0]);
                out.right = ModuleCommand::still(tips[1]);
            }
        }
        out
    }
}

impl<T: Real> Path<T, PATH_ROWS> for MotionPath<T> {
    type Error = crate::kin::Error;

    /// The actuators' `q'(s)` and `q''(s)` from the controller's step of
    /// the robot at `s` moving with `s_dot = 1`, `s_ddot = 0` (see the
    /// module's documentation), then the motion's own rows.
    fn derivatives(&self, s: T) -> Result<Derivatives<T, PATH_ROWS>, crate::kin::Error> {
        let at = self.sample(s, T::one(), T::zero());
        let step = self.controller.step_commanded(
            &at.platform,
            &at.left,
            &at.right,
            &mut MarginTracker::new(),
        )?;
        Ok(PathPoint::of(&step).derivatives(self.own_rates()))
    }
}
