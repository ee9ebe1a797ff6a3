//! The anatomy file and the gaps, against values derived by hand: point and
//! segment to a sphere and to a box in closed form, a mesh of a box against
//! the box's own distance, penetration depths, and every refusal of a bad
//! file naming the file, the region and the key.

use std::path::Path;

use nalgebra::Vector3;
use parasils_anatomy::{Anatomy, AnatomyError, Body, InBody, Mesh, MeshProblem, Region, Shape};
use parasils_io::Rng;

fn body(tip: [f64; 3], port: [f64; 3], radius: f64) -> InBody {
    InBody {
        body: Body::Left,
        tip: Vector3::from(tip),
        port: Vector3::from(port),
        radius,
    }
}

/// parry's GJK (box, mesh triangles against a capsule) stops within about
/// 1e-7 mm at these sizes; spheres and capsules are exact.
const GJK_MM: f64 = 1e-6;

fn region(shape: Shape) -> Region {
    Region::new("r".into(), shape).expect("a valid region")
}

/// The distance from `p` to the box of centre `c` and half-extents `h`
/// aligned with the axes: the norm of the excess along each axis, or minus
/// the smallest distance to a face when inside.
fn box_distance(p: [f64; 3], c: [f64; 3], h: [f64; 3]) -> f64 {
    let e: Vec<f64> = (0..3).map(|i| (p[i] - c[i]).abs() - h[i]).collect();
    let outside = e.iter().map(|x| x.max(0.0).powi(2)).sum::<f64>().sqrt();
    if outside > 0.0 {
        outside
    } else {
        e.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }
}

#[test]
fn a_segment_to_a_sphere_is_the_centre_s_distance_to_the_segment_minus_both_radii() {
    let sphere = region(Shape::Sphere {
        centre_mm: [20.0, 3.0, -5.0],
        radius_mm: 5.0,
    });
    // The closest point of the segment x = y = 0, z in [-10, 0] to the
    // centre is (0, 0, -5): distance sqrt(20^2 + 3^2).
    let b = body([0.0, 0.0, -10.0], [0.0, 0.0, 0.0], 2.5);
    let gap = Anatomy::gap(&sphere, &b).expect("gap");
    let truth = (400.0_f64 + 9.0).sqrt() - 5.0 - 2.5;
    assert!((gap - truth).abs() < 1e-9, "{gap} vs {truth}");
    // Beyond the segment's end: the end (0, 0, -10) is the closest point.
    let far = region(Shape::Sphere {
        centre_mm: [3.0, 4.0, -22.0],
        radius_mm: 1.0,
    });
    let truth = (9.0_f64 + 16.0 + 144.0).sqrt() - 1.0 - 2.5;
    let gap = Anatomy::gap(&far, &b).expect("gap");
    assert!((gap - truth).abs() < 1e-9, "{gap} vs {truth}");
}

#[test]
fn an_overlap_with_a_sphere_is_minus_its_depth() {
    let sphere = region(Shape::Sphere {
        centre_mm: [4.0, 0.0, -5.0],
        radius_mm: 3.0,
    });
    let b = body([0.0, 0.0, -10.0], [0.0, 0.0, 0.0], 2.0);
    let gap = Anatomy::gap(&sphere, &b).expect("gap");
    assert!((gap - (4.0 - 3.0 - 2.0)).abs() < 1e-9, "{gap}");
}

#[test]
fn a_point_to_a_box_and_a_rotated_box_match_the_closed_form() {
    let (c, h) = ([1.0, -2.0, 3.0], [2.0, 3.0, 4.0]);
    let aligned = region(Shape::Box {
        centre_mm: c,
        half_extents_mm: h,
        rotation_deg: [0.0; 3],
    });
    let mut rng = Rng::new(7);
    let mut checked = 0;
    for _ in 0..2000 {
        let p = [0; 3].map(|_| rng.uniform(-15.0, 15.0));
        let truth = box_distance(p, c, h);
        if truth <= 0.1 {
            continue;
        }
        let r = 0.05;
        let gap = Anatomy::gap(&aligned, &body(p, p, r)).expect("gap");
        assert!(
            (gap - (truth - r)).abs() < GJK_MM,
            "{p:?}: {gap} vs {}",
            truth - r
        );
        checked += 1;
    }
    assert!(checked > 1000);
    // Turned by phi = 90 deg about z, the box's own x lies along the fixed
    // y: seen from +x its face is at half-extent y = 3.
    let turned = region(Shape::Box {
        centre_mm: [10.0, 0.0, 5.0],
        half_extents_mm: [2.0, 3.0, 4.0],
        rotation_deg: [0.0, 0.0, 90.0],
    });
    let b = body([0.0, 0.0, 0.0], [0.0, 0.0, 10.0], 1.0);
    let gap = Anatomy::gap(&turned, &b).expect("gap");
    assert!((gap - (10.0 - 3.0 - 1.0)).abs() < GJK_MM, "{gap}");
    // Turned by psi = 90 deg about x, its own z lies along the fixed y and
    // its own y along z: from above (+z) its face is at half-extent y = 3.
    let tilted = region(Shape::Box {
        centre_mm: [0.0, 0.0, -20.0],
        half_extents_mm: [2.0, 3.0, 4.0],
        rotation_deg: [90.0, 0.0, 0.0],
    });
    let b = body([0.0, 0.0, -10.0], [0.0, 0.0, 0.0], 1.0);
    let gap = Anatomy::gap(&tilted, &b).expect("gap");
    assert!((gap - (10.0 - 3.0 - 1.0)).abs() < GJK_MM, "{gap}");
}

#[test]
fn a_segment_to_a_capsule_region_is_the_axes_distance_minus_both_radii() {
    // Two skew segments: x-axis at z = -30 and the body along z at x = y = 5.
    let capsule = region(Shape::Capsule {
        start_mm: [-50.0, 0.0, -30.0],
        end_mm: [50.0, 0.0, -30.0],
        radius_mm: 4.0,
    });
    let b = body([5.0, 7.0, -40.0], [5.0, 7.0, 0.0], 2.5);
    let gap = Anatomy::gap(&capsule, &b).expect("gap");
    assert!((gap - (7.0 - 4.0 - 2.5)).abs() < 1e-9, "{gap}");
}

/// The twelve triangles of the box `c`, `h`, counter-clockwise from outside.
fn box_mesh(c: [f64; 3], h: [f64; 3]) -> Mesh {
    let mut v = Vec::new();
    for i in 0..8 {
        let s = |bit: u32| if i & (1 << bit) == 0 { -1.0 } else { 1.0 };
        v.push([c[0] + s(0) * h[0], c[1] + s(1) * h[1], c[2] + s(2) * h[2]]);
    }
    let t = vec![
        [0, 2, 3],
        [0, 3, 1], // z-
        [4, 5, 7],
        [4, 7, 6], // z+
        [0, 1, 5],
        [0, 5, 4], // y-
        [2, 6, 7],
        [2, 7, 3], // y+
        [0, 4, 6],
        [0, 6, 2], // x-
        [1, 3, 7],
        [1, 7, 5], // x+
    ];
    Mesh::new(v, t).expect("a box mesh")
}

#[test]
fn a_mesh_of_a_box_gives_the_box_s_distance_outside_and_its_depth_inside() {
    let (c, h) = ([0.0, 5.0, -40.0], [10.0, 6.0, 8.0]);
    let mesh = box_mesh(c, h);
    assert!(mesh.is_closed());
    let m = region(Shape::Mesh {
        file: "box.stl".into(),
        translation_mm: [0.0; 3],
        mesh,
        solid: true,
    });
    let mut rng = Rng::new(11);
    let r = 0.5;
    let (mut outside, mut inside) = (0, 0);
    for _ in 0..4000 {
        let p = [0; 3].map(|_| rng.uniform(-25.0, 25.0));
        let p = [p[0], p[1] + 5.0, p[2] - 40.0];
        let d = box_distance(p, c, h);
        let gap = Anatomy::gap(&m, &body(p, p, r)).expect("gap");
        if d > r + 1e-6 {
            assert!((gap - (d - r)).abs() < GJK_MM, "{p:?}: {gap} vs {}", d - r);
            outside += 1;
        } else if d < -(r + 1e-6) {
            // Inside, clear of the surface: minus (depth of the point + r).
            assert!((gap - (d - r)).abs() < GJK_MM, "{p:?}: {gap} vs {}", d - r);
            inside += 1;
        } else {
            assert!(gap <= 1e-9, "{p:?}: touching gives {gap}");
        }
    }
    assert!(outside > 1000 && inside > 50, "{outside} {inside}");
}

#[test]
fn a_closed_ellipsoid_is_outward_and_its_inside_is_negative() {
    let mesh = Mesh::ellipsoid([0.0, 0.0, -50.0], [20.0, 20.0, 20.0], 24, 32).expect("mesh");
    assert_eq!(mesh.triangles().len(), 2 * 32 * 23);
    assert!(mesh.is_closed());
    let m = region(Shape::Mesh {
        file: "e.stl".into(),
        translation_mm: [0.0; 3],
        mesh,
        solid: true,
    });
    let gap_in = Anatomy::gap(&m, &body([0.0, 0.0, -50.0], [0.0, 0.0, -48.0], 1.0)).expect("gap");
    assert!(gap_in < -15.0, "{gap_in}");
    // Outside: the tessellated sphere lies within the true one, and beyond
    // its inscribed polyhedron's faces by at most the sagitta.
    let gap_out = Anatomy::gap(&m, &body([0.0, 0.0, 0.0], [0.0, 0.0, -10.0], 1.0)).expect("gap");
    assert!((gap_out - (40.0 - 20.0 - 1.0)).abs() < GJK_MM, "{gap_out}");
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

const TETRA_STL: &str = "solid t
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 10 0
vertex 10 0 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 10 0 0
vertex 0 0 10
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0 10
vertex 0 10 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 10 0 0
vertex 0 10 0
vertex 0 0 10
endloop
endfacet
endsolid t
";

#[test]
fn stl_and_obj_files_read_relative_to_the_anatomy_file_with_their_translation() {
    let dir = tempfile::tempdir().expect("dir");
    std::fs::create_dir(dir.path().join("meshes")).expect("mkdir");
    write(&dir.path().join("meshes"), "t.stl", TETRA_STL);
    write(
        &dir.path().join("meshes"),
        "t.obj",
        "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    );
    let file = write(
        dir.path(),
        "a.toml",
        "[[region]]\nname = \"stl\"\nshape = \"mesh\"\nfile = \"meshes/t.stl\"\ntranslation_mm = [0, 0, -100]\n\n[[region]]\nname = \"obj\"\nshape = \"mesh\"\nfile = \"meshes/t.obj\"\n",
    );
    let anatomy = Anatomy::load(&file).expect("loads");
    assert_eq!(anatomy.regions.len(), 2);
    for r in &anatomy.regions {
        assert_eq!(r.triangle_count(), 4);
        assert!(
            matches!(r.shape, Shape::Mesh { solid: true, .. }),
            "{}",
            r.name
        );
    }
    // The z = 0 face of the unmoved one, 3 mm below it.
    let below = body([1.0, 1.0, -3.0], [1.0, 1.0, -4.0], 0.0);
    let gap = Anatomy::gap(&anatomy.regions[1], &below).expect("gap");
    assert!((gap - 3.0).abs() < 1e-9, "{gap}");
    let below_moved = body([1.0, 1.0, -103.0], [1.0, 1.0, -104.0], 0.0);
    let gap = Anatomy::gap(&anatomy.regions[0], &below_moved).expect("gap");
    assert!((gap - 3.0).abs() < 1e-9, "{gap}");
}

fn refusal(text: &str) -> AnatomyError {
    let dir = tempfile::tempdir().expect("dir");
    write(
        dir.path(),
        "flat.stl",
        &TETRA_STL.replacen("vertex 0 10 0", "vertex 20 0 0", 1),
    );
    write(
        dir.path(),
        "nan.obj",
        "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n",
    );
    write(dir.path(), "empty.stl", "solid e\nendsolid e\n");
    let file = write(dir.path(), "a.toml", text);
    let e = Anatomy::load(&file).expect_err("refused");
    let message = e.to_string();
    assert!(message.contains("a.toml"), "{message}");
    e
}

#[test]
fn every_bad_file_is_refused_naming_the_file_the_region_and_the_key() {
    let key = |text: &str, region: &str, key: &str| match refusal(text) {
        AnatomyError::Key {
            region: r, key: k, ..
        } => {
            assert_eq!((r.as_str(), k.as_str()), (region, key), "{text}");
        }
        e => panic!("{text}: {e}"),
    };
    let sphere = "[[region]]\nname = \"kidney\"\nshape = \"sphere\"\n";
    key(&format!("{sphere}radius_mm = 5\n"), "kidney", "centre_mm");
    key(
        &format!("{sphere}centre_mm = [0, 0]\nradius_mm = 5\n"),
        "kidney",
        "centre_mm",
    );
    key(
        &format!("{sphere}centre_mm = [0, nan, 0]\nradius_mm = 5\n"),
        "kidney",
        "centre_mm",
    );
    key(
        &format!("{sphere}centre_mm = [0, 0, 0]\nradius_mm = -1\n"),
        "kidney",
        "radius_mm",
    );
    key(
        &format!("{sphere}centre_mm = [0, 0, 0]\nradius = 5\n"),
        "kidney",
        "radius",
    );
    key("[[region]]\nshape = \"sphere\"\n", "#1", "name");
    key("[[region]]\nname = \"x\"\nshape = \"cone\"\n", "x", "shape");
    key(
        "[[region]]\nname = \"b\"\nshape = \"box\"\ncentre_mm = [0, 0, 0]\nhalf_extents_mm = [1, 0, 1]\n",
        "b",
        "half_extents_mm",
    );
    key(
        &format!(
            "{sphere}centre_mm = [0, 0, 0]\nradius_mm = 5\n\n{sphere}centre_mm = [0, 0, 0]\nradius_mm = 5\n"
        ),
        "#2",
        "name",
    );
    let mesh = |file: &str| match refusal(&format!(
        "[[region]]\nname = \"liver\"\nshape = \"mesh\"\nfile = \"{file}\"\n"
    )) {
        AnatomyError::Mesh {
            region,
            mesh,
            problem,
            ..
        } => {
            assert_eq!(region, "liver");
            assert!(mesh.ends_with(file), "{mesh:?}");
            problem
        }
        e => panic!("{file}: {e}"),
    };
    assert_eq!(mesh("flat.stl"), MeshProblem::Degenerate { triangle: 0 });
    assert!(matches!(
        mesh("nan.obj"),
        MeshProblem::NonFinite { vertex: 2, .. }
    ));
    assert_eq!(mesh("empty.stl"), MeshProblem::Empty);
    assert!(matches!(mesh("missing.stl"), MeshProblem::Unreadable(_)));
    assert_eq!(mesh("liver.ply"), MeshProblem::UnknownFormat);
    assert!(matches!(
        refusal("region = 3\n"),
        AnatomyError::Syntax { .. }
    ));
    assert!(matches!(
        refusal("units = \"mm\"\n"),
        AnatomyError::Syntax { .. }
    ));
    assert!(matches!(
        refusal("[[region]\n"),
        AnatomyError::Syntax { .. }
    ));
    assert!(matches!(
        Anatomy::load("/nonexistent/a.toml"),
        Err(AnatomyError::Read { .. })
    ));
}

#[test]
fn a_body_that_is_not_finite_is_an_error_not_a_nan() {
    let sphere = region(Shape::Sphere {
        centre_mm: [0.0; 3],
        radius_mm: 1.0,
    });
    let e = Anatomy::gap(&sphere, &body([f64::NAN, 0.0, 0.0], [0.0; 3], 1.0)).expect_err("NaN");
    assert!(e.to_string().contains("left shaft"), "{e}");
}

#[test]
fn a_mesh_of_a_box_and_the_box_give_the_same_gap_to_random_shafts() {
    // Long, slanted segments, as shafts are: the mesh's own search (its
    // BVH bound and closed-form triangles) against parry's box distance.
    let (c, h) = ([5.0, -3.0, -60.0], [20.0, 12.0, 9.0]);
    let as_mesh = region(Shape::Mesh {
        file: "box.stl".into(),
        translation_mm: [0.0; 3],
        mesh: box_mesh(c, h),
        solid: true,
    });
    let as_box = region(Shape::Box {
        centre_mm: c,
        half_extents_mm: h,
        rotation_deg: [0.0; 3],
    });
    let mut rng = Rng::new(5);
    let mut apart = 0;
    for _ in 0..3000 {
        let tip = [0; 3].map(|_| rng.uniform(-60.0, 60.0));
        let tip = [tip[0], tip[1], tip[2] - 60.0];
        let port = [0; 3].map(|_| rng.uniform(-80.0, 80.0));
        let b = body(tip, [port[0], port[1], port[2] - 40.0], 2.5);
        let want = Anatomy::gap(&as_box, &b).expect("gap");
        let got = Anatomy::gap(&as_mesh, &b).expect("gap");
        if want > 1e-3 {
            // The box's side is GJK's, whose stop grows with the length of
            // the shaft (up to 160 mm here): 1e-5 mm.
            assert!((got - want).abs() < 1e-5, "{b:?}: {got} vs {want}");
            apart += 1;
        } else {
            assert!(got <= 1e-6, "{b:?}: overlapping gives {got}");
        }
    }
    assert!(apart > 1000, "{apart}");
}
