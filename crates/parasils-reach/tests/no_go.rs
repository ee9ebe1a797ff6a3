//! The forbidden regions among the reach map's constraints: a sphere
//! placed, from the geometry computed here, against the left shaft's
//! in-body part at one cell of the grid limits exactly the cells where an
//! independent distance (the sphere's centre to the segment from the held
//! tip to the port `P + R (-10, 0, 0)`, written out here) leaves less than
//! the stop threshold, with the code `no_go.<region name>`; without the
//! anatomy the map is unchanged.

use std::sync::Arc;

use parasils::kin::nalgebra::{Matrix3, Vector3};
use parasils_anatomy::{Anatomy, Region, Shape};
use parasils_reach::{Constraint, ReachMap, ReachOptions};
use parasils_sim::Scenario;

/// The sphere's radius, mm.
const SPHERE_MM: f64 = 5.0;
/// The shafts' radius, mm (the assumed 5 mm diameter of `[bodies]`).
const SHAFT_MM: f64 = 2.5;
/// The stop threshold without a robot file's, mm.
const STOP_MM: f64 = 0.5;

/// `R = R_X(psi) R_Y(theta) R_Z(phi)`, written out.
fn rotation(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    let (sx, cx) = psi.sin_cos();
    let (sy, cy) = theta.sin_cos();
    let (sz, cz) = phi.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx);
    let ry = Matrix3::new(cy, 0.0, sy, 0.0, 1.0, 0.0, -sy, 0.0, cy);
    let rz = Matrix3::new(cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0);
    rx * ry * rz
}

/// The in-body part of the `side` shaft (-1 left, +1 right) at
/// `(dpsi, dtheta)` deg from the start: from its held tip to its port.
fn in_body(s: &Scenario, side: f64, dpsi: f64, dtheta: f64) -> (Vector3<f64>, Vector3<f64>) {
    let [x, y, z, psi, theta, phi] = s.start_mm_deg;
    let r = rotation(
        (psi + dpsi).to_radians(),
        (theta + dtheta).to_radians(),
        phi.to_radians(),
    );
    let port = Vector3::new(x, y, z) + r * Vector3::new(10.0 * side, 0.0, 0.0);
    let tips = s.tips();
    let tip = if side < 0.0 { tips.left } else { tips.right };
    (tip, port)
}

/// The distance from `c` to the segment `a`-`b`.
fn to_segment(c: &Vector3<f64>, (a, b): (Vector3<f64>, Vector3<f64>)) -> f64 {
    let d = b - a;
    let s = ((c - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (c - (a + d * s)).norm()
}

/// The smallest gap of either shaft's in-body part to the sphere at `c`.
fn gap(s: &Scenario, c: &Vector3<f64>, dpsi: f64, dtheta: f64) -> f64 {
    [-1.0, 1.0]
        .map(|side| to_segment(c, in_body(s, side, dpsi, dtheta)) - SHAFT_MM - SPHERE_MM)
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

/// A sphere just touching the left shaft's in-body part at `(15, 20)` deg,
/// on the side away from where that part is at the start: the turn
/// towards that cell brings the shaft into it.
fn sphere(s: &Scenario) -> Vector3<f64> {
    let (a, b) = in_body(s, -1.0, 15.0, 20.0);
    let (a0, b0) = in_body(s, -1.0, 0.0, 0.0);
    let axis = (b - a).normalize();
    let away = (a + b - a0 - b0) * 0.5;
    let n = (away - axis * away.dot(&axis)).normalize();
    (a + b) * 0.5 + n * (SHAFT_MM + SPHERE_MM)
}

fn with_sphere(s: &Scenario, centre: &Vector3<f64>) -> Scenario {
    let shape = Shape::Sphere {
        centre_mm: [centre.x, centre.y, centre.z],
        radius_mm: SPHERE_MM,
    };
    let region = |name: &str, shape| Region::new(name.into(), shape).expect("region");
    // A second region far from everything, never limiting: the codes
    // follow the file's order.
    let far = Shape::Sphere {
        centre_mm: [0.0, 0.0, 500.0],
        radius_mm: 1.0,
    };
    Scenario {
        anatomy: Some(Arc::new(Anatomy {
            file: "organs.toml".into(),
            regions: vec![region("gallbladder", shape), region("far", far)],
        })),
        ..s.clone()
    }
}

#[test]
fn exactly_the_cells_the_sphere_comes_too_close_to_carry_its_code() {
    let plain = Scenario::paper();
    let centre = sphere(&plain);
    let s = with_sphere(&plain, &centre);
    let options = ReachOptions {
        psi_range_deg: [-10.0, 20.0],
        theta_range_deg: [-10.0, 25.0],
        step_deg: 2.5,
        line: false,
        threads: 1,
        deflection_load_n: None,
    };
    let map = ReachMap::compute(&s, &options).expect("map");
    let free = ReachMap::compute(&plain, &options).expect("map");
    assert_eq!(map.regions, ["gallbladder", "far"]);
    assert!(free.regions.is_empty());
    let mut limited = 0;
    for (k, (cell, other)) in map.cells.iter().zip(&free.cells).enumerate() {
        let (c, r) = (k % map.psi.count, k / map.psi.count);
        let (dpsi, dtheta) = (map.psi.value_deg(c), map.theta.value_deg(r));
        if !other.feasible {
            // The kinematics fail: the same constraint with the anatomy.
            assert_eq!(cell.limiting, other.limiting, "({dpsi}, {dtheta})");
            continue;
        }
        let g = gap(&s, &centre, dpsi, dtheta);
        assert!((g - STOP_MM).abs() > 1e-6, "a cell on the threshold: {g}");
        let code = map.code(cell.limiting);
        if g < STOP_MM {
            assert_eq!(
                cell.limiting,
                Constraint::NoGo(0),
                "({dpsi}, {dtheta}): {g}"
            );
            assert_eq!(code, "no_go.gallbladder");
            // Normalised by the shaft's radius.
            assert!(
                (cell.margin - (g - STOP_MM) / SHAFT_MM).abs() < 1e-6,
                "({dpsi}, {dtheta}): {} vs {g}",
                cell.margin
            );
            limited += 1;
        } else {
            assert!(cell.feasible, "({dpsi}, {dtheta}): {code} at {g} mm");
            assert!(cell.margin <= (g - STOP_MM) / SHAFT_MM + 1e-6);
        }
    }
    let feasible = free.cells.iter().filter(|c| c.feasible).count();
    assert!(
        limited >= 3 && limited < feasible / 2,
        "{limited} of {feasible}"
    );
    assert!(map.cells[map.start_index()].feasible);
    assert!(
        !map.cells[map.index(10, 12)].feasible,
        "the (15, 20) deg cell"
    );
    // The CSV and the summary write the region's name.
    let mut csv = Vec::new();
    parasils_reach::csv::write(&map, &mut csv).expect("writes");
    let text = String::from_utf8(csv).expect("utf8");
    assert_eq!(
        text.lines()
            .filter(|l| l.contains(",no_go.gallbladder,"))
            .count(),
        limited
    );
    assert_eq!(map.code(Constraint::NoGo(1)), "no_go.far");
    assert_eq!(
        Constraint::from_code_in("no_go.gallbladder", &map.regions),
        Some(Constraint::NoGo(0))
    );
}

#[test]
fn a_robot_file_s_stop_threshold_moves_the_limit() {
    // 3 mm instead of 0.5: more cells limited, each where the gap is below
    // 3 mm.
    let plain = Scenario::paper();
    let centre = sphere(&plain);
    let mut s = with_sphere(&plain, &centre);
    s.supervisor.clearance_stop_mm = Some(3.0);
    s.supervisor.clearance_warn_mm = Some(4.0);
    let options = ReachOptions {
        psi_range_deg: [0.0, 20.0],
        theta_range_deg: [0.0, 25.0],
        step_deg: 5.0,
        line: false,
        threads: 1,
        deflection_load_n: None,
    };
    let map = ReachMap::compute(&s, &options).expect("map");
    for (k, cell) in map.cells.iter().enumerate() {
        let (c, r) = (k % map.psi.count, k / map.psi.count);
        let (dpsi, dtheta) = (map.psi.value_deg(c), map.theta.value_deg(r));
        let g = gap(&s, &centre, dpsi, dtheta);
        if matches!(cell.limiting, Constraint::NoGo(_)) {
            assert!(g < 3.0, "({dpsi}, {dtheta}): {g}");
        } else if cell.feasible {
            assert!(g >= 3.0, "({dpsi}, {dtheta}): {g}");
        }
    }
}
