//! The robot file parser with arbitrary text. No call may panic; an error
//! says what is wrong in a message that is not empty; a geometry accepted
//! is valid (the controller can be built from it) and comes back unchanged
//! through the file's own writer, with the `[supervisor]` thresholds the
//! file gave (to the bit).

use parasils::kin::{Controller, RobotGeometry};
use parasils_sim::robot_file;

/// The target's check. Bytes that are not UTF-8 are read as the CLI would
/// refuse them, so the parser sees them with replacement characters: every
/// input reaches the parser.
pub fn robot_file(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    check_text(&text);
}

/// The checks on one text.
pub fn check_text(text: &str) {
    let robot = match robot_file::parse_robot(text) {
        Ok(r) => r,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            return;
        }
    };
    accepted(&robot.geometry);
    let written = robot_file::robot_to_toml_string(&robot)
        .unwrap_or_else(|e| panic!("an accepted robot cannot be written: {e}"));
    let back = robot_file::parse_robot(&written).unwrap_or_else(|e| {
        panic!("the file written for an accepted robot is refused: {e}\n{written}")
    });
    assert_eq!(
        back.geometry, robot.geometry,
        "the geometry changed through its own file:\n{written}"
    );
    let bits = |r: &parasils_sim::Robot| -> Vec<(&str, u64)> {
        r.supervisor
            .given()
            .map(|(k, v)| (k, v.to_bits()))
            .collect()
    };
    assert_eq!(
        bits(&back),
        bits(&robot),
        "the supervisor thresholds changed through their own file:\n{written}"
    );
}

/// An accepted geometry is valid and builds a controller.
fn accepted(geometry: &RobotGeometry<f64>) {
    if let Err(e) = geometry.validate() {
        panic!("the parser accepted an invalid geometry: {e}");
    }
    if let Err(e) = Controller::from_geometry(geometry) {
        panic!("the parser accepted a geometry the controller refuses: {e}");
    }
}
