//! What the benchmarks share: the paper's reorientation
//! ([`Reorientation::paper`]) and the controller's inputs at an instant of it,
//! in `f32` or `f64`.
//!
//! Every benchmark runs on an instant of the paper's reorientation where the
//! platform both turns and accelerates (`t = 1 s`: psi and theta accelerating
//! at 3 and 5 deg/s^2), so that no rate or acceleration term is zero and the
//! code measured is the general one.
#![allow(dead_code, reason = "each bench uses a part")]

use parasils::kin::{Controller, PlatformState, TipTargets};
use parasils::{Real, Reorientation};

/// The paper's reorientation: `psi` +15 deg, `theta` +25 deg from `P0`,
/// 10 deg/s and 5 deg/s^2, phase-synchronised (4.5 s).
pub fn paper_motion<T: Real>() -> Reorientation<T> {
    Reorientation::paper().expect("the paper's limits are valid")
}

/// The paper's controller, tips and the states at `t = 0.999 s` and `t = 1 s`,
/// the controller having stepped at `0.999 s`: a bench that alternates the
/// two states times each step from the previous cycle's margin direction,
/// 1 ms away, as in a 1 kHz loop.
pub fn paper_step_inputs<T: Real>() -> (Controller<T>, TipTargets<T>, [PlatformState<T>; 2]) {
    let motion = paper_motion::<T>();
    let lit = <T as parasils::kin::Real>::lit;
    let states = [motion.state_at(lit(0.999)), motion.state_at(lit(1.0))];
    let mut controller = Controller::paper();
    let tips = TipTargets::paper();
    controller.step(&states[0], &tips).expect("regular");
    (controller, tips, states)
}

/// A short criterion configuration: these functions take nanoseconds, and
/// the machine is shared, so many short samples beat a few long ones.
pub fn criterion() -> criterion::Criterion {
    criterion::Criterion::default()
        .warm_up_time(core::time::Duration::from_millis(500))
        .measurement_time(core::time::Duration::from_secs(2))
        .configure_from_args()
}
