//! Forbidden regions in a run: the `no_go_clearance_mm` of every record
//! against an independent computation, the stop before any output naming
//! the region and the body, and the anatomy given twice refused.
//!
//! The independent computation: each shaft's in-body part is the segment
//! from its tip (the record's) to its port (`P + R rcm`, `R` built here
//! from the Euler angles, the paper's ports at `x' = -10` and `+10` mm); a
//! sphere's gap is the distance from its centre to that segment (a
//! point-segment projection) minus both radii; a capsule region's the
//! distance between the two segments, minimised by ternary search over a
//! convex function, minus both radii. None of it calls parry.

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};
use parasils_anatomy::{Anatomy, Body, Region, Shape};
use parasils_sim::input::{Input, InputError, ProcedureSource};
use parasils_sim::{Record, Scenario, Simulation, SimulationError};

type V = Vector3<f64>;

fn rotation(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    let (sx, cx) = psi.sin_cos();
    let (sy, cy) = theta.sin_cos();
    let (sz, cz) = phi.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx);
    let ry = Matrix3::new(cy, 0.0, sy, 0.0, 1.0, 0.0, -sy, 0.0, cy);
    let rz = Matrix3::new(cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0);
    rx * ry * rz
}

fn point_segment(p: &V, a: &V, b: &V) -> f64 {
    let d = b - a;
    let s = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (p - (a + d * s)).norm()
}

fn segment_segment(a: (V, V), b: (V, V)) -> f64 {
    let f = |s: f64| point_segment(&(a.0 + (a.1 - a.0) * s), &b.0, &b.1);
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0))
}

/// The in-body segments of both shafts of `r`, tip to port.
fn shafts(r: &Record) -> [(V, V); 2] {
    let p = V::new(r.pose[0], r.pose[1], r.pose[2]);
    let rot = rotation(r.pose[3], r.pose[4], r.pose[5]);
    [(r.left.tip, -10.0), (r.right.tip, 10.0)].map(|(tip, x)| (tip, p + rot * V::new(x, 0.0, 0.0)))
}

const SHAFT_RADIUS: f64 = 2.5;
const BALL: ([f64; 3], f64) = ([40.0, -50.0, -640.0], 10.0);
const VESSEL: ([f64; 3], [f64; 3], f64) = ([-40.0, 60.0, -660.0], [40.0, 60.0, -660.0], 6.0);

fn anatomy() -> Arc<Anatomy> {
    let regions = vec![
        Region::new(
            "ball".into(),
            Shape::Sphere {
                centre_mm: BALL.0,
                radius_mm: BALL.1,
            },
        )
        .expect("valid"),
        Region::new(
            "vessel".into(),
            Shape::Capsule {
                start_mm: VESSEL.0,
                end_mm: VESSEL.1,
                radius_mm: VESSEL.2,
            },
        )
        .expect("valid"),
    ];
    Arc::new(Anatomy {
        file: "test.toml".into(),
        regions,
    })
}

fn independent(r: &Record) -> f64 {
    let vessel = (V::from(VESSEL.0), V::from(VESSEL.1));
    shafts(r)
        .iter()
        .flat_map(|s| {
            [
                point_segment(&V::from(BALL.0), &s.0, &s.1) - BALL.1 - SHAFT_RADIUS,
                segment_segment(*s, vessel) - VESSEL.2 - SHAFT_RADIUS,
            ]
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn every_record_s_no_go_clearance_matches_the_independent_computation() {
    let scenario = Scenario {
        anatomy: Some(anatomy()),
        ..Scenario::paper()
    };
    let sim = Simulation::new(scenario).expect("clear of both regions");
    let records: Vec<Record> = sim.samples().map(|r| r.expect("runs")).collect();
    let mut smallest = f64::INFINITY;
    for r in records.iter().step_by(97) {
        let want = independent(r);
        assert!(
            (r.no_go_clearance_mm - want).abs() < 1e-6,
            "t = {}: {} vs {want}",
            r.t,
            r.no_go_clearance_mm
        );
        smallest = smallest.min(want);
    }
    // Near enough to matter, clear of the stop threshold.
    assert!((0.5..20.0).contains(&smallest), "{smallest}");
    let plain = Simulation::new(Scenario::paper()).expect("valid");
    let columns = parasils_sim::no_go::csv_columns_of(plain.scenario());
    assert!(columns.iter().all(|c| c.name != "no_go_clearance_mm"));
    let columns = parasils_sim::no_go::csv_columns_of(sim.scenario());
    assert_eq!(columns.last().map(|c| c.name), Some("no_go_clearance_mm"));
}

#[test]
fn a_run_into_a_region_stops_before_any_record_naming_region_and_body() {
    // A ball 5 mm below the left tip: the shaft (2.5 mm radius) is inside
    // it from the start.
    let mut anatomy = (*anatomy()).clone();
    anatomy.regions[0] = Region::new(
        "ball".into(),
        Shape::Sphere {
            centre_mm: [50.0, -50.0, -625.0],
            radius_mm: 6.0,
        },
    )
    .expect("valid");
    let scenario = Scenario {
        anatomy: Some(Arc::new(anatomy)),
        ..Scenario::paper()
    };
    // Refused while planning, before any record exists.
    let Err(e) = Simulation::new(scenario) else {
        panic!("planned without a stop")
    };
    match &e {
        SimulationError::NoGo {
            region,
            body,
            gap_mm,
            stop_mm,
            t,
            ..
        } => {
            assert_eq!(
                (region.as_str(), *body, *stop_mm),
                ("ball", Body::Left, 0.5)
            );
            // Minus the depth: 5 - 6 - 2.5, at the first sample.
            assert!((*gap_mm + 3.5).abs() < 1e-9 && *t == 0.0, "{e}");
        }
        e => panic!("{e}"),
    }
}

#[test]
fn an_anatomy_given_with_a_procedure_that_names_one_is_refused() {
    let dir = tempfile::tempdir().expect("dir");
    let region =
        "[[region]]\nname = \"b\"\nshape = \"sphere\"\ncentre_mm = [0, 0, -900]\nradius_mm = 1\n";
    std::fs::write(dir.path().join("a.toml"), region).expect("write");
    let procedure =
        "anatomy = \"a.toml\"\n[[motion]]\ntype = \"reorient\"\npsi_deg = 1\ntheta_deg = 1\n";
    std::fs::write(dir.path().join("p.toml"), procedure).expect("write");
    let by_file = Input {
        procedure: Some(ProcedureSource::File(dir.path().join("p.toml"))),
        ..Input::default()
    }
    .resolve()
    .expect("reads");
    assert_eq!(by_file.anatomy.as_ref().map(|a| a.regions.len()), Some(1));
    let twice = Input {
        procedure: Some(ProcedureSource::File(dir.path().join("p.toml"))),
        anatomy: Some(dir.path().join("a.toml")),
        ..Input::default()
    }
    .resolve();
    assert!(matches!(twice, Err(InputError::AnatomyTwice)), "{twice:?}");
}

/// The `required` fields of `pointer` in the SceneUpdate schema the crate
/// embeds.
fn required(schema: &serde_json::Value, pointer: &str) -> Vec<String> {
    schema
        .pointer(pointer)
        .and_then(|v| v["required"].as_array())
        .map(|a| {
            a.iter()
                .filter_map(|s| s.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_else(|| panic!("no {pointer} in the schema"))
}

#[test]
fn the_mcap_scene_draws_each_region_once_with_its_shape_and_place() {
    use parasils_anatomy::Mesh;
    use parasils_sim::mcap::SCENE_TOPIC;
    use parasils_sim::{McapOptions, McapSink};
    let tetra = Mesh::new(
        vec![
            [0.0, 0.0, -900.0],
            [10.0, 0.0, -900.0],
            [0.0, 10.0, -900.0],
            [0.0, 0.0, -890.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
    .expect("a tetrahedron");
    let shapes = [
        Shape::Sphere {
            centre_mm: [0.0, 0.0, -800.0],
            radius_mm: 20.0,
        },
        Shape::Box {
            centre_mm: [100.0, 0.0, -800.0],
            half_extents_mm: [10.0, 20.0, 30.0],
            rotation_deg: [30.0, -20.0, 60.0],
        },
        Shape::Capsule {
            start_mm: [0.0, 100.0, -800.0],
            end_mm: [30.0, 140.0, -800.0],
            radius_mm: 5.0,
        },
        Shape::Mesh {
            file: "t.stl".into(),
            translation_mm: [0.0; 3],
            solid: tetra.is_closed(),
            mesh: tetra,
        },
    ];
    let regions = shapes
        .into_iter()
        .enumerate()
        .map(|(k, s)| Region::new(format!("r\"{k}"), s).expect("valid"))
        .collect();
    let scenario = Scenario {
        rate_hz: 50.0,
        anatomy: Some(Arc::new(Anatomy {
            file: "a.toml".into(),
            regions,
        })),
        ..Scenario::paper()
    };
    let sim = Simulation::new(scenario).expect("clear");
    let mut sink = McapSink::with_options(
        std::io::Cursor::new(Vec::new()),
        sim.scenario(),
        McapOptions::default(),
    )
    .expect("sink");
    sim.run(&mut sink).expect("runs");
    let bytes = sink.finish().expect("finish").into_inner();
    let schema: serde_json::Value =
        serde_json::from_str(include_str!("../schemas/SceneUpdate.json")).expect("the schema");
    let entity_keys = required(&schema, "/properties/entities/items");
    let mut drawn = Vec::new();
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        if m.channel.topic != SCENE_TOPIC {
            continue;
        }
        let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
        for e in v["entities"].as_array().expect("entities") {
            if e["id"].as_str().is_some_and(|id| id.starts_with("no_go_")) {
                for key in &entity_keys {
                    assert!(e.get(key).is_some(), "{key} missing");
                }
                drawn.push(e.clone());
            }
        }
    }
    assert_eq!(drawn.len(), 4, "each region drawn once");
    let mm = |v: &serde_json::Value| {
        V::new(
            v["x"].as_f64().expect("x"),
            v["y"].as_f64().expect("y"),
            v["z"].as_f64().expect("z"),
        ) * 1e3
    };
    let close = |a: V, b: V| (a - b).norm() < 1e-9;
    assert_eq!(drawn[0]["metadata"][0]["value"], "r\"0");
    let ball = &drawn[0]["spheres"][0];
    assert!(close(
        mm(&ball["pose"]["position"]),
        V::new(0.0, 0.0, -800.0)
    ));
    assert!(close(mm(&ball["size"]), V::repeat(40.0)));
    // The box: its orientation turns its own axes as R_X R_Y R_Z does.
    let cube = &drawn[1]["cubes"][0];
    assert!(close(mm(&cube["size"]), V::new(20.0, 40.0, 60.0)));
    let o = &cube["pose"]["orientation"];
    let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        o["w"].as_f64().expect("w"),
        o["x"].as_f64().expect("x"),
        o["y"].as_f64().expect("y"),
        o["z"].as_f64().expect("z"),
    ));
    let r = rotation(
        30f64.to_radians(),
        (-20f64).to_radians(),
        60f64.to_radians(),
    );
    assert!((q.to_rotation_matrix().into_inner() - r).norm() < 1e-12);
    // The capsule: a cylinder along its axis, a ball at each end.
    let cyl = &drawn[2]["cylinders"][0];
    assert!(close(mm(&cyl["size"]), V::new(10.0, 10.0, 50.0)));
    assert!(close(
        mm(&cyl["pose"]["position"]),
        V::new(15.0, 120.0, -800.0)
    ));
    assert_eq!(drawn[2]["spheres"].as_array().map(Vec::len), Some(2));
    for key in required(
        &schema,
        "/properties/entities/items/properties/cylinders/items",
    ) {
        assert!(cyl.get(&key).is_some(), "{key}");
    }
    // The mesh: its four vertices once, three indices a triangle.
    let tri = &drawn[3]["triangles"][0];
    assert_eq!(tri["points"].as_array().map(Vec::len), Some(4));
    assert_eq!(tri["indices"].as_array().map(Vec::len), Some(12));
    assert!(close(mm(&tri["points"][3]), V::new(0.0, 0.0, -890.0)));
    assert!(
        drawn
            .iter()
            .all(|e| e["lifetime"]["sec"] == 0 && e["lifetime"]["nsec"] == 0)
    );
}

/// An online run (a turn to `psi = -30`, `theta = 10` deg, then the same
/// goal commanded again at 0.3 s) with the right tip moved by `(60, -40, 40)` mm from the default so
/// that the shafts and the endoscope stay clear of each other; with
/// `regions`, the anatomy, and with `watched`, the robot file's clearance
/// thresholds (warn 2 mm, stop 0.5 mm).
fn online(regions: Option<Arc<Anatomy>>, watched: bool) -> Vec<Record> {
    let g = [-30.0, 10.0];
    let right = parasils::kin::TipTargets::<f64>::paper().right + V::new(60.0, -40.0, 40.0);
    let mut scenario = Input {
        psi_deg: Some(g[0]),
        theta_deg: Some(g[1]),
        tip_right_mm: Some([right.x, right.y, right.z]),
        retarget: Some(vec![parasils_sim::scenario::Retarget {
            t_s: 0.3,
            psi_deg: g[0],
            theta_deg: g[1],
        }]),
        ..Input::default()
    }
    .resolve()
    .expect("an online run");
    scenario.anatomy = regions;
    if watched {
        scenario.supervisor.clearance_warn_mm = Some(2.0);
        scenario.supervisor.clearance_stop_mm = Some(0.5);
    }
    let sim = Simulation::new(scenario).expect("planned");
    sim.samples().map(|r| r.expect("runs")).collect()
}

/// The gap from the left shaft of `r` to the sphere `(c, radius)`, mm.
fn ball_gap(r: &Record, c: &V, radius: f64) -> f64 {
    let [left, _] = shafts(r);
    point_segment(c, &left.0, &left.1) - radius - SHAFT_RADIUS
}

#[test]
fn an_online_run_stops_ahead_of_a_forbidden_region() {
    // The turn without regions: the left port sweeps 1.2 mm across the
    // shaft while the tip holds. A 20 mm ball on the side the port moves
    // to, 0.1 mm into the shaft's last position at its port.
    let free = online(None, false);
    let (first, last) = (&free[0], free.last().expect("records"));
    let (start, end) = (shafts(first)[0], shafts(last)[0]);
    let axis = (end.1 - end.0).normalize();
    let sweep = (end.1 - start.1) - axis * axis.dot(&(end.1 - start.1));
    assert!(sweep.norm() > 1.0, "the port moves {} mm", sweep.norm());
    let radius = 20.0;
    let centre = end.1 + sweep.normalize() * (radius + SHAFT_RADIUS - 0.1);
    let ball = Arc::new(Anatomy {
        file: "test.toml".into(),
        regions: vec![
            Region::new(
                "ball".into(),
                Shape::Sphere {
                    centre_mm: centre.into(),
                    radius_mm: radius,
                },
            )
            .expect("valid"),
        ],
    });
    let (at_start, at_end) = (
        ball_gap(first, &centre, radius),
        ball_gap(last, &centre, radius),
    );
    assert!(at_start > 0.8 && at_end < 0.0, "{at_start} {at_end}");
    // The pairs never come near their threshold on this turn: whatever
    // stops the watched run is the region.
    let pairs = free
        .iter()
        .map(|r| {
            r.clearance
                .left_right
                .min(r.clearance.left_endoscope)
                .min(r.clearance.right_endoscope)
        })
        .fold(f64::INFINITY, f64::min);
    assert!(pairs > 1.0, "{pairs}");

    // Recorded but not watched without the thresholds: the shaft enters.
    let recorded = online(Some(ball.clone()), false);
    let deepest = recorded
        .iter()
        .map(|r| ball_gap(r, &centre, radius))
        .fold(f64::INFINITY, f64::min);
    assert!(deepest < 0.0, "{deepest}");
    assert!(
        recorded
            .iter()
            .all(|r| r.kind != parasils_sim::scenario::CommandKind::SupervisorStop)
    );

    // Watched: the controller stops ahead of the stop threshold, every
    // record's gap (computed here) at or above it and equal to its column.
    let held = online(Some(ball), true);
    assert!(
        held.iter()
            .any(|r| r.kind == parasils_sim::scenario::CommandKind::SupervisorStop)
    );
    for r in &held {
        let gap = ball_gap(r, &centre, radius);
        assert!(gap >= 0.5 - 1e-9, "t = {}: {gap}", r.t);
        assert!(
            (r.no_go_clearance_mm - gap).abs() < 1e-6,
            "t = {}: {} vs {gap}",
            r.t,
            r.no_go_clearance_mm
        );
    }
    // Stopped short, after closing in.
    let end = held.last().expect("records");
    let last_gap = ball_gap(end, &centre, radius);
    assert!(last_gap < at_start - 0.1, "{last_gap} from {at_start}");
}
