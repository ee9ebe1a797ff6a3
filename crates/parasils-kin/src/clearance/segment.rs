//! Clearance between bodies modelled as capsules: the closest points of two
//! segments and their distance, in closed form.
//!
//! An instrument shaft or the endoscope is a capsule: the set of points
//! within `radius` of a segment (its axis). The surface gap between two
//! capsules is the distance between their axes minus both radii, negative
//! when they overlap. Everything here is closed form, allocation-free and
//! never panics; the only error is a non-finite input (or a result that
//! overflows the float type), reported as [`Error::NonFinite`] naming it.
//!
//! # Derivation
//!
//! Write the two segments `a(s) = a0 + s u` and `b(t) = b0 + t v` with
//! `u = a1 - a0`, `v = b1 - b0`, `s, t` in `[0, 1]`. The squared distance
//! `f(s, t) = |a(s) - b(t)|^2` is a convex quadratic on the unit square, so
//! its minimum is either
//!
//! 1. **on an edge of the square**: `s = 0`, `s = 1`, `t = 0` or `t = 1`.
//!    Each edge is a point against a segment, whose minimum is the
//!    projection clamped to the segment: for the point `p` and the segment
//!    `b`, `t = clamp((p - b0).v / v.v, 0, 1)` (`t = 0` when `v = 0`);
//! 2. or **inside**: there the connecting vector `w = a(s) - b(t)` is
//!    normal to both `u` and `v`, so it is parallel to `n = u x v`. With
//!    `r = b0 - a0`, `s u - t v - r = w`; the dot product with `v x n`
//!    kills `v` and `w`, and `u.(v x n) = n.n`, so
//!    `s = (r x v).n / n.n`; the dot product with `u x n` gives likewise
//!    `t = (r x u).n / n.n`. This exists only when `n != 0` (the segments
//!    are not parallel and neither is a point).
//!
//! The kernel evaluates the four edge candidates and the interior one and
//! keeps the pair of points **actually on the segments** whose distance is
//! smallest. The interior candidate is clamped to the square and then
//! improved by one projection each way (`t` from `a(s)`, then `s` from
//! `b(t)`), so a candidate is always a pair of points of the segments and
//! the result is never below the true distance by more than rounding.
//!
//! Why this is robust where the textbook solution of the 2x2 normal
//! equations is not:
//!
//! - the denominator is `n.n = |u x v|^2`, computed from the cross product,
//!   not `(u.u)(v.v) - (u.v)^2`, whose cancellation leaves no correct digit
//!   once the angle between the segments is below about `1e-8` rad in `f64`;
//! - when the segments are parallel (`n = 0`) or nearly so, the interior
//!   candidate is ill-conditioned along the direction of the segments, but
//!   `f` is nearly constant along that direction, so an error there costs
//!   only a second-order amount of distance; and the minimum of parallel
//!   segments is always on an edge, where the point-segment candidates
//!   are exact up to rounding;
//! - a zero-length segment (a point) has `n = 0` and `v.v = 0`: its edge
//!   candidates are a point against a segment and a point against a point;
//! - no division is by a number that can be zero, and a NaN from an
//!   overflowing intermediate is never chosen (comparisons with NaN are
//!   false), so the result is either finite or an error.
//!
//! **Error budget** (the kernel's tests, `tests/clearance.rs`, and
//! `benches/python/clearance_vs_coal.py`): in `f64`, within 3e-14 mm of the
//! exact minimum (rational arithmetic) for coordinates up to 100 mm,
//! near-parallel pairs down to 1e-12 rad included; in `f32`, within 1e-4 mm
//! of `f64` on the same inputs for coordinates up to 200 mm.
//!
//! Two segments crossing at right angles, one unit apart (the points
//! `(1, 0, 0)` and `(1, 0, 1)`, half way along each), and the capsules of
//! radius 0.25 around them, whose surfaces are 0.5 apart:
//!
//! ```
//! use nalgebra::Vector3;
//! use parasils_kin::{Capsule, Segment, segment_distance};
//!
//! let a = Segment::new(Vector3::new(0.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0));
//! let b = Segment::new(Vector3::new(1.0, -1.0, 1.0), Vector3::new(1.0, 1.0, 1.0));
//! let c = segment_distance(&a, &b)?;
//! assert_eq!(c.distance, 1.0);
//! assert_eq!((c.s, c.t), (0.5, 0.5));
//! assert_eq!(c.point_a, Vector3::new(1.0, 0.0, 0.0));
//! assert_eq!(c.point_b, Vector3::new(1.0, 0.0, 1.0));
//! let gap = Capsule::new(a, 0.25).gap(&Capsule::new(b, 0.25))?;
//! assert_eq!(gap.gap, 0.5);
//! # Ok::<(), parasils_kin::Error>(())
//! ```

use nalgebra::Vector3;

use crate::check::check_vector;
use crate::error::Error;
use crate::real::Real;

/// A segment from `start` to `end` (mm, any one frame); `start == end` is a
/// point, which the kernel handles like any other segment.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Segment<T: Real> {
    /// The first end, mm.
    pub start: Vector3<T>,
    /// The second end, mm.
    pub end: Vector3<T>,
}

impl<T: Real> Segment<T> {
    /// The segment from `start` to `end` (mm).
    pub fn new(start: Vector3<T>, end: Vector3<T>) -> Self {
        Self { start, end }
    }

    /// The point at parameter `s` (0 at `start`, 1 at `end`), both ends
    /// returned exactly.
    pub fn at(&self, s: T) -> Vector3<T> {
        if s == T::one() {
            self.end
        } else {
            self.start + (self.end - self.start) * s
        }
    }
}

/// A capsule: the points within `radius` (mm) of the segment `axis`, the
/// model of an instrument shaft or the endoscope.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Capsule<T: Real> {
    /// The axis, mm.
    pub axis: Segment<T>,
    /// The radius, mm, finite and not negative.
    pub radius: T,
}

impl<T: Real> Capsule<T> {
    /// The capsule of `radius` (mm) around `axis`.
    pub fn new(axis: Segment<T>, radius: T) -> Self {
        Self { axis, radius }
    }

    /// The surface gap between `self` and `other`: the distance between the
    /// axes minus both radii (mm, negative when they overlap), with the
    /// closest points of the axes.
    ///
    /// [`Error::InvalidParameter`] `"capsule.radius"` when a radius is
    /// negative or not finite; otherwise the errors of [`segment_distance`].
    pub fn gap(&self, other: &Capsule<T>) -> Result<CapsuleGap<T>, Error> {
        for radius in [self.radius, other.radius] {
            if !(radius >= T::zero()) || !radius.finite() {
                return Err(Error::InvalidParameter {
                    what: "capsule.radius",
                    value: radius.to_f64(),
                });
            }
        }
        let axes = segment_distance(&self.axis, &other.axis)?;
        Ok(CapsuleGap {
            gap: axes.distance - self.radius - other.radius,
            axes,
        })
    }
}

/// The closest points of two segments `a` and `b` and their distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoints<T: Real> {
    /// `|point_a - point_b|`, mm, finite and not negative.
    pub distance: T,
    /// The parameter of `point_a` on `a`, in `[0, 1]`.
    pub s: T,
    /// The parameter of `point_b` on `b`, in `[0, 1]`.
    pub t: T,
    /// The closest point of `a`, mm.
    pub point_a: Vector3<T>,
    /// The closest point of `b`, mm.
    pub point_b: Vector3<T>,
}

/// The surface gap between two capsules ([`Capsule::gap`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CapsuleGap<T: Real> {
    /// The distance between the axes minus both radii, mm (negative when the
    /// capsules overlap).
    pub gap: T,
    /// The closest points of the axes.
    pub axes: ClosestPoints<T>,
}

/// `x` clamped to `[0, 1]`, NaN to 0.
#[inline]
fn clamp01<T: Real>(x: T) -> T {
    if x >= T::one() {
        T::one()
    } else if x > T::zero() {
        x
    } else {
        T::zero()
    }
}

/// The parameter of the point of `seg` (direction `d = end - start`,
/// `dd = d.d`) closest to `p`: the projection clamped to `[0, 1]`, 0 for a
/// point.
#[inline]
fn project<T: Real>(p: &Vector3<T>, seg: &Segment<T>, d: &Vector3<T>, dd: T) -> T {
    if dd > T::zero() {
        clamp01((p - seg.start).dot(d) / dd)
    } else {
        T::zero()
    }
}

/// The closest points of the segments `a` and `b` and their distance (mm):
/// exact up to rounding for crossing, parallel, near-parallel and
/// zero-length segments (see the module's derivation).
///
/// [`Error::NonFinite`] naming the first NaN or infinite coordinate
/// (`"segment a.start.x"` ...), or `"segment distance (overflow)"` when
/// finite coordinates are so large that the distance overflows the float
/// type (beyond about `1e154` mm in `f64`, `1e19` mm in `f32`).
pub fn segment_distance<T: Real>(
    a: &Segment<T>,
    b: &Segment<T>,
) -> Result<ClosestPoints<T>, Error> {
    check_vector(
        &a.start,
        [
            "segment a.start.x",
            "segment a.start.y",
            "segment a.start.z",
        ],
    )?;
    check_vector(
        &a.end,
        ["segment a.end.x", "segment a.end.y", "segment a.end.z"],
    )?;
    check_vector(
        &b.start,
        [
            "segment b.start.x",
            "segment b.start.y",
            "segment b.start.z",
        ],
    )?;
    check_vector(
        &b.end,
        ["segment b.end.x", "segment b.end.y", "segment b.end.z"],
    )?;
    let u = a.end - a.start;
    let v = b.end - b.start;
    let uu = u.dot(&u);
    let vv = v.dot(&v);

    // The best pair so far, its `distance` holding the squared distance.
    let mut best: Option<ClosestPoints<T>> = None;
    let mut consider = |s: T, t: T| {
        let point_a = a.at(s);
        let point_b = b.at(t);
        let w = point_a - point_b;
        let d2 = w.dot(&w);
        // A NaN never wins: `d2 < best` is false for it, and a NaN first
        // candidate is replaced by any later number.
        let better = match &best {
            None => true,
            Some(b) => d2 < b.distance || b.distance.is_nan(),
        };
        if better {
            best = Some(ClosestPoints {
                distance: d2,
                s,
                t,
                point_a,
                point_b,
            });
        }
    };

    // The edges of the parameter square: each end against the other segment.
    consider(T::zero(), project(&a.start, b, &v, vv));
    consider(T::one(), project(&a.end, b, &v, vv));
    consider(project(&b.start, a, &u, uu), T::zero());
    consider(project(&b.end, a, &u, uu), T::one());

    // The interior stationary point, from the cross product.
    let n = u.cross(&v);
    let nn = n.dot(&n);
    if nn > T::zero() && nn.finite() {
        let r = b.start - a.start;
        let s = clamp01(r.cross(&v).dot(&n) / nn);
        let t = project(&a.at(s), b, &v, vv);
        let s = project(&b.at(t), a, &u, uu);
        let t = project(&a.at(s), b, &v, vv);
        consider(s, t);
    }

    match best {
        Some(c) if c.distance.finite() => Ok(ClosestPoints {
            distance: c.distance.sqrt(),
            ..c
        }),
        Some(c) => Err(Error::NonFinite {
            what: "segment distance (overflow)",
            value: c.distance.to_f64(),
        }),
        None => Err(Error::NonFinite {
            what: "segment distance (overflow)",
            value: f64::NAN,
        }),
    }
}
