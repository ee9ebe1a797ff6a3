//! Typed errors: what went wrong, where, and by how much.
//!
//! Every solver of the crate returns `Result<_, Error>`; none panics and none
//! returns a NaN. Values in the variants are `f64` in the crate's units (mm,
//! rad); the `Display` text converts angles to degrees for people, and writes
//! every number with up to 6 significant digits: plain decimals from `1e-3`
//! to `1e6`, exponent form (`1e-6`, `2.5e308`) beyond, `NaN` and `inf` by
//! name. A value beyond a limit gets as many more digits as it takes to read
//! differently from the limit. Each message names its subject once, first:
//! `left instrument: ...`, `module 1: ...`, `module 1 forward kinematics: ...`,
//! or the input (`non-finite input: pose.psi = NaN`).
//!
//! # When this happens, how to handle it
//! - [`Error::NonFinite`]: a NaN or infinity reached a solver. Upstream bug
//!   or sensor fault: stop the motion.
//! - [`Error::OutOfReach`]: the tip asks the instrument for a direction its
//!   spherical linkage cannot point in. Re-plan the target; the platform
//!   orientation alone may bring it back into reach.
//! - [`Error::Singular`]: the target is reachable but on or next to a
//!   singularity (`cos qs2 = 0`, or the tip at the RCM), where joint rates
//!   blow up. Keep away: watch the margins the solvers report every cycle.
//! - [`Error::JointLimit`]: the solution exists but a joint is beyond its
//!   limit. The other assembly mode may be within limits; otherwise re-plan.
//! - Module 1 variants: the same meanings for the parallel robot.
//!   [`Error::LegOutOfReach`]: a leg cannot reach its node at the pose
//!   asked; re-plan the pose. [`Error::ActuatorLimit`]: the pose needs an
//!   actuator beyond its stroke; re-plan. [`Error::SerialSingular`]: a link
//!   (nearly) perpendicular to its guide, where its rate is unbounded; keep
//!   away by watching the serial margins. Forward kinematics:
//!   [`Error::NoConvergence`] and [`Error::BranchMismatch`] mean the guess was
//!   too far (seed with the previous pose); [`Error::SingularJacobian`] means
//!   a parallel singularity (stop: the platform is not held) or an iterate at
//!   `theta = +-90 deg` (the Euler angles cannot describe the motion there).

use core::fmt;

use parasils_num::Num;

use crate::real::Real;
use crate::side::Side;

/// A joint of a spherical instrument module.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Joint {
    /// First rotation, rad.
    Qs1,
    /// Second rotation, rad.
    Qs2,
    /// Insertion (RCM to tip), mm.
    Qs3,
}

impl Joint {
    /// `value` (rad or mm) in the unit people read: degrees for `qs1`, `qs2`; mm for `qs3`.
    pub fn display_value(self, value: f64) -> f64 {
        match self {
            Joint::Qs1 | Joint::Qs2 => value.to_degrees(),
            Joint::Qs3 => value,
        }
    }

    /// The unit of [`Joint::display_value`]: `"deg"` or `"mm"`.
    pub fn display_unit(self) -> &'static str {
        match self {
            Joint::Qs1 | Joint::Qs2 => "deg",
            Joint::Qs3 => "mm",
        }
    }
}

impl fmt::Display for Joint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Joint::Qs1 => "qs1",
            Joint::Qs2 => "qs2",
            Joint::Qs3 => "qs3",
        })
    }
}

/// The singularity of an instrument module whose margin fell below its
/// threshold ([`Error::Singular`]). Not the supervisor's
/// `parasils::supervisor::Margin`, which names each of the margins a cycle
/// reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum InstrumentSingularity {
    /// `|cos qs2|` (dimensionless): the tool on the reach boundary.
    CosQs2,
    /// `qs3` (mm): the tip at the RCM.
    Qs3,
}

/// The old name of [`InstrumentSingularity`]. `Margin` now means only the
/// supervisor's margins (`parasils::supervisor::Margin`).
#[deprecated(since = "0.1.0", note = "renamed `InstrumentSingularity`")]
pub type Margin = InstrumentSingularity;

impl fmt::Display for InstrumentSingularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            InstrumentSingularity::CosQs2 => "|cos qs2|",
            InstrumentSingularity::Qs3 => "qs3 (mm)",
        })
    }
}

/// Everything that can go wrong in the kinematics.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A NaN or infinite input; or finite input so large that a result
    /// overflows the float type (`what` then names the result and ends with
    /// `(overflow)`, or is `|tip_local| (beyond the float type)`).
    #[error("non-finite input: {what} = {}", Num::new(*value))]
    NonFinite {
        /// Which input, e.g. `"pose.psi"`, `"tip.x"`, or which result.
        what: &'static str,
        /// The value (NaN or +-inf).
        value: f64,
    },

    /// A geometry parameter out of its valid range.
    #[error("invalid parameter: {what} = {}", Num::new(*value))]
    InvalidParameter {
        /// Which parameter, e.g. `"instrument.beta"`.
        what: &'static str,
        /// Its value (in the crate's units: mm, rad).
        value: f64,
    },

    /// The tool direction asked of an instrument module is outside its cone of
    /// reach: `|v_x| > cos(beta)`, i.e. `|sin qs2|` would exceed 1.
    #[error(
        "{side} instrument: tip out of reach: the tool direction needs |sin qs2| = {} > 1",
        Num::apart_from(*sin_qs2, 1.0)
    )]
    OutOfReach {
        /// Which module.
        side: Side,
        /// `|v_x| / cos(beta)`, above `1 + reach tolerance`.
        sin_qs2: f64,
    },

    /// An instrument module at or next to a singular configuration.
    #[error(
        "{side} instrument: singular configuration: {margin} = {} is below {}",
        Num::apart_from(*value, *threshold), Num::new(*threshold)
    )]
    Singular {
        /// Which module.
        side: Side,
        /// Which margin.
        margin: InstrumentSingularity,
        /// Its value (dimensionless for `|cos qs2|`, mm for `qs3`).
        value: f64,
        /// The threshold it fell below.
        threshold: f64,
    },

    /// An instrument joint beyond its limit.
    #[error(
        "{side} instrument: joint {joint} = {} {unit} is outside [{}, {}] {unit}",
        Num::outside(joint.display_value(*value), joint.display_value(*min), joint.display_value(*max)),
        Num::new(joint.display_value(*min)), Num::new(joint.display_value(*max)),
        unit = joint.display_unit()
    )]
    JointLimit {
        /// Which module.
        side: Side,
        /// Which joint.
        joint: Joint,
        /// Its value (rad or mm).
        value: f64,
        /// The lower limit (rad or mm).
        min: f64,
        /// The upper limit (rad or mm).
        max: f64,
    },

    /// Module 1: the leg of actuator `q{actuator}` cannot reach its platform
    /// node at this pose (negative square-root argument in the IK).
    #[error(
        "module 1: actuator q{actuator}: the pose is out of its leg's reach (square-root argument {} mm^2 < 0)",
        Num::new(*discriminant)
    )]
    LegOutOfReach {
        /// The actuator, 1 to 6.
        actuator: u8,
        /// `l^2 - |r|^2 + (r.u)^2`, mm^2, negative.
        discriminant: f64,
    },

    /// Module 1: an actuator beyond its stroke.
    #[error(
        "module 1: actuator q{actuator} = {} mm is outside [{}, {}] mm",
        Num::outside(*value, *min, *max), Num::new(*min), Num::new(*max)
    )]
    ActuatorLimit {
        /// The actuator, 1 to 6.
        actuator: u8,
        /// Its value, mm.
        value: f64,
        /// The lower limit, mm.
        min: f64,
        /// The upper limit, mm.
        max: f64,
    },

    /// Module 1: a link perpendicular (or nearly) to its guide, a serial
    /// singularity where the actuator rate is unbounded.
    #[error(
        "module 1: actuator q{actuator}: serial singularity: margin |e.u|/l = {} is below {}",
        Num::apart_from(*margin, *threshold), Num::new(*threshold)
    )]
    SerialSingular {
        /// The actuator, 1 to 6.
        actuator: u8,
        /// `|e_j . u_j| / l_j`, dimensionless.
        margin: f64,
        /// The threshold it fell below.
        threshold: f64,
    },

    /// Module 1: the commanded pose is at or next to a parallel (type 2)
    /// singularity, where the platform is not held by the locked actuators.
    #[error(
        "module 1: parallel singularity: margin {} is below {}",
        Num::apart_from(*margin, *threshold), Num::new(*threshold)
    )]
    ParallelSingular {
        /// The parallel margin (dimensionless, see `parallel`).
        margin: f64,
        /// The threshold it fell below.
        threshold: f64,
    },

    /// Module 1 forward kinematics: Newton's method did not converge.
    #[error(
        "module 1 forward kinematics: no convergence after {iterations} iterations (relative residual {})",
        Num::new(*residual)
    )]
    NoConvergence {
        /// Iterations run.
        iterations: u32,
        /// The final residual, relative to the link lengths.
        residual: f64,
    },

    /// Module 1 forward kinematics: the Jacobian is singular at an iterate.
    #[error(
        "module 1 forward kinematics: singular Jacobian ({kind}) at iteration {iteration}: margin {} is below {}",
        Num::apart_from(*margin, *threshold), Num::new(*threshold)
    )]
    SingularJacobian {
        /// Which singularity: the robot's (parallel) or the Euler angles'.
        kind: ParallelSingularity,
        /// The iteration at which it happened (0 = the starting guess).
        iteration: u32,
        /// The dimensionless margin that vanished: the parallel margin, or
        /// `|cos theta|` for the Euler angles.
        margin: f64,
        /// The threshold it fell below.
        threshold: f64,
    },

    /// Module 1 forward kinematics: the constraints are solved, but the link
    /// of actuator `q{actuator}` is on the other branch than the geometry's
    /// (the sign of `e.u` differs from `s`): another assembly mode, which the
    /// inverse kinematics would not give back. Start closer.
    #[error(
        "module 1 forward kinematics: converged to another assembly mode: the link of actuator q{actuator} is on the other branch"
    )]
    BranchMismatch {
        /// The actuator, 1 to 6.
        actuator: u8,
    },

    /// The endoscope's insertion depth is outside its range.
    #[error(
        "endoscope: insertion depth {} mm is outside [{}, {}] mm",
        Num::outside(*value, *min, *max),
        Num::new(*min),
        Num::new(*max)
    )]
    EndoscopeDepth {
        /// The depth, mm.
        value: f64,
        /// The smallest depth, mm.
        min: f64,
        /// The largest depth, mm.
        max: f64,
    },
}

/// The kind of a singular Jacobian in module 1's forward kinematics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ParallelSingularity {
    /// A parallel (type 2) singularity of the robot: the parallel margin vanished.
    Parallel,
    /// The Euler angles' own singularity, `theta = +-90 deg`: `|cos theta|` vanished.
    EulerAngles,
}

impl fmt::Display for ParallelSingularity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ParallelSingularity::Parallel => "parallel singularity",
            ParallelSingularity::EulerAngles => "Euler angles at theta = +-90 deg",
        })
    }
}

/// `Err(Error::NonFinite)` when `value` is NaN or infinite.
#[inline]
pub fn check_finite<T: Real>(value: T, what: &'static str) -> Result<(), Error> {
    if value.finite() {
        Ok(())
    } else {
        Err(Error::NonFinite {
            what,
            value: value.to_f64(),
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    #[test]
    fn joint_limit_message_names_joint_value_and_limit_in_degrees() {
        let e = Error::JointLimit {
            side: Side::Left,
            joint: Joint::Qs2,
            value: -1.5,
            min: -80f64.to_radians(),
            max: 80f64.to_radians(),
        };
        assert_eq!(
            e.to_string(),
            "left instrument: joint qs2 = -85.9437 deg is outside [-80, 80] deg"
        );
    }

    #[test]
    fn a_value_just_beyond_its_limit_does_not_read_as_the_limit() {
        let e = Error::ActuatorLimit {
            actuator: 4,
            value: 320.000_000_1,
            min: 0.0,
            max: 320.0,
        };
        assert_eq!(
            e.to_string(),
            "module 1: actuator q4 = 320.0000001 mm is outside [0, 320] mm"
        );
        let e = Error::OutOfReach {
            side: Side::Right,
            sin_qs2: 1.000_000_000_01,
        };
        assert_eq!(
            e.to_string(),
            "right instrument: tip out of reach: the tool direction needs |sin qs2| = 1.00000000001 > 1"
        );
    }

    #[test]
    fn non_finite_message_names_the_input() {
        let e = check_finite(f32::NAN, "tip.y").expect_err("NaN");
        assert_eq!(e.to_string(), "non-finite input: tip.y = NaN");
    }
}
