//! The clearance kernel (`parasils_kin::segment_distance`) with arbitrary
//! `f64` and `f32` bit patterns, and with the shapes where distance kernels
//! fail: near-parallel segments (one segment a copy of the other turned by
//! a fuzzed amount down to nothing), collinear ones, and zero-length ones
//! (one or both a point).
//!
//! What must hold: no panic; finite inputs of moderate size (below `1e150`
//! in `f64`, `1e18` in `f32`: beyond, the squared distance may overflow,
//! which is a typed error) give `Ok`, a NaN or infinite one an error naming
//! a coordinate; an `Ok` is finite and not negative, with `s` and `t` in
//! `[0, 1]`; and, for ends below those sizes, each closest point is on
//! its segment (the point at its parameter), the distance is
//! `|point_a - point_b|`, swapping the segments gives the same distance and
//! it is no larger than any
//! endpoint's distance to the other segment (computed here in `f64`, by
//! its own projection, where that does not overflow). Tolerances: `64 eps` of the largest coordinate,
//! plus the smallest distance the type's squares can resolve (`1e-150` in
//! `f64`, `1e-18` in `f32`, where `d^2` underflows).

use nalgebra::Vector3;
use parasils::kin::{Error, Segment, segment_distance as kernel};

use crate::input::{FuzzFloat, Input};

/// The target: the float type from the first byte, then the shape.
pub fn segment_distance(data: &[u8]) {
    let mut inp = Input::new(data);
    if inp.flag() {
        segment_distance_in::<f32>(&mut inp);
    } else {
        segment_distance_in::<f64>(&mut inp);
    }
}

fn vector<T: FuzzFloat>(inp: &mut Input) -> Vector3<T> {
    Vector3::from(inp.reals::<T, 3>())
}

fn wide<T: FuzzFloat>(v: &Vector3<T>) -> Vector3<f64> {
    Vector3::new(v.x.wide(), v.y.wide(), v.z.wide())
}

/// The distance from `p` to the segment `a`-`b`, in `f64`: the projection
/// clamped to the segment.
fn point_segment(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let d = b - a;
    let dd = d.dot(&d);
    let s = if dd > 0.0 {
        ((p - a).dot(&d) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * s)).norm()
}

fn segment_distance_in<T: FuzzFloat>(inp: &mut Input) {
    let a0 = vector::<T>(inp);
    let a1 = vector::<T>(inp);
    let (b0, b1) = match inp.choose(4) {
        // Any four ends.
        0 => (vector::<T>(inp), vector::<T>(inp)),
        // Near-parallel: `b` is `a` moved by an offset, its far end nudged
        // by a fuzzed vector scaled down by up to 2^-63.
        1 => {
            let offset = vector::<T>(inp);
            let nudge = vector::<T>(inp);
            let scale = T::of(f64::powi(2.0, -i32::from(inp.choose(64))));
            let b0 = a0 + offset;
            (b0, b0 + (a1 - a0) + nudge * scale)
        }
        // `b` a point.
        2 => {
            let p = vector::<T>(inp);
            (p, p)
        }
        // Both points (`a` collapsed onto its start).
        _ => {
            let p = vector::<T>(inp);
            let q = vector::<T>(inp);
            return check(&Segment::new(a0, a0), &Segment::new(p, q));
        }
    };
    check(&Segment::new(a0, a1), &Segment::new(b0, b1));
}

fn check<T: FuzzFloat>(a: &Segment<T>, b: &Segment<T>) {
    let ends = [a.start, a.end, b.start, b.end].map(|v| wide(&v));
    let finite = ends.iter().all(|v| v.iter().all(|x| x.is_finite()));
    let scale = ends
        .iter()
        .flat_map(|v| v.iter().map(|x| x.abs()))
        .fold(0.0, f64::max);
    let (limit, floor) = if T::BYTES == 4 {
        (1e18, 1e-18)
    } else {
        (1e150, 1e-150)
    };
    let result = kernel(a, b);
    let c = match result {
        Ok(c) => c,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            assert!(
                matches!(e, Error::NonFinite { what, .. } if what.starts_with("segment")),
                "{e:?}"
            );
            assert!(
                !finite || scale >= limit,
                "an error for finite ends of size {scale} ({}): {e}",
                T::NAME
            );
            return;
        }
    };
    assert!(finite, "Ok for a non-finite end ({})", T::NAME);
    let tol = 64.0 * T::EPS * scale + floor;
    let d = c.distance.wide();
    let (s, t) = (c.s.wide(), c.t.wide());
    let (pa, pb) = (wide(&c.point_a), wide(&c.point_b));
    let all = [d, s, t, pa.x, pa.y, pa.z, pb.x, pb.y, pb.z];
    assert!(
        all.iter().all(|x| x.is_finite()),
        "a non-finite Ok: {all:?} ({})",
        T::NAME
    );
    assert!(d >= 0.0, "a negative distance {d}");
    assert!(
        (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t),
        "s = {s}, t = {t}"
    );
    // Beyond the sizes whose squares the type holds, the kernel's
    // intermediates overflow and its result, though finite and a true
    // distance of two points of the segments, need not be the smallest
    // (found by this target in `f32` near 1e20 mm): only the properties
    // above are asked there (the references below would overflow too).
    if scale >= limit {
        return;
    }
    let [a0, a1, b0, b1] = ends;
    for (p, x0, x1, u, what) in [(pa, a0, a1, s, "a"), (pb, b0, b1, t, "b")] {
        let on = x0 + (x1 - x0) * u;
        assert!(
            (p - on).norm() <= tol,
            "point_{what} {p:?} is not at {u} on its segment: {on:?} (tolerance {tol})"
        );
    }
    let between = (pa - pb).norm();
    assert!(
        (d - between).abs() <= tol,
        "distance {d} but |point_a - point_b| = {between} (tolerance {tol})"
    );
    match kernel(b, a) {
        Ok(swapped) => {
            let e = swapped.distance.wide();
            assert!(
                (d - e).abs() <= tol,
                "not symmetric: {d} and {e} (tolerance {tol})"
            );
        }
        Err(e) => panic!("the swap fails: {e}"),
    }
    for (p, x0, x1) in [(a0, b0, b1), (a1, b0, b1), (b0, a0, a1), (b1, a0, a1)] {
        let bound = point_segment(&p, &x0, &x1);
        // The reference's own squares may overflow for huge ends.
        assert!(
            !bound.is_finite() || d <= bound + tol,
            "distance {d} above an end's distance {bound} (tolerance {tol})"
        );
    }
}
