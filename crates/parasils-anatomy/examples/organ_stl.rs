//! Writes the shipped example organ, `procedures/anatomy/organ.stl`: a
//! closed ellipsoid (`Mesh::ellipsoid`) as binary STL, in mm, centred at the
//! origin (the anatomy file places it with `translation_mm`).
//!
//! ```text
//! cargo run -p parasils-anatomy --example organ_stl -- procedures/anatomy/organ.stl
//! ```
//!
//! `tests/shipped.rs` reads the file back and compares it with the same
//! ellipsoid, so the file and this generator cannot drift apart.

use std::process::ExitCode;

use parasils_anatomy::Mesh;

/// The organ's semi-axes, mm, and its tessellation (720 triangles).
pub const RADII_MM: [f64; 3] = [70.0, 45.0, 22.0];
/// Bands from pole to pole.
pub const RINGS: u32 = 16;
/// Segments around the `z` axis.
pub const SEGMENTS: u32 = 24;

fn main() -> ExitCode {
    let Some(path) = std::env::args_os().nth(1) else {
        eprintln!("usage: organ_stl OUT.stl");
        return ExitCode::FAILURE;
    };
    let mesh = match Mesh::ellipsoid([0.0; 3], RADII_MM, RINGS, SEGMENTS) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("organ_stl: the ellipsoid {e}");
            return ExitCode::FAILURE;
        }
    };
    let v = mesh.vertices();
    let corner = |i: u32| {
        let p = v.get(i as usize).copied().unwrap_or_default();
        p.map(|c| c as f32)
    };
    let triangles = mesh.triangles().iter().map(|t| {
        let [a, b, c] = t.map(corner);
        let (u, w) = (
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
            [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
        );
        let n = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
            .sqrt()
            .max(f32::MIN_POSITIVE);
        stl_io::Triangle {
            normal: stl_io::Normal::new(n.map(|x| x / len)),
            vertices: [a, b, c].map(stl_io::Vertex::new),
        }
    });
    let written = std::fs::File::create(&path)
        .and_then(|f| stl_io::write_stl(&mut std::io::BufWriter::new(f), triangles));
    match written {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("organ_stl: {}: {e}", std::path::Path::new(&path).display());
            ExitCode::FAILURE
        }
    }
}
