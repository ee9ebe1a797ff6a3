//! The ports, where the shafts and the endoscope cross the skin: their
//! positions in the records and in the CSV's columns against `P + R rcm`
//! computed here from the Euler angles, each motion's largest displacement
//! in the check, and the robot file's `port_motion_stop_mm`, exceeded and
//! not.

use nalgebra::{Matrix3, Vector3};
use parasils_sim::robot_file::{parse_robot, robot_to_toml_string};
use parasils_sim::{CsvSink, Record, Scenario, Simulation, SimulationError, Sink, procedure};

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

/// The ports of `r` from its pose: the RCMs at `(-+10, 0, 0)` mm in the
/// platform frame, the endoscope's at `P`.
fn ports(r: &Record) -> [Vector3<f64>; 3] {
    let p = Vector3::new(r.pose[0], r.pose[1], r.pose[2]);
    let rot = rotation(r.pose[3], r.pose[4], r.pose[5]);
    [
        p + rot * Vector3::new(-10.0, 0.0, 0.0),
        p + rot * Vector3::new(10.0, 0.0, 0.0),
        p,
    ]
}

fn demo() -> Scenario {
    procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))
    .expect("the demo loads")
}

fn robot_text(extra: &str) -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../robots/default.toml"
    ))
    .expect("robots/default.toml")
        + extra
}

#[test]
fn the_ports_are_where_the_rcms_and_p_are() {
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    let rs: Vec<Record> = sim.samples().map(|r| r.expect("runs")).collect();
    for r in rs.iter().step_by(250) {
        for (got, want) in r.ports.iter().zip(ports(r)) {
            assert!((got - want).norm() < 1e-9, "t = {}: {got} vs {want}", r.t);
        }
    }
    // The paper's turn: P stays, each RCM turns about it, 10 mm away, so it
    // moves by the chord 2 * 10 * sin(angle / 2) of the whole rotation.
    let (first, last) = (&rs[0], rs.last().expect("records"));
    let turn = rotation(last.pose[3], last.pose[4], last.pose[5])
        * rotation(first.pose[3], first.pose[4], first.pose[5]).transpose();
    let angle = ((turn.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
    assert_eq!((last.ports[2] - first.ports[2]).norm(), 0.0);
    for k in 0..2 {
        let moved = (last.ports[k] - first.ports[k]).norm();
        assert!(
            moved > 0.0 && moved <= 20.0 * (angle / 2.0).sin() + 1e-9,
            "{moved}"
        );
    }
}

#[test]
fn the_csv_s_port_columns_are_p_plus_r_times_the_offsets_of_its_own_pose() {
    // The demo procedure: the platform moves (`P` lowered 40 mm) and turns,
    // so every port moves, the endoscope's with `P`.
    let sim = Simulation::new(demo()).expect("valid");
    let mut sink = CsvSink::for_scenario(Vec::new(), sim.scenario()).expect("header");
    for r in sim.samples() {
        sink.push(&r.expect("runs")).expect("row");
    }
    let text = String::from_utf8(sink.finish().expect("flush")).expect("utf8");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let offsets = [
        ("left", Vector3::new(-10.0, 0.0, 0.0)),
        ("right", Vector3::new(10.0, 0.0, 0.0)),
        ("endoscope", Vector3::zeros()),
    ];
    let mut moved = [0.0_f64; 3];
    for row in rows.iter().step_by(997).chain(rows.last()) {
        let at = |name: &str| row[col(name)];
        let p = Vector3::new(at("x_mm"), at("y_mm"), at("z_mm"));
        let rot = rotation(
            at("psi_deg").to_radians(),
            at("theta_deg").to_radians(),
            at("phi_deg").to_radians(),
        );
        for (k, (body, offset)) in offsets.iter().enumerate() {
            let got = Vector3::new(
                at(&format!("{body}_port_x_mm")),
                at(&format!("{body}_port_y_mm")),
                at(&format!("{body}_port_z_mm")),
            );
            let want = p + rot * offset;
            assert!(
                (got - want).norm() < 1e-9,
                "t = {} s, {body}: {got} vs {want}",
                at("t_s")
            );
            let first = Vector3::new(
                rows[0][col(&format!("{body}_port_x_mm"))],
                rows[0][col(&format!("{body}_port_y_mm"))],
                rows[0][col(&format!("{body}_port_z_mm"))],
            );
            moved[k] = moved[k].max((got - first).norm());
        }
    }
    assert!(rows.len() > 5000, "{}", rows.len());
    assert!(moved.iter().all(|m| *m > 10.0), "{moved:?}");
}

#[test]
fn the_check_gives_each_motions_largest_port_displacement() {
    let sim = Simulation::new(demo()).expect("valid");
    let check = sim.procedure_check().expect("checked");
    let rs: Vec<Record> = sim.samples().map(|r| r.expect("runs")).collect();
    for (k, m) in check.motions.iter().enumerate() {
        let mine: Vec<&Record> = rs.iter().filter(|r| r.motion as usize == k).collect();
        let start = ports(mine[0]);
        for (p, (from, got)) in start.iter().zip(m.port_motion_mm).enumerate() {
            let largest = mine
                .iter()
                .map(|r| (ports(r)[p] - from).norm())
                .fold(0.0, f64::max);
            assert!(
                (got - largest).abs() < 1e-9,
                "motion {k}, port {p}: {got} vs {largest}"
            );
        }
    }
    // Motion 0 lowers the platform 40 mm without turning: every port moves
    // 40 mm. The endoscope's insertion (motion 1) moves none.
    for p in 0..3 {
        assert!((check.motions[0].port_motion_mm[p] - 40.0).abs() < 1e-9);
        assert_eq!(check.motions[1].port_motion_mm[p], 0.0);
    }
}

#[test]
fn a_port_limit_fails_the_paper_run_naming_the_port_and_passes_when_wide() {
    let robot =
        parse_robot(&robot_text("\n[supervisor]\nport_motion_stop_mm = 1.0\n")).expect("valid");
    assert_eq!(robot.supervisor.port_motion_stop_mm, Some(1.0));
    let text = robot_to_toml_string(&robot).expect("writes");
    assert_eq!(parse_robot(&text).expect("reads back"), robot);
    let sim = Simulation::new(Scenario {
        supervisor: robot.supervisor,
        ..Scenario::paper()
    })
    .expect("planned");
    let e = sim
        .samples()
        .find_map(Result::err)
        .expect("the ports move more than 1 mm");
    match &e {
        SimulationError::PortMotion {
            t,
            port,
            displacement_mm,
            stop_mm,
            ..
        } => {
            assert!(*t > 0.0 && *t < 4.5, "{t}");
            assert_ne!(*port, parasils::motions::Port::Endoscope);
            assert!(
                *displacement_mm > 1.0 && *displacement_mm < 1.1,
                "{displacement_mm}"
            );
            assert_eq!(*stop_mm, 1.0);
        }
        other => panic!("{other}"),
    }
    assert!(e.to_string().contains("port moved"), "{e}");
    // 10 mm: more than any port moves in the turn.
    let wide =
        parse_robot(&robot_text("\n[supervisor]\nport_motion_stop_mm = 10.0\n")).expect("valid");
    let sim = Simulation::new(Scenario {
        supervisor: wide.supervisor,
        ..Scenario::paper()
    })
    .expect("planned");
    assert!(sim.samples().all(|r| r.is_ok()));
}

#[test]
fn a_port_limit_fails_a_procedure_before_output_naming_the_motion() {
    let mut scenario = demo();
    scenario.supervisor.port_motion_stop_mm = Some(30.0);
    let e = Simulation::new(scenario).expect_err("motion 0 moves every port 40 mm");
    let SimulationError::Motion { motion, error, .. } = &e else {
        panic!("{e}")
    };
    assert_eq!(motion.index, 0);
    assert!(
        matches!(**error, SimulationError::PortMotion { displacement_mm, .. } if displacement_mm > 30.0 && displacement_mm < 30.1),
        "{e}"
    );
    let mut scenario = demo();
    scenario.supervisor.port_motion_stop_mm = Some(40.5);
    Simulation::new(scenario).expect("no port moves more than 40 mm in the demo");
}

#[test]
fn a_bad_port_limit_is_refused_with_its_key() {
    for bad in ["port_motion_stop_mm = -1.0", "port_motion_stop_mm = 0.0"] {
        let e = parse_robot(&robot_text(&format!("\n[supervisor]\n{bad}\n"))).expect_err(bad);
        assert!(e.to_string().contains("port_motion_stop_mm"), "{bad}: {e}");
    }
}
