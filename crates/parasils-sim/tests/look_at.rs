//! Look-at motions in procedures: a type-4 motion given what to look at
//! instead of angles ends with that point on the camera's view axis, both
//! tips held.

use std::path::Path;

use parasils::kin::nalgebra::{Matrix3, Vector3};
use parasils::kin::{Camera, PlatformState, Pose};
use parasils_sim::{Record, Simulation};

mod common;

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// The demo's start, the platform over the port, the endoscope 60 mm in.
const START: &str = r#"
pose = [15, 20, -500, -15, 10, -60]
tip_left_mm = [50, -50, -580]
endoscope_depth_mm = 60
"#;

fn simulate_in(text: &str, base: &Path) -> Result<Simulation> {
    common::simulate_text(text, base)
}

fn error(motions: &str) -> String {
    common::refusal(&format!("{START}{motions}"))
}

fn rows(sim: &Simulation) -> Result<Vec<Record>> {
    Ok(sim.samples().collect::<core::result::Result<Vec<_>, _>>()?)
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)`, written out here.
fn rotation(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
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

/// The angle between a straight scope's view (`-Z'` from its tip) and the
/// direction to `target`, rad.
fn straight_aim(r: &Record, depth: f64, target: &Vector3<f64>) -> f64 {
    let [x, y, z, psi, theta, phi] = r.pose;
    let rot = rotation(psi, theta, phi);
    let eye = Vector3::new(x, y, z) + rot * Vector3::new(0.0, 0.0, -depth);
    let view = -rot.column(2);
    let to = target - eye;
    view.cross(&to).norm().atan2(view.dot(&to))
}

#[test]
fn looking_at_the_tips_centres_their_midpoint_and_holds_them() -> Result {
    let sim = simulate_in(
        &format!("{START}[[motion]]\ntype = \"reorient\"\nlook_at = \"tips\"\n"),
        Path::new("."),
    )?;
    let rows = rows(&sim)?;
    let (first, last) = (&rows[0], &rows[rows.len() - 1]);
    let mid = (first.left.tip + first.right.tip) / 2.0;
    // Not centred at the start, centred at the end.
    assert!(straight_aim(first, 60.0, &mid) > 1e-2);
    let aim = straight_aim(last, 60.0, &mid);
    assert!(aim < 1e-9, "{aim}");
    // Both tips held all along, phi and P still.
    for r in &rows {
        assert!((r.left.tip - first.left.tip).norm() < 1e-9);
        assert!((r.right.tip - first.right.tip).norm() < 1e-9);
        assert_eq!(r.pose[5], first.pose[5]);
        assert_eq!(r.pose[..3], first.pose[..3]);
        assert_eq!(r.motion_type, 4);
    }
    Ok(())
}

#[test]
fn looking_at_a_point_with_an_oblique_scope_of_the_robot_file() -> Result {
    let dir = std::env::temp_dir().join(format!("parasils-look-at-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/default.toml");
    let robot = std::fs::read_to_string(robots)?;
    std::fs::write(
        dir.join("oblique.toml"),
        format!("{robot}\n[camera]\noblique_deg = 30\noblique_direction_deg = 90\n"),
    )?;
    let target = [40.0, -10.0, -640.0];
    let text = format!(
        "robot = \"oblique.toml\"\n{START}[[motion]]\ntype = \"reorient\"\nlook_at_mm = {target:?}\n"
    );
    let sim = simulate_in(&text, &dir);
    std::fs::remove_dir_all(&dir)?;
    let sim = sim?;
    let last = rows(&sim)?.pop().ok_or("no rows")?;
    let [x, y, z, psi, theta, phi] = last.pose;
    let frame = PlatformState::at_rest(Pose {
        x,
        y,
        z,
        psi,
        theta,
        phi,
    })
    .frame()?;
    let camera = Camera::new(
        70f64.to_radians(),
        16.0 / 9.0,
        30f64.to_radians(),
        90f64.to_radians(),
    )?;
    let target = Vector3::from(target);
    let aim = camera.aim_error(&frame, 60.0, &target);
    assert!(aim < 1e-9, "{aim}");
    // The straight scope would not be centred on it: the tilt matters.
    assert!(straight_aim(&last, 60.0, &target) > 0.4);
    Ok(())
}

#[test]
fn look_at_keys_are_checked_and_named() {
    let both = error("[[motion]]\ntype = \"reorient\"\npsi_deg = 5\nlook_at = \"tips\"\n");
    assert!(
        both.contains("psi_deg") && both.contains("look-at target"),
        "{both}"
    );
    let two =
        error("[[motion]]\ntype = \"reorient\"\nlook_at = \"tips\"\nlook_at_mm = [0, 0, -650]\n");
    assert!(two.contains("look_at"), "{two}");
    let word = error("[[motion]]\ntype = \"reorient\"\nlook_at = \"gallbladder\"\n");
    assert!(word.contains("\"gallbladder\" is not one of"), "{word}");
    let wrong_type = error(
        "[[motion]]\ntype = \"insert\"\ninstrument = \"left\"\ndepth_mm = 5\nlook_at = \"tips\"\n",
    );
    assert!(
        wrong_type.contains("look_at") && wrong_type.contains("does not apply"),
        "{wrong_type}"
    );
    // 30 mm below the port with the endoscope 60 mm in: behind the camera.
    let behind = error("[[motion]]\ntype = \"reorient\"\nlook_at_mm = [15, 20, -530]\n");
    assert!(
        behind.contains("motion 0") && behind.contains("not beyond the endoscope's tip"),
        "{behind}"
    );
}
