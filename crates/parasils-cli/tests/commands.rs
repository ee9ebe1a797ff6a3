//! `parasils ik`, `parasils fk` and `parasils robot` run as processes.

mod common;

use common::process::{ok, parasils};

fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&ok(args)).expect("JSON")
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().expect("a number")
}

#[test]
fn ik_at_p0_gives_the_check_values() {
    let v = json(&["ik", "--json"]);
    // Module 1's check values at P0 (assumed geometry; see docs/model.md,
    // *Check values*).
    let want = [117.942, 151.459, 56.937, 89.428, 132.193, 77.441];
    let q = v["module1"]["q_mm"].as_array().expect("q_mm");
    for (got, want) in q.iter().zip(want) {
        assert!((num(got) - want).abs() < 5e-4, "{got} vs {want}");
    }
    assert_eq!(v["module1"]["assumed_geometry"], serde_json::json!(true));
    // The paper's joints at P0 (docs/model.md, *Check values*): both modules,
    // mode A, and the left's mode B; the right one with the mirrored tip
    // (mirror symmetry), and with the default tip, its own values.
    let mirrored = json(&["ik", "--json", "--tip-right", "mirror"]);
    assert_eq!(mirrored["left"], v["left"]);
    let a = &v["right"]["mode_a"];
    assert!((num(&a["qs1_deg"]) - 37.6768).abs() < 5e-5);
    assert!((num(&a["qs2_deg"]) + 18.1170).abs() < 5e-5);
    assert!((num(&a["qs3_mm"]) - 185.6585).abs() < 5e-5);
    for (side, v) in [("left", &v), ("right", &mirrored)] {
        let a = &v[side]["mode_a"];
        assert!((num(&a["qs1_deg"]) - 3.0889).abs() < 5e-5);
        assert!((num(&a["qs2_deg"]) + 38.8695).abs() < 5e-5);
        assert!((num(&a["qs3_mm"]) - 147.7687).abs() < 5e-5);
        assert!(a["limit_error"].is_null());
        let b = &v[side]["mode_b"];
        assert!((num(&b["qs1_deg"]) + 151.3897).abs() < 5e-5);
        assert!(
            b["limit_error"]
                .as_str()
                .expect("beyond limits")
                .contains("qs1")
        );
    }
}

#[test]
fn ik_text_names_the_assumed_geometry() {
    let text = ok(&[
        "ik",
        "--pose",
        "15,20,-500,-15,10,-60",
        "--tip-left",
        "50,-50,-620",
    ]);
    assert!(text.contains("ASSUMED"), "{text}");
    assert!(
        text.contains("mode A: qs1 =    3.0889 deg, qs2 =  -38.8695 deg, qs3 = 147.7687 mm"),
        "{text}"
    );
}

#[test]
fn fk_recovers_p0_and_the_tip() {
    let v = json(&[
        "fk",
        "--q",
        "117.94221,151.45877,56.93665,89.42758,132.19295,77.44067",
        "--guess",
        "10,15,-495,-10,5,-55",
        "--qs-left",
        "3.0889,-38.8695,147.7687",
        "--json",
    ]);
    let p = &v["pose"];
    for (k, want) in [
        ("x_mm", 15.0),
        ("y_mm", 20.0),
        ("z_mm", -500.0),
        ("psi_deg", -15.0),
        ("theta_deg", 10.0),
        ("phi_deg", -60.0),
    ] {
        // The actuators above carry five decimals: about 1e-5 mm of input noise.
        assert!((num(&p[k]) - want).abs() < 1e-3, "{k}: {}", p[k]);
    }
    assert!(v["module1"]["iterations"].as_u64().expect("iterations") <= 10);
    let tip = v["left"]["tip_mm"].as_array().expect("tip");
    for (got, want) in tip.iter().zip([50.0, -50.0, -620.0]) {
        assert!((num(got) - want).abs() < 1e-2, "{got} vs {want}");
    }
}

#[test]
fn fk_from_a_singular_guess_fails_cleanly() {
    let err = parasils(&[
        "fk",
        "--q",
        "117.942,151.459,56.937,89.428,132.193,77.441",
        "--guess",
        "15,20,-500,-15,90,-60",
    ])
    .run()
    .error_line();
    assert!(
        err.starts_with("parasils: error: module 1 forward kinematics"),
        "{err}"
    );
}

#[test]
fn robot_prints_the_committed_default_file() {
    let printed = ok(&["robot"]);
    let committed = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../robots/default.toml"
    ))
    .expect("robots/default.toml");
    assert_eq!(printed, committed);
}

/// Runs a command expected to fail: its whole standard error.
fn error_of(args: &[&str]) -> String {
    let out = parasils(args).run();
    assert!(out.stdout.is_empty(), "{args:?} printed {:?}", out.stdout);
    out.fails()
}

#[test]
fn errors_name_their_subject_once() {
    // Module 1 out of stroke: one `module 1:`, numbers to 6 digits.
    assert_eq!(
        error_of(&["ik", "--pose", "15,20,-300,-15,10,-60"]),
        "parasils: error: module 1: actuator q1 = -82.0578 mm is outside [0, 320] mm\n"
    );
    assert_eq!(
        error_of(&["ik", "--pose", "15,20,-900,-15,10,-60"]),
        "parasils: error: module 1: actuator q1 = 517.942 mm is outside [0, 320] mm\n"
    );
    // The left tip on its port: one `left instrument:`.
    assert_eq!(
        error_of(&["ik", "--pose", "0,0,-500,0,0,0", "--tip-left", "-10,0,-500"]),
        "parasils: error: left instrument: singular configuration: qs3 (mm) = 0 is below 1e-6\n"
    );
    // A missing robot file: the path once, then the system's words.
    assert_eq!(
        error_of(&["fk", "--q", "1,2,3,4,5,6", "--robot", "/no/such/robot.toml"]),
        "parasils: error: /no/such/robot.toml: No such file or directory (os error 2)\n"
    );
}
