//! The mapping's parameters (dead zone, scales, filter, the tip's and the
//! view's limits, the input timeout) and the core's typed errors.

use crate::kin::Real;
use crate::traj::Limits;

/// How inputs become motion, and the limits of that motion. Units in each
/// field's name or doc; every default is **assumed** (see `docs/model.md`,
/// *Teleoperation*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TeleopParams<T> {
    /// The dead zone of every normalised axis, in `[0, 1)` (**assumed** 0.1:
    /// a SpaceMouse at rest reads a few percent).
    pub dead_zone: T,
    /// A rate hand's tip speed at full scale on one axis, mm/s per unit
    /// (**assumed** 20 mm/s).
    pub rate_scale_mm_s: T,
    /// A master's motion scale, tip mm per master mm (**assumed** 0.2, the
    /// dVRK's default).
    pub position_scale: T,
    /// The tremor filter's pole frequency `f_c`, Hz, in `(0, 6)` (**assumed**
    /// 2.5 Hz: see [`LowPass`](crate::teleop::LowPass)).
    pub cutoff_hz: T,
    /// The tip's speed limit, mm/s, fixed frame (**assumed** 25 mm/s).
    pub tip_speed_mm_s: T,
    /// The tip's acceleration limit, mm/s^2 (**assumed** 50 mm/s^2: below
    /// `qs3`'s assumed 60 mm/s^2 by the centripetal share of a 25 mm/s tip
    /// 62.5 mm or more from its RCM, so that a controlled stop keeps to the
    /// actuators' limits; each cycle's actuator rates are checked anyway).
    pub tip_accel_mm_s2: T,
    /// The view's limits on each of `psi` and `theta`, rad/s and rad/s^2
    /// (default the paper's 10 deg/s and 5 deg/s^2); a camera rate at full
    /// scale asks for `v_max`.
    pub camera: Limits<T>,
    /// An input older than this while enabled is a fault, s (**assumed**
    /// 0.05 s, 50 cycles at 1 kHz).
    pub timeout_s: T,
    /// A decoupled tip slower than this is put at rest, mm/s (**assumed**
    /// 1e-3 mm/s; the view likewise below this times 1e-3 rad/mm).
    pub rest_mm_s: T,
}

impl<T: Real> TeleopParams<T> {
    /// The assumed defaults (see each field).
    pub fn assumed() -> Self {
        Self {
            dead_zone: T::lit(0.1),
            rate_scale_mm_s: T::lit(20.0),
            position_scale: T::lit(0.2),
            cutoff_hz: T::lit(2.5),
            tip_speed_mm_s: T::lit(25.0),
            tip_accel_mm_s2: T::lit(50.0),
            camera: Limits::paper(),
            timeout_s: T::lit(0.05),
            rest_mm_s: T::lit(1e-3),
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TeleopError::InvalidParameter`] naming the first that is not finite
    /// or out of its range: `0 <= dead_zone < 1`, `0 < cutoff_hz < 6`, the
    /// others positive.
    pub fn validate(&self) -> Result<(), TeleopError> {
        let bad = |what: &'static str, value: T| {
            Err(TeleopError::InvalidParameter {
                what,
                value: value.to_f64(),
            })
        };
        if !(self.dead_zone >= T::zero() && self.dead_zone < T::one()) {
            return bad("dead_zone", self.dead_zone);
        }
        if !(self.cutoff_hz > T::zero() && self.cutoff_hz < T::lit(6.0)) {
            return bad("cutoff_hz", self.cutoff_hz);
        }
        for (what, v) in [
            ("rate_scale_mm_s", self.rate_scale_mm_s),
            ("position_scale", self.position_scale),
            ("tip_speed_mm_s", self.tip_speed_mm_s),
            ("tip_accel_mm_s2", self.tip_accel_mm_s2),
            ("camera.v_max", self.camera.v_max),
            ("camera.a_max", self.camera.a_max),
            ("timeout_s", self.timeout_s),
            ("rest_mm_s", self.rest_mm_s),
        ] {
            if !(v > T::zero() && v.finite()) {
                return bad(what, v);
            }
        }
        Ok(())
    }
}

/// What the teleoperation core refuses. Mid-operation, limits and faults
/// are never errors (they are states and holds of the cycle); these are the
/// caller's mistakes and a setup that cannot run.
///
/// When this happens: at construction, fix the parameters or the start;
/// from [`Teleop::step`](crate::teleop::Teleop::step), the clock is wrong
/// and nothing changed (the loop keeps the previous setpoint).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TeleopError {
    /// A parameter is not finite or out of its range.
    #[error("teleoperation: the parameter {what} is {value}, out of its range")]
    InvalidParameter {
        /// The parameter's name.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The home pose, the supervisor or the bodies cannot be used (the
    /// kinematics fail at home, or a threshold is invalid).
    #[error("teleoperation: {0}")]
    Setup(#[from] crate::error::Error),
    /// A cycle's time is not finite.
    #[error("teleoperation: the time {value} s is not finite")]
    NonFiniteTime {
        /// The time given, s.
        value: f64,
    },
    /// A cycle's time is before the previous one.
    #[error("teleoperation: the time {t} s is before {last} s, the latest time given")]
    TimeReversed {
        /// The time given, s.
        t: f64,
        /// The latest time given before, s.
        last: f64,
    },
}
