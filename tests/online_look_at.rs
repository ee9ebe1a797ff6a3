//! The online controller's look-at command: after the motion ends the
//! camera's view axis passes through the target, the tips are held all the
//! way, and a target that cannot be looked at is refused with the
//! controller unchanged.
//!
//! The aim is checked with a second computation written here: the eye
//! `E = P - depth Z'` and the angle between `-Z'` (the assumed straight
//! scope's view) and `target - E`, from the platform's rotation matrix.

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{CameraError, Controller, PlatformState, Pose, TipTargets};
use parasils::traj::Limits;
use parasils::{Error, OnlineController, Real, Supervisor};

const DEPTH_MM: f64 = 60.0;

type Outcome = Result<(), Box<dyn core::error::Error>>;

fn controller<T: Real>() -> Result<OnlineController<T>, Error> {
    let deg = |x: f64| T::lit(x.to_radians());
    OnlineController::new(
        Controller::paper(),
        TipTargets::paper(),
        Pose::paper_start(),
        [Limits::new(deg(10.0), deg(5.0)); 2],
        Supervisor::default(),
    )
}

/// The angle (rad) between the straight scope's view `-Z'` and the
/// direction from its eye to `target`, written independently of the camera
/// module.
fn aim_angle<T: Real>(state: &PlatformState<T>, target: &Vector3<f64>) -> Result<f64, Error> {
    let frame = state.frame()?;
    let r = frame.rotation.map(|x| x.to_f64());
    let p = frame.position.map(|x| x.to_f64());
    let z = r.column(2).into_owned();
    let eye = p - z * DEPTH_MM;
    let to = target - eye;
    let view = -z;
    Ok(view.cross(&to).norm().atan2(view.dot(&to)))
}

/// The two targets: a point off to one side beyond the endoscope's tip,
/// then (commanded while turning) the midpoint of the two tips.
fn targets() -> [Vector3<f64>; 2] {
    let tips = TipTargets::<f64>::paper();
    [
        Vector3::new(40.0, 50.0, -650.0),
        (tips.left + tips.right) / 2.0,
    ]
}

/// Runs both look-at commands at 1 kHz (the second at 1.5 s, while the
/// first is under way) until rest; returns the aim error at rest (rad) and
/// the largest distance of a tip from its target on the way (mm).
fn run<T: Real>() -> Result<(f64, f64), Error> {
    let mut online = controller::<T>()?.with_endoscope_depth(T::lit(DEPTH_MM))?;
    let [first, second] = targets();
    let lit = |v: &Vector3<f64>| v.map(T::lit);
    let tips = TipTargets::<f64>::paper();
    let mut drift = 0f64;
    let mut k = 0u32;
    loop {
        let t = T::lit(f64::from(k) / 1000.0);
        if k == 0 {
            online.command_look_at(t, lit(&first))?;
        }
        if k == 1500 {
            assert!(
                !online.is_at_rest(t),
                "the second target comes while turning"
            );
            online.command_look_at(t, lit(&second))?;
        }
        let s = online.tick(t)?;
        let c = online.controller();
        let pose = &s.state.pose;
        let left = c.left.fk(pose, &s.step.left.q)?.map(|x| x.to_f64());
        let right = c.right.fk(pose, &s.step.right.q)?.map(|x| x.to_f64());
        drift = drift
            .max((left - tips.left).norm())
            .max((right - tips.right).norm());
        if online.is_at_rest(t) {
            assert_eq!(
                online.command_index(),
                1,
                "rest at cycle {k}, goal {:?}",
                online.goal()
            );
            return Ok((aim_angle(&online.state_at(t), &second)?, drift));
        }
        k += 1;
        assert!(k < 20_000, "the motion ends");
    }
}

#[test]
fn look_at_aims_the_view_through_the_target_with_the_tips_held_f64() -> Outcome {
    let (aim, drift) = run::<f64>()?;
    assert!(aim < 1e-9, "aim error {aim} rad");
    assert!(drift < 1e-9, "tip drift {drift} mm");
    Ok(())
}

#[test]
fn look_at_aims_the_view_through_the_target_with_the_tips_held_f32() -> Outcome {
    let (aim, drift) = run::<f32>()?;
    assert!(aim < 1e-3, "aim error {aim} rad");
    assert!(drift < 1e-2, "tip drift {drift} mm");
    Ok(())
}

#[test]
fn look_at_from_rest_matches_the_goal_of_the_camera_and_moves() -> Outcome {
    // The goal is a real turn (not the start), and the start does not aim.
    let mut online = controller::<f64>()?.with_endoscope_depth(DEPTH_MM)?;
    let [first, _] = targets();
    assert!(aim_angle(&online.state_at(0.0), &first)? > 0.05);
    online.command_look_at(0.0, first)?;
    let goal = online.goal();
    let p0 = Pose::<f64>::paper_start();
    assert!((goal[0] - p0.psi).abs() + (goal[1] - p0.theta).abs() > 0.05);
    let end = online.motion_end();
    assert!(aim_angle(&online.state_at(end), &first)? < 1e-9);
    Ok(())
}

#[test]
fn look_at_refuses_what_cannot_be_looked_at_and_changes_nothing() -> Outcome {
    let mut online = controller::<f64>()?.with_endoscope_depth(DEPTH_MM)?;
    let [first, _] = targets();
    online.command_look_at(0.0, first)?;
    let before = online;
    // P itself: nearer the port than the endoscope's tip.
    let p = Pose::<f64>::paper_start().position();
    let got = online.command_look_at(1.0, p);
    assert!(
        matches!(got, Err(Error::Camera(CameraError::Behind { depth_mm, .. })) if depth_mm == DEPTH_MM),
        "{got:?}"
    );
    let got = online.command_look_at(1.0, Vector3::new(f64::NAN, 0.0, -600.0));
    assert!(
        matches!(
            got,
            Err(Error::Camera(CameraError::NonFinite {
                what: "target.x",
                ..
            }))
        ),
        "{got:?}"
    );
    assert_eq!(online, before);
    // Without a depth there is no camera position.
    let mut bare = controller::<f64>()?;
    assert_eq!(
        bare.command_look_at(0.0, first),
        Err(Error::NoEndoscopeDepth)
    );
    assert_eq!(bare, controller::<f64>()?);
    // A depth outside the endoscope's range is refused.
    assert!(controller::<f64>()?.with_endoscope_depth(1e4).is_err());
    assert!(controller::<f64>()?.with_endoscope_depth(f64::NAN).is_err());
    Ok(())
}
