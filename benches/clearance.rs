//! Clearance per control cycle: the three surface gaps between the default
//! bodies (both instrument shafts and the endoscope, sizes assumed) at
//! `t = 1 s` of the paper's motion, from the capsules and from the step's
//! joints (the capsules built as well); and the kernel alone on one pair,
//! crossing and near-parallel. `f64` and `f32`.
//!
//! `cargo bench -p parasils --bench clearance`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::kin::nalgebra::Vector3;
use parasils::kin::{Bodies, BodyGeometry, Segment, segment_distance};

use common::paper_step_inputs;

fn bench_bodies<T: Real>(c: &mut Criterion, name: &str) {
    let common::StepInputs {
        controller,
        mut tracker,
        tips,
        states,
    } = paper_step_inputs::<T>();
    let step = controller
        .step(&states[1], &tips, &mut tracker)
        .expect("the paper's step is regular");
    let geometry = BodyGeometry::<T>::assumed();
    let depth = T::lit(50.0);
    let build = || {
        Bodies::at(
            black_box(&geometry),
            black_box(&step.frame),
            &controller.left,
            black_box(&step.left.q),
            &controller.right,
            black_box(&step.right.q),
            black_box(depth),
        )
    };
    let bodies = build().expect("finite");
    c.bench_function(&format!("clearance/three_gaps/{name}"), |b| {
        b.iter(|| black_box(&bodies).clearance())
    });
    c.bench_function(&format!("clearance/bodies_and_three_gaps/{name}"), |b| {
        b.iter(|| build().and_then(|bodies| bodies.clearance()))
    });
}

fn bench_kernel<T: Real>(c: &mut Criterion, name: &str) {
    let v = |x: f64, y: f64, z: f64| Vector3::new(T::lit(x), T::lit(y), T::lit(z));
    let a = Segment::new(v(0.0, 0.0, 0.0), v(100.0, 0.0, 0.0));
    let crossing = Segment::new(v(40.0, -30.0, 5.0), v(60.0, 30.0, -5.0));
    let near_parallel = Segment::new(v(10.0, 2.0, -1e-7), v(110.0, 2.0, 1e-7));
    for (case, b) in [("crossing", crossing), ("near_parallel", near_parallel)] {
        c.bench_function(
            &format!("clearance/segment_distance/{case}/{name}"),
            |bench| bench.iter(|| segment_distance(black_box(&a), black_box(&b))),
        );
    }
}

fn main() {
    let mut c = common::criterion();
    bench_bodies::<f64>(&mut c, "f64");
    bench_bodies::<f32>(&mut c, "f32");
    bench_kernel::<f64>(&mut c, "f64");
    bench_kernel::<f32>(&mut c, "f32");
    c.final_summary();
}
