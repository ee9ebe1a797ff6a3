//! One trajectory sample: the paper's two phase-synchronised trapezoids
//! (`Multi::sample`, position, velocity and acceleration of both axes) and
//! the next sample of the 1 kHz sampler (what a control loop calls), then a
//! single jerk-limited axis. `f64` and `f32`.
//!
//! `cargo bench -p parasils --bench trajectory`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::traj::{DoubleS, JerkLimits, Motion};

use common::{Float, paper_motion};

fn bench<T: Float>(c: &mut Criterion, name: &str) {
    let lit = <T as parasils::kin::Real>::lit;
    let motion = paper_motion::<T>();
    c.bench_function(&format!("trajectory/multi_sample/{name}"), |b| {
        b.iter(|| motion.sample(black_box(lit(1.0))))
    });
    let sampler = motion.sampler(lit(1000.0)).expect("valid rate");
    c.bench_function(&format!("trajectory/sampler_next/{name}"), |b| {
        let mut s = sampler.clone();
        b.iter(|| match s.next() {
            Some(x) => x,
            None => {
                s = sampler.clone();
                s.next().expect("samples")
            }
        })
    });
    let ds = DoubleS::new(
        lit(0.0),
        lit(1.0),
        JerkLimits::new(lit(1.0), lit(1.0), lit(10.0)),
    )
    .expect("valid limits");
    c.bench_function(&format!("trajectory/double_s_sample/{name}"), |b| {
        b.iter(|| ds.sample(black_box(lit(0.7))))
    });
}

fn main() {
    let mut c = common::criterion();
    bench::<f64>(&mut c, "f64");
    bench::<f32>(&mut c, "f32");
    c.final_summary();
}
