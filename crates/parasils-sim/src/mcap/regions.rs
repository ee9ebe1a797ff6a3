//! The forbidden regions in the 3D view: one `foxglove.SceneUpdate` on
//! `/scene` at the run's first sample, one entity per region (`no_go_<n>`,
//! its name in the metadata), semi-transparent red, kept for the whole run
//! (no lifetime), in the `world` frame, metres.
//!
//! A sphere is a `spheres` primitive, a box a `cubes` one (its rotation as
//! the pose's orientation), a capsule a `cylinders` one along its axis with
//! a sphere at each end, a mesh a `triangles` one (its vertices and
//! indices, so each vertex is written once).

use nalgebra::{UnitQuaternion, Vector3};
use parasils_anatomy::{Anatomy, Shape};

use super::error::McapError;
use super::json::Json;

/// The regions' colour: red, semi-transparent.
const NO_GO: [f64; 4] = [0.9, 0.15, 0.15, 0.35];

/// Millimetres to metres.
const M: f64 = 1e-3;

fn m(v: [f64; 3]) -> Vector3<f64> {
    Vector3::from(v) * M
}

/// `R_X(psi) R_Y(theta) R_Z(phi)` of `[psi, theta, phi]` deg, the anatomy
/// file's convention for a box.
fn rotation(deg: [f64; 3]) -> UnitQuaternion<f64> {
    let [psi, theta, phi] = deg.map(f64::to_radians);
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), psi)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), theta)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), phi)
}

impl Json<'_> {
    fn pose(&mut self, position: &Vector3<f64>, q: &UnitQuaternion<f64>) -> &mut Self {
        self.raw("{\"position\":")
            .vec3(position)
            .raw(",\"orientation\":")
            .quat(q)
            .raw("}")
    }

    fn sphere(&mut self, centre: &Vector3<f64>, diameter: f64) -> &mut Self {
        self.raw("{\"pose\":")
            .pose(centre, &UnitQuaternion::identity())
            .raw(",\"size\":")
            .vec3(&Vector3::repeat(diameter))
            .raw(",\"color\":")
            .color(NO_GO)
            .raw("}")
    }
}

/// Writes the `/scene` message drawing `anatomy`'s regions (logged at
/// `ns`, the first sample's time `t`) into `out`.
pub(crate) fn write_regions(
    anatomy: &Anatomy,
    t: f64,
    ns: u64,
    out: &mut Vec<u8>,
    ryu: &mut ryu::Buffer,
) -> Result<(), McapError> {
    let mut j = Json::new(out, ryu);
    j.raw("{\"deletions\":[],\"entities\":[");
    for (k, region) in anatomy.regions.iter().enumerate() {
        if k > 0 {
            j.raw(",");
        }
        // The name quoted and escaped as a JSON string.
        let name = serde_json::to_string(&region.name).unwrap_or_else(|_| "\"?\"".to_owned());
        j.raw("{\"timestamp\":")
            .time(ns)
            .raw(",\"frame_id\":\"world\",\"id\":\"no_go_")
            .int(k as u64)
            .raw("\",\"lifetime\":{\"sec\":0,\"nsec\":0},\"frame_locked\":false,")
            .raw("\"metadata\":[{\"key\":\"region\",\"value\":")
            .raw(&name)
            .raw("},{\"key\":\"shape\",\"value\":\"")
            .raw(region.shape.kind())
            .raw("\"}],\"arrows\":[],\"cubes\":[");
        if let Shape::Box {
            centre_mm,
            half_extents_mm,
            rotation_deg,
        } = &region.shape
        {
            j.raw("{\"pose\":")
                .pose(&m(*centre_mm), &rotation(*rotation_deg))
                .raw(",\"size\":")
                .vec3(&(m(*half_extents_mm) * 2.0))
                .raw(",\"color\":")
                .color(NO_GO)
                .raw("}");
        }
        j.raw("],\"spheres\":[");
        match &region.shape {
            Shape::Sphere {
                centre_mm,
                radius_mm,
            } => {
                j.sphere(&m(*centre_mm), 2.0 * radius_mm * M);
            }
            Shape::Capsule {
                start_mm,
                end_mm,
                radius_mm,
            } => {
                j.sphere(&m(*start_mm), 2.0 * radius_mm * M)
                    .raw(",")
                    .sphere(&m(*end_mm), 2.0 * radius_mm * M);
            }
            _ => {}
        }
        j.raw("],\"cylinders\":[");
        if let Shape::Capsule {
            start_mm,
            end_mm,
            radius_mm,
        } = &region.shape
        {
            j.cylinder(&m(*start_mm), &m(*end_mm), 2.0 * radius_mm * M, NO_GO);
        }
        j.raw("],\"lines\":[],\"triangles\":[");
        if let Shape::Mesh { mesh, .. } = &region.shape {
            j.raw("{\"pose\":").identity_pose().raw(",\"points\":[");
            for (i, v) in mesh.vertices().iter().enumerate() {
                if i > 0 {
                    j.raw(",");
                }
                j.vec3(&m(*v));
            }
            j.raw("],\"color\":")
                .color(NO_GO)
                .raw(",\"colors\":[],\"indices\":[");
            for (i, t) in mesh.triangles().iter().enumerate() {
                for (c, index) in t.iter().enumerate() {
                    if i > 0 || c > 0 {
                        j.raw(",");
                    }
                    j.int(u64::from(*index));
                }
            }
            j.raw("]}");
        }
        j.raw("],\"texts\":[],\"models\":[]}");
    }
    j.raw("]}");
    j.check(super::scene::SCENE_TOPIC, "entities", t)
}
