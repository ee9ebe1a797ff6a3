//! The follow law: its dead zones, dwell and hysteresis against tips placed
//! in the image by a pinhole written here, its turns within the limits, its
//! aim after settling, and its errors.

#![allow(clippy::float_cmp, reason = "held setpoints are compared exactly")]

use nalgebra::{Vector3, Vector3 as V};
use parasils::follow::{Follow, FollowError, FollowParams, FollowPhase, FollowStep};
use parasils::kin::{Camera, Pose};

const RATE_HZ: f64 = 1000.0;
const DEPTH_MM: f64 = 40.0;

fn pose() -> Pose<f64> {
    Pose::from_mm_deg(15.0, 20.0, -500.0, -8.0, 4.0, -60.0)
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)`, written out here.
fn rotation(p: &Pose<f64>) -> nalgebra::Matrix3<f64> {
    let rx = nalgebra::Matrix3::new(
        1.0,
        0.0,
        0.0,
        0.0,
        p.psi.cos(),
        -p.psi.sin(),
        0.0,
        p.psi.sin(),
        p.psi.cos(),
    );
    let ry = nalgebra::Matrix3::new(
        p.theta.cos(),
        0.0,
        p.theta.sin(),
        0.0,
        1.0,
        0.0,
        -p.theta.sin(),
        0.0,
        p.theta.cos(),
    );
    let rz = nalgebra::Matrix3::new(
        p.phi.cos(),
        -p.phi.sin(),
        0.0,
        p.phi.sin(),
        p.phi.cos(),
        0.0,
        0.0,
        0.0,
        1.0,
    );
    rx * ry * rz
}

/// The assumed camera's `tan(hfov / 2)` and `tan(hfov / 2) / aspect`.
fn tans() -> (f64, f64) {
    let t = 35f64.to_radians().tan();
    (t, t * 9.0 / 16.0)
}

/// The point `ahead_mm` in front of the straight scope at `pose` that the
/// image shows at `(u, v)`: the pinhole read backwards.
fn point_at(pose: &Pose<f64>, u: f64, v: f64, ahead_mm: f64) -> Vector3<f64> {
    let r = rotation(pose);
    let eye = pose.position() + r * V::new(0.0, 0.0, -DEPTH_MM);
    let (tu, tv) = tans();
    eye + r * V::new(u * tu * ahead_mm, v * tv * ahead_mm, -ahead_mm)
}

/// `(u, v)` of `p` for the straight scope at `pose`, and whether it is ahead.
fn pinhole(pose: &Pose<f64>, p: &Vector3<f64>) -> (f64, f64, bool) {
    let r = rotation(pose);
    let eye = pose.position() + r * V::new(0.0, 0.0, -DEPTH_MM);
    let w = r.transpose() * (p - eye);
    let (tu, tv) = tans();
    (w.x / -w.z / tu, w.y / -w.z / tv, w.z < 0.0)
}

/// Two tips 20 mm apart across the image, their midpoint at `(u, v)`.
fn tips_at(pose: &Pose<f64>, u: f64, v: f64) -> [Vector3<f64>; 2] {
    let m = point_at(pose, u, v, 90.0);
    let across = rotation(pose) * V::new(10.0, 0.0, 0.0);
    [m - across, m + across]
}

fn law() -> Follow<f64> {
    Follow::new(Camera::assumed(), FollowParams::assumed(), pose(), DEPTH_MM).expect("law")
}

fn t(k: usize) -> f64 {
    k as f64 / RATE_HZ
}

fn with_angles(angles: [f64; 2]) -> Pose<f64> {
    Pose {
        psi: angles[0],
        theta: angles[1],
        ..pose()
    }
}

/// Runs `law` from cycle `from` for `n` cycles on `tips(k)`, every step.
fn run(
    law: &mut Follow<f64>,
    from: usize,
    n: usize,
    tips: impl Fn(usize) -> [Vector3<f64>; 2],
) -> Vec<FollowStep<f64>> {
    (from..from + n)
        .map(|k| law.step(t(k), &tips(k)).expect("step"))
        .collect()
}

#[test]
fn the_test_pinhole_reads_back_its_points() {
    let p = pose();
    let (u, v, ahead) = pinhole(&p, &point_at(&p, 0.3, -0.7, 75.0));
    assert!(ahead && (u - 0.3).abs() < 1e-12 && (v + 0.7).abs() < 1e-12);
}

#[test]
fn inside_the_trigger_zone_the_platform_never_moves() {
    let mut law = law();
    // The midpoint at radius 0.25 < 0.3, moving about there, then still.
    let steps = run(&mut law, 0, 3000, |k| {
        let a = t(k);
        tips_at(&pose(), 0.2 + 0.05 * a.sin(), 0.1 * a.cos())
    });
    for s in &steps {
        assert_eq!(s.phase, FollowPhase::Idle);
        assert_eq!(s.angles[0].position, pose().psi);
        assert_eq!(s.angles[1].position, pose().theta);
        assert_eq!((s.angles[0].velocity, s.angles[1].velocity), (0.0, 0.0));
    }
}

#[test]
fn beyond_it_the_turn_waits_for_the_dwell_then_centres_the_midpoint() {
    let mut law = law();
    let tips = tips_at(&pose(), 0.4, 0.2);
    let steps = run(&mut law, 0, 20_000, |_| tips);
    // Still from t = 0: armed and held until t = 0.25 s, the dwell.
    let first = steps.iter().position(|s| s.replanned).expect("a turn");
    assert_eq!(first, 250);
    for s in &steps[..first] {
        assert_eq!(s.phase, FollowPhase::Armed);
        assert_eq!(s.angles[0].position, pose().psi);
    }
    // Within the limits, each angle continuous at the cycle.
    let p = FollowParams::<f64>::assumed();
    for w in steps.windows(2) {
        for i in 0..2 {
            let (a, b) = (w[0].angles[i], w[1].angles[i]);
            assert!(b.velocity.abs() <= p.limits.v_max * (1.0 + 1e-12));
            assert!(b.acceleration.abs() <= p.limits.a_max * (1.0 + 1e-12));
            assert!((b.position - a.position).abs() <= p.limits.v_max / RATE_HZ * (1.0 + 1e-9));
        }
    }
    // Settled: idle, at rest, the midpoint on the view axis by the test's
    // own pinhole.
    let last = steps.last().expect("steps");
    assert_eq!(last.phase, FollowPhase::Idle);
    let aimed = with_angles(last.angles.map(|a| a.position));
    let (u, v, ahead) = pinhole(&aimed, &((tips[0] + tips[1]) * 0.5));
    assert!(ahead && u.abs() < 1e-9 && v.abs() < 1e-9, "u {u} v {v}");
    assert_eq!(last.angles[0].velocity, 0.0);
    // Exactly one plan: the tips never moved.
    assert_eq!(steps.iter().filter(|s| s.replanned).count(), 1);
}

#[test]
fn a_tip_near_the_edge_turns_at_once() {
    let mut law = law();
    // The midpoint at 0.45 across, one tip beyond the 0.6 edge.
    let m = point_at(&pose(), 0.45, 0.0, 90.0);
    let across = rotation(&pose()) * V::new(20.0, 0.0, 0.0);
    let step = law.step(0.0, &[m - across, m + across]).expect("step");
    assert_eq!(step.phase, FollowPhase::Recentring);
    assert!(step.replanned);
}

#[test]
fn moving_tips_keep_it_armed_and_back_inside_the_inner_zone_disarm_it() {
    let mut law = law();
    // Out to 0.35 and moving (2 mm/s across): armed, no turn.
    let steps = run(&mut law, 0, 500, |k| {
        let drift = rotation(&pose()) * V::new(0.002 * k as f64, 0.0, 0.0);
        tips_at(&pose(), 0.35, 0.0).map(|p| p + drift)
    });
    assert!(steps.iter().all(|s| s.phase == FollowPhase::Armed));
    // Back to the band between the zones, still moving: still armed.
    let band = run(&mut law, 500, 100, |k| {
        let drift = rotation(&pose()) * V::new(0.002 * k as f64, 0.0, 0.0);
        tips_at(&pose(), 0.2, 0.0).map(|p| p + drift)
    });
    assert!(band.iter().all(|s| s.phase == FollowPhase::Armed));
    // Within the inner zone: idle, and it stays idle once still there.
    let inner = run(&mut law, 600, 1000, |_| tips_at(&pose(), 0.05, 0.0));
    assert!(inner.iter().all(|s| s.phase == FollowPhase::Idle));
    assert!(inner.iter().all(|s| s.angles[0].position == pose().psi));
}

#[test]
fn a_target_moving_during_the_turn_is_chased_and_the_aim_settles_within_the_retarget_angle() {
    let mut law = law();
    let drift = |k: usize| {
        // 5 mm/s across the picture for 3 s, then still.
        let s = t(k.min(3000)) * 5.0;
        rotation(&pose()) * V::new(s, 0.5 * s, 0.0)
    };
    let start = point_at(&pose(), 0.7, 0.0, 90.0);
    let across = rotation(&pose()) * V::new(10.0, 0.0, 0.0);
    let tips = |k: usize| [start - across + drift(k), start + across + drift(k)];
    let steps = run(&mut law, 0, 20_000, tips);
    assert!(steps.iter().filter(|s| s.replanned).count() > 2);
    let last = steps.last().expect("steps");
    assert_eq!(last.phase, FollowPhase::Idle);
    let aimed = with_angles(last.angles.map(|a| a.position));
    let m = (tips(20_000)[0] + tips(20_000)[1]) * 0.5;
    let r = rotation(&aimed);
    let eye = aimed.position() + r * V::new(0.0, 0.0, -DEPTH_MM);
    let axis = r * V::new(0.0, 0.0, -1.0);
    let error = axis.angle(&(m - eye));
    // The goal is replanned when it moves by more than 1e-3 rad in an angle.
    assert!(error < 2e-3, "aim error {error} rad");
}

#[test]
fn bad_inputs_are_typed_errors_and_leave_the_state_as_it_was() {
    let mut law = law();
    let tips = tips_at(&pose(), 0.1, 0.0);
    law.step(1.0, &tips).expect("step");
    let before = law;
    let nan = [V::new(f64::NAN, 0.0, -600.0), tips[1]];
    assert!(matches!(
        law.step(1.001, &nan),
        Err(FollowError::NonFinite {
            what: "left tip x",
            ..
        })
    ));
    assert!(matches!(
        law.step(0.5, &tips),
        Err(FollowError::TimeReversed { t: 0.5, last: 1.0 })
    ));
    assert_eq!(law, before);
    // The midpoint behind the endoscope's tip cannot be looked at.
    let behind = [pose().position(), pose().position()];
    let mut law = self::law();
    assert!(matches!(
        law.step(0.0, &behind),
        Err(FollowError::Camera(_))
    ));
    let params = FollowParams {
        inner_radius: 0.5,
        ..FollowParams::assumed()
    };
    let e = Follow::new(Camera::assumed(), params, pose(), DEPTH_MM).expect_err("inner > outer");
    assert!(matches!(
        e,
        FollowError::InvalidParameter {
            what: "outer_radius",
            ..
        }
    ));
    assert_eq!(
        e.to_string(),
        "follow: outer_radius = 0.3 is not valid: at least inner_radius"
    );
}

#[test]
fn in_f32_the_turn_settles_on_the_midpoint() {
    let p = Pose::<f32>::from_mm_deg(15.0, 20.0, -500.0, -8.0, 4.0, -60.0);
    let mut law =
        Follow::<f32>::new(Camera::assumed(), FollowParams::assumed(), p, 40.0).expect("law");
    let tips64 = tips_at(&pose(), 0.4, 0.2);
    let tips = tips64.map(|v| v.map(|x| x as f32));
    let mut last = law.step(0.0, &tips).expect("step");
    for k in 1..20_000 {
        last = law.step(k as f32 / 1000.0, &tips).expect("step");
    }
    assert_eq!(last.phase, FollowPhase::Idle);
    let aimed = with_angles(last.angles.map(|a| f64::from(a.position)));
    let (u, v, _) = pinhole(&aimed, &((tips64[0] + tips64[1]) * 0.5));
    assert!(u.abs() < 1e-4 && v.abs() < 1e-4, "u {u} v {v}");
}
