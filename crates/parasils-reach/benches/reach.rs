//! The default reach map (181 x 181 cells at 0.5 deg, the paper's setup)
//! with and without the straight lines from the start, on every core.

use core::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use parasils_reach::{ReachMap, ReachOptions};
use parasils_sim::Scenario;

fn default_map(c: &mut Criterion) {
    let scenario = Scenario::paper();
    let mut group = c.benchmark_group("reach_default");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(15));
    for (name, line) in [("with_line", true), ("without_line", false)] {
        let options = ReachOptions {
            line,
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
