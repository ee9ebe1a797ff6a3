//! One perturbed robot along the paper's reorientation at 100 Hz (451
//! samples): the Monte Carlo's unit of work (`replay`: module 1's forward
//! kinematics from the previous pose and both instruments' at every
//! sample), beside the first-order model's prediction of the same robot
//! and the nominal trace's own cost. `cargo bench -p parasils-tolerance`.

use core::hint::black_box;
use criterion::{Criterion, criterion_group, criterion_main};
use parasils_sim::Scenario;
use parasils_tolerance::{Spec, Study, Trace};

fn paper_trace() -> Trace {
    let mut scenario = Scenario::paper();
    scenario.rate_hz = 100.0;
    Trace::from_scenario(scenario).expect("the paper's motion")
}

fn bench(c: &mut Criterion) {
    let study = Study::new(Spec::default(), paper_trace(), 0).expect("valid");
    let linear = study.linearisation().expect("regular");
    let mut g = c.benchmark_group("tolerance_paper_100hz");
    let mut i = 0u64;
    g.bench_function("replay_one_robot", |b| {
        b.iter(|| {
            i += 1;
            black_box(study.sample(black_box(i)))
        });
    });
    g.bench_function("first_order_one_robot", |b| {
        b.iter(|| {
            i += 1;
            black_box(linear.predict(&study.perturbation(black_box(i))))
        });
    });
    g.bench_function("nominal_trace", |b| b.iter(|| black_box(paper_trace())));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
