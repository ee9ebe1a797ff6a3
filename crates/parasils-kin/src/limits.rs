//! The actuators' velocity, acceleration and force limits, and the check of
//! one control cycle against them.
//!
//! The robot has twelve actuators, always listed in this order (the
//! [`Actuator::index`]): module 1's sliders `q1..q6` (mm), then the left
//! module's `qs1`, `qs2` (rad), `qs3` (mm), then the right module's. An
//! [`ActuatorLimits`] holds one velocity and one acceleration maximum per
//! actuator, in the crate's units (mm/s, mm/s^2 for sliders and `qs3`;
//! rad/s, rad/s^2 for `qs1`, `qs2`), and one force maximum (N for the
//! sliders and `qs3`, N mm for the torques of `qs1`, `qs2`; see
//! `docs/model.md`, *Forces*). The paper gives none: the defaults
//! ([`ActuatorLimits::assumed`]) are **assumed** (see `docs/model.md`,
//! *Time-optimal timing*).
//!
//! ```
//! use parasils_kin::{Actuator, ActuatorLimits, Joint, Side};
//!
//! let limits = ActuatorLimits::<f64>::assumed();
//! let qs2 = Actuator::Instrument { side: Side::Left, joint: Joint::Qs2 };
//! assert_eq!(qs2.index(), 7);
//! assert!((limits.velocity[7].to_degrees() - 30.0).abs() < 1e-12);
//! // A left qs2 rate of 31 deg/s is an error naming it:
//! let mut rates = [0.0; 12];
//! rates[7] = 31f64.to_radians();
//! let e = limits.check_rates(&rates, &[0.0; 12]).expect_err("31 > 30 deg/s");
//! assert_eq!(e.to_string(), "left qs2: velocity 31 deg/s is beyond its limit 30 deg/s");
//! ```

use core::fmt;

use parasils_num::Num;

use crate::error::Joint;
use crate::real::Real;
use crate::side::Side;

/// How many actuators the robot has: six sliders and two times three joints.
pub const ACTUATOR_COUNT: usize = 12;

/// Module 1's slider velocity limit, mm/s (**assumed**).
pub const SLIDER_VELOCITY_MAX_MM_S: f64 = 50.0;
/// Module 1's slider acceleration limit, mm/s^2 (**assumed**).
pub const SLIDER_ACCELERATION_MAX_MM_S2: f64 = 100.0;
/// `qs1`'s and `qs2`'s velocity limit, deg/s (**assumed**).
pub const QS12_VELOCITY_MAX_DEG_S: f64 = 30.0;
/// `qs1`'s and `qs2`'s acceleration limit, deg/s^2 (**assumed**).
pub const QS12_ACCELERATION_MAX_DEG_S2: f64 = 60.0;
/// `qs3`'s velocity limit, mm/s (**assumed**).
pub const QS3_VELOCITY_MAX_MM_S: f64 = 60.0;
/// `qs3`'s acceleration limit, mm/s^2 (**assumed**).
pub const QS3_ACCELERATION_MAX_MM_S2: f64 = 60.0;
/// Module 1's slider force limit, N (**assumed**).
pub const SLIDER_FORCE_MAX_N: f64 = 200.0;
/// `qs1`'s and `qs2`'s torque limit, N mm (**assumed**).
pub const QS12_TORQUE_MAX_NMM: f64 = 3000.0;
/// `qs3`'s force limit, N (**assumed**).
pub const QS3_FORCE_MAX_N: f64 = 40.0;

/// One of the robot's twelve actuators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Actuator {
    /// Module 1's slider `q{0}`, numbered 1 to 6.
    Module1(u8),
    /// A joint of an instrument module.
    Instrument {
        /// Which module.
        side: Side,
        /// Which joint.
        joint: Joint,
    },
}

impl Actuator {
    /// The twelve actuators in their order: `q1..q6`, left `qs1..qs3`, right `qs1..qs3`.
    pub const ALL: [Actuator; ACTUATOR_COUNT] = [
        Actuator::Module1(1),
        Actuator::Module1(2),
        Actuator::Module1(3),
        Actuator::Module1(4),
        Actuator::Module1(5),
        Actuator::Module1(6),
        Actuator::Instrument {
            side: Side::Left,
            joint: Joint::Qs1,
        },
        Actuator::Instrument {
            side: Side::Left,
            joint: Joint::Qs2,
        },
        Actuator::Instrument {
            side: Side::Left,
            joint: Joint::Qs3,
        },
        Actuator::Instrument {
            side: Side::Right,
            joint: Joint::Qs1,
        },
        Actuator::Instrument {
            side: Side::Right,
            joint: Joint::Qs2,
        },
        Actuator::Instrument {
            side: Side::Right,
            joint: Joint::Qs3,
        },
    ];

    /// Its place in [`Actuator::ALL`] (and in every array of twelve), 0 to 11.
    /// A module-1 number outside 1 to 6 is clamped into it.
    pub fn index(self) -> usize {
        match self {
            Actuator::Module1(n) => usize::from(n.clamp(1, 6)) - 1,
            Actuator::Instrument { side, joint } => {
                let base = match side {
                    Side::Left => 6,
                    Side::Right => 9,
                };
                base + match joint {
                    Joint::Qs1 => 0,
                    Joint::Qs2 => 1,
                    Joint::Qs3 => 2,
                }
            }
        }
    }

    /// The actuator at `index` in [`Actuator::ALL`], if any.
    pub fn from_index(index: usize) -> Option<Actuator> {
        Actuator::ALL.get(index).copied()
    }

    /// Whether its position is an angle (rad inside, degrees for people).
    pub fn is_angular(self) -> bool {
        matches!(
            self,
            Actuator::Instrument {
                joint: Joint::Qs1 | Joint::Qs2,
                ..
            }
        )
    }

    /// `value` (rad or mm, per s or s^2) in the unit people read: degrees for
    /// `qs1`, `qs2`; unchanged otherwise.
    pub fn display_value(self, value: f64) -> f64 {
        if self.is_angular() {
            value.to_degrees()
        } else {
            value
        }
    }

    /// The position unit of [`Actuator::display_value`]: `"deg"` or `"mm"`.
    pub fn display_unit(self) -> &'static str {
        if self.is_angular() { "deg" } else { "mm" }
    }

    /// What it exerts and its unit: `("torque", "N mm")` for `qs1`, `qs2`,
    /// `("force", "N")` otherwise.
    pub fn effort(self) -> (&'static str, &'static str) {
        if self.is_angular() {
            ("torque", "N mm")
        } else {
            ("force", "N")
        }
    }
}

impl fmt::Display for Actuator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Actuator::Module1(n) => write!(f, "module 1 q{n}"),
            Actuator::Instrument { side, joint } => write!(f, "{side} {joint}"),
        }
    }
}

/// Which limit of an actuator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum RateKind {
    /// The velocity (mm/s or rad/s).
    Velocity,
    /// The acceleration (mm/s^2 or rad/s^2).
    Acceleration,
}

impl fmt::Display for RateKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RateKind::Velocity => "velocity",
            RateKind::Acceleration => "acceleration",
        })
    }
}

/// An actuator's velocity or acceleration beyond its limit, or a limit that
/// is not a positive number.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LimitError {
    /// A rate beyond its limit (values in the crate's units: mm or rad, per s or s^2).
    #[error(
        "{actuator}: {kind} {} {}/s{} is beyond its limit {} {}/s{}",
        Num::apart_from(actuator.display_value(*value), actuator.display_value(*limit)),
        actuator.display_unit(), kind_power(*kind),
        Num::new(actuator.display_value(*limit)), actuator.display_unit(), kind_power(*kind)
    )]
    Exceeded {
        /// Which actuator.
        actuator: Actuator,
        /// Velocity or acceleration.
        kind: RateKind,
        /// The value (signed), mm/s or rad/s (or per s^2).
        value: f64,
        /// The limit, a magnitude.
        limit: f64,
    },
    /// A limit that is zero, negative or NaN (an infinite limit means none).
    #[error(
        "{actuator}: {kind} limit {} is not a positive number",
        Num::new(actuator.display_value(*value))
    )]
    Invalid {
        /// Which actuator.
        actuator: Actuator,
        /// Velocity or acceleration.
        kind: RateKind,
        /// The value given (crate units).
        value: f64,
    },
    /// A force or torque beyond its limit (N, or N mm for `qs1`, `qs2`).
    #[error(
        "{actuator}: {} {} {} is beyond its limit {} {}",
        actuator.effort().0,
        Num::apart_from(*value, *limit), actuator.effort().1,
        Num::new(*limit), actuator.effort().1
    )]
    ForceExceeded {
        /// Which actuator.
        actuator: Actuator,
        /// The force or torque (signed), N or N mm.
        value: f64,
        /// The limit, a magnitude.
        limit: f64,
    },
    /// A force limit that is zero, negative or NaN (an infinite limit
    /// means none).
    #[error(
        "{actuator}: {} limit {} is not a positive number",
        actuator.effort().0, Num::new(*value)
    )]
    InvalidForce {
        /// Which actuator.
        actuator: Actuator,
        /// The value given, N or N mm.
        value: f64,
    },
}

fn kind_power(kind: RateKind) -> &'static str {
    match kind {
        RateKind::Velocity => "",
        RateKind::Acceleration => "^2",
    }
}

/// One velocity and one acceleration maximum per actuator, in the order of
/// [`Actuator::ALL`], in the crate's units (mm/s, mm/s^2; rad/s, rad/s^2).
/// A limit is a magnitude: `|rate| <= limit`; `+inf` means none. With them,
/// one force maximum per actuator: N for the sliders and `qs3`, N mm for
/// the torques of `qs1`, `qs2`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ActuatorLimits<T> {
    /// Velocity maxima.
    pub velocity: [T; ACTUATOR_COUNT],
    /// Acceleration maxima.
    pub acceleration: [T; ACTUATOR_COUNT],
    /// Force (N) and torque (N mm) maxima.
    pub force: [T; ACTUATOR_COUNT],
}

impl<T: Real> ActuatorLimits<T> {
    /// The **assumed** defaults: module 1's sliders 50 mm/s, 100 mm/s^2 and
    /// 200 N, `qs1` and `qs2` 30 deg/s, 60 deg/s^2 and 3000 N mm, `qs3`
    /// 60 mm/s, 60 mm/s^2 and 40 N.
    pub fn assumed() -> Self {
        let mut velocity = [T::lit(SLIDER_VELOCITY_MAX_MM_S); ACTUATOR_COUNT];
        let mut acceleration = [T::lit(SLIDER_ACCELERATION_MAX_MM_S2); ACTUATOR_COUNT];
        for (a, (v, acc)) in Actuator::ALL
            .iter()
            .zip(velocity.iter_mut().zip(acceleration.iter_mut()))
        {
            if let Actuator::Instrument { joint, .. } = a {
                (*v, *acc) = match joint {
                    Joint::Qs1 | Joint::Qs2 => (
                        T::lit(QS12_VELOCITY_MAX_DEG_S.to_radians()),
                        T::lit(QS12_ACCELERATION_MAX_DEG_S2.to_radians()),
                    ),
                    Joint::Qs3 => (
                        T::lit(QS3_VELOCITY_MAX_MM_S),
                        T::lit(QS3_ACCELERATION_MAX_MM_S2),
                    ),
                };
            }
        }
        let force = Actuator::ALL.map(|a| match a {
            Actuator::Module1(_) => T::lit(SLIDER_FORCE_MAX_N),
            Actuator::Instrument {
                joint: Joint::Qs3, ..
            } => T::lit(QS3_FORCE_MAX_N),
            Actuator::Instrument { .. } => T::lit(QS12_TORQUE_MAX_NMM),
        });
        Self {
            velocity,
            acceleration,
            force,
        }
    }

    /// No limit at all (every maximum `+inf`).
    pub fn unlimited() -> Self {
        Self {
            velocity: [T::lit(f64::INFINITY); ACTUATOR_COUNT],
            acceleration: [T::lit(f64::INFINITY); ACTUATOR_COUNT],
            force: [T::lit(f64::INFINITY); ACTUATOR_COUNT],
        }
    }

    /// `Err(LimitError::Invalid)` for the first limit that is zero, negative
    /// or NaN.
    pub fn validate(&self) -> Result<(), LimitError> {
        for (k, (&v, &a)) in self.velocity.iter().zip(&self.acceleration).enumerate() {
            let actuator = Actuator::ALL
                .get(k)
                .copied()
                .unwrap_or(Actuator::Module1(1));
            for (kind, value) in [(RateKind::Velocity, v), (RateKind::Acceleration, a)] {
                if !(value > T::zero()) {
                    return Err(LimitError::Invalid {
                        actuator,
                        kind,
                        value: value.to_f64(),
                    });
                }
            }
        }
        for (&actuator, &value) in Actuator::ALL.iter().zip(&self.force) {
            if !(value > T::zero()) {
                return Err(LimitError::InvalidForce {
                    actuator,
                    value: value.to_f64(),
                });
            }
        }
        Ok(())
    }

    /// Checks forces and torques given in the order of [`Actuator::ALL`]
    /// (N, N mm: `RobotForces::to_array`): the first beyond its limit is the
    /// error ([`LimitError::ForceExceeded`]). A NaN is beyond any limit.
    pub fn check_forces(&self, force: &[T; ACTUATOR_COUNT]) -> Result<(), LimitError> {
        for ((&actuator, &value), &limit) in Actuator::ALL.iter().zip(force).zip(&self.force) {
            if !(value.abs() <= limit) {
                return Err(LimitError::ForceExceeded {
                    actuator,
                    value: value.to_f64(),
                    limit: limit.to_f64(),
                });
            }
        }
        Ok(())
    }

    /// Checks rates and accelerations given in the order of [`Actuator::ALL`]:
    /// the first actuator (velocity before acceleration) beyond its limit is
    /// the error. A NaN rate is beyond any limit.
    pub fn check_rates(
        &self,
        q_dot: &[T; ACTUATOR_COUNT],
        q_ddot: &[T; ACTUATOR_COUNT],
    ) -> Result<(), LimitError> {
        let rows = Actuator::ALL
            .iter()
            .zip(q_dot.iter().zip(q_ddot))
            .zip(self.velocity.iter().zip(&self.acceleration));
        for ((&actuator, (&v, &a)), (&v_max, &a_max)) in rows {
            for (kind, value, limit) in [
                (RateKind::Velocity, v, v_max),
                (RateKind::Acceleration, a, a_max),
            ] {
                if !(value.abs() <= limit) {
                    return Err(LimitError::Exceeded {
                        actuator,
                        kind,
                        value: value.to_f64(),
                        limit: limit.to_f64(),
                    });
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    #[test]
    fn every_index_round_trips_and_names_read_as_the_columns() {
        for (k, a) in Actuator::ALL.iter().enumerate() {
            assert_eq!(a.index(), k);
            assert_eq!(Actuator::from_index(k), Some(*a));
        }
        assert_eq!(Actuator::from_index(12), None);
        assert_eq!(Actuator::ALL[3].to_string(), "module 1 q4");
        assert_eq!(Actuator::ALL[11].to_string(), "right qs3");
    }

    #[test]
    fn assumed_limits_are_the_documented_numbers() {
        let l = ActuatorLimits::<f64>::assumed();
        assert_eq!(l.velocity[0], 50.0);
        assert_eq!(l.acceleration[5], 100.0);
        assert!((l.velocity[9].to_degrees() - 30.0).abs() < 1e-12);
        assert!((l.acceleration[10].to_degrees() - 60.0).abs() < 1e-12);
        assert_eq!((l.velocity[8], l.acceleration[11]), (60.0, 60.0));
        assert!(l.validate().is_ok());
    }

    #[test]
    fn the_first_excess_is_named_with_its_value_and_limit() {
        let l = ActuatorLimits::<f64>::assumed();
        let mut v = [0.0; 12];
        let mut a = [0.0; 12];
        a[2] = -100.5;
        v[11] = 61.0;
        let e = l.check_rates(&v, &a).expect_err("q3 first");
        assert_eq!(
            e.to_string(),
            "module 1 q3: acceleration -100.5 mm/s^2 is beyond its limit 100 mm/s^2"
        );
        a[2] = -100.0; // exactly at the limit is within it
        let e = l.check_rates(&v, &a).expect_err("right qs3");
        assert_eq!(
            e,
            LimitError::Exceeded {
                actuator: Actuator::ALL[11],
                kind: RateKind::Velocity,
                value: 61.0,
                limit: 60.0
            }
        );
        v[11] = f64::NAN;
        assert!(
            l.check_rates(&v, &a).is_err(),
            "NaN is never within a limit"
        );
        let mut bad = l;
        bad.acceleration[7] = 0.0;
        assert_eq!(
            bad.validate().map_err(|e| e.to_string()),
            Err("left qs2: acceleration limit 0 is not a positive number".to_string())
        );
        assert!(ActuatorLimits::<f32>::unlimited().validate().is_ok());
    }

    #[test]
    fn forces_beyond_their_limits_are_named_in_newtons_or_newton_millimetres() {
        let l = ActuatorLimits::<f64>::assumed();
        assert_eq!((l.force[0], l.force[7], l.force[11]), (200.0, 3000.0, 40.0));
        let mut f = [0.0; 12];
        f[5] = -200.0;
        f[10] = 3000.0;
        assert!(
            l.check_forces(&f).is_ok(),
            "a limit is reached, not exceeded"
        );
        f[10] = -3100.0;
        assert_eq!(
            l.check_forces(&f).map_err(|e| e.to_string()),
            Err("right qs2: torque -3100 N mm is beyond its limit 3000 N mm".to_string())
        );
        f[2] = 250.5;
        assert_eq!(
            l.check_forces(&f).map_err(|e| e.to_string()),
            Err("module 1 q3: force 250.5 N is beyond its limit 200 N".to_string())
        );
        f[2] = f64::NAN;
        assert!(l.check_forces(&f).is_err(), "NaN is never within a limit");
        let mut bad = l;
        bad.force[8] = -1.0;
        assert_eq!(
            bad.validate().map_err(|e| e.to_string()),
            Err("left qs3: force limit -1 is not a positive number".to_string())
        );
    }
}
