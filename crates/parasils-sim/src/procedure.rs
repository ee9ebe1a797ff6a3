//! Procedures: a surgical task as a sequence of motions of the paper's four
//! types, each starting where the previous one ended, read from a TOML file
//! (the format of `procedures/sils-demo.toml`) or from JSON of the same
//! structure (the Python bindings' dicts) into a [`Scenario`] whose run is
//! a planned timeline of these motions
//! ([`Motions::Procedure`](crate::scenario::Motions::Procedure)); the start
//! (pose, tips, endoscope depth, robot) is the file's, the sampling rate
//! the caller's.
//! [`Simulation::new`](crate::Simulation::new) plans every motion and checks
//! the whole procedure before a record is written (see
//! [`ProcedureCheck`](crate::ProcedureCheck)).
//!
//! The file has the robot file's habits (every key names its unit):
//!
//! ```toml
//! robot = "../robots/default.toml"    # optional, relative to this file
//! anatomy = "anatomy/demo.toml"       # optional, forbidden regions, relative to this file
//! pose = [15, 20, -460, -15, 10, -60] # start pose, mm and deg (default: the paper's P0)
//! tip_left_mm = [50, -50, -580]       # start tips (joints from the IK, mode A)
//! # tip_right_mm: default the left tip's mirror across the platform at the start,
//! #   moved 35 mm along X' and 100 mm along Y' (parasils_kin::default_right_tip)
//! endoscope_depth_mm = 0              # default 0
//!
//! [[motion]]
//! type = "position"                   # 1: pose = [x, y, z, psi, theta, phi], absolute
//! pose = [15, 20, -500, -15, 10, -60]
//! [[motion]]
//! type = "insert"                     # 2: instrument = "left", "right" or "endoscope"
//! instrument = "endoscope"
//! depth_mm = 60                       # signed, positive inwards
//! [[motion]]
//! type = "manipulate"                 # 3: instrument = "left" or "right" with tip_mm,
//! instrument = "left"                 #    or "both" with tip_left_mm and tip_right_mm
//! tip_mm = [60, -40, -630]
//! camera = "follow"                   #    optional: the camera follows the tips
//! [[motion]]
//! type = "reorient"                   # 4: increments, or final angles with absolute = true
//! psi_deg = 15
//! theta_deg = 25
//! [[motion]]
//! type = "reorient"                   # 4, aimed: look_at_mm = [x, y, z], or
//! look_at = "tips"                    #    look_at = "tips", "left" or "right"
//! ```
//!
//! Each motion may also give `name` and its limits: `velocity_mm_s` and
//! `acceleration_mm_s2` (types 1 to 3), `velocity_deg_s` and
//! `acceleration_deg_s2` (types 1 and 4); see
//! [`MotionLimits`] for the defaults. A jerk limit, `jerk_mm_s3` (types 1
//! to 3) or `jerk_deg_s3` (types 1 and 4; type 1 gives both), times the
//! motion by the jerk-limited double S along its straight line instead of
//! the trapezoid, under either timing. A type-3 motion with
//! `camera = "follow"` turns the platform to keep the tips in view while
//! they move ([`parasils::Follow`]), within its `velocity_deg_s` and
//! `acceleration_deg_s2` (which it then takes), and lasts until the camera
//! has settled; `camera = "fixed"` (the default) holds the platform. `until_s = T` hands over to the next
//! motion `T` s after the motion's start: before its end, the motion is cut
//! short and the next one (`type = "stop"`, the controlled stop, or a motion
//! of the same type, replanned from the moving state) starts at its speed;
//! after its end, the robot rests until then. A key that does not apply to
//! its motion's type, an unknown or missing key and a bad value are errors
//! naming the motion (index from 0), the key and the line.

use std::sync::Arc;

use core::fmt;
use parasils_anatomy::{Anatomy, AnatomyError};
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::motion::{
    CameraMode, LookAt, LookAtTips, MotionGoal, MotionLimits, MotionSpec, MotionType, Port,
};
use crate::robot_file::{self, RobotFileError};
use crate::scenario::{Run, Scenario};
use parasils_io::Shortest;

/// What went wrong with a procedure.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProcedureError {
    /// The file could not be read.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// Malformed TOML, or a key or value that is wrong.
    #[error("{origin}{}: {message}", Place { line: *line, motion: *motion, key: key.as_deref() })]
    Invalid {
        /// The file's path, or `"procedure"`.
        origin: Box<str>,
        /// The line (1-based), when known.
        line: Option<usize>,
        /// The motion's index (from 0), when the error is inside one.
        motion: Option<usize>,
        /// The key, when the error is about one.
        key: Option<Box<str>>,
        /// What is wrong.
        message: String,
    },
    /// The robot file the procedure names is wrong.
    #[error("{0}")]
    Robot(#[from] RobotFileError),
    /// The anatomy file the procedure names is wrong.
    #[error("{0}")]
    Anatomy(#[from] AnatomyError),
}

struct Place<'a> {
    line: Option<usize>,
    motion: Option<usize>,
    key: Option<&'a str>,
}

impl fmt::Display for Place<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, ", line {line}")?;
        }
        if let Some(motion) = self.motion {
            write!(f, ", motion {motion}")?;
        }
        if let Some(key) = self.key {
            write!(f, ", key `{key}`")?;
        }
        Ok(())
    }
}

/// The file's top level.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ProcedureFile {
    robot: Option<String>,
    anatomy: Option<String>,
    pose: Option<[f64; 6]>,
    tip_left_mm: Option<[f64; 3]>,
    tip_right_mm: Option<[f64; 3]>,
    endoscope_depth_mm: Option<f64>,
    motion: Vec<MotionFile>,
}

/// One `[[motion]]`: every key any type takes; which apply is checked after.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionFile {
    #[serde(rename = "type")]
    kind: String,
    name: Option<String>,
    pose: Option<[f64; 6]>,
    instrument: Option<String>,
    depth_mm: Option<f64>,
    tip_mm: Option<[f64; 3]>,
    tip_left_mm: Option<[f64; 3]>,
    tip_right_mm: Option<[f64; 3]>,
    psi_deg: Option<f64>,
    theta_deg: Option<f64>,
    absolute: Option<bool>,
    look_at_mm: Option<[f64; 3]>,
    look_at: Option<String>,
    velocity_mm_s: Option<f64>,
    acceleration_mm_s2: Option<f64>,
    velocity_deg_s: Option<f64>,
    acceleration_deg_s2: Option<f64>,
    jerk_mm_s3: Option<f64>,
    jerk_deg_s3: Option<f64>,
    until_s: Option<f64>,
    camera: Option<String>,
}

/// Reads the procedure at `path` (a robot it names is read relative to the
/// file's folder), starting from [`Scenario::paper`] for everything the
/// file does not give (the sampling rate, for one).
///
/// # Errors
/// [`ProcedureError::Io`] when a file cannot be read,
/// [`ProcedureError::Invalid`] naming the line, motion and key of what is
/// wrong, [`ProcedureError::Robot`] for the robot file's own errors.
pub fn load(path: impl AsRef<Path>) -> Result<Scenario, ProcedureError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|error| ProcedureError::Io {
        path: path.to_owned(),
        error,
    })?;
    let base = path.parent().unwrap_or(Path::new(""));
    parse(&text, &path.display().to_string(), base)
}

/// A procedure's TOML text; `origin` names it in errors and a robot it
/// names is read relative to `base`.
///
/// # Errors
/// As [`load`].
pub fn parse(text: &str, origin: &str, base: &Path) -> Result<Scenario, ProcedureError> {
    let file: ProcedureFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map(|s| line_of(text, s.start));
        let motion = e.span().and_then(|s| motion_at(text, s.start));
        ProcedureError::Invalid {
            origin: origin.into(),
            line,
            motion,
            key: None,
            message: e.message().trim_end().to_owned(),
        }
    })?;
    build(file, origin, Some(text), base)
}

/// A procedure from JSON text of the same structure as the TOML file (what
/// the Python bindings send for a dict); a robot it names is read relative
/// to `base`. Errors name the motion and key (there are no lines).
///
/// # Errors
/// As [`load`].
pub fn parse_json(text: &str, base: &Path) -> Result<Scenario, ProcedureError> {
    let origin = "procedure";
    let file: ProcedureFile = serde_json::from_str(text).map_err(|e| ProcedureError::Invalid {
        origin: origin.into(),
        line: None,
        motion: None,
        key: None,
        message: e.to_string(),
    })?;
    build(file, origin, None, base)
}

/// The line (1-based) of byte offset `at`.
fn line_of(text: &str, at: usize) -> usize {
    let at = at.min(text.len());
    text.as_bytes()
        .get(..at)
        .map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count())
        + 1
}

/// Whether a line is a `[[motion]]` header.
fn is_motion_header(line: &str) -> bool {
    line.split('#').next().unwrap_or("").trim() == "[[motion]]"
}

/// The motion (from 0) whose table holds byte offset `at`, if any.
fn motion_at(text: &str, at: usize) -> Option<usize> {
    let mut offset = 0;
    let mut count = 0usize;
    for line in text.split_inclusive('\n') {
        if offset > at {
            break;
        }
        if is_motion_header(line) {
            count += 1;
        }
        offset += line.len();
    }
    count.checked_sub(1)
}

/// The line of `key` in motion `motion` (`None`: the top level), or of the
/// motion's header when the key is not written.
fn locate(text: &str, motion: Option<usize>, key: &str) -> Option<usize> {
    let mut current: Option<usize> = None;
    let mut header = None;
    for (n, line) in text.lines().enumerate() {
        if is_motion_header(line) {
            current = Some(current.map_or(0, |k| k + 1));
            if current == motion {
                header = Some(n + 1);
            }
            continue;
        }
        if current == motion {
            let k = line.split('=').next().unwrap_or("").trim();
            if k == key {
                return Some(n + 1);
            }
        }
    }
    header
}

/// Builds errors with the place of a key.
struct Errors<'a> {
    origin: &'a str,
    text: Option<&'a str>,
}

impl Errors<'_> {
    fn at(&self, motion: Option<usize>, key: &str, message: String) -> ProcedureError {
        ProcedureError::Invalid {
            origin: self.origin.into(),
            line: self.text.and_then(|t| locate(t, motion, key)),
            motion,
            key: Some(key.into()),
            message,
        }
    }

    fn finite<const N: usize>(
        &self,
        motion: Option<usize>,
        key: &str,
        v: [f64; N],
    ) -> Result<[f64; N], ProcedureError> {
        match v.iter().find(|x| !x.is_finite()) {
            Some(x) => Err(self.at(
                motion,
                key,
                format!("{} is not a finite number", Shortest(*x)),
            )),
            None => Ok(v),
        }
    }

    fn positive(
        &self,
        m: usize,
        key: &str,
        v: Option<f64>,
        default: f64,
    ) -> Result<f64, ProcedureError> {
        match v {
            None => Ok(default),
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            Some(x) => Err(self.at(
                Some(m),
                key,
                format!("{} is not a positive number", Shortest(x)),
            )),
        }
    }
}

fn build(
    file: ProcedureFile,
    origin: &str,
    text: Option<&str>,
    base: &Path,
) -> Result<Scenario, ProcedureError> {
    let errors = Errors { origin, text };
    let mut scenario = Scenario::paper();
    if let Some(robot) = &file.robot {
        let robot = robot_file::load_robot(base.join(robot))?;
        scenario.robot = robot.geometry;
        scenario.supervisor = robot.supervisor;
        scenario.bodies = robot.bodies;
        scenario.dynamics = robot.dynamics;
        scenario.stiffness = robot.stiffness;
    }
    if let Some(anatomy) = &file.anatomy {
        scenario.anatomy = Some(Arc::new(Anatomy::load(base.join(anatomy))?));
    }
    if let Some(pose) = file.pose {
        scenario.start_mm_deg = errors.finite(None, "pose", pose)?;
    }
    if let Some(tip) = file.tip_left_mm {
        scenario.tip_left_mm = errors.finite(None, "tip_left_mm", tip)?;
    }
    if let Some(tip) = file.tip_right_mm {
        scenario.tip_right_mm = Some(errors.finite(None, "tip_right_mm", tip)?);
    }
    if let Some(depth) = file.endoscope_depth_mm {
        scenario.endoscope_depth_mm = errors.finite(None, "endoscope_depth_mm", [depth])?[0];
    }
    if file.motion.is_empty() {
        return Err(ProcedureError::Invalid {
            origin: origin.into(),
            line: None,
            motion: None,
            key: Some("motion".into()),
            message: String::from("a procedure needs at least one [[motion]]"),
        });
    }
    scenario.run = Run::procedure(
        file.motion
            .into_iter()
            .enumerate()
            .map(|(k, m)| motion(&errors, k, m))
            .collect::<Result<_, _>>()?,
    );
    Ok(scenario)
}

/// The keys of a motion that are given, with their names.
fn given(m: &MotionFile) -> [(&'static str, bool); 18] {
    [
        ("pose", m.pose.is_some()),
        ("instrument", m.instrument.is_some()),
        ("depth_mm", m.depth_mm.is_some()),
        ("tip_mm", m.tip_mm.is_some()),
        ("tip_left_mm", m.tip_left_mm.is_some()),
        ("tip_right_mm", m.tip_right_mm.is_some()),
        ("psi_deg", m.psi_deg.is_some()),
        ("theta_deg", m.theta_deg.is_some()),
        ("absolute", m.absolute.is_some()),
        ("look_at_mm", m.look_at_mm.is_some()),
        ("look_at", m.look_at.is_some()),
        ("velocity_mm_s", m.velocity_mm_s.is_some()),
        ("acceleration_mm_s2", m.acceleration_mm_s2.is_some()),
        ("velocity_deg_s", m.velocity_deg_s.is_some()),
        ("acceleration_deg_s2", m.acceleration_deg_s2.is_some()),
        ("jerk_mm_s3", m.jerk_mm_s3.is_some()),
        ("jerk_deg_s3", m.jerk_deg_s3.is_some()),
        ("camera", m.camera.is_some()),
    ]
}

/// The keys each type takes (besides `type`, `name` and `until_s`); `None`
/// is the stop, which takes the limits.
fn applies(t: Option<MotionType>, key: &str) -> bool {
    let linear = matches!(key, "velocity_mm_s" | "acceleration_mm_s2" | "jerk_mm_s3");
    let angular = matches!(
        key,
        "velocity_deg_s" | "acceleration_deg_s2" | "jerk_deg_s3"
    );
    match t {
        Some(MotionType::Position) => key == "pose" || linear || angular,
        Some(MotionType::Insert) => matches!(key, "instrument" | "depth_mm") || linear,
        Some(MotionType::Manipulate) => {
            matches!(
                key,
                "instrument"
                    | "tip_mm"
                    | "tip_left_mm"
                    | "tip_right_mm"
                    | "camera"
                    | "velocity_deg_s"
                    | "acceleration_deg_s2"
            ) || linear
        }
        Some(MotionType::Reorient) => {
            matches!(
                key,
                "psi_deg" | "theta_deg" | "absolute" | "look_at_mm" | "look_at"
            ) || angular
        }
        // A stop is timed by the online profile, which has no jerk limit.
        None => (linear || angular) && !key.starts_with("jerk"),
    }
}

fn motion(errors: &Errors<'_>, k: usize, m: MotionFile) -> Result<MotionSpec, ProcedureError> {
    let at = Some(k);
    let motion_type = match m.kind.as_str() {
        "position" => Some(MotionType::Position),
        "insert" => Some(MotionType::Insert),
        "manipulate" => Some(MotionType::Manipulate),
        "reorient" => Some(MotionType::Reorient),
        "stop" => None,
        other => {
            return Err(errors.at(
                at,
                "type",
                format!(
                    "unknown motion type {other:?}: expected \"position\", \"insert\", \"manipulate\", \"reorient\" or \"stop\""
                ),
            ));
        }
    };
    let type_name = motion_type.map_or("stop", MotionType::name);
    for (key, present) in given(&m) {
        if present && !applies(motion_type, key) {
            return Err(errors.at(at, key, format!("does not apply to a {type_name:?} motion")));
        }
    }
    let missing = |key: &str| errors.at(at, key, format!("missing for a {type_name:?} motion"));
    let instrument = |allowed: &[&str]| -> Result<String, ProcedureError> {
        let name = m.instrument.clone().ok_or_else(|| missing("instrument"))?;
        if allowed.contains(&name.as_str()) {
            Ok(name)
        } else {
            Err(errors.at(
                at,
                "instrument",
                format!("{name:?} is not one of {}", allowed.join(", ")),
            ))
        }
    };
    let goal = match motion_type {
        None => MotionGoal::Stop,
        Some(MotionType::Position) => MotionGoal::Position {
            pose_mm_deg: errors.finite(at, "pose", m.pose.ok_or_else(|| missing("pose"))?)?,
        },
        Some(MotionType::Insert) => {
            let port = match instrument(&["left", "right", "endoscope"])?.as_str() {
                "left" => Port::Left,
                "right" => Port::Right,
                _ => Port::Endoscope,
            };
            let depth = m.depth_mm.ok_or_else(|| missing("depth_mm"))?;
            MotionGoal::Insert {
                port,
                depth_mm: errors.finite(at, "depth_mm", [depth])?[0],
            }
        }
        Some(MotionType::Manipulate) => {
            let which = instrument(&["left", "right", "both"])?;
            let tip = |key: &str, v: Option<[f64; 3]>| -> Result<[f64; 3], ProcedureError> {
                errors.finite(at, key, v.ok_or_else(|| missing(key))?)
            };
            let wrong = |key: &str| {
                errors.at(
                    at,
                    key,
                    format!("does not apply with instrument = {which:?} (use tip_mm for one instrument, tip_left_mm and tip_right_mm for both)"),
                )
            };
            if which == "both" {
                if m.tip_mm.is_some() {
                    return Err(wrong("tip_mm"));
                }
                MotionGoal::Manipulate {
                    tip_left_mm: Some(tip("tip_left_mm", m.tip_left_mm)?),
                    tip_right_mm: Some(tip("tip_right_mm", m.tip_right_mm)?),
                }
            } else {
                for (key, v) in [
                    ("tip_left_mm", m.tip_left_mm),
                    ("tip_right_mm", m.tip_right_mm),
                ] {
                    if v.is_some() {
                        return Err(wrong(key));
                    }
                }
                let t = tip("tip_mm", m.tip_mm)?;
                if which == "left" {
                    MotionGoal::Manipulate {
                        tip_left_mm: Some(t),
                        tip_right_mm: None,
                    }
                } else {
                    MotionGoal::Manipulate {
                        tip_left_mm: None,
                        tip_right_mm: Some(t),
                    }
                }
            }
        }
        Some(MotionType::Reorient) if m.look_at.is_some() || m.look_at_mm.is_some() => {
            let both = |key: &str| {
                errors.at(
                    at,
                    key,
                    String::from(
                        "does not apply with a look-at target: give psi_deg and theta_deg, or look_at_mm, or look_at",
                    ),
                )
            };
            for (key, given) in [
                ("psi_deg", m.psi_deg.is_some()),
                ("theta_deg", m.theta_deg.is_some()),
                ("absolute", m.absolute.is_some()),
            ] {
                if given {
                    return Err(both(key));
                }
            }
            let target = match (m.look_at_mm, m.look_at.as_deref()) {
                (Some(_), Some(_)) => return Err(both("look_at")),
                (Some(p), None) => LookAt::Point(errors.finite(at, "look_at_mm", p)?),
                (None, Some("tips")) => LookAt::Tips(LookAtTips::Tips),
                (None, Some("left")) => LookAt::Tips(LookAtTips::Left),
                (None, Some("right")) => LookAt::Tips(LookAtTips::Right),
                (None, Some(other)) => {
                    return Err(errors.at(
                        at,
                        "look_at",
                        format!(
                            "{other:?} is not one of \"tips\", \"left\", \"right\" (a point is look_at_mm = [x, y, z])"
                        ),
                    ));
                }
                (None, None) => return Err(missing("look_at")),
            };
            MotionGoal::LookAt { target }
        }
        Some(MotionType::Reorient) => {
            let psi = m.psi_deg.ok_or_else(|| missing("psi_deg"))?;
            let theta = m.theta_deg.ok_or_else(|| missing("theta_deg"))?;
            MotionGoal::Reorient {
                psi_deg: errors.finite(at, "psi_deg", [psi])?[0],
                theta_deg: errors.finite(at, "theta_deg", [theta])?[0],
                absolute: m.absolute.unwrap_or(false),
            }
        }
    };
    let d = MotionLimits::default();
    let limits = MotionLimits {
        velocity_mm_s: errors.positive(k, "velocity_mm_s", m.velocity_mm_s, d.velocity_mm_s)?,
        acceleration_mm_s2: errors.positive(
            k,
            "acceleration_mm_s2",
            m.acceleration_mm_s2,
            d.acceleration_mm_s2,
        )?,
        velocity_deg_s: errors.positive(k, "velocity_deg_s", m.velocity_deg_s, d.velocity_deg_s)?,
        acceleration_deg_s2: errors.positive(
            k,
            "acceleration_deg_s2",
            m.acceleration_deg_s2,
            d.acceleration_deg_s2,
        )?,
        jerk_mm_s3: m
            .jerk_mm_s3
            .map(|v| errors.positive(k, "jerk_mm_s3", Some(v), v))
            .transpose()?,
        jerk_deg_s3: m
            .jerk_deg_s3
            .map(|v| errors.positive(k, "jerk_deg_s3", Some(v), v))
            .transpose()?,
    };
    if motion_type == Some(MotionType::Position)
        && limits.jerk_mm_s3.is_some() != limits.jerk_deg_s3.is_some()
    {
        let key = if limits.jerk_mm_s3.is_some() {
            "jerk_deg_s3"
        } else {
            "jerk_mm_s3"
        };
        return Err(errors.at(
            at,
            key,
            String::from("missing: a \"position\" motion moves lengths and angles, so a jerk-limited one gives jerk_mm_s3 and jerk_deg_s3 together"),
        ));
    }
    let until_s = match m.until_s {
        None => None,
        Some(t) if t.is_finite() && t > 0.0 => Some(t),
        Some(t) => {
            return Err(errors.at(
                at,
                "until_s",
                format!("{} is not a positive number of seconds", Shortest(t)),
            ));
        }
    };
    let camera = match m.camera.as_deref() {
        None | Some("fixed") => CameraMode::Fixed,
        Some("follow") => CameraMode::Follow,
        Some(other) => {
            return Err(errors.at(
                at,
                "camera",
                format!("{other:?} is not one of \"fixed\", \"follow\""),
            ));
        }
    };
    if motion_type == Some(MotionType::Manipulate) && camera == CameraMode::Fixed {
        // The angular limits bind the platform's turn, which only a
        // following camera makes in a type-3 motion.
        for (key, v) in [
            ("velocity_deg_s", m.velocity_deg_s),
            ("acceleration_deg_s2", m.acceleration_deg_s2),
        ] {
            if v.is_some() {
                return Err(errors.at(
                    at,
                    key,
                    String::from(
                        "applies to a \"manipulate\" motion only with camera = \"follow\" (the platform is still otherwise)",
                    ),
                ));
            }
        }
    }
    if camera == CameraMode::Follow && until_s.is_some() {
        return Err(errors.at(
            at,
            "until_s",
            String::from(
                "does not apply with camera = \"follow\": the motion lasts until the camera has settled",
            ),
        ));
    }
    let stated = [
        m.velocity_mm_s.is_some() || m.acceleration_mm_s2.is_some(),
        m.velocity_deg_s.is_some() || m.acceleration_deg_s2.is_some(),
    ];
    Ok(MotionSpec {
        goal,
        limits,
        stated,
        name: m.name,
        until_s,
        camera,
    })
}
