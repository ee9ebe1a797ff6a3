//! The segment distance kernel against independent truths: hand-derived
//! cases (crossing, parallel, collinear, near-parallel, points), symmetry,
//! invariance under rigid motions, a brute-force minimisation on a fine
//! grid, the `f32` error budget against `f64`, and every error path.

use nalgebra::{Rotation3, Vector3};
use parasils_kin::{Capsule, ClosestPoints, Error, Segment, segment_distance};
use proptest::prelude::*;

fn seg(a: [f64; 3], b: [f64; 3]) -> Segment<f64> {
    Segment::new(Vector3::from(a), Vector3::from(b))
}

fn dist(a: &Segment<f64>, b: &Segment<f64>) -> ClosestPoints<f64> {
    segment_distance(a, b).expect("finite segments")
}

/// The result is a pair of points of the segments at its own parameters,
/// and its distance is theirs.
fn assert_consistent(a: &Segment<f64>, b: &Segment<f64>, c: &ClosestPoints<f64>) {
    assert!(
        (0.0..=1.0).contains(&c.s) && (0.0..=1.0).contains(&c.t),
        "{c:?}"
    );
    assert!((c.point_a - a.at(c.s)).norm() <= 1e-12 * (1.0 + a.start.norm()));
    assert!((c.point_b - b.at(c.t)).norm() <= 1e-12 * (1.0 + b.start.norm()));
    assert!((c.distance - (c.point_a - c.point_b).norm()).abs() <= 1e-13 * (1.0 + c.distance));
}

#[test]
fn crossing_at_right_angles_one_apart() {
    // a along x, b along y one unit above: closest at a's x = 1, b's y = 0.
    let a = seg([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
    let b = seg([1.0, -1.0, 1.0], [1.0, 1.0, 1.0]);
    let c = dist(&a, &b);
    assert_eq!(c.distance, 1.0);
    assert_eq!((c.s, c.t), (0.5, 0.5));
    assert_consistent(&a, &b, &c);
}

#[test]
fn skew_with_the_closest_point_at_an_end() {
    // b's line crosses a's line at x = 3, beyond a's end at x = 1: the
    // closest points are a's end (1, 0, 0) and b's (3, 0, 0)... but b is
    // along y at x = 3, z = 0.5, so the gap is sqrt(2^2 + 0.5^2).
    let a = seg([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let b = seg([3.0, -2.0, 0.5], [3.0, 2.0, 0.5]);
    let c = dist(&a, &b);
    assert!((c.distance - 4.25_f64.sqrt()).abs() < 1e-15);
    assert_eq!(c.point_a, Vector3::new(1.0, 0.0, 0.0));
    assert_eq!(c.point_b, Vector3::new(3.0, 0.0, 0.5));
}

#[test]
fn parallel_overlapping_segments_are_their_offset_apart() {
    let a = seg([0.0, 0.0, 0.0], [4.0, 0.0, 0.0]);
    for b in [
        seg([1.0, 2.0, 0.0], [6.0, 2.0, 0.0]),
        seg([6.0, 2.0, 0.0], [1.0, 2.0, 0.0]), // opposite direction
        seg([-1.0, 0.0, 2.0], [5.0, 0.0, 2.0]), // covers a
    ] {
        let c = dist(&a, &b);
        assert_eq!(c.distance, 2.0, "{b:?}");
        assert_consistent(&a, &b, &c);
        // Closest points face each other within the overlap.
        assert!((c.point_b - c.point_a).dot(&Vector3::x()).abs() < 1e-15);
        assert!(c.point_a.x >= 0.0 && c.point_a.x <= 4.0);
    }
}

#[test]
fn collinear_segments() {
    let a = seg([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    // Apart: end to start.
    let c = dist(&a, &seg([3.0, 0.0, 0.0], [5.0, 0.0, 0.0]));
    assert_eq!(c.distance, 2.0);
    assert_eq!(c.point_a, Vector3::new(1.0, 0.0, 0.0));
    assert_eq!(c.point_b, Vector3::new(3.0, 0.0, 0.0));
    // Overlapping: zero.
    let c = dist(&a, &seg([0.5, 0.0, 0.0], [2.0, 0.0, 0.0]));
    assert_eq!(c.distance, 0.0);
    // Diagonal, in the other direction, apart by sqrt(3).
    let c = dist(
        &seg([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        &seg([3.0, 3.0, 3.0], [2.0, 2.0, 2.0]),
    );
    assert!((c.distance - 3.0_f64.sqrt()).abs() < 1e-15);
}

#[test]
fn points_against_points_and_segments() {
    // Point to point: a 3-4-5 triangle.
    let p = seg([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]);
    let q = seg([4.0, 6.0, 3.0], [4.0, 6.0, 3.0]);
    let c = dist(&p, &q);
    assert_eq!(c.distance, 5.0);
    assert_eq!((c.point_a, c.point_b), (p.start, q.start));
    // Point above the middle of a segment.
    let s = seg([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let c = dist(&seg([0.0, 3.0, 0.0], [0.0, 3.0, 0.0]), &s);
    assert_eq!((c.distance, c.t), (3.0, 0.5));
    // Point beyond the end of a segment, and the other way round.
    let s = seg([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
    let pt = seg([5.0, 4.0, 0.0], [5.0, 4.0, 0.0]);
    let c = dist(&s, &pt);
    assert_eq!((c.distance, c.s), (5.0, 1.0));
    let c = dist(&pt, &s);
    assert_eq!((c.distance, c.t), (5.0, 1.0));
    // Point on the segment.
    assert_eq!(
        dist(&seg([0.5, 0.0, 0.0], [0.5, 0.0, 0.0]), &s).distance,
        0.0
    );
}

#[test]
fn near_parallel_segments_crossing_in_the_middle() {
    // a along x over 100 mm; b turns by an angle ~ 2 delta / 100 about the
    // z axis through (50, 0, 0) and is lifted by h: the lines are h apart at
    // x = 50, while the ends are sqrt(h^2 + delta^2) apart. The
    // normal-equation denominator (u.u)(v.v) - (u.v)^2 has no correct digit
    // for the smaller angles here.
    for k in 2..=14 {
        let delta = 10f64.powi(-k);
        for h in [0.0, 1e-9, 1.0] {
            let a = seg([0.0, 0.0, 0.0], [100.0, 0.0, 0.0]);
            let b = seg([0.0, -delta, h], [100.0, delta, h]);
            let c = dist(&a, &b);
            assert!(
                (c.distance - h).abs() <= 1e-13,
                "delta {delta:e}, h {h}: {} (ends {:e} apart)",
                c.distance,
                (h * h + delta * delta).sqrt()
            );
            assert_consistent(&a, &b, &c);
        }
    }
}

#[test]
fn near_parallel_segments_offset_along_their_length() {
    // b is a shifted 30 mm along x and 2 mm along y, turned by eps about z
    // through its own start: the closest points are a's end and b's line,
    // at the distance of a point to a line (derived by hand: the end
    // (100, 0, 0) against b through (30, 2, 0) with direction (cos, sin, 0)).
    for k in 1..=12 {
        let eps = 10f64.powi(-k);
        let (s, co) = eps.sin_cos();
        let a = seg([0.0, 0.0, 0.0], [100.0, 0.0, 0.0]);
        let b = seg([30.0, 2.0, 0.0], [30.0 + 100.0 * co, 2.0 + 100.0 * s, 0.0]);
        // Distance from (100, 0) to the line: |(70, -2) x (co, s)|.
        let line = (70.0 * s + 2.0 * co).abs();
        // And from b's start (30, 2) to a: 2.  The smaller wins.
        let expected = line.min(2.0);
        let c = dist(&a, &b);
        assert!(
            (c.distance - expected).abs() < 1e-13,
            "eps {eps:e}: {} vs {expected}",
            c.distance
        );
    }
}

#[test]
fn non_finite_inputs_are_named() {
    let good = seg([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let bad = seg([0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0]);
    assert!(matches!(
        segment_distance(&good, &bad),
        Err(Error::NonFinite {
            what: "segment b.start.y",
            ..
        })
    ));
    let bad = seg([0.0, 0.0, 0.0], [1.0, 0.0, f64::INFINITY]);
    assert!(matches!(
        segment_distance(&bad, &good),
        Err(Error::NonFinite {
            what: "segment a.end.z",
            ..
        })
    ));
    // Finite but so large that the squared distance overflows: an error, not NaN.
    let far = seg([1e300, 0.0, 0.0], [-1e300, 1e300, 0.0]);
    assert!(matches!(
        segment_distance(&good, &far),
        Err(Error::NonFinite {
            what: "segment distance (overflow)",
            ..
        })
    ));
    let far32 = Segment::new(
        Vector3::new(1e30_f32, 0.0, 0.0),
        Vector3::new(-1e30, 1e30, 0.0),
    );
    let good32 = Segment::new(Vector3::new(0.0_f32, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0));
    assert!(matches!(
        segment_distance(&far32, &good32),
        Err(Error::NonFinite {
            what: "segment distance (overflow)",
            ..
        })
    ));
}

#[test]
fn capsule_gaps_subtract_both_radii_and_check_them() {
    let a = Capsule::new(seg([0.0, 0.0, 0.0], [10.0, 0.0, 0.0]), 2.5);
    let b = Capsule::new(seg([5.0, -5.0, 3.0], [5.0, 5.0, 3.0]), 1.0);
    assert_eq!(a.gap(&b).expect("valid").gap, -0.5); // 3 - 2.5 - 1
    for r in [-1.0, f64::NAN, f64::INFINITY] {
        let bad = Capsule::new(b.axis, r);
        assert!(matches!(
            a.gap(&bad),
            Err(Error::InvalidParameter {
                what: "capsule.radius",
                ..
            })
        ));
    }
}

/// The smallest distance over an `n x n` grid of parameters, and the bound
/// on how far below it the true minimum can be: half a step along each
/// segment.
fn grid_minimum(a: &Segment<f64>, b: &Segment<f64>, n: usize) -> (f64, f64) {
    let mut best = f64::INFINITY;
    let h = 1.0 / (n - 1) as f64;
    for i in 0..n {
        let pa = a.at(i as f64 * h);
        for j in 0..n {
            best = best.min((pa - b.at(j as f64 * h)).norm());
        }
    }
    let slack = 0.5 * h * ((a.end - a.start).norm() + (b.end - b.start).norm());
    (best, slack)
}

fn coord() -> impl Strategy<Value = f64> {
    -100.0..100.0_f64
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [coord(), coord(), coord()]
}

/// Random pairs: general, one of them a point, or `b` nearly parallel to
/// `a` (turned by `10^-k` rad about a random axis and shifted).
fn pair() -> impl Strategy<Value = (Segment<f64>, Segment<f64>)> {
    prop_oneof![
        (point(), point(), point(), point()).prop_map(|(a, b, c, d)| (seg(a, b), seg(c, d))),
        (point(), point(), point()).prop_map(|(a, b, c)| (seg(a, b), seg(c, c))),
        (
            point(),
            point(),
            point(),
            point(),
            0.0..13.0_f64,
            -1.0..2.0_f64
        )
            .prop_map(|(a0, a1, axis, shift, k, stretch)| {
                let a = seg(a0, a1);
                let axis = Vector3::from(axis);
                let turn = Rotation3::new(axis.normalize() * 10f64.powf(-k));
                let u = a.end - a.start;
                let start = a.start + Vector3::from(shift) * 0.05 + u * stretch;
                (a, Segment::new(start, start + turn * u))
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2_000))]

    #[test]
    fn never_above_a_fine_grid_nor_below_its_bound((a, b) in pair()) {
        let c = dist(&a, &b);
        assert_consistent(&a, &b, &c);
        let (grid, slack) = grid_minimum(&a, &b, 301);
        prop_assert!(c.distance <= grid + 1e-12, "{} above the grid's {}", c.distance, grid);
        prop_assert!(c.distance >= grid - slack - 1e-12);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(50_000))]

    #[test]
    fn symmetric_under_swapping_the_segments((a, b) in pair()) {
        let ab = dist(&a, &b);
        let ba = dist(&b, &a);
        prop_assert!((ab.distance - ba.distance).abs() <= 1e-12, "{} vs {}", ab.distance, ba.distance);
        prop_assert!(ab.distance >= 0.0 && ab.distance.is_finite());
    }

    #[test]
    fn invariant_under_rigid_motions(
        (a, b) in pair(),
        axis in point(),
        angle in -3.0..3.0_f64,
        shift in point(),
    ) {
        let rot = Rotation3::new(Vector3::from(axis).normalize() * angle);
        let shift = Vector3::from(shift);
        let moved = |s: &Segment<f64>| Segment::new(rot * s.start + shift, rot * s.end + shift);
        let before = dist(&a, &b).distance;
        let after = dist(&moved(&a), &moved(&b)).distance;
        // Moving the points costs a few ulps of their ~300 mm coordinates.
        prop_assert!((before - after).abs() <= 1e-12, "{before} vs {after}");
    }

    #[test]
    fn reversing_a_segment_keeps_the_distance((a, b) in pair()) {
        let d = dist(&a, &b).distance;
        let r = dist(&Segment::new(a.end, a.start), &b).distance;
        prop_assert!((d - r).abs() <= 1e-12);
    }

    /// The `f32` error budget: within 1e-4 mm of `f64` for coordinates of
    /// at most 200 mm (the targets ask 1e-3 mm).
    #[test]
    fn f32_within_its_budget((a, b) in pair()) {
        let to32 = |v: Vector3<f64>| v.map(|x| x as f32);
        let a32 = Segment::new(to32(a.start), to32(a.end));
        let b32 = Segment::new(to32(b.start), to32(b.end));
        // The f64 truth of the rounded inputs, so only the arithmetic counts.
        let back = |s: &Segment<f32>| Segment::new(s.start.map(f64::from), s.end.map(f64::from));
        let truth = dist(&back(&a32), &back(&b32)).distance;
        let got = segment_distance(&a32, &b32).expect("finite");
        prop_assert!((f64::from(got.distance) - truth).abs() <= 1e-4, "{} vs {truth}", got.distance);
    }
}

mod bodies {
    //! The capsules of a cycle against the kinematics they come from: each
    //! shaft starts at the tip forward kinematics gives, passes through its
    //! port (the RCM in the fixed frame) `qs3` mm further, and is as long
    //! as the file says; the endoscope starts at its tip.

    use nalgebra::Vector3;
    use parasils_kin::{
        Bodies, BodyGeometry, ClearancePair, Controller, EndoscopeGeometry, Error, Joints,
        PlatformState, Pose,
    };
    use proptest::prelude::*;

    fn point_line_distance(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        let d = (b - a).normalize();
        let w = p - a;
        (w - d * w.dot(&d)).norm()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2_000))]

        #[test]
        fn shafts_run_from_the_tips_through_the_ports(
            x in -50.0..50.0_f64, y in -50.0..50.0_f64, z in -550.0..-450.0_f64,
            psi in -30.0..30.0_f64, theta in -30.0..30.0_f64, phi in -90.0..90.0_f64,
            ql in (-1.0..1.0_f64, -1.0..1.0_f64, 20.0..250.0_f64),
            qr in (-1.0..1.0_f64, -1.0..1.0_f64, 20.0..250.0_f64),
            depth in 0.0..200.0_f64,
        ) {
            let c = Controller::<f64>::paper();
            let pose = Pose::from_mm_deg(x, y, z, psi, theta, phi);
            let frame = PlatformState::at_rest(pose).frame().expect("finite");
            let ql = Joints::new(ql.0, ql.1, ql.2);
            let qr = Joints::new(qr.0, qr.1, qr.2);
            let g = BodyGeometry::assumed();
            let b = Bodies::at(&g, &frame, &c.left, &ql, &c.right, &qr, depth).expect("finite");
            for (shaft, module, q) in [(&b.left, &c.left, &ql), (&b.right, &c.right, &qr)] {
                let tip = module.fk(&pose, q).expect("finite");
                prop_assert!((shaft.axis.start - tip).norm() < 1e-9);
                prop_assert!(((shaft.axis.end - shaft.axis.start).norm() - 400.0).abs() < 1e-9);
                let port = frame.to_fixed(&module.geometry().rcm);
                prop_assert!(point_line_distance(&port, &shaft.axis.start, &shaft.axis.end) < 1e-9);
                prop_assert!(((port - tip).norm() - q.qs3).abs() < 1e-9);
                prop_assert_eq!(shaft.radius, 2.5);
            }
            let endo_tip = EndoscopeGeometry::paper().tip(&frame, depth).expect("in range");
            prop_assert!((b.endoscope.axis.start - endo_tip).norm() < 1e-9);
            prop_assert_eq!(b.endoscope.radius, 5.0);
            // The minimum is the smallest of the three, and its pair's.
            let gaps = b.clearance().expect("finite");
            let (pair, min) = gaps.min();
            prop_assert_eq!(min, gaps.get(pair).gap);
            for p in ClearancePair::ALL {
                prop_assert!(min <= gaps.get(p).gap);
            }
        }
    }

    #[test]
    fn bad_sizes_and_inputs_are_named() {
        let c = Controller::<f64>::paper();
        let frame = PlatformState::at_rest(Pose::paper_start())
            .frame()
            .expect("finite");
        let q = Joints::new(0.1, -0.2, 120.0);
        let mut g = BodyGeometry::assumed();
        g.endoscope_diameter = -1.0;
        assert!(matches!(
            Bodies::at(&g, &frame, &c.left, &q, &c.right, &q, 10.0),
            Err(Error::InvalidParameter {
                what: "bodies.endoscope_diameter",
                ..
            })
        ));
        let g = BodyGeometry::assumed();
        assert!(matches!(
            Bodies::at(&g, &frame, &c.left, &q, &c.right, &q, f64::NAN),
            Err(Error::NonFinite {
                what: "endoscope depth",
                ..
            })
        ));
        let bad = Joints::new(0.1, f64::INFINITY, 120.0);
        assert!(matches!(
            Bodies::at(&g, &frame, &c.left, &bad, &c.right, &q, 10.0),
            Err(Error::NonFinite { .. })
        ));
        assert_eq!(
            ClearancePair::LeftEndoscope.to_string(),
            "left shaft - endoscope"
        );
        assert_eq!(ClearancePair::RightEndoscope.key(), "right_endoscope");
    }
}
