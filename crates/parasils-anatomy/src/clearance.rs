//! The gap between the in-body part of each body and each region, at one
//! instant, mm.
//!
//! # What the gap is
//! - **Apart**: the distance between the body's surface (its in-body
//!   capsule) and the region's, as parry's `query::distance` gives it.
//! - **Overlapping**: parry's distance is 0 for shapes that touch or
//!   intersect, so the gap is then minus the penetration depth of parry's
//!   `query::contact` (the distance the body must move to leave the region,
//!   for a mesh the depth into its deepest triangle), or 0 where the
//!   contact query gives none.
//! - **Inside a closed mesh**: a body wholly inside an organ does not touch
//!   its surface, so its distance is positive; for a closed mesh (a solid)
//!   the tip is tested against the mesh's pseudo-normals, and a body inside
//!   gets minus (the distance of its axis to the surface plus its radius):
//!   at least how far it must move to leave. An open mesh is a surface and
//!   has no inside.
//!
//! A body with nothing inside the patient (a shaft retracted to its port)
//! is not checked; a region no body reaches has no gap (`+inf`).

use parry3d_f64::math::{Pose3, Vector};
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::{self, PointQuery};
use parry3d_f64::shape::{self, Shape as ParryShape, TriMesh};

use parasils_kin::{Segment, segment_distance};

use crate::body::{Body, InBody};
use crate::error::AnatomyError;
use crate::file::Anatomy;
use crate::region::{Collider, Region};

/// The smallest gap to one region over the bodies, and which body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionGap {
    /// The region's index in [`Anatomy::regions`].
    pub region: usize,
    /// The body closest to it (`None` when no body is inside the patient).
    pub body: Option<Body>,
    /// The gap, mm (negative inside the region; `+inf` when no body is
    /// inside the patient).
    pub gap_mm: f64,
}

/// Every region's smallest gap at one instant, in the file's order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NoGoClearance {
    /// One per region.
    pub regions: Vec<RegionGap>,
}

impl NoGoClearance {
    /// The smallest gap over every region and body (the first region on a
    /// tie); `None` without regions.
    pub fn min(&self) -> Option<RegionGap> {
        self.regions
            .iter()
            .copied()
            .reduce(|a, b| if b.gap_mm < a.gap_mm { b } else { a })
    }
}

fn shape_of(collider: &Collider) -> &dyn ParryShape {
    match collider {
        Collider::Ball(s) => s,
        Collider::Cuboid(s) => s,
        Collider::Capsule(s) => s,
        Collider::Mesh(s) => s.as_ref(),
    }
}

/// The point of the segment `a`-`b` closest to `p`.
fn closest_on_segment(p: Vector, a: Vector, b: Vector) -> Vector {
    let d = b - a;
    let len2 = d.length_squared();
    let s = if len2 > 0.0 {
        ((p - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a + d * s
}

/// A lower bound of the distance between the segment `a`-`b` and the box
/// `mins`-`maxs`: their separation along the direction `n` from the
/// segment's point `q` closest to the box's centre `c` to `c`. Every point
/// `x` of the segment has `(x - q).n <= 0` (`q` is the closest), so the
/// segment lies below `q.n` along `n` and the box above `c.n - sum h_i
/// |n_i|` (`h` its half-extents): the gap between is `|c - q| - sum h_i
/// |n_i|`. For the thin boxes of a mesh's surface this is much tighter
/// than the box's circumscribed sphere. With the gap between the two
/// axis-aligned boxes, the larger of the two bounds.
fn segment_box_bound(a: Vector, b: Vector, mins: Vector, maxs: Vector) -> f64 {
    let (c, h) = ((mins + maxs) * 0.5, (maxs - mins) * 0.5);
    let q = closest_on_segment(c, a, b);
    let to_c = c - q;
    let dist = to_c.length();
    let along = if dist > 0.0 {
        let n = to_c / dist;
        dist - (h * n.abs()).element_sum()
    } else {
        0.0
    };
    let boxes = (mins - a.max(b)).max(a.min(b) - maxs).max(Vector::ZERO);
    along.max(boxes.length())
}

/// The distance between `capsule` and the mesh's surface (0 on contact);
/// `None` when no triangle gives a finite distance.
///
/// parry's own shape-to-mesh distance bounds each BVH node by the
/// capsule's axis-aligned box, which for a long, slanted shaft covers much
/// of an organ, so it visits thousands of triangles. Here parry's BVH is
/// searched (`Bvh::find_best`) with a bound of the shaft's own
/// ([`segment_box_bound`] minus the radius), and each triangle left is
/// measured in closed form ([`segment_triangle`]).
fn mesh_distance(mesh: &TriMesh, capsule: &shape::Capsule) -> Option<f64> {
    let (a, b, r) = (capsule.segment.a, capsule.segment.b, capsule.radius);
    mesh.bvh()
        .find_best(
            f64::MAX,
            |node: &BvhNode, _| segment_box_bound(a, b, node.mins(), node.maxs()) - r,
            |id, _| segment_triangle(a, b, &mesh.triangle(id)).map(|d| (d - r).max(0.0)),
        )
        .map(|(_, d)| d)
}

/// The distance between the segment `a`-`b` and `triangle`: 0 where the
/// segment crosses it (parry's ray cast), else the smallest of the ends'
/// distances to the triangle (parry's point projection) and of the
/// segment's distances to the three edges (`parasils_kin`'s closed-form
/// segment kernel): the closest points of a segment and a triangle that do
/// not meet are an end against the triangle or the segment against an
/// edge. `None` for a coordinate that is not finite.
fn segment_triangle(a: Vector, b: Vector, triangle: &shape::Triangle) -> Option<f64> {
    use parry3d_f64::query::{Ray, RayCast};
    if triangle
        .cast_local_ray(&Ray::new(a, b - a), 1.0, true)
        .is_some()
    {
        return Some(0.0);
    }
    let to_nalgebra = |v: Vector| nalgebra::Vector3::new(v.x, v.y, v.z);
    let axis = Segment::new(to_nalgebra(a), to_nalgebra(b));
    let mut best = f64::INFINITY;
    for p in [a, b] {
        best = best.min((p - triangle.project_local_point(p, true).point).length());
    }
    for (p, q) in [
        (triangle.a, triangle.b),
        (triangle.b, triangle.c),
        (triangle.c, triangle.a),
    ] {
        let edge = Segment::new(to_nalgebra(p), to_nalgebra(q));
        best = best.min(segment_distance(&axis, &edge).ok()?.distance);
    }
    best.is_finite().then_some(best)
}

fn vector(v: &nalgebra::Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

impl Anatomy {
    /// The gap between `body` and `region`, mm (see the [module
    /// docs](self)).
    ///
    /// [`AnatomyError::Query`] when the body's ends or radius are not
    /// finite, or parry gives no finite distance.
    pub fn gap(region: &Region, body: &InBody) -> Result<f64, AnatomyError> {
        let fail = |what| AnatomyError::Query {
            region: region.name.clone(),
            body: body.body,
            what,
        };
        let finite = |v: &nalgebra::Vector3<f64>| v.iter().all(|c| c.is_finite());
        if !(finite(&body.tip)
            && finite(&body.port)
            && body.radius.is_finite()
            && body.radius >= 0.0)
        {
            return Err(fail("the body's axis or radius is not finite"));
        }
        let capsule = shape::Capsule::new(vector(&body.tip), vector(&body.port), body.radius);
        let target = shape_of(&region.collider);
        let d = match &region.collider {
            Collider::Mesh(mesh) => {
                mesh_distance(mesh, &capsule).ok_or_else(|| fail("the distance is not finite"))?
            }
            _ => {
                query::distance(&Pose3::IDENTITY, &capsule, &region.pose, target)
                    .map_err(|_| fail("parry has no distance for this pair of shapes"))?
                    .distance
            }
        };
        if !d.is_finite() {
            return Err(fail("the distance is not finite"));
        }
        if d > 0.0 {
            if let Collider::Mesh(mesh) = &region.collider
                && mesh.pseudo_normals().is_some()
                && mesh.contains_local_point(vector(&body.tip))
            {
                return Ok(-(d + 2.0 * body.radius));
            }
            return Ok(d);
        }
        let depth = query::contact(&Pose3::IDENTITY, &capsule, &region.pose, target, 0.0)
            .ok()
            .flatten()
            .map_or(0.0, |c| c.dist.min(0.0));
        Ok(if depth.is_finite() { depth } else { 0.0 })
    }

    /// Every region's smallest gap to the in-body parts `bodies` (`None`
    /// for a body with nothing inside); the first error of [`Anatomy::gap`].
    pub fn clearance(&self, bodies: &[Option<InBody>]) -> Result<NoGoClearance, AnatomyError> {
        let mut out = Vec::with_capacity(self.regions.len());
        for (index, region) in self.regions.iter().enumerate() {
            let mut best = RegionGap {
                region: index,
                body: None,
                gap_mm: f64::INFINITY,
            };
            for body in bodies.iter().flatten() {
                let gap = Self::gap(region, body)?;
                if best.body.is_none() || gap < best.gap_mm {
                    best = RegionGap {
                        region: index,
                        body: Some(body.body),
                        gap_mm: gap,
                    };
                }
            }
            out.push(best);
        }
        Ok(NoGoClearance { regions: out })
    }
}
