//! The camera's per-cycle work: aiming the view at a point in closed form
//! (`Camera::look_at`) and where both tips fall in the image
//! (`Camera::project` twice, and one `Camera::projection` for both, as a
//! cycle places its points), in `f64` and `f32`, beside one control step of
//! the same robot, measured in the same run as a yardstick.
//!
//! `cargo bench -p parasils --bench camera`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::kin::{Camera, Controller, MarginTracker, PlatformState, Pose, TipTargets};

fn bench<T: Real>(c: &mut Criterion, name: &str) {
    let camera = Camera::<T>::assumed();
    let pose = Pose::<T>::paper_start();
    let depth = T::lit(60.0);
    let tips = TipTargets::<T>::paper();
    let target = (tips.left + tips.right) * T::lit(0.5);
    let frame = PlatformState::at_rest(pose)
        .frame()
        .expect("the paper's pose");
    c.bench_function(&format!("camera/look_at/{name}"), |b| {
        b.iter(|| camera.look_at(black_box(&pose), black_box(depth), black_box(&target)))
    });
    c.bench_function(&format!("camera/project_both_tips/{name}"), |b| {
        b.iter(|| {
            let f = black_box(&frame);
            (
                camera.project(f, depth, black_box(&tips.left)),
                camera.project(f, depth, black_box(&tips.right)),
            )
        })
    });
    c.bench_function(&format!("camera/look_at_and_project/{name}"), |b| {
        b.iter(|| {
            let aim = camera.look_at(black_box(&pose), depth, black_box(&target));
            let f = black_box(&frame);
            (
                aim,
                camera.project(f, depth, &tips.left),
                camera.project(f, depth, &tips.right),
            )
        })
    });
    c.bench_function(&format!("camera/look_at_and_projection/{name}"), |b| {
        b.iter(|| {
            let aim = camera.look_at(black_box(&pose), depth, black_box(&target));
            let image = camera.projection(black_box(&frame), depth);
            (aim, image.project(&tips.left), image.project(&tips.right))
        })
    });
    let controller = Controller::<T>::paper();
    let state = PlatformState::at_rest(pose);
    c.bench_function(&format!("camera/yardstick_control_step/{name}"), |b| {
        b.iter(|| {
            controller.step(
                black_box(&state),
                black_box(&tips),
                &mut MarginTracker::new(),
            )
        })
    });
}

fn main() {
    let mut c = common::criterion();
    bench::<f64>(&mut c, "f64");
    bench::<f32>(&mut c, "f32");
    c.final_summary();
}
