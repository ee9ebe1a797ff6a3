//! The forces in the MCAP recording: `/forces` against the records bit for
//! bit, the other channels' ids kept, and the scene's arrows read back
//! into the forces they draw (each arrow's direction and length over the
//! stated millimetres per newton, from the slider or the tip).

use std::collections::{BTreeMap, HashMap};
use std::io::Cursor;

use nalgebra::{UnitQuaternion, Vector3};
use parasils::kin::{Payload, RobotGeometry};
use parasils_sim::columns;
use parasils_sim::mcap::{FORCE_ARROW_MM_PER_N, FORCES_TOPIC, SCENE_TOPIC};
use parasils_sim::{McapOptions, McapSink, Record, Scenario, SceneGeometry, Simulation};

const LEFT_N: [f64; 3] = [4.0, -6.0, 9.0];
const RIGHT_N: [f64; 3] = [-3.0, 2.5, -12.0];

fn loaded() -> Scenario {
    Scenario {
        rate_hz: 50.0,
        tip_load_left_n: Some(LEFT_N),
        tip_load_right_n: Some(RIGHT_N),
        dynamics: Some(Payload::assumed()),
        ..Scenario::paper()
    }
}

/// The run's records and its recording, a scene at every record.
fn write(scenario: &Scenario) -> (Vec<Record>, Vec<u8>) {
    let sim = Simulation::new(scenario.clone()).expect("valid");
    let options = McapOptions {
        scene_period_s: 0.0,
        ..McapOptions::default()
    };
    let mut sink =
        McapSink::with_options(Cursor::new(Vec::new()), sim.scenario(), options).expect("new");
    sim.run(&mut sink).expect("run");
    let records = sim.samples().collect::<Result<Vec<_>, _>>().expect("runs");
    (records, sink.finish().expect("finish").into_inner())
}

fn channel_ids(bytes: &[u8]) -> BTreeMap<String, u16> {
    let summary = mcap::Summary::read(bytes)
        .expect("summary readable")
        .expect("summary present");
    summary
        .channels
        .values()
        .map(|c| (c.topic.clone(), c.id))
        .collect()
}

#[test]
fn forces_are_a_channel_of_their_own_after_the_others() {
    let (records, bytes) = write(&loaded());
    let ids = channel_ids(&bytes);
    let (_, plain) = write(&Scenario {
        rate_hz: 50.0,
        ..Scenario::paper()
    });
    let plain_ids = channel_ids(&plain);
    assert!(!plain_ids.contains_key(FORCES_TOPIC));
    for (topic, id) in &plain_ids {
        assert_eq!(ids[topic], *id, "{topic}");
    }
    assert_eq!(ids.len(), plain_ids.len() + 1);
    assert!(ids[FORCES_TOPIC] > *plain_ids.values().max().expect("channels"));

    let mut messages = Vec::new();
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        if m.channel.topic == FORCES_TOPIC {
            let schema = m.channel.schema.as_ref().expect("schema");
            assert_eq!(schema.name, "parasils.Forces");
            let schema: serde_json::Value = serde_json::from_slice(&schema.data).expect("JSON");
            let required: Vec<&str> = schema["required"]
                .as_array()
                .expect("required")
                .iter()
                .map(|v| v.as_str().expect("name"))
                .collect();
            let expected: Vec<&str> = core::iter::once("t_s")
                .chain(columns::FORCES.iter().map(|c| c.name))
                .collect();
            assert_eq!(required, expected);
            messages.push(serde_json::from_slice::<serde_json::Value>(&m.data).expect("JSON"));
        }
    }
    assert_eq!(messages.len(), records.len());
    for (m, r) in messages.iter().zip(&records) {
        assert_eq!(m["t_s"].as_f64(), Some(r.t));
        for c in columns::FORCES {
            let v = m[c.name].as_f64().expect("number");
            assert_eq!(v.to_bits(), c.value(r).to_bits(), "{} at {}", c.name, r.t);
        }
    }
    // Not zeros: the body's weight and the loads load module 1.
    assert!(
        records
            .iter()
            .all(|r| r.forces.module1.iter().any(|f| f.abs() > 1.0))
    );
}

/// An arrow read back: its base (mm) and the force it draws (N), from its
/// orientation's `x` axis (the quaternion's first column, written out) and
/// its whole length (shaft and head) over the stated scale.
fn force_of(arrow: &serde_json::Value) -> (Vector3<f64>, Vector3<f64>) {
    let n = |v: &serde_json::Value| v.as_f64().expect("number");
    let p = &arrow["pose"]["position"];
    let base = Vector3::new(n(&p["x"]), n(&p["y"]), n(&p["z"])) * 1e3;
    let o = &arrow["pose"]["orientation"];
    let (x, y, z, w) = (n(&o["x"]), n(&o["y"]), n(&o["z"]), n(&o["w"]));
    let axis = Vector3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
    );
    let length_m = n(&arrow["shaft_length"]) + n(&arrow["head_length"]);
    (base, axis * (length_m * 1e3 / FORCE_ARROW_MM_PER_N))
}

#[test]
fn the_arrows_draw_each_slider_s_force_along_its_guide_and_each_tip_s_load() {
    let scenario = loaded();
    let (records, bytes) = write(&scenario);
    let geometry = SceneGeometry::from_robot(&RobotGeometry::paper()).expect("geometry");
    let by_time: HashMap<u64, &Record> = records
        .iter()
        .map(|r| ((r.t * 1e9).round() as u64, r))
        .collect();
    let mut drawn = 0;
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        if m.channel.topic != SCENE_TOPIC {
            continue;
        }
        let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
        let entity = &v["entities"][0];
        if entity["id"] != "forces" {
            continue;
        }
        assert_eq!(entity["frame_id"], "world");
        assert_eq!(entity["metadata"][0]["key"], "mm_per_n");
        let scale = entity["metadata"][0]["value"]
            .as_str()
            .map(str::parse::<f64>);
        assert_eq!(scale, Some(Ok(FORCE_ARROW_MM_PER_N)));
        let r = by_time[&m.log_time];
        let arrows = entity["arrows"].as_array().expect("arrows");
        assert_eq!(arrows.len(), 8);
        let close = |a: &Vector3<f64>, b: &Vector3<f64>| (a - b).norm() <= 1e-9 * b.norm().max(1.0);
        for (j, arrow) in arrows[..6].iter().enumerate() {
            let (base, force) = force_of(arrow);
            let u = Vector3::from(geometry.guide_directions[j]);
            let slider = Vector3::from(geometry.guide_points_mm[j]) + r.module1.q[j] * u;
            assert!(close(&base, &slider), "q{} base {base} vs {slider}", j + 1);
            let expected = u * r.forces.module1[j];
            assert!(
                close(&force, &expected),
                "q{}: {force} vs {expected}",
                j + 1
            );
        }
        for (arrow, tip, load) in [
            (&arrows[6], r.left.tip, LEFT_N),
            (&arrows[7], r.right.tip, RIGHT_N),
        ] {
            let (base, force) = force_of(arrow);
            assert!(close(&base, &tip), "{base} vs {tip}");
            assert!(close(&force, &Vector3::from(load)), "{force}");
            // A unit quaternion.
            let o = &arrow["pose"]["orientation"];
            let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                o["w"].as_f64().expect("w"),
                o["x"].as_f64().expect("x"),
                o["y"].as_f64().expect("y"),
                o["z"].as_f64().expect("z"),
            ));
            assert!((q.norm() - 1.0).abs() < 1e-12);
        }
        drawn += 1;
    }
    assert_eq!(drawn, records.len());
}
