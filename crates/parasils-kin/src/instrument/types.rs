//! The value types of an instrument module: assembly modes, joints, limits,
//! thresholds, margins, solutions and tip motions.

use nalgebra::Vector3;

use crate::check::check_vector;
use crate::error::{Error, Joint, check_finite};
use crate::interval::Interval;
use crate::presets;
use crate::real::{Real, deg};
use crate::side::Side;

/// One of the two solutions of the inverse kinematics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum AssemblyMode {
    /// `cos qs2 > 0`, `|qs2| < 90 deg`: the working mode, the default.
    #[default]
    A,
    /// `cos qs2 < 0`, `|qs2| > 90 deg`.
    B,
}

impl AssemblyMode {
    /// The mode a configuration is in (A when `cos qs2 >= 0`).
    pub fn of<T: Real>(q: &Joints<T>) -> Self {
        if q.qs2.sincos().1 >= T::zero() {
            AssemblyMode::A
        } else {
            AssemblyMode::B
        }
    }
}

/// The joints of an instrument module, or their rates.
///
/// As positions: `qs1`, `qs2` in rad, `qs3` in mm. As rates: rad/s and mm/s;
/// as accelerations: rad/s^2 and mm/s^2.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Joints<T> {
    /// First rotation (about the linkage's `x`), rad.
    pub qs1: T,
    /// Second rotation (about the linkage's `y`), rad.
    pub qs2: T,
    /// Insertion, the distance from the RCM to the tip, mm.
    pub qs3: T,
}

impl<T: Real> Joints<T> {
    /// Joints from `qs1`, `qs2` (rad) and `qs3` (mm).
    pub const fn new(qs1: T, qs2: T, qs3: T) -> Self {
        Self { qs1, qs2, qs3 }
    }

    /// Joints from `qs1`, `qs2` in **degrees** and `qs3` in mm.
    pub fn from_deg_mm(qs1: f64, qs2: f64, qs3: f64) -> Self {
        Self::new(deg(qs1), deg(qs2), T::lit(qs3))
    }

    /// `[qs1, qs2, qs3]`.
    pub fn to_array(&self) -> [T; 3] {
        [self.qs1, self.qs2, self.qs3]
    }

    /// `[qs1, qs2, qs3]` as a vector.
    pub fn to_vector(&self) -> Vector3<T> {
        Vector3::new(self.qs1, self.qs2, self.qs3)
    }

    /// Joints from a vector `[qs1, qs2, qs3]`.
    pub fn from_vector(v: &Vector3<T>) -> Self {
        Self::new(v.x, v.y, v.z)
    }

    /// `Err(Error::NonFinite)` naming the first NaN or infinite joint.
    pub fn check_finite(&self) -> Result<(), Error> {
        check_finite(self.qs1, "joints.qs1")?;
        check_finite(self.qs2, "joints.qs2")?;
        check_finite(self.qs3, "joints.qs3")
    }
}

/// A configuration's joints with the sines and cosines of `qs1` and `qs2`:
/// what the forward kinematics needs of them
/// ([`Instrument::fk_platform_trig`](super::Instrument::fk_platform_trig)),
/// computed once for several modules at the same joints (the perturbed
/// robots of a tolerance study replaying one command).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointsTrig<T> {
    /// `sin qs1`, `cos qs1`, `sin qs2`, `cos qs2`.
    pub(super) s1: T,
    pub(super) c1: T,
    pub(super) s2: T,
    pub(super) c2: T,
    /// The insertion `qs3`, mm.
    pub(super) qs3: T,
}

impl<T: Real> JointsTrig<T> {
    /// The sines and cosines of `q`'s angles (the crate's
    /// [`Real::sincos`], as every solver of the module), with its `qs3`.
    pub fn of(q: &Joints<T>) -> Self {
        let (s1, c1) = q.qs1.sincos();
        let (s2, c2) = q.qs2.sincos();
        Self {
            s1,
            c1,
            s2,
            c2,
            qs3: q.qs3,
        }
    }
}

/// Joint limits of an instrument module.
///
/// The defaults are **assumed** (the paper gives none; see `docs/model.md`,
/// *Instrument modules*): `qs1` in `[-120, 120] deg`, `qs2` in
/// `[-80, 80] deg`, `qs3` in `[10, 300] mm` ([`presets::QS1_LIMITS_DEG`],
/// [`presets::QS2_LIMITS_DEG`], [`presets::QS3_LIMITS_MM`]).
/// Note that the default `qs2` range excludes assembly mode B entirely.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JointLimits<T> {
    /// `qs1`, rad.
    pub qs1: Interval<T>,
    /// `qs2`, rad.
    pub qs2: Interval<T>,
    /// `qs3`, mm.
    pub qs3: Interval<T>,
}

impl<T: Real> Default for JointLimits<T> {
    fn default() -> Self {
        let [qs1_min, qs1_max] = presets::QS1_LIMITS_DEG;
        let [qs2_min, qs2_max] = presets::QS2_LIMITS_DEG;
        let [qs3_min, qs3_max] = presets::QS3_LIMITS_MM;
        Self {
            qs1: Interval::new(deg(qs1_min), deg(qs1_max)),
            qs2: Interval::new(deg(qs2_min), deg(qs2_max)),
            qs3: Interval::new(T::lit(qs3_min), T::lit(qs3_max)),
        }
    }
}

impl<T: Real> JointLimits<T> {
    /// No limits at all: every configuration the linkage reaches is accepted
    /// (the singularity thresholds still apply).
    pub fn unlimited() -> Self {
        let inf = T::lit(f64::INFINITY);
        Self {
            qs1: Interval::new(-inf, inf),
            qs2: Interval::new(-inf, inf),
            qs3: Interval::new(-inf, inf),
        }
    }

    /// The distance of each joint to its nearer limit (rad, rad, mm),
    /// negative for a joint beyond its limit.
    pub fn margins(&self, q: &Joints<T>) -> Joints<T> {
        Joints::new(
            self.qs1.margin(q.qs1),
            self.qs2.margin(q.qs2),
            self.qs3.margin(q.qs3),
        )
    }

    /// `Err(Error::JointLimit)` for the first joint beyond its limit.
    pub fn check(&self, side: Side, q: &Joints<T>) -> Result<(), Error> {
        for (joint, value, range) in [
            (Joint::Qs1, q.qs1, &self.qs1),
            (Joint::Qs2, q.qs2, &self.qs2),
            (Joint::Qs3, q.qs3, &self.qs3),
        ] {
            if !(value >= range.min && value <= range.max) {
                return Err(Error::JointLimit {
                    side,
                    joint,
                    value: value.to_f64(),
                    min: range.min.to_f64(),
                    max: range.max.to_f64(),
                });
            }
        }
        Ok(())
    }
}

/// The thresholds at which the inverse kinematics reports an error.
///
/// Defaults (see `docs/model.md`, *Singularities and thresholds*): out of
/// reach when `|v_x| > cos(beta) (1 + reach)` with `reach = max(1e-12, 8 eps)`
/// (relative; 1e-12 in f64, about 1e-6 in f32);
/// between `cos(beta)` and that bound the direction is clamped onto the
/// boundary, where it is singular. Singular when `|cos qs2| < 1e-6` or
/// `qs3 < 1e-6 mm`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Thresholds<T> {
    /// Relative tolerance of the reach test (dimensionless).
    pub reach: T,
    /// Smallest accepted `|cos qs2|` (dimensionless).
    pub cos_qs2: T,
    /// Smallest accepted `qs3`, mm.
    pub qs3: T,
}

impl<T: Real> Default for Thresholds<T> {
    fn default() -> Self {
        let eight_eps = T::EPSILON * T::lit(8.0);
        Self {
            reach: T::lit(1e-12).max(eight_eps),
            cos_qs2: T::lit(1e-6),
            qs3: T::lit(1e-6),
        }
    }
}

/// What a controller watches on an instrument module every cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct InstrumentMargins<T> {
    /// `|cos qs2|`: 1 far from the reach boundary, 0 on it (dimensionless).
    pub cos_qs2: T,
    /// `qs3`, mm: 0 when the tip is at the RCM.
    pub qs3: T,
    /// Each joint's distance to its nearer limit (rad, rad, mm).
    pub limits: Joints<T>,
}

/// The solution for one module at one instant: joints, rates, accelerations
/// and margins.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct InstrumentSolution<T> {
    /// Joint positions (rad, rad, mm).
    pub q: Joints<T>,
    /// Joint velocities (rad/s, rad/s, mm/s).
    pub q_dot: Joints<T>,
    /// Joint accelerations (rad/s^2, rad/s^2, mm/s^2).
    pub q_ddot: Joints<T>,
    /// Margins at `q`.
    pub margins: InstrumentMargins<T>,
}

/// Joints commanded directly, with their rates and accelerations: a module
/// whose joints are held (motion types 1 and 4 for the module that does not
/// move its tip) or driven one by one (motion type 2, the insertion along the
/// tool's axis, which moves `qs3` only).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JointMotion<T> {
    /// Joint positions (rad, rad, mm).
    pub q: Joints<T>,
    /// Joint velocities (rad/s, rad/s, mm/s).
    pub q_dot: Joints<T>,
    /// Joint accelerations (rad/s^2, rad/s^2, mm/s^2).
    pub q_ddot: Joints<T>,
}

impl<T: Real> JointMotion<T> {
    /// The joints `q` held still.
    pub fn held(q: Joints<T>) -> Self {
        let zero = Joints::new(T::zero(), T::zero(), T::zero());
        Self {
            q,
            q_dot: zero,
            q_ddot: zero,
        }
    }
}

/// A tip target in the fixed frame with its velocity and acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TipMotion<T: Real> {
    /// Position, mm, fixed frame.
    pub position: Vector3<T>,
    /// Velocity, mm/s, fixed frame.
    pub velocity: Vector3<T>,
    /// Acceleration, mm/s^2, fixed frame.
    pub acceleration: Vector3<T>,
}

impl<T: Real> TipMotion<T> {
    /// A tip held still at `position` (mm, fixed frame): motion type 4.
    pub fn still(position: Vector3<T>) -> Self {
        Self {
            position,
            velocity: Vector3::zeros(),
            acceleration: Vector3::zeros(),
        }
    }

    /// `Err(Error::NonFinite)` naming the first NaN or infinite component.
    pub fn check_finite(&self) -> Result<(), Error> {
        check_vector(&self.position, ["tip.x", "tip.y", "tip.z"])?;
        check_vector(
            &self.velocity,
            ["tip_velocity.x", "tip_velocity.y", "tip_velocity.z"],
        )?;
        check_vector(
            &self.acceleration,
            [
                "tip_acceleration.x",
                "tip_acceleration.y",
                "tip_acceleration.z",
            ],
        )
    }
}
