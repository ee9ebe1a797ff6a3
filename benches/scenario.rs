//! The paper's whole scenario in memory (4.5 s at 1 kHz, 4501 control
//! cycles; see `docs/model.md`, *Check values*):
//! - `loop`: the trajectory sampled at 1 kHz through `Controller::step`, as a
//!   controller runs it (`f64` and `f32`);
//! - `simulation`: `parasils simulate`'s engine (`parasils_sim::engine`),
//!   which also recomputes both tips by forward kinematics, into a sink that
//!   discards the samples;
//! - `csv`, `mcap`: the same into the simulation library's writers, in memory (no file
//!   system), to separate the writers' cost from the process's.
//!
//! `cargo bench -p parasils --bench scenario`; results in `BENCHMARKS.md`.

mod common;

use core::convert::Infallible;
use core::hint::black_box;
use std::io::Cursor;

use criterion::Criterion;
use parasils::Real;
use parasils::kin::{Controller, MarginTracker, TipTargets};
use parasils_sim::csv::CsvSink;
use parasils_sim::mcap::McapSink;
use parasils_sim::{Record, Scenario, Simulation, Sink};

use common::paper_motion;

/// Discards the samples (keeps the last time, so that nothing is optimised away).
struct Discard(f64);

impl Sink for Discard {
    type Error = Infallible;
    fn push(&mut self, record: &Record) -> Result<(), Infallible> {
        self.0 = black_box(record.t);
        Ok(())
    }
}

fn bench_loop<T: Real>(c: &mut Criterion, name: &str) {
    let motion = paper_motion::<T>();
    let tips = TipTargets::<T>::paper();
    let lit = T::lit;
    c.bench_function(&format!("scenario/loop/{name}"), |b| {
        b.iter(|| {
            let controller = Controller::<T>::paper();
            let mut tracker = MarginTracker::new();
            let mut n = 0usize;
            for s in black_box(motion).sampler(lit(1000.0)).expect("rate") {
                let out = controller
                    .step(&s.state, &tips, &mut tracker)
                    .expect("regular");
                black_box(&out);
                n += 1;
            }
            assert_eq!(n, 4501);
        })
    });
}

fn bench_engine(c: &mut Criterion) {
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    c.bench_function("scenario/simulation/f64", |b| {
        b.iter(|| {
            let mut sink = Discard(0.0);
            sim.run(&mut sink).expect("runs");
            sink.0
        })
    });
    c.bench_function("scenario/csv_in_memory/f64", |b| {
        b.iter(|| {
            let mut sink = CsvSink::new(Vec::with_capacity(4 << 20)).expect("header");
            sim.run(&mut sink).expect("runs");
            sink.finish().expect("flush").len()
        })
    });
    c.bench_function("scenario/mcap_in_memory/f64", |b| {
        b.iter(|| {
            let mut sink = McapSink::new(Cursor::new(Vec::with_capacity(4 << 20)), sim.scenario())
                .expect("header");
            sim.run(&mut sink).expect("runs");
            sink.finish().expect("finish").into_inner().len()
        })
    });
}

fn main() {
    let mut c = common::criterion().sample_size(20);
    bench_loop::<f64>(&mut c, "f64");
    bench_loop::<f32>(&mut c, "f32");
    bench_engine(&mut c);
    c.final_summary();
}
