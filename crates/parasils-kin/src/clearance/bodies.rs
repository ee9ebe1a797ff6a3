//! The bodies at a control cycle: each instrument shaft and the endoscope as
//! a capsule, and the surface gaps between the three.
//!
//! An instrument's shaft runs from its tip back along the tool axis, through
//! its port (the RCM), for the shaft's length: in the module's RCM frame the
//! tool points along the tool frame's `-z` with the tip at `z = -qs3`
//! ([`Instrument::tool_rotation`]), so the axis is
//! `RCM + R_tool (0, 0, -qs3)` to `RCM + R_tool (0, 0, length - qs3)` in the
//! platform frame. The endoscope's runs from its tip `P + R (0, 0, -depth)`
//! back along `+Z'`, to `P + R (0, 0, length - depth)`.
//!
//! ```
//! use parasils_kin::{Bodies, BodyGeometry, ClearancePair, Controller, PlatformState, Pose};
//! use parasils_kin::Joints;
//!
//! let controller = Controller::<f64>::paper();
//! // Platform level at the origin, both tools straight down (qs1 = qs2 =
//! // 0 but for the modules' fixed tilts), the endoscope 50 mm in.
//! let frame = PlatformState::at_rest(Pose::from_mm_deg(0.0, 0.0, -500.0, 0.0, 0.0, 0.0)).frame()?;
//! let q = Joints::new(0.0, 0.0, 100.0);
//! let bodies = Bodies::at(&BodyGeometry::assumed(), &frame, &controller.left, &q, &controller.right, &q, 50.0)?;
//! let gaps = bodies.clearance()?;
//! // Every gap is an axis distance minus both radii.
//! let axes = (bodies.left.axis.start - bodies.right.axis.start).norm();
//! assert!(gaps.left_right.gap <= axes - 5.0);
//! let (pair, min) = gaps.min();
//! assert!(min <= gaps.left_right.gap && min <= gaps.left_endoscope.gap);
//! assert!(matches!(pair, ClearancePair::LeftRight | ClearancePair::LeftEndoscope | ClearancePair::RightEndoscope));
//! # Ok::<(), parasils_kin::Error>(())
//! ```

use core::fmt;

use nalgebra::Vector3;

use super::segment::{Capsule, CapsuleGap, Segment};
use crate::error::Error;
use crate::frame::PlatformFrame;
use crate::instrument::{Instrument, Joints};
use crate::presets;
use crate::real::Real;

/// The bodies' sizes, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BodyGeometry<T> {
    /// Each instrument shaft's diameter, mm (default **assumed** 5).
    pub instrument_diameter: T,
    /// Each instrument shaft's length from its tip, mm (default **assumed** 400).
    pub instrument_length: T,
    /// The endoscope's diameter, mm (default **assumed** 10).
    pub endoscope_diameter: T,
    /// The endoscope's length from its tip, mm (default **assumed** 400).
    pub endoscope_length: T,
}

impl<T: Real> BodyGeometry<T> {
    /// The **assumed** sizes of [`presets::BODIES_MM`]: shafts of 5 mm, the
    /// endoscope of 10 mm, each 400 mm long.
    pub fn assumed() -> Self {
        let [id, il, ed, el] = presets::BODIES_MM;
        Self {
            instrument_diameter: T::lit(id),
            instrument_length: T::lit(il),
            endoscope_diameter: T::lit(ed),
            endoscope_length: T::lit(el),
        }
    }

    /// [`Error::InvalidParameter`] naming the first size that is not finite
    /// or is negative (`"bodies.instrument_diameter"` ...).
    pub fn validate(&self) -> Result<(), Error> {
        for (value, what) in [
            (self.instrument_diameter, "bodies.instrument_diameter"),
            (self.instrument_length, "bodies.instrument_length"),
            (self.endoscope_diameter, "bodies.endoscope_diameter"),
            (self.endoscope_length, "bodies.endoscope_length"),
        ] {
            if !(value >= T::zero()) || !value.finite() {
                return Err(Error::InvalidParameter {
                    what,
                    value: value.to_f64(),
                });
            }
        }
        Ok(())
    }
}

/// Which two bodies a gap is between.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ClearancePair {
    /// The two instrument shafts.
    LeftRight,
    /// The left shaft and the endoscope.
    LeftEndoscope,
    /// The right shaft and the endoscope.
    RightEndoscope,
}

impl ClearancePair {
    /// The three pairs, in the order of [`Clearance`]'s fields and of the
    /// CSV columns.
    pub const ALL: [ClearancePair; 3] = [
        ClearancePair::LeftRight,
        ClearancePair::LeftEndoscope,
        ClearancePair::RightEndoscope,
    ];

    /// `"left_right"`, `"left_endoscope"`, `"right_endoscope"`: the pair's
    /// name in column names and file keys.
    pub fn key(self) -> &'static str {
        match self {
            ClearancePair::LeftRight => "left_right",
            ClearancePair::LeftEndoscope => "left_endoscope",
            ClearancePair::RightEndoscope => "right_endoscope",
        }
    }
}

impl fmt::Display for ClearancePair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ClearancePair::LeftRight => "left shaft - right shaft",
            ClearancePair::LeftEndoscope => "left shaft - endoscope",
            ClearancePair::RightEndoscope => "right shaft - endoscope",
        })
    }
}

/// The three bodies at one instant, fixed frame, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bodies<T: Real> {
    /// The left shaft, its axis from the tip back through the port.
    pub left: Capsule<T>,
    /// The right shaft, likewise.
    pub right: Capsule<T>,
    /// The endoscope, its axis from its tip back along `+Z'`.
    pub endoscope: Capsule<T>,
}

/// The surface gaps between the three bodies (mm, negative when two
/// overlap), with the closest points of their axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance<T: Real> {
    /// Left shaft to right shaft.
    pub left_right: CapsuleGap<T>,
    /// Left shaft to endoscope.
    pub left_endoscope: CapsuleGap<T>,
    /// Right shaft to endoscope.
    pub right_endoscope: CapsuleGap<T>,
}

impl<T: Real> Clearance<T> {
    /// The gap of `pair`.
    pub fn get(&self, pair: ClearancePair) -> &CapsuleGap<T> {
        match pair {
            ClearancePair::LeftRight => &self.left_right,
            ClearancePair::LeftEndoscope => &self.left_endoscope,
            ClearancePair::RightEndoscope => &self.right_endoscope,
        }
    }

    /// The smallest of the three gaps and its pair (the first of
    /// [`ClearancePair::ALL`] on a tie), mm.
    pub fn min(&self) -> (ClearancePair, T) {
        let mut best = (ClearancePair::LeftRight, self.left_right.gap);
        for pair in [ClearancePair::LeftEndoscope, ClearancePair::RightEndoscope] {
            let gap = self.get(pair).gap;
            if gap < best.1 {
                best = (pair, gap);
            }
        }
        best
    }
}

/// The shaft's axis in the platform frame: `RCM + R_tool (0, 0, -qs3)` to
/// `RCM + R_tool (0, 0, length - qs3)`. `R_tool (0, 0, -1)` is the unit
/// vector from the RCM to the tip, which the forward kinematics gives at
/// `qs3 = 1` ([`Instrument::fk_local`], with the kinematics' own sine and
/// cosine: the rotation matrix itself would take four of the float
/// library's, most of a cycle's cost on a microcontroller).
fn shaft<T: Real>(
    frame: &PlatformFrame<T>,
    module: &Instrument<T>,
    q: &Joints<T>,
    length: T,
) -> Segment<T> {
    let rcm = module.geometry().rcm;
    let down = module.fk_local(&Joints::new(q.qs1, q.qs2, T::one()));
    let along = |z: T| frame.to_fixed(&(rcm - down * z));
    Segment::new(along(-q.qs3), along(length - q.qs3))
}

impl<T: Real> Bodies<T> {
    /// The three capsules at the platform frame `frame`, the left and right
    /// modules' joints `q_left`, `q_right` and the endoscope's insertion
    /// `depth` (mm).
    ///
    /// [`Error::InvalidParameter`] for a bad size
    /// ([`BodyGeometry::validate`]); [`Error::NonFinite`] naming the first
    /// non-finite joint, depth or end of an axis.
    pub fn at(
        geometry: &BodyGeometry<T>,
        frame: &PlatformFrame<T>,
        left: &Instrument<T>,
        q_left: &Joints<T>,
        right: &Instrument<T>,
        q_right: &Joints<T>,
        depth: T,
    ) -> Result<Self, Error> {
        geometry.validate()?;
        q_left.check_finite()?;
        q_right.check_finite()?;
        if !depth.finite() {
            return Err(Error::NonFinite {
                what: "endoscope depth",
                value: depth.to_f64(),
            });
        }
        let half = T::lit(0.5);
        let r_shaft = geometry.instrument_diameter * half;
        let endoscope = Segment::new(
            frame.to_fixed(&Vector3::new(T::zero(), T::zero(), -depth)),
            frame.to_fixed(&Vector3::new(
                T::zero(),
                T::zero(),
                geometry.endoscope_length - depth,
            )),
        );
        Ok(Self {
            left: Capsule::new(
                shaft(frame, left, q_left, geometry.instrument_length),
                r_shaft,
            ),
            right: Capsule::new(
                shaft(frame, right, q_right, geometry.instrument_length),
                r_shaft,
            ),
            endoscope: Capsule::new(endoscope, geometry.endoscope_diameter * half),
        })
    }

    /// The three surface gaps; the errors of [`Capsule::gap`] (a non-finite
    /// end of an axis is named there).
    pub fn clearance(&self) -> Result<Clearance<T>, Error> {
        Ok(Clearance {
            left_right: self.left.gap(&self.right)?,
            left_endoscope: self.left.gap(&self.endoscope)?,
            right_endoscope: self.right.gap(&self.endoscope)?,
        })
    }
}
