//! One perturbed robot along the paper's reorientation at 100 Hz (451
//! samples): the Monte Carlo's unit of work, the study's replay (module 1's
//! forward kinematics by the chord method from the nominal Jacobians, both
//! instruments' at every sample) beside the reference replay (Newton's
//! method from the previous pose at every sample) on the same robots, the
//! first-order model's prediction of the same robot and the nominal
//! trace's own cost. `cargo bench -p parasils-tolerance`; for a whole study
//! both ways, `--example replay_speed`.

use core::hint::black_box;
use criterion::{Criterion, criterion_group, criterion_main};
use parasils_sim::Scenario;
use parasils_tolerance::{Spec, Study, Trace, replay};

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
    let mut k = 0u64;
    g.bench_function("replay_one_robot_newton_reference", |b| {
        b.iter(|| {
            k += 1;
            black_box(replay(&study.robot(black_box(k)), study.trace()))
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
