//! The default reach map (181 x 181 cells at 0.5 deg, the paper's setup)
//! with and without the straight lines from the start, each with and
//! without the stiffness measure (both tips' deflection pressing with
//! 10 N down), on every core.

use core::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use parasils_reach::{ReachMap, ReachOptions};
use parasils_sim::Scenario;

fn default_map(c: &mut Criterion) {
    let scenario = Scenario::paper();
    let mut group = c.benchmark_group("reach_default");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(15));
    for (name, line, deflection_load_n) in [
        ("with_line", true, None),
        ("without_line", false, None),
        ("with_line_and_stiffness", true, Some([0.0, 0.0, -10.0])),
        (
            "without_line_with_stiffness",
            false,
            Some([0.0, 0.0, -10.0]),
        ),
    ] {
        let options = ReachOptions {
            line,
            deflection_load_n,
            ..ReachOptions::default()
        };
        group.bench_function(name, |b| {
            b.iter(|| ReachMap::compute(&scenario, &options).expect("map"));
        });
    }
    group.finish();
}

criterion_group!(benches, default_map);
criterion_main!(benches);
