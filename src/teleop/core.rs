//! The core: [`Teleop`], its state from cycle to cycle, its construction,
//! and the one call per cycle, [`Teleop::step`].

use crate::error::Error;
use crate::follow::Follow;
use crate::kin::nalgebra::Vector3;
use crate::kin::{
    BodyGeometry, Camera, Clearance, ControlStep, Controller, MarginTracker, PlatformState, Pose,
    Real, Side, TipTargets, step_positions,
};
use crate::supervisor::{ClearanceThresholds, Margins, Supervisor};
use crate::traj::OnlineMulti;

use super::cycle::{CommandOutcome, Fault, TeleopCycle};
use super::filter::LowPass;
use super::input::{Command, Device, Inputs};
use super::params::{TeleopError, TeleopParams};
use super::state::OperatingState;

/// The velocities of one cycle's candidate motion: both tips (mm/s, fixed
/// frame, `[left module, right module]`) and `[psi, theta]` (rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Velocities<T: Real> {
    pub(super) tips: [Vector3<T>; 2],
    pub(super) angles: [T; 2],
}

impl<T: Real> Velocities<T> {
    pub(super) fn zero() -> Self {
        Self {
            tips: [Vector3::zeros(); 2],
            angles: [T::zero(); 2],
        }
    }

    pub(super) fn is_zero(&self) -> bool {
        self.tips.iter().all(|v| v.iter().all(|x| *x == T::zero()))
            && self.angles.iter().all(|x| *x == T::zero())
    }

    /// `self + s (other - self)` for the parts `which` names (the left tip,
    /// the right tip, the view), `other` for the rest.
    pub(super) fn lerp(&self, other: &Self, s: T, which: [bool; 3]) -> Self {
        let k = |on: bool| if on { s } else { T::one() };
        let (l, r, a) = (k(which[0]), k(which[1]), k(which[2]));
        Self {
            tips: [
                self.tips[0] + (other.tips[0] - self.tips[0]) * l,
                self.tips[1] + (other.tips[1] - self.tips[1]) * r,
            ],
            angles: [
                self.angles[0] + (other.angles[0] - self.angles[0]) * a,
                self.angles[1] + (other.angles[1] - self.angles[1]) * a,
            ],
        }
    }
}

/// What keeps the core busy (CRTK's `is_busy`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Busy<T: Real> {
    /// Nothing: the hands drive.
    Idle,
    /// A planned move (home, look-at, move-to) and its start time, s.
    Move(OnlineMulti<T, 8>, T),
    /// A `stop`: the controlled stop to rest while ENABLED.
    Stop,
}

/// The teleoperation core (see the [module docs](crate::teleop)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Teleop<T: Real> {
    pub(super) controller: Controller<T>,
    pub(super) params: TeleopParams<T>,
    pub(super) supervisor: Supervisor<T>,
    pub(super) camera: Camera<T>,
    /// The endoscope's insertion below `P`, mm.
    pub(super) depth: T,
    pub(super) watch: Option<(BodyGeometry<T>, ClearanceThresholds<T>)>,
    /// The home pose's `[psi, theta]` and tips.
    pub(super) home: ([T; 2], [Vector3<T>; 2]),
    /// `P` and `phi` (held); `psi`, `theta` of the current setpoint.
    pub(super) pose: Pose<T>,
    /// The current setpoint's tips and velocities, `[left, right]` module.
    pub(super) tips: [Vector3<T>; 2],
    pub(super) velocity: Velocities<T>,
    /// The longest a controlled stop from the current setpoint may take, s:
    /// the stop its cycle was checked with, or what is left of the stop
    /// under way (none at rest).
    pub(super) stop_left: Option<T>,
    /// The limit the previous cycle held at when reducing its own parts
    /// did not suffice and everything was reduced.
    pub(super) widened: Option<super::cycle::HoldAt>,
    /// Module 1's weakest direction, at the setpoints and at the stop points.
    pub(super) tracker: MarginTracker<T>,
    pub(super) end_tracker: MarginTracker<T>,
    /// The same at the stop lines' middles (each point warm-started from
    /// its own of the cycle before, which is near it).
    pub(super) mid_tracker: MarginTracker<T>,
    pub(super) last: Option<T>,
    pub(super) state: OperatingState,
    /// What keeps the core busy: a planned move, or a `stop`.
    pub(super) busy: Busy<T>,
    pub(super) follow: Option<Follow<T>>,
    /// The tremor filters: each hand's velocity (fixed frame), the view's.
    pub(super) filters: [LowPass<T, 3>; 2],
    pub(super) camera_filter: LowPass<T, 2>,
    /// Whether each hand was engaged at the previous cycle, and a master's
    /// position then.
    pub(super) engaged: [bool; 2],
    pub(super) master: [Option<Vector3<T>>; 2],
    /// The module each hand drives, `[left hand, right hand]`.
    pub(super) hands: [Side; 2],
    /// The current setpoint's step, margins and gaps between the bodies.
    pub(super) step: ControlStep<T>,
    pub(super) margins: Margins<T>,
    pub(super) clearance: Option<Clearance<T>>,
    /// The lowest margins and gaps the current setpoint's checks found (at
    /// it, or along its stop line), the gaps in `ClearancePair::ALL`'s order.
    pub(super) path_low: (Margins<T>, Option<[T; 3]>),
    pub(super) fault: Option<Fault>,
}

impl<T: Real> Teleop<T> {
    /// DISABLED, at rest at `home` (mm, rad: `P` and `phi` are held, `psi`,
    /// `theta` are the view's home) with the tips at `tips` (mm, fixed
    /// frame; also their home), the endoscope at `depth` mm, the camera
    /// [`Camera::assumed`], the default [`Supervisor`], no clearance watch.
    ///
    /// # Errors
    /// [`TeleopError::InvalidParameter`] for invalid parameters or depth;
    /// [`TeleopError::Setup`] when the kinematics fail at home.
    pub fn new(
        controller: Controller<T>,
        home: Pose<T>,
        tips: TipTargets<T>,
        depth: T,
        params: TeleopParams<T>,
    ) -> Result<Self, TeleopError> {
        params.validate()?;
        if !(depth.finite() && depth >= T::zero()) {
            return Err(TeleopError::InvalidParameter {
                what: "depth",
                value: depth.to_f64(),
            });
        }
        let mut tracker = MarginTracker::new();
        let step = controller
            .step(&PlatformState::at_rest(home), &tips, &mut tracker)
            .map_err(Error::from)?;
        let supervisor = Supervisor::default();
        supervisor.validate(&Margins::hard(&controller))?;
        Ok(Self {
            controller,
            params,
            supervisor,
            camera: Camera::assumed(),
            depth,
            watch: None,
            home: ([home.psi, home.theta], [tips.left, tips.right]),
            pose: home,
            tips: [tips.left, tips.right],
            velocity: Velocities::zero(),
            stop_left: None,
            widened: None,
            tracker,
            end_tracker: tracker,
            mid_tracker: tracker,
            last: None,
            state: OperatingState::Disabled,
            busy: Busy::Idle,
            follow: None,
            filters: [LowPass::new(params.cutoff_hz); 2],
            camera_filter: LowPass::new(params.cutoff_hz),
            engaged: [false; 2],
            master: [None; 2],
            hands: [Side::Left, Side::Right],
            margins: Margins::of(&step),
            path_low: (Margins::of(&step), None),
            step,
            clearance: None,
            fault: None,
        })
    }

    /// The same core with the supervisor's thresholds `supervisor`.
    ///
    /// # Errors
    /// [`TeleopError::Setup`] with [`Error::InvalidThreshold`].
    pub fn with_supervisor(mut self, supervisor: Supervisor<T>) -> Result<Self, TeleopError> {
        supervisor.validate(&Margins::hard(&self.controller))?;
        self.supervisor = supervisor;
        Ok(self)
    }

    /// The same core watching the gaps between the shafts and the endoscope
    /// (`bodies`, mm) against `thresholds` (mm).
    ///
    /// # Errors
    /// [`TeleopError::Setup`]: invalid thresholds, or bodies the kinematics
    /// refuse.
    pub fn with_clearance(
        mut self,
        bodies: BodyGeometry<T>,
        thresholds: ClearanceThresholds<T>,
    ) -> Result<Self, TeleopError> {
        thresholds.validate()?;
        self.watch = Some((bodies, thresholds));
        self.clearance = self.clearance_of(&self.step).map_err(Error::from)?;
        self.path_low.1 = self.clearance.as_ref().map(super::hold::gap_array);
        Ok(self)
    }

    /// The same core with the endoscope's `camera`.
    ///
    /// # Errors
    /// [`TeleopError::Setup`] with the camera's error.
    pub fn with_camera(mut self, camera: Camera<T>) -> Result<Self, TeleopError> {
        camera.validate().map_err(Error::from)?;
        self.camera = camera;
        Ok(self)
    }

    /// The operating state.
    pub fn state(&self) -> OperatingState {
        self.state
    }

    /// CRTK's `is_busy`: a planned move or a `stop` is under way.
    pub fn is_busy(&self) -> bool {
        !matches!(self.busy, Busy::Idle)
    }

    /// CRTK's `is_homed`: always true (see the [state docs](crate::teleop::OperatingState)).
    pub fn is_homed(&self) -> bool {
        true
    }

    /// CRTK's `is_ready`: `is_enabled && is_homed`.
    pub fn is_ready(&self) -> bool {
        self.state == OperatingState::Enabled && self.is_homed()
    }

    /// Whether every tip and the view are at rest.
    pub fn is_at_rest(&self) -> bool {
        self.velocity.is_zero()
    }

    /// The module each hand drives, `[left hand, right hand]`.
    pub fn hands(&self) -> [Side; 2] {
        self.hands
    }

    /// The current tips, `[left module, right module]`, mm, fixed frame.
    pub fn tips(&self) -> [Vector3<T>; 2] {
        self.tips
    }

    /// The current pose (its `psi`, `theta` the view's setpoint).
    pub fn pose(&self) -> Pose<T> {
        self.pose
    }

    /// The parameters.
    pub fn params(&self) -> &TeleopParams<T> {
        &self.params
    }

    /// The controller.
    pub fn controller(&self) -> &Controller<T> {
        &self.controller
    }

    /// The camera.
    pub fn camera(&self) -> &Camera<T> {
        &self.camera
    }

    /// The endoscope's depth, mm.
    pub fn depth(&self) -> T {
        self.depth
    }

    /// One cycle at `t` (s, never decreasing): this cycle's command, the
    /// fault checks, the motion (the hands and the camera when ENABLED, the
    /// home move when busy, a controlled stop otherwise), reduced to stop
    /// short of any limit; returns the twelve setpoints and what happened.
    ///
    /// # Errors
    /// [`TeleopError::NonFiniteTime`] or [`TeleopError::TimeReversed`]; the
    /// core is then unchanged. Nothing else is an error: limits are held,
    /// faults are a state.
    pub fn step(&mut self, t: T, inputs: &Inputs<T>) -> Result<TeleopCycle<T>, TeleopError> {
        if !t.finite() {
            return Err(TeleopError::NonFiniteTime { value: t.to_f64() });
        }
        let dt = match self.last {
            Some(last) if t < last => {
                return Err(TeleopError::TimeReversed {
                    t: t.to_f64(),
                    last: last.to_f64(),
                });
            }
            Some(last) => t - last,
            None => T::zero(),
        };
        let previous = self.last.unwrap_or(t);
        self.last = Some(t);
        let command = inputs.command.map(|c| self.apply(t, previous, c, inputs));
        if self.state == OperatingState::Enabled
            && let Some(fault) = self.input_fault(t, inputs)
        {
            self.enter_fault(fault);
        }
        let enabled = self.state == OperatingState::Enabled;
        let (candidate, from_home) = match (enabled, self.busy) {
            (true, Busy::Move(plan, start)) => (self.home_velocity(t, dt, &plan, start), true),
            (true, Busy::Stop) => (self.brake(dt), false),
            (true, Busy::Idle) => (self.input_velocity(t, dt, inputs), false),
            (false, _) => (self.brake(dt), false),
        };
        let hold = self.advance(dt, &candidate, enabled);
        if hold.is_some() {
            // A held plan or law no longer describes the setpoint; the
            // filters of what was reduced restart from the velocities held
            // (no wind-up: a reversal acts at once). A stop goes on.
            if from_home {
                self.busy = Busy::Idle;
            }
            self.follow = None;
            for h in 0..2 {
                let m = match self.hands[h] {
                    Side::Left => 0,
                    Side::Right => 1,
                };
                if self.velocity.tips[m] != candidate.tips[m] {
                    self.filters[h].hold_at(self.velocity.tips[m].into());
                }
            }
            if self.velocity.angles != candidate.angles {
                self.camera_filter.hold_at(self.velocity.angles);
            }
        } else if from_home
            && let Busy::Move(plan, start) = self.busy
            && t - start >= plan.duration()
        {
            // A move's end: the hands start again from rest and re-anchor
            // (the velocity is the last cycle's, which the next one brings
            // to 0).
            self.busy = Busy::Idle;
            self.reset_inputs();
        } else if matches!(self.busy, Busy::Stop) && self.is_at_rest() {
            // A stop's end: at rest; the hands re-anchor from here.
            self.busy = Busy::Idle;
            self.reset_inputs();
        }
        Ok(self.cycle(t, command, hold))
    }

    /// A command's transition and what it starts or ends; `previous` is the
    /// previous cycle's time, s, where the current setpoint is (a home move
    /// starts there, so that this cycle is its first step).
    fn apply(&mut self, t: T, previous: T, command: Command, inputs: &Inputs<T>) -> CommandOutcome {
        let cleared = self.is_at_rest() && self.input_fault(t, inputs).is_none();
        let before = self.state;
        let tr = before.after(command, cleared);
        if tr.accepted {
            match command {
                Command::Enable if before != OperatingState::Enabled => {
                    self.fault = None;
                    self.hands = self.assign();
                    self.reset_inputs();
                }
                Command::Resume => self.reset_inputs(),
                Command::Home | Command::LookAtTips
                    if self.plan_command(previous, command).is_err() =>
                {
                    return CommandOutcome {
                        command,
                        accepted: false,
                    };
                }
                Command::Stop => {
                    // In ENABLED, the controlled stop to rest (busy); in
                    // the other states the robot is already stopping or
                    // held, and stays so.
                    self.follow = None;
                    self.busy = if before == OperatingState::Enabled {
                        Busy::Stop
                    } else {
                        Busy::Idle
                    };
                }
                Command::Disable | Command::Pause => {
                    self.busy = Busy::Idle;
                    self.follow = None;
                    if command == Command::Disable {
                        self.fault = None;
                    }
                }
                _ => {}
            }
            self.state = tr.state;
        }
        CommandOutcome {
            command,
            accepted: tr.accepted,
        }
    }

    fn reset_inputs(&mut self) {
        for f in &mut self.filters {
            f.reset();
        }
        self.camera_filter.reset();
        self.engaged = [false; 2];
        self.master = [None; 2];
    }

    pub(super) fn enter_fault(&mut self, fault: Fault) {
        self.state = OperatingState::Fault;
        self.fault = Some(fault);
        self.busy = Busy::Idle;
        self.follow = None;
    }

    /// The first fault of this cycle's inputs: a non-finite number, or a
    /// device older than the timeout.
    fn input_fault(&self, t: T, inputs: &Inputs<T>) -> Option<Fault> {
        let devices = [
            (Device::Left, inputs.left.non_finite(), inputs.left.stamp_s),
            (
                Device::Right,
                inputs.right.non_finite(),
                inputs.right.stamp_s,
            ),
            (
                Device::Camera,
                inputs.camera.non_finite(),
                inputs.camera.stamp_s,
            ),
        ];
        for (device, bad, stamp) in devices {
            if let Some((what, value)) = bad {
                return Some(Fault::NonFinite {
                    device,
                    what,
                    value: value.to_f64(),
                });
            }
            let age = t - stamp;
            if age > self.params.timeout_s {
                return Some(Fault::Timeout {
                    device,
                    age_s: age.to_f64(),
                });
            }
        }
        None
    }

    /// The hands' modules from where the tips appear in the image: the left
    /// hand drives the tip on the left of the picture (smaller `u`); the
    /// modules' own sides when a tip is behind the camera.
    fn assign(&self) -> [Side; 2] {
        let frame = &self.step.frame;
        let [l, r] = self
            .tips
            .map(|p| self.camera.project(frame, self.depth, &p));
        if l.in_front && r.in_front && r.u < l.u {
            [Side::Right, Side::Left]
        } else {
            [Side::Left, Side::Right]
        }
    }

    /// The cycle's report.
    fn cycle(
        &self,
        t: T,
        command: Option<CommandOutcome>,
        hold: Option<super::cycle::HoldAt>,
    ) -> TeleopCycle<T> {
        TeleopCycle {
            t,
            state: self.state,
            busy: self.is_busy(),
            command,
            setpoints: step_positions(&self.step),
            step: self.step,
            tips: self.tips,
            tip_velocity: self.velocity.tips,
            angles: [self.pose.psi, self.pose.theta],
            angle_rates: self.velocity.angles,
            margins: self.margins,
            clearance: self.clearance,
            hold,
            fault: self.fault,
            hands: self.hands,
            following: self.follow.is_some(),
        }
    }
}
