//! The instrument IK and module 1's IK over a batch: the scalar loop
//! against each kernel level this CPU has, side by side (ns per row = the
//! time / 4096).
//!
//! `cargo bench -p parasils-batch --bench kernels`; results in BENCHMARKS.md.

use core::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use parasils_batch::{
    InstrumentIk, Level, Module1Ik, OnRowError, Strided, atan2_slice, sin_cos_slice,
};
use parasils_kin::{AssemblyMode, Instrument, ParallelRobot, Pose, Side};

const ROWS: usize = 4096;

/// Poses and tips around the paper's start pose and left tip (SplitMix-like
/// spread, deterministic).
fn inputs() -> (Vec<f64>, Vec<f64>) {
    let p0 = Pose::<f64>::paper_start().to_array();
    let tip0 = [50.0, -50.0, -620.0];
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let spread = [10.0, 10.0, 10.0, 0.1, 0.1, 0.1];
    let mut pose = Vec::with_capacity(6 * ROWS);
    let mut tip = Vec::with_capacity(3 * ROWS);
    for _ in 0..ROWS {
        for j in 0..6 {
            pose.push(p0[j] + spread[j] * next());
        }
        for t in tip0 {
            tip.push(t + 20.0 * next());
        }
    }
    (pose, tip)
}

fn instrument_ik(c: &mut Criterion) {
    let (pose, tip) = inputs();
    let module = Instrument::<f64>::paper(Side::Left);
    let mut group = c.benchmark_group("instrument_ik_4096_rows");
    group.throughput(Throughput::Elements(ROWS as u64));
    let mut out = vec![0.0; 3 * ROWS];
    let mut ok = vec![false; ROWS];
    for level in Level::supported() {
        let ik = InstrumentIk::new(module, AssemblyMode::A)
            .at_level(level)
            .expect("a supported level");
        group.bench_function(level.name(), |b| {
            b.iter(|| {
                ik.solve(
                    0..ROWS,
                    Strided::rows(black_box(&pose)),
                    Strided::rows(black_box(&tip)),
                    &mut out,
                    &mut ok,
                    OnRowError::Nan,
                )
            })
        });
    }
    group.finish();
}

fn module1_ik(c: &mut Criterion) {
    let (pose, _) = inputs();
    let mut group = c.benchmark_group("module1_ik_4096_rows");
    group.throughput(Throughput::Elements(ROWS as u64));
    let mut out = vec![0.0; 6 * ROWS];
    let mut ok = vec![false; ROWS];
    for level in Level::supported() {
        let ik = Module1Ik::new(ParallelRobot::assumed())
            .at_level(level)
            .expect("a supported level");
        group.bench_function(level.name(), |b| {
            b.iter(|| {
                ik.solve(
                    0..ROWS,
                    Strided::rows(black_box(&pose)),
                    &mut out,
                    &mut ok,
                    OnRowError::Nan,
                )
            })
        });
    }
    group.finish();
}

fn math(c: &mut Criterion) {
    let (pose, tip) = inputs();
    let x: Vec<f64> = pose.iter().take(ROWS).copied().collect();
    let y: Vec<f64> = tip.iter().take(ROWS).copied().collect();
    let mut group = c.benchmark_group("math_4096_values");
    group.throughput(Throughput::Elements(ROWS as u64));
    let (mut s, mut co) = (vec![0.0; ROWS], vec![0.0; ROWS]);
    for level in Level::supported() {
        group.bench_function(format!("sin_cos/{level}"), |b| {
            b.iter(|| sin_cos_slice(level, black_box(&x), &mut s, &mut co))
        });
        group.bench_function(format!("atan2/{level}"), |b| {
            b.iter(|| atan2_slice(level, black_box(&y), black_box(&x), &mut s))
        });
    }
    group.finish();
}

criterion_group!(benches, instrument_ik, module1_ik, math);
criterion_main!(benches);
