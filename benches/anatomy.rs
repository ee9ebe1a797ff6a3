//! Forbidden regions per control cycle: a closed organ-like mesh of 10^5
//! triangles (an ellipsoid, `Mesh::ellipsoid(.., 201, 250)`) against the
//! three in-body segments (both shafts and the endoscope, 50 mm in) at
//! `t = 1 s` of the paper's motion, through parry's BVH; the organ 10 mm
//! below the lowest tip (`near`: the query must descend to the triangles
//! under the tips) and 100 mm below (`far`). The primitives alone for
//! comparison (a sphere, a rotated box). `f64`.
//!
//! Each mesh case twice: from nothing (`Anatomy::clearance`, every cycle a
//! walk from the hierarchy's root) and warm (`Anatomy::clearance_warm`, the
//! loop's `WarmStart` carried from one cycle to the next: the bench
//! alternates the instants `t = 0.999 s` and `t = 1 s`, so each cycle starts
//! from the triangles nearest 1 ms before).
//!
//! `cargo bench -p parasils --bench anatomy`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::kin::{Bodies, BodyGeometry};
use parasils_anatomy::{Anatomy, InBody, Mesh, Region, Shape, WarmStart};

use common::paper_step_inputs;

/// The three in-body segments at `t = 1 s` of the paper's motion, the
/// endoscope 50 mm in.
fn in_body() -> [Option<InBody>; 3] {
    in_body_at()[1]
}

/// The three in-body segments at `t = 0.999 s` and `t = 1 s`.
fn in_body_at() -> [[Option<InBody>; 3]; 2] {
    let common::StepInputs {
        controller,
        mut tracker,
        tips,
        states,
    } = paper_step_inputs::<f64>();
    states.map(|state| at(&controller, &state, &tips, &mut tracker))
}

fn at(
    controller: &parasils::kin::Controller<f64>,
    state: &parasils::kin::PlatformState<f64>,
    tips: &parasils::kin::TipTargets<f64>,
    tracker: &mut parasils::kin::MarginTracker<f64>,
) -> [Option<InBody>; 3] {
    let step = controller
        .step(state, tips, tracker)
        .expect("the paper's step is regular");
    let depth = 50.0;
    let bodies = Bodies::at(
        &BodyGeometry::assumed(),
        &step.frame,
        &controller.left,
        &step.left.q,
        &controller.right,
        &step.right.q,
        depth,
    )
    .expect("finite");
    InBody::of(&bodies, step.left.q.qs3, step.right.q.qs3, depth)
}

fn organ(below_mm: f64, bodies: &[Option<InBody>; 3]) -> Anatomy {
    let lowest = bodies
        .iter()
        .flatten()
        .map(|b| b.tip)
        .min_by(|a, b| a.z.total_cmp(&b.z))
        .expect("three bodies inside");
    let radii = [80.0, 50.0, 30.0];
    let centre = [lowest.x, lowest.y, lowest.z - below_mm - radii[2]];
    let mesh = Mesh::ellipsoid(centre, radii, 201, 250).expect("a valid ellipsoid");
    assert_eq!(mesh.triangles().len(), 100_000);
    let shape = Shape::Mesh {
        file: "organ.stl".into(),
        translation_mm: [0.0; 3],
        solid: mesh.is_closed(),
        mesh,
    };
    // Once per anatomy file, not per cycle: parry's hierarchy and the
    // cylinders of its nodes. Printed, not measured by criterion.
    let started = std::time::Instant::now();
    let region = Region::new("organ".into(), shape).expect("parry builds it");
    eprintln!(
        "anatomy/mesh_1e5: region built in {:.0} ms",
        started.elapsed().as_secs_f64() * 1e3
    );
    Anatomy {
        file: "bench.toml".into(),
        regions: vec![region],
    }
}

fn bench_mesh(c: &mut Criterion) {
    let cycles = in_body_at();
    let bodies = cycles[1];
    for (case, below) in [("near", 10.0), ("far", 100.0)] {
        let anatomy = organ(below, &bodies);
        let gap = anatomy
            .clearance(&bodies)
            .ok()
            .and_then(|g| g.min())
            .map(|g| g.gap_mm);
        eprintln!("anatomy/mesh_1e5/{case}: smallest gap {gap:?} mm");
        c.bench_function(&format!("anatomy/mesh_1e5_three_segments/{case}"), |b| {
            b.iter(|| black_box(&anatomy).clearance(black_box(&bodies)))
        });
        let mut warm = WarmStart::new();
        let mut cycle = 0;
        c.bench_function(
            &format!("anatomy/mesh_1e5_three_segments/{case}_warm"),
            |b| {
                b.iter(|| {
                    cycle ^= 1;
                    black_box(&anatomy).clearance_warm(black_box(&cycles[cycle]), &mut warm)
                })
            },
        );
    }
}

fn bench_primitives(c: &mut Criterion) {
    let bodies = in_body();
    let shapes = [
        (
            "sphere",
            Shape::Sphere {
                centre_mm: [0.0, 0.0, -700.0],
                radius_mm: 40.0,
            },
        ),
        (
            "box",
            Shape::Box {
                centre_mm: [0.0, 0.0, -700.0],
                half_extents_mm: [40.0, 30.0, 20.0],
                rotation_deg: [10.0, -5.0, 30.0],
            },
        ),
    ];
    for (name, shape) in shapes {
        let anatomy = Anatomy {
            file: "bench.toml".into(),
            regions: vec![Region::new(name.into(), shape).expect("valid")],
        };
        c.bench_function(&format!("anatomy/{name}_three_segments"), |b| {
            b.iter(|| black_box(&anatomy).clearance(black_box(&bodies)))
        });
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    bench_mesh(&mut c);
    bench_primitives(&mut c);
    c.final_summary();
}
