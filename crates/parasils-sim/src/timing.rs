//! Time-optimal timing under the actuators' limits (see `docs/model.md`,
//! *Time-optimal timing*): any motion type's [`MotionPath`]
//! ([`OptimalMotion`]: a procedure's motions, and the paper's turn through
//! [`OptimalMotion::turn`]), solved by
//! [`parasils::traj::optimal`] on a grid of [`TimingOptions::knots`]
//! points, checked [`TimingOptions::checks`] times denser, and sampled like
//! any planned motion.
//!
//! **Clearance.** The gaps between the shafts and the endoscope are a
//! function of where the bodies are, not of when: of the path point alone
//! (the platform's pose, the tips, the endoscope's depth), never of its
//! rates. The time-optimal motion follows the same path as the motion's
//! other timings, so its samples go through the same per-sample check as
//! every planned run (a gap below the robot file's `clearance_stop_mm`
//! fails the run, `SimulationError::Clearance`), and the smallest gap of
//! the path, found once from its geometry, is the one every timing meets
//! (up to where the samples fall): the timing needs no clearance limit of
//! its own (`crates/parasils-sim/tests/clearance.rs`).
//!
//! ```
//! use parasils::kin::{ActuatorLimits, Controller, Pose, TipTargets};
//! use parasils::traj::Motion;
//! use parasils_sim::timing::{OptimalMotion, TimingOptions};
//!
//! let start = Pose::paper_start();
//! let goal = [start.psi + 15f64.to_radians(), start.theta + 25f64.to_radians()];
//! let plan = OptimalMotion::turn(
//!     &Controller::paper(),
//!     start,
//!     goal,
//!     TipTargets::paper(),
//!     &ActuatorLimits::assumed(),
//!     &TimingOptions::default(),
//! )?;
//! assert!(plan.duration() < 4.5); // the paper's trapezoid takes 4.5 s
//! let first = plan.phases()[0];
//! assert_eq!(first.binding.to_string(), "module 1 q6");
//! for sample in (&plan).sampler(1000.0)? {
//!     let _robot = sample.state; // a MotionSample for Controller::step_commanded
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use core::fmt;

pub use parasils::geometry::RobotState;
use parasils::geometry::{MotionSample, MotionType};
use parasils::kin::{
    ACTUATOR_COUNT, Actuator, ActuatorLimits, Controller, LimitError, Pose, RateKind, TipTargets,
};
use parasils::path::row_limits;
pub use parasils::path::{MotionPath, PATH_ROWS, PathPoint};
use parasils::traj::optimal::{self, Certificate, Knot, RowLimits, Schedule};
use parasils::traj::{LimitKind, Limits, Motion, State};

/// How the optimal law is computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimingOptions {
    /// Grid points on the path (at least 2; default 1000).
    pub knots: usize,
    /// Check points per grid interval (at least 2; default 10).
    pub checks: usize,
    /// The Euler angles' own limits `[psi, theta]` (rad/s, rad/s^2), binding
    /// as well when given; `None` (default): only the actuators' bind.
    pub angular: Option<[Limits<f64>; 2]>,
}

impl Default for TimingOptions {
    fn default() -> Self {
        Self {
            knots: 1000,
            checks: 10,
            angular: None,
        }
    }
}

/// Why the optimal law could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TimingError {
    /// An actuator limit that is zero, negative or NaN.
    #[error(transparent)]
    Limits(#[from] LimitError),
    /// The path leaves the robot's workspace at `s` (0 to 1 along it).
    #[error("the path at s = {s}: {error}")]
    Kinematics {
        /// Where along the turn.
        s: f64,
        /// The kinematics' error.
        error: parasils::kin::Error,
    },
    /// The solver's error (an invalid option or angular limit, ...).
    #[error(transparent)]
    Solver(optimal::Error),
}

impl From<optimal::Error<parasils::kin::Error>> for TimingError {
    fn from(e: optimal::Error<parasils::kin::Error>) -> Self {
        match e.split() {
            Ok(solver) => TimingError::Solver(solver),
            Err((s, error)) => TimingError::Kinematics { s, error },
        }
    }
}

/// What limits a phase: an actuator, or one of the motion's own
/// coordinates (rows 12 and 13 of [`MotionPath`]) under the limits stated
/// for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Binding {
    /// An actuator's limit.
    Actuator(Actuator),
    /// `psi`'s own limit (type 4; `--omega-max`, `--eps-max`).
    Psi,
    /// `theta`'s own limit (type 4).
    Theta,
    /// The platform's `x, y, z` (type 1: the motion's linear limits).
    Translation,
    /// The platform's `psi, theta, phi` (type 1: its angular limits).
    Rotation,
    /// The inserted `qs3` or depth (type 2: the motion's linear limits).
    Depth,
    /// The left tip's arc length (type 3).
    LeftTip,
    /// The right tip's arc length (type 3).
    RightTip,
}

impl Binding {
    /// What row `row` of a path of `motion_type` is (see [`MotionPath`]).
    fn of_row(row: usize, motion_type: MotionType) -> Self {
        let own = row - ACTUATOR_COUNT.min(row);
        match (Actuator::from_index(row), motion_type, own) {
            (Some(a), ..) => Binding::Actuator(a),
            (None, MotionType::Position, 0) => Binding::Translation,
            (None, MotionType::Position, _) => Binding::Rotation,
            (None, MotionType::Insert, _) => Binding::Depth,
            (None, MotionType::Manipulate, 0) => Binding::LeftTip,
            (None, MotionType::Manipulate, _) => Binding::RightTip,
            (None, MotionType::Reorient, 0) => Binding::Psi,
            (None, MotionType::Reorient, _) => Binding::Theta,
        }
    }
}

impl fmt::Display for Binding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Binding::Actuator(a) => a.fmt(f),
            Binding::Psi => f.write_str("psi"),
            Binding::Theta => f.write_str("theta"),
            Binding::Translation => f.write_str("x, y, z"),
            Binding::Rotation => f.write_str("psi, theta, phi"),
            Binding::Depth => f.write_str("depth"),
            Binding::LeftTip => f.write_str("left tip"),
            Binding::RightTip => f.write_str("right tip"),
        }
    }
}

/// One phase of the optimal law: from `start_s` to `end_s` (time), the
/// `kind` limit of `binding` is the most used, up to `usage` of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseSummary {
    /// When the phase starts, s.
    pub start_s: f64,
    /// When it ends, s.
    pub end_s: f64,
    /// What limits it.
    pub binding: Binding,
    /// Velocity or acceleration.
    pub kind: RateKind,
    /// The largest fraction of that limit used in the phase.
    pub usage: f64,
}

impl fmt::Display for PhaseSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:.4} s to {:.4} s: {} {} limit",
            self.start_s, self.end_s, self.binding, self.kind
        )
    }
}

/// A path timed to be as fast as its limits allow: the path, the solver's
/// limits (one per row), and the solved knots: [`OptimalMotion`], any
/// motion type's path (the paper's turn, a procedure's motions).
#[derive(Debug, Clone)]
pub struct OptimalLaw<P> {
    path: P,
    limits: [RowLimits<f64>; PATH_ROWS],
    knots: Vec<Knot<f64, PATH_ROWS>>,
    certificate: Option<Certificate<f64>>,
}

/// Any motion type timed to be as fast as the actuators' limits (and the
/// limits given for its own coordinates) allow: a [`Motion`] of
/// [`MotionSample`]s, what a procedure's motion becomes under
/// `--timing optimal`.
///
/// ```
/// use parasils::kin::{ActuatorLimits, Controller, Joints, Pose};
/// use parasils::motions::{Port, RobotState};
/// use parasils::path::MotionPath;
/// use parasils_sim::timing::{OptimalMotion, TimingOptions};
///
/// let controller = Controller::<f64>::paper();
/// let start = RobotState {
///     pose: Pose::paper_start(),
///     joints: [Joints::from_deg_mm(3.0, -10.0, 120.0), Joints::from_deg_mm(-3.0, 10.0, 120.0)],
///     endoscope_depth: 0.0,
/// };
/// // The left qs3 by 30 mm: qs3's own 60 mm/s^2 binds, sqrt(4 d / a) = sqrt(2) s.
/// let path = MotionPath::insertion(&controller, &start, Port::Left, 30.0);
/// let plan = OptimalMotion::plan(path, &ActuatorLimits::assumed(), [None, None], &TimingOptions::default())?;
/// assert!((plan.duration() - 2f64.sqrt()).abs() < 1e-5);
/// assert_eq!(plan.phases()[0].binding.to_string(), "left qs3");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub type OptimalMotion = OptimalLaw<MotionPath<f64>>;

impl<P: optimal::Path<f64, PATH_ROWS, Error = parasils::kin::Error>> OptimalLaw<P> {
    /// Solves `path` within `limits` (`still`: nothing moves along it, and
    /// it takes no time).
    fn solve(
        path: P,
        limits: [RowLimits<f64>; PATH_ROWS],
        still: bool,
        options: &TimingOptions,
    ) -> Result<Self, TimingError> {
        let mut law = Self {
            path,
            limits,
            knots: Vec::new(),
            certificate: None,
        };
        if still {
            return Ok(law);
        }
        law.knots = vec![Knot::default(); options.knots];
        let (_, certificate) = optimal::plan(&law.path, &limits, &mut law.knots, options.checks)?;
        law.certificate = Some(certificate);
        Ok(law)
    }

    /// The path.
    pub fn path(&self) -> &P {
        &self.path
    }

    /// The solver's limits, one per row (twelve actuators, then the
    /// motion's own two coordinates).
    pub fn limits(&self) -> &[RowLimits<f64>; PATH_ROWS] {
        &self.limits
    }

    /// The solved schedule `s(t)`.
    pub fn schedule(&self) -> Schedule<'_, f64, PATH_ROWS> {
        Schedule::view(&self.knots)
    }

    /// What the check between grid points found and did (`None` for a path
    /// along which nothing moves).
    pub fn certificate(&self) -> Option<&Certificate<f64>> {
        self.certificate.as_ref()
    }

    /// The duration, s.
    pub fn duration(&self) -> f64 {
        self.schedule().duration()
    }

    /// `(s, s_dot, s_ddot)` at `t`.
    pub fn path_state(&self, t: f64) -> State<f64> {
        if self.knots.is_empty() {
            return State::rest(0.0);
        }
        self.schedule().state(t)
    }
}

impl OptimalMotion {
    /// The fastest rest-to-rest turn from `start` to `goal = [psi, theta]`
    /// (rad) along the straight line in `(psi, theta)`, tips held at `tips`
    /// (the paper's scenario), within `actuators` (and `options.angular`,
    /// on `psi` and `theta`, when given). A turn of zero length takes no
    /// time.
    ///
    /// # Errors
    /// [`TimingError::Limits`] for an invalid limit,
    /// [`TimingError::Kinematics`] where the line leaves the workspace (its
    /// start included, at `s = 0`), [`TimingError::Solver`] for invalid
    /// options.
    pub fn turn(
        controller: &Controller<f64>,
        start: Pose<f64>,
        goal: [f64; 2],
        tips: TipTargets<f64>,
        actuators: &ActuatorLimits<f64>,
        options: &TimingOptions,
    ) -> Result<Self, TimingError> {
        actuators.validate()?;
        let state = RobotState::solved(controller, start, &tips, 0.0)
            .map_err(|error| TimingError::Kinematics { s: 0.0, error })?;
        let path = MotionPath::turning(controller, &state, goal, [tips.left, tips.right]);
        let own = options
            .angular
            .map_or([None, None], |[psi, theta]| [Some(psi), Some(theta)]);
        Self::plan(path, actuators, own, options)
    }

    /// The fastest rest-to-rest law along `path` within `actuators` and,
    /// for the motion's own coordinates (rows 12 and 13, see
    /// [`MotionPath`]), `own` where given. A path along which nothing
    /// moves takes no time.
    ///
    /// # Errors
    /// [`TimingError::Limits`] for an invalid limit,
    /// [`TimingError::Kinematics`] where the path leaves the workspace,
    /// [`TimingError::Solver`] for invalid options or own limits.
    pub fn plan(
        path: MotionPath<f64>,
        actuators: &ActuatorLimits<f64>,
        own: [Option<Limits<f64>>; 2],
        options: &TimingOptions,
    ) -> Result<Self, TimingError> {
        actuators.validate()?;
        let mut limits = row_limits(actuators, None);
        for (row, own) in limits[ACTUATOR_COUNT..].iter_mut().zip(own) {
            if let Some(l) = own {
                *row = RowLimits::new(l.v_max, l.a_max);
            }
        }
        Self::solve(path, limits, path.is_still(), options)
    }

    /// The robot at `t` (s): at rest at the start for `t <= 0`, at rest at
    /// the end for `t >= duration`.
    pub fn sample_at(&self, t: f64) -> MotionSample<f64> {
        let st = self.path_state(t);
        self.path.sample(st.position, st.velocity, st.acceleration)
    }

    /// The phases, in time order, each with what limits it.
    pub fn phases(&self) -> Vec<PhaseSummary> {
        phases(&self.schedule(), &self.limits, self.path.motion_type())
    }
}

impl Motion<f64> for OptimalMotion {
    type Output = MotionSample<f64>;

    fn duration(&self) -> f64 {
        OptimalLaw::duration(self)
    }

    fn sample(&self, t: f64) -> MotionSample<f64> {
        self.sample_at(t)
    }
}

/// The phases of `schedule` under `limits` on a path of `motion_type`.
fn phases(
    schedule: &Schedule<'_, f64, PATH_ROWS>,
    limits: &[RowLimits<f64>; PATH_ROWS],
    motion_type: MotionType,
) -> Vec<PhaseSummary> {
    schedule
        .phases(limits)
        .map(|p| PhaseSummary {
            start_s: p.start_t,
            end_s: p.end_t,
            binding: Binding::of_row(p.row, motion_type),
            kind: match p.limit {
                LimitKind::Velocity => RateKind::Velocity,
                _ => RateKind::Acceleration,
            },
            usage: p.usage,
        })
        .collect()
}

/// The optimal law in the phase plane: at every grid knot, the path
/// speed `s_dot` (1/s) of the schedule and the limit curves it stays under
/// (the picture `--plot` draws for `--timing optimal`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PhasePlane {
    /// The path parameter at each knot.
    pub s: Vec<f64>,
    /// The schedule's `s_dot`.
    pub s_dot: Vec<f64>,
    /// The velocity limit curve: the largest `s_dot` every row's velocity
    /// limit admits (`+inf` where none binds).
    pub velocity_limit: Vec<f64>,
    /// The acceleration limit curve: the largest `s_dot` at which some path
    /// acceleration keeps every row's acceleration within its limit.
    pub acceleration_limit: Vec<f64>,
    /// The controllable set's upper end: the largest `s_dot` from which the
    /// end can still be reached at rest.
    pub controllable: Vec<f64>,
    /// The phases: the `s` where each starts and ends, and what limits it.
    pub phases: Vec<(f64, f64, String)>,
}

impl OptimalMotion {
    /// The phase plane of this law (empty for a path along which nothing
    /// moves).
    pub fn phase_plane(&self) -> PhasePlane {
        self.plane(&self.phases())
    }
}

impl<P: optimal::Path<f64, PATH_ROWS, Error = parasils::kin::Error>> OptimalLaw<P> {
    /// The phase plane of this law with its `phases`.
    fn plane(&self, phases: &[PhaseSummary]) -> PhasePlane {
        let knots = &self.knots;
        let s_at = |t: f64| self.schedule().state(t).position;
        PhasePlane {
            s: knots.iter().map(|k| k.s).collect(),
            s_dot: knots.iter().map(Knot::s_dot).collect(),
            velocity_limit: knots
                .iter()
                .map(|k| k.derivatives.velocity_limit(&self.limits).sqrt())
                .collect(),
            acceleration_limit: knots
                .iter()
                .map(|k| k.derivatives.acceleration_limit(&self.limits).sqrt())
                .collect(),
            controllable: knots.iter().map(|k| k.x_max().sqrt()).collect(),
            phases: phases
                .iter()
                .map(|p| {
                    (
                        s_at(p.start_s),
                        s_at(p.end_s),
                        format!("{} {}", p.binding, p.kind),
                    )
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(goal_deg: [f64; 2], options: &TimingOptions) -> Result<OptimalMotion, TimingError> {
        let start = Pose::paper_start();
        OptimalMotion::turn(
            &Controller::paper(),
            start,
            [
                start.psi + goal_deg[0].to_radians(),
                start.theta + goal_deg[1].to_radians(),
            ],
            TipTargets::paper(),
            &ActuatorLimits::assumed(),
            options,
        )
    }

    #[test]
    fn a_turn_of_zero_length_takes_no_time_and_rests_at_the_start() -> Result<(), TimingError> {
        let p = plan([0.0, 0.0], &TimingOptions::default())?;
        assert_eq!(p.duration(), 0.0);
        assert!(p.phases().is_empty() && p.certificate().is_none());
        let st = p.sample_at(1.0).platform;
        assert_eq!(
            st,
            parasils::kin::PlatformState::at_rest(Pose::paper_start())
        );
        Ok(())
    }

    #[test]
    fn the_paper_turn_ends_on_its_goal_at_rest() -> Result<(), TimingError> {
        let p = plan([15.0, 25.0], &TimingOptions::default())?;
        let end = p.sample_at(p.duration()).platform;
        let start = Pose::<f64>::paper_start();
        assert!((end.pose.psi - (start.psi + 15f64.to_radians())).abs() < 1e-15);
        assert!((end.pose.theta - (start.theta + 25f64.to_radians())).abs() < 1e-15);
        assert_eq!((end.velocity.psi, end.velocity.theta), (0.0, 0.0));
        // q6's acceleration, velocity, then acceleration again.
        let phases = p.phases();
        let kinds: Vec<_> = phases
            .iter()
            .map(|ph| (ph.binding.to_string(), ph.kind))
            .collect();
        assert_eq!(
            kinds,
            [
                ("module 1 q6".to_string(), RateKind::Acceleration),
                ("module 1 q6".to_string(), RateKind::Velocity),
                ("module 1 q6".to_string(), RateKind::Acceleration),
            ]
        );
        assert!(phases.iter().all(|ph| (ph.usage - 1.0).abs() < 1e-6));
        Ok(())
    }

    #[test]
    fn the_law_stays_under_its_limit_curves() -> Result<(), TimingError> {
        let p = plan([15.0, 25.0], &TimingOptions::default())?;
        let plane = p.phase_plane();
        assert_eq!(plane.s.len(), TimingOptions::default().knots);
        assert_eq!((plane.s[0], plane.s_dot[0]), (0.0, 0.0));
        let mut touches = 0;
        for k in 0..plane.s.len() {
            let bound = plane.velocity_limit[k].min(plane.acceleration_limit[k]);
            assert!(plane.s_dot[k] <= bound * (1.0 + 1e-12), "{k}");
            assert!(
                plane.s_dot[k] <= plane.controllable[k] * (1.0 + 1e-12),
                "{k}"
            );
            // The velocity curve from the path's own derivatives, row by row.
            let d = optimal::Path::derivatives(p.path(), plane.s[k]).expect("on the path");
            let mut v = f64::INFINITY;
            for (j, lim) in p.limits().iter().enumerate() {
                if d.first[j] != 0.0 {
                    v = v.min(lim.velocity / d.first[j].abs());
                }
            }
            assert!((plane.velocity_limit[k] - v).abs() <= 1e-12 * v, "{k}");
            touches += usize::from(plane.s_dot[k] > plane.velocity_limit[k] * (1.0 - 1e-6));
        }
        // q6's velocity phase runs on the velocity curve.
        assert!(touches > 100, "{touches}");
        let phases: Vec<&str> = plane.phases.iter().map(|(_, _, l)| l.as_str()).collect();
        assert_eq!(
            phases,
            [
                "module 1 q6 acceleration",
                "module 1 q6 velocity",
                "module 1 q6 acceleration"
            ]
        );
        assert_eq!(plane.phases[0].0, 0.0);
        assert!((plane.phases[2].1 - 1.0).abs() < 1e-12);
        Ok(())
    }

    #[test]
    fn the_angular_limits_bind_when_given() -> Result<(), TimingError> {
        let deg = 1f64.to_radians();
        let options = TimingOptions {
            angular: Some([Limits::new(5.0 * deg, 2.0 * deg); 2]),
            ..TimingOptions::default()
        };
        let p = plan([15.0, 25.0], &options)?;
        // theta's own trapezoid: 25 / 5 + 5 / 2 = 7.5 s.
        assert!((p.duration() - 7.5).abs() < 7.5 * 2e-3, "{}", p.duration());
        assert!(p.phases().iter().all(|ph| ph.binding == Binding::Theta));
        Ok(())
    }

    #[test]
    fn errors_say_what_and_where() {
        let e = plan([0.0, 170.0], &TimingOptions::default()).expect_err("out of reach");
        assert!(matches!(e, TimingError::Kinematics { .. }), "{e}");
        assert!(e.to_string().starts_with("the path at s = "), "{e}");
        let options = TimingOptions {
            knots: 1,
            ..TimingOptions::default()
        };
        let e = plan([15.0, 25.0], &options).expect_err("one knot");
        assert_eq!(
            e.to_string(),
            "time-optimal timing: 1 knots, at least 2 are needed"
        );
        let mut limits = ActuatorLimits::assumed();
        limits.velocity[3] = -1.0;
        let start = Pose::paper_start();
        let e = OptimalMotion::turn(
            &Controller::paper(),
            start,
            [start.psi, start.theta + 0.1],
            TipTargets::paper(),
            &limits,
            &TimingOptions::default(),
        )
        .expect_err("negative limit");
        assert_eq!(
            e.to_string(),
            "module 1 q4: velocity limit -1 is not a positive number"
        );
    }
}
