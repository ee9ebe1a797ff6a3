//! Forbidden regions as the online controller sees them: the smallest gap
//! from the in-body parts of the shafts and the endoscope to regions of the
//! patient they must keep out of.
//!
//! The regions themselves (spheres, boxes, capsules, triangle meshes from
//! an anatomy file) live in `parasils-anatomy`, which needs `std` and a
//! collision library; this crate is `no_std`. The controller therefore asks
//! through a small trait, [`ForbiddenRegions`]: given the cycle's in-body
//! capsules ([`InBodyCapsules`]), the smallest gap (mm) and which region
//! ([`NearestRegion`]). `parasils-anatomy` implements it for its `Anatomy`;
//! [`NoRegions`] is the empty set, what
//! [`OnlineController::tick`](crate::OnlineController::tick) uses.
//!
//! The in-body part of a body is its capsule from the tip back to its port
//! (the incision): the first `qs3` mm of an instrument's axis (its tip is
//! `qs3` from its RCM), the first `depth` mm of the endoscope's. What is
//! outside the patient is not checked against the regions.

use crate::Real;
use crate::kin::{Bodies, Capsule, Segment};

/// The in-body capsules of one cycle, mm, fixed frame: each from the tip
/// back to the port, `None` for a body with nothing inside the patient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InBodyCapsules<T: Real> {
    /// The left shaft's.
    pub left: Option<Capsule<T>>,
    /// The right shaft's.
    pub right: Option<Capsule<T>>,
    /// The endoscope's.
    pub endoscope: Option<Capsule<T>>,
}

impl<T: Real> InBodyCapsules<T> {
    /// The in-body parts of `bodies` (their axes start at the tips) with
    /// the instruments' insertions `qs3_left`, `qs3_right` and the
    /// endoscope's `depth` (mm): the first that many mm of each axis, the
    /// whole axis when it is shorter, `None` for an insertion that is not
    /// above 0 (or NaN).
    pub fn of(bodies: &Bodies<T>, qs3_left: T, qs3_right: T, depth: T) -> Self {
        Self {
            left: inside(&bodies.left, qs3_left),
            right: inside(&bodies.right, qs3_right),
            endoscope: inside(&bodies.endoscope, depth),
        }
    }

    /// The three, `[left, right, endoscope]`.
    pub fn all(&self) -> [Option<Capsule<T>>; 3] {
        [self.left, self.right, self.endoscope]
    }
}

/// The first `inserted` mm of `capsule`'s axis from its start.
fn inside<T: Real>(capsule: &Capsule<T>, inserted: T) -> Option<Capsule<T>> {
    if !(inserted > T::zero()) {
        return None;
    }
    let axis = capsule.axis.end - capsule.axis.start;
    let length = axis.norm();
    let end = if length > inserted {
        capsule.axis.start + axis * (inserted / length)
    } else {
        capsule.axis.end
    };
    Some(Capsule::new(
        Segment::new(capsule.axis.start, end),
        capsule.radius,
    ))
}

/// The smallest gap from the in-body parts to the regions, and which
/// region it is to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NearestRegion<T> {
    /// The region's index in its set (for an anatomy file, the file's
    /// order).
    pub region: usize,
    /// The gap, mm: the distance between the body's surface and the
    /// region's, negative inside the region.
    pub gap_mm: T,
}

/// A region's gap could not be computed (a body's axis not finite, or the
/// query gave no finite distance).
///
/// # When this happens / how to handle it
/// The controller cannot tell how close the bodies are: the tick that asked
/// fails and changes nothing; hold the drives or command a stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("forbidden region {region}: its gap to the bodies could not be computed")]
pub struct RegionQueryError {
    /// The region's index in its set.
    pub region: usize,
}

/// Regions the bodies must keep out of, asked once per control cycle.
///
/// An implementation answers with the smallest gap over every region and
/// every in-body part given, `Ok(None)` when it has no region or no body is
/// inside; never a NaN gap (a failed query is a [`RegionQueryError`]). It is
/// called from the control loop, so it should answer within the cycle.
pub trait ForbiddenRegions<T: Real> {
    /// The smallest gap from `bodies` to the regions (see the trait's docs).
    ///
    /// # Errors
    /// [`RegionQueryError`] naming the region whose gap could not be
    /// computed.
    fn nearest(
        &self,
        bodies: &InBodyCapsules<T>,
    ) -> Result<Option<NearestRegion<T>>, RegionQueryError>;

    /// Whether there is no region at all (then nothing is computed for
    /// them). `false` unless the implementation says otherwise.
    fn is_empty(&self) -> bool {
        false
    }
}

/// No region: what [`OnlineController::tick`](crate::OnlineController::tick)
/// checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NoRegions;

impl<T: Real> ForbiddenRegions<T> for NoRegions {
    fn nearest(
        &self,
        _bodies: &InBodyCapsules<T>,
    ) -> Result<Option<NearestRegion<T>>, RegionQueryError> {
        Ok(None)
    }

    fn is_empty(&self) -> bool {
        true
    }
}
