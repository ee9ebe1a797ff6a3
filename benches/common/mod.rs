//! What the benchmarks share: the paper's motion (SPEC section 7) and the
//! platform state at a time along it, in `f32` or `f64`.
//!
//! Every benchmark runs on an instant of the paper's reorientation where the
//! platform both turns and accelerates (`t = 1 s`: psi and theta accelerating
//! at 3 and 5 deg/s^2), so that no rate or acceleration term is zero and the
//! code measured is the general one.
#![allow(dead_code, reason = "each bench uses a part")]

use parasils::kin::{Controller, PlatformState, Pose, TipTargets};
use parasils::traj::{Limits, Multi, Synchronization};

/// A float type of both crates.
pub trait Float: parasils::kin::Real + parasils::traj::Real {}
impl<T: parasils::kin::Real + parasils::traj::Real> Float for T {}

/// `x` degrees in radians, as `T`.
pub fn deg<T: Float>(x: f64) -> T {
    <T as parasils::kin::Real>::lit(x.to_radians())
}

/// The paper's reorientation: `psi` +15 deg, `theta` +25 deg from `P0`,
/// 10 deg/s and 5 deg/s^2, phase-synchronised (4.5 s).
pub fn paper_motion<T: Float>() -> Multi<T, 2> {
    let start = Pose::<T>::paper_start();
    Multi::new(
        [start.psi, start.theta],
        [start.psi + deg(15.0), start.theta + deg(25.0)],
        [Limits::new(deg(10.0), deg(5.0)); 2],
        Synchronization::Phase,
    )
    .expect("the paper's limits are valid")
}

/// The platform state of the paper's motion at `t` (s).
pub fn state_at<T: Float>(motion: &Multi<T, 2>, t: T) -> PlatformState<T> {
    let [psi, theta] = motion.sample(t);
    let mut pose = Pose::<T>::paper_start();
    pose.psi = psi.position;
    pose.theta = theta.position;
    PlatformState::reorientation(
        pose,
        [psi.velocity, theta.velocity],
        [psi.acceleration, theta.acceleration],
    )
}

/// The paper's controller, tips and the states at `t = 0.999 s` and `t = 1 s`,
/// the controller having stepped at `0.999 s`: a bench that alternates the
/// two states times each step from the previous cycle's margin direction,
/// 1 ms away, as in a 1 kHz loop.
pub fn paper_step_inputs<T: Float>() -> (Controller<T>, TipTargets<T>, [PlatformState<T>; 2]) {
    let motion = paper_motion::<T>();
    let lit = <T as parasils::kin::Real>::lit;
    let states = [state_at(&motion, lit(0.999)), state_at(&motion, lit(1.0))];
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
