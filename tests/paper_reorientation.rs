//! The paper's reorientation end to end, across the crates: the trapezoidal
//! trajectory of `parasils-traj` drives the controller of `parasils-kin`, and
//! the instrument tips stay where they are, with nothing integrated.

use parasils::kin::{Controller, PlatformState, Pose, Real, TipTargets};
use parasils::traj::{Limits, Motion, Multi, Synchronization};

/// The largest tip drift (mm) of both modules over the paper's motion sampled
/// at 1 kHz, and the number of samples.
fn drift<T: Real + parasils::traj::Real>() -> (f64, usize) {
    let start = Pose::<T>::paper_start();
    let deg = |x: f64| <T as parasils::kin::Real>::lit(x.to_radians());
    let motion = Multi::new(
        [start.psi, start.theta],
        [start.psi + deg(15.0), start.theta + deg(25.0)],
        [Limits::new(deg(10.0), deg(5.0)); 2],
        Synchronization::Phase,
    )
    .expect("valid limits");
    let mut controller = Controller::<T>::paper();
    let tips = TipTargets::<T>::paper();
    let mut worst = 0.0f64;
    let mut n = 0;
    for s in motion
        .sampler(<T as parasils::kin::Real>::lit(1000.0))
        .expect("valid rate")
    {
        let [psi, theta] = s.state;
        let mut pose = start;
        pose.psi = psi.position;
        pose.theta = theta.position;
        let state = PlatformState::reorientation(
            pose,
            [psi.velocity, theta.velocity],
            [psi.acceleration, theta.acceleration],
        );
        let out = controller
            .step(&state, &tips)
            .expect("regular along the paper's motion");
        for (m, q, target) in [
            (&controller.left, &out.left.q, &tips.left),
            (&controller.right, &out.right.q, &tips.right),
        ] {
            let tip = m.tip(&pose, q).expect("finite");
            worst = worst.max(
                (tip - target)
                    .map(|v| parasils::kin::Real::to_f64(v))
                    .norm(),
            );
        }
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
