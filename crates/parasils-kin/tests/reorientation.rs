//! Motion type 4 along a smooth stand-in of the paper's reorientation: the
//! controller's joints put both tips back where they were asked, at every
//! sample, in f64 and in f32, with nothing integrated.

use nalgebra::Vector3;
use parasils_kin::{Controller, MarginTracker, Real, TipTargets};

mod common;
use common::motion::reorientation;

/// The largest tip drift (mm) over 4501 samples at 1 kHz, both modules.
fn largest_drift<T: Real>() -> f64 {
    let controller = Controller::<T>::paper();
    let mut tracker = MarginTracker::new();
    let tips = TipTargets::<T>::paper();
    let mut worst = 0.0f64;
    for k in 0..=4500 {
        let st = reorientation::<T>(f64::from(k) / 1000.0);
        let out = controller
            .step(&st, &tips, &mut tracker)
            .expect("the paper's motion is regular");
        for (module, sol, target) in [
            (&controller.left, &out.left, &tips.left),
            (&controller.right, &out.right, &tips.right),
        ] {
            let tip = module.fk(&st.pose, &sol.q).expect("finite");
            let d: Vector3<f64> = (tip - target).map(|v| v.to_f64());
            worst = worst.max(d.norm());
            assert!(sol.margins.cos_qs2 > T::lit(0.3));
            assert!(sol.q_ddot.to_vector().iter().all(|v| v.finite()));
        }
    }
    worst
}

#[test]
fn tips_do_not_drift_in_f64() {
    let d = largest_drift::<f64>();
    assert!(d < 1e-9, "largest drift {d} mm");
}

#[test]
fn tips_do_not_drift_in_f32() {
    let d = largest_drift::<f32>();
    assert!(d < 2e-3, "largest drift {d} mm");
}

#[test]
fn end_of_the_motion_matches_the_check_values() {
    let controller = Controller::<f64>::paper();
    let out = controller
        .step(
            &reorientation(4.5),
            &TipTargets::mirrored(),
            &mut MarginTracker::new(),
        )
        .expect("regular");
    let deg = |q: &parasils_kin::Joints<f64>| [q.qs1.to_degrees(), q.qs2.to_degrees(), q.qs3];
    let (l, r) = (deg(&out.left.q), deg(&out.right.q));
    for (got, want) in [
        (l, [20.7942, -61.8435, 151.0378]),
        (r, [18.5977, -13.0799, 143.6301]),
    ] {
        for i in 0..3 {
            assert!((got[i] - want[i]).abs() < 5e-5, "{got:?} vs {want:?}");
        }
    }
    // At rest at the end: rates and accelerations vanish.
    assert!(out.left.q_dot.to_vector().amax() < 1e-12);
    assert!(out.right.q_ddot.to_vector().amax() < 1e-12);
}
