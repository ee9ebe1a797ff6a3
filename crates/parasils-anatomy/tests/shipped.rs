//! The shipped example anatomy, `procedures/anatomy/demo.toml`, reads, and
//! its organ (`organ.stl`) is the ellipsoid the generator
//! (`examples/organ_stl.rs`) writes: same triangles, the vertices to
//! single precision, moved by the file's translation.

use parasils_anatomy::{Anatomy, Mesh, Shape};

#[test]
fn the_example_anatomy_reads_and_its_organ_is_the_generator_s_ellipsoid() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/anatomy/demo.toml"
    );
    let anatomy = Anatomy::load(path).expect("the shipped anatomy reads");
    let names: Vec<&str> = anatomy.regions.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["organ", "vessel", "kidney", "spine"]);
    let Shape::Mesh {
        mesh,
        solid,
        translation_mm,
        ..
    } = &anatomy.regions[0].shape
    else {
        panic!("the organ is a mesh");
    };
    assert!(*solid, "the organ is closed");
    let want = Mesh::ellipsoid([0.0; 3], [70.0, 45.0, 22.0], 16, 24).expect("valid");
    assert_eq!(mesh.triangles().len(), want.triangles().len());
    assert_eq!(mesh.triangles().len(), 720);
    // STL merges equal corners into one vertex each, in the order first
    // met; compare each triangle's corners.
    let corner = |m: &Mesh, t: usize, c: usize| m.vertices()[m.triangles()[t][c] as usize];
    for t in 0..720 {
        for c in 0..3 {
            let (got, w) = (corner(mesh, t, c), corner(&want, t, c));
            for k in 0..3 {
                let expected = f64::from(w[k] as f32) + translation_mm[k];
                assert!(
                    (got[k] - expected).abs() < 1e-9,
                    "triangle {t}: {got:?} vs {w:?}"
                );
            }
        }
    }
    let bytes = std::fs::metadata(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/anatomy/organ.stl"
    ))
    .expect("organ.stl")
    .len();
    assert!(bytes < 100_000, "{bytes} bytes");
}
