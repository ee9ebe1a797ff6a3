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
use parry3d_f64::query::{self, PointQuery};
use parry3d_f64::shape::{self, Shape as ParryShape};

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
        let d = query::distance(&Pose3::IDENTITY, &capsule, &region.pose, target)
            .map_err(|_| fail("parry has no distance for this pair of shapes"))?
            .distance;
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
