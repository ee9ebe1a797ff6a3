//! The motion-type-4 control step, `parasils_kin::Controller::step`: the
//! platform frame (rotation, angular velocity and acceleration), module 1's
//! six actuators with rates, accelerations and margins (the parallel margin's
//! 6x6 singular values included), and both instrument modules' joints with
//! rates, accelerations and margins. `f64` and `f32`, at `t = 1 s` of the
//! paper's motion; the online controller's cycle around it (the step and the
//! margin supervisor) and a new goal while turning; then the step's parts one
//! by one, to show where the time goes.
//!
//! `cargo bench -p parasils --bench controller`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::{BatchSize, Criterion};
use parasils::kin::{TipMotion, frame::PlatformFrame};

use common::paper_step_inputs;
use parasils::Real;

fn bench_step<T: Real>(c: &mut Criterion, name: &str) {
    let common::StepInputs {
        controller,
        mut tracker,
        tips,
        states,
    } = paper_step_inputs::<T>();
    let mut k = 0;
    c.bench_function(&format!("controller/step/{name}"), |b| {
        b.iter(|| {
            // t = 1 s and t = 0.999 s in turn: every margin from the last one's direction.
            k = (k + 1) % 2;
            controller.step(black_box(&states[k]), black_box(&tips), &mut tracker)
        })
    });
}

/// The online controller's cycle: the step above and the margin supervisor
/// (and the platform state of the active motion), at `t = 1 s` from the tick
/// 1 ms earlier; and a new goal while turning (one two-axis online plan).
/// `online_tick`: each call runs on a fresh copy (the controller's clock
/// never runs backwards), made outside the timing, so that each tick reads
/// a controller of 3 KB that is not in the cache; `online_loop`: the ticks
/// of a control loop, one controller ticking every 1 ms.
fn bench_online<T: Real>(c: &mut Criterion, name: &str) {
    let online = common::paper_online::<T>();
    let t = T::lit(1.0);
    c.bench_function(&format!("controller/online_tick/{name}"), |b| {
        b.iter_batched_ref(|| online, |o| o.tick(black_box(t)), BatchSize::SmallInput)
    });
    // As a control loop runs it: one controller, hot in the cache, ticking
    // the paper's turn every 1 ms from t = 1 s (no command, no replanning);
    // a fresh copy every 100 ticks (its cost shared by them), so that
    // every tick is within 0.1 s of t = 1 s.
    c.bench_function(&format!("controller/online_loop/{name}"), |b| {
        b.iter_custom(|iters| {
            let mut o = online;
            let begin = std::time::Instant::now();
            for k in 0..iters {
                let j = k % 100;
                if j == 0 {
                    o = black_box(online);
                }
                let _ = black_box(o.tick(black_box(t + T::lit(j as f64 * 1e-3))));
            }
            begin.elapsed()
        })
    });
    let goal = common::retarget::<T>();
    c.bench_function(&format!("controller/online_command/{name}"), |b| {
        b.iter_batched_ref(
            || online,
            |o| o.command(black_box(t), black_box(goal)),
            BatchSize::SmallInput,
        )
    });
}

fn bench_parts<T: Real>(c: &mut Criterion, name: &str) {
    let common::StepInputs {
        controller,
        mut tracker,
        tips,
        states,
    } = paper_step_inputs::<T>();
    let state = states[1];
    let frame = state.frame().expect("finite");
    c.bench_function(&format!("controller/part/frame/{name}"), |b| {
        b.iter(|| PlatformFrame::new(black_box(&state)))
    });
    c.bench_function(&format!("controller/part/module1_solve/{name}"), |b| {
        b.iter(|| controller.module1.solve(black_box(&frame)))
    });
    let frames = states.map(|s| s.frame().expect("finite"));
    let mut k = 0;
    c.bench_function(
        &format!("controller/part/module1_solve_tracking/{name}"),
        |b| {
            b.iter(|| {
                k = (k + 1) % 2;
                controller
                    .module1
                    .solve_tracking(black_box(&frames[k]), &mut tracker)
            })
        },
    );
    c.bench_function(&format!("controller/part/module1_margins/{name}"), |b| {
        b.iter(|| controller.module1.margins(black_box(&state.pose)))
    });
    c.bench_function(&format!("controller/part/module1_ik/{name}"), |b| {
        b.iter(|| controller.module1.ik(black_box(&state.pose)))
    });
    let tip = TipMotion::still(tips.left);
    c.bench_function(&format!("controller/part/instrument_solve/{name}"), |b| {
        b.iter(|| {
            controller
                .left
                .solve(black_box(&frame), black_box(&tip), controller.modes[0])
        })
    });
}

fn main() {
    let mut c = common::criterion();
    bench_step::<f64>(&mut c, "f64");
    bench_step::<f32>(&mut c, "f32");
    bench_online::<f64>(&mut c, "f64");
    bench_online::<f32>(&mut c, "f32");
    bench_parts::<f64>(&mut c, "f64");
    bench_parts::<f32>(&mut c, "f32");
    c.final_summary();
}
