//! One trajectory sample: the paper's two phase-synchronised trapezoids
//! (`Multi::sample`, position, velocity and acceleration of both axes) and
//! the next sample of their 1 kHz sampler; the same as the platform state the
//! controller takes (`Reorientation::state_at`, the profile on the start
//! pose) and the next state of its 1 kHz sampler (what a control loop calls);
//! then a single jerk-limited axis. `f64` and `f32`.
//!
//! `cargo bench -p parasils --bench trajectory`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::traj::{DoubleS, JerkLimits, Motion, Sampler};

use common::paper_motion;

/// Benchmarks `id`: the next item of `sampler`, started again once it is over.
fn bench_next<T: Real, M: Motion<T> + Clone>(c: &mut Criterion, id: &str, sampler: Sampler<T, M>) {
    c.bench_function(id, |b| {
        let mut s = sampler.clone();
        b.iter(|| match s.next() {
            Some(x) => x,
            None => {
                s = sampler.clone();
                s.next().expect("samples")
            }
        })
    });
}

fn bench<T: Real>(c: &mut Criterion, name: &str) {
    let lit = T::lit;
    let motion = paper_motion::<T>();
    let profile = *motion.profile();
    c.bench_function(&format!("trajectory/multi_sample/{name}"), |b| {
        b.iter(|| profile.sample(black_box(lit(1.0))))
    });
    let rate = lit(1000.0);
    let id = format!("trajectory/sampler_next/{name}");
    bench_next(c, &id, profile.sampler(rate).expect("valid rate"));
    c.bench_function(&format!("trajectory/reorientation_state_at/{name}"), |b| {
        b.iter(|| motion.state_at(black_box(lit(1.0))))
    });
    let id = format!("trajectory/reorientation_sampler_next/{name}");
    bench_next(c, &id, motion.sampler(rate).expect("valid rate"));
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
