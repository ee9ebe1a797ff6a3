//! The forces in the recording, in a run that has them
//! ([`Scenario::has_forces`](crate::Scenario::has_forces): a tip load or
//! the robot file's `[dynamics]`):
//! - `/forces` (schema `parasils.Forces`), one message per record: `t_s`,
//!   then the fourteen force columns ([`columns::FORCES`](crate::columns::FORCES)):
//!   the six slider forces (N), each module's joint efforts (N mm, N) and
//!   both tips' deflections (mm);
//! - on `/scene`, with the rest of the 3D view, one more entity, `forces`
//!   (in the `world` frame, replaced at each scene): an arrow per slider
//!   from the slider `B_j` along its guide, `tau_j u_j` (the force the
//!   actuator pushes its slider with), and an arrow per loaded tip from the
//!   tip, the force it exerts on the tissue, each [`FORCE_ARROW_MM_PER_N`]
//!   mm long per newton; a zero force draws no arrow.

use nalgebra::{UnitQuaternion, Vector3};

use super::error::McapError;
use super::json::Json;
use super::scene::{SCENE_TOPIC, SceneGeometry};
use crate::record::Record;

/// The topic of the forces, in a run that has them.
pub const FORCES_TOPIC: &str = "/forces";

/// The force arrows' length per newton, mm/N: a 10 N tip load is drawn
/// 20 mm long.
pub const FORCE_ARROW_MM_PER_N: f64 = 2.0;

/// The sliders' arrows: magenta.
const SLIDER: [f64; 4] = [0.85, 0.2, 0.75, 0.9];
/// The tip loads' arrows: orange.
const TIP: [f64; 4] = [1.0, 0.55, 0.1, 0.9];

/// Millimetres to metres.
const M: f64 = 1e-3;

impl Json<'_> {
    /// A `foxglove.ArrowPrimitive` from `base` (mm) drawing `force` (N) at
    /// [`FORCE_ARROW_MM_PER_N`]: the arrow's own `x` along the force, its
    /// head a quarter of its length.
    fn arrow(&mut self, base: &Vector3<f64>, force: &Vector3<f64>, color: [f64; 4]) -> &mut Self {
        let length = force.norm() * FORCE_ARROW_MM_PER_N * M;
        let q = UnitQuaternion::rotation_between(&Vector3::x(), force).unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), core::f64::consts::PI)
        });
        self.raw("{\"pose\":{\"position\":")
            .vec3(&(base * M))
            .raw(",\"orientation\":")
            .quat(&q)
            .raw("},\"shaft_length\":")
            .num(0.75 * length)
            .raw(",\"shaft_diameter\":")
            .num(3.0 * M)
            .raw(",\"head_length\":")
            .num(0.25 * length)
            .raw(",\"head_diameter\":")
            .num(8.0 * M)
            .raw(",\"color\":")
            .color(color)
            .raw("}")
    }
}

/// The arrows of `record` (logged at `ns`): each slider's force at its
/// slider, then each tip's load `loads` (N, fixed frame, `[left, right]`)
/// at its tip, as `(base mm, force N, colour)`; zero forces left out.
pub(crate) fn arrows(
    g: &SceneGeometry,
    loads: &[Vector3<f64>; 2],
    record: &Record,
) -> Vec<(Vector3<f64>, Vector3<f64>, [f64; 4])> {
    let sliders = (0..6).map(|j| {
        let u = Vector3::from(g.guide_directions[j]);
        let base = Vector3::from(g.guide_points_mm[j]) + record.module1.q[j] * u;
        (base, u * record.forces.module1[j], SLIDER)
    });
    let tips = [(record.left.tip, loads[0]), (record.right.tip, loads[1])]
        .into_iter()
        .map(|(tip, load)| (tip, load, TIP));
    sliders
        .chain(tips)
        .filter(|(_, f, _)| *f != Vector3::zeros())
        .collect()
}

/// Writes the `/scene` message of `record`'s force arrows (see the
/// [module docs](self)) into `out`.
pub(crate) fn write_arrows(
    g: &SceneGeometry,
    loads: &[Vector3<f64>; 2],
    record: &Record,
    ns: u64,
    out: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
) -> Result<(), McapError> {
    let mut j = Json::new(out, ryu);
    j.raw("{\"deletions\":[],\"entities\":[{\"timestamp\":")
        .time(ns)
        .raw(",\"frame_id\":\"world\",\"id\":\"forces\",\"lifetime\":{\"sec\":0,\"nsec\":0},")
        .raw("\"frame_locked\":false,\"metadata\":[{\"key\":\"mm_per_n\",\"value\":\"")
        .num(FORCE_ARROW_MM_PER_N)
        .raw("\"}],\"arrows\":[");
    for (k, (base, force, color)) in arrows(g, loads, record).iter().enumerate() {
        if k > 0 {
            j.raw(",");
        }
        j.arrow(base, force, *color);
    }
    j.raw("],\"cubes\":[],\"spheres\":[],\"cylinders\":[],\"lines\":[],\"triangles\":[],")
        .raw("\"texts\":[],\"models\":[]}]}");
    j.check(SCENE_TOPIC, "forces", record.t)
}
