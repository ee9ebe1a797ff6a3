//! Instruction counts of the hot paths, repeatable on a shared machine where
//! times are noisy: `cargo bench -p parasils --bench instructions` runs each
//! kernel below 1000 times under `valgrind --tool=callgrind`, counting only
//! inside the kernel's never-inlined wrapper, and prints the instructions per
//! call (x86-64, the same inputs as the criterion benches: `t = 1 s` of the
//! paper's motion). Without valgrind it says so and exits.
//!
//! Instruction counts find where the work is; they do not rank code whose
//! time is the latency of divisions and square roots (module 1's Jacobi
//! SVD): there the criterion medians decide. `BENCHMARKS.md` has both.

mod common;

use core::hint::black_box;
use std::process::Command;

use parasils::Reorientation;
use parasils::kin::{
    Actuators, AssemblyMode, Bodies, BodyGeometry, Clearance, ControlStep, Controller, FkSolution,
    InstrumentSolution, Joints, MarginTracker, ParallelSolution, PlatformFrame, PlatformState,
    Pose, TipMotion, TipTargets,
};
use parasils::traj::{Multi, State, Synchronization};
use parasils::{OnlineController, Setpoint};

use common::{paper_motion, paper_online, paper_online_watching, paper_step_inputs, retarget};

/// The kernels, by name: what each call does.
const KERNELS: [(&str, &str); 17] = [
    (
        "step_f64",
        "Controller::step (from the step 1 ms earlier), f64",
    ),
    (
        "step_f32",
        "Controller::step (from the step 1 ms earlier), f32",
    ),
    (
        "frame_f64",
        "PlatformState::frame (rotation, omega, alpha), f64",
    ),
    (
        "module1_solve_f64",
        "ParallelRobot::solve (IK, rates, margins by the full SVD), f64",
    ),
    (
        "module1_solve_tracking_f64",
        "ParallelRobot::solve_tracking (the margin from 1 ms earlier), f64",
    ),
    (
        "instrument_solve_f64",
        "Instrument::solve (IK, rates, margins), f64",
    ),
    (
        "instrument_ik_f64",
        "Instrument::ik from the Euler angles, f64",
    ),
    (
        "instrument_ik_local_f64",
        "Instrument::ik_local (module frame), f64",
    ),
    (
        "module1_fk_f64",
        "ParallelRobot::fk from the pose 1 ms earlier, f64",
    ),
    (
        "online_tick_f64",
        "OnlineController::tick (step and supervisor, from 1 ms earlier), f64",
    ),
    (
        "online_tick_f32",
        "OnlineController::tick (step and supervisor, from 1 ms earlier), f32",
    ),
    (
        "online_tick_clearance_f64",
        "OnlineController::tick watching the clearance (the three gaps, checked ahead), f64",
    ),
    (
        "online_tick_clearance_f32",
        "OnlineController::tick watching the clearance (the three gaps, checked ahead), f32",
    ),
    (
        "clearance_f64",
        "Bodies::at and Bodies::clearance (the three capsule gaps of a cycle), f64",
    ),
    (
        "online_command_f64",
        "OnlineController::command while turning (a two-axis online plan), f64",
    ),
    ("trajectory_sample_f64", "Multi::sample, 2 trapezoids, f64"),
    (
        "reorientation_state_f64",
        "Reorientation::state_at (the same, on the start pose), f64",
    ),
];

#[inline(never)]
fn kernel_step_f64(
    c: &Controller<f64>,
    s: &PlatformState<f64>,
    t: &TipTargets<f64>,
    tracker: &mut MarginTracker<f64>,
) -> Option<ControlStep<f64>> {
    c.step(s, t, tracker).ok()
}

#[inline(never)]
fn kernel_step_f32(
    c: &Controller<f32>,
    s: &PlatformState<f32>,
    t: &TipTargets<f32>,
    tracker: &mut MarginTracker<f32>,
) -> Option<ControlStep<f32>> {
    c.step(s, t, tracker).ok()
}

#[inline(never)]
fn kernel_frame_f64(s: &PlatformState<f64>) -> Option<PlatformFrame<f64>> {
    s.frame().ok()
}

#[inline(never)]
fn kernel_module1_solve_f64(
    c: &Controller<f64>,
    f: &PlatformFrame<f64>,
) -> Option<ParallelSolution<f64>> {
    c.module1.solve(f).ok()
}

#[inline(never)]
fn kernel_module1_solve_tracking_f64(
    c: &Controller<f64>,
    f: &PlatformFrame<f64>,
    tracker: &mut MarginTracker<f64>,
) -> Option<ParallelSolution<f64>> {
    c.module1.solve_tracking(f, tracker).ok()
}

#[inline(never)]
fn kernel_instrument_solve_f64(
    c: &Controller<f64>,
    f: &PlatformFrame<f64>,
    tip: &TipMotion<f64>,
) -> Option<InstrumentSolution<f64>> {
    c.left.solve(f, tip, AssemblyMode::A).ok()
}

#[inline(never)]
fn kernel_instrument_ik_f64(
    c: &Controller<f64>,
    p: &Pose<f64>,
    t: &TipTargets<f64>,
) -> Option<Joints<f64>> {
    c.left.ik(p, &t.left, AssemblyMode::A).ok()
}

#[inline(never)]
fn kernel_instrument_ik_local_f64(
    c: &Controller<f64>,
    local: &parasils::kin::nalgebra::Vector3<f64>,
) -> Option<Joints<f64>> {
    c.left.ik_local(local, AssemblyMode::A).ok()
}

#[inline(never)]
fn kernel_module1_fk_f64(
    c: &Controller<f64>,
    q: &Actuators<f64>,
    guess: &Pose<f64>,
) -> Option<FkSolution<f64>> {
    c.module1.fk(q, guess).ok()
}

#[inline(never)]
fn kernel_online_tick_f64(o: &mut OnlineController<f64>, t: f64) -> Option<Setpoint<f64>> {
    o.tick(t).ok()
}

#[inline(never)]
fn kernel_online_tick_f32(o: &mut OnlineController<f32>, t: f32) -> Option<Setpoint<f32>> {
    o.tick(t).ok()
}

#[inline(never)]
fn kernel_online_tick_clearance_f64(
    o: &mut OnlineController<f64>,
    t: f64,
) -> Option<Clearance<f64>> {
    // The tick's gaps, so that this wrapper is not folded into
    // `kernel_online_tick_f64` (the same code otherwise).
    o.tick(t).ok()?.clearance
}

#[inline(never)]
fn kernel_online_tick_clearance_f32(
    o: &mut OnlineController<f32>,
    t: f32,
) -> Option<Clearance<f32>> {
    // The tick's gaps, so that this wrapper is not folded into
    // `kernel_online_tick_f32` (the same code otherwise).
    o.tick(t).ok()?.clearance
}

#[inline(never)]
fn kernel_clearance_f64(
    c: &Controller<f64>,
    step: &ControlStep<f64>,
    bodies: &BodyGeometry<f64>,
) -> Option<Clearance<f64>> {
    Bodies::at(
        bodies,
        &step.frame,
        &c.left,
        &step.left.q,
        &c.right,
        &step.right.q,
        0.0,
    )
    .ok()?
    .clearance()
    .ok()
}

#[inline(never)]
fn kernel_online_command_f64(
    o: &mut OnlineController<f64>,
    t: f64,
    goal: [f64; 2],
) -> Option<Synchronization> {
    o.command(t, goal).ok()
}

#[inline(never)]
fn kernel_trajectory_sample_f64(m: &Multi<f64, 2>, t: f64) -> [State<f64>; 2] {
    m.sample(t)
}

#[inline(never)]
fn kernel_reorientation_state_f64(m: &Reorientation<f64>, t: f64) -> PlatformState<f64> {
    m.state_at(t)
}

/// Runs kernel `name` `n` times.
fn run(name: &str, n: usize) {
    let common::StepInputs {
        controller: c,
        tracker: mut tracker64,
        tips,
        states,
    } = paper_step_inputs::<f64>();
    let common::StepInputs {
        controller: c32,
        tracker: mut tracker32,
        tips: tips32,
        states: states32,
    } = paper_step_inputs::<f32>();
    let state = states[1];
    let frame = state.frame().expect("finite");
    let frames = states.map(|s| s.frame().expect("finite"));
    let mut tracker = tracker64;
    let tip = TipMotion::still(tips.left);
    let local = c
        .left
        .tip_to_local(&state.pose, &tips.left)
        .expect("finite");
    let motion = paper_motion::<f64>();
    let previous = motion.state_at(0.999).pose;
    let q = c.module1.ik(&state.pose).expect("reachable");
    // The online controller at 0.999 s: each call works on a copy (its clock
    // never runs backwards), made outside the kernel.
    let online = paper_online::<f64>();
    let online32 = paper_online::<f32>();
    let watching = paper_online_watching::<f64>();
    let watching32 = paper_online_watching::<f32>();
    let bodies = BodyGeometry::<f64>::assumed();
    let step = c
        .step(&state, &tips, &mut MarginTracker::new())
        .expect("regular");
    let goal = retarget::<f64>();
    for i in 0..n {
        // The steps alternate t = 1 s and t = 0.999 s (see `paper_step_inputs`).
        let k = (i + 1) % 2;
        match name {
            "step_f64" => drop(black_box(kernel_step_f64(
                black_box(&c),
                black_box(&states[k]),
                black_box(&tips),
                black_box(&mut tracker64),
            ))),
            "step_f32" => drop(black_box(kernel_step_f32(
                black_box(&c32),
                black_box(&states32[k]),
                black_box(&tips32),
                black_box(&mut tracker32),
            ))),
            "module1_solve_tracking_f64" => drop(black_box(kernel_module1_solve_tracking_f64(
                black_box(&c),
                black_box(&frames[k]),
                black_box(&mut tracker),
            ))),
            "frame_f64" => drop(black_box(kernel_frame_f64(black_box(&state)))),
            "module1_solve_f64" => drop(black_box(kernel_module1_solve_f64(
                black_box(&c),
                black_box(&frame),
            ))),
            "instrument_solve_f64" => drop(black_box(kernel_instrument_solve_f64(
                black_box(&c),
                black_box(&frame),
                black_box(&tip),
            ))),
            "instrument_ik_f64" => drop(black_box(kernel_instrument_ik_f64(
                black_box(&c),
                black_box(&state.pose),
                black_box(&tips),
            ))),
            "instrument_ik_local_f64" => drop(black_box(kernel_instrument_ik_local_f64(
                black_box(&c),
                black_box(&local),
            ))),
            "module1_fk_f64" => drop(black_box(kernel_module1_fk_f64(
                black_box(&c),
                black_box(&q),
                black_box(&previous),
            ))),
            "online_tick_f64" => {
                let mut o = black_box(online);
                let _ = black_box(kernel_online_tick_f64(&mut o, black_box(1.0)));
            }
            "online_tick_f32" => {
                let mut o = black_box(online32);
                let _ = black_box(kernel_online_tick_f32(&mut o, black_box(1.0)));
            }
            "online_tick_clearance_f64" => {
                let mut o = black_box(watching);
                let _ = black_box(kernel_online_tick_clearance_f64(&mut o, black_box(1.0)));
            }
            "online_tick_clearance_f32" => {
                let mut o = black_box(watching32);
                let _ = black_box(kernel_online_tick_clearance_f32(&mut o, black_box(1.0)));
            }
            "clearance_f64" => drop(black_box(kernel_clearance_f64(
                black_box(&c),
                black_box(&step),
                black_box(&bodies),
            ))),
            "online_command_f64" => {
                let mut o = black_box(online);
                let _ = black_box(kernel_online_command_f64(
                    &mut o,
                    black_box(1.0),
                    black_box(goal),
                ));
            }
            "trajectory_sample_f64" => drop(black_box(kernel_trajectory_sample_f64(
                black_box(motion.profile()),
                black_box(1.0),
            ))),
            "reorientation_state_f64" => drop(black_box(kernel_reorientation_state_f64(
                black_box(&motion),
                black_box(1.0),
            ))),
            _ => {}
        }
    }
}

/// `totals:` of a callgrind output file.
fn totals(path: &std::path::Path) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    text.lines()
        .find_map(|l| {
            l.strip_prefix("totals:")
                .or_else(|| l.strip_prefix("summary:"))
        })
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--kernel") {
        let name = args.get(i + 1).map_or("", String::as_str);
        let n = args.get(i + 2).and_then(|v| v.parse().ok()).unwrap_or(1000);
        run(name, n);
        return;
    }
    // `cargo bench -- --list` / `--test` (and `cargo test --benches`): nothing to measure.
    if args.iter().any(|a| a == "--list" || a == "--test") {
        return;
    }
    let exe = std::env::current_exe().expect("the bench's own path");
    if Command::new("valgrind").arg("--version").output().is_err() {
        println!("instructions: valgrind not found (apt-get install valgrind); nothing measured");
        return;
    }
    let n = 1000u64;
    let dir = std::env::temp_dir();
    println!("instructions per call (callgrind, {n} calls each):");
    for (name, what) in KERNELS {
        let out = dir.join(format!(
            "parasils-callgrind-{}-{name}.out",
            std::process::id()
        ));
        let status = Command::new("valgrind")
            .arg("--tool=callgrind")
            .arg(format!("--callgrind-out-file={}", out.display()))
            .arg(format!("--toggle-collect=instructions::kernel_{name}"))
            .arg(&exe)
            .args(["--kernel", name, &n.to_string()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status();
        match (status, totals(&out)) {
            (Ok(s), Some(total)) if s.success() => {
                println!("  {name:24} {:>7} ({what})", total / n);
            }
            _ => println!("  {name:24} (failed) ({what})"),
        }
        let _ = std::fs::remove_file(&out);
    }
}
