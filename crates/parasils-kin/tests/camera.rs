//! The camera: the image coordinates against a pinhole projection written
//! here from the model's equations, and the look-at turn against targets
//! placed on a known view axis.

use parasils_kin::nalgebra::{Matrix3, Vector3};
use parasils_kin::{Camera, CameraError, PlatformState, Pose};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// A small deterministic generator (SplitMix64), uniform in `[lo, hi)`.
struct Rng(u64);

impl Rng {
    fn next(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// A platform pose near the paper's height, `psi` and `theta` within
    /// `+-turn` rad, `phi` within 1.5 rad.
    fn pose(&mut self, turn: f64) -> Pose<f64> {
        Pose {
            x: self.next(-20.0, 20.0),
            y: self.next(-20.0, 20.0),
            z: self.next(-520.0, -480.0),
            psi: self.next(-turn, turn),
            theta: self.next(-turn, turn),
            phi: self.next(-1.5, 1.5),
        }
    }
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)`, written out here.
fn rotation(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    let rx = Matrix3::new(
        1.0,
        0.0,
        0.0,
        0.0,
        psi.cos(),
        -psi.sin(),
        0.0,
        psi.sin(),
        psi.cos(),
    );
    let ry = Matrix3::new(
        theta.cos(),
        0.0,
        theta.sin(),
        0.0,
        1.0,
        0.0,
        -theta.sin(),
        0.0,
        theta.cos(),
    );
    let rz = Matrix3::new(
        phi.cos(),
        -phi.sin(),
        0.0,
        phi.sin(),
        phi.cos(),
        0.0,
        0.0,
        0.0,
        1.0,
    );
    rx * ry * rz
}

/// The view direction in the platform frame, from the model's words: `-Z'`
/// tilted by `o` towards the direction `d` from `X'`.
fn view_local(o: f64, d: f64) -> Vector3<f64> {
    Vector3::new(o.sin() * d.cos(), o.sin() * d.sin(), -o.cos())
}

/// The angle between the view axis of `pose` and the direction from the
/// endoscope's tip to `target`.
fn residual(camera: &Camera<f64>, pose: &Pose<f64>, depth: f64, target: &Vector3<f64>) -> f64 {
    let r = rotation(pose.psi, pose.theta, pose.phi);
    let eye = pose.position() + r * Vector3::new(0.0, 0.0, -depth);
    let view = r * view_local(camera.oblique, camera.oblique_direction);
    let to = target - eye;
    view.cross(&to).norm().atan2(view.dot(&to))
}

#[test]
fn a_straight_scope_projects_as_the_pinhole_of_the_model() -> Result {
    let camera = Camera::<f64>::assumed();
    let mut rng = Rng(7);
    let tan = (35f64).to_radians().tan();
    for _ in 0..2000 {
        let pose = rng.pose(0.6);
        let depth = rng.next(0.0, 120.0);
        let p = Vector3::new(
            rng.next(-150.0, 150.0),
            rng.next(-150.0, 150.0),
            rng.next(-800.0, -500.0),
        );
        let r = rotation(pose.psi, pose.theta, pose.phi);
        let eye = pose.position() + r * Vector3::new(0.0, 0.0, -depth);
        let (x, y, z) = (r.column(0), r.column(1), r.column(2));
        let ahead = (-z).dot(&(p - eye));
        let u = x.dot(&(p - eye)) / ahead / tan;
        let v = y.dot(&(p - eye)) / ahead / (tan / (16.0 / 9.0));
        let frame = PlatformState::at_rest(pose).frame()?;
        let seen = camera.project(&frame, depth, &p);
        assert_eq!(seen.in_front, ahead > 0.0);
        if ahead > 1.0 {
            assert!(
                (seen.u - u).abs() < 1e-9 * (1.0 + u.abs()),
                "{} vs {u}",
                seen.u
            );
            assert!(
                (seen.v - v).abs() < 1e-9 * (1.0 + v.abs()),
                "{} vs {v}",
                seen.v
            );
            assert_eq!(seen.in_view(), u.abs() <= 1.0 && v.abs() <= 1.0);
        }
    }
    Ok(())
}

#[test]
fn the_image_edges_are_half_the_field_of_view_from_the_axis() -> Result {
    for (o, d) in [
        (0.0, 0.0),
        (30f64.to_radians(), 0.0),
        (30f64.to_radians(), 2.0),
    ] {
        let camera = Camera::new(70f64.to_radians(), 16.0 / 9.0, o, d)?;
        let axes = camera.axes();
        // Orthonormal, the view third: (u, v, -view) is right-handed, as
        // (X', Y', Z') is for a straight scope.
        assert!((axes.transpose() * axes - Matrix3::identity()).norm() < 1e-15);
        assert!((axes.determinant() + 1.0).abs() < 1e-15);
        assert!((camera.view() - view_local(o, d)).norm() < 1e-15);
        let pose = Pose::<f64>::paper_start();
        let frame = PlatformState::at_rest(pose).frame()?;
        let eye = Camera::eye(&frame, 50.0);
        let r = rotation(pose.psi, pose.theta, pose.phi);
        // 100 mm ahead, turned by half the horizontal field of view about
        // the image's v axis: on the right edge, u = 1, v = 0.
        let half = 35f64.to_radians();
        let (across, up, view) = (axes.column(0), axes.column(1), axes.column(2));
        let edge = eye + r * ((view * half.cos() + across * half.sin()) * 100.0);
        let seen = camera.project(&frame, 50.0, &edge);
        assert!(
            (seen.u - 1.0).abs() < 1e-12 && seen.v.abs() < 1e-12,
            "{seen:?}"
        );
        // The top edge: half the vertical field, tan(v) = tan(h) / aspect.
        let vhalf = (half.tan() * 9.0 / 16.0).atan();
        let top = eye + r * ((view * vhalf.cos() + up * vhalf.sin()) * 100.0);
        let seen = camera.project(&frame, 50.0, &top);
        assert!(
            seen.u.abs() < 1e-12 && (seen.v - 1.0).abs() < 1e-12,
            "{seen:?}"
        );
        assert!(seen.in_view());
        let behind = eye - r * (view * 10.0);
        assert!(!camera.project(&frame, 50.0, &behind).in_view());
    }
    Ok(())
}

/// Random reachable targets: a pose, a point on its view axis; the look-at
/// from another orientation nearby must find an aim as good, and no
/// farther from the start than the pose the target was made from.
fn random_targets(camera: &Camera<f64>, seed: u64, count: usize) -> Result<f64> {
    let mut rng = Rng(seed);
    let mut worst = 0.0_f64;
    for _ in 0..count {
        let aim = rng.pose(0.7);
        let depth = rng.next(0.0, 120.0);
        let r = rotation(aim.psi, aim.theta, aim.phi);
        let eye = aim.position() + r * Vector3::new(0.0, 0.0, -depth);
        let view = r * view_local(camera.oblique, camera.oblique_direction);
        let target = eye + view * rng.next(5.0, 200.0);
        let start = Pose {
            psi: aim.psi + rng.next(-0.3, 0.3),
            theta: aim.theta + rng.next(-0.3, 0.3),
            ..aim
        };
        let [psi, theta] = camera.look_at(&start, depth, &target)?;
        let found = Pose { psi, theta, ..aim };
        let e = residual(camera, &found, depth, &target);
        worst = worst.max(e);
        let d = |p: f64, t: f64| (p - start.psi).powi(2) + (t - start.theta).powi(2);
        assert!(
            d(psi, theta) <= d(aim.psi, aim.theta) * (1.0 + 1e-9) + 1e-24,
            "not the nearest: {psi} {theta} vs {} {}",
            aim.psi,
            aim.theta
        );
    }
    Ok(worst)
}

#[test]
fn look_at_aims_a_straight_scope_within_1e_12_rad() -> Result {
    let worst = random_targets(&Camera::assumed(), 11, 100_000)?;
    assert!(worst <= 1e-12, "{worst}");
    Ok(())
}

#[test]
fn look_at_aims_an_oblique_scope_within_1e_12_rad() -> Result {
    for (seed, d) in [(12, 0.0), (13, 1.0), (14, -2.5)] {
        let camera = Camera::new(70f64.to_radians(), 16.0 / 9.0, 30f64.to_radians(), d)?;
        let worst = random_targets(&camera, seed, 30_000)?;
        assert!(worst <= 1e-12, "direction {d}: {worst}");
    }
    Ok(())
}

#[test]
fn look_at_in_f32_is_within_its_precision() -> Result {
    let camera = Camera::<f32>::assumed();
    let pose = Pose::<f32>::paper_start();
    let target = Vector3::new(40.0_f32, 50.0, -650.0);
    let [psi, theta] = camera.look_at(&pose, 60.0, &target)?;
    let frame = PlatformState::at_rest(Pose { psi, theta, ..pose }).frame()?;
    let e = camera.aim_error(&frame, 60.0, &target);
    assert!(e < 2e-6, "{e}");
    Ok(())
}

#[test]
fn targets_that_cannot_be_looked_at_are_typed_errors() -> Result {
    let camera = Camera::<f64>::assumed();
    let pose = Pose::<f64>::paper_start();
    // 40 mm from the port with the endoscope 60 mm in: behind the camera.
    let near = pose.position() + Vector3::new(0.0, 0.0, -40.0);
    let e = camera.look_at(&pose, 60.0, &near);
    assert!(matches!(e, Err(CameraError::Behind { .. })), "{e:?}");
    // Straight along X from P: theta = +-90 deg.
    let side = pose.position() + Vector3::new(100.0, 0.0, 0.0);
    assert_eq!(camera.look_at(&pose, 0.0, &side), Err(CameraError::Gimbal));
    let nan = Vector3::new(f64::NAN, 0.0, -600.0);
    let e = camera.look_at(&pose, 60.0, &nan);
    assert!(
        matches!(
            e,
            Err(CameraError::NonFinite {
                what: "target.x",
                ..
            })
        ),
        "{e:?}"
    );
    for (h, a, o) in [
        (0.0, 1.0, 0.0),
        (4.0, 1.0, 0.0),
        (1.0, -1.0, 0.0),
        (1.0, 1.0, 1.6),
    ] {
        assert!(Camera::new(h, a, o, 0.0).is_err(), "{h} {a} {o}");
    }
    // A scope tilted 60 deg cannot look straight down its own port axis's
    // extension from a pose whose phi turns the tilt away, when the target
    // is near the port: the sphere of view directions misses it.
    let oblique = Camera::new(1.2, 1.0, 60f64.to_radians(), 0.0)?;
    let e = oblique.look_at(
        &pose,
        100.0,
        &(pose.position() + Vector3::new(0.0, 0.0, -30.0)),
    );
    assert!(e.is_err(), "{e:?}");
    let message = CameraError::Behind {
        distance_mm: 40.0,
        depth_mm: 60.0,
    }
    .to_string();
    assert!(
        message.contains("40 mm") && message.contains("60 mm in"),
        "{message}"
    );
    Ok(())
}

/// The twist about `axis` (a unit vector) of the rotation `r`, rad, in
/// `(-pi, pi]`: `r` written as a swing (about an axis across `axis`) after
/// a twist about `axis`, from its quaternion `(w, v)`, `2 atan2(v . axis,
/// w)`. A second way to the roll, through quaternions.
fn twist(r: &Matrix3<f64>, axis: &Vector3<f64>) -> f64 {
    use parasils_kin::nalgebra::{Rotation3, UnitQuaternion};
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
fn the_roll_is_the_twist_of_the_rotation_between_frames_about_the_start_view() {
    let mut rng = Rng(11);
    for oblique in [0.0, 30f64.to_radians()] {
        let camera = Camera {
            oblique,
            oblique_direction: 0.7,
            ..Camera::<f64>::assumed()
        };
        for _ in 0..2000 {
            let (a, b) = (rng.pose(0.8), rng.pose(0.8));
            let r0 = rotation(a.psi, a.theta, a.phi);
            let r1 = rotation(b.psi, b.theta, b.phi);
            let view = r0 * view_local(oblique, 0.7);
            let expected = twist(&(r1 * r0.transpose()), &view);
            let roll = camera.roll(&r0, &r1);
            let d = (roll - expected).abs();
            let d = d.min((2.0 * core::f64::consts::PI - d).abs());
            assert!(d < 1e-9, "roll {roll} vs twist {expected}");
        }
    }
}

#[test]
fn a_turn_about_phi_rolls_the_image_back_and_a_turn_across_the_view_not_at_all() {
    let camera = Camera::<f64>::assumed();
    let mut rng = Rng(5);
    for _ in 0..200 {
        let p = rng.pose(0.8);
        let r0 = rotation(p.psi, p.theta, p.phi);
        let d = rng.next(-1.0, 1.0);
        // phi turns the platform about Z' = -view: the image rolls by -d
        // about the view.
        let r1 = rotation(p.psi, p.theta, p.phi + d);
        assert!((camera.roll(&r0, &r1) + d).abs() < 1e-12);
        // theta alone turns about R_X(psi) Y, across the view: no roll.
        let r2 = rotation(p.psi, p.theta + d, p.phi);
        assert!(camera.roll(&r0, &r2).abs() < 1e-12);
    }
}
