//! What the benchmarks share: the paper's reorientation
//! ([`Reorientation::paper`]) and the controller's inputs at an instant of it,
//! in `f32` or `f64`.
//!
//! Every benchmark runs on an instant of the paper's reorientation where the
//! platform both turns and accelerates (`t = 1 s`: psi and theta accelerating
//! at 3 and 5 deg/s^2), so that no rate or acceleration term is zero and the
//! code measured is the general one.
#![allow(dead_code, reason = "each bench uses a part")]

use parasils::kin::{BodyGeometry, Controller, MarginTracker, PlatformState, Pose, TipTargets};
use parasils::supervisor::ClearanceThresholds;
use parasils::traj::Limits;
use parasils::{ClearanceWatch, OnlineController, Real, Reorientation, Supervisor};

/// The paper's reorientation: `psi` +15 deg, `theta` +25 deg from `P0`,
/// 10 deg/s and 5 deg/s^2, phase-synchronised (4.5 s).
pub fn paper_motion<T: Real>() -> Reorientation<T> {
    Reorientation::paper().expect("the paper's limits are valid")
}

/// The paper's controller, tips and the states at `t = 0.999 s` and `t = 1 s`,
/// with module 1's margin tracker having stepped at `0.999 s`: a bench that
/// alternates the two states times each step from the previous cycle's
/// margin direction, 1 ms away, as in a 1 kHz loop.
pub struct StepInputs<T: Real> {
    /// The paper's controller.
    pub controller: Controller<T>,
    /// Module 1's weakest direction at `0.999 s`.
    pub tracker: MarginTracker<T>,
    /// The paper's tips.
    pub tips: TipTargets<T>,
    /// The states at `0.999 s` and `1 s`.
    pub states: [PlatformState<T>; 2],
}

/// See [`StepInputs`].
pub fn paper_step_inputs<T: Real>() -> StepInputs<T> {
    let motion = paper_motion::<T>();
    let lit = T::lit;
    let states = [motion.state_at(lit(0.999)), motion.state_at(lit(1.0))];
    let controller = Controller::paper();
    let mut tracker = MarginTracker::new();
    let tips = TipTargets::paper();
    controller
        .step(&states[0], &tips, &mut tracker)
        .expect("regular");
    StepInputs {
        controller,
        tracker,
        tips,
        states,
    }
}

/// The online controller of the paper's scenario (the paper's goal commanded
/// at rest at `t = 0`, the default supervisor) having ticked at `0.998 s` and
/// `0.999 s`: its tick at `t = 1 s` is the same cycle as the step of
/// [`paper_step_inputs`], with the supervisor's rates from 1 ms earlier. A
/// bench ticks (or commands) a copy of it at `t = 1 s`, since the
/// controller's clock never runs backwards.
pub fn paper_online<T: Real>() -> OnlineController<T> {
    paper_online_with(None)
}

/// [`paper_online`] watching the clearance of the assumed bodies (the
/// endoscope at depth 0) with thresholds no gap of the paper's run reaches
/// (-1000 mm: its shafts overlap, see `docs/model.md`, *Clearance*), so
/// that every tick computes the three gaps and checks them ahead and the
/// supervisor stops nothing: the cost of the clearance on a tick.
pub fn paper_online_watching<T: Real>() -> OnlineController<T> {
    paper_online_with(Some(ClearanceWatch {
        bodies: BodyGeometry::assumed(),
        endoscope_depth: T::zero(),
        thresholds: ClearanceThresholds {
            warn: T::lit(-1000.0),
            stop: T::lit(-1000.0),
        },
    }))
}

fn paper_online_with<T: Real>(watch: Option<ClearanceWatch<T>>) -> OnlineController<T> {
    let lit = T::lit;
    let rad = |deg: f64| lit(deg.to_radians());
    let p0 = Pose::<T>::paper_start();
    let mut online = OnlineController::new(
        Controller::paper(),
        TipTargets::paper(),
        p0,
        [Limits::new(rad(10.0), rad(5.0)); 2],
        Supervisor::default(),
    )
    .expect("the paper's start is regular");
    if let Some(w) = watch {
        online = online.with_clearance(w).expect("valid bodies");
    }
    online
        .command(T::zero(), [p0.psi + rad(15.0), p0.theta + rad(25.0)])
        .expect("a finite goal");
    for t in [0.998, 0.999] {
        online.tick(lit(t)).expect("regular");
    }
    online
}

/// A new goal for [`paper_online`] at `t = 1 s`, while it turns: `psi` -10
/// and `theta` +15 deg from `P0` (`psi` turns back; time-synchronised), rad.
pub fn retarget<T: Real>() -> [T; 2] {
    let p0 = Pose::<T>::paper_start();
    let rad = |deg: f64| T::lit(deg.to_radians());
    [p0.psi + rad(-10.0), p0.theta + rad(15.0)]
}

/// A short criterion configuration: these functions take nanoseconds, and
/// the machine is shared, so many short samples beat a few long ones.
pub fn criterion() -> criterion::Criterion {
    criterion::Criterion::default()
        .warm_up_time(core::time::Duration::from_millis(500))
        .measurement_time(core::time::Duration::from_secs(2))
        .configure_from_args()
}
