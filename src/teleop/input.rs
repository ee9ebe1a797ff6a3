//! What the console gives the core each cycle: one input per hand and one
//! for the camera, each with its buttons and the time its device last
//! reported, and at most one command.

use crate::kin::Real;
use crate::kin::nalgebra::Vector3;

/// Bit 0 of a device's buttons: the enable (dead-man) button, held for any
/// motion of what the device drives.
pub const BUTTON_ENABLE: u8 = 1;
/// Bit 1 of a hand's buttons: the clutch. While it is held the hand's
/// motion does not move the tip; releasing it re-anchors the hand.
pub const BUTTON_CLUTCH: u8 = 2;

/// Which device an input comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Device {
    /// The surgeon's left hand.
    Left,
    /// The surgeon's right hand.
    Right,
    /// The camera's device.
    Camera,
}

impl Device {
    /// The device's name as the input files write it (`left`, `right`,
    /// `camera`).
    pub const fn name(self) -> &'static str {
        match self {
            Device::Left => "left",
            Device::Right => "right",
            Device::Camera => "camera",
        }
    }
}

impl core::fmt::Display for Device {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a hand commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HandCommand<T> {
    /// A rate device (a SpaceMouse): six axes normalised to `[-1, 1]`,
    /// `[tx, ty, tz, rx, ry, rz]`. The translation drives the tip's
    /// velocity in the image frame: `tx` along the image's `u` axis
    /// (rightwards), `ty` along `v` (upwards), `tz` into the picture (along
    /// the view). The rotation axes are not used by a hand (the instrument
    /// modules place a tip, they have no wrist).
    Rate([T; 6]),
    /// A master arm's position, mm, in the master's frame whose axes the
    /// image's are: `x` along `u`, `y` along `v`, `z` into the picture. Its
    /// change from one cycle to the next, scaled, moves the tip (its
    /// absolute value never does: see the clutch).
    Position(Vector3<T>),
}

/// One hand's input for a cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandInput<T> {
    /// The command.
    pub command: HandCommand<T>,
    /// The buttons: [`BUTTON_ENABLE`], [`BUTTON_CLUTCH`].
    pub buttons: u8,
    /// When the device last reported, s, on the clock of
    /// [`Teleop::step`](crate::teleop::Teleop::step): an input older than
    /// the timeout while enabled is a fault.
    pub stamp_s: T,
}

impl<T: Real> HandInput<T> {
    /// A rate device at rest (every axis 0), no button, reported at `stamp_s`.
    pub fn idle(stamp_s: T) -> Self {
        Self {
            command: HandCommand::Rate([T::zero(); 6]),
            buttons: 0,
            stamp_s,
        }
    }

    /// Whether the enable button is held and the clutch is not.
    pub fn engaged(&self) -> bool {
        self.buttons & BUTTON_ENABLE != 0 && self.buttons & BUTTON_CLUTCH == 0
    }

    /// The first non-finite number of the input, with its name.
    pub(crate) fn non_finite(&self) -> Option<(&'static str, T)> {
        const RATE: [&str; 6] = ["tx", "ty", "tz", "rx", "ry", "rz"];
        const POSITION: [&str; 3] = ["x", "y", "z"];
        if !self.stamp_s.finite() {
            return Some(("stamp_s", self.stamp_s));
        }
        match &self.command {
            HandCommand::Rate(axes) => RATE
                .iter()
                .zip(axes)
                .find(|(_, v)| !v.finite())
                .map(|(n, v)| (*n, *v)),
            HandCommand::Position(p) => POSITION
                .iter()
                .zip(p.iter())
                .find(|(_, v)| !v.finite())
                .map(|(n, v)| (*n, *v)),
        }
    }
}

/// What the camera's device commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CameraCommand<T> {
    /// The view turned at a rate: of the six normalised axes
    /// `[tx, ty, tz, rx, ry, rz]`, `rx` drives `psi`'s rate and `ry`
    /// `theta`'s; the others are not used.
    Rate([T; 6]),
    /// The camera follows the tips ([`Follow`](crate::Follow)).
    Follow,
}

/// The camera's input for a cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraInput<T> {
    /// The command.
    pub command: CameraCommand<T>,
    /// The buttons: [`BUTTON_ENABLE`] held for a rate to turn the view
    /// (following needs no button).
    pub buttons: u8,
    /// When the device last reported, s (as [`HandInput::stamp_s`]).
    pub stamp_s: T,
}

impl<T: Real> CameraInput<T> {
    /// A rate device at rest, no button, reported at `stamp_s`.
    pub fn idle(stamp_s: T) -> Self {
        Self {
            command: CameraCommand::Rate([T::zero(); 6]),
            buttons: 0,
            stamp_s,
        }
    }

    /// The first non-finite number of the input, with its name.
    pub(crate) fn non_finite(&self) -> Option<(&'static str, T)> {
        const RATE: [&str; 6] = ["tx", "ty", "tz", "rx", "ry", "rz"];
        if !self.stamp_s.finite() {
            return Some(("stamp_s", self.stamp_s));
        }
        match &self.command {
            CameraCommand::Rate(axes) => RATE
                .iter()
                .zip(axes)
                .find(|(_, v)| !v.finite())
                .map(|(n, v)| (*n, *v)),
            CameraCommand::Follow => None,
        }
    }
}

/// A command of the operating state machine (CRTK's names; see
/// [`OperatingState`](crate::teleop::OperatingState)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// Power the motion: DISABLED to ENABLED (or a retry from FAULT).
    Enable,
    /// Stop and hold, motion off.
    Disable,
    /// Hold still with the motion on: ENABLED to PAUSED.
    Pause,
    /// PAUSED back to ENABLED.
    Resume,
    /// A planned move to the home pose (ENABLED only; busy while it runs).
    Home,
    /// A planned turn of the view to the tips' midpoint, the tips held
    /// (ENABLED only; busy while it runs).
    LookAtTips,
    /// The controlled stop to rest: ends any move and, in ENABLED, brings
    /// the robot to rest (busy until it is) before the hands drive again.
    /// Valid in every state.
    Stop,
}

impl Command {
    /// Every command, in the order of CRTK's table (then `home`,
    /// `look_at_tips`, `stop`).
    pub const ALL: [Command; 7] = [
        Command::Enable,
        Command::Disable,
        Command::Pause,
        Command::Resume,
        Command::Home,
        Command::LookAtTips,
        Command::Stop,
    ];

    /// The command's name as the input files write it.
    pub const fn name(self) -> &'static str {
        match self {
            Command::Enable => "enable",
            Command::Disable => "disable",
            Command::Pause => "pause",
            Command::Resume => "resume",
            Command::Home => "home",
            Command::LookAtTips => "look_at_tips",
            Command::Stop => "stop",
        }
    }
}

impl core::fmt::Display for Command {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Everything the console gives one cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inputs<T> {
    /// The left hand.
    pub left: HandInput<T>,
    /// The right hand.
    pub right: HandInput<T>,
    /// The camera's device.
    pub camera: CameraInput<T>,
    /// A command given at this cycle, applied before the motion.
    pub command: Option<Command>,
}

impl<T: Real> Inputs<T> {
    /// Every device idle and reported at `stamp_s`, no command.
    pub fn idle(stamp_s: T) -> Self {
        Self {
            left: HandInput::idle(stamp_s),
            right: HandInput::idle(stamp_s),
            camera: CameraInput::idle(stamp_s),
            command: None,
        }
    }

    /// The same inputs with `command`.
    #[must_use]
    pub fn with_command(mut self, command: Command) -> Self {
        self.command = Some(command);
        self
    }
}
