//! The robot file: the committed default, round trips, and every way a file
//! can be wrong, each with a message that names the key and its line.

use std::path::PathBuf;

use parasils::kin::{Branch, Camera, Controller, Interval, RobotGeometry};
use parasils_sim::robot_file::{self, RobotFileError};

fn default_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots/default.toml")
}

fn default_text() -> String {
    robot_file::to_toml_string(&RobotGeometry::paper()).expect("serialisable")
}

/// The 1-based line of the first line of `text` that starts with `prefix`.
fn line_of(text: &str, prefix: &str, occurrence: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with(prefix))
        .nth(occurrence)
        .map(|(n, _)| n + 1)
        .expect("line present")
}

/// A geometry with nothing at its default: every field distinct, an
/// infinite stroke, a reversed branch, angles of many decimals.
fn unusual() -> RobotGeometry<f64> {
    let mut g = RobotGeometry::<f64>::paper();
    g.module1.assumed = false;
    for (j, guide) in g.module1.guides.iter_mut().enumerate() {
        let k = j as f64;
        guide.point.x += 0.123_456_789 * k;
        guide.direction = nalgebra::Vector3::new(0.01 * k, -0.02, -1.0).normalize();
        guide.link_length = 350.0 + k / 3.0;
        guide.stroke = Interval::new(-k, 320.0 + k);
    }
    g.module1.guides[4].branch = Branch::Minus;
    g.module1.guides[5].stroke.max = f64::INFINITY;
    g.module1.nodes[1].z = 99.999_999_999;
    g.module1.thresholds.serial = 1e-3;
    g.module1.fk.tolerance = 2.5e-12;
    g.module1.fk.max_iterations = 17;
    g.left.alpha = 12.345_678_901f64.to_radians();
    g.right.beta = (11.0f64 / 3.0).to_radians();
    g.right.limits.qs1 = Interval::new(f64::NEG_INFINITY, f64::INFINITY);
    g.left.thresholds.cos_qs2 = 3e-5;
    g.endoscope.camera = Camera {
        horizontal_fov: 80f64.to_radians(),
        aspect_ratio: 4.0 / 3.0,
        oblique: 30f64.to_radians(),
        oblique_direction: (-45.5f64).to_radians(),
    };
    g.limits.force[3] = 123.5;
    g.limits.force[7] = 2_500.25;
    g.limits.force[11] = 35.0;
    g
}

#[test]
fn committed_default_file_is_the_generated_one() {
    let committed = std::fs::read_to_string(default_path()).expect("robots/default.toml");
    assert_eq!(
        committed,
        default_text(),
        "robots/default.toml is stale: regenerate it with `parasils robot > robots/default.toml`"
    );
    let loaded = robot_file::load(default_path()).expect("valid");
    assert_eq!(loaded, RobotGeometry::paper());
    assert!(loaded.module1.assumed);
    assert!(committed.contains("ASSUMED"));
    assert_eq!(
        Controller::from_geometry(&loaded).expect("valid"),
        Controller::paper()
    );
}

#[test]
fn keys_name_their_units() {
    let text = default_text();
    for key in [
        "point_mm = [160.0, 200.0, 0.0]",
        "link_length_mm = 350.0",
        "stroke_mm = [0.0, 320.0]",
        "node_mm = [0.0, -150.0, 100.0]",
        "alpha_deg = 10.0",
        "qs1_deg = [-120.0, 120.0]",
        "qs3_mm = [10.0, 300.0]",
        "fk_tolerance_rel = 1e-13",
        "assumed = true",
        "force_max_n = 200.0",
        "qs1_torque_max_nmm = 3000.0",
        "qs3_force_max_n = 40.0",
    ] {
        assert!(text.contains(key), "missing `{key}`");
    }
}

#[test]
fn round_trip_is_exact() {
    let g = unusual();
    let text = robot_file::to_toml_string(&g).expect("serialisable");
    let back = robot_file::parse(&text).expect("valid");
    assert_eq!(back, g);
    // Bit for bit, angles included.
    assert_eq!(back.left.alpha.to_bits(), g.left.alpha.to_bits());
    assert_eq!(back.right.beta.to_bits(), g.right.beta.to_bits());
    assert!(text.contains("branch = -1"));
    assert!(text.contains("assumed = false"));
    assert!(text.contains("inf"));
    assert!(
        text.contains("[camera]") && text.contains("oblique_deg = 30"),
        "{text}"
    );
    assert_eq!(back.endoscope.camera, g.endoscope.camera);
    // The assumed camera is not written.
    let plain = robot_file::to_toml_string(&RobotGeometry::<f64>::paper()).expect("ok");
    assert!(!plain.contains("[camera]"));
    // And once more: the text is a fixed point.
    assert_eq!(robot_file::to_toml_string(&back).expect("ok"), text);
}

#[test]
fn any_angle_round_trips_within_one_ulp() {
    let mut g = RobotGeometry::<f64>::paper();
    g.left.alpha = 0.123_456_789_012_345_68;
    g.right.beta = 0.2;
    let back = robot_file::parse(&robot_file::to_toml_string(&g).expect("ok")).expect("valid");
    for (a, b) in [
        (back.left.alpha, g.left.alpha),
        (back.right.beta, g.right.beta),
    ] {
        assert!((a - b).abs() <= b * f64::EPSILON, "{a} vs {b}");
    }
}

#[test]
fn save_and_load() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("robot.toml");
    let g = unusual();
    robot_file::save(&path, &g).expect("written");
    assert_eq!(robot_file::load(&path).expect("valid"), g);
}

/// The parse error of `text`, with its line and key, and its message.
fn parse_error(text: &str) -> (Option<usize>, Option<String>, String) {
    match robot_file::parse(text) {
        Err(e @ RobotFileError::Parse { .. }) => {
            let message = e.to_string();
            let RobotFileError::Parse { line, key, .. } = e else {
                unreachable!()
            };
            (line, key.map(String::from), message)
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn malformed_file_names_the_line() {
    let text = default_text().replacen("[left]", "[left", 1);
    let (line, _, message) = parse_error(&text);
    let expected = line_of(&text, "[left", 0);
    assert_eq!(line, Some(expected));
    assert!(
        message.starts_with(&format!("robot file, line {expected}, column 6")),
        "{message}"
    );
    assert!(message.contains("[left"), "{message}");
}

#[test]
fn missing_field_is_named_with_its_table_line() {
    let text = default_text().replacen("link_length_mm = 350.0\n", "", 1);
    let (line, _, message) = parse_error(&text);
    assert_eq!(line, Some(line_of(&text, "[[module1.guides]]", 0)));
    assert!(
        message.contains("missing field `link_length_mm`"),
        "{message}"
    );
    assert!(message.contains("[[module1.guides]] # q1"), "{message}");
}

#[test]
fn missing_table_is_named() {
    let text = default_text();
    let start = text.find("[right]").expect("right table");
    let (_, _, message) = parse_error(&text[..start]);
    assert!(message.contains("missing field `right`"), "{message}");
}

#[test]
fn unknown_field_is_named_with_its_line() {
    let text = default_text().replacen("alpha_deg = 10.0", "alpha_deg = 10.0\nalfa_deg = 3.0", 1);
    let (line, key, message) = parse_error(&text);
    assert_eq!(line, Some(line_of(&text, "alfa_deg", 0)));
    assert_eq!(key.as_deref(), Some("alfa_deg"));
    assert!(message.contains("unknown field `alfa_deg`"), "{message}");
}

#[test]
fn mistyped_value_is_named_with_its_line() {
    let text = default_text().replacen("link_length_mm = 350.0", "link_length_mm = \"350\"", 3);
    let (line, key, message) = parse_error(&text);
    assert_eq!(line, Some(line_of(&text, "link_length_mm", 0)));
    assert_eq!(key.as_deref(), Some("link_length_mm"));
    assert!(
        message.contains("invalid type: string \"350\""),
        "{message}"
    );
}

#[test]
fn values_out_of_range_are_named_with_their_line() {
    for (from, to, key, what) in [
        (
            "link_length_mm = 350.0",
            "link_length_mm = -350.0",
            "link_length_mm",
            "> 0",
        ),
        ("branch = 1", "branch = 0", "branch", "1 or -1"),
        (
            "stroke_mm = [0.0, 320.0]",
            "stroke_mm = [320.0, 0.0]",
            "stroke_mm",
            "min <= max",
        ),
        (
            "node_mm = [0.0, -150.0, 100.0]",
            "node_mm = [0.0, nan, 100.0]",
            "node_mm",
            "finite",
        ),
        (
            "fk_max_iterations = 100",
            "fk_max_iterations = 0",
            "fk_max_iterations",
            "at least 1",
        ),
    ] {
        let text = default_text().replacen(from, to, 1);
        let (line, got_key, message) = parse_error(&text);
        assert_eq!(line, Some(line_of(&text, to, 0)), "{message}");
        assert_eq!(got_key.as_deref(), Some(key), "{message}");
        assert!(message.contains(what), "{message}");
    }
}

#[test]
fn wrong_number_of_guides() {
    let text = default_text();
    let fifth = text
        .match_indices("[[module1.guides]]")
        .nth(5)
        .expect("q6")
        .0;
    let legs = text.find("[[module1.legs]]").expect("legs");
    let five = format!("{}{}", &text[..fifth], &text[legs..]);
    let (_, _, message) = parse_error(&five);
    assert!(
        message.contains("expected an array of length 6"),
        "{message}"
    );
}

#[test]
fn invalid_geometry_is_named_with_its_line() {
    // Parses, but a guide without a direction makes no robot.
    let text = default_text();
    let at = text
        .match_indices("direction = [0.0, 0.0, -1.0]")
        .nth(2)
        .expect("q3")
        .0;
    let text = format!(
        "{}direction = [0.0, 0.0, 0.0]{}",
        &text[..at],
        &text[at + "direction = [0.0, 0.0, -1.0]".len()..]
    );
    match robot_file::parse(&text) {
        Err(e @ RobotFileError::Invalid { .. }) => {
            let message = e.to_string();
            let RobotFileError::Invalid { line, key, .. } = e else {
                unreachable!()
            };
            assert_eq!(line, Some(line_of(&text, "direction", 2)), "{message}");
            assert_eq!(key.as_deref(), Some("[[module1.guides]] #3 (q3) direction"));
            assert!(message.contains("module1.guides[2].direction"), "{message}");
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
    // An instrument's error names its side.
    let text = default_text();
    let right = text.find("[right]").expect("right");
    let text = format!(
        "{}{}",
        &text[..right],
        text[right..].replacen("beta_deg = 10.0", "beta_deg = 95.0", 1)
    );
    match robot_file::parse(&text) {
        Err(RobotFileError::Invalid { line, key, .. }) => {
            assert_eq!(key.as_deref(), Some("[right] beta_deg"));
            assert_eq!(line, Some(line_of(&text, "beta_deg", 1)));
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
}

#[test]
fn unreadable_file_names_the_path() {
    let e = robot_file::load("/nonexistent/robot.toml").expect_err("no such file");
    assert!(matches!(e, RobotFileError::Io { .. }));
    assert!(
        e.to_string().starts_with("/nonexistent/robot.toml: "),
        "{e}"
    );
}

#[test]
fn errors_from_a_file_name_the_file() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("bad.toml");
    std::fs::write(
        &path,
        default_text().replacen("radius_mm = 110.0", "radius_mm = 0.0", 1),
    )
    .expect("written");
    let e = robot_file::load(&path).expect_err("radius 0");
    let message = e.to_string();
    assert!(
        message.starts_with(&format!("{}, line ", path.display())),
        "{message}"
    );
    assert!(message.contains("key `radius_mm`"), "{message}");
}
