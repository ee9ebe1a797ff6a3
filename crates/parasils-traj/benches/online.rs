//! Planning online motions: two axes from a moving state to rest at new
//! targets (time synchronisation, the general case; a straight line when the
//! velocity is along the displacement), one axis, and the controlled stop of
//! two axes. `f64` and `f32`.
//!
//! `cargo bench -p parasils-traj --bench online`; results in `BENCHMARKS.md`.

use core::hint::black_box;
use core::time::Duration;

use criterion::Criterion;
use parasils_traj::{Limits, OnlineMulti, OnlineTrapezoid, Real, State, Synchronization};

fn moving<T: Real>(position: f64, velocity: f64) -> State<T> {
    State {
        position: T::lit(position),
        velocity: T::lit(velocity),
        acceleration: T::zero(),
    }
}

fn bench<T: Real>(c: &mut Criterion, name: &str) {
    let deg = core::f64::consts::PI / 180.0;
    let limits = [Limits::<T>::paper(); 2];
    // The paper's reorientation 1.2 s in (psi and theta accelerating along
    // their straight line), retargeted across it.
    let turning = [
        moving::<T>(-12.84 * deg, 3.6 * deg),
        moving(13.6 * deg, 6.0 * deg),
    ];
    let target = [T::lit(5.0 * deg), T::lit(20.0 * deg)];
    c.bench_function(&format!("online/plan_two_axes_time/{name}"), |b| {
        b.iter(|| {
            OnlineMulti::new(
                black_box(turning),
                black_box(target),
                black_box(limits),
                Synchronization::Phase,
            )
        })
    });
    // Moving along the displacement: the straight line is kept.
    let along = [moving::<T>(0.0, 3.0 * deg), moving(0.0, 6.0 * deg)];
    let far = [T::lit(10.0 * deg), T::lit(20.0 * deg)];
    c.bench_function(&format!("online/plan_two_axes_line/{name}"), |b| {
        b.iter(|| {
            OnlineMulti::new(
                black_box(along),
                black_box(far),
                black_box(limits),
                Synchronization::Phase,
            )
        })
    });
    c.bench_function(&format!("online/plan_one_axis/{name}"), |b| {
        b.iter(|| OnlineTrapezoid::new(black_box(turning[0]), black_box(target[0]), limits[0]))
    });
    c.bench_function(&format!("online/stop_two_axes/{name}"), |b| {
        b.iter(|| OnlineMulti::stop(black_box(turning), black_box(limits)))
    });
    let plan =
        OnlineMulti::new(turning, target, limits, Synchronization::Phase).expect("valid problem");
    c.bench_function(&format!("online/sample_two_axes/{name}"), |b| {
        b.iter(|| plan.sample(black_box(T::lit(1.0))))
    });
}

fn main() {
    // These calls take nanoseconds and the machine is shared: many short
    // samples beat a few long ones.
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .configure_from_args();
    bench::<f64>(&mut c, "f64");
    bench::<f32>(&mut c, "f32");
    c.final_summary();
}
