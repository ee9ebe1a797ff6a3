//! The follow law's per-cycle cost (`parasils::Follow::step`): held in its
//! dead zone, turning on a still target, and the worst case, a target that
//! moves by more than the retarget angle every cycle so that each cycle
//! solves the look-at and replans the online profile; then the average over
//! a wander of 5 s at 1 kHz (armed, turning, replanning and idle cycles
//! mixed), in `f64` and `f32`.
//!
//! `cargo bench -p parasils --bench follow`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::follow::{Follow, FollowParams, FollowPhase};
use parasils::kin::nalgebra::Vector3;
use parasils::kin::{Camera, Pose};

/// Two tips 20 mm apart around `(x, y, z)` (mm, fixed frame).
fn pair<T: Real>(x: f64, y: f64, z: f64) -> [Vector3<T>; 2] {
    [
        Vector3::new(T::lit(x - 10.0), T::lit(y), T::lit(z)),
        Vector3::new(T::lit(x + 10.0), T::lit(y), T::lit(z)),
    ]
}

fn bench<T: Real>(c: &mut Criterion, name: &str) {
    let pose = Pose::<T>::from_mm_deg(15.0, 20.0, -500.0, -8.0, 4.0, -60.0);
    let depth = T::lit(40.0);
    let fresh = Follow::new(Camera::assumed(), FollowParams::assumed(), pose, depth)
        .expect("valid parameters");
    let dt = T::lit(1e-3);
    // Idle: the tips near the view's centre, the law holding.
    let mut idle = fresh;
    let centre = pair::<T>(20.0, 10.0, -620.0);
    let _ = idle.step(T::zero(), &centre);
    c.bench_function(&format!("follow/idle/{name}"), |b| {
        b.iter(|| {
            let mut law = idle;
            law.step(black_box(dt), black_box(&centre))
        })
    });
    // Turning on a still target: far off-centre, past the dwell.
    let off = pair::<T>(60.0, 30.0, -600.0);
    let mut turning = fresh;
    let mut t = T::zero();
    while turning.phase() != FollowPhase::Recentring || t < T::lit(0.5) {
        t += dt;
        let _ = turning.step(t, &off);
    }
    c.bench_function(&format!("follow/turning/{name}"), |b| {
        b.iter(|| {
            let mut law = turning;
            law.step(black_box(t + dt), black_box(&off))
        })
    });
    // Replanning every cycle: the target 5 mm away from the one planned for.
    let moved = pair::<T>(65.0, 30.0, -600.0);
    c.bench_function(&format!("follow/replanning/{name}"), |b| {
        b.iter(|| {
            let mut law = turning;
            law.step(black_box(t + dt), black_box(&moved))
        })
    });
    // A wander: 5 s of tips moving at up to 20 mm/s across the view.
    let cycles = 5000;
    let wander: Vec<[Vector3<T>; 2]> = (0..cycles)
        .map(|k| {
            let s = k as f64 / 1000.0;
            pair(
                20.0 + 30.0 * (0.6 * s).sin(),
                10.0 + 20.0 * (0.9 * s).sin(),
                -620.0,
            )
        })
        .collect();
    c.bench_function(&format!("follow/wander_5000_cycles/{name}"), |b| {
        b.iter(|| {
            let mut law = fresh;
            let mut last = None;
            for (k, tips) in wander.iter().enumerate() {
                last = Some(law.step(T::from_index(k) * dt, black_box(tips)));
            }
            last
        })
    });
}

fn main() {
    let mut c = common::criterion();
    bench::<f64>(&mut c, "f64");
    bench::<f32>(&mut c, "f32");
    c.final_summary();
}
