//! Any motion type as a geometric path, for time-optimal timing: `s in
//! [0, 1]` runs along its [`Geometry`]'s straight line in the motion's own
//! coordinates (for type 4, `(psi, theta) = (psi_0 + s dpsi, theta_0 +
//! s dtheta)`, `P` and `phi` still, both tips held).
//!
//! Along the path, each actuator is a function `q(s)`. Its derivatives come
//! from the controller's own cycle ([`Controller::step_commanded`], the same
//! call a control loop makes, with a fresh margin tracker): the robot at
//! `s` with `s_dot = 1`, `s_ddot = 0` (for type 4, Euler rates
//! `(dpsi, dtheta)`, no Euler acceleration) gives actuator velocities
//! `q'(s)` and accelerations `q''(s)`, since `q_dot = q' s_dot` and
//! `q_ddot = q' s_ddot + q'' s_dot^2`. No finite difference, no spline, and
//! no second copy of the cycle or of the geometry: a point of the path is
//! what the controller accepts (strokes, joint limits, singularity
//! thresholds, the parallel margin included).
//!
//! The path has [`PATH_ROWS`] rows for the solver
//! ([`parasils_traj::optimal`]): the twelve actuators in the order of
//! [`Actuator::ALL`](crate::kin::Actuator::ALL), then the motion's own two
//! rows (for type 4, `psi` and `theta` themselves, rad), so that the
//! paper's angular limits can bind too when asked ([`row_limits`]).
//!
//! ```
//! use parasils::geometry::RobotState;
//! use parasils::kin::{ActuatorLimits, Controller, Pose, TipTargets};
//! use parasils::path::{MotionPath, row_limits};
//! use parasils::traj::optimal::{self, Knot};
//!
//! let deg = core::f64::consts::PI / 180.0;
//! let controller = Controller::paper();
//! let tips = TipTargets::paper();
//! let start = RobotState::solved(&controller, Pose::paper_start(), &tips, 0.0)?;
//! let goal = [start.pose.psi + 15.0 * deg, start.pose.theta + 25.0 * deg];
//! let path = MotionPath::turning(&controller, &start, goal, [tips.left, tips.right]);
//! let limits = row_limits(&ActuatorLimits::assumed(), None);
//! let mut knots = vec![Knot::default(); 1000];
//! let (schedule, _) = optimal::plan(&path, &limits, &mut knots, 10)?;
//! // Faster than the paper's 4.5 s trapezoid under the assumed limits.
//! assert!(schedule.duration() < 4.5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::Real;
use crate::geometry::{Geometry, MotionSample, MotionType, Port, RobotState};
use crate::kin::nalgebra::Vector3;
use crate::kin::{
    ACTUATOR_COUNT, ActuatorLimits, ControlStep, Controller, MarginTracker, Pose, step_positions,
    step_rates,
};
use crate::traj::Limits;
use crate::traj::optimal::{Derivatives, Path, RowLimits};

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

/// Any of the paper's four motion types from rest to rest as a geometric
/// path `s in [0, 1]`, for time-optimal timing: the same straight line its
/// [`Motion`](crate::motions::Motion) follows, with the time law left open.
///
/// Rows 0 to 11 are the twelve actuators (see the module's documentation); rows
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
    geometry: Geometry<T>,
}

impl<T: Real> MotionPath<T> {
    /// `geometry`'s straight line on `controller`'s robot and assembly
    /// modes.
    pub fn new(controller: &Controller<T>, geometry: Geometry<T>) -> Self {
        Self {
            controller: *controller,
            geometry,
        }
    }

    /// Type 1: the platform from `start.pose` to `goal` on the straight
    /// line in pose space, the instrument joints and the endoscope held.
    pub fn positioning(controller: &Controller<T>, start: &RobotState<T>, goal: Pose<T>) -> Self {
        Self::new(controller, Geometry::positioning(start, goal))
    }

    /// Type 2: `port`'s `qs3` (or the endoscope's depth) by `depth` mm,
    /// everything else held.
    pub fn insertion(
        controller: &Controller<T>,
        start: &RobotState<T>,
        port: Port,
        depth: T,
    ) -> Self {
        Self::new(controller, Geometry::insertion(start, port, depth))
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
        Self::new(controller, Geometry::manipulation(start, from, to))
    }

    /// Type 4: `(psi, theta)` from `start.pose`'s to `goal` (rad), the tips
    /// held at `tips` (`[left, right]`, mm, fixed frame).
    pub fn turning(
        controller: &Controller<T>,
        start: &RobotState<T>,
        goal: [T; 2],
        tips: [Vector3<T>; 2],
    ) -> Self {
        Self::new(controller, Geometry::turning(start, goal, tips))
    }

    /// Its geometry.
    pub fn geometry(&self) -> &Geometry<T> {
        &self.geometry
    }

    /// The motion's type.
    pub fn motion_type(&self) -> MotionType {
        self.geometry.motion_type()
    }

    /// The state it starts from.
    pub fn start(&self) -> &RobotState<T> {
        self.geometry.start()
    }

    /// Whether nothing moves along it (a displacement of zero): it takes no
    /// time.
    pub fn is_still(&self) -> bool {
        self.geometry.is_still()
    }

    /// The motion's own coordinates' derivatives in `s` (rows 12 and 13,
    /// see [`MotionPath`]).
    pub fn own_rates(&self) -> [T; 2] {
        self.geometry.own_rates()
    }

    /// The robot at `s` moving with path speed `s_dot` (1/s) and path
    /// acceleration `s_ddot` (1/s^2): what
    /// [`Controller::step_commanded`] takes, through the geometry's one map
    /// ([`Geometry::sample`]).
    pub fn sample(&self, s: T, s_dot: T, s_ddot: T) -> MotionSample<T> {
        self.geometry.sample(s, s_dot, s_ddot)
    }

    /// The actuators and their derivatives in `s` at `s`.
    ///
    /// # Errors
    /// The kinematics' error where the path leaves the robot's workspace: a
    /// leg out of reach, a serial singularity, a stroke or joint limit, a tip
    /// out of reach, an instrument singularity, a non-finite number.
    pub fn point(&self, s: T) -> Result<PathPoint<T>, crate::kin::Error> {
        let at = self.sample(s, T::one(), T::zero());
        let step = self.controller.step_commanded(
            &at.platform,
            &at.left,
            &at.right,
            &mut MarginTracker::new(),
        )?;
        Ok(PathPoint::of(&step))
    }
}

impl<T: Real> Path<T, PATH_ROWS> for MotionPath<T> {
    type Error = crate::kin::Error;

    /// The actuators' `q'(s)` and `q''(s)` from the controller's step of
    /// the robot at `s` moving with `s_dot = 1`, `s_ddot = 0` (see the
    /// module's documentation), then the motion's own rows.
    fn derivatives(&self, s: T) -> Result<Derivatives<T, PATH_ROWS>, crate::kin::Error> {
        Ok(self.point(s)?.derivatives(self.own_rates()))
    }
}
