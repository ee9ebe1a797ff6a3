//! What clients send: a hand's (or the camera's) input and the CRTK
//! commands, as JSON on client-published channels, parsed into typed values
//! or refused with the reason.
//!
//! | topic | message |
//! |---|---|
//! | `/left/servo_input`, `/right/servo_input`, `/camera/servo_input` | `{"axes": [tx, ty, tz, rx, ry, rz], "buttons": 3, "id": 7}`: the six normalised axes of the device driving that hand (each in `[-1, 1]`, the core's rate command), the buttons (bit 0 enable, bit 1 clutch), an optional `id` echoed in `/diagnostics` |
//! | `/command` | `{"command": "enable", "id": 12}`: one of `enable`, `disable`, `pause`, `resume` (CRTK's names), `home`, `look_at_tips`, `stop`; `{"command": "look_at", "point_mm": [x, y, z]}` (a point in the fixed frame, mm); `{"command": "move_to", "psi_deg": a, "theta_deg": b, "left_tip_mm": [x, y, z], "right_tip_mm": [x, y, z]}` (the view's angles, deg, and the tips, mm, fixed frame; a tip not given stays where it is); an optional `id` echoed in the acknowledgement |
//!
//! A device's input is held until its next message, as a SpaceMouse's
//! state is; a message that does not parse changes nothing and gets an
//! error back to the client that sent it.
//!
//! An input topic also takes a twist, `{"linear": {"x", "y", "z"},
//! "angular": {"x", "y", "z"}}` (`geometry_msgs/Twist`'s fields, what
//! Foxglove's teleop panel publishes while a button is held): the six axes
//! in that order, the enable button held, and held for [`TWIST_HOLD_S`]
//! only: a panel stops publishing when its button is released, so the
//! device returns to rest (enable still held) when no twist came for that
//! long.

use parasils::teleop::Command;

/// The topic a client publishes the session's token on.
pub const AUTH_TOPIC: &str = "/auth";

/// The JSON Schema of a command (`/command`'s message, and the `/command`
/// service's request).
pub fn command_schema() -> serde_json::Value {
    let point = |d: &str| serde_json::json!({"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3, "description": d});
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "parasils.Command",
        "description": "A command: CRTK's (enable, disable, pause, resume), home, look_at_tips, stop, or a planned move with its goal (look_at: point_mm; move_to: psi_deg, theta_deg, the tips)",
        "type": "object",
        "properties": {
            "command": {"type": "string", "enum": LiveCommand::NAMES},
            "id": {"type": ["integer", "null"], "description": "echoed in the acknowledgement"},
            "point_mm": point("look_at: the point, mm, fixed frame"),
            "psi_deg": {"type": "number", "description": "move_to: psi, deg"},
            "theta_deg": {"type": "number", "description": "move_to: theta, deg"},
            "left_tip_mm": point("move_to: the left module's tip, mm, fixed frame (where it is if not given)"),
            "right_tip_mm": point("move_to: the right module's tip, mm, fixed frame (where it is if not given)"),
        },
        "required": ["command"],
    })
}

/// Which device an input drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputDevice {
    /// The device driving the left hand.
    Left,
    /// The device driving the right hand.
    Right,
    /// The endoscope's device.
    Camera,
}

impl InputDevice {
    /// Every device, in the order of the core's inputs.
    pub const ALL: [InputDevice; 3] = [InputDevice::Left, InputDevice::Right, InputDevice::Camera];

    /// The index in `[left, right, camera]`.
    pub const fn index(self) -> usize {
        match self {
            InputDevice::Left => 0,
            InputDevice::Right => 1,
            InputDevice::Camera => 2,
        }
    }

    /// Its name: `left`, `right`, `camera`.
    pub const fn name(self) -> &'static str {
        match self {
            InputDevice::Left => "left",
            InputDevice::Right => "right",
            InputDevice::Camera => "camera",
        }
    }

    /// The topic its inputs are published on.
    pub const fn topic(self) -> &'static str {
        match self {
            InputDevice::Left => "/left/servo_input",
            InputDevice::Right => "/right/servo_input",
            InputDevice::Camera => "/camera/servo_input",
        }
    }
}

/// How long a twist input holds without a new one, s.
pub const TWIST_HOLD_S: f64 = 0.25;

/// The topic of the commands.
pub const COMMAND_TOPIC: &str = "/command";

/// A device's state as a client sends it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceInput {
    /// The device.
    pub device: InputDevice,
    /// `tx ty tz rx ry rz`, each in `[-1, 1]`.
    pub axes: [f64; 6],
    /// Bit 0 enable, bit 1 clutch.
    pub buttons: u8,
    /// The client's number for it, if given.
    pub id: Option<u64>,
    /// How long it holds without a new one, s (`None`: until the next).
    pub hold_s: Option<f64>,
}

/// A command on `/command`: one of the core's, or a planned move with its
/// goal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LiveCommand {
    /// One of the core's commands given at a cycle (`enable`, `disable`,
    /// `pause`, `resume`, `home`, `stop`), through CRTK's table.
    Core(Command),
    /// Turn the view to the tips' midpoint, the tips held.
    LookAtTips,
    /// Turn the view to a point (mm, fixed frame), the tips held.
    LookAt([f64; 3]),
    /// Move the view to `[psi, theta]` (deg) and each tip to its point
    /// (mm, fixed frame; `None`: where it is).
    MoveTo {
        /// `[psi, theta]`, deg.
        angles_deg: [f64; 2],
        /// `[left module, right module]` tips, mm.
        tips_mm: [Option<[f64; 3]>; 2],
    },
}

impl LiveCommand {
    /// Its name on `/command`.
    pub const fn name(&self) -> &'static str {
        match self {
            LiveCommand::Core(c) => c.name(),
            LiveCommand::LookAtTips => "look_at_tips",
            LiveCommand::LookAt(_) => "look_at",
            LiveCommand::MoveTo { .. } => "move_to",
        }
    }

    /// Every name `/command` takes.
    pub const NAMES: [&'static str; 9] = [
        "enable",
        "disable",
        "pause",
        "resume",
        "home",
        "stop",
        "look_at_tips",
        "look_at",
        "move_to",
    ];
}

/// A command as a client sends it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandRequest {
    /// The command.
    pub command: LiveCommand,
    /// The client's number for it, if given.
    pub id: Option<u64>,
}

/// A parsed client message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ClientMessage {
    /// A device's input.
    Input(DeviceInput),
    /// A command.
    Command(CommandRequest),
}

/// Why a client message was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MessageError {
    /// Published on a topic that takes no input.
    #[error(
        "{topic}: not an input topic (inputs: /left/servo_input, /right/servo_input, /camera/servo_input, /command)"
    )]
    UnknownTopic {
        /// The topic.
        topic: String,
    },
    /// Not JSON, or not an object.
    #[error("{topic}: not a JSON object: {reason}")]
    NotJson {
        /// The topic.
        topic: &'static str,
        /// The parser's message.
        reason: String,
    },
    /// A field missing or of the wrong type.
    #[error("{topic}: field `{field}`: {expected}")]
    Field {
        /// The topic.
        topic: &'static str,
        /// The field.
        field: &'static str,
        /// What it must be.
        expected: &'static str,
    },
    /// An axis out of `[-1, 1]` or not finite.
    #[error("{topic}: axis {axis} = {value} is outside [-1, 1]")]
    Axis {
        /// The topic.
        topic: &'static str,
        /// The axis' name.
        axis: &'static str,
        /// Its value.
        value: f64,
    },
    /// A command name CRTK's table does not have here.
    #[error(
        "/command: unknown command `{name}` (enable, disable, pause, resume, home, stop, look_at_tips, look_at, move_to)"
    )]
    UnknownCommand {
        /// The name sent.
        name: String,
    },
}

const AXES: [&str; 6] = ["tx", "ty", "tz", "rx", "ry", "rz"];

fn id_of(
    obj: &serde_json::Map<String, serde_json::Value>,
    topic: &'static str,
) -> Result<Option<u64>, MessageError> {
    match obj.get("id") {
        None | Some(serde_json::Value::Null) => Ok(None),
        Some(v) => v.as_u64().map(Some).ok_or(MessageError::Field {
            topic,
            field: "id",
            expected: "a whole number from 0",
        }),
    }
}

/// Parses `payload`, published on `topic`.
///
/// # Errors
/// [`MessageError`] naming the topic and the field at fault.
pub fn parse(topic: &str, payload: &[u8]) -> Result<ClientMessage, MessageError> {
    let (topic, device) = if topic == COMMAND_TOPIC {
        (COMMAND_TOPIC, None)
    } else if let Some(d) = InputDevice::ALL.into_iter().find(|d| d.topic() == topic) {
        (d.topic(), Some(d))
    } else {
        return Err(MessageError::UnknownTopic {
            topic: topic.to_owned(),
        });
    };
    let value: serde_json::Value =
        serde_json::from_slice(payload).map_err(|e| MessageError::NotJson {
            topic,
            reason: e.to_string(),
        })?;
    let serde_json::Value::Object(obj) = value else {
        return Err(MessageError::NotJson {
            topic,
            reason: "a JSON value that is not an object".to_owned(),
        });
    };
    let id = id_of(&obj, topic)?;
    if let Some(device) = device
        && obj.contains_key("linear")
    {
        return twist(topic, device, &obj, id);
    }
    let Some(device) = device else {
        return command(&obj, id);
    };
    let list = obj
        .get("axes")
        .and_then(serde_json::Value::as_array)
        .filter(|a| a.len() == 6)
        .ok_or(MessageError::Field {
            topic,
            field: "axes",
            expected: "a list of six numbers (tx, ty, tz, rx, ry, rz)",
        })?;
    let mut axes = [0.0; 6];
    for (k, (slot, v)) in axes.iter_mut().zip(list).enumerate() {
        let x = v.as_f64().ok_or(MessageError::Field {
            topic,
            field: "axes",
            expected: "a list of six numbers (tx, ty, tz, rx, ry, rz)",
        })?;
        if !(x.abs() <= 1.0) {
            return Err(MessageError::Axis {
                topic,
                axis: AXES[k],
                value: x,
            });
        }
        *slot = x;
    }
    let buttons = match obj.get("buttons") {
        None => 0,
        Some(v) => v
            .as_u64()
            .and_then(|b| u8::try_from(b).ok())
            .ok_or(MessageError::Field {
                topic,
                field: "buttons",
                expected: "a bit mask from 0 to 255 (bit 0 enable, bit 1 clutch)",
            })?,
    };
    Ok(ClientMessage::Input(DeviceInput {
        device,
        axes,
        buttons,
        id,
        hold_s: None,
    }))
}

/// `field`: a list of `N` numbers (`None` when absent).
fn numbers<const N: usize>(
    obj: &serde_json::Map<String, serde_json::Value>,
    field: &'static str,
    expected: &'static str,
) -> Result<Option<[f64; N]>, MessageError> {
    let Some(v) = obj.get(field) else {
        return Ok(None);
    };
    let bad = MessageError::Field {
        topic: COMMAND_TOPIC,
        field,
        expected,
    };
    let list = v.as_array().filter(|a| a.len() == N).ok_or(bad.clone())?;
    let mut out = [0.0; N];
    for (slot, x) in out.iter_mut().zip(list) {
        *slot = x.as_f64().ok_or(bad.clone())?;
    }
    Ok(Some(out))
}

/// `field`: a number.
fn number(
    obj: &serde_json::Map<String, serde_json::Value>,
    field: &'static str,
) -> Result<f64, MessageError> {
    obj.get(field)
        .and_then(serde_json::Value::as_f64)
        .ok_or(MessageError::Field {
            topic: COMMAND_TOPIC,
            field,
            expected: "a number, deg",
        })
}

/// A message on `/command`.
fn command(
    obj: &serde_json::Map<String, serde_json::Value>,
    id: Option<u64>,
) -> Result<ClientMessage, MessageError> {
    let name = obj
        .get("command")
        .and_then(serde_json::Value::as_str)
        .ok_or(MessageError::Field {
            topic: COMMAND_TOPIC,
            field: "command",
            expected: "a string",
        })?;
    let tip = "a list of three numbers, mm (x, y, z in the fixed frame)";
    let command = match name {
        "look_at_tips" => LiveCommand::LookAtTips,
        "look_at" => {
            LiveCommand::LookAt(numbers(obj, "point_mm", tip)?.ok_or(MessageError::Field {
                topic: COMMAND_TOPIC,
                field: "point_mm",
                expected: tip,
            })?)
        }
        "move_to" => LiveCommand::MoveTo {
            angles_deg: [number(obj, "psi_deg")?, number(obj, "theta_deg")?],
            tips_mm: [
                numbers(obj, "left_tip_mm", tip)?,
                numbers(obj, "right_tip_mm", tip)?,
            ],
        },
        _ => LiveCommand::Core(
            Command::ALL
                .into_iter()
                .filter(|c| *c != Command::LookAtTips)
                .find(|c| c.name() == name)
                .ok_or_else(|| MessageError::UnknownCommand {
                    name: name.to_owned(),
                })?,
        ),
    };
    Ok(ClientMessage::Command(CommandRequest { command, id }))
}

/// A twist on `device`'s topic: `linear` then `angular`, each `x y z`,
/// clamped to `[-1, 1]` (a panel's speeds are its own scale), enable held.
fn twist(
    topic: &'static str,
    device: InputDevice,
    obj: &serde_json::Map<String, serde_json::Value>,
    id: Option<u64>,
) -> Result<ClientMessage, MessageError> {
    let mut axes = [0.0; 6];
    for (k, (part, field)) in [("linear", "linear"), ("angular", "angular")]
        .into_iter()
        .enumerate()
    {
        let Some(v) = obj.get(part) else { continue };
        for (j, c) in ["x", "y", "z"].into_iter().enumerate() {
            let x = match v.get(c) {
                None => 0.0,
                Some(n) => n
                    .as_f64()
                    .filter(|x| x.is_finite())
                    .ok_or(MessageError::Field {
                        topic,
                        field,
                        expected: "an object of finite numbers x, y, z",
                    })?,
            };
            axes[3 * k + j] = x.clamp(-1.0, 1.0);
        }
    }
    Ok(ClientMessage::Input(DeviceInput {
        device,
        axes,
        buttons: parasils::teleop::BUTTON_ENABLE,
        id,
        hold_s: Some(TWIST_HOLD_S),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_and_commands_parse_and_bad_ones_name_their_field() {
        let m = parse(
            "/right/servo_input",
            br#"{"axes":[0.5,0,0,0,0,-1],"buttons":1,"id":9}"#,
        );
        assert_eq!(
            m,
            Ok(ClientMessage::Input(DeviceInput {
                device: InputDevice::Right,
                axes: [0.5, 0.0, 0.0, 0.0, 0.0, -1.0],
                buttons: 1,
                id: Some(9),
                hold_s: None,
            }))
        );
        // A teleop panel's twist: the six axes clamped, enable held, held
        // for a quarter of a second only.
        assert_eq!(
            parse(
                "/left/servo_input",
                br#"{"linear":{"x":2,"y":-0.5,"z":0},"angular":{"x":0,"y":0,"z":0.25}}"#
            ),
            Ok(ClientMessage::Input(DeviceInput {
                device: InputDevice::Left,
                axes: [1.0, -0.5, 0.0, 0.0, 0.0, 0.25],
                buttons: 1,
                id: None,
                hold_s: Some(0.25),
            }))
        );
        assert!(matches!(
            parse("/left/servo_input", br#"{"linear":{"x":"fast"}}"#),
            Err(MessageError::Field {
                field: "linear",
                ..
            })
        ));
        assert_eq!(
            parse("/command", br#"{"command":"pause"}"#),
            Ok(ClientMessage::Command(CommandRequest {
                command: LiveCommand::Core(Command::Pause),
                id: None
            }))
        );
        assert_eq!(
            parse(
                "/command",
                br#"{"command":"look_at","point_mm":[1,-2.5,-600],"id":4}"#
            ),
            Ok(ClientMessage::Command(CommandRequest {
                command: LiveCommand::LookAt([1.0, -2.5, -600.0]),
                id: Some(4)
            }))
        );
        assert_eq!(
            parse(
                "/command",
                br#"{"command":"move_to","psi_deg":-10,"theta_deg":5,"right_tip_mm":[1,2,3]}"#
            ),
            Ok(ClientMessage::Command(CommandRequest {
                command: LiveCommand::MoveTo {
                    angles_deg: [-10.0, 5.0],
                    tips_mm: [None, Some([1.0, 2.0, 3.0])]
                },
                id: None
            }))
        );
        assert_eq!(
            parse("/command", br#"{"command":"look_at_tips"}"#),
            Ok(ClientMessage::Command(CommandRequest {
                command: LiveCommand::LookAtTips,
                id: None
            }))
        );
        assert!(matches!(
            parse("/command", br#"{"command":"look_at","point_mm":[1,2]}"#),
            Err(MessageError::Field {
                field: "point_mm",
                ..
            })
        ));
        assert!(matches!(
            parse("/command", br#"{"command":"look_at"}"#),
            Err(MessageError::Field {
                field: "point_mm",
                ..
            })
        ));
        assert!(matches!(
            parse("/command", br#"{"command":"move_to","psi_deg":1}"#),
            Err(MessageError::Field {
                field: "theta_deg",
                ..
            })
        ));
        // Every name parses to a command of that name.
        for name in LiveCommand::NAMES {
            let text = format!(
                r#"{{"command":"{name}","point_mm":[0,0,-600],"psi_deg":0,"theta_deg":0}}"#
            );
            match parse("/command", text.as_bytes()) {
                Ok(ClientMessage::Command(r)) => assert_eq!(r.command.name(), name),
                other => panic!("{name}: {other:?}"),
            }
        }
        assert!(matches!(
            parse("/left/servo_input", br#"{"axes":[0,0,1.5,0,0,0]}"#),
            Err(MessageError::Axis { axis: "tz", value, .. }) if value == 1.5
        ));
        assert!(matches!(
            parse("/left/servo_input", br#"{"axes":[0,0,0]}"#),
            Err(MessageError::Field { field: "axes", .. })
        ));
        assert!(matches!(
            parse(
                "/left/servo_input",
                br#"{"axes":[0,0,0,0,0,0],"buttons":256}"#
            ),
            Err(MessageError::Field {
                field: "buttons",
                ..
            })
        ));
        assert!(matches!(
            parse("/command", br#"{"command":"fly"}"#),
            Err(MessageError::UnknownCommand { .. })
        ));
        assert!(matches!(
            parse("/command", b"[1]"),
            Err(MessageError::NotJson { .. })
        ));
        assert!(matches!(
            parse("/left", b"{}"),
            Err(MessageError::UnknownTopic { .. })
        ));
        let text = parse("/left/servo_input", br#"{"axes":[0,0,0,0,2,0]}"#)
            .err()
            .map(|e| e.to_string());
        assert_eq!(
            text.as_deref(),
            Some("/left/servo_input: axis ry = 2 is outside [-1, 1]")
        );
    }
}
