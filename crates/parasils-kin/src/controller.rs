//! The controller's one call per cycle.
//!
//! [`Controller::step`] takes the platform's state (pose, Euler rates and
//! accelerations) and the two tip targets held still in the fixed frame, and
//! returns module 1's actuators, rates, accelerations and margins, and both
//! instrument modules' joints, rates, accelerations and margins: motion type
//! 4, the endoscope reorientation with the tips kept where they are. The
//! platform's motion may be any (the general formula is used, see
//! `docs/model.md`, *Instrument modules*, rates); motion type 4 is `P` still
//! and `phi` constant. The trigonometry of
//! the platform is evaluated once ([`PlatformFrame`]) and shared by the three
//! modules.
//!
//! The whole robot's parameters are one [`RobotGeometry`], which a file can
//! hold; [`Controller::paper`] uses module 1's **assumed** geometry
//! ([`ParallelGeometry::assumed`]).
//!
//! A step is a pure function of its inputs (`&self`): the one state a
//! control loop carries from cycle to cycle, module 1's weakest direction
//! ([`MarginTracker`]), is the caller's, passed to every step. A planner
//! that evaluates the robot at scattered instants passes a fresh tracker
//! (the margin then comes from the full decomposition); a loop passes the
//! same one every cycle.
//!
//! ```
//! use parasils_kin::controller::{Controller, TipTargets};
//! use parasils_kin::frame::{PlatformState, Pose};
//! use parasils_kin::MarginTracker;
//!
//! let controller = Controller::<f64>::paper();
//! let mut tracker = MarginTracker::new();
//! let tips = TipTargets::paper();
//! // At P0, psi turning at 5 deg/s and theta accelerating at 5 deg/s^2.
//! let state = PlatformState::reorientation(
//!     Pose::paper_start(),
//!     [5f64.to_radians(), 0.0],
//!     [0.0, 5f64.to_radians()],
//! );
//! let out = controller.step(&state, &tips, &mut tracker)?;
//! assert!((out.left.q.qs1.to_degrees() - 3.0889).abs() < 1e-4);
//! assert!(out.left.margins.cos_qs2 > 0.7);
//! // Module 1 (assumed geometry) at P0.
//! assert!((out.module1.q[0] - 117.942).abs() < 5e-4);
//! assert!(out.module1.margins.serial_min > 0.5);
//! # Ok::<(), parasils_kin::Error>(())
//! ```

use nalgebra::Vector3;

use crate::check::check_vector;
use crate::endoscope::EndoscopeGeometry;
use crate::error::Error;
use crate::frame::{PlatformFrame, PlatformState, Pose};
use crate::instrument::{
    AssemblyMode, Instrument, InstrumentGeometry, InstrumentSolution, JointMotion, TipMotion,
};
use crate::limits::{ACTUATOR_COUNT, ActuatorLimits, LimitError};
use crate::parallel::{MarginTracker, ParallelGeometry, ParallelRobot, ParallelSolution};
use crate::presets;
use crate::real::Real;
use crate::side::Side;

/// The two instrument tips the controller holds still, mm, fixed frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TipTargets<T: Real> {
    /// The left instrument's tip, mm, fixed frame.
    pub left: Vector3<T>,
    /// The right instrument's tip, mm, fixed frame.
    pub right: Vector3<T>,
}

impl<T: Real> TipTargets<T> {
    /// The paper's tips: left `(50, -50, -620)` mm
    /// ([`presets::LEFT_TIP_MM`]), and the default right one
    /// ([`default_right_tip`] at `P0`), about `(92.9107, 68.3284, -659.5392)`
    /// mm (see `docs/model.md`, *Check values*).
    pub fn paper() -> Self {
        let left = Self::paper_left();
        Self {
            left,
            right: default_right_tip(&Pose::paper_start(), &left),
        }
    }

    /// The paper's left tip with the right one its exact mirror image across
    /// the platform's `Y'Z'` plane at `P0`, about
    /// `(-9.6103, 53.9889, -636.9821)` mm: the default before
    /// [`default_right_tip`], kept because mirror symmetry is a property the
    /// tests check, but physically impossible (the two shafts intersect).
    pub fn mirrored() -> Self {
        let left = Self::paper_left();
        Self {
            left,
            right: mirror_across_platform(&Pose::paper_start(), &left),
        }
    }

    fn paper_left() -> Vector3<T> {
        let [x, y, z] = presets::LEFT_TIP_MM;
        Vector3::new(T::lit(x), T::lit(y), T::lit(z))
    }
}

/// What an instrument module is commanded by in one cycle
/// ([`Controller::step_commanded`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModuleCommand<T: Real> {
    /// Its tip, with the tip's velocity and acceleration, fixed frame.
    Tip(TipMotion<T>),
    /// Its joints, with their rates and accelerations.
    Joints(JointMotion<T>),
}

impl<T: Real> ModuleCommand<T> {
    /// The tip held still at `position`, mm, fixed frame.
    pub fn still(position: Vector3<T>) -> Self {
        Self::Tip(TipMotion::still(position))
    }
}

/// The default right tip for the left tip `left` (mm, fixed frame) at
/// `pose`: its mirror image ([`mirror_across_platform`]) moved by
/// [`presets::RIGHT_TIP_SHIFT_MM`] in the platform frame,
/// `P + R (S R^T (left - P) + shift)` with `S = diag(-1, 1, 1)`.
///
/// ```
/// use parasils_kin::{Pose, TipTargets, default_right_tip, mirror_across_platform};
/// let p0 = Pose::<f64>::paper_start();
/// let t = TipTargets::<f64>::paper();
/// assert_eq!(default_right_tip(&p0, &t.left), t.right);
/// // 35 mm along X' and 100 mm along Y' from the mirror image.
/// let d = p0.rotation().transpose() * (t.right - mirror_across_platform(&p0, &t.left));
/// assert!((d - nalgebra::Vector3::new(35.0, 100.0, 0.0)).norm() < 1e-12);
/// ```
pub fn default_right_tip<T: Real>(pose: &Pose<T>, left: &Vector3<T>) -> Vector3<T> {
    let [x, y, z] = presets::RIGHT_TIP_SHIFT_MM;
    let shift = Vector3::new(T::lit(x), T::lit(y), T::lit(z));
    mirror_across_platform(pose, left) + pose.rotation() * shift
}

/// The mirror image of a fixed-frame point (mm) across the platform's `Y'Z'`
/// plane at `pose`: `P + R S R^T (p - P)` with `S = diag(-1, 1, 1)`.
pub fn mirror_across_platform<T: Real>(pose: &Pose<T>, p: &Vector3<T>) -> Vector3<T> {
    let r = pose.rotation();
    let mut c = r.tr_mul(&(p - pose.position()));
    c.x = -c.x;
    r * c + pose.position()
}

/// The whole robot's parameters: module 1 and both instrument modules, with
/// their limits and thresholds. What a robot file holds.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RobotGeometry<T: Real> {
    /// Module 1, the parallel robot.
    pub module1: ParallelGeometry<T>,
    /// The left instrument module (`side` must be [`Side::Left`]).
    pub left: InstrumentGeometry<T>,
    /// The right instrument module (`side` must be [`Side::Right`]).
    pub right: InstrumentGeometry<T>,
    /// The endoscope (its insertion depth's range).
    pub endoscope: EndoscopeGeometry<T>,
    /// The twelve actuators' velocity and acceleration limits (default
    /// [`ActuatorLimits::assumed`]).
    pub limits: ActuatorLimits<T>,
}

impl<T: Real> RobotGeometry<T> {
    /// The paper's instrument modules ([`InstrumentGeometry::paper`]) on
    /// module 1's **assumed** geometry ([`ParallelGeometry::assumed`]).
    pub fn paper() -> Self {
        Self {
            module1: ParallelGeometry::assumed(),
            left: InstrumentGeometry::paper(Side::Left),
            right: InstrumentGeometry::paper(Side::Right),
            endoscope: EndoscopeGeometry::paper(),
            limits: ActuatorLimits::assumed(),
        }
    }

    /// Checks every module ([`ParallelGeometry::validate`],
    /// [`InstrumentGeometry::validate`]) and that `left` and `right` are on
    /// their sides ([`Error::InvalidParameter`] `"robot.left.side"` or
    /// `"robot.right.side"` otherwise, with the value 0 for left, 1 for right).
    pub fn validate(&self) -> Result<(), Error> {
        self.module1.validate()?;
        for (what, g, side) in [
            ("robot.left.side", &self.left, Side::Left),
            ("robot.right.side", &self.right, Side::Right),
        ] {
            if g.side != side {
                return Err(Error::InvalidParameter {
                    what,
                    value: match g.side {
                        Side::Left => 0.0,
                        Side::Right => 1.0,
                    },
                });
            }
            g.validate()?;
        }
        self.endoscope.validate()?;
        if let Err(LimitError::Invalid { value, .. } | LimitError::InvalidForce { value, .. }) =
            self.limits.validate()
        {
            return Err(Error::InvalidParameter {
                what: "limits",
                value,
            });
        }
        Ok(())
    }
}

/// One cycle's result: the platform frame used, and the three modules' solutions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlStep<T: Real> {
    /// The platform frame at this instant (rotation, angular rates).
    pub frame: PlatformFrame<T>,
    /// Module 1: actuators, rates, accelerations, margins.
    pub module1: ParallelSolution<T>,
    /// The left module: joints, rates, accelerations, margins.
    pub left: InstrumentSolution<T>,
    /// The right module: joints, rates, accelerations, margins.
    pub right: InstrumentSolution<T>,
}

impl<T: Real> ControlStep<T> {
    /// The step of `frame` and the three modules' solutions, the first
    /// error in the order module 1, left, right: each solution moves once,
    /// from where its solver wrote it into the step (a `?` on each would
    /// move it into a local first, and these are hundreds of bytes moved
    /// every cycle).
    fn of(
        frame: &PlatformFrame<T>,
        module1: Result<ParallelSolution<T>, Error>,
        left: Result<InstrumentSolution<T>, Error>,
        right: Result<InstrumentSolution<T>, Error>,
    ) -> Result<Self, Error> {
        match (module1, left, right) {
            (Ok(module1), Ok(left), Ok(right)) => Ok(Self {
                frame: *frame,
                module1,
                left,
                right,
            }),
            (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => Err(e),
        }
    }
}

/// The value of `result` by reference, or its error, for `?`: the value
/// stays where its solver wrote it (see [`ControlStep::of`]).
fn first<V>(result: &Result<V, Error>) -> Result<&V, Error> {
    result.as_ref().map_err(|e| *e)
}

/// The per-cycle solver: module 1, both instrument modules, and the assembly
/// mode each instrument module is kept in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Controller<T: Real> {
    /// Module 1, the parallel robot.
    pub module1: ParallelRobot<T>,
    /// The left module.
    pub left: Instrument<T>,
    /// The right module.
    pub right: Instrument<T>,
    /// The assembly mode of each module, `[left, right]` (default A, A).
    pub modes: [AssemblyMode; 2],
    /// The endoscope (default [`EndoscopeGeometry::paper`]).
    pub endoscope: EndoscopeGeometry<T>,
    /// The actuators' velocity and acceleration limits (default
    /// [`ActuatorLimits::assumed`]); [`ActuatorLimits::check`] checks a step
    /// against them.
    pub limits: ActuatorLimits<T>,
}

impl<T: Real> Controller<T> {
    /// The controller of module 1 and two instrument modules, both in
    /// assembly mode A.
    pub fn new(module1: ParallelRobot<T>, left: Instrument<T>, right: Instrument<T>) -> Self {
        Self {
            module1,
            left,
            right,
            modes: [AssemblyMode::A; 2],
            endoscope: EndoscopeGeometry::paper(),
            limits: ActuatorLimits::assumed(),
        }
    }

    /// The paper's two instrument modules ([`Instrument::paper`]), mode A, on
    /// module 1's **assumed** geometry ([`ParallelRobot::assumed`]).
    pub fn paper() -> Self {
        Self::new(
            ParallelRobot::assumed(),
            Instrument::paper(Side::Left),
            Instrument::paper(Side::Right),
        )
    }

    /// The controller of a whole robot's geometry (validated first, see
    /// [`RobotGeometry::validate`]), both instrument modules in mode A.
    pub fn from_geometry(geometry: &RobotGeometry<T>) -> Result<Self, Error> {
        geometry.validate()?;
        let mut controller = Self::new(
            ParallelRobot::new(geometry.module1)?,
            Instrument::new(geometry.left)?,
            Instrument::new(geometry.right)?,
        );
        controller.endoscope = geometry.endoscope;
        controller.limits = geometry.limits;
        Ok(controller)
    }

    /// The whole robot's geometry (module 1's guide directions normalised).
    pub fn geometry(&self) -> RobotGeometry<T> {
        RobotGeometry {
            module1: *self.module1.geometry(),
            left: *self.left.geometry(),
            right: *self.right.geometry(),
            endoscope: self.endoscope,
            limits: self.limits,
        }
    }

    /// One control cycle of motion type 4: both tips held still at `tips`
    /// while the platform moves as `platform` says.
    ///
    /// Module 1 is solved first ([`ParallelRobot::solve_tracking`]: strokes
    /// checked, the parallel margin reported for the caller to watch, from
    /// the previous cycle's weakest direction in `tracker`), then the
    /// instrument modules. Errors name the module and what failed:
    /// non-finite input, a leg or a tip out of reach, a singular
    /// configuration, an actuator or joint beyond its limit.
    ///
    /// The controller is not changed; the only state a step leaves behind is
    /// module 1's weakest direction in the caller's `tracker`, which makes
    /// the next margin cheaper. Every output is a function of this call's
    /// inputs (the margin to within [`MarginTracker`]'s certified tolerance).
    pub fn step(
        &self,
        platform: &PlatformState<T>,
        tips: &TipTargets<T>,
        tracker: &mut MarginTracker<T>,
    ) -> Result<ControlStep<T>, Error> {
        let frame = platform.frame();
        let frame = first(&frame)?;
        check_vector(&tips.left, ["tips.left.x", "tips.left.y", "tips.left.z"])?;
        check_vector(
            &tips.right,
            ["tips.right.x", "tips.right.y", "tips.right.z"],
        )?;
        let module1 = self.module1.solve_tracking(frame, tracker);
        first(&module1)?;
        let left = self
            .left
            .solve(frame, &TipMotion::still(tips.left), self.modes[0]);
        first(&left)?;
        let right = self
            .right
            .solve(frame, &TipMotion::still(tips.right), self.modes[1]);
        ControlStep::of(frame, module1, left, right)
    }

    /// [`Controller::step`] for a platform at rest at `pose` (mm, rad) and
    /// both tips held at `tips`: a static pose, as the reach map checks
    /// one. The same checks, errors, actuators, joints and margins as
    /// `step` with [`PlatformState::at_rest`]`(pose)` (the margin to within
    /// [`MarginTracker`]'s tolerance, as every tracked margin); every rate
    /// and acceleration is zero, without being evaluated. Not for a
    /// control loop: the platform's motion is not an input.
    pub fn step_at_rest(
        &self,
        pose: &Pose<T>,
        tips: &TipTargets<T>,
        tracker: &mut MarginTracker<T>,
    ) -> Result<ControlStep<T>, Error> {
        pose.check_finite()?;
        let frame = PlatformFrame::at_rest(pose);
        check_vector(&tips.left, ["tips.left.x", "tips.left.y", "tips.left.z"])?;
        check_vector(
            &tips.right,
            ["tips.right.x", "tips.right.y", "tips.right.z"],
        )?;
        let module1 = self.module1.solve_at_rest(&frame, tracker)?;
        let left = self.left.solve_at_rest(&frame, &tips.left, self.modes[0])?;
        let right = self
            .right
            .solve_at_rest(&frame, &tips.right, self.modes[1])?;
        Ok(ControlStep {
            frame,
            module1,
            left,
            right,
        })
    }

    /// One control cycle of any motion type: the platform moves as
    /// `platform` says, and each instrument module is commanded either by
    /// its tip ([`ModuleCommand::Tip`]: the IK in the module's assembly mode,
    /// the rates in closed form, as in [`Controller::step`]) or by its joints
    /// ([`ModuleCommand::Joints`]: checked, the tip following by forward
    /// kinematics). Motion type 1 holds both modules' joints while the
    /// platform moves; type 2 drives one module's `qs3`; type 3 moves one or
    /// both tips with the platform still; type 4 holds both tips
    /// ([`Controller::step`], the same numbers).
    ///
    /// ```
    /// use parasils_kin::{
    ///     Controller, JointMotion, MarginTracker, ModuleCommand, PlatformState, Pose, TipTargets,
    /// };
    ///
    /// let controller = Controller::<f64>::paper();
    /// let mut tracker = MarginTracker::new();
    /// let tips = TipTargets::paper();
    /// let at_rest = PlatformState::at_rest(Pose::paper_start());
    /// let held = controller.step(&at_rest, &tips, &mut tracker)?;
    /// // The right module driven by its joints, at the joints the IK gave:
    /// // the same solution.
    /// let right = ModuleCommand::Joints(JointMotion::held(held.right.q));
    /// let left = ModuleCommand::still(tips.left);
    /// let out = controller.step_commanded(&at_rest, &left, &right, &mut tracker)?;
    /// assert_eq!(out.right.q, held.right.q);
    /// assert_eq!(out.left, held.left);
    /// # Ok::<(), parasils_kin::Error>(())
    /// ```
    pub fn step_commanded(
        &self,
        platform: &PlatformState<T>,
        left: &ModuleCommand<T>,
        right: &ModuleCommand<T>,
        tracker: &mut MarginTracker<T>,
    ) -> Result<ControlStep<T>, Error> {
        let frame = platform.frame();
        let frame = first(&frame)?;
        let module1 = self.module1.solve_tracking(frame, tracker);
        first(&module1)?;
        let solve = |m: &Instrument<T>, command: &ModuleCommand<T>, mode| match command {
            ModuleCommand::Tip(tip) => m.solve(frame, tip, mode),
            ModuleCommand::Joints(joints) => m.solve_joints(joints),
        };
        let left = solve(&self.left, left, self.modes[0]);
        first(&left)?;
        let right = solve(&self.right, right, self.modes[1]);
        ControlStep::of(frame, module1, left, right)
    }
}

/// The per-cycle checks of [`ActuatorLimits`] on a [`ControlStep`] (here, so
/// that `limits` needs nothing of the controller).
impl<T: Real> ActuatorLimits<T> {
    /// Checks one control cycle's rates and accelerations (see
    /// [`ActuatorLimits::check_rates`]).
    pub fn check(&self, step: &ControlStep<T>) -> Result<(), LimitError> {
        let (q_dot, q_ddot) = step_rates(step);
        self.check_rates(&q_dot, &q_ddot)
    }

    /// Each actuator's velocity and acceleration as a fraction of its limit,
    /// `(|q_dot| / v_max, |q_ddot| / a_max)` (0 where the limit is infinite).
    pub fn usage(&self, step: &ControlStep<T>) -> ([T; ACTUATOR_COUNT], [T; ACTUATOR_COUNT]) {
        let (mut v, mut a) = step_rates(step);
        for (x, &m) in v.iter_mut().zip(&self.velocity) {
            *x = x.abs() / m;
        }
        for (x, &m) in a.iter_mut().zip(&self.acceleration) {
            *x = x.abs() / m;
        }
        (v, a)
    }
}

/// The twelve actuators' velocities and accelerations of one cycle, in the
/// order of [`Actuator::ALL`](crate::Actuator::ALL).
pub fn step_rates<T: Real>(step: &ControlStep<T>) -> ([T; ACTUATOR_COUNT], [T; ACTUATOR_COUNT]) {
    let m1 = (step.module1.q_dot.0, step.module1.q_ddot.0);
    let (l, r) = (&step.left, &step.right);
    let v = [
        m1.0[0],
        m1.0[1],
        m1.0[2],
        m1.0[3],
        m1.0[4],
        m1.0[5],
        l.q_dot.qs1,
        l.q_dot.qs2,
        l.q_dot.qs3,
        r.q_dot.qs1,
        r.q_dot.qs2,
        r.q_dot.qs3,
    ];
    let a = [
        m1.1[0],
        m1.1[1],
        m1.1[2],
        m1.1[3],
        m1.1[4],
        m1.1[5],
        l.q_ddot.qs1,
        l.q_ddot.qs2,
        l.q_ddot.qs3,
        r.q_ddot.qs1,
        r.q_ddot.qs2,
        r.q_ddot.qs3,
    ];
    (v, a)
}

/// The twelve actuator positions of one cycle, in the order of
/// [`Actuator::ALL`](crate::Actuator::ALL) (mm, rad).
pub fn step_positions<T: Real>(step: &ControlStep<T>) -> [T; ACTUATOR_COUNT] {
    let m = step.module1.q.0;
    let (l, r) = (&step.left.q, &step.right.q);
    [
        m[0], m[1], m[2], m[3], m[4], m[5], l.qs1, l.qs2, l.qs3, r.qs1, r.qs2, r.qs3,
    ]
}
