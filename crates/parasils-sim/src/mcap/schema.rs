//! The channels' schemas: the data channels' fields and JSON Schemas, derived
//! from the [column table](crate::columns), and Foxglove's official schemas
//! of `/tf` and `/scene`, embedded.

use crate::columns::{self, Channel, Column};

/// Foxglove's official schema of `foxglove.FrameTransforms` (MIT, see
/// `schemas/LICENSE`).
pub const FRAME_TRANSFORMS_SCHEMA: &str = include_str!("../../schemas/FrameTransforms.json");
/// Foxglove's official schema of `foxglove.SceneUpdate` (MIT, see
/// `schemas/LICENSE`).
pub const SCENE_UPDATE_SCHEMA: &str = include_str!("../../schemas/SceneUpdate.json");

/// The schema of `foxglove.CameraCalibration`, written here from the
/// fields Foxglove documents (see `schemas/README.md`).
pub const CAMERA_CALIBRATION_SCHEMA: &str = include_str!("../../schemas/CameraCalibration.json");
/// The schema of `foxglove.ImageAnnotations`, written here from the fields
/// Foxglove documents (see `schemas/README.md`).
pub const IMAGE_ANNOTATIONS_SCHEMA: &str = include_str!("../../schemas/ImageAnnotations.json");

/// One field of a data channel's messages: its column, and the JSON text
/// before its value (`{"t_s":` for the first, `,"x_mm":` for the others).
#[derive(Debug, Clone)]
pub struct Field {
    /// The column whose value follows.
    pub column: Column,
    /// The JSON text before the value.
    pub key: Vec<u8>,
}

/// The fields of `channel`'s messages: `t_s`, then the channel's columns in
/// the table's order.
pub fn fields(channel: Channel) -> Vec<Field> {
    fields_of(
        columns::ALL
            .into_iter()
            .filter(|c| c.channel == Some(channel)),
    )
}

/// The fields of `/forces`' messages: `t_s`, then [`columns::FORCES`].
pub(crate) fn forces_fields() -> Vec<Field> {
    fields_of(columns::FORCES.into_iter())
}

/// `t_s`, then `columns`, as fields.
fn fields_of(columns: impl Iterator<Item = Column>) -> Vec<Field> {
    core::iter::once(columns::T_S)
        .chain(columns)
        .enumerate()
        .map(|(k, column)| Field {
            key: format!("{}\"{}\":", if k == 0 { "{" } else { "," }, column.name).into_bytes(),
            column,
        })
        .collect()
}

/// The JSON Schema of `channel`'s messages: an object of the numbers in
/// `fields`, all required, none other allowed.
pub fn data_schema(channel: Channel, fields: &[Field]) -> serde_json::Value {
    numbers_schema(channel.schema_name(), channel.description(), fields)
}

/// The name of `/forces`' JSON schema.
pub(crate) const FORCES_SCHEMA_NAME: &str = "parasils.Forces";

/// The JSON Schema of `/forces`' messages.
pub(crate) fn forces_schema(fields: &[Field]) -> serde_json::Value {
    numbers_schema(
        FORCES_SCHEMA_NAME,
        "Every actuator's force holding the tip loads and moving the platform's body: module 1's slider forces (positive pushing the slider along its guide), each module's joint torques and insertion force, each tip's deflection",
        fields,
    )
}

/// An object of the numbers in `fields`, all required, none other allowed.
fn numbers_schema(title: &str, description: &str, fields: &[Field]) -> serde_json::Value {
    let mut properties = serde_json::Map::new();
    for f in fields {
        properties.insert(
            f.column.name.to_owned(),
            serde_json::json!({
                "type": "number",
                "description": format!("unit: {}", f.column.unit),
            }),
        );
    }
    let required: Vec<&str> = fields.iter().map(|f| f.column.name).collect();
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": title,
        "description": description,
        "type": "object",
        "properties": properties,
        "required": required,
        "additionalProperties": false,
    })
}

/// The fields of a teleoperation run's `/teleop` messages: `t_s`, then
/// the teleoperation columns on no other channel (each device's axes and
/// buttons, the codes), in [`crate::teleop::TELEOP`]'s order.
pub(crate) fn teleop_fields() -> Vec<Field> {
    fields_of(
        crate::teleop::TELEOP
            .into_iter()
            .filter(|c| c.channel.is_none()),
    )
}

/// The name of `/teleop`'s JSON schema.
pub(crate) const TELEOP_SCHEMA_NAME: &str = "parasils.Teleop";

/// The JSON Schema of `/teleop`'s messages: the numbers of
/// [`teleop_fields`], then the state, the limit held at and the fault in
/// words.
pub(crate) fn teleop_schema(fields: &[Field]) -> serde_json::Value {
    let mut properties = serde_json::Map::new();
    for f in fields {
        let kind = if f.column.integer {
            "integer"
        } else {
            "number"
        };
        properties.insert(
            f.column.name.to_owned(),
            serde_json::json!({"type": kind, "description": format!("unit: {}", f.column.unit)}),
        );
    }
    properties.insert(
        "state".to_owned(),
        serde_json::json!({
            "type": "string",
            "enum": ["DISABLED", "ENABLED", "PAUSED", "FAULT"],
            "description": "the operating state after the cycle (CRTK's names)",
        }),
    );
    for (name, what) in [
        (
            "hold",
            "the limit the cycle holds at, in words; empty when none",
        ),
        (
            "fault",
            "the fault that put the core in FAULT, in words; empty when none",
        ),
    ] {
        properties.insert(
            name.to_owned(),
            serde_json::json!({"type": "string", "description": what}),
        );
    }
    let mut required: Vec<&str> = fields.iter().map(|f| f.column.name).collect();
    required.extend(["state", "hold", "fault"]);
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": TELEOP_SCHEMA_NAME,
        "description": "One teleoperation cycle: what each device held (axes normalised to [-1, 1], buttons as a bit mask), the command given, and what the core made of it (codes as the CSV's, and in words)",
        "type": "object",
        "properties": properties,
        "required": required,
        "additionalProperties": false,
    })
}

/// The name of `/motion`'s JSON schema.
pub(crate) const MOTION_SCHEMA_NAME: &str = "parasils.Motion";

/// The JSON Schema of `/motion`'s messages: `t_s`, the active command's
/// index and what it is.
pub(crate) fn motion_schema() -> serde_json::Value {
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": MOTION_SCHEMA_NAME,
        "description": "The active command: its index (0 for the reorientation, one more at each retarget and at each stop) and what it is",
        "type": "object",
        "properties": {
            "t_s": {"type": "number", "description": "unit: s"},
            "command": {
                "type": "integer",
                "minimum": 0,
                "description": "index of the active command (the CSV's command column)",
            },
            "kind": {
                "type": "string",
                "enum": ["reorient", "retarget", "stop", "supervisor_stop"],
                "description": "reorient: the scenario's reorientation; retarget: a new goal; stop: the controlled stop commanded; supervisor_stop: a controlled stop the margin supervisor demanded",
            },
        },
        "required": ["t_s", "command", "kind"],
        "additionalProperties": false,
    })
}

/// The name of `/motion`'s JSON schema in a procedure.
pub(crate) const PROCEDURE_MOTION_SCHEMA_NAME: &str = "parasils.ProcedureMotion";

/// The JSON Schema of a procedure's `/motion` messages: the motion under way
/// and the endoscope.
pub(crate) fn procedure_motion_schema() -> serde_json::Value {
    let number =
        |unit: &str| serde_json::json!({"type": "number", "description": format!("unit: {unit}")});
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": PROCEDURE_MOTION_SCHEMA_NAME,
        "description": "The procedure's motion under way (index from 0, the paper's type 1 to 4, its name) and the endoscope's insertion",
        "type": "object",
        "properties": {
            "t_s": number("s"),
            "endoscope_depth_mm": number("mm"),
            "endoscope_tip_x_mm": number("mm"),
            "endoscope_tip_y_mm": number("mm"),
            "endoscope_tip_z_mm": number("mm"),
            "motion": {"type": "integer", "minimum": 0, "description": "index of the motion (the CSV's motion column)"},
            "motion_type": {"type": "integer", "minimum": 1, "maximum": 4, "description": "the paper's motion type (the CSV's motion_type column)"},
            "type_name": {"type": "string", "enum": ["position", "insert", "manipulate", "reorient"], "description": "the type as procedure files name it"},
            "name": {"type": ["string", "null"], "description": "the motion's name in the procedure, if it has one"},
        },
        "required": ["t_s", "endoscope_depth_mm", "endoscope_tip_x_mm", "endoscope_tip_y_mm", "endoscope_tip_z_mm", "motion", "motion_type", "type_name", "name"],
        "additionalProperties": false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_column_is_on_exactly_one_data_channel_after_t_s() {
        let all: Vec<Vec<Field>> = Channel::ALL.iter().map(|c| fields(*c)).collect();
        let counts: Vec<usize> = all.iter().map(Vec::len).collect();
        assert_eq!(counts, [11, 19, 10, 10, 18, 9, 9]);
        assert_eq!(counts.iter().sum::<usize>(), columns::ALL.len() + 6);
        for f in &all {
            assert_eq!(f[0].key, b"{\"t_s\":");
        }
        assert_eq!(all[4][1].key, b",\"left_tip_err_mm\":");
        let schema = data_schema(Channel::Module1, &all[1]);
        assert_eq!(
            schema["properties"]["q1_acc_mm_s2"]["description"],
            "unit: mm/s^2"
        );
        assert_eq!(schema["properties"]["t_s"]["description"], "unit: s");
        assert_eq!(schema["required"].as_array().map(Vec::len), Some(19));
    }

    #[test]
    fn embedded_schemas_are_the_official_ones() {
        let tf: serde_json::Value = serde_json::from_str(FRAME_TRANSFORMS_SCHEMA).expect("json");
        assert_eq!(tf["title"], "foxglove.FrameTransforms");
        let scene: serde_json::Value = serde_json::from_str(SCENE_UPDATE_SCHEMA).expect("json");
        assert_eq!(scene["title"], "foxglove.SceneUpdate");
        let cal: serde_json::Value = serde_json::from_str(CAMERA_CALIBRATION_SCHEMA).expect("json");
        assert_eq!(cal["title"], "foxglove.CameraCalibration");
        let required = [
            "timestamp",
            "frame_id",
            "width",
            "height",
            "distortion_model",
        ];
        for key in required.iter().chain(&["D", "K", "R", "P"]) {
            assert!(cal["properties"][key].is_object(), "{key}");
        }
        let ann: serde_json::Value = serde_json::from_str(IMAGE_ANNOTATIONS_SCHEMA).expect("json");
        assert_eq!(ann["title"], "foxglove.ImageAnnotations");
        for key in ["circles", "points", "texts"] {
            assert_eq!(ann["properties"][key]["type"], "array", "{key}");
        }
    }
}
