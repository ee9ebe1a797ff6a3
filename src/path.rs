//! Motion type 4 as a geometric path, for time-optimal timing: `s in [0, 1]`
//! turns the platform from its start pose along the straight line
//! `(psi, theta) = (psi_0 + s dpsi, theta_0 + s dtheta)`, `P` and `phi`
//! still, both tips held.
//!
//! Along the path, each actuator is a function `q(s)`. Its derivatives come
//! from the controller's own closed-form rates: the platform state at `s`
//! with `s_dot = 1`, `s_ddot = 0` (Euler rates `(dpsi, dtheta)`, no Euler
//! acceleration) gives actuator velocities `q'(s)` and accelerations
//! `q''(s)`, since `q_dot = q' s_dot` and `q_ddot = q' s_ddot + q'' s_dot^2`.
//! No finite difference, no spline.
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
use crate::kin::{
    ACTUATOR_COUNT, ActuatorLimits, AssemblyMode, Controller, Instrument, ParallelRobot,
    PlatformState, Pose, TipMotion, TipTargets,
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

/// Motion type 4's straight turn as a path `s in [0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReorientationPath<T: Real> {
    module1: ParallelRobot<T>,
    left: Instrument<T>,
    right: Instrument<T>,
    modes: [AssemblyMode; 2],
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
            module1: controller.module1,
            left: controller.left,
            right: controller.right,
            modes: controller.modes,
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
        let frame = state.frame()?;
        let q1 = self.module1.ik(&state.pose)?;
        let (v1, a1) = self.module1.rates(&frame, &q1)?;
        let l = self
            .left
            .solve(&frame, &TipMotion::still(self.tips.left), self.modes[0])?;
        let r = self
            .right
            .solve(&frame, &TipMotion::still(self.tips.right), self.modes[1])?;
        let pack = |m: [T; 6], a: [T; 3], b: [T; 3]| {
            [
                m[0], m[1], m[2], m[3], m[4], m[5], a[0], a[1], a[2], b[0], b[1], b[2],
            ]
        };
        Ok(PathPoint {
            q: pack(q1.0, l.q.to_array(), r.q.to_array()),
            q_s: pack(v1.0, l.q_dot.to_array(), r.q_dot.to_array()),
            q_ss: pack(a1.0, l.q_ddot.to_array(), r.q_ddot.to_array()),
        })
    }
}

impl<T: Real> Path<T, PATH_ROWS> for ReorientationPath<T> {
    type Error = crate::kin::Error;

    fn derivatives(&self, s: T) -> Result<Derivatives<T, PATH_ROWS>, crate::kin::Error> {
        let p = self.point(s)?;
        let mut first = [T::zero(); PATH_ROWS];
        let mut second = [T::zero(); PATH_ROWS];
        for (dst, &src) in first.iter_mut().zip(&p.q_s) {
            *dst = src;
        }
        for (dst, &src) in second.iter_mut().zip(&p.q_ss) {
            *dst = src;
        }
        let [dpsi, dtheta] = self.increment;
        let [.., psi, theta] = &mut first;
        (*psi, *theta) = (dpsi, dtheta);
        Ok(Derivatives { first, second })
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
