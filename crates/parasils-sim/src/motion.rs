//! A procedure's motions in user units: what each does ([`MotionGoal`], one
//! per motion type of the paper), within which limits ([`MotionLimits`],
//! with the defaults stated once), and how messages name it
//! ([`MotionName`]). A [`Scenario`](crate::Scenario) holds them in its
//! planned timeline ([`Motions::Procedure`](crate::Motions::Procedure)); the
//! [`procedure`](crate::procedure) module reads them from files, and the
//! [`engine`](crate::engine) plans them with `parasils::motions`.
//!
//! ```
//! use parasils::Port;
//! use parasils_sim::{MotionGoal, MotionSpec};
//! use parasils_sim::{Run, Scenario, Simulation};
//!
//! let scenario = Scenario {
//!     run: Run::procedure(vec![
//!         MotionSpec::new(MotionGoal::Insert { port: Port::Endoscope, depth_mm: 40.0 }),
//!         MotionSpec::new(MotionGoal::Reorient { psi_deg: 15.0, theta_deg: 25.0, absolute: false }),
//!     ]),
//!     ..Scenario::paper()
//! };
//! let sim = Simulation::new(scenario)?;
//! // 40 mm at the default 20 mm/s and 20 mm/s^2: 1 s to reach 20 mm/s, 1 s
//! // at it, 1 s to stop (rows 0 to 3000 at 1 kHz); then, from the next
//! // cycle, the paper's 4.5 s turn: its last row at 3.001 + 4.5 s.
//! assert!((sim.duration() - 7.501).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub use parasils::motions::{MotionType, Port};

/// A port by its name in procedure files.
fn port_name<S: serde::Serializer>(port: &Port, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(port.name())
}

/// The final `[psi, theta]` (rad) of a turn given as `psi_deg`,
/// `theta_deg`: increments from `from` (rad), or final angles with
/// `absolute`. How every turn reads its angles: a procedure's, the paper's
/// and a retarget's.
pub(crate) fn turn_goal_rad(
    psi_deg: f64,
    theta_deg: f64,
    absolute: bool,
    from: [f64; 2],
) -> [f64; 2] {
    let [psi, theta] = [psi_deg.to_radians(), theta_deg.to_radians()];
    if absolute {
        [psi, theta]
    } else {
        [from[0] + psi, from[1] + theta]
    }
}

/// The default linear velocity limit of a motion, mm/s: the platform's `x`,
/// `y`, `z` (type 1), an insertion's depth (type 2), a tip's arc length
/// (type 3). Chosen here, not the paper's: a slow, deliberate speed inside
/// the patient.
pub const VELOCITY_MM_S: f64 = 20.0;

/// The default linear acceleration limit of a motion, mm/s^2 (see
/// [`VELOCITY_MM_S`]).
pub const ACCELERATION_MM_S2: f64 = 20.0;

/// The limits of one motion, in user units. The angular ones bind the
/// platform's Euler angles (types 1 and 4), each angle on its own; the
/// linear ones bind `x, y, z` each (type 1), the depth (type 2) and each
/// tip's arc length (type 3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MotionLimits {
    /// mm/s (default 20 mm/s).
    pub velocity_mm_s: f64,
    /// mm/s^2 (default 20 mm/s^2).
    pub acceleration_mm_s2: f64,
    /// deg/s (default the paper's 10 deg/s).
    pub velocity_deg_s: f64,
    /// deg/s^2 (default the paper's 5 deg/s^2).
    pub acceleration_deg_s2: f64,
    /// mm/s^3: given, the motion is timed by the jerk-limited double S
    /// along its straight line instead of the trapezoid (see
    /// [`MotionLimits::jerk`]); `None` by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jerk_mm_s3: Option<f64>,
    /// deg/s^3: as [`MotionLimits::jerk_mm_s3`], for the Euler angles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jerk_deg_s3: Option<f64>,
}

impl MotionLimits {
    /// The linear limits in library units (mm/s, mm/s^2).
    pub fn linear(&self) -> parasils::traj::Limits<f64> {
        parasils::traj::Limits::new(self.velocity_mm_s, self.acceleration_mm_s2)
    }

    /// The angular limits in library units (rad/s, rad/s^2).
    pub fn angular(&self) -> parasils::traj::Limits<f64> {
        parasils::traj::Limits::new(
            self.velocity_deg_s.to_radians(),
            self.acceleration_deg_s2.to_radians(),
        )
    }
}

impl MotionLimits {
    /// The limits of the double S in library units, `[linear, angular]`
    /// (mm/s, mm/s^2, mm/s^3; rad/s, rad/s^2, rad/s^3), when the motion
    /// gives a jerk limit: its law is then the double S in `s` along its
    /// straight line ([`parasils::Motion::jerk_limited`]), velocity and
    /// acceleration continuous. A group without its jerk limit does not
    /// move in such a motion (procedure files give type 1 both), so its
    /// acceleration limit stands in for it and never binds.
    pub fn jerk(&self) -> Option<[parasils::traj::JerkLimits<f64>; 2]> {
        if self.jerk_mm_s3.is_none() && self.jerk_deg_s3.is_none() {
            return None;
        }
        let linear = self.jerk_mm_s3.unwrap_or(self.acceleration_mm_s2);
        let angular = self.jerk_deg_s3.unwrap_or(self.acceleration_deg_s2);
        Some([
            parasils::traj::JerkLimits::from_limits(self.linear(), linear),
            parasils::traj::JerkLimits::from_limits(self.angular(), angular.to_radians()),
        ])
    }
}

impl Default for MotionLimits {
    fn default() -> Self {
        Self {
            velocity_mm_s: VELOCITY_MM_S,
            acceleration_mm_s2: ACCELERATION_MM_S2,
            velocity_deg_s: parasils::paper::OMEGA_MAX_DEG_S,
            acceleration_deg_s2: parasils::paper::EPS_MAX_DEG_S2,
            jerk_mm_s3: None,
            jerk_deg_s3: None,
        }
    }
}

/// What a type-4 motion looks at: a point, or the tips where the motion
/// starts (they are held, so they stay where the camera aims).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum LookAt {
    /// A point, mm, fixed frame (`look_at_mm = [x, y, z]`).
    #[serde(rename = "look_at_mm")]
    Point([f64; 3]),
    /// The midpoint of both tips (`look_at = "tips"`).
    #[serde(rename = "look_at")]
    Tips(LookAtTips),
}

/// Which tips a [`LookAt::Tips`] aims at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LookAtTips {
    /// The midpoint of both.
    Tips,
    /// The left tip.
    Left,
    /// The right tip.
    Right,
}

impl LookAt {
    /// The point looked at, mm, fixed frame, given both tips.
    pub fn point(&self, tips: [[f64; 3]; 2]) -> [f64; 3] {
        let [l, r] = tips;
        match self {
            LookAt::Point(p) => *p,
            LookAt::Tips(LookAtTips::Tips) => core::array::from_fn(|k| 0.5 * (l[k] + r[k])),
            LookAt::Tips(LookAtTips::Left) => l,
            LookAt::Tips(LookAtTips::Right) => r,
        }
    }
}

/// What one motion does, in user units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum MotionGoal {
    /// Type 1: the platform to `pose_mm_deg` (`x, y, z` mm, `psi, theta,
    /// phi` deg, absolute), on a straight line in pose space.
    Position {
        /// The final pose.
        #[serde(rename = "pose")]
        pose_mm_deg: [f64; 6],
    },
    /// Type 2: `port` inserted by `depth_mm` (positive inwards) along its
    /// axis.
    Insert {
        /// The instrument or the endoscope.
        #[serde(rename = "instrument", serialize_with = "port_name")]
        port: Port,
        /// The signed depth, mm.
        depth_mm: f64,
    },
    /// Type 3: the tips to these points (mm, fixed frame) on straight lines;
    /// `None` holds a tip. At least one is given.
    Manipulate {
        /// The left tip's target.
        tip_left_mm: Option<[f64; 3]>,
        /// The right tip's target.
        tip_right_mm: Option<[f64; 3]>,
    },
    /// The controlled stop of the motion before it, cut short while moving
    /// ([`MotionSpec::until_s`]): its coordinates to rest together, at the
    /// limits of the motion it stops (or its own, when it gives them). It
    /// keeps the type of the motion it stops.
    Stop,
    /// Type 4 defined by what the camera looks at: the platform turned
    /// (`phi` held) so that `target` is on the view axis
    /// ([`parasils::kin::Camera::look_at`], the solution nearest the
    /// orientation the motion starts from), both tips held.
    #[serde(rename = "reorient")]
    LookAt {
        /// What to look at.
        #[serde(flatten)]
        target: LookAt,
    },
    /// Type 4: the platform turned by `psi_deg`, `theta_deg` (increments, or
    /// final angles with `absolute`), both tips held.
    Reorient {
        /// `psi`, deg.
        psi_deg: f64,
        /// `theta`, deg.
        theta_deg: f64,
        /// Whether the angles are final rather than increments.
        absolute: bool,
    },
}

impl MotionGoal {
    /// The motion's type; `None` for a stop, whose type is that of the
    /// motion it stops.
    pub fn motion_type(&self) -> Option<MotionType> {
        match self {
            MotionGoal::Position { .. } => Some(MotionType::Position),
            MotionGoal::Insert { .. } => Some(MotionType::Insert),
            MotionGoal::Manipulate { .. } => Some(MotionType::Manipulate),
            MotionGoal::Reorient { .. } | MotionGoal::LookAt { .. } => Some(MotionType::Reorient),
            MotionGoal::Stop => None,
        }
    }
}

/// What the camera does during a type-3 motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CameraMode {
    /// The platform holds still (`camera = "fixed"`, the default).
    #[default]
    Fixed,
    /// The platform turns to keep the tips in view while they move
    /// (`camera = "follow"`, [`parasils::Follow`] with its assumed
    /// parameters and the motion's angular limits), both tips commanded in
    /// the fixed frame; the motion lasts until the camera has settled.
    Follow,
}

impl CameraMode {
    /// Whether the platform holds still.
    pub fn is_fixed(&self) -> bool {
        *self == CameraMode::Fixed
    }
}

/// One motion of a procedure: its goal, its limits and an optional name.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MotionSpec {
    /// What it does.
    #[serde(flatten)]
    pub goal: MotionGoal,
    /// Within which limits.
    pub limits: MotionLimits,
    /// Which of `limits` were given rather than defaulted, `[linear,
    /// angular]` (a value of the pair given counts for both). Under
    /// `--timing optimal` only these bind besides the actuators' limits, as
    /// `--omega-max` does for the paper's turn; an endoscope insertion,
    /// which moves no actuator, is always bound by its linear limits.
    #[serde(skip)]
    pub stated: [bool; 2],
    /// A name for messages and outputs (`"camera to the gallbladder"`).
    pub name: Option<String>,
    /// When the next motion takes over, s from this one's start: before the
    /// motion's end, it is cut short there and the next motion (a `stop`, or
    /// one of the same type) starts from its moving state; after its end, the
    /// robot rests until then. `None`: at the motion's end.
    pub until_s: Option<f64>,
    /// What the camera does while a type-3 motion moves the tips (the
    /// platform still, by default).
    #[serde(skip_serializing_if = "CameraMode::is_fixed")]
    pub camera: CameraMode,
}

impl MotionSpec {
    /// `goal` with the default limits and no name.
    pub fn new(goal: MotionGoal) -> Self {
        Self {
            goal,
            limits: MotionLimits::default(),
            stated: [false; 2],
            name: None,
            until_s: None,
            camera: CameraMode::Fixed,
        }
    }

    /// The motion's type; `None` for a stop (see [`MotionGoal::motion_type`]).
    pub fn motion_type(&self) -> Option<MotionType> {
        self.goal.motion_type()
    }
}

/// A motion as messages name it: `motion 3 (reorient "camera up")`, the
/// index counted from 0 as in the output's `motion` column.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MotionName {
    /// The index, from 0.
    pub index: usize,
    /// The type (a stop's is that of the motion it stops).
    pub motion_type: MotionType,
    /// Whether it is a stop.
    pub stop: bool,
    /// The name, if the motion has one.
    pub name: Option<String>,
}

impl MotionName {
    /// How procedures name its type: `"position"`, ..., or `"stop"`.
    pub fn type_name(&self) -> &'static str {
        if self.stop {
            "stop"
        } else {
            self.motion_type.name()
        }
    }
}

impl core::fmt::Display for MotionName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "motion {} ({}", self.index, self.type_name())?;
        if let Some(name) = &self.name {
            write!(f, " {name:?}")?;
        }
        f.write_str(")")
    }
}

/// `P` counts as moved when it leaves the incision point by more than
/// this, mm.
pub(crate) const MOVE_TOLERANCE_MM: f64 = 1e-6;

/// `phi` counts as turned when it leaves its value by more than this, deg.
pub(crate) const TURN_TOLERANCE_DEG: f64 = 1e-6;

/// What is inside the patient before a motion starts, and where the
/// incision is (see docs/model.md, *Inside or outside the patient*): the
/// endoscope while its depth is above 0 mm; an instrument once an insertion
/// of it ended deeper than at the procedure's start, until one ends at most
/// at that depth.
///
/// `Display` writes `outside`, or `inside: ` and what is inside
/// (`inside: endoscope, left`), as the `--check` table shows it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Inside {
    /// Whether the endoscope is inside (its depth above 0 mm).
    pub endoscope: bool,
    /// Whether the left instrument is inside (inserted deeper than at the
    /// procedure's start).
    pub left: bool,
    /// Whether the right instrument is inside.
    pub right: bool,
    /// The incision point, mm, fixed frame: `P` (the platform's origin, the
    /// endoscope's remote centre of motion) when the first insertion began;
    /// `None` while everything is outside.
    pub incision_mm: Option<[f64; 3]>,
}

impl Inside {
    /// Whether anything is inside.
    pub fn any(&self) -> bool {
        self.endoscope || self.left || self.right
    }

    /// What is inside, in words: `the endoscope`, `the endoscope and the
    /// left instrument`, `the endoscope, the left and the right
    /// instruments`; `nothing` when everything is outside.
    pub fn what(&self) -> &'static str {
        match (self.endoscope, self.left, self.right) {
            (true, false, false) => "the endoscope",
            (true, true, false) => "the endoscope and the left instrument",
            (true, false, true) => "the endoscope and the right instrument",
            (true, true, true) => "the endoscope, the left and the right instruments",
            (false, true, false) => "the left instrument",
            (false, false, true) => "the right instrument",
            (false, true, true) => "the left and the right instruments",
            (false, false, false) => "nothing",
        }
    }

    /// The verb that goes with [`Inside::what`]: `is` or `are`.
    fn verb(&self) -> &'static str {
        if usize::from(self.endoscope) + usize::from(self.left) + usize::from(self.right) > 1 {
            "are"
        } else {
            "is"
        }
    }
}

impl core::fmt::Display for Inside {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if !self.any() {
            return f.write_str("outside");
        }
        f.write_str("inside:")?;
        let mut sep = " ";
        for (is, what) in [
            (self.endoscope, "endoscope"),
            (self.left, "left"),
            (self.right, "right"),
        ] {
            if is {
                write!(f, "{sep}{what}")?;
                sep = ", ";
            }
        }
        Ok(())
    }
}

/// A rule the paper states for motions while anything is inside the
/// patient.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum InsideRule {
    /// The motion moves `P` off the incision point (type 1 moves the
    /// platform outside the patient only).
    MovesIncision,
    /// The motion changes `phi`, turning the platform about the endoscope's
    /// axis, which would twist the port at the skin (`phi` is held once
    /// anything is in).
    TurnsAboutAxis,
}

impl core::fmt::Display for InsideRule {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            InsideRule::MovesIncision => "moves the incision point",
            InsideRule::TurnsAboutAxis => "turns about the endoscope's axis",
        })
    }
}

/// A refusal's words after the motion's name: the rule, what is inside,
/// how far the motion would go, and what to do instead.
pub(crate) fn refusal(rule: InsideRule, inside: &Inside, moved_mm: f64, turned_deg: f64) -> String {
    use parasils_io::Fixed;
    let turn = || format!("phi would turn by {} deg", Fixed(turned_deg, 3));
    let amounts = match rule {
        InsideRule::MovesIncision if turned_deg > TURN_TOLERANCE_DEG => format!(
            "P would leave the incision point by {} mm and {}",
            Fixed(moved_mm, 3),
            turn()
        ),
        InsideRule::MovesIncision => format!(
            "P would leave the incision point by {} mm",
            Fixed(moved_mm, 3)
        ),
        InsideRule::TurnsAboutAxis => format!("{}, twisting the port at the skin", turn()),
    };
    format!(
        "{rule} while {} {} inside: {amounts}; retract everything first (the endoscope to depth 0, each instrument to its start depth)",
        inside.what(),
        inside.verb()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_is_inside_in_words() {
        let s = |endoscope, left, right| Inside {
            endoscope,
            left,
            right,
            incision_mm: None,
        };
        assert_eq!(
            s(true, true, true).what(),
            "the endoscope, the left and the right instruments"
        );
        assert_eq!(s(true, true, false).verb(), "are");
        assert_eq!(s(false, true, false).verb(), "is");
        assert_eq!(s(false, false, false).to_string(), "outside");
        assert_eq!(s(true, false, true).to_string(), "inside: endoscope, right");
        let text = refusal(
            InsideRule::TurnsAboutAxis,
            &s(false, true, false),
            0.0,
            30.0,
        );
        assert!(
            text.starts_with("turns about the endoscope's axis while the left instrument is inside: phi would turn by 30.000 deg"),
            "{text}"
        );
    }
}
