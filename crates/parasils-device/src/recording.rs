//! A recorded input stream: the console's inputs, one row per event, replayed
//! at any rate.
//!
//! The file is CSV with the header
//! `t_s,device,tx,ty,tz,rx,ry,rz,buttons,command`:
//!
//! | column | what |
//! |---|---|
//! | `t_s` | the event's time, s; never decreasing from row to row |
//! | `device` | `left`, `right` (the hands) or `camera` |
//! | `tx` ... `rz` | the six axes in the console's frame (see the crate's docs), each in `[-1, 1]` |
//! | `buttons` | bit mask: bit 0 enable (the dead-man button, held for motion), bit 1 clutch |
//! | `command` | empty, or one of `enable`, `disable`, `pause`, `resume`, `home` |
//!
//! A device's axes and buttons hold until its next row; a command is given
//! once, at its row's time. [`Player::advance`] walks the rows as a control
//! loop's clock passes them.

use std::path::Path;

use parasils::teleop::{Command, Device};

use crate::error::DeviceError;

/// The header a recording starts with, in this order.
pub const HEADER: [&str; 10] = [
    "t_s", "device", "tx", "ty", "tz", "rx", "ry", "rz", "buttons", "command",
];

/// The devices, in the order [`Player::held`] gives them.
pub const DEVICES: [Device; 3] = [Device::Left, Device::Right, Device::Camera];

/// What one device holds from its row on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Held {
    /// `tx`, `ty`, `tz`, `rx`, `ry`, `rz`, each in `[-1, 1]`.
    pub axes: [f64; 6],
    /// Bit 0 enable, bit 1 clutch.
    pub buttons: u8,
}

impl Held {
    /// A device at rest, no button held.
    pub const REST: Self = Self {
        axes: [0.0; 6],
        buttons: 0,
    };
}

/// One row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InputEvent {
    /// When, s.
    pub t_s: f64,
    /// From which device.
    pub device: Device,
    /// Its axes and buttons from now on.
    pub held: Held,
    /// The command given at this instant, if any.
    pub command: Option<Command>,
}

/// A whole recorded stream, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    events: Vec<InputEvent>,
}

impl Recording {
    /// Reads and checks a recording file.
    ///
    /// # Errors
    /// [`DeviceError::RecordingFile`] when the file cannot be read;
    /// [`DeviceError::Recording`], naming the file, the line and the
    /// column, when its content is wrong.
    pub fn read(path: &Path) -> Result<Self, DeviceError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| DeviceError::RecordingFile {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &file)
    }

    /// Parses and checks a recording's text; `file` names it in errors.
    ///
    /// # Errors
    /// [`DeviceError::Recording`]: a header other than [`HEADER`], a time
    /// that is not finite or goes back, an unknown device or command, an
    /// axis that is not a number in `[-1, 1]`, buttons that are not a
    /// non-negative integer.
    pub fn parse(text: &str, file: &str) -> Result<Self, DeviceError> {
        let fail = |line: u64, message: String| DeviceError::Recording {
            file: file.to_owned(),
            line,
            message,
        };
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header = reader.headers().map_err(|e| fail(1, e.to_string()))?;
        if header.iter().ne(HEADER) {
            return Err(fail(1, format!("the header must be {}", HEADER.join(","))));
        }
        let mut events = Vec::new();
        let mut last = f64::NEG_INFINITY;
        for row in reader.records() {
            let row = row.map_err(|e| {
                let line = e.position().map_or(0, csv::Position::line);
                fail(line, e.to_string())
            })?;
            let line = row.position().map_or(0, csv::Position::line);
            let field = |k: usize| row.get(k).unwrap_or("");
            let number = |k: usize| -> Result<f64, DeviceError> {
                field(k)
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        fail(
                            line,
                            format!("{}: `{}` is not a finite number", HEADER[k], field(k)),
                        )
                    })
            };
            let t_s = number(0)?;
            if t_s < last {
                return Err(fail(
                    line,
                    format!("t_s: {t_s} s is before the previous row's {last} s"),
                ));
            }
            last = t_s;
            let device = DEVICES
                .into_iter()
                .find(|s| s.name() == field(1))
                .ok_or_else(|| {
                    fail(
                        line,
                        format!("device: `{}`, expected left, right or camera", field(1)),
                    )
                })?;
            let mut axes = [0.0; 6];
            for (k, axis) in axes.iter_mut().enumerate() {
                *axis = number(k + 2)?;
                if !(-1.0..=1.0).contains(axis) {
                    return Err(fail(
                        line,
                        format!("{}: {} is outside [-1, 1]", HEADER[k + 2], axis),
                    ));
                }
            }
            let buttons = field(8).parse::<u8>().map_err(|_| {
                fail(
                    line,
                    format!("buttons: `{}` is not a bit mask from 0 to 255", field(8)),
                )
            })?;
            let command = match field(9) {
                "" => None,
                name => Some(
                    Command::ALL
                        .into_iter()
                        .find(|c| c.name() == name)
                        .ok_or_else(|| {
                            fail(line, format!("command: `{name}`, expected enable, disable, pause, resume or home"))
                        })?,
                ),
            };
            events.push(InputEvent {
                t_s,
                device,
                held: Held { axes, buttons },
                command,
            });
        }
        Ok(Self { events })
    }

    /// The rows, in order.
    pub fn events(&self) -> &[InputEvent] {
        &self.events
    }

    /// The last row's time, s (0 for an empty recording).
    pub fn end_s(&self) -> f64 {
        self.events.last().map_or(0.0, |e| e.t_s)
    }

    /// A player at the start: every device at rest, no button held.
    pub fn player(&self) -> Player<'_> {
        Player {
            events: &self.events,
            next: 0,
            held: [Held::REST; 3],
        }
    }
}

/// Walks a recording as a clock passes its rows.
#[derive(Clone, Debug)]
pub struct Player<'a> {
    events: &'a [InputEvent],
    next: usize,
    held: [Held; 3],
}

impl Player<'_> {
    /// Applies every row up to and including `t_s` not applied yet, and
    /// returns the commands among them, in order.
    pub fn advance(&mut self, t_s: f64) -> Vec<Command> {
        let mut commands = Vec::new();
        while let Some(event) = self.events.get(self.next).filter(|e| e.t_s <= t_s) {
            if let Some(slot) = self.held.get_mut(index(event.device)) {
                *slot = event.held;
            }
            commands.extend(event.command);
            self.next += 1;
        }
        commands
    }

    /// What each device holds now: left, right, camera.
    pub fn held(&self) -> [Held; 3] {
        self.held
    }

    /// What `device` holds now.
    pub fn state(&self, device: Device) -> Held {
        self.held[index(device)]
    }

    /// Whether every row has been applied.
    pub fn is_done(&self) -> bool {
        self.next >= self.events.len()
    }
}

/// `device`'s place in [`DEVICES`].
fn index(device: Device) -> usize {
    match device {
        Device::Left => 0,
        Device::Right => 1,
        Device::Camera => 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "\
t_s,device,tx,ty,tz,rx,ry,rz,buttons,command
0.0,left,0,0,0,0,0,0,0,enable
0.5,left,0.25,-1,0,0,0,0,1,
0.5,right,0,0,0.5,0,0,0,3,
1.25,camera,0,0,0,0.1,0,0,0,
2.0,left,0,0,0,0,0,0,0,pause
";

    #[test]
    fn rows_hold_until_the_next_and_commands_fire_once() -> Result<(), DeviceError> {
        let rec = Recording::parse(TEXT, "demo.csv")?;
        assert_eq!(rec.events().len(), 5);
        assert_eq!(rec.end_s(), 2.0);
        let mut player = rec.player();
        assert_eq!(player.advance(0.0), [Command::Enable]);
        assert_eq!(player.advance(0.0), []); // given once
        assert_eq!(player.advance(0.499), []);
        assert_eq!(player.state(Device::Left).axes[0], 0.0);
        assert_eq!(player.advance(1.0), []);
        assert_eq!(player.state(Device::Left).axes[..2], [0.25, -1.0]);
        assert_eq!(player.state(Device::Left).buttons, 1);
        assert_eq!(player.state(Device::Right).axes[2], 0.5);
        assert_eq!(player.state(Device::Right).buttons, 3);
        assert_eq!(player.state(Device::Camera).axes[3], 0.0);
        assert_eq!(player.advance(1.25), []);
        assert_eq!(player.state(Device::Camera).axes[3], 0.1);
        assert!(!player.is_done());
        assert_eq!(player.advance(10.0), [Command::Pause]);
        assert!(player.is_done());
        // the left hand's last row holds: at rest, no button
        assert_eq!(player.held()[0].buttons, 0);
        Ok(())
    }

    fn error_of(text: &str) -> String {
        match Recording::parse(text, "bad.csv") {
            Err(e) => e.to_string(),
            Ok(_) => String::from("accepted"),
        }
    }

    #[test]
    fn bad_rows_name_file_line_and_column() {
        let head = "t_s,device,tx,ty,tz,rx,ry,rz,buttons,command\n";
        assert_eq!(
            error_of("t,device\n"),
            "bad.csv: line 1: the header must be t_s,device,tx,ty,tz,rx,ry,rz,buttons,command"
        );
        let cases = [
            (
                "1,left,0,0,0,0,0,0,0,\n0.5,left,0,0,0,0,0,0,0,\n",
                "line 3: t_s: 0.5 s is before",
            ),
            ("0,foot,0,0,0,0,0,0,0,\n", "line 2: device: `foot`"),
            (
                "0,left,0,1.5,0,0,0,0,0,\n",
                "line 2: ty: 1.5 is outside [-1, 1]",
            ),
            (
                "0,left,0,0,NaN,0,0,0,0,\n",
                "line 2: tz: `NaN` is not a finite number",
            ),
            (
                "inf,left,0,0,0,0,0,0,0,\n",
                "line 2: t_s: `inf` is not a finite number",
            ),
            ("0,left,0,0,0,0,0,0,-1,\n", "line 2: buttons: `-1`"),
            ("0,left,0,0,0,0,0,0,0,jump\n", "line 2: command: `jump`"),
            ("0,left,0,0,0\n", "line 2:"),
        ];
        for (rows, expected) in cases {
            let text = error_of(&format!("{head}{rows}"));
            assert!(
                text.starts_with("bad.csv: ") && text.contains(expected),
                "{text}"
            );
        }
    }

    #[test]
    fn reads_a_file_and_names_a_missing_one() -> Result<(), Box<dyn core::error::Error>> {
        let dir = std::env::temp_dir().join(format!("parasils-device-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let path = dir.join("session.csv");
        std::fs::write(&path, TEXT)?;
        let rec = Recording::read(&path)?;
        std::fs::remove_dir_all(&dir)?;
        assert_eq!(rec, Recording::parse(TEXT, "other name")?);
        let missing = Recording::read(&dir.join("none.csv"))
            .err()
            .map(|e| e.to_string());
        assert!(missing.is_some_and(|m| m.starts_with("cannot read ") && m.contains("none.csv: ")));
        Ok(())
    }
}
