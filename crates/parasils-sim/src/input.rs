//! What a user asks `simulate` for, as given: the one input model of every
//! front end.
//!
//! The command line, the Python bindings and the fuzz targets only translate
//! their own syntax into an [`Input`]; [`Input::resolve`] then applies the
//! rules, once, for all of them:
//! - **not given is not the default.** Every field is `None` until the user
//!   gives it, so "given the paper's value" and "not given" stay distinct:
//!   `--omega-max 10` binds under `--timing optimal` although 10 deg/s is the
//!   paper's limit, and so does `omega_max_deg_s=10`;
//! - **the defaults** are the paper's ([`Scenario::paper`]);
//! - **the exclusions**: a procedure brings its own start, robot and motions,
//!   so only the rate, the timing and the tip loads may be given with it
//!   ([`InputError::WithProcedure`] names the first field that may not);
//! - **what a turn is given by**: its angles (`psi_deg`, `theta_deg`,
//!   `absolute`) or what the camera is to look at (`look_at`), never both
//!   ([`InputError::Conflict`]); a look-at takes no command either, since a
//!   retarget's angles are read like the turn's;
//! - **the timing rule**: under [`TimingKind::Optimal`], the angular limits
//!   bind only when one of them is given, and no command (retarget, stop)
//!   may be given ([`InputError::OptimalOnline`]);
//! - **the kind of run**: a procedure, or the turn alone, is a planned
//!   [`Timeline`]; a turn with commands an [`Online`] run ([`Run`]);
//! - **files are read once**: a robot file into one [`Robot`] (geometry and
//!   supervisor thresholds), a procedure into its scenario.
//!
//! ```
//! use parasils_sim::input::{Input, TimingKind};
//! use parasils_sim::scenario::{Run, Timing, Turn};
//!
//! // Given, even at the paper's value: the angular limits bind.
//! let given = Input {
//!     timing: Some(TimingKind::Optimal),
//!     omega_max_deg_s: Some(10.0),
//!     ..Input::default()
//! }
//! .resolve()?;
//! assert_eq!(given.timing(), Timing::Optimal { angular: true });
//! assert_eq!(given.turn().map(|t| t.omega_max_deg_s), Some(10.0));
//!
//! // Not given: only the actuators' limits bind.
//! let free = Input { timing: Some(TimingKind::Optimal), ..Input::default() }.resolve()?;
//! assert_eq!(free.timing(), Timing::Optimal { angular: false });
//!
//! // A stop makes it an online run.
//! let online = Input { stop_at_s: Some(2.0), ..Input::default() }.resolve()?;
//! assert!(matches!(&online.run, Run::Online(o) if o.turn == Turn::paper()));
//!
//! // Nothing given is the paper's scenario.
//! assert_eq!(Input::default().resolve()?, parasils_sim::Scenario::paper());
//! # Ok::<(), parasils_sim::input::InputError>(())
//! ```

use std::path::{Path, PathBuf};
use std::sync::Arc;

use parasils_anatomy::{Anatomy, AnatomyError};

use parasils::traj::Synchronization;

use crate::motion::{LookAt, LookAtTips};
use crate::procedure::{self, ProcedureError};
use crate::robot::Robot;
use crate::robot_file::{self, RobotFileError};
use crate::scenario::{Motions, Online, Retarget, Run, Scenario, Timeline, Timing, Turn};

/// A procedure as a front end has it.
#[derive(Debug, Clone, PartialEq)]
pub enum ProcedureSource {
    /// A procedure file (TOML); a robot it names is read relative to the
    /// file's folder.
    File(PathBuf),
    /// JSON text of the same structure (what Python sends for a dict); a
    /// robot it names is read relative to the working directory.
    Json(String),
}

/// A robot as a front end has it.
#[derive(Debug, Clone, PartialEq)]
pub enum RobotSource {
    /// A robot file, read once by [`Input::resolve`].
    File(PathBuf),
    /// A robot already read (Python's `parasils.Robot`), with its
    /// supervisor thresholds.
    Loaded(Box<Robot>),
}

/// How the reorientation (or each motion of a procedure) is timed, as a user
/// names it; [`Input::resolve`] turns it into a [`Timing`] with the rule for
/// the angular limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TimingKind {
    /// The paper's synchronised trapezoids within the angular limits.
    #[default]
    Trapezoid,
    /// The fastest rest-to-rest law within the actuators' limits.
    Optimal,
}

/// Every field of an [`Input`], named as the libraries and Python name it
/// and as the command line spells it, so that an error can name the field
/// in its user's own words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum InputField {
    /// `procedure`, `--procedure`.
    Procedure,
    /// `psi_deg`, `--psi`.
    PsiDeg,
    /// `theta_deg`, `--theta`.
    ThetaDeg,
    /// `absolute`, `--absolute`.
    Absolute,
    /// `omega_max_deg_s`, `--omega-max`.
    OmegaMaxDegS,
    /// `eps_max_deg_s2`, `--eps-max`.
    EpsMaxDegS2,
    /// `sync`, `--sync`.
    Sync,
    /// `timing`, `--timing`.
    Timing,
    /// `rate_hz`, `--rate`.
    RateHz,
    /// `pose_mm_deg`, `--pose`.
    PoseMmDeg,
    /// `tip_left_mm`, `--tip-left`.
    TipLeftMm,
    /// `tip_right_mm`, `--tip-right`.
    TipRightMm,
    /// `robot`, `--robot`.
    Robot,
    /// `retarget`, `--retarget`.
    Retarget,
    /// `stop_at_s`, `--stop-at`.
    StopAtS,
    /// `tip_load_left_n`, `--tip-load-left`.
    TipLoadLeftN,
    /// `tip_load_right_n`, `--tip-load-right`.
    TipLoadRightN,
    /// `look_at`, `--look-at`.
    LookAt,
    /// `anatomy`, `--anatomy`.
    Anatomy,
}

impl InputField {
    /// The name in Rust and Python: `omega_max_deg_s`.
    pub const fn name(self) -> &'static str {
        self.names().0
    }

    /// The command line's flag: `--omega-max`.
    pub const fn flag(self) -> &'static str {
        self.names().1
    }

    const fn names(self) -> (&'static str, &'static str) {
        match self {
            Self::Procedure => ("procedure", "--procedure"),
            Self::PsiDeg => ("psi_deg", "--psi"),
            Self::ThetaDeg => ("theta_deg", "--theta"),
            Self::Absolute => ("absolute", "--absolute"),
            Self::OmegaMaxDegS => ("omega_max_deg_s", "--omega-max"),
            Self::EpsMaxDegS2 => ("eps_max_deg_s2", "--eps-max"),
            Self::Sync => ("sync", "--sync"),
            Self::Timing => ("timing", "--timing"),
            Self::RateHz => ("rate_hz", "--rate"),
            Self::PoseMmDeg => ("pose_mm_deg", "--pose"),
            Self::TipLeftMm => ("tip_left_mm", "--tip-left"),
            Self::TipRightMm => ("tip_right_mm", "--tip-right"),
            Self::Robot => ("robot", "--robot"),
            Self::Retarget => ("retarget", "--retarget"),
            Self::StopAtS => ("stop_at_s", "--stop-at"),
            Self::TipLoadLeftN => ("tip_load_left_n", "--tip-load-left"),
            Self::TipLoadRightN => ("tip_load_right_n", "--tip-load-right"),
            Self::LookAt => ("look_at", "--look-at"),
            Self::Anatomy => ("anatomy", "--anatomy"),
        }
    }
}

impl core::fmt::Display for InputField {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.pad(self.name())
    }
}

/// Why an [`Input`] does not resolve.
///
/// # When this happens, how to handle it
/// - [`InputError::WithProcedure`]: drop the field, or put it in the
///   procedure file.
/// - [`InputError::OptimalOnline`]: drop the command, or the optimal
///   timing.
/// - [`InputError::Unknown`]: use one of the names the message lists.
/// - [`InputError::Conflict`]: give one of the two fields.
/// - [`InputError::Procedure`], [`InputError::Robot`],
///   [`InputError::Anatomy`]: fix the file where the message says.
/// - [`InputError::AnatomyTwice`]: give the anatomy in the procedure file
///   or on its own, not both.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// A field was given together with a procedure, which has its own
    /// start, robot and motions.
    #[error(
        "{0} cannot be given with a procedure: a procedure has its own start, robot and motions"
    )]
    WithProcedure(InputField),
    /// A field's value is not one of the names it takes.
    #[error("{field} must be {expected}, got {value:?}")]
    Unknown {
        /// The field.
        field: InputField,
        /// What was given.
        value: String,
        /// The names it takes, as a phrase: `'phase', 'time' or 'none'`.
        expected: &'static str,
    },
    /// The procedure does not read.
    #[error(transparent)]
    Procedure(#[from] ProcedureError),
    /// The robot file does not read.
    #[error(transparent)]
    Robot(#[from] RobotFileError),
    /// The anatomy file does not read.
    #[error(transparent)]
    Anatomy(#[from] AnatomyError),
    /// An anatomy was given together with a procedure that names its own:
    /// which one is meant cannot be guessed.
    #[error(
        "anatomy cannot be given with a procedure that names its own anatomy file: drop one of the two"
    )]
    AnatomyTwice,
    /// The time-optimal timing was asked for together with a command (a
    /// retarget or a stop): it plans motions from rest to rest, ahead,
    /// while commands are taken online.
    #[error(
        "{0} cannot be given with the optimal timing: it plans one motion from rest to rest, while commands are taken online"
    )]
    OptimalOnline(InputField),
    /// Two fields that say the same thing two ways were both given: a turn
    /// is given by its angles or by what the camera looks at.
    #[error("{field} cannot be given with {with}: {why}")]
    Conflict {
        /// The field given.
        field: InputField,
        /// The field it excludes, also given.
        with: InputField,
        /// Why, as a phrase.
        why: &'static str,
    },
}

impl InputError {
    /// The field the error is about.
    pub fn field(&self) -> InputField {
        match self {
            Self::WithProcedure(field)
            | Self::OptimalOnline(field)
            | Self::Unknown { field, .. }
            | Self::Conflict { field, .. } => *field,
            Self::Procedure(_) => InputField::Procedure,
            Self::Robot(_) => InputField::Robot,
            Self::Anatomy(_) | Self::AnatomyTwice => InputField::Anatomy,
        }
    }
}

/// What a user asks a simulation for, in user units (mm, deg, deg/s,
/// deg/s^2, Hz, s): each field `None` when not given. See the [module
/// docs](self) for the rules [`Input::resolve`] applies.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Input {
    /// A procedure: the motions of a file, each from where the previous one
    /// ended; it gives the start, the tips and the robot.
    pub procedure: Option<ProcedureSource>,
    /// `psi`: the increment from the start (or, with `absolute`, the final
    /// value), deg. Default: 15.
    pub psi_deg: Option<f64>,
    /// `theta`: the increment from the start (or the final value), deg.
    /// Default: 25.
    pub theta_deg: Option<f64>,
    /// Whether `psi_deg` and `theta_deg` are final angles. Default: false.
    pub absolute: Option<bool>,
    /// The velocity limit of each Euler angle, deg/s. Default: 10; under
    /// the optimal timing it binds only when given.
    pub omega_max_deg_s: Option<f64>,
    /// The acceleration limit of each Euler angle, deg/s^2. Default: 5;
    /// under the optimal timing it binds only when given.
    pub eps_max_deg_s2: Option<f64>,
    /// How psi and theta are timed together. Default: phase.
    pub sync: Option<Synchronization>,
    /// The timing law. Default: the trapezoid.
    pub timing: Option<TimingKind>,
    /// Samples per second, Hz. Default: 1000.
    pub rate_hz: Option<f64>,
    /// The start pose `[x, y, z]` mm, `[psi, theta, phi]` deg. Default: the
    /// paper's `P0`.
    pub pose_mm_deg: Option<[f64; 6]>,
    /// The left tip, held still, mm, fixed frame. Default: the paper's.
    pub tip_left_mm: Option<[f64; 3]>,
    /// The right tip, mm. Default: [`parasils::kin::default_right_tip`], the
    /// left one's mirror image across the platform's `Y'Z'` plane at the
    /// start, moved 35 mm along `X'` and 100 mm along `Y'` (see
    /// [`Input::mirrored_right_tip_mm`] for the mirror itself).
    pub tip_right_mm: Option<[f64; 3]>,
    /// The robot. Default: the paper's (module 1 assumed).
    pub robot: Option<RobotSource>,
    /// New goals commanded while the platform moves, in time order.
    pub retarget: Option<Vec<Retarget>>,
    /// The time of a controlled stop, s.
    pub stop_at_s: Option<f64>,
    /// The force the left tip exerts on the tissue, N, fixed frame.
    /// Default: none (zero), and no force columns unless a tip load is
    /// given. Allowed with a procedure.
    pub tip_load_left_n: Option<[f64; 3]>,
    /// The force the right tip exerts, N, fixed frame. Default: none.
    pub tip_load_right_n: Option<[f64; 3]>,
    /// What the camera is to look at: a point (mm, fixed frame) or the
    /// tips (their midpoint, or one of them), instead of `psi_deg`,
    /// `theta_deg` and `absolute`. Default: none (the turn's angles).
    pub look_at: Option<LookAt>,
    /// An anatomy file (TOML) of forbidden regions, read once. Default:
    /// none. Allowed with a procedure that names none itself.
    pub anatomy: Option<PathBuf>,
}

impl Input {
    /// The fields a procedure brings itself, each with whether it is given.
    fn given_besides_procedure(&self) -> [(InputField, bool); 13] {
        [
            (InputField::LookAt, self.look_at.is_some()),
            (InputField::PsiDeg, self.psi_deg.is_some()),
            (InputField::ThetaDeg, self.theta_deg.is_some()),
            (InputField::Absolute, self.absolute.is_some()),
            (InputField::OmegaMaxDegS, self.omega_max_deg_s.is_some()),
            (InputField::EpsMaxDegS2, self.eps_max_deg_s2.is_some()),
            (InputField::Sync, self.sync.is_some()),
            (InputField::PoseMmDeg, self.pose_mm_deg.is_some()),
            (InputField::TipLeftMm, self.tip_left_mm.is_some()),
            (InputField::TipRightMm, self.tip_right_mm.is_some()),
            (InputField::Robot, self.robot.is_some()),
            (InputField::Retarget, self.retarget.is_some()),
            (InputField::StopAtS, self.stop_at_s.is_some()),
        ]
    }

    /// The left tip's exact mirror image across the platform's `Y'Z'` plane
    /// at the start pose, mm, fixed frame, for this input's pose and left tip
    /// (each the paper's when not given): the right tip before the default
    /// moved it, which makes the two shafts intersect; what
    /// `--tip-right mirror` gives.
    pub fn mirrored_right_tip_mm(&self) -> [f64; 3] {
        let [x, y, z, psi, theta, phi] = self
            .pose_mm_deg
            .unwrap_or(parasils::kin::presets::START_POSE_MM_DEG);
        let pose = parasils::kin::Pose::from_mm_deg(x, y, z, psi, theta, phi);
        let left = nalgebra::Vector3::from(
            self.tip_left_mm
                .unwrap_or(parasils::kin::presets::LEFT_TIP_MM),
        );
        parasils::kin::mirror_across_platform(&pose, &left).into()
    }

    /// The scenario this input asks for: the paper's wherever a field is not
    /// given, files read (once each).
    ///
    /// Values are not checked here: [`Simulation::new`](crate::Simulation::new)
    /// validates the whole and says what is wrong.
    ///
    /// # Errors
    /// [`InputError::WithProcedure`] for a field given with a procedure,
    /// [`InputError::OptimalOnline`] for a retarget or a stop given with the
    /// optimal timing, [`InputError::Conflict`] for `look_at` given with an
    /// angle, `absolute`, a retarget or a stop,
    /// [`InputError::Procedure`] and [`InputError::Robot`] for files that do
    /// not read.
    pub fn resolve(self) -> Result<Scenario, InputError> {
        let angular = self.omega_max_deg_s.is_some() || self.eps_max_deg_s2.is_some();
        let timing = match self.timing.unwrap_or_default() {
            TimingKind::Trapezoid => Timing::Trapezoid,
            TimingKind::Optimal => Timing::Optimal { angular },
        };
        let paper = Scenario::paper();
        let rate_hz = self.rate_hz.unwrap_or(paper.rate_hz);
        if let Some(procedure) = &self.procedure {
            if let Some((field, _)) = self.given_besides_procedure().iter().find(|(_, g)| *g) {
                return Err(InputError::WithProcedure(*field));
            }
            let scenario = match procedure {
                ProcedureSource::File(path) => procedure::load(path)?,
                ProcedureSource::Json(text) => procedure::parse_json(text, Path::new("."))?,
            };
            let mut scenario = scenario;
            scenario.rate_hz = rate_hz;
            scenario.tip_load_left_n = self.tip_load_left_n;
            scenario.tip_load_right_n = self.tip_load_right_n;
            if let Some(path) = &self.anatomy {
                if scenario.anatomy.is_some() {
                    return Err(InputError::AnatomyTwice);
                }
                scenario.anatomy = Some(Arc::new(Anatomy::load(path)?));
            }
            if let Run::Planned(timeline) = &mut scenario.run {
                timeline.timing = timing;
            }
            return Ok(scenario);
        }
        let retargets = self.retarget.unwrap_or_default();
        let commanded = if retargets.is_empty() {
            self.stop_at_s.map(|_| InputField::StopAtS)
        } else {
            Some(InputField::Retarget)
        };
        if let (Some(field), Some(TimingKind::Optimal)) = (commanded, self.timing) {
            return Err(InputError::OptimalOnline(field));
        }
        if self.look_at.is_some() {
            let angles = [
                (InputField::PsiDeg, self.psi_deg.is_some()),
                (InputField::ThetaDeg, self.theta_deg.is_some()),
                (InputField::Absolute, self.absolute.is_some()),
            ];
            if let Some((with, _)) = angles.iter().find(|(_, g)| *g) {
                return Err(InputError::Conflict {
                    field: InputField::LookAt,
                    with: *with,
                    why: "the turn is given either by its angles or by what the camera looks at",
                });
            }
            if let Some(with) = commanded {
                return Err(InputError::Conflict {
                    field: InputField::LookAt,
                    with,
                    why: "commands are read like the turn's angles, which a look-at does not give",
                });
            }
        }
        let robot = match self.robot {
            None => Robot::paper(),
            Some(RobotSource::File(path)) => robot_file::load_robot(path)?,
            Some(RobotSource::Loaded(robot)) => *robot,
        };
        let p = Turn::paper();
        // A look-at gives no angles: none, rather than the paper's.
        let unused = self.look_at.map(|_| 0.0);
        let turn = Turn {
            psi_deg: self.psi_deg.or(unused).unwrap_or(p.psi_deg),
            theta_deg: self.theta_deg.or(unused).unwrap_or(p.theta_deg),
            absolute: self.absolute.unwrap_or(p.absolute),
            omega_max_deg_s: self.omega_max_deg_s.unwrap_or(p.omega_max_deg_s),
            eps_max_deg_s2: self.eps_max_deg_s2.unwrap_or(p.eps_max_deg_s2),
            sync: self.sync.unwrap_or(p.sync),
            look_at: self.look_at,
        };
        let run = match commanded {
            Some(_) => Run::Online(Online {
                turn,
                retargets,
                stop_at_s: self.stop_at_s,
            }),
            None => Run::Planned(Timeline {
                motions: Motions::Turn(turn),
                timing,
            }),
        };
        Ok(Scenario {
            start_mm_deg: self.pose_mm_deg.unwrap_or(paper.start_mm_deg),
            rate_hz,
            tip_left_mm: self.tip_left_mm.unwrap_or(paper.tip_left_mm),
            tip_right_mm: self.tip_right_mm,
            robot: robot.geometry,
            supervisor: robot.supervisor,
            run,
            bodies: robot.bodies,
            dynamics: robot.dynamics,
            stiffness: robot.stiffness,
            tip_load_left_n: self.tip_load_left_n,
            tip_load_right_n: self.tip_load_right_n,
            anatomy: self
                .anatomy
                .map(|path| Anatomy::load(path).map(Arc::new))
                .transpose()?,
            ..paper
        })
    }
}

/// `name` as a [`Synchronization`]: `"phase"`, `"time"` or `"none"`.
///
/// # Errors
/// [`InputError::Unknown`] naming `sync` for any other name.
pub fn sync_named(name: &str) -> Result<Synchronization, InputError> {
    match name {
        "phase" => Ok(Synchronization::Phase),
        "time" => Ok(Synchronization::Time),
        "none" => Ok(Synchronization::None),
        _ => Err(InputError::Unknown {
            field: InputField::Sync,
            value: name.into(),
            expected: "'phase', 'time' or 'none'",
        }),
    }
}

/// `text` as a [`LookAt`]: `"tips"`, `"left"` or `"right"`, or a point
/// `"X,Y,Z"` (mm, fixed frame), as `--look-at` takes it.
///
/// # Errors
/// [`InputError::Unknown`] naming `look_at` for anything else.
pub fn look_at_named(text: &str) -> Result<LookAt, InputError> {
    let unknown = || InputError::Unknown {
        field: InputField::LookAt,
        value: text.into(),
        expected: "'tips', 'left', 'right' or a point X,Y,Z in mm",
    };
    match text.trim() {
        "tips" => return Ok(LookAt::Tips(LookAtTips::Tips)),
        "left" => return Ok(LookAt::Tips(LookAtTips::Left)),
        "right" => return Ok(LookAt::Tips(LookAtTips::Right)),
        _ => {}
    }
    let parts: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| unknown())?;
    match parts[..] {
        [x, y, z] if parts.iter().all(|v| v.is_finite()) => Ok(LookAt::Point([x, y, z])),
        _ => Err(unknown()),
    }
}

/// `name` as a [`TimingKind`]: `"trapezoid"` or `"optimal"`.
///
/// # Errors
/// [`InputError::Unknown`] naming `timing` for any other name.
pub fn timing_named(name: &str) -> Result<TimingKind, InputError> {
    match name {
        "trapezoid" => Ok(TimingKind::Trapezoid),
        "optimal" => Ok(TimingKind::Optimal),
        _ => Err(InputError::Unknown {
            field: InputField::Timing,
            value: name.into(),
            expected: "'trapezoid' or 'optimal'",
        }),
    }
}
