//! Clearance: the instrument shafts and the endoscope as capsules, and the
//! surface gaps between them at a control cycle.
//!
//! - [`segment`]: the kernel, the closest points of two segments and their
//!   distance in closed form ([`segment_distance`]), exact for crossing,
//!   parallel, near-parallel and zero-length segments, with its derivation;
//!   capsules and their surface gap ([`Capsule::gap`]);
//! - [`bodies`]: the bodies' sizes ([`BodyGeometry`], **assumed** defaults),
//!   the three capsules at a cycle from the platform frame, the instrument
//!   joints and the endoscope's depth ([`Bodies`]), and the three gaps
//!   between them ([`Clearance`]). See `docs/model.md`, *Clearance*;
//! - [`certify`](mod@certify): the smallest gap over a whole interval of time, not only
//!   at samples: how fast an axis' ends can move ([`AxisState`]), the
//!   lower bound between two instants ([`gap_lower_bound`]) and its
//!   refinement by bisection ([`certify()`]).

pub mod bodies;
pub mod certify;
pub mod segment;

pub use bodies::{Bodies, BodyGeometry, Clearance, ClearancePair};
pub use certify::{
    AxisAccelerations, AxisState, Certificate, Probe, certify, gap_lower_bound, rate_over,
};
pub use segment::{Capsule, CapsuleGap, ClosestPoints, Segment, segment_distance};
