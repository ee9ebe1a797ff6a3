//! The paper's reorientation end to end, across the crates: the bridge
//! ([`parasils::Reorientation`]) turns the synchronised profile of
//! `parasils-traj` into the platform states that the controller of
//! `parasils-kin` steps through, and the instrument tips stay where they are,
//! with nothing integrated. The drift bounds are those of `docs/model.md`,
//! *Check values*: 1e-9 mm in `f64`, 2e-3 mm in `f32`.

use parasils::kin::{ControlStep, Controller, MarginTracker, PlatformState, TipTargets};
use parasils::{Real, Reorientation, paper};

/// `x` as `T`.
fn lit<T: Real>(x: f64) -> T {
    T::lit(x)
}

/// The larger distance (mm) of the two tips, recomputed from the step's
/// joints by forward kinematics at the state's pose, to their targets.
fn tip_drift<T: Real>(
    controller: &Controller<T>,
    state: &PlatformState<T>,
    out: &ControlStep<T>,
    tips: &TipTargets<T>,
) -> f64 {
    let mut worst = 0.0f64;
    for (m, q, target) in [
        (&controller.left, &out.left.q, &tips.left),
        (&controller.right, &out.right.q, &tips.right),
    ] {
        let tip = m.fk(&state.pose, q).expect("finite");
        worst = worst.max((tip - target).map(|v| v.to_f64()).norm());
    }
    worst
}

/// The largest tip drift (mm) of both modules over the paper's motion sampled
/// at 1 kHz, and the number of samples.
fn drift<T: Real>() -> (f64, usize) {
    let motion = Reorientation::<T>::paper().expect("valid limits");
    let controller = Controller::<T>::paper();
    let mut tracker = MarginTracker::new();
    let tips = TipTargets::<T>::paper();
    let mut worst = 0.0f64;
    let mut n = 0;
    for s in motion.sampler(lit(paper::RATE_HZ)).expect("valid rate") {
        let out = controller
            .step(&s.state, &tips, &mut tracker)
            .expect("regular along the paper's motion");
        worst = worst.max(tip_drift(&controller, &s.state, &out, &tips));
        n += 1;
    }
    (worst, n)
}

#[test]
fn tips_stay_put_in_f64() {
    let (d, n) = drift::<f64>();
    assert_eq!(n, 4501);
    assert!(d < 1e-9, "largest drift {d} mm");
}

#[test]
fn tips_stay_put_in_f32() {
    let (d, n) = drift::<f32>();
    assert_eq!(n, 4501);
    assert!(d < 2e-3, "largest drift {d} mm");
}

/// Checks that every sample of the bridge at 1 kHz is the profile's
/// `(psi, theta)` on the start pose at `t_k = k / rate`, and that the
/// controller stepped with these states, and with [`Reorientation::state_at`]
/// half-way between them, holds both tips within `bound` mm. Returns the
/// number of samples.
fn bridge_drives_the_controller<T: Real>(bound: f64) -> usize {
    let motion = Reorientation::<T>::paper().expect("valid limits");
    let start = *motion.start();
    let rate = lit::<T>(paper::RATE_HZ);
    let tips = TipTargets::<T>::paper();
    let (on_samples, between) = (Controller::<T>::paper(), Controller::<T>::paper());
    let mut trackers = [MarginTracker::new(), MarginTracker::new()];
    let mut n = 0;
    for s in motion.sampler(rate).expect("valid rate") {
        let k = s.index;
        assert_eq!(k, n, "indices count up from 0");
        let t = lit::<T>(k as f64) / rate;
        assert_eq!(s.time, t, "sample {k} at t = k / rate");
        assert_eq!(s.state, motion.state_at(t), "sample {k} is state_at(t_k)");

        // The profile on the start pose: psi and theta move, nothing else.
        let [psi, theta] = motion.profile().sample(t);
        let (pose, v, a) = (&s.state.pose, &s.state.velocity, &s.state.acceleration);
        assert_eq!(
            (pose.psi, pose.theta),
            (psi.position, theta.position),
            "sample {k}: angles"
        );
        assert_eq!(
            (v.psi, v.theta, a.psi, a.theta),
            (
                psi.velocity,
                theta.velocity,
                psi.acceleration,
                theta.acceleration
            ),
            "sample {k}: Euler rates and accelerations"
        );
        assert_eq!(
            (pose.x, pose.y, pose.z, pose.phi),
            (start.x, start.y, start.z, start.phi),
            "sample {k}: P and phi stay at the start"
        );
        assert_eq!(
            [v.x, v.y, v.z, v.phi, a.x, a.y, a.z, a.phi],
            [lit::<T>(0.0); 8],
            "sample {k}: P and phi at rest"
        );

        let out = on_samples
            .step(&s.state, &tips, &mut trackers[0])
            .expect("regular");
        let d = tip_drift(&on_samples, &s.state, &out, &tips);
        assert!(d < bound, "sample {k}: drift {d} mm");

        let mid = motion.state_at(t + lit::<T>(0.5) / rate);
        let out = between
            .step(&mid, &tips, &mut trackers[1])
            .expect("regular");
        let d = tip_drift(&between, &mid, &out, &tips);
        assert!(d < bound, "half-way after sample {k}: drift {d} mm");
        n += 1;
    }
    let goal = motion.goal();
    let end = motion.state_at(motion.duration());
    assert_eq!(
        [end.pose.psi, end.pose.theta],
        goal,
        "the motion ends on its goal"
    );
    n
}

#[test]
fn bridge_drives_the_controller_in_f64() {
    assert_eq!(bridge_drives_the_controller::<f64>(1e-9), 4501);
}

#[test]
fn bridge_drives_the_controller_in_f32() {
    assert_eq!(bridge_drives_the_controller::<f32>(2e-3), 4501);
}
