//! What one cycle of the core returns: the twelve setpoints with the whole
//! control step, the state, the limit held at, the fault.

use crate::kin::nalgebra::Vector3;
use crate::kin::{
    ACTUATOR_COUNT, Actuator, Clearance, ClearancePair, ControlStep, RateKind, Real, Side,
};
use crate::supervisor::{Margin, Margins};

use super::input::{Command, Device};
use super::state::OperatingState;

/// The limit a cycle holds at: the commanded step would have crossed it (at
/// this cycle or before the robot could stop), so the step was reduced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HoldAt {
    /// A supervised margin (a joint limit, a stroke end, a singularity's
    /// margin) would have fallen below the supervisor's stop threshold.
    Margin(Margin),
    /// The gap of a pair of bodies would have fallen below the clearance
    /// stop threshold.
    Clearance(ClearancePair),
    /// The kinematics refuse the commanded pose (out of reach, or a hard
    /// limit the margins do not watch).
    Reach(crate::kin::Error),
    /// An actuator's velocity or acceleration would have gone beyond its
    /// limit ([`Controller::limits`](crate::kin::Controller::limits)).
    Actuator {
        /// Which actuator.
        actuator: Actuator,
        /// Its velocity or its acceleration.
        kind: RateKind,
    },
}

impl core::fmt::Display for HoldAt {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            HoldAt::Margin(m) => write!(f, "margin {m}"),
            HoldAt::Clearance(p) => write!(f, "clearance {p}"),
            HoldAt::Reach(e) => write!(f, "reach: {e}"),
            HoldAt::Actuator { actuator, kind } => write!(f, "{actuator} {kind} limit"),
        }
    }
}

/// Why the core went to FAULT.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// A device's input holds a NaN or an infinity.
    NonFinite {
        /// The device.
        device: Device,
        /// The field (`tx` ... `rz`, `x`, `y`, `z`, `stamp_s`).
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// A device has not reported for longer than the timeout.
    Timeout {
        /// The device.
        device: Device,
        /// How long ago it last reported, s.
        age_s: f64,
    },
    /// Even the controlled stop's cycle cannot be solved: the setpoint is
    /// held where it was.
    Unsolvable(crate::kin::Error),
}

impl core::fmt::Display for Fault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Fault::NonFinite {
                device,
                what,
                value,
            } => write!(f, "the {device} device's {what} is {value}"),
            Fault::Timeout { device, age_s } => {
                write!(f, "the {device} device last reported {age_s} s ago")
            }
            Fault::Unsolvable(e) => write!(f, "the stop cannot be solved: {e}"),
        }
    }
}

/// A command given at a cycle and what became of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CommandOutcome {
    /// The command.
    pub command: Command,
    /// Whether it was valid in the state it was given in.
    pub accepted: bool,
}

/// Everything one cycle of [`Teleop::step`](crate::teleop::Teleop::step)
/// computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TeleopCycle<T: Real> {
    /// The cycle's time, s.
    pub t: T,
    /// The operating state after this cycle.
    pub state: OperatingState,
    /// Whether a command (the home move) is being executed (CRTK's
    /// `is_busy`).
    pub busy: bool,
    /// This cycle's command, if any, and whether it was valid.
    pub command: Option<CommandOutcome>,
    /// The twelve actuator setpoints (module 1's six legs, mm; each
    /// module's `qs1`, `qs2` in rad and `qs3` in mm), in the order of
    /// [`Actuator::ALL`](crate::kin::Actuator::ALL).
    pub setpoints: [T; ACTUATOR_COUNT],
    /// The whole control step: the platform frame, every joint with its
    /// rates, accelerations and margins.
    pub step: ControlStep<T>,
    /// The tips commanded, `[left module, right module]`, mm, fixed frame.
    pub tips: [Vector3<T>; 2],
    /// Their velocities, mm/s, fixed frame.
    pub tip_velocity: [Vector3<T>; 2],
    /// The platform's `[psi, theta]`, rad, and their rates, rad/s.
    pub angles: [T; 2],
    /// The rates of `[psi, theta]`, rad/s.
    pub angle_rates: [T; 2],
    /// The supervised margins of this cycle.
    pub margins: Margins<T>,
    /// The gaps between the bodies, when the core watches them.
    pub clearance: Option<Clearance<T>>,
    /// The limit this cycle holds at (the commanded step was reduced), if
    /// any.
    pub hold: Option<HoldAt>,
    /// The fault that put the core in FAULT (kept until it leaves FAULT).
    pub fault: Option<Fault>,
    /// The module each hand drives, `[left hand, right hand]`, fixed at
    /// enable from where the tips appear in the image.
    pub hands: [Side; 2],
    /// Whether the camera is following the tips.
    pub following: bool,
}
