//! The mesh distance against brute force: every triangle measured by a
//! second implementation written here (the point-to-triangle distance in
//! closed form, minimised along the segment by a golden-section search,
//! which finds the minimum because that distance is convex along a
//! segment), on random shafts near, far, across and inside a closed
//! non-convex mesh; and the warm start, which must not change a gap.

use nalgebra::Vector3;
use parasils_anatomy::{Anatomy, Body, InBody, Mesh, Region, Shape, WarmStart};
use parasils_io::Rng;

type V = Vector3<f64>;

/// The distance from `p` to the segment `a`-`b`.
fn point_segment(p: &V, a: &V, b: &V) -> f64 {
    let d = b - a;
    let s = if d.norm_squared() > 0.0 {
        ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * s)).norm()
}

/// The distance from `p` to the triangle `t`: to its plane when `p`
/// projects inside it (all three edge tests on the inner side), else to
/// the nearest edge.
fn point_triangle(p: &V, t: &[V; 3]) -> f64 {
    let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
    let inside = (0..3).all(|i| {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        (b - a).cross(&(p - a)).dot(&n) >= 0.0
    });
    if inside {
        return ((p - t[0]).dot(&n) / n.norm()).abs();
    }
    (0..3)
        .map(|i| point_segment(p, &t[i], &t[(i + 1) % 3]))
        .fold(f64::INFINITY, f64::min)
}

/// The distance from the segment `a`-`b` to `t`, by golden section along
/// the segment (to 1e-20 of its length), the ends included.
fn segment_triangle(a: &V, b: &V, t: &[V; 3]) -> f64 {
    let f = |s: f64| point_triangle(&(a + (b - a) * s), t);
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (0.0, 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..100 {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
    }
    f1.min(f2).min(f(0.0)).min(f(1.0))
}

/// The smallest distance from the segment to any triangle of `mesh`,
/// skipping a triangle whose bounding sphere is already farther.
fn brute_force(a: &V, b: &V, mesh: &Mesh) -> f64 {
    let v = mesh.vertices();
    let mut best = f64::INFINITY;
    for tri in mesh.triangles() {
        let t = tri.map(|i| V::from(v[i as usize]));
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let radius = t.iter().map(|p| (p - c).norm()).fold(0.0, f64::max);
        if point_segment(&c, a, b) - radius >= best {
            continue;
        }
        best = best.min(segment_triangle(a, b, &t));
    }
    best
}

/// A closed, non-convex organ: an ellipsoid's vertices pushed out and in
/// along their direction from the centre by up to 25 %, so that bumps and
/// hollows alternate (`2 * 40 * 29` triangles). Its radius along a
/// direction, for the inside test of the truth.
fn bumpy() -> (Mesh, impl Fn(&V) -> f64) {
    let centre = V::new(10.0, -5.0, -80.0);
    let sphere = Mesh::ellipsoid(centre.into(), [40.0, 40.0, 40.0], 30, 40).expect("mesh");
    let radius = move |d: &V| {
        let u = d.normalize();
        40.0 * (1.0 + 0.25 * (3.0 * u.x).sin() * (4.0 * u.y).cos())
    };
    let vertices = sphere
        .vertices()
        .iter()
        .map(|p| {
            let d = V::from(*p) - centre;
            (centre + d.normalize() * radius(&d)).into()
        })
        .collect();
    let mesh = Mesh::new(vertices, sphere.triangles().to_vec()).expect("a valid mesh");
    assert!(mesh.is_closed());
    (mesh, move |p: &V| {
        radius(&(p - centre)) - (p - centre).norm()
    })
}

fn region(mesh: &Mesh) -> Region {
    Region::new(
        "organ".into(),
        Shape::Mesh {
            file: "organ.stl".into(),
            translation_mm: [0.0; 3],
            mesh: mesh.clone(),
            solid: true,
        },
    )
    .expect("parry builds it")
}

#[test]
fn the_mesh_distance_is_the_smallest_over_every_triangle() {
    let (mesh, depth_inside) = bumpy();
    let organ = region(&mesh);
    let centre = V::new(10.0, -5.0, -80.0);
    let mut rng = Rng::new(27);
    let (mut apart, mut inside, mut touching) = (0, 0, 0);
    for i in 0..240 {
        // Tips anywhere from the organ's middle to 150 mm away, shafts of
        // 20 to 200 mm in any direction (near, far, across), and short ones
        // about the middle (inside).
        let (reach, length) = [(45.0, 200.0), (60.0, 200.0), (150.0, 200.0), (20.0, 20.0)][i % 4];
        let tip = centre + V::from([0; 3].map(|_| rng.uniform(-reach, reach)));
        let dir = V::from([0; 3].map(|_| rng.uniform(-1.0, 1.0)));
        let port = tip + dir.normalize() * rng.uniform(length / 10.0, length);
        let radius = [0.0, 2.5, 5.0][i % 3];
        let body = InBody {
            body: Body::Left,
            tip,
            port,
            radius,
        };
        let gap = Anatomy::gap(&organ, &body).expect("a gap");
        let d = brute_force(&tip, &port, &mesh);
        if d > radius + 1e-6 {
            // Clear of the surface: outside, or wholly inside the organ.
            // The facets cut the bumps by less than 1 mm; the inside test
            // is checked only clear of that.
            let within = depth_inside(&tip);
            if within.abs() > 1.0 {
                let want = if within > 0.0 {
                    inside += 1;
                    -(d + radius)
                } else {
                    apart += 1;
                    d - radius
                };
                assert!((gap - want).abs() < 1e-9, "{body:?}: {gap} vs {want}");
            } else {
                let either = [d - radius, -(d + radius)];
                assert!(
                    either.iter().any(|w| (gap - w).abs() < 1e-9),
                    "{body:?}: {gap} vs {either:?}"
                );
            }
        } else {
            touching += 1;
            assert!(gap <= 1e-9, "{body:?}: overlapping gives {gap}");
        }
    }
    assert!(
        apart > 60 && inside > 30 && touching > 30,
        "{apart} {inside} {touching}"
    );
}

#[test]
fn a_warm_start_gives_the_same_gaps_as_a_walk_from_the_root() {
    let (mesh, _) = bumpy();
    let anatomy = Anatomy {
        file: "a.toml".into(),
        regions: vec![region(&mesh)],
    };
    let mut rng = Rng::new(28);
    let mut warm = WarmStart::new();
    let mut stale = WarmStart::new();
    let centre = V::new(10.0, -5.0, -80.0);
    // Three shafts swept along a path in small steps (a cycle's motion),
    // through near, touching and far positions; a second start kept from
    // 500 cycles back.
    let start = [0; 3].map(|_| V::from([0; 3].map(|_| rng.uniform(-60.0, 60.0))));
    let step = [0; 3].map(|_| V::from([0; 3].map(|_| rng.uniform(-0.1, 0.1))));
    let bodies_at = |k: f64| {
        Body::ALL.map(|body| {
            let i = body as usize;
            let tip = centre + start[i] + step[i] * k;
            Some(InBody {
                body,
                tip,
                port: tip + V::new(0.3 * k.sin(), 0.2, 1.0).normalize() * 150.0,
                radius: 2.5,
            })
        })
    };
    for k in 0..1500 {
        let bodies = bodies_at(f64::from(k));
        let cold = anatomy.clearance(&bodies).expect("gaps");
        let hot = anatomy.clearance_warm(&bodies, &mut warm).expect("gaps");
        assert_eq!(cold, hot, "cycle {k}");
        if k % 500 == 0 {
            stale = warm.clone();
        }
        let old = anatomy
            .clearance_warm(&bodies, &mut stale.clone())
            .expect("gaps");
        assert_eq!(cold, old, "cycle {k}");
    }
}
