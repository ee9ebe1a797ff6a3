//! The in-body part of each instrument shaft and of the endoscope: what is
//! checked against the anatomy.
//!
//! A shaft's capsule ([`parasils_kin::Bodies`]) runs from its tip back along
//! the tool axis through its port (the RCM, the incision) and on outside the
//! patient. Only the part from the tip back to the port is inside: for an
//! instrument that is the first `qs3` mm of the axis (the tip is at
//! `z = -qs3` of the tool frame, the port at `z = 0`), for the endoscope the
//! first `depth` mm (its tip at `P + R (0, 0, -depth)`, its port at `P`).
//! The part outside the body is not checked against anatomy.

use core::fmt;

use nalgebra::Vector3;
use parasils_kin::{Bodies, Capsule};

/// Which body a gap is measured from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Body {
    /// The left instrument's shaft.
    Left,
    /// The right instrument's shaft.
    Right,
    /// The endoscope.
    Endoscope,
}

impl Body {
    /// The three bodies, in the order of [`InBody::of`]'s array.
    pub const ALL: [Body; 3] = [Body::Left, Body::Right, Body::Endoscope];

    /// `"left"`, `"right"`, `"endoscope"`: the body's name in columns and
    /// reports.
    pub fn key(self) -> &'static str {
        match self {
            Body::Left => "left",
            Body::Right => "right",
            Body::Endoscope => "endoscope",
        }
    }
}

impl fmt::Display for Body {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Body::Left => "left shaft",
            Body::Right => "right shaft",
            Body::Endoscope => "endoscope",
        })
    }
}

/// The in-body part of one body: a capsule from its tip back to its port,
/// fixed frame, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InBody {
    /// Which body.
    pub body: Body,
    /// The tip, mm, fixed frame.
    pub tip: Vector3<f64>,
    /// The port (where the axis enters the patient), mm, fixed frame.
    pub port: Vector3<f64>,
    /// The body's radius, mm.
    pub radius: f64,
}

impl InBody {
    /// The first `inserted_mm` of `capsule`'s axis from its start (the tip),
    /// or `None` when nothing is inside (`inserted_mm <= 0`, or not a
    /// number). An insertion longer than the axis keeps the whole axis.
    pub fn from_tip(body: Body, capsule: &Capsule<f64>, inserted_mm: f64) -> Option<Self> {
        if !(inserted_mm > 0.0) {
            return None;
        }
        let axis = capsule.axis.end - capsule.axis.start;
        let length = axis.norm();
        let s = if length > inserted_mm {
            inserted_mm / length
        } else {
            1.0
        };
        Some(Self {
            body,
            tip: capsule.axis.start,
            port: capsule.axis.start + axis * s,
            radius: capsule.radius,
        })
    }

    /// The in-body parts of `bodies`, `[left, right, endoscope]`, with the
    /// instruments' insertions `qs3` (mm) and the endoscope's `depth` (mm).
    pub fn of(
        bodies: &Bodies<f64>,
        qs3_left: f64,
        qs3_right: f64,
        depth: f64,
    ) -> [Option<Self>; 3] {
        [
            Self::from_tip(Body::Left, &bodies.left, qs3_left),
            Self::from_tip(Body::Right, &bodies.right, qs3_right),
            Self::from_tip(Body::Endoscope, &bodies.endoscope, depth),
        ]
    }
}
