//! A simulation's inputs resolved into a typed run, in the units people give
//! them in: what every run shares ([`Scenario`]: the start pose, the tips,
//! the rate, the robot) and what kind of run it is ([`Run`]): a planned
//! [`Timeline`] (the paper's [`Turn`], or a procedure's motions) or an
//! [`Online`] run with commands given while the platform moves (new goals,
//! a stop).
//!
//! The defaults ([`Scenario::paper`]) are the paper's section 4, taken from
//! [`parasils::paper`] and the kinematics' presets;
//! [`Input::resolve`](crate::Input::resolve) starts from them and changes
//! what its user gave.

use std::sync::Arc;

use nalgebra::Vector3;
use parasils::kin::presets;
use parasils::kin::{
    ActuatorStiffness, BodyGeometry, Payload, Pose, RobotGeometry, TipTargets, default_right_tip,
};
use parasils::paper;
use parasils::traj::{Limits, Synchronization};
use parasils_anatomy::Anatomy;
use serde::Serialize;

use crate::motion::{LookAt, MotionGoal, MotionLimits, MotionSpec, turn_goal_rad};
use crate::supervisor::SupervisorTable;

/// A run, resolved: what every run shares (the robot, where it starts, the
/// tips, the rate, the supervisor's thresholds), in user units (mm, deg,
/// Hz), and [`Run`], what kind of run it is: a planned [`Timeline`] of
/// motions (the paper's turn is a timeline of one motion, a procedure one
/// of many) or an [`Online`] run, whose commands the online controller
/// takes while the platform moves.
///
/// [`Input::resolve`](crate::Input::resolve) builds the right kind from
/// what a user gave; a combination no kind holds (a procedure with
/// retargets, the time-optimal timing with a stop) cannot be written down.
/// Build one from [`Scenario::paper`] and change what differs:
///
/// ```
/// use parasils_sim::{Run, Scenario, Turn};
///
/// let s = Scenario {
///     rate_hz: 250.0,
///     run: Run::turn(Turn { psi_deg: -10.0, ..Turn::paper() }),
///     ..Scenario::paper()
/// };
/// assert_eq!(s.turn().map(|t| t.theta_deg), Some(25.0));
/// assert_eq!(s.goal_rad()[0], s.start().psi + (-10f64).to_radians());
/// ```
///
/// Nothing is checked here: [`Simulation::new`](crate::Simulation::new)
/// validates the whole (finite numbers, positive limits and rate, a valid
/// robot) and says what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The platform's pose at `t = 0`: `[x, y, z]` in mm, then
    /// `[psi, theta, phi]` in degrees.
    pub start_mm_deg: [f64; 6],
    /// Samples per second, Hz.
    pub rate_hz: f64,
    /// The left tip at the start, mm, fixed frame.
    pub tip_left_mm: [f64; 3],
    /// The right tip at the start, mm, fixed frame; `None` for the default
    /// ([`default_right_tip`]: the left tip's mirror image across the
    /// platform's `Y'Z'` plane at the start pose, moved 35 mm along `X'` and
    /// 100 mm along `Y'` so that the shafts do not meet).
    pub tip_right_mm: Option<[f64; 3]>,
    /// The robot: module 1 and both instrument modules (library units).
    pub robot: RobotGeometry<f64>,
    /// The endoscope's insertion depth at the start, mm (0 at its port,
    /// positive inwards).
    pub endoscope_depth_mm: f64,
    /// The margin supervisor's thresholds the robot file sets (its
    /// `[supervisor]` table; none by default): they replace the defaults in
    /// the supervisor's warnings and, online, its stops.
    pub supervisor: SupervisorTable,
    /// The shafts' and the endoscope's sizes for the clearance columns (the
    /// robot file's `[bodies]`; assumed by default).
    pub bodies: BodyGeometry<f64>,
    /// The platform with its modules as one rigid body (the robot file's
    /// `[dynamics]`; `None` by default): with it, every sample's actuator
    /// forces hold its weight and move its inertia (Newton-Euler), and the
    /// run writes the force columns ([`Scenario::has_forces`]).
    pub dynamics: Option<Payload<f64>>,
    /// Each actuator's stiffness for the tips' deflections (the robot
    /// file's `[stiffness]`; assumed by default).
    pub stiffness: ActuatorStiffness<f64>,
    /// The force the left tip exerts on the tissue, N, fixed frame; `None`
    /// when not given (zero). With either tip's load (or the robot's
    /// `[dynamics]`) the run writes every actuator's force
    /// ([`columns::FORCES`](crate::columns::FORCES)).
    pub tip_load_left_n: Option<[f64; 3]>,
    /// The force the right tip exerts, N, fixed frame; `None` when not given.
    pub tip_load_right_n: Option<[f64; 3]>,
    /// The forbidden regions (`--anatomy`, a procedure's `anatomy` key):
    /// with them every cycle checks the in-body part of each shaft and of
    /// the endoscope against each region, and the run writes
    /// `no_go_clearance_mm`; `None` when not given.
    pub anatomy: Option<Arc<Anatomy>>,
    /// What kind of run, with what only that kind has.
    pub run: Run,
}

/// What kind of run a [`Scenario`] is.
#[derive(Debug, Clone, PartialEq)]
pub enum Run {
    /// Planned before the first sample: motions one after the other, each
    /// from rest to rest on the control cycle.
    Planned(Timeline),
    /// Run by the online controller, cycle by cycle, with commands given
    /// while the platform moves.
    Online(Online),
}

impl Run {
    /// A planned timeline of one turn, timed by the paper's trapezoids.
    pub fn turn(turn: Turn) -> Self {
        Run::Planned(Timeline {
            motions: Motions::Turn(turn),
            timing: Timing::Trapezoid,
        })
    }

    /// A planned timeline of a procedure's motions, timed by the
    /// trapezoids.
    pub fn procedure(motions: Vec<MotionSpec>) -> Self {
        Run::Planned(Timeline {
            motions: Motions::Procedure(motions),
            timing: Timing::Trapezoid,
        })
    }
}

/// A planned run: its motions and how they are timed.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    /// The motions.
    pub motions: Motions,
    /// How each motion is timed: its trapezoids, or the fastest law within
    /// the actuators' limits.
    pub timing: Timing,
}

/// The motions of a [`Timeline`], as the user gave them.
#[derive(Debug, Clone, PartialEq)]
pub enum Motions {
    /// One turn of the endoscope (motion type 4), given by its angles and
    /// limits: the paper's run. It is planned as a timeline of one
    /// reorientation ([`Turn::motion`]).
    Turn(Turn),
    /// A procedure's motions, in order (see [`MotionSpec`]), each from where
    /// the one before ended.
    Procedure(Vec<MotionSpec>),
}

/// An online run: a turn commanded at `t = 0`, then each command at its
/// time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Online {
    /// The turn commanded at `t = 0`.
    pub turn: Turn,
    /// New goals commanded while the platform moves, in time order. See
    /// [`Command`].
    pub retargets: Vec<Retarget>,
    /// The time of a controlled stop, s from the start; `None` for no stop.
    pub stop_at_s: Option<f64>,
}

/// One endoscope reorientation (motion type 4) in user units: its angles
/// (or what the camera is to look at), its limits and how the two angles
/// are timed together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turn {
    /// `psi`: the increment from the start (or, with `absolute`, the final
    /// value), deg.
    pub psi_deg: f64,
    /// `theta`: the increment from the start (or, with `absolute`, the final
    /// value), deg.
    pub theta_deg: f64,
    /// Whether `psi_deg` and `theta_deg` are final angles rather than
    /// increments.
    pub absolute: bool,
    /// The velocity limit of each Euler angle, deg/s.
    pub omega_max_deg_s: f64,
    /// The acceleration limit of each Euler angle, deg/s^2.
    pub eps_max_deg_s2: f64,
    /// How the two angles are timed together.
    pub sync: Synchronization,
    /// What the camera is to look at, instead of the angles: the turn's
    /// goal is then the `(psi, theta)`, `phi` held, that puts the point on
    /// the view axis ([`parasils::kin::Camera::look_at`], the solution
    /// nearest the start), and `psi_deg`, `theta_deg` and `absolute` are
    /// not used. `None`: the turn is given by its angles.
    pub look_at: Option<LookAt>,
}

impl Default for Turn {
    /// [`Turn::paper`].
    fn default() -> Self {
        Self::paper()
    }
}

impl Turn {
    /// The paper's turn: `psi` and `theta` increased by 15 and 25 deg within
    /// 10 deg/s and 5 deg/s^2, phase-synchronised.
    pub fn paper() -> Self {
        Self {
            psi_deg: paper::PSI_DEG,
            theta_deg: paper::THETA_DEG,
            absolute: false,
            omega_max_deg_s: paper::OMEGA_MAX_DEG_S,
            eps_max_deg_s2: paper::EPS_MAX_DEG_S2,
            sync: Synchronization::Phase,
            look_at: None,
        }
    }

    /// The limits of each angle, rad/s and rad/s^2.
    pub fn limits(&self) -> Limits<f64> {
        Limits::new(
            self.omega_max_deg_s.to_radians(),
            self.eps_max_deg_s2.to_radians(),
        )
    }

    /// `[psi, theta]` given as the turn reads them (increments from `start`
    /// in deg, or final angles with `absolute`) as final angles, rad: the
    /// goal of the turn or of a [`Retarget`].
    pub fn angles_rad(&self, start: &Pose<f64>, [psi_deg, theta_deg]: [f64; 2]) -> [f64; 2] {
        turn_goal_rad(psi_deg, theta_deg, self.absolute, [start.psi, start.theta])
    }

    /// The final `[psi, theta]` from `start`, rad.
    pub fn goal_rad(&self, start: &Pose<f64>) -> [f64; 2] {
        self.angles_rad(start, [self.psi_deg, self.theta_deg])
    }

    /// The turn as a procedure's motion of type 4 (a
    /// [`MotionGoal::LookAt`] when it looks at something), its angular
    /// limits binding under the time-optimal timing when `angular` is true
    /// (see [`Timing::Optimal`]); its `sync` is the timeline's to apply.
    pub fn motion(&self, angular: bool) -> MotionSpec {
        let goal = match self.look_at {
            Some(target) => MotionGoal::LookAt { target },
            None => MotionGoal::Reorient {
                psi_deg: self.psi_deg,
                theta_deg: self.theta_deg,
                absolute: self.absolute,
            },
        };
        MotionSpec {
            limits: MotionLimits {
                velocity_deg_s: self.omega_max_deg_s,
                acceleration_deg_s2: self.eps_max_deg_s2,
                ..MotionLimits::default()
            },
            stated: [false, angular],
            ..MotionSpec::new(goal)
        }
    }
}

/// A new goal commanded at `t_s`: `psi_deg` and `theta_deg` are read like
/// [`Turn::psi_deg`] and [`Turn::theta_deg`] of the online run's turn,
/// increments from the start pose (not from the previous goal), or final
/// angles with [`Turn::absolute`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Retarget {
    /// When the goal is commanded, s from the start.
    pub t_s: f64,
    /// `psi`: increment from the start pose (or final value), deg.
    pub psi_deg: f64,
    /// `theta`: increment from the start pose (or final value), deg.
    pub theta_deg: f64,
}

/// What a command asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CommandKind {
    /// The scenario's own reorientation, commanded at `t = 0`: command 0.
    #[default]
    Reorient,
    /// A new goal ([`Retarget`]), replanned from the state of the motion.
    Retarget,
    /// The controlled stop: psi and theta to rest together, the one needing
    /// longer at its acceleration limit, along the direction of their
    /// velocity.
    Stop,
    /// A controlled stop the online controller's margin supervisor demanded
    /// (not a command of the scenario): a margin was heading below its stop
    /// threshold.
    #[serde(rename = "supervisor_stop")]
    SupervisorStop,
}

impl CommandKind {
    /// The name written out: `"reorient"`, `"retarget"`, `"stop"`,
    /// `"supervisor_stop"`.
    pub const fn name(self) -> &'static str {
        match self {
            CommandKind::Reorient => "reorient",
            CommandKind::Retarget => "retarget",
            CommandKind::Stop => "stop",
            CommandKind::SupervisorStop => "supervisor_stop",
        }
    }
}

impl core::fmt::Display for CommandKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.pad(self.name())
    }
}

/// One command of a run, in time order: the reorientation at `t = 0`
/// (index 0), then each retarget and the stop, numbered from 1 in the order
/// they are commanded. The index is what the output's `command` column
/// holds while the command's motion is the active one.
///
/// A command takes effect at the first sample at or after its time `t_s`;
/// the motion is replanned from the state the active motion has at that
/// sample, so that position and velocity stay continuous.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Command {
    /// The index: 0 for the reorientation, then 1, 2, ...
    pub index: u32,
    /// What it asks for.
    pub kind: CommandKind,
    /// When it is commanded, s from the start.
    pub t_s: f64,
    /// The goal `[psi, theta]` as given (increments from the start, or final
    /// angles with `absolute`), deg; `None` for the stop.
    pub goal_deg: Option<[f64; 2]>,
}

impl Default for Scenario {
    /// [`Scenario::paper`].
    fn default() -> Self {
        Self::paper()
    }
}

impl Scenario {
    /// The paper's scenario: `P0 = (15, 20, -500 mm, -15, 10, -60 deg)`,
    /// [`Turn::paper`] timed by the trapezoids, the left tip at
    /// `(50, -50, -620)` mm and the right one the default (the mirror moved
    /// clear of the left shaft, [`default_right_tip`]), sampled at 1 kHz,
    /// on the paper's robot (module 1 assumed). See `docs/model.md`,
    /// *Check values*.
    pub fn paper() -> Self {
        Self {
            start_mm_deg: presets::START_POSE_MM_DEG,
            rate_hz: paper::RATE_HZ,
            tip_left_mm: TipTargets::<f64>::paper().left.into(),
            tip_right_mm: None,
            robot: RobotGeometry::paper(),
            endoscope_depth_mm: 0.0,
            supervisor: SupervisorTable::default(),
            run: Run::turn(Turn::paper()),
            bodies: BodyGeometry::assumed(),
            dynamics: None,
            stiffness: ActuatorStiffness::assumed(),
            tip_load_left_n: None,
            tip_load_right_n: None,
            anatomy: None,
        }
    }

    /// The turn of the run: a timeline's single turn, or the one an online
    /// run commands at `t = 0`; `None` for a procedure.
    pub fn turn(&self) -> Option<&Turn> {
        match &self.run {
            Run::Planned(Timeline {
                motions: Motions::Turn(turn),
                ..
            })
            | Run::Online(Online { turn, .. }) => Some(turn),
            Run::Planned(_) => None,
        }
    }

    /// The planned timeline; `None` for an online run.
    pub fn timeline(&self) -> Option<&Timeline> {
        match &self.run {
            Run::Planned(timeline) => Some(timeline),
            Run::Online(_) => None,
        }
    }

    /// The online run; `None` for a planned one.
    pub fn online(&self) -> Option<&Online> {
        match &self.run {
            Run::Online(online) => Some(online),
            Run::Planned(_) => None,
        }
    }

    /// A procedure's motions; empty for a turn or an online run.
    pub fn motions(&self) -> &[MotionSpec] {
        match &self.run {
            Run::Planned(Timeline {
                motions: Motions::Procedure(m),
                ..
            }) => m,
            _ => &[],
        }
    }

    /// Whether the run writes every actuator's force
    /// ([`columns::FORCES`](crate::columns::FORCES)): with a tip load, or
    /// with the robot file's `[dynamics]` (even of mass 0: the table asks
    /// for the forces; they are then the tips' alone).
    pub fn has_forces(&self) -> bool {
        self.tip_load_left_n.is_some() || self.tip_load_right_n.is_some() || self.dynamics.is_some()
    }

    /// Whether the run is a procedure's (its output names each motion and
    /// follows the endoscope).
    pub fn is_procedure(&self) -> bool {
        matches!(
            &self.run,
            Run::Planned(Timeline {
                motions: Motions::Procedure(_),
                ..
            })
        )
    }

    /// Whether the run goes through the online controller with commands
    /// (retargets, a stop): its output has the `command` column.
    pub fn has_commands(&self) -> bool {
        matches!(self.run, Run::Online(_))
    }

    /// The scenario with its timeline timed by `timing` (an online run, which
    /// the trapezoids time, unchanged).
    #[must_use]
    pub fn with_timing(mut self, timing: Timing) -> Self {
        if let Run::Planned(timeline) = &mut self.run {
            timeline.timing = timing;
        }
        self
    }

    /// How a planned run is timed; the trapezoids for an online run.
    pub fn timing(&self) -> Timing {
        self.timeline().map_or(Timing::Trapezoid, |t| t.timing)
    }

    /// The commands in the order they are given: the turn at `t = 0`
    /// (without a goal in a procedure), then, online, the retargets and the
    /// stop merged by time (the stop before a retarget given for the same
    /// time; such a scenario does not validate).
    pub fn commands(&self) -> Vec<Command> {
        let online = self.online();
        let mut out = Vec::with_capacity(online.map_or(0, |o| o.retargets.len()) + 2);
        out.push(Command {
            index: 0,
            kind: CommandKind::Reorient,
            t_s: 0.0,
            goal_deg: self.turn().map(|t| match t.look_at {
                // A look-at: the increments the camera's aim asks for.
                Some(_) => {
                    let (start, [psi, theta]) = (self.start(), self.goal_rad());
                    [
                        (psi - start.psi).to_degrees(),
                        (theta - start.theta).to_degrees(),
                    ]
                }
                None => [t.psi_deg, t.theta_deg],
            }),
        });
        let Some(online) = online else {
            return out;
        };
        let mut stop = online.stop_at_s;
        let push = |out: &mut Vec<Command>, kind, t_s, goal_deg| {
            let index = u32::try_from(out.len()).unwrap_or(u32::MAX);
            out.push(Command {
                index,
                kind,
                t_s,
                goal_deg,
            });
        };
        for r in &online.retargets {
            if let Some(t) = stop.filter(|t| *t <= r.t_s) {
                push(&mut out, CommandKind::Stop, t, None);
                stop = None;
            }
            push(
                &mut out,
                CommandKind::Retarget,
                r.t_s,
                Some([r.psi_deg, r.theta_deg]),
            );
        }
        if let Some(t) = stop {
            push(&mut out, CommandKind::Stop, t, None);
        }
        out
    }

    /// The start pose in library units (mm, rad).
    pub fn start(&self) -> Pose<f64> {
        let [x, y, z, psi, theta, phi] = self.start_mm_deg;
        Pose::from_mm_deg(x, y, z, psi, theta, phi)
    }

    /// The final `[psi, theta]` of the run's turn, rad; the start's for a
    /// procedure (which has no turn of its own). A turn that looks at a
    /// point has the camera's aim ([`Scenario::look_at_rad`]), or the
    /// start's angles when there is none (planning the run says why).
    pub fn goal_rad(&self) -> [f64; 2] {
        let start = self.start();
        match self.turn() {
            Some(Turn {
                look_at: Some(_), ..
            }) => self
                .look_at_rad()
                .and_then(Result::ok)
                .unwrap_or([start.psi, start.theta]),
            Some(t) => t.goal_rad(&start),
            None => [start.psi, start.theta],
        }
    }

    /// The point the run's turn looks at, mm, fixed frame (the tips where
    /// the run starts, which the turn holds); `None` for a turn given by its
    /// angles and for a procedure.
    pub fn look_at_mm(&self) -> Option<[f64; 3]> {
        let look = self.turn()?.look_at?;
        let tips = self.tips();
        Some(look.point([tips.left.into(), tips.right.into()]))
    }

    /// The `[psi, theta]` (rad) that aim the robot's camera at
    /// [`Scenario::look_at_mm`] from the start, `phi` held; `None` for a
    /// turn given by its angles.
    pub fn look_at_rad(&self) -> Option<Result<[f64; 2], parasils::kin::CameraError>> {
        let point = Vector3::from(self.look_at_mm()?);
        Some(
            self.robot
                .endoscope
                .camera
                .look_at(&self.start(), self.endoscope_depth_mm, &point),
        )
    }

    /// `[psi, theta]` given as the run's turn reads them (increments from
    /// the start pose in deg, or final angles with `absolute`) as final
    /// angles, rad: the goal of the turn or of a [`Retarget`].
    pub fn angles_rad(&self, angles_deg: [f64; 2]) -> [f64; 2] {
        let turn = self.turn().copied().unwrap_or_default();
        turn.angles_rad(&self.start(), angles_deg)
    }

    /// The limits of each angle of the run's turn, rad/s and rad/s^2 (the
    /// paper's for a procedure).
    pub fn limits(&self) -> Limits<f64> {
        self.turn().copied().unwrap_or_default().limits()
    }

    /// The two tips at the start, mm, fixed frame (the right one
    /// resolved).
    pub fn tips(&self) -> TipTargets<f64> {
        let left = Vector3::from(self.tip_left_mm);
        TipTargets {
            left,
            right: self
                .tip_right_mm
                .map_or_else(|| default_right_tip(&self.start(), &left), Vector3::from),
        }
    }

    /// The scenario in library units (mm, rad, s), as the MCAP file's
    /// `parasils.scenario` metadata records it (a procedure with the
    /// paper's turn, which it does not use, as it always has).
    pub fn library_units(&self) -> LibraryUnits<'_> {
        let start = self.start();
        let turn = self.turn().copied().unwrap_or_default();
        let (retargets, stop_at) = match self.online() {
            Some(o) => (o.retargets.as_slice(), o.stop_at_s),
            None => (&[][..], None),
        };
        LibraryUnits {
            start,
            psi: turn.psi_deg.to_radians(),
            theta: turn.theta_deg.to_radians(),
            absolute: turn.absolute,
            omega_max: turn.omega_max_deg_s.to_radians(),
            eps_max: turn.eps_max_deg_s2.to_radians(),
            sync: turn.sync,
            rate_hz: self.rate_hz,
            tip_left: self.tip_left_mm,
            tip_right: self.tip_right_mm,
            robot: &self.robot,
            retargets: retargets
                .iter()
                .map(|r| RetargetUnits {
                    t: r.t_s,
                    psi: r.psi_deg.to_radians(),
                    theta: r.theta_deg.to_radians(),
                })
                .collect(),
            stop_at,
            motions: self.motions(),
            endoscope_depth_mm: self.is_procedure().then_some(self.endoscope_depth_mm),
            timing: self.timing(),
            look_at: turn.look_at,
        }
    }
}

/// How a timeline's motions are timed along their paths.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Timing {
    /// The paper's: each motion's coordinates on synchronised trapezoids
    /// within its limits (a turn's `psi` and `theta` within
    /// [`Turn::omega_max_deg_s`] and [`Turn::eps_max_deg_s2`]).
    #[default]
    Trapezoid,
    /// The fastest rest-to-rest law whose twelve actuators stay within their
    /// velocity and acceleration limits (the robot's); a turn's angular
    /// limits bind as well when `angular` is true, a procedure's motion's
    /// when the procedure states them (see [`crate::timing`]).
    Optimal {
        /// Whether [`Turn::omega_max_deg_s`] and [`Turn::eps_max_deg_s2`]
        /// of a [`Motions::Turn`] bind too.
        angular: bool,
    },
}

/// A [`Retarget`] in library units (s, rad), for records.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RetargetUnits {
    /// When the goal is commanded, s.
    pub t: f64,
    /// `psi`: increment (or final value), rad.
    pub psi: f64,
    /// `theta`: increment (or final value), rad.
    pub theta: f64,
}

/// A [`Scenario`] in library units (mm, rad, s), for records: the MCAP
/// file's `parasils.scenario` metadata is this, serialised as JSON (the
/// commands only when there are some, so that a run without them is
/// recorded as before they existed).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LibraryUnits<'a> {
    /// The start pose, mm and rad.
    pub start: Pose<f64>,
    /// `psi`: increment (or final value), rad.
    pub psi: f64,
    /// `theta`: increment (or final value), rad.
    pub theta: f64,
    /// Whether `psi` and `theta` are final angles.
    pub absolute: bool,
    /// Velocity limit, rad/s.
    pub omega_max: f64,
    /// Acceleration limit, rad/s^2.
    pub eps_max: f64,
    /// Synchronisation.
    pub sync: Synchronization,
    /// Samples per second, Hz.
    pub rate_hz: f64,
    /// The left tip, mm.
    pub tip_left: [f64; 3],
    /// The right tip, mm, if given.
    pub tip_right: Option<[f64; 3]>,
    /// The robot.
    pub robot: &'a RobotGeometry<f64>,
    /// The retargets (times in s, angles in rad), if any.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub retargets: Vec<RetargetUnits>,
    /// The time of the stop, s, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop_at: Option<f64>,
    /// A procedure's motions, as given (in their own units: mm, deg, mm/s,
    /// deg/s, s), if any.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub motions: &'a [MotionSpec],
    /// A procedure's starting endoscope depth, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub endoscope_depth_mm: Option<f64>,
    /// The timing, when it is not the paper's trapezoid.
    #[serde(skip_serializing_if = "is_trapezoid")]
    pub timing: Timing,
    /// What the turn looks at, when it is given so (`{"look_at_mm": [x, y,
    /// z]}` or `{"look_at": "tips"}`); `psi` and `theta` are then unused.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub look_at: Option<LookAt>,
}

fn is_trapezoid(t: &Timing) -> bool {
    *t == Timing::Trapezoid
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_start_is_the_kinematics_own() {
        let s = Scenario::paper();
        assert_eq!(s.start(), Pose::paper_start());
        assert_eq!(s.tips(), TipTargets::paper());
        let [psi, theta] = s.goal_rad();
        assert_eq!(psi, Pose::<f64>::paper_start().psi + 15f64.to_radians());
        assert_eq!(theta, Pose::<f64>::paper_start().theta + 25f64.to_radians());
    }

    #[test]
    fn absolute_angles_are_the_goal() {
        let s = Scenario {
            run: Run::turn(Turn {
                absolute: true,
                psi_deg: 5.0,
                theta_deg: -5.0,
                ..Turn::paper()
            }),
            ..Scenario::paper()
        };
        assert_eq!(s.goal_rad(), [5f64.to_radians(), (-5f64).to_radians()]);
    }
}
