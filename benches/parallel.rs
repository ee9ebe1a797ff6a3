//! Module 1, the parallel robot: forward kinematics by Newton's method
//! seeded with the previous pose of the motion (1 ms earlier at 1 kHz, the
//! way a controller tracks the measured actuators), and the closed-form
//! inverse kinematics for comparison. `f64` and `f32`, at `t = 1 s` of the
//! paper's motion.
//!
//! `cargo bench -p parasils --bench parallel`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::kin::ParallelRobot;

use common::paper_motion;

fn bench<T: Real>(c: &mut Criterion, name: &str) {
    let lit = T::lit;
    let motion = paper_motion::<T>();
    let robot = ParallelRobot::<T>::assumed();
    let pose = motion.state_at(lit(1.0)).pose;
    let previous = motion.state_at(lit(0.999)).pose;
    let q = robot.ik(&pose).expect("reachable");
    let fk = robot.fk(&q, &previous).expect("converges");
    println!(
        "parallel/fk/{name}: {} Newton steps from the pose 1 ms earlier, residual {:.1e}",
        fk.iterations,
        fk.residual.to_f64()
    );
    c.bench_function(&format!("parallel/fk_from_previous/{name}"), |b| {
        b.iter(|| robot.fk(black_box(&q), black_box(&previous)))
    });
    c.bench_function(&format!("parallel/ik/{name}"), |b| {
        b.iter(|| robot.ik(black_box(&pose)))
    });
}

fn main() {
    let mut c = common::criterion();
    bench::<f64>(&mut c, "f64");
    bench::<f32>(&mut c, "f32");
    c.final_summary();
}
