//! The cost of a control cycle: SysTick read around calls under QEMU's
//! `-icount`, turned into instructions, and the breakdown of a cycle by part.

use core::hint::black_box;
use core::sync::atomic::{Ordering, compiler_fence};

use cortex_m::peripheral::SYST;

use parasils::kin::PlatformState;
use parasils::kin::nalgebra::ComplexField;
use parasils::supervisor::Margins;

use crate::out::Out;
use crate::{reference, scenario};

/// SysTick runs at the board's 25 MHz core clock; QEMU with `-icount shift=6`
/// advances its virtual clock by 64 ns per instruction: 1.6 ticks per
/// instruction, calibrated at run time ([`calibrate`]).
pub const SYST_RELOAD: u32 = 0x00FF_FFFF;

pub fn systick() -> u32 {
    compiler_fence(Ordering::SeqCst);
    let v = SYST::get_current();
    compiler_fence(Ordering::SeqCst);
    v
}

pub fn elapsed(from: u32, to: u32) -> u32 {
    from.wrapping_sub(to) & SYST_RELOAD
}

/// SysTick ticks for 1000 instructions: a block of 1000 `nop`s timed, minus
/// the same timing with nothing in between.
#[inline(never)]
pub fn calibrate() -> u32 {
    let a = SYST::get_current();
    // SAFETY: no-ops.
    unsafe {
        core::arch::asm!(
            ".rept 1000",
            "nop",
            ".endr",
            options(nomem, nostack, preserves_flags)
        )
    };
    let b = SYST::get_current();
    let c = SYST::get_current();
    let d = SYST::get_current();
    elapsed(a, b).wrapping_sub(elapsed(c, d))
}

/// Min, sum and max of a cost in SysTick ticks.
pub struct Cost {
    pub min: u32,
    pub max: u32,
    pub sum: u64,
    pub n: u64,
}

impl Cost {
    pub const fn new() -> Self {
        Self {
            min: u32::MAX,
            max: 0,
            sum: 0,
            n: 0,
        }
    }
    pub fn add(&mut self, ticks: u32) {
        self.min = self.min.min(ticks);
        self.max = self.max.max(ticks);
        self.sum += u64::from(ticks);
        self.n += 1;
    }
}

/// Ticks to instructions, with the calibration (ticks per 1000 instructions).
pub fn instructions(ticks: u64, calibration: u32) -> u64 {
    (ticks * 1000 + u64::from(calibration) / 2)
        .checked_div(u64::from(calibration))
        .unwrap_or(0)
}

/// Where a cycle's instructions go: the run replayed, each part timed alone
/// (mean instructions per cycle; the plans per command).
pub fn breakdown(out: &mut Out, calibration: u32) {
    let Ok(mut online) = scenario::online::<f32>() else {
        return;
    };
    let orders = scenario::orders::<f32>();
    let c = *online.controller();
    let supervisor = *online.supervisor();
    let tips = *online.tips();
    // Module 1's margin tracked from cycle to cycle, seeded as
    // `OnlineController::new` does.
    let mut tracker = parasils::kin::MarginTracker::new();
    let mut parts = [
        Cost::new(),
        Cost::new(),
        Cost::new(),
        Cost::new(),
        Cost::new(),
        Cost::new(),
        Cost::new(),
        Cost::new(),
        Cost::new(),
    ];
    let [
        plan,
        traj,
        frame_cost,
        module1,
        instruments,
        fk,
        watch,
        trig,
        forces,
    ] = &mut parts;
    let loads = scenario::loads::<f32>();
    let mut previous: Option<Margins<f32>> = None;
    let mut next = 0usize;
    for k in 0..reference::CYCLES {
        let t = black_box(scenario::time::<f32>(k));
        if let Some(&(at, goal)) = orders.get(next)
            && at == k
        {
            let t0 = systick();
            let r = black_box(scenario::give(&mut online, t, goal));
            let t1 = systick();
            plan.add(elapsed(t0, t1));
            next += 1;
            if r.is_err() {
                return;
            }
        }
        let t0 = systick();
        let state: PlatformState<f32> = black_box(online.state_at(t));
        let t1 = systick();
        traj.add(elapsed(t0, t1));
        let pose = &state.pose;
        let t0 = systick();
        let _ = black_box(ComplexField::sin_cos(black_box(pose.psi)));
        let t1 = systick();
        trig.add(elapsed(t0, t1));
        let t0 = systick();
        let frame = black_box(state.frame());
        let t1 = systick();
        frame_cost.add(elapsed(t0, t1));
        let Ok(frame) = frame else { return };
        let t0 = systick();
        let m1 = black_box(c.module1.solve_tracking(black_box(&frame), &mut tracker));
        let t1 = systick();
        // The first replayed cycle seeds the tracker: not a cycle's cost.
        if k > 0 {
            module1.add(elapsed(t0, t1));
        }
        let t0 = systick();
        let left = black_box(c.left.solve(
            black_box(&frame),
            &parasils::kin::TipMotion::still(tips.left),
            c.modes[0],
        ));
        let right = black_box(c.right.solve(
            black_box(&frame),
            &parasils::kin::TipMotion::still(tips.right),
            c.modes[1],
        ));
        let t1 = systick();
        instruments.add(elapsed(t0, t1));
        let (Ok(m1), Ok(left), Ok(right)) = (m1, left, right) else {
            return;
        };
        let t0 = systick();
        let _ = black_box(c.left.fk(black_box(pose), &left.q));
        let _ = black_box(c.right.fk(black_box(pose), &right.q));
        let t1 = systick();
        fk.add(elapsed(t0, t1));
        let step = black_box(parasils::kin::ControlStep {
            frame,
            module1: m1,
            left,
            right,
        });
        let t0 = systick();
        let _ = black_box(scenario::forces(&c, black_box(&step), black_box(&loads)));
        let t1 = systick();
        forces.add(elapsed(t0, t1));
        let t0 = systick();
        let now = Margins::of(&step);
        let mut rates = Margins::splat(0.0f32);
        if let Some(p) = previous {
            for ((r, m), q) in rates.0.iter_mut().zip(now.0).zip(p.0) {
                *r = (m - q) * black_box(1000.0);
            }
        }
        let verdict = black_box(supervisor.check_ahead(&now, &rates, black_box(1.0)));
        let t1 = systick();
        watch.add(elapsed(t0, t1));
        let _ = verdict;
        previous = Some(now);
    }
    out.str("cost.breakdown (mean instructions):");
    for (label, part) in [
        (" trajectory (platform state) ", &parts[1]),
        (", frame ", &parts[2]),
        (
            ", module 1 (IK, rates, margins, the parallel one tracked) ",
            &parts[3],
        ),
        (", both instrument modules ", &parts[4]),
        (", both tips FK ", &parts[5]),
        (", supervisor ", &parts[6]),
        (
            ", feedforward forces (both tips loaded, weight, Newton-Euler) ",
            &parts[8],
        ),
        ("; one f32 sin_cos (libm) ", &parts[7]),
    ] {
        let mean = part.sum.checked_div(part.n).unwrap_or(0);
        out.str(label).u64(instructions(mean, calibration));
    }
    out.nl();
    let p = &parts[0];
    out.str("cost.plan (instructions per command): mean ");
    out.u64(instructions(
        p.sum.checked_div(p.n).unwrap_or(0),
        calibration,
    ));
    out.str(", max ")
        .u64(instructions(p.max.into(), calibration));
    out.str(" (").u64(p.n).str(" commands)").nl();
}
