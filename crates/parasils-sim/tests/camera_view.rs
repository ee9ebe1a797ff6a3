//! What the camera sees, every sample: the image columns against a pinhole
//! written here, the roll against the rotation between frames and against
//! the integral of `psi_dot sin theta`, and the turn given by what to look
//! at (`Input::look_at`) under both timings.

use parasils::kin::nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use parasils_sim::input::{Input, TimingKind};
use parasils_sim::{LookAt, LookAtTips, Record, Scenario, Simulation};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

fn rows(scenario: Scenario) -> Result<Vec<Record>> {
    let sim = Simulation::new(scenario)?;
    Ok(sim.samples().collect::<core::result::Result<Vec<_>, _>>()?)
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)`, written out here.
fn rotation(pose: &[f64; 6]) -> Matrix3<f64> {
    let [_, _, _, psi, theta, phi] = *pose;
    let (s1, c1, s2, c2, s3, c3) = (
        psi.sin(),
        psi.cos(),
        theta.sin(),
        theta.cos(),
        phi.sin(),
        phi.cos(),
    );
    Matrix3::new(
        c2 * c3,
        -c2 * s3,
        s2,
        c1 * s3 + s1 * s2 * c3,
        c1 * c3 - s1 * s2 * s3,
        -s1 * c2,
        s1 * s3 - c1 * s2 * c3,
        s1 * c3 + c1 * s2 * s3,
        c1 * c2,
    )
}

/// A straight 70 deg, 16:9 scope at the platform's centre (depth 0): the
/// pinhole of the model, `u = X'.d / (-Z'.d) / tan 35 deg`, `v = Y'.d /
/// (-Z'.d) / (tan 35 deg / (16 / 9))`, `d` from the eye to `p`.
fn pinhole(pose: &[f64; 6], p: &Vector3<f64>) -> (f64, f64, bool) {
    let r = rotation(pose);
    let d = p - Vector3::new(pose[0], pose[1], pose[2]);
    let ahead = -r.column(2).dot(&d);
    let tan = 35f64.to_radians().tan();
    let u = r.column(0).dot(&d) / ahead / tan;
    let v = r.column(1).dot(&d) / ahead / (tan / (16.0 / 9.0));
    (u, v, ahead > 0.0 && u.abs() <= 1.0 && v.abs() <= 1.0)
}

#[test]
fn the_image_columns_are_the_pinhole_of_the_commanded_tips() -> Result {
    let scenario = Scenario {
        rate_hz: 100.0,
        ..Scenario::paper()
    };
    let tips = scenario.tips();
    let rows = rows(scenario)?;
    assert_eq!(rows.len(), 451);
    let mid = (tips.left + tips.right) / 2.0;
    for r in &rows {
        for (k, tip) in [tips.left, tips.right].iter().enumerate() {
            let (u, v, seen) = pinhole(&r.pose, tip);
            let [cu, cv] = r.camera.tips[k];
            assert!((cu - u).abs() < 1e-12, "t = {}: u {cu} vs {u}", r.t);
            assert!((cv - v).abs() < 1e-12, "t = {}: v {cv} vs {v}", r.t);
            assert_eq!(r.camera.in_view[k], seen);
        }
        // Given by angles: the aim error is to the tips' midpoint.
        let view = -rotation(&r.pose).column(2);
        let to = mid - Vector3::new(r.pose[0], r.pose[1], r.pose[2]);
        let aim = (view.dot(&to) / to.norm()).clamp(-1.0, 1.0).acos();
        assert!((r.camera.aim_error - aim).abs() < 1e-7, "{}", r.t);
    }
    Ok(())
}

/// The twist about `axis` of the rotation `r`, rad, in `(-pi, pi]`: `r` as
/// a swing across `axis` after a twist about it, from its quaternion.
fn twist(r: &Matrix3<f64>, axis: &Vector3<f64>) -> f64 {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    let g = 2.0 * q.imag().dot(axis).atan2(q.w);
    let pi = core::f64::consts::PI;
    if g > pi {
        g - 2.0 * pi
    } else if g <= -pi {
        g + 2.0 * pi
    } else {
        g
    }
}

#[test]
fn the_roll_is_the_twist_between_frames_and_about_the_integral_of_psi_dot_sin_theta() -> Result {
    let rows = rows(Scenario::paper())?;
    let r0 = rotation(&rows[0].pose);
    let view0 = -r0.column(2);
    // The image's spin about the view, integrated by the trapezoid rule:
    // the view is -Z', whose angular rate is -(psi_dot sin theta + phi_dot).
    let mut spin = 0.0;
    for (k, r) in rows.iter().enumerate() {
        let expected = twist(&(rotation(&r.pose) * r0.transpose()), &view0);
        assert!(
            (r.camera.roll - expected).abs() < 1e-9,
            "t = {}: roll {} vs twist {expected}",
            r.t,
            r.camera.roll
        );
        if k > 0 {
            let p = &rows[k - 1];
            let rate = |r: &Record| -r.euler_dot[0] * r.pose[4].sin();
            spin += 0.5 * (rate(p) + rate(r)) * (r.t - p.t);
        }
    }
    let last = rows.last().ok_or("no rows")?;
    assert!(
        last.camera.roll < -4f64.to_radians(),
        "{}",
        last.camera.roll
    );
    // The roll from the shortest carry differs from the integrated spin by
    // the solid angle between the view's path and the arc: small here.
    let gap = (last.camera.roll - spin).abs();
    assert!(
        gap < 0.05 * spin.abs(),
        "roll {} vs spin {spin}",
        last.camera.roll
    );
    Ok(())
}

/// The last record of the paper's start looking at `look`, timed by
/// `timing`.
fn look(look: LookAt, timing: TimingKind) -> Result<(Scenario, Record, Record)> {
    let scenario = Input {
        look_at: Some(look),
        timing: Some(timing),
        rate_hz: Some(200.0),
        ..Input::default()
    }
    .resolve()?;
    let rows = rows(scenario.clone())?;
    let first = *rows.first().ok_or("no rows")?;
    let last = *rows.last().ok_or("no rows")?;
    Ok((scenario, first, last))
}

#[test]
fn a_look_at_turn_ends_with_the_target_on_the_view_axis_under_every_timing() -> Result {
    let targets = [
        LookAt::Tips(LookAtTips::Tips),
        LookAt::Tips(LookAtTips::Right),
        LookAt::Point([40.0, 50.0, -650.0]),
    ];
    for target in targets {
        for timing in [TimingKind::Trapezoid, TimingKind::Optimal] {
            let (scenario, first, last) = look(target, timing)?;
            let point = Vector3::from(scenario.look_at_mm().ok_or("a look-at")?);
            assert!(first.camera.aim_error > 1e-3, "{target:?}: already aimed");
            let aim_deg = last.camera.aim_error.to_degrees();
            assert!(aim_deg < 1e-9, "{target:?} {timing:?}: {aim_deg} deg");
            // Independently: the view axis from the last pose through it.
            let view = -rotation(&last.pose).column(2);
            let to = point - Vector3::new(last.pose[0], last.pose[1], last.pose[2]);
            assert!(view.cross(&to).norm() / to.norm() < 1e-11);
            // Phi held, the tips held.
            assert_eq!(last.pose[5], first.pose[5]);
            assert!(last.left.tip_err < 1e-9 && last.right.tip_err < 1e-9);
        }
    }
    Ok(())
}

#[test]
fn the_paper_run_is_unchanged_by_the_look_at_field() -> Result {
    let given = Input {
        psi_deg: Some(15.0),
        theta_deg: Some(25.0),
        ..Input::default()
    }
    .resolve()?;
    assert_eq!(given, Scenario::paper());
    assert_eq!(given.turn().and_then(|t| t.look_at), None);
    assert_eq!(given.look_at_mm(), None);
    Ok(())
}
