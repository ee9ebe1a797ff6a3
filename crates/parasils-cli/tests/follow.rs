//! `procedures/follow-demo.toml`: the camera follows the tips. Its targets
//! are computed here from the CSV alone, each tip projected by a pinhole
//! written in this test (the assumed straight scope: 70 deg across, 16:9),
//! and compared with what `--check` reports.

mod common;

use std::path::PathBuf;

use common::process::parasils;
use common::table::Table;

fn follow_demo() -> String {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "procedures",
        "follow-demo.toml",
    ]
    .iter()
    .collect();
    path.to_string_lossy().into_owned()
}

/// `R = R_X(psi) R_Y(theta) R_Z(phi)` (angles in deg) applied to `c`.
fn rotate(angles_deg: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let [a, b, g] = angles_deg.map(f64::to_radians);
    // R_Z(phi), then R_Y(theta), then R_X(psi).
    let z = [
        g.cos() * c[0] - g.sin() * c[1],
        g.sin() * c[0] + g.cos() * c[1],
        c[2],
    ];
    let y = [
        b.cos() * z[0] + b.sin() * z[2],
        z[1],
        -b.sin() * z[0] + b.cos() * z[2],
    ];
    [
        y[0],
        a.cos() * y[1] - a.sin() * y[2],
        a.sin() * y[1] + a.cos() * y[2],
    ]
}

/// `R^T c`, through the columns of `R`.
fn unrotate(angles_deg: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let col = |k: usize| {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        rotate(angles_deg, e)
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    [dot(col(0), c), dot(col(1), c), dot(col(2), c)]
}

/// One row's camera: the eye `E = P + R (0, 0, -depth)` and the angles.
struct View {
    eye: [f64; 3],
    angles: [f64; 3],
}

impl View {
    fn of(t: &Table, k: usize) -> View {
        let angles = ["psi_deg", "theta_deg", "phi_deg"].map(|c| t.at(c, k));
        let p = ["x_mm", "y_mm", "z_mm"].map(|c| t.at(c, k));
        let d = rotate(angles, [0.0, 0.0, -t.at("endoscope_depth_mm", k)]);
        View {
            eye: [p[0] + d[0], p[1] + d[1], p[2] + d[2]],
            angles,
        }
    }

    /// `(u, v, ahead)` of `p`.
    fn project(&self, p: [f64; 3]) -> (f64, f64, bool) {
        let w = unrotate(
            self.angles,
            [p[0] - self.eye[0], p[1] - self.eye[1], p[2] - self.eye[2]],
        );
        let tan = 35f64.to_radians().tan();
        let ahead = -w[2];
        (
            w[0] / ahead / tan,
            w[1] / ahead / (tan * 9.0 / 16.0),
            ahead > 0.0,
        )
    }

    /// The angle between the view axis and the direction to `p`, deg.
    fn aim_error_deg(&self, p: [f64; 3]) -> f64 {
        let w = unrotate(
            self.angles,
            [p[0] - self.eye[0], p[1] - self.eye[1], p[2] - self.eye[2]],
        );
        let across = w[0].hypot(w[1]);
        across.atan2(-w[2]).to_degrees()
    }
}

fn tip(t: &Table, side: &str, k: usize) -> [f64; 3] {
    ["x", "y", "z"].map(|c| t.at(&format!("{side}_tip_{c}_mm"), k))
}

#[test]
fn the_follow_demo_keeps_both_tips_in_the_picture_and_settles_on_them() {
    let dir = tempfile::tempdir().expect("tempdir");
    parasils(&[
        "simulate",
        "--procedure",
        &follow_demo(),
        "-o",
        "follow.csv",
    ])
    .dir(dir.path())
    .run()
    .ok();
    let t = Table::read(&dir.path().join("follow.csv"));
    let (motion, motion_type) = (t.col("motion"), t.col("motion_type"));
    let (psi_rate, theta_rate) = (t.col("psi_rate_deg_s"), t.col("theta_rate_deg_s"));
    let (mut samples, mut in_view, mut central, mut settles) = (0usize, 0usize, 0usize, 0usize);
    let mut worst_aim_deg: f64 = 0.0;
    let mut turning = false;
    let mut followed = std::collections::BTreeSet::new();
    for k in 0..t.rows() {
        // The demo's following motions: the five wanders, 4 to 8.
        if !(motion[k] >= 4.0 && motion_type[k] == 3.0) {
            turning = false;
            continue;
        }
        followed.insert(motion[k] as u32);
        let view = View::of(&t, k);
        let seen = ["left", "right"].map(|s| view.project(tip(&t, s, k)));
        samples += 1;
        in_view += usize::from(
            seen.iter()
                .all(|&(u, v, a)| a && u.abs() <= 1.0 && v.abs() <= 1.0),
        );
        central += usize::from(
            seen.iter()
                .all(|&(u, v, a)| a && u.abs() <= 0.8 && v.abs() <= 0.8),
        );
        let now = psi_rate[k] != 0.0 || theta_rate[k] != 0.0;
        if turning && !now {
            let (l, r) = (tip(&t, "left", k), tip(&t, "right", k));
            let mid = [0, 1, 2].map(|i| 0.5 * (l[i] + r[i]));
            worst_aim_deg = worst_aim_deg.max(view.aim_error_deg(mid));
            settles += 1;
        }
        turning = now;
    }
    assert_eq!(followed.len(), 5);
    assert!(samples > 20_000);
    // Targets: both tips in view in every sample, in the central 80 % in
    // at least 99.9 %, the aim after every settling below 0.5 deg.
    assert_eq!(in_view, samples);
    assert!(
        central as f64 >= 0.999 * samples as f64,
        "{central} of {samples}"
    );
    assert!(settles >= 3, "{settles} settles");
    assert!(worst_aim_deg < 0.5, "aim error {worst_aim_deg} deg");
    // The check reports the same numbers.
    let report = parasils(&["simulate", "--procedure", &follow_demo(), "--check"])
        .run()
        .ok();
    let table: Vec<&str> = report
        .lines()
        .skip_while(|l| !l.starts_with("camera following the tips"))
        .skip(1)
        .take(5)
        .collect();
    assert_eq!(table.len(), 5, "{report}");
    let reported_settles: usize = table
        .iter()
        .map(|l| {
            l.split_whitespace()
                .nth(3)
                .and_then(|s| s.parse::<usize>().ok())
        })
        .sum::<Option<usize>>()
        .expect("settles");
    assert_eq!(reported_settles, settles, "{report}");
    for l in &table {
        assert_eq!(l.split_whitespace().nth(1), Some("100.000"), "{report}");
    }
}
