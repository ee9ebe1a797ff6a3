//! A teleoperation run's columns, after the run's others (CSV and Python
//! only; the MCAP file has the same channels as `simulate`'s): the tips,
//! each
//! device's six axes and buttons as held at the cycle, the command given,
//! the operating state, the limit a held cycle holds at, the fault, and the
//! module each hand drives; and the teleoperation block of the summary
//! ([`TeleopSummary`]).
//!
//! Names are whole numbers in the columns, as the table writes the motion's
//! type and the command's index (`integer` columns), with these codes:
//!
//! | column | codes |
//! |---|---|
//! | `teleop_command` | 0 none, then 1 `enable`, 2 `disable`, 3 `pause`, 4 `resume`, 5 `home`, 6 `look_at_tips`, 7 `stop` (`Command::ALL`'s order, from 1) |
//! | `teleop_state` | 0 DISABLED, 1 ENABLED, 2 PAUSED, 3 FAULT (`OperatingState::ALL`'s order) |
//! | `teleop_hold` | 0 none; 1 to 11 a supervised margin (`Margin::ALL`'s order, from 1); 12 to 14 a clearance pair (`ClearancePair::ALL`'s order); 15 the kinematics' reach; 16 to 39 an actuator's velocity (even) or acceleration (odd) limit, `16 + 2 k + rate` with `k` its place in `Actuator::ALL` |
//! | `teleop_fault` | 0 none, 1 a non-finite input, 2 a silent device, 3 a stop that cannot be solved |
//! | `left_hand_module`, `right_hand_module` | 0 the left module, 1 the right module |

use parasils::kin::{ClearancePair, RateKind, Side};
use parasils::supervisor::Margin;
use parasils::teleop::{Command, Fault, HoldAt, OperatingState};

use crate::columns::{CSV, CSV_COUNT, Column, LEFT, RIGHT, join};
use crate::record::Record;
use crate::sink::Sink;

/// The number of teleoperation columns.
pub const TELEOP_COUNT: usize = 33;

const fn axis(name: &'static str, get: fn(&Record) -> f64) -> Column {
    Column {
        name,
        unit: "1 (normalised, -1 to 1)",
        channel: None,
        csv: true,
        integer: false,
        get,
    }
}

const fn code(name: &'static str, unit: &'static str, get: fn(&Record) -> f64) -> Column {
    Column {
        name,
        unit,
        channel: None,
        csv: true,
        integer: true,
        get,
    }
}

/// The code of `command` in `teleop_command` (0 for none).
pub fn command_code(command: Option<Command>) -> u8 {
    command.map_or(0, |c| {
        let k = Command::ALL.iter().position(|a| *a == c).unwrap_or(0);
        u8::try_from(k + 1).unwrap_or(u8::MAX)
    })
}

/// The code of `state` in `teleop_state`.
pub fn state_code(state: OperatingState) -> u8 {
    let k = OperatingState::ALL.iter().position(|s| *s == state);
    k.and_then(|k| u8::try_from(k).ok()).unwrap_or(u8::MAX)
}

/// The code of `hold` in `teleop_hold` (0 for none).
pub fn hold_code(hold: Option<HoldAt>) -> u8 {
    let k = match hold {
        None => 0,
        Some(HoldAt::Margin(m)) => 1 + m.index(),
        Some(HoldAt::Clearance(p)) => {
            1 + Margin::COUNT + ClearancePair::ALL.iter().position(|a| *a == p).unwrap_or(0)
        }
        Some(HoldAt::Reach(_)) => 1 + Margin::COUNT + ClearancePair::ALL.len(),
        Some(HoldAt::Actuator { actuator, kind }) => {
            let rate = match kind {
                RateKind::Velocity => 0,
                RateKind::Acceleration => 1,
            };
            2 + Margin::COUNT + ClearancePair::ALL.len() + 2 * actuator.index() + rate
        }
    };
    u8::try_from(k).unwrap_or(u8::MAX)
}

/// The code of `fault` in `teleop_fault` (0 for none).
pub fn fault_code(fault: Option<Fault>) -> u8 {
    match fault {
        None => 0,
        Some(Fault::NonFinite { .. }) => 1,
        Some(Fault::Timeout { .. }) => 2,
        Some(Fault::Unsolvable(_)) => 3,
    }
}

fn side_code(side: Side) -> f64 {
    match side {
        Side::Left => 0.0,
        Side::Right => 1.0,
    }
}

const fn in_csv(c: Column) -> Column {
    Column { csv: true, ..c }
}

/// The teleoperation columns, in order: the tips (by forward kinematics
/// from the joints, mm, fixed frame, as a procedure writes them), then each
/// device's axes and buttons, then the codes of the module's table.
pub const TELEOP: [Column; TELEOP_COUNT] = [
    in_csv(LEFT.tip[0]),
    in_csv(LEFT.tip[1]),
    in_csv(LEFT.tip[2]),
    in_csv(RIGHT.tip[0]),
    in_csv(RIGHT.tip[1]),
    in_csv(RIGHT.tip[2]),
    axis("left_tx", |r| r.teleop.axes[0][0]),
    axis("left_ty", |r| r.teleop.axes[0][1]),
    axis("left_tz", |r| r.teleop.axes[0][2]),
    axis("left_rx", |r| r.teleop.axes[0][3]),
    axis("left_ry", |r| r.teleop.axes[0][4]),
    axis("left_rz", |r| r.teleop.axes[0][5]),
    code("left_buttons", "bit mask", |r| {
        f64::from(r.teleop.buttons[0])
    }),
    axis("right_tx", |r| r.teleop.axes[1][0]),
    axis("right_ty", |r| r.teleop.axes[1][1]),
    axis("right_tz", |r| r.teleop.axes[1][2]),
    axis("right_rx", |r| r.teleop.axes[1][3]),
    axis("right_ry", |r| r.teleop.axes[1][4]),
    axis("right_rz", |r| r.teleop.axes[1][5]),
    code("right_buttons", "bit mask", |r| {
        f64::from(r.teleop.buttons[1])
    }),
    axis("camera_tx", |r| r.teleop.axes[2][0]),
    axis("camera_ty", |r| r.teleop.axes[2][1]),
    axis("camera_tz", |r| r.teleop.axes[2][2]),
    axis("camera_rx", |r| r.teleop.axes[2][3]),
    axis("camera_ry", |r| r.teleop.axes[2][4]),
    axis("camera_rz", |r| r.teleop.axes[2][5]),
    code("camera_buttons", "bit mask", |r| {
        f64::from(r.teleop.buttons[2])
    }),
    code("teleop_command", "code", |r| {
        f64::from(command_code(r.teleop.command))
    }),
    code("teleop_state", "code", |r| {
        f64::from(state_code(r.teleop.state))
    }),
    code("teleop_hold", "code", |r| {
        f64::from(hold_code(r.teleop.hold))
    }),
    code("teleop_fault", "code", |r| {
        f64::from(fault_code(r.teleop.fault))
    }),
    code("left_hand_module", "code", |r| side_code(r.teleop.hands[0])),
    code("right_hand_module", "code", |r| {
        side_code(r.teleop.hands[1])
    }),
];

/// A teleoperation run's CSV columns: `simulate`'s ([`CSV`]), then
/// [`TELEOP`].
pub const CSV_WITH_TELEOP: [Column; CSV_COUNT + TELEOP_COUNT] = join(&CSV, &TELEOP);

/// The teleoperation block of the summary: the states visited in order,
/// the cycles held and at which limits, the faults, and the largest change
/// of a commanded tip across a cycle on which a hand's clutch was pressed
/// or released.
#[derive(Debug, Clone, Default)]
pub struct TeleopSummary {
    /// Cycles seen.
    pub cycles: usize,
    /// The states visited, each time the state changed, with the time, s.
    pub states: Vec<(f64, OperatingState)>,
    /// Each limit held at: its description, the number of cycles and the
    /// first time, s.
    pub holds: Vec<(String, usize, f64)>,
    /// Each fault: its description and its first time, s.
    pub faults: Vec<(String, f64)>,
    /// The clutch's presses and releases seen (on either hand).
    pub clutch_changes: usize,
    /// The largest change of a commanded tip's position across a cycle on
    /// which a clutch changed, mm.
    pub clutch_jump_mm: f64,
    last: Option<Record>,
}

impl TeleopSummary {
    /// Nothing seen yet.
    pub fn new() -> Self {
        Self::default()
    }
}

/// The clutch bit of device `d`'s buttons in `r`.
fn clutch(r: &Record, d: usize) -> bool {
    r.teleop.buttons[d] & parasils::teleop::BUTTON_CLUTCH != 0
}

impl Sink for TeleopSummary {
    type Error = core::convert::Infallible;

    fn push(&mut self, r: &Record) -> Result<(), Self::Error> {
        self.cycles += 1;
        let state = r.teleop.state;
        if self.states.last().is_none_or(|(_, s)| *s != state) {
            self.states.push((r.t, state));
        }
        if let Some(hold) = r.teleop.hold {
            let name = hold.to_string();
            match self.holds.iter_mut().find(|(n, _, _)| *n == name) {
                Some((_, n, _)) => *n += 1,
                None => self.holds.push((name, 1, r.t)),
            }
        }
        if let Some(fault) = r.teleop.fault {
            let name = fault.to_string();
            if !self.faults.iter().any(|(n, _)| *n == name) {
                self.faults.push((name, r.t));
            }
        }
        if let Some(last) = &self.last {
            for d in 0..2 {
                if clutch(last, d) != clutch(r, d) {
                    self.clutch_changes += 1;
                    let jump = (r.left.tip - last.left.tip)
                        .norm()
                        .max((r.right.tip - last.right.tip).norm());
                    self.clutch_jump_mm = self.clutch_jump_mm.max(jump);
                }
            }
        }
        self.last = Some(*r);
        Ok(())
    }
}

impl core::fmt::Display for TeleopSummary {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        use parasils_io::Fixed;
        writeln!(f, "teleoperation: {} cycles", self.cycles)?;
        let states: Vec<String> = self
            .states
            .iter()
            .map(|(t, s)| format!("{s} ({} s)", Fixed(*t, 3)))
            .collect();
        writeln!(f, "  states: {}", states.join(" -> "))?;
        if self.holds.is_empty() {
            writeln!(f, "  held at a limit: never")?;
        }
        for (name, n, t) in &self.holds {
            writeln!(f, "  held at {name}: {n} cycles, from {} s", Fixed(*t, 3))?;
        }
        if self.faults.is_empty() {
            writeln!(f, "  faults: none")?;
        }
        for (name, t) in &self.faults {
            writeln!(f, "  fault at {} s: {name}", Fixed(*t, 3))?;
        }
        write!(
            f,
            "  clutch: {} presses and releases, largest tip change across one ",
            self.clutch_changes
        )?;
        // Exactly zero is the design: say it as such, anything else in full.
        if self.clutch_jump_mm == 0.0 {
            write!(f, "0 mm (exactly)")
        } else {
            write!(f, "{:e} mm", self.clutch_jump_mm)
        }
    }
}
