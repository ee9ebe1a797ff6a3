//! `parasils simulate --look-at`: the turn given by what the camera looks
//! at, checked on the CSV it writes (the view axis through the target at
//! the end, by a pinhole written here), and its refusals.

mod common;

use common::process::{fails, ok, parasils};
use common::table::Table;

/// `R = R_X(psi) R_Y(theta) R_Z(phi)` of the angles in deg, written out
/// here, as rows.
fn rotation(psi: f64, theta: f64, phi: f64) -> [[f64; 3]; 3] {
    let (psi, theta, phi) = (psi.to_radians(), theta.to_radians(), phi.to_radians());
    let (s1, c1, s2, c2, s3, c3) = (
        psi.sin(),
        psi.cos(),
        theta.sin(),
        theta.cos(),
        phi.sin(),
        phi.cos(),
    );
    [
        [c2 * c3, -c2 * s3, s2],
        [c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2],
        [s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2],
    ]
}

/// The angle (rad) at row `k` between the straight scope's view `-Z'` from
/// `P` (the endoscope at its port) and the direction to `target`.
fn aim(t: &Table, k: usize, target: [f64; 3]) -> f64 {
    let v = |name: &str| t.col(name)[k];
    let r = rotation(v("psi_deg"), v("theta_deg"), v("phi_deg"));
    let view = [-r[0][2], -r[1][2], -r[2][2]];
    let d = [
        target[0] - v("x_mm"),
        target[1] - v("y_mm"),
        target[2] - v("z_mm"),
    ];
    let cross = [
        view[1] * d[2] - view[2] * d[1],
        view[2] * d[0] - view[0] * d[2],
        view[0] * d[1] - view[1] * d[0],
    ];
    let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let dot = view[0] * d[0] + view[1] * d[1] + view[2] * d[2];
    norm(cross).atan2(dot)
}

#[test]
fn look_at_a_point_ends_with_the_view_axis_through_it_under_both_timings() {
    for timing in ["trapezoid", "optimal"] {
        let out = ok(&[
            "simulate",
            "--look-at",
            "40,50,-650",
            "--timing",
            timing,
            "--rate",
            "200",
            "-o",
            "-",
        ]);
        let t = Table::parse(&out);
        let last = t.rows() - 1;
        let target = [40.0, 50.0, -650.0];
        assert!(aim(&t, 0, target) > 0.05, "{timing}: aimed at the start");
        assert!(aim(&t, last, target) < 1e-11, "{timing}");
        let err = t.col("camera_aim_error_deg")[last];
        assert!(err < 1e-9, "{timing}: {err} deg");
        assert!((t.col("camera_aim_error_deg")[0] - aim(&t, 0, target).to_degrees()).abs() < 1e-9);
        // phi held, the tips held.
        let phi = t.col("phi_deg");
        assert!(phi.iter().all(|p| *p == phi[0]));
        for side in ["left", "right"] {
            let e = t.col(&format!("{side}_tip_err_mm"));
            assert!(e.iter().all(|e| *e < 1e-9), "{side}");
        }
    }
}

#[test]
fn look_at_the_tips_centres_their_midpoint_in_the_image() {
    let out = ok(&["simulate", "--look-at", "tips", "--rate", "100", "-o", "-"]);
    let t = Table::parse(&out);
    let last = t.rows() - 1;
    assert!(t.col("camera_aim_error_deg")[last] < 1e-9);
    let mid_u = 0.5 * (t.col("left_tip_u")[last] + t.col("right_tip_u")[last]);
    let mid_v = 0.5 * (t.col("left_tip_v")[last] + t.col("right_tip_v")[last]);
    // The midpoint of the two image points is not the image of the
    // midpoint (perspective), but close to the centre.
    assert!(mid_u.abs() < 0.2 && mid_v.abs() < 0.2, "{mid_u} {mid_v}");
    assert_eq!(t.text("left_tip_in_view")[last], "1.0");
}

#[test]
fn look_at_with_angles_or_commands_is_refused_in_one_line() {
    let e = fails(&["simulate", "--look-at", "tips", "--psi", "10"]);
    assert!(e.contains("--look-at cannot be given with --psi"), "{e}");
    let e = fails(&["simulate", "--look-at", "left", "--stop-at", "1"]);
    assert!(
        e.contains("--look-at cannot be given with --stop-at"),
        "{e}"
    );
    // A value clap cannot read: its usual error, naming what it takes.
    let e = parasils(&["simulate", "--look-at", "1,2"]).run().fails();
    assert!(
        e.contains("expected tips, left, right or a point X,Y,Z"),
        "{e}"
    );
}
