//! The CRTK topics: each arm's joints and Cartesian pose as the surgical
//! robotics toolkit (CRTK) names them, under the arm's namespace, with
//! their JSON Schemas and builders.
//!
//! | topic | schema | what |
//! |---|---|---|
//! | `/{arm}/setpoint_js`, `/{arm}/measured_js` | `parasils.JointState` | `{"t_s", "name": [...], "position": [...], "velocity": [...], "unit": [...]}` |
//! | `/{arm}/setpoint_cp`, `/{arm}/measured_cp` | `parasils.CartesianPose` | `{"t_s", "frame_id": "world", "position": {x, y, z} mm, "orientation": {x, y, z, w}}` |
//! | `/{arm}/operating_state` | `parasils.OperatingState` | `{"t_s", "state": "ENABLED", "is_homed", "is_busy"}` |
//!
//! `{arm}` is `left`, `right` (the instrument modules: `qs1`, `qs2` in
//! degrees, `qs3` in mm; their tip and tool axes) or `platform` (module 1:
//! `q1`..`q6` in mm; the platform's centre `P` and its rotation `R`).
//! The robot here is simulated and follows its setpoint exactly, so a
//! `measured_` message holds the setpoint's numbers: the topics are there so
//! that a layout made for the simulation works unchanged on drives.

use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use parasils::kin::{Joints, Side};
use parasils::teleop::OperatingState;
use parasils_sim::{Record, SceneGeometry};
use serde_json::{Value, json};

/// An arm: a namespace of CRTK topics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arm {
    /// The left instrument module.
    Left,
    /// The right instrument module.
    Right,
    /// Module 1, the parallel platform.
    Platform,
}

impl Arm {
    /// Every arm.
    pub const ALL: [Arm; 3] = [Arm::Left, Arm::Right, Arm::Platform];

    /// The namespace, `left`, `right`, `platform`.
    pub const fn name(self) -> &'static str {
        match self {
            Arm::Left => "left",
            Arm::Right => "right",
            Arm::Platform => "platform",
        }
    }
}

/// A CRTK message kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Crtk {
    /// `measured_js`.
    MeasuredJs,
    /// `setpoint_js`.
    SetpointJs,
    /// `measured_cp`.
    MeasuredCp,
    /// `setpoint_cp`.
    SetpointCp,
    /// `operating_state`.
    OperatingState,
}

impl Crtk {
    /// Every kind.
    pub const ALL: [Crtk; 5] = [
        Crtk::MeasuredJs,
        Crtk::SetpointJs,
        Crtk::MeasuredCp,
        Crtk::SetpointCp,
        Crtk::OperatingState,
    ];

    /// CRTK's name.
    pub const fn name(self) -> &'static str {
        match self {
            Crtk::MeasuredJs => "measured_js",
            Crtk::SetpointJs => "setpoint_js",
            Crtk::MeasuredCp => "measured_cp",
            Crtk::SetpointCp => "setpoint_cp",
            Crtk::OperatingState => "operating_state",
        }
    }

    /// The schema's name.
    pub const fn schema_name(self) -> &'static str {
        match self {
            Crtk::MeasuredJs | Crtk::SetpointJs => "parasils.JointState",
            Crtk::MeasuredCp | Crtk::SetpointCp => "parasils.CartesianPose",
            Crtk::OperatingState => "parasils.OperatingState",
        }
    }

    /// The JSON Schema of its messages.
    pub fn schema(self) -> Value {
        let number = |d: &str| json!({"type": "number", "description": d});
        let list =
            |d: &str, items: Value| json!({"type": "array", "items": items, "description": d});
        let (description, properties, required): (&str, Value, Vec<&str>) = match self {
            Crtk::MeasuredJs | Crtk::SetpointJs => (
                "An arm's joints (CRTK *_js): names, positions and velocities, each in the unit at its index",
                json!({
                    "t_s": number("unit: s"),
                    "name": list("the joints' names", json!({"type": "string"})),
                    "position": list("positions, in the unit at the same index", json!({"type": "number"})),
                    "velocity": list("velocities, in the unit at the same index per second", json!({"type": "number"})),
                    "unit": list("each position's unit (deg or mm)", json!({"type": "string"})),
                }),
                vec!["t_s", "name", "position", "velocity", "unit"],
            ),
            Crtk::MeasuredCp | Crtk::SetpointCp => {
                let xyz = json!({"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}}, "required": ["x", "y", "z"]});
                let quat = json!({"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}, "w": {"type": "number"}}, "required": ["x", "y", "z", "w"]});
                (
                    "An arm's Cartesian pose (CRTK *_cp) in the fixed frame: an instrument's tip and tool axes (the tool along -z), or the platform's centre P and rotation R",
                    json!({
                        "t_s": number("unit: s"),
                        "frame_id": {"type": "string", "description": "the frame the pose is in: world (the fixed frame)"},
                        "position": {"description": "unit: mm", "allOf": [xyz]},
                        "orientation": {"description": "a unit quaternion", "allOf": [quat]},
                    }),
                    vec!["t_s", "frame_id", "position", "orientation"],
                )
            }
            Crtk::OperatingState => (
                "The operating state as CRTK names it (the teleoperation core's: one for the whole robot, published under each arm)",
                json!({
                    "t_s": number("unit: s"),
                    "state": {"type": "string", "enum": ["DISABLED", "ENABLED", "PAUSED", "FAULT"]},
                    "is_homed": {"type": "boolean"},
                    "is_busy": {"type": "boolean", "description": "a command is under way (a planned move: home, look_at, look_at_tips, move_to; or a stop to rest)"},
                }),
                vec!["t_s", "state", "is_homed", "is_busy"],
            ),
        };
        json!({
            "$schema": "https://json-schema.org/draft/2020-12/schema",
            "title": self.schema_name(),
            "description": description,
            "type": "object",
            "properties": properties,
            "required": required,
            "additionalProperties": false,
        })
    }
}

/// The topic of `kind` under `arm`: `/left/setpoint_js`.
pub fn topic(arm: Arm, kind: Crtk) -> String {
    format!("/{}/{}", arm.name(), kind.name())
}

/// `arm`'s joints in `record`: names, positions, velocities, units.
fn joints(arm: Arm, r: &Record) -> Value {
    let deg = f64::to_degrees;
    match arm {
        Arm::Left | Arm::Right => {
            let m = if arm == Arm::Left { &r.left } else { &r.right };
            json!({
                "t_s": r.t,
                "name": ["qs1", "qs2", "qs3"],
                "position": [deg(m.q[0]), deg(m.q[1]), m.q[2]],
                "velocity": [deg(m.q_dot[0]), deg(m.q_dot[1]), m.q_dot[2]],
                "unit": ["deg", "deg", "mm"],
            })
        }
        Arm::Platform => json!({
            "t_s": r.t,
            "name": ["q1", "q2", "q3", "q4", "q5", "q6"],
            "position": r.module1.q,
            "velocity": r.module1.q_dot,
            "unit": ["mm", "mm", "mm", "mm", "mm", "mm"],
        }),
    }
}

/// The platform's rotation `R = R_X(psi) R_Y(theta) R_Z(phi)` in `record`.
fn platform_rotation(r: &Record) -> Rotation3<f64> {
    let [_, _, _, psi, theta, phi] = r.pose;
    Rotation3::from_axis_angle(&Vector3::x_axis(), psi)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), theta)
        * Rotation3::from_axis_angle(&Vector3::z_axis(), phi)
}

/// `arm`'s pose in `record`, fixed frame, mm.
fn pose(arm: Arm, g: &SceneGeometry, r: &Record) -> Value {
    let platform = platform_rotation(r);
    let (p, rotation) = match arm {
        Arm::Platform => (Vector3::new(r.pose[0], r.pose[1], r.pose[2]), platform),
        Arm::Left | Arm::Right => {
            let (side, m) = if arm == Arm::Left {
                (Side::Left, &r.left)
            } else {
                (Side::Right, &r.right)
            };
            let tool = g.tool_rotation(side, &Joints::new(m.q[0], m.q[1], m.q[2]));
            (m.tip, platform * Rotation3::from_matrix_unchecked(tool))
        }
    };
    let q = UnitQuaternion::from_rotation_matrix(&rotation);
    json!({
        "t_s": r.t,
        "frame_id": "world",
        "position": {"x": p.x, "y": p.y, "z": p.z},
        "orientation": {"x": q.i, "y": q.j, "z": q.k, "w": q.w},
    })
}

/// The message of `kind` under `arm` for `record`, as JSON text; the state
/// and whether the core is busy for `operating_state`.
pub fn message(arm: Arm, kind: Crtk, g: &SceneGeometry, r: &Record, busy: bool) -> Vec<u8> {
    let value = match kind {
        Crtk::MeasuredJs | Crtk::SetpointJs => joints(arm, r),
        Crtk::MeasuredCp | Crtk::SetpointCp => pose(arm, g, r),
        Crtk::OperatingState => state_message(r.t, r.teleop.state, busy),
    };
    value.to_string().into_bytes()
}

/// An `operating_state` message.
fn state_message(t: f64, state: OperatingState, busy: bool) -> Value {
    json!({"t_s": t, "state": state.name(), "is_homed": true, "is_busy": busy})
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_platform_rotation_is_x_then_y_then_z_and_the_left_tip_is_the_record_s() {
        let mut r = Record {
            pose: [1.0, 2.0, 3.0, 0.3, -0.2, 0.1],
            ..Record::default()
        };
        // R e_z computed by hand for R_X(psi) R_Y(theta) R_Z(phi): the third
        // column, (sin theta, -sin psi cos theta, cos psi cos theta).
        let (psi, theta) = (0.3_f64, -0.2_f64);
        let col = platform_rotation(&r) * Vector3::z();
        let want = Vector3::new(
            theta.sin(),
            -psi.sin() * theta.cos(),
            psi.cos() * theta.cos(),
        );
        assert!((col - want).norm() < 1e-15, "{col} {want}");
        r.left.tip = Vector3::new(4.0, 5.0, -6.0);
        r.left.q = [0.1, 0.2, 30.0];
        let robot = parasils_sim::Scenario::paper().robot;
        let g = SceneGeometry::from_robot(&robot).expect("geometry");
        let v: Value = serde_json::from_slice(&message(Arm::Left, Crtk::SetpointCp, &g, &r, false))
            .expect("json");
        assert_eq!(v["position"], json!({"x": 4.0, "y": 5.0, "z": -6.0}));
        let js: Value =
            serde_json::from_slice(&message(Arm::Left, Crtk::SetpointJs, &g, &r, false))
                .expect("json");
        assert_eq!(js["position"][2], 30.0);
        assert!((js["position"][0].as_f64().unwrap_or(0.0) - 0.1_f64.to_degrees()).abs() < 1e-12);
        let q = &v["orientation"];
        let n: f64 = ["x", "y", "z", "w"]
            .iter()
            .map(|k| q[k].as_f64().unwrap_or(0.0).powi(2))
            .sum();
        assert!((n - 1.0).abs() < 1e-12);
    }
}
