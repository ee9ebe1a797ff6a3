//! The 3D view: the frames of `/tf` (`foxglove.FrameTransforms`) and the
//! drawing of `/scene` (`foxglove.SceneUpdate`), in metres as Foxglove
//! expects, from a [`Record`] and the robot's [`SceneGeometry`].
//!
//! The platform's frame comes from the kinematics
//! ([`PlatformFrame`]: `R` and `P`, and `R c + P` for the points fixed on
//! the platform); the tips are the record's, recomputed by the kinematics'
//! forward kinematics; the shafts and the endoscope are the kinematics'
//! bodies ([`Bodies`], with the robot file's `[bodies]` sizes), drawn as
//! translucent cylinders of their diameters, split where they cross the
//! skin ([`InBody`]: the part inside the patient, then the part outside).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use parasils::kin::{
    Bodies, BodyGeometry, Camera, Capsule, Error, Instrument, InstrumentGeometry, Joints,
    PlatformFrame, PlatformState, Pose, RobotGeometry, Side,
};
use parasils_anatomy::{Body, InBody};
use serde::Serialize;

use super::camera::{CAMERA_FRAME, frame_axes, frustum};
use super::error::McapError;
use super::json::Json;
use crate::record::Record;

/// The topic of the `foxglove.FrameTransforms` messages.
pub const TF_TOPIC: &str = "/tf";
/// The topic of the `foxglove.SceneUpdate` messages.
pub const SCENE_TOPIC: &str = "/scene";

/// How far along the view the 3D scene draws the camera's frustum, mm.
const FRUSTUM_MM: f64 = 80.0;

/// Millimetres to metres.
const M: f64 = 1e-3;

/// What the 3D scene is drawn from: module 1 and the instrument ports, in
/// plain arrays, mm and rad.
///
/// Built from a [`RobotGeometry`] by [`SceneGeometry::from_robot`], the one
/// place that reads module 1's types. The MCAP file records it as JSON in
/// its `parasils.scenario` metadata.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SceneGeometry {
    /// Guide points where the reading is 0, `G_j - o_j u_j` (`G_j` itself
    /// without an encoder offset), mm, fixed frame.
    pub guide_points_mm: [[f64; 3]; 6],
    /// Guide unit directions `u_j`, fixed frame.
    pub guide_directions: [[f64; 3]; 6],
    /// Each actuator's stroke `[min, max]`, mm.
    pub strokes_mm: [[f64; 2]; 6],
    /// Link lengths `l_j`, mm.
    pub link_lengths_mm: [f64; 6],
    /// Platform nodes `a_i`, mm, platform frame.
    pub nodes_mm: [[f64; 3]; 3],
    /// Whether module 1's geometry is assumed (not the real robot's).
    pub module1_assumed: bool,
    /// The instrument ports (RCMs), left then right, mm, platform frame.
    pub rcms_mm: [[f64; 3]; 2],
    /// The spherical modules' `alpha`, left then right, rad.
    pub alphas_rad: [f64; 2],
    /// The spherical modules' `beta`, left then right, rad.
    pub betas_rad: [f64; 2],
    /// Both instrument modules' solvers, left then right, for their frames.
    #[serde(skip)]
    instruments: [Instrument<f64>; 2],
    /// The endoscope's camera, for its frame, its frustum and its image.
    #[serde(skip)]
    pub(crate) camera: Camera<f64>,
    /// The shafts' and the endoscope's sizes, mm: the assumed ones
    /// ([`BodyGeometry::assumed`]) until [`SceneGeometry::with_bodies`].
    #[serde(skip)]
    bodies: BodyGeometry<f64>,
}

impl SceneGeometry {
    /// The scene's geometry from the robot's.
    ///
    /// # Errors
    /// The kinematics' error for an invalid instrument module geometry.
    pub fn from_robot(robot: &RobotGeometry<f64>) -> Result<Self, parasils::kin::Error> {
        let m1 = &robot.module1;
        let v = |v: &Vector3<f64>| [v.x, v.y, v.z];
        let modules: [&InstrumentGeometry<f64>; 2] = [&robot.left, &robot.right];
        Ok(Self {
            // Where the reading is 0: the slider is at `G_j + (q_j - o_j) u_j`.
            guide_points_mm: m1
                .guides
                .map(|g| v(&(g.point - g.direction * g.encoder_offset))),
            guide_directions: m1.guides.map(|g| v(&g.direction)),
            strokes_mm: m1.guides.map(|g| [g.stroke.min, g.stroke.max]),
            link_lengths_mm: m1.guides.map(|g| g.link_length),
            nodes_mm: m1.nodes.map(|n| v(&n)),
            module1_assumed: m1.assumed,
            rcms_mm: modules.map(|m| v(&m.rcm)),
            alphas_rad: modules.map(|m| m.alpha),
            betas_rad: modules.map(|m| m.beta),
            instruments: [Instrument::new(robot.left)?, Instrument::new(robot.right)?],
            camera: robot.endoscope.camera,
            bodies: BodyGeometry::assumed(),
        })
    }

    /// The same, the shafts and the endoscope drawn at `bodies`' sizes (a
    /// robot file's `[bodies]`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming a size that is negative or not
    /// finite ([`BodyGeometry::validate`]).
    pub fn with_bodies(self, bodies: BodyGeometry<f64>) -> Result<Self, Error> {
        bodies.validate()?;
        Ok(Self { bodies, ..self })
    }

    /// The shafts' and the endoscope's sizes the scene draws, mm.
    pub fn bodies(&self) -> &BodyGeometry<f64> {
        &self.bodies
    }

    /// The last frame of a spherical module relative to its RCM frame, from
    /// the kinematics ([`Instrument::tool_rotation`]): the tool points along
    /// its `-z`, the tip at `z = -qs3` (see `docs/model.md`, *Instrument
    /// modules*).
    pub fn tool_rotation(&self, side: Side, q: &Joints<f64>) -> Matrix3<f64> {
        let k = match side {
            Side::Left => 0,
            Side::Right => 1,
        };
        self.instruments[k].tool_rotation(q)
    }

    fn rcm(&self, k: usize) -> Vector3<f64> {
        Vector3::from(self.rcms_mm[k])
    }
}

/// The platform's frame at `record` (its pose; rates do not matter here).
fn frame_of(record: &Record) -> PlatformFrame<f64> {
    PlatformFrame::new(&PlatformState::at_rest(Pose::from_array(record.pose)))
}

fn quat(m: &Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*m))
}

/// Writes the `/tf` message of `record` (logged at `ns`) into `out`: `world
/// -> platform`, `platform -> left_rcm`, `platform -> right_rcm`,
/// `left_rcm -> left_tool`, `right_rcm -> right_tool`, `platform ->
/// camera` (at the endoscope's tip, `x` along the image's `u`, `y` down
/// the image, `z` along the view: see `camera`).
pub fn write_tf(
    g: &SceneGeometry,
    record: &Record,
    ns: u64,
    out: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
) -> Result<(), McapError> {
    let frame = frame_of(record);
    let q_of = |q: [f64; 3]| Joints::new(q[0], q[1], q[2]);
    let tools = [
        g.tool_rotation(Side::Left, &q_of(record.left.q)),
        g.tool_rotation(Side::Right, &q_of(record.right.q)),
    ];
    let identity = UnitQuaternion::identity();
    let zero = Vector3::zeros();
    let eye = Vector3::new(0.0, 0.0, -record.endoscope_depth) * M;
    let frames: [(&str, &str, Vector3<f64>, UnitQuaternion<f64>); 6] = [
        (
            "world",
            "platform",
            frame.position * M,
            quat(&frame.rotation),
        ),
        ("platform", "left_rcm", g.rcm(0) * M, identity),
        ("platform", "right_rcm", g.rcm(1) * M, identity),
        ("left_rcm", "left_tool", zero, quat(&tools[0])),
        ("right_rcm", "right_tool", zero, quat(&tools[1])),
        ("platform", CAMERA_FRAME, eye, quat(&frame_axes(&g.camera))),
    ];
    let mut j = Json::new(out, ryu);
    j.raw("{\"transforms\":[");
    for (k, (parent, child, t, q)) in frames.iter().enumerate() {
        if k > 0 {
            j.raw(",");
        }
        j.raw("{\"timestamp\":")
            .time(ns)
            .raw(",\"parent_frame_id\":\"")
            .raw(parent)
            .raw("\",\"child_frame_id\":\"")
            .raw(child)
            .raw("\",\"translation\":")
            .vec3(t)
            .raw(",\"rotation\":")
            .quat(q)
            .raw("}");
    }
    j.raw("]}");
    j.check(TF_TOPIC, "transforms", record.t)
}

/// A line primitive, in metres, world frame.
struct Line<'p> {
    /// `LINE_STRIP`, `LINE_LOOP` or `LINE_LIST`.
    kind: u8,
    /// m.
    thickness: f64,
    color: [f64; 4],
    points: &'p [Vector3<f64>],
}

/// One body (a shaft, the endoscope) as two cylinders, in metres, world
/// frame: from its tip to its port (inside the patient) and from its port
/// to its end (outside), each of the body's diameter.
struct Shaft {
    /// Tip, port, end.
    points: [Vector3<f64>; 3],
    /// m.
    diameter: f64,
    /// Inside, outside.
    colors: [[f64; 4]; 2],
}

impl Shaft {
    /// `capsule`'s axis split where `body` crosses the skin, `inserted` mm
    /// from its tip ([`InBody::from_tip`]: nothing inside for 0 or less,
    /// all of it beyond its length), in metres.
    fn of(body: Body, capsule: &Capsule<f64>, inserted: f64, color: [f64; 4]) -> Self {
        let (tip, end) = (capsule.axis.start, capsule.axis.end);
        let port = InBody::from_tip(body, capsule, inserted).map_or(tip, |b| b.port);
        let [r, g, b, _] = color;
        Self {
            points: [tip * M, port * M, end * M],
            diameter: 2.0 * capsule.radius * M,
            colors: [[r, g, b, IN_BODY_ALPHA], [r, g, b, OUT_OF_BODY_ALPHA]],
        }
    }
}

/// The opacity of a body's part inside the patient.
const IN_BODY_ALPHA: f64 = 0.6;
/// The opacity of a body's part outside the patient.
const OUT_OF_BODY_ALPHA: f64 = 0.3;

/// Spheres of one size and colour, in metres, world frame.
struct Spheres<'p> {
    /// m.
    diameter: f64,
    color: [f64; 4],
    centres: &'p [Vector3<f64>],
}

fn line(kind: u8, thickness: f64, color: [f64; 4], points: &[Vector3<f64>]) -> Line<'_> {
    Line {
        kind,
        thickness,
        color,
        points,
    }
}

fn spheres(diameter: f64, color: [f64; 4], centres: &[Vector3<f64>]) -> Spheres<'_> {
    Spheres {
        diameter,
        color,
        centres,
    }
}

/// What a procedure's `/scene` adds: the piece of each tip's path (left,
/// right, endoscope, mm) from where the previous scene drew it.
#[derive(Debug, Clone, Copy)]
pub struct ProcedureScene {
    /// The tips at the previous scene (at the first, the tips now).
    pub path_from: [Vector3<f64>; 3],
    /// The piece's number, from 0: its entity is `tip_paths_<n>`.
    pub path_piece: u32,
}

/// One scene entity's primitives, in metres, world frame.
#[derive(Default)]
struct Entity<'p> {
    id: &'p str,
    lines: Vec<Line<'p>>,
    spheres: Vec<Spheres<'p>>,
    /// A body as its two cylinders.
    shaft: Option<Shaft>,
    /// One filled triangle list: `(color, points)`.
    triangles: Option<([f64; 4], &'p [Vector3<f64>])>,
    /// Metadata key/values.
    metadata: &'static [(&'static str, &'static str)],
}

const LINE_STRIP: u8 = 0;
const LINE_LOOP: u8 = 1;
const LINE_LIST: u8 = 2;

const GREY: [f64; 4] = [0.55, 0.55, 0.6, 1.0];
const STEEL: [f64; 4] = [0.2, 0.45, 0.8, 1.0];
const ORANGE: [f64; 4] = [0.95, 0.55, 0.1, 1.0];
const PLATFORM: [f64; 4] = [0.3, 0.7, 0.4, 0.6];
const GREEN: [f64; 4] = [0.2, 0.6, 0.3, 1.0];
const LEFT: [f64; 4] = [0.85, 0.2, 0.2, 1.0];
const RIGHT: [f64; 4] = [0.6, 0.2, 0.85, 1.0];
const ENDOSCOPE: [f64; 4] = [0.1, 0.1, 0.1, 1.0];
const TARGET: [f64; 4] = [1.0, 0.85, 0.0, 0.8];
const CAMERA: [f64; 4] = [0.1, 0.75, 0.85, 0.9];

impl Json<'_> {
    fn entity(&mut self, ns: u64, e: &Entity<'_>) -> &mut Self {
        self.raw("{\"timestamp\":")
            .time(ns)
            .raw(",\"frame_id\":\"world\",\"id\":\"")
            .raw(e.id)
            .raw("\",\"lifetime\":{\"sec\":0,\"nsec\":0},\"frame_locked\":false,\"metadata\":[");
        for (k, (key, value)) in e.metadata.iter().enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.raw("{\"key\":\"")
                .raw(key)
                .raw("\",\"value\":\"")
                .raw(value)
                .raw("\"}");
        }
        self.raw("],\"arrows\":[],\"cubes\":[],\"spheres\":[");
        let mut first = true;
        for sp in &e.spheres {
            for p in sp.centres {
                if !first {
                    self.raw(",");
                }
                first = false;
                self.raw("{\"pose\":{\"position\":")
                    .vec3(p)
                    .raw(",\"orientation\":{\"x\":0,\"y\":0,\"z\":0,\"w\":1}},\"size\":")
                    .vec3(&Vector3::repeat(sp.diameter))
                    .raw(",\"color\":")
                    .color(sp.color)
                    .raw("}");
            }
        }
        self.raw("],\"cylinders\":[");
        if let Some(shaft) = &e.shaft {
            let [tip, port, end] = &shaft.points;
            self.cylinder(tip, port, shaft.diameter, shaft.colors[0])
                .raw(",")
                .cylinder(port, end, shaft.diameter, shaft.colors[1]);
        }
        self.raw("],\"lines\":[");
        for (k, line) in e.lines.iter().enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.raw("{\"type\":")
                .int(u64::from(line.kind))
                .raw(",\"pose\":")
                .identity_pose()
                .raw(",\"thickness\":")
                .num(line.thickness)
                .raw(",\"scale_invariant\":false,\"points\":[");
            for (i, p) in line.points.iter().enumerate() {
                if i > 0 {
                    self.raw(",");
                }
                self.vec3(p);
            }
            self.raw("],\"color\":")
                .color(line.color)
                .raw(",\"colors\":[],\"indices\":[]}");
        }
        self.raw("],\"triangles\":[");
        if let Some((c, points)) = e.triangles {
            self.raw("{\"pose\":").identity_pose().raw(",\"points\":[");
            for (i, p) in points.iter().enumerate() {
                if i > 0 {
                    self.raw(",");
                }
                self.vec3(p);
            }
            self.raw("],\"color\":")
                .color(c)
                .raw(",\"colors\":[],\"indices\":[]}");
        }
        self.raw("],\"texts\":[],\"models\":[]}")
    }
}

/// Writes the `/scene` message of `record` (logged at `ns`) into `out`, all
/// in the `world` frame, metres: module 1's six guides (over their strokes),
/// sliders and legs (slider `B_j` to node `A_i`), the platform triangle and
/// its spokes to `P`, the endoscope and both instrument shafts as the
/// kinematics' bodies (`g`'s sizes; each two translucent cylinders of its
/// diameter, from its tip to its port, then from its port to its end: the
/// endoscope from its tip at the record's depth up along `+z'`, a shaft
/// from its tip back along the tool axis through its RCM), the ports and
/// the tips, the target tips, and the camera's view frustum (lines from the
/// eye at the endoscope's tip to the image's corners, `FRUSTUM_MM` (80 mm) along
/// the view).
///
/// In a procedure, the targets are left out (each motion has its own), and
/// a kept entity per scene adds the piece of the three tips' paths since the
/// previous scene, so that the paths build up without being sent again.
pub fn write_scene(
    g: &SceneGeometry,
    targets: &[Vector3<f64>; 2],
    record: &Record,
    procedure: Option<&ProcedureScene>,
    ns: u64,
    out: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
) -> Result<(), McapError> {
    let frame = frame_of(record);
    let p = frame.position;
    let world = |v: Vector3<f64>| v * M;
    let mut guides = [Vector3::zeros(); 12];
    let mut legs = [Vector3::zeros(); 12];
    let mut sliders = [Vector3::zeros(); 6];
    let nodes: [Vector3<f64>; 3] = g.nodes_mm.map(|a| frame.to_fixed(&Vector3::from(a)));
    for j in 0..6 {
        let gp = Vector3::from(g.guide_points_mm[j]);
        let u = Vector3::from(g.guide_directions[j]);
        let b = gp + record.module1.q[j] * u;
        guides[2 * j] = world(gp + g.strokes_mm[j][0] * u);
        guides[2 * j + 1] = world(gp + g.strokes_mm[j][1] * u);
        sliders[j] = world(b);
        legs[2 * j] = world(b);
        legs[2 * j + 1] = world(nodes[j / 2]);
    }
    let nodes_m = nodes.map(world);
    let centre = [world(p)];
    let spokes = [
        world(p),
        nodes_m[0],
        world(p),
        nodes_m[1],
        world(p),
        nodes_m[2],
    ];
    let q_of = |q: [f64; 3]| Joints::new(q[0], q[1], q[2]);
    let (q_left, q_right) = (q_of(record.left.q), q_of(record.right.q));
    let bodies = Bodies::at(
        &g.bodies,
        &frame,
        &g.instruments[0],
        &q_left,
        &g.instruments[1],
        &q_right,
        record.endoscope_depth,
    )
    .map_err(|error| match error {
        Error::NonFinite { what, value } => McapError::NonFinite {
            topic: SCENE_TOPIC,
            field: what,
            t: record.t,
            value,
        },
        error => McapError::Geometry(error),
    })?;
    let shafts = [
        Shaft::of(Body::Left, &bodies.left, q_left.qs3, LEFT),
        Shaft::of(Body::Right, &bodies.right, q_right.qs3, RIGHT),
        Shaft::of(
            Body::Endoscope,
            &bodies.endoscope,
            record.endoscope_depth,
            ENDOSCOPE,
        ),
    ];
    let rcms_world = [
        world(frame.to_fixed(&g.rcm(0))),
        world(frame.to_fixed(&g.rcm(1))),
    ];
    let tips = [world(record.left.tip), world(record.right.tip)];
    let targets = targets.map(world);
    let view = frustum(&g.camera, &frame, record.endoscope_depth, FRUSTUM_MM).map(world);
    let module1_note: &'static [(&str, &str)] = if g.module1_assumed {
        &[("geometry", "assumed, not the real robot's")]
    } else {
        &[]
    };
    let now = [record.left.tip, record.right.tip, record.endoscope_tip].map(world);
    let pieces = procedure.map(|s| {
        (
            format!("tip_paths_{}", s.path_piece),
            [0, 1, 2].map(|k| [world(s.path_from[k]), now[k]]),
        )
    });
    let [left_shaft, right_shaft, endoscope] = shafts;
    let parts: &'static [(&str, &str)] = &[(
        "cylinders",
        "inside the patient (tip to port), then outside (port to the end), at the [bodies] diameter",
    )];
    let mut entities = vec![
        Entity {
            id: "module1_guides",
            lines: vec![line(LINE_LIST, 0.004, GREY, &guides[..])],
            metadata: module1_note,
            ..Entity::default()
        },
        Entity {
            id: "module1_legs",
            lines: vec![line(LINE_LIST, 0.006, STEEL, &legs[..])],
            spheres: vec![spheres(0.016, ORANGE, &sliders[..])],
            metadata: module1_note,
            ..Entity::default()
        },
        Entity {
            id: "platform",
            lines: vec![
                line(LINE_LOOP, 0.005, GREEN, &nodes_m[..]),
                line(LINE_LIST, 0.003, GREEN, &spokes[..]),
            ],
            spheres: vec![
                spheres(0.012, GREEN, &nodes_m[..]),
                spheres(0.01, ENDOSCOPE, &centre[..]),
            ],
            triangles: Some((PLATFORM, &nodes_m[..])),
            ..Entity::default()
        },
        Entity {
            id: "endoscope",
            shaft: Some(endoscope),
            metadata: parts,
            ..Entity::default()
        },
        Entity {
            id: "left_instrument",
            shaft: Some(left_shaft),
            metadata: parts,
            spheres: vec![
                spheres(0.008, LEFT, &rcms_world[..1]),
                spheres(0.006, LEFT, &tips[..1]),
            ],
            ..Entity::default()
        },
        Entity {
            id: "right_instrument",
            shaft: Some(right_shaft),
            metadata: parts,
            spheres: vec![
                spheres(0.008, RIGHT, &rcms_world[1..]),
                spheres(0.006, RIGHT, &tips[1..]),
            ],
            ..Entity::default()
        },
    ];
    entities.push(Entity {
        id: "camera_frustum",
        lines: vec![line(LINE_LIST, 0.002, CAMERA, &view[..])],
        metadata: &[(
            "view",
            "the camera's field of view from the endoscope's tip",
        )],
        ..Entity::default()
    });
    match &pieces {
        None => entities.push(Entity {
            id: "tip_targets",
            spheres: vec![spheres(0.012, TARGET, &targets[..])],
            ..Entity::default()
        }),
        Some((id, [l, r, e])) => entities.push(Entity {
            id,
            lines: vec![
                line(LINE_STRIP, 0.002, LEFT, &l[..]),
                line(LINE_STRIP, 0.002, RIGHT, &r[..]),
                line(LINE_STRIP, 0.002, ENDOSCOPE, &e[..]),
            ],
            metadata: &[("path", "the tips' paths: left, right, endoscope")],
            ..Entity::default()
        }),
    }
    let mut j = Json::new(out, ryu);
    j.raw("{\"deletions\":[],\"entities\":[");
    for (k, e) in entities.iter().enumerate() {
        if k > 0 {
            j.raw(",");
        }
        j.entity(ns, e);
    }
    j.raw("]}");
    j.check(SCENE_TOPIC, "entities", record.t)
}
