//! The gap between the in-body part of each body and each region, at one
//! instant, mm.
//!
//! # What the gap is
//! - **Apart**: the distance between the body's surface (its in-body
//!   capsule) and the region's, as parry's `query::distance` gives it (for
//!   a mesh, the distance of the body's axis to its nearest triangle, found
//!   by walking parry's hierarchy with bounds of the axis' own, minus the
//!   radius).
//! - **Overlapping**: parry's distance is 0 for shapes that touch or
//!   intersect, so the gap is then minus the penetration depth of parry's
//!   `query::contact` (the distance the body must move to leave the region,
//!   for a mesh the depth into its deepest triangle), or 0 where the
//!   contact query gives none.
//! - **Inside a closed mesh**: a body wholly inside an organ does not touch
//!   its surface, so its distance is positive; for a closed mesh (a solid)
//!   the axis' point nearest the surface is tested against the mesh's
//!   pseudo-normals at the nearest triangle (parry's test, there: the axis
//!   does not cross the surface, so it is all inside or all outside), and a
//!   body inside
//!   gets minus (the distance of its axis to the surface plus its radius):
//!   at least how far it must move to leave. An open mesh is a surface and
//!   has no inside.
//!
//! A body with nothing inside the patient (a shaft retracted to its port)
//! is not checked; a region no body reaches has no gap (`+inf`).

use parry3d_f64::math::{Pose3, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::{self, Shape as ParryShape};

use crate::body::{Body, InBody};
use crate::error::AnatomyError;
use crate::file::Anatomy;
use crate::nearest::{Axis, inside, nearest};
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
        Collider::Mesh(s) => &s.mesh,
    }
}

/// The triangle of each region's mesh nearest each body at the last
/// cycle: what a loop carries from one cycle to the next, so that each mesh
/// distance starts from the triangle that was nearest (see
/// [`Anatomy::clearance_warm`]). Between two cycles a gap moves by at most
/// the bodies' speed times the period, so the triangle nearest at the last
/// cycle is nearest now or close to it, and the walk of the mesh's
/// hierarchy starts with a distance near the answer. Any value (a new one,
/// one kept from another anatomy or from an instant far away) gives the
/// same gaps; a close one gives them sooner.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct WarmStart {
    /// Per region, per body (`Body::ALL`'s order): the triangle's index.
    nearest: Vec<[Option<u32>; 3]>,
}

impl WarmStart {
    /// A start from nothing (the same as [`WarmStart::default`]).
    pub fn new() -> Self {
        Self::default()
    }
}

fn index(body: Body) -> usize {
    match body {
        Body::Left => 0,
        Body::Right => 1,
        Body::Endoscope => 2,
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
        Self::gap_from(region, body, &mut None)
    }

    /// [`Anatomy::gap`], a mesh's walk starting from the triangle `hint`
    /// and leaving there the triangle nearest now (the same gap whatever
    /// the hint).
    fn gap_from(
        region: &Region,
        body: &InBody,
        hint: &mut Option<u32>,
    ) -> Result<f64, AnatomyError> {
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
        let (tip, port, r) = (vector(&body.tip), vector(&body.port), body.radius);
        let capsule = shape::Capsule::new(tip, port, r);
        let target = shape_of(&region.collider);
        let d = match &region.collider {
            Collider::Mesh(m) => {
                let near = nearest(&m.mesh, &m.hierarchy, &Axis::new(tip, port), r, *hint)
                    .ok_or_else(|| fail("the distance is not finite"))?;
                *hint = Some(near.triangle);
                let d = near.distance - r;
                if d > 0.0 && inside(&m.mesh, &near) == Some(true) {
                    return Ok(-(d + 2.0 * r));
                }
                d
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
        self.gaps(bodies, None)
    }

    /// [`Anatomy::clearance`], each mesh's walk starting from the triangle
    /// `warm` kept as nearest at the last cycle, and `warm` left with the
    /// triangles nearest now: the same gaps, found sooner when the bodies
    /// have moved little.
    pub fn clearance_warm(
        &self,
        bodies: &[Option<InBody>],
        warm: &mut WarmStart,
    ) -> Result<NoGoClearance, AnatomyError> {
        warm.nearest.resize(self.regions.len(), [None; 3]);
        self.gaps(bodies, Some(warm))
    }

    fn gaps(
        &self,
        bodies: &[Option<InBody>],
        mut warm: Option<&mut WarmStart>,
    ) -> Result<NoGoClearance, AnatomyError> {
        let mut out = Vec::with_capacity(self.regions.len());
        for (index_of_region, region) in self.regions.iter().enumerate() {
            let mut best = RegionGap {
                region: index_of_region,
                body: None,
                gap_mm: f64::INFINITY,
            };
            for body in bodies.iter().flatten() {
                let mut cold = None;
                let hint = warm
                    .as_deref_mut()
                    .and_then(|w| w.nearest.get_mut(index_of_region))
                    .map_or(&mut cold, |hints| &mut hints[index(body.body)]);
                let gap = Self::gap_from(region, body, hint)?;
                if best.body.is_none() || gap < best.gap_mm {
                    best = RegionGap {
                        region: index_of_region,
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
