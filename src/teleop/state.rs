//! The operating states and their transitions, as the Collaborative
//! Robotics Toolkit (CRTK) names them (the table is
//! [`OperatingState`]'s).

use super::input::Command;

/// The operating state (CRTK's meta-states).
///
/// Our reading of CRTK's *robot meta-states*: four mutually exclusive
/// states, DISABLED (motion power off: here the setpoint comes to rest and
/// holds, inputs ignored), ENABLED (the robot moves as commanded), PAUSED
/// (power on, the robot cannot be moved: it comes to rest and holds) and
/// FAULT (entered only by the system on a fault it detects, never by a
/// command: here a non-finite input, an input older than the timeout, or a
/// cycle that cannot be solved; the robot makes a controlled stop and
/// holds). CRTK's table, with the planned moves added (`home` and
/// `look_at_tips` here; `look_at` a point and `move_to` a pose, which carry
/// their goal, through [`Teleop::start_move`](crate::teleop::Teleop::start_move)
/// under the same rule: accepted in ENABLED only) and `stop`:
///
/// | state \ command | enable | disable | pause | resume | home, look_at_tips (and the moves) | stop |
/// |---|---|---|---|---|---|---|
/// | DISABLED | ENABLED | DISABLED | DISABLED (invalid) | DISABLED (invalid) | DISABLED (invalid) | DISABLED |
/// | ENABLED | ENABLED | DISABLED | PAUSED | ENABLED (invalid) | ENABLED, busy | ENABLED, busy until at rest |
/// | PAUSED | PAUSED (invalid) | DISABLED | PAUSED | ENABLED | PAUSED (invalid) | PAUSED |
/// | FAULT | ENABLED if cleared, else FAULT (retry refused) | DISABLED | FAULT (invalid) | FAULT (invalid) | FAULT (invalid) | FAULT |
///
/// A fault is *cleared* when this cycle's inputs are finite and fresh and
/// the controlled stop has ended. `is_busy` is CRTK's: a command is being
/// executed, here a planned move or a stop to rest (teleoperation itself
/// is a servo command, never busy); `is_homed` is true (the core starts from a known pose: the
/// drives' referencing is below it); `is_ready` is CRTK's
/// `is_enabled && is_homed`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum OperatingState {
    /// Motion off: the setpoint comes to rest and holds; inputs ignored.
    #[default]
    Disabled,
    /// The hands and the camera drive the robot.
    Enabled,
    /// Power on, held still: the setpoint comes to rest and holds.
    Paused,
    /// A fault was detected: a controlled stop, then held.
    Fault,
}

impl OperatingState {
    /// Every state.
    pub const ALL: [OperatingState; 4] = [
        OperatingState::Disabled,
        OperatingState::Enabled,
        OperatingState::Paused,
        OperatingState::Fault,
    ];

    /// The state's name as CRTK writes it.
    pub const fn name(self) -> &'static str {
        match self {
            OperatingState::Disabled => "DISABLED",
            OperatingState::Enabled => "ENABLED",
            OperatingState::Paused => "PAUSED",
            OperatingState::Fault => "FAULT",
        }
    }

    /// The state after `command` and whether the command is valid (see the
    /// table above); `fault_cleared` decides an `enable` from FAULT.
    pub const fn after(self, command: Command, fault_cleared: bool) -> Transition {
        use Command as C;
        use OperatingState as S;
        let (state, accepted) = match (self, command) {
            (_, C::Disable) => (S::Disabled, true),
            (S::Disabled, C::Enable) => (S::Enabled, true),
            (S::Enabled, C::Enable | C::Home | C::LookAtTips) => (S::Enabled, true),
            (s, C::Stop) => (s, true),
            (S::Enabled, C::Pause) => (S::Paused, true),
            (S::Paused, C::Pause) => (S::Paused, true),
            (S::Paused, C::Resume) => (S::Enabled, true),
            (S::Fault, C::Enable) if fault_cleared => (S::Enabled, true),
            (s, _) => (s, false),
        };
        Transition { state, accepted }
    }
}

impl core::fmt::Display for OperatingState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// A command's outcome: the state after it, and whether it was valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Transition {
    /// The state after the command.
    pub state: OperatingState,
    /// Whether the command was valid in the state it was given in (an
    /// invalid one leaves the state as it was).
    pub accepted: bool,
}
