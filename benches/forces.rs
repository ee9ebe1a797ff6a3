//! The actuator forces of one control cycle, `parasils_kin::Controller::forces`:
//! both tips loaded (10 N-scale forces, fixed frame) and the payload's
//! Newton-Euler wrench (2 kg off the axis, an inertia tensor), through both
//! instrument modules' `J^T R^T F` and
//! module 1's `J^-T W` (a 6x6 elimination), at `t = 1 s` of the paper's
//! motion, `f64` and `f32`; and the step with its forces, as one cycle.
//!
//! `cargo bench -p parasils --bench forces`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::kin::nalgebra::Vector3;
use parasils::kin::{Loads, Payload};

use common::paper_step_inputs;

fn loads<T: Real>() -> Loads<T> {
    let v = |x: f64, y: f64, z: f64| Vector3::new(T::lit(x), T::lit(y), T::lit(z));
    Loads {
        payload: Payload::new(T::lit(2.0), v(5.0, -3.0, 40.0)).with_inertia(
            parasils::kin::nalgebra::Matrix3::from_diagonal(&v(2.0e4, 3.0e4, 1.5e4)),
        ),
        ..Loads::tips(v(5.0, -3.0, 8.0), v(-2.0, 4.0, 10.0))
    }
}

fn bench_forces<T: Real>(c: &mut Criterion, name: &str) {
    let common::StepInputs {
        controller,
        mut tracker,
        tips,
        states,
    } = paper_step_inputs::<T>();
    let loads = loads::<T>();
    let step = controller
        .step(&states[1], &tips, &mut tracker)
        .expect("regular");
    c.bench_function(&format!("forces/cycle/{name}"), |b| {
        b.iter(|| controller.forces(black_box(&step), black_box(&loads)))
    });
    let mut k = 0;
    c.bench_function(&format!("forces/step_and_forces/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 2;
            let step = controller.step(black_box(&states[k]), black_box(&tips), &mut tracker)?;
            controller.forces(&step, black_box(&loads))
        })
    });
}

fn main() {
    let mut c = common::criterion();
    bench_forces::<f64>(&mut c, "f64");
    bench_forces::<f32>(&mut c, "f32");
    c.final_summary();
}
