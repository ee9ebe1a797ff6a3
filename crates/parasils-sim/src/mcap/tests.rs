//! The MCAP writer read back: counts, schemas, times, metadata, the 3D
//! messages, and the errors.

use std::collections::HashMap;
use std::io::Cursor;

use nalgebra::Vector3;
use parasils::kin::{Joints, Pose, Side};

use mcap::records::Metadata;

use super::*;
use crate::columns::{self, Channel};
use crate::engine::Simulation;
use crate::scenario::Scenario;
use crate::sink::Sink;

/// The paper's scenario at `rate_hz`.
fn scenario(rate_hz: f64) -> Scenario {
    Scenario {
        rate_hz,
        ..Scenario::paper()
    }
}

/// Runs `scenario` into an in-memory MCAP.
fn write(scenario: &Scenario, options: McapOptions) -> (Vec<u8>, usize) {
    let sim = Simulation::new(scenario.clone()).expect("valid scenario");
    let mut sink =
        McapSink::with_options(Cursor::new(Vec::new()), sim.scenario(), options).expect("new");
    sim.run(&mut sink).expect("run");
    (
        sink.finish().expect("finish").into_inner(),
        sim.sample_count(),
    )
}

#[test]
fn reads_back_with_counts_schemas_times_and_metadata() {
    let sc = scenario(100.0);
    let (bytes, n) = write(&sc, McapOptions::default());
    assert_eq!(n, 451);

    let summary = mcap::Summary::read(&bytes)
        .expect("summary readable")
        .expect("summary present");
    let stats = summary.stats.as_ref().expect("statistics");
    assert!(!summary.chunk_indexes.is_empty());
    assert!(
        summary
            .chunk_indexes
            .iter()
            .all(|c| !c.message_index_offsets.is_empty()),
        "message indexes"
    );
    assert_eq!(stats.metadata_count, 2);

    let mut per_topic: HashMap<String, Vec<(u64, serde_json::Value)>> = HashMap::new();
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        assert_eq!(m.channel.message_encoding, "json");
        let schema = m.channel.schema.as_ref().expect("schema");
        assert_eq!(schema.encoding, "jsonschema");
        assert_eq!(m.log_time, m.publish_time);
        let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON message");
        per_topic
            .entry(m.channel.topic.clone())
            .or_default()
            .push((m.log_time, v));
    }
    for (k, topic) in SAMPLE_TOPICS.iter().enumerate() {
        let msgs = &per_topic[*topic];
        assert_eq!(msgs.len(), n, "{topic}");
        let ch = summary
            .channels
            .values()
            .find(|c| c.topic == *topic)
            .expect("channel");
        assert_eq!(stats.channel_message_counts[&ch.id], n as u64);
        let schema: serde_json::Value =
            serde_json::from_slice(&ch.schema.as_ref().expect("schema").data).expect("schema");
        assert_eq!(schema["title"], Channel::ALL[k].schema_name());
        assert_eq!(schema["additionalProperties"], false);
        let required = schema["required"].as_array().expect("required");
        for (j, (ns, v)) in msgs.iter().enumerate() {
            let obj = v.as_object().expect("object");
            assert_eq!(obj.len(), required.len());
            assert!(
                required
                    .iter()
                    .all(|f| obj[f.as_str().expect("name")].is_f64())
            );
            let t = obj["t_s"].as_f64().expect("t_s");
            assert_eq!(t.to_bits(), (j as f64 / 100.0).to_bits());
            assert_eq!(*ns, (t * 1e9).round() as u64);
        }
    }
    // The data agree with the CSV row to the last bit.
    let sim = Simulation::new(sc.clone()).expect("valid");
    let r100 = sim.samples().nth(100).expect("a record").expect("ok");
    let row = columns::csv_row(&r100);
    for topic in SAMPLE_TOPICS {
        let obj = per_topic[topic][100].1.as_object().expect("object").clone();
        for (name, v) in obj {
            let value = v.as_f64().expect("number");
            if let Some(c) = columns::CSV_NAMES.iter().position(|c| *c == name) {
                assert_eq!(value.to_bits(), row[c].to_bits(), "{name}");
            }
        }
    }
    assert_eq!(
        per_topic["/tips"][100].1["left_tip_z_mm"].as_f64(),
        Some(r100.left.tip.z)
    );

    // /tf and /scene: the first record, every 20 ms, the last.
    let tf = &per_topic[TF_TOPIC];
    assert_eq!(tf.len(), 226);
    assert_eq!(tf[0].0, 0);
    assert_eq!(tf[1].0, 20_000_000);
    assert_eq!(tf.last().map(|m| m.0), Some(4_500_000_000));
    assert_eq!(per_topic[SCENE_TOPIC].len(), tf.len());

    // Metadata.
    let by_name: HashMap<String, Metadata> = summary
        .metadata_indexes
        .iter()
        .map(|i| {
            let m = mcap::read::metadata(&bytes, i).expect("metadata");
            (m.name.clone(), m)
        })
        .collect();
    let sc_meta = &by_name[SCENARIO_METADATA].metadata;
    let scen: serde_json::Value = serde_json::from_str(&sc_meta["scenario"]).expect("json");
    assert_eq!(scen["rate_hz"], 100.0);
    assert_eq!(scen["psi"], 15f64.to_radians());
    assert_eq!(scen["start"]["psi"], (-15f64).to_radians());
    assert_eq!(scen["tip_left"], serde_json::json!([50.0, -50.0, -620.0]));
    let geo: serde_json::Value = serde_json::from_str(&sc_meta["geometry"]).expect("json");
    assert_eq!(geo["link_lengths_mm"][0], 350.0);
    assert!(sc_meta["module1_geometry"].starts_with("assumed"));
    let bodies: serde_json::Value = serde_json::from_str(&sc_meta["bodies_mm"]).expect("json");
    assert_eq!(bodies["instrument_diameter"], 5.0);
    assert_eq!(bodies["endoscope_length"], 400.0);
    let run = &by_name[RUN_METADATA].metadata;
    assert_eq!(run["samples"], "451");
    assert_eq!(run["t_last_s"], "4.5");
}

#[test]
fn the_frames_put_the_tool_tip_on_the_recomputed_tip() {
    let sim = Simulation::new(scenario(10.0)).expect("valid");
    let g = SceneGeometry::from_robot(&sim.scenario().robot).expect("valid");
    for r in sim.samples() {
        let r = r.expect("ok");
        let pose = Pose::from_array(r.pose);
        for (side, m, k) in [(Side::Left, &r.left, 0), (Side::Right, &r.right, 1)] {
            let q = Joints::new(m.q[0], m.q[1], m.q[2]);
            let tool = g.tool_rotation(side, &q);
            let local = Vector3::from(g.rcms_mm[k]) + tool * Vector3::new(0.0, 0.0, -m.q[2]);
            let world = pose.position() + pose.rotation() * local;
            assert!((world - m.tip).norm() < 1e-9, "{side:?} at {}", r.t);
            assert!((tool.determinant() - 1.0).abs() < 1e-12);
        }
    }
}

#[test]
fn scene_and_tf_follow_the_official_shapes() {
    let (bytes, _) = write(
        &scenario(50.0),
        McapOptions {
            scene_period_s: 0.0,
            ..McapOptions::default()
        },
    );
    let mut scenes = 0;
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
        match m.channel.topic.as_str() {
            TF_TOPIC => {
                assert_eq!(
                    m.channel.schema.as_ref().map(|s| s.name.as_str()),
                    Some("foxglove.FrameTransforms")
                );
                let tr = v["transforms"].as_array().expect("transforms");
                assert_eq!(tr.len(), 6);
                let q = &tr[0]["rotation"];
                let norm: f64 = ["x", "y", "z", "w"]
                    .iter()
                    .map(|c| q[c].as_f64().expect("number").powi(2))
                    .sum();
                assert!((norm - 1.0).abs() < 1e-12);
                assert_eq!(
                    tr[0]["timestamp"]["sec"].as_u64().expect("sec") * 1_000_000_000
                        + tr[0]["timestamp"]["nsec"].as_u64().expect("nsec"),
                    m.log_time
                );
            }
            SCENE_TOPIC => {
                scenes += 1;
                assert_eq!(
                    m.channel.schema.as_ref().map(|s| s.name.as_str()),
                    Some("foxglove.SceneUpdate")
                );
                let entities = v["entities"].as_array().expect("entities");
                assert_eq!(entities.len(), 8);
                let frustum = &entities[6];
                assert_eq!(frustum["id"], "camera_frustum");
                assert_eq!(
                    frustum["lines"][0]["points"].as_array().map(Vec::len),
                    Some(16)
                );
                let legs = &entities[1]["lines"][0]["points"];
                assert_eq!(legs.as_array().map(Vec::len), Some(12));
                // Metres: the platform is about half a metre below the base.
                let z = entities[2]["spheres"][3]["pose"]["position"]["z"]
                    .as_f64()
                    .expect("z");
                assert!((z + 0.5).abs() < 1e-9, "{z}");
            }
            _ => {}
        }
    }
    assert_eq!(scenes, 226);
}

#[test]
fn the_error_can_cross_threads() {
    fn send_sync<T: Send + Sync + 'static>() {}
    send_sync::<McapError>();
}

#[test]
fn non_finite_values_and_time_going_back_are_errors() {
    let sc = Scenario::paper();
    let mut sink = McapSink::new(Cursor::new(Vec::new()), &sc).expect("new");
    let good = Simulation::new(sc.clone())
        .expect("valid")
        .samples()
        .next()
        .expect("one")
        .expect("ok");
    let mut bad = good;
    bad.module1.q[2] = f64::NAN;
    match sink.push(&bad) {
        Err(McapError::NonFinite { topic, field, .. }) => {
            assert_eq!((topic, field), ("/module1", "q3_mm"));
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
    let mut sink = McapSink::new(Cursor::new(Vec::new()), &sc).expect("new");
    sink.push(&good).expect("first");
    assert!(matches!(
        sink.push(&good),
        Err(McapError::TimeNotIncreasing { .. })
    ));
    let mut late = good;
    late.t = -1.0;
    assert!(matches!(
        sink.push(&late),
        Err(McapError::InvalidTime { .. })
    ));
    late.t = 1e300;
    let err = sink.push(&late).expect_err("too late");
    assert_eq!(
        err.to_string(),
        "sample time t = 1e300 s cannot be a log time (finite, >= 0, < 1.8e10 s)"
    );
    assert!(matches!(
        McapSink::with_options(
            Cursor::new(Vec::new()),
            &sc,
            McapOptions {
                scene_period_s: f64::NAN,
                ..McapOptions::default()
            }
        ),
        Err(McapError::InvalidOption { .. })
    ));
}

#[test]
fn an_empty_run_is_still_a_valid_file() {
    let sink = McapSink::new(Cursor::new(Vec::new()), &Scenario::paper()).expect("new");
    let bytes = sink.finish().expect("finish").into_inner();
    let summary = mcap::Summary::read(&bytes).expect("ok").expect("summary");
    assert_eq!(summary.stats.map(|s| s.message_count), Some(0));
    assert_eq!(summary.channels.len(), 11);
}

/// `{"x": .., "y": .., "z": ..}` (and `"w"`) as numbers.
fn xyz(v: &serde_json::Value, keys: &[&str]) -> Vec<f64> {
    keys.iter()
        .map(|k| v[*k].as_f64().expect("number"))
        .collect()
}

#[test]
fn the_calibration_and_the_camera_frame_put_each_tip_at_its_annotated_pixel() {
    use nalgebra::{Quaternion, UnitQuaternion};
    let sc = scenario(20.0);
    let (bytes, _) = write(&sc, McapOptions::default());
    let tips = sc.tips();
    let mut last: HashMap<String, serde_json::Value> = HashMap::new();
    let (mut checked, mut seen) = (0, 0);
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
        let topic = m.channel.topic.clone();
        if topic == "/camera/calibration" {
            assert_eq!(
                m.channel.schema.as_ref().map(|s| s.name.as_str()),
                Some("foxglove.CameraCalibration")
            );
        }
        last.insert(topic.clone(), v);
        if topic != "/camera/annotations" {
            continue;
        }
        // /tf, /scene, the calibration and the annotations come together.
        let (tf, cal, ann) = (
            &last["/tf"],
            &last["/camera/calibration"],
            &last["/camera/annotations"],
        );
        let frame = |child: &str| {
            let t = tf["transforms"]
                .as_array()
                .expect("transforms")
                .iter()
                .find(|t| t["child_frame_id"] == child)
                .expect("frame")
                .clone();
            let p = xyz(&t["translation"], &["x", "y", "z"]);
            let q = xyz(&t["rotation"], &["x", "y", "z", "w"]);
            let q = UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]));
            (Vector3::new(p[0], p[1], p[2]), q)
        };
        let (p_world, q_world) = frame("platform");
        let (p_cam, q_cam) = frame(CAMERA_FRAME);
        assert_eq!(tf["transforms"][5]["parent_frame_id"], "platform");
        let k: Vec<f64> = cal["K"]
            .as_array()
            .expect("K")
            .iter()
            .map(|x| x.as_f64().expect("n"))
            .collect();
        assert_eq!(
            (cal["width"].as_u64(), cal["height"].as_u64()),
            (Some(1280), Some(720))
        );
        assert_eq!(cal["frame_id"], CAMERA_FRAME);
        let points = ann["points"].as_array().expect("points");
        // The cross and the centre, then each tip ahead of the camera.
        assert_eq!(points[1]["points"][0]["x"].as_f64(), Some(640.0));
        assert_eq!(points[1]["points"][0]["y"].as_f64(), Some(360.0));
        let mut expected = Vec::new();
        for tip in [tips.left, tips.right] {
            // The tip (m) in the camera frame: world -> platform -> camera.
            let in_platform = q_world.inverse() * (tip * 1e-3 - p_world);
            let c = q_cam.inverse() * (in_platform - p_cam);
            if c.z > 0.0 {
                expected.push([k[0] * c.x / c.z + k[2], k[4] * c.y / c.z + k[5]]);
            }
        }
        assert_eq!(points.len(), 2 + expected.len());
        for (j, px) in expected.iter().enumerate() {
            let drawn = &points[2 + j]["points"][0];
            assert!(
                (drawn["x"].as_f64().expect("x") - px[0]).abs() < 1e-6,
                "{j}"
            );
            assert!(
                (drawn["y"].as_f64().expect("y") - px[1]).abs() < 1e-6,
                "{j}"
            );
        }
        seen = seen.max(expected.len());
        checked += 1;
    }
    // At 20 Hz every record is at least one scene period after the last.
    assert_eq!(checked, 91);
    assert_eq!(seen, 2, "both tips drawn at some record");
}

/// The two ends of a `foxglove.CylinderPrimitive`: its centre minus and
/// plus half its height along its own `z` (the quaternion's third column,
/// written out), and its diameter.
fn cylinder_ends(c: &serde_json::Value) -> (Vector3<f64>, Vector3<f64>, f64) {
    let centre = Vector3::from_vec(xyz(&c["pose"]["position"], &["x", "y", "z"]));
    let q = xyz(&c["pose"]["orientation"], &["x", "y", "z", "w"]);
    let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
    let axis = Vector3::new(
        2.0 * (x * z + w * y),
        2.0 * (y * z - w * x),
        1.0 - 2.0 * (x * x + y * y),
    );
    let size = xyz(&c["size"], &["x", "y", "z"]);
    assert_eq!(size[0], size[1], "a round cylinder");
    let half = axis * (size[2] / 2.0);
    (centre - half, centre + half, size[0])
}

#[test]
fn the_shafts_and_the_endoscope_are_cylinders_of_their_bodies_split_at_the_ports() {
    let mut sc = scenario(20.0);
    sc.endoscope_depth_mm = 30.0;
    sc.bodies.instrument_diameter = 6.0;
    sc.bodies.endoscope_length = 350.0;
    let (bytes, _) = write(&sc, McapOptions::default());
    let mut tips: HashMap<u64, serde_json::Value> = HashMap::new();
    let mut platform: HashMap<u64, serde_json::Value> = HashMap::new();
    let mut scenes = Vec::new();
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
        match m.channel.topic.as_str() {
            "/tips" => drop(tips.insert(m.log_time, v)),
            "/platform" => drop(platform.insert(m.log_time, v)),
            SCENE_TOPIC if v["entities"][0]["id"] != "no_go_0" => scenes.push((m.log_time, v)),
            _ => {}
        }
    }
    assert!(scenes.len() > 50, "{}", scenes.len());
    let mm = |v: &serde_json::Value, name: &str| v[name].as_f64().expect("number") * 1e-3;
    let close = |a: &Vector3<f64>, b: &Vector3<f64>| (a - b).norm() < 1e-12;
    for (ns, scene) in &scenes {
        let (t, p) = (&tips[ns], &platform[ns]);
        let entities: HashMap<&str, &serde_json::Value> = scene["entities"]
            .as_array()
            .expect("entities")
            .iter()
            .map(|e| (e["id"].as_str().expect("id"), e))
            .collect();
        for side in ["left", "right"] {
            let e = entities[format!("{side}_instrument").as_str()];
            assert_eq!(e["lines"].as_array().map(Vec::len), Some(0));
            let c = e["cylinders"].as_array().expect("cylinders");
            assert_eq!(c.len(), 2);
            let (tip, port, d_in) = cylinder_ends(&c[0]);
            let (from, end, d_out) = cylinder_ends(&c[1]);
            // The tip and the port of the `/tips` channel (forward
            // kinematics, `P + R rcm`), the shaft 400 mm long.
            let field = |what: &str| {
                Vector3::new(
                    mm(t, &format!("{side}_{what}_x_mm")),
                    mm(t, &format!("{side}_{what}_y_mm")),
                    mm(t, &format!("{side}_{what}_z_mm")),
                )
            };
            assert!(close(&tip, &field("tip")), "{side} tip at {ns} ns");
            assert!(close(&port, &field("port")), "{side} port at {ns} ns");
            assert!(close(&from, &port));
            assert!(((end - tip).norm() - 0.4).abs() < 1e-12);
            assert!((d_in - 0.006).abs() < 1e-15 && (d_out - 0.006).abs() < 1e-15);
            assert!(c[0]["color"]["a"].as_f64() < Some(1.0));
            assert!(c[1]["color"]["a"].as_f64() < c[0]["color"]["a"].as_f64());
        }
        // The endoscope: 30 mm inside, from its tip below `P` up to `P`,
        // then 320 mm outside, 10 mm across.
        let c = entities["endoscope"]["cylinders"]
            .as_array()
            .expect("cylinders");
        let (tip, port, d) = cylinder_ends(&c[0]);
        let (_, end, _) = cylinder_ends(&c[1]);
        let centre = Vector3::new(mm(p, "x_mm"), mm(p, "y_mm"), mm(p, "z_mm"));
        assert!(close(&port, &centre), "{port} vs P {centre}");
        assert!(((tip - port).norm() - 0.03).abs() < 1e-12);
        assert!(((end - port).norm() - 0.32).abs() < 1e-12);
        assert!((d - 0.01).abs() < 1e-15);
        // Straight: tip, P and end on one line.
        assert!((tip - port).cross(&(end - port)).norm() < 1e-12);
    }
}
