//! The teleoperation core's per-cycle cost (`parasils::Teleop::step`): both
//! hands at full scale and the view turning (the step at its setpoint and
//! its stop checked at two points: three controller steps), the same
//! watching the clearance, and a push held at a limit (the hold's search);
//! with `Controller::step` alone, measured in the same run, as the
//! yardstick. `f64` and `f32`.
//!
//! `cargo bench -p parasils --bench teleop`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::Supervisor;
use parasils::kin::{BodyGeometry, Controller, Pose, TipTargets};
use parasils::supervisor::{ClearanceThresholds, Margin};
use parasils::teleop::{
    BUTTON_ENABLE, CameraCommand, Command, HandCommand, Inputs, Teleop, TeleopParams,
};

const DT: f64 = 1e-3;

/// Both hands pushing `hand` (normalised axes), the camera turning at
/// `camera`, at time `t`.
fn inputs<T: Real>(t: T, hand: [f64; 6], camera: [f64; 6]) -> Inputs<T> {
    let mut i = Inputs::idle(t);
    for h in [&mut i.left, &mut i.right] {
        h.command = HandCommand::Rate(hand.map(T::lit));
        h.buttons = BUTTON_ENABLE;
    }
    i.camera.command = CameraCommand::Rate(camera.map(T::lit));
    i.camera.buttons = BUTTON_ENABLE;
    i
}

/// The core after `cycles` cycles of `hand` and `camera` from enable, and
/// the time of its next cycle.
fn warmed<T: Real>(
    mut core: Teleop<T>,
    cycles: u32,
    hand: [f64; 6],
    camera: [f64; 6],
) -> (Teleop<T>, T) {
    let dt = T::lit(DT);
    let _ = core.step(
        T::zero(),
        &Inputs::idle(T::zero()).with_command(Command::Enable),
    );
    let mut t = T::zero();
    for _ in 0..cycles {
        t += dt;
        let _ = core.step(t, &inputs(t, hand, camera));
    }
    (core, t + dt)
}

fn core<T: Real>(tips: TipTargets<T>, depth: f64) -> Teleop<T> {
    Teleop::new(
        Controller::paper(),
        Pose::paper_start(),
        tips,
        T::lit(depth),
        TeleopParams::assumed(),
    )
    .expect("the paper's start is reachable")
}

fn bench<T: Real>(c: &mut Criterion, name: &str) {
    let common::StepInputs {
        controller,
        mut tracker,
        tips,
        states,
    } = common::paper_step_inputs::<T>();
    let mut k = 0;
    c.bench_function(&format!("teleop/controller_step/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % 2;
            controller.step(black_box(&states[k]), black_box(&tips), &mut tracker)
        })
    });
    let hand = [0.8, -0.6, 0.5, 0.0, 0.0, 0.0];
    let turn = [0.0, 0.0, 0.0, 0.7, -0.7, 0.0];
    // Moving: both tips at speed, the view turning, nothing held.
    let (moving, t) = warmed(core::<T>(TipTargets::paper(), 60.0), 400, hand, turn);
    let next = inputs(t, hand, turn);
    c.bench_function(&format!("teleop/step_moving/{name}"), |b| {
        b.iter(|| {
            let mut copy = moving;
            copy.step(black_box(t), black_box(&next))
        })
    });
    // The same watching the three gaps (thresholds no gap reaches).
    let watched = core::<T>(TipTargets::paper(), 60.0)
        .with_clearance(
            BodyGeometry::assumed(),
            ClearanceThresholds {
                warn: T::lit(-1000.0),
                stop: T::lit(-1000.0),
            },
        )
        .expect("valid thresholds");
    let (watching, t) = warmed(watched, 400, hand, turn);
    c.bench_function(&format!("teleop/step_moving_clearance/{name}"), |b| {
        b.iter(|| {
            let mut copy = watching;
            copy.step(black_box(t), black_box(&next))
        })
    });
    // Held: pushing along the view into a qs3 stop threshold 5 mm inside
    // the start, reached and held (each cycle searches for the admissible fraction of its step).
    let start = core::<T>(TipTargets::paper(), 60.0);
    let mut probe = start;
    let margins = probe
        .step(T::zero(), &Inputs::idle(T::zero()))
        .expect("a finite time")
        .margins;
    let mut sup = Supervisor::<T>::default();
    for m in [Margin::LeftQs3Limits, Margin::RightQs3Limits] {
        sup.stop[m] = margins[m] - T::lit(5.0);
        sup.warn[m] = sup.stop[m];
    }
    let push = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let limited = start.with_supervisor(sup).expect("valid");
    // Braking into it: at 0.6 s the tips still close in at about 8 mm/s,
    // each cycle the latest stop that ends at the threshold.
    let (braking, t) = warmed(limited, 600, push, [0.0; 6]);
    let pushing = inputs(t, push, [0.0; 6]);
    c.bench_function(&format!("teleop/step_held_braking/{name}"), |b| {
        b.iter(|| {
            let mut copy = braking;
            copy.step(black_box(t), black_box(&pushing))
        })
    });
    // Resting at it (from 0.8 s).
    let (held, t) = warmed(limited, 2000, push, [0.0; 6]);
    let pushing = inputs(t, push, [0.0; 6]);
    c.bench_function(&format!("teleop/step_held/{name}"), |b| {
        b.iter(|| {
            let mut copy = held;
            copy.step(black_box(t), black_box(&pushing))
        })
    });
}

fn main() {
    let mut c = common::criterion();
    bench::<f64>(&mut c, "f64");
    bench::<f32>(&mut c, "f32");
    c.final_summary();
}
