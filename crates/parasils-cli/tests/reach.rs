//! `parasils reach` run as a process: the CSV, the pictures, the summary.

mod common;

use common::process::{ok, parasils};
use common::table::Table;

#[test]
fn the_csv_has_a_row_per_cell_and_the_paper_target_is_straight_ahead() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("map.csv");
    let path_s = path.to_str().expect("path");
    ok(&["reach", "--step", "5", "-o", path_s]);
    let table = Table::read(&path);
    assert_eq!(
        table.header().join(","),
        "dpsi_deg,dtheta_deg,psi_deg,theta_deg,feasible,reachable,line,limiting,margin"
    );
    let rows: Vec<Vec<&str>> = (0..table.rows()).map(|k| table.cells(k)).collect();
    assert_eq!(rows.len(), 19 * 19);
    // The start, and the paper's target (15, 25): at psi -15 + 15 = 0 deg,
    // theta 10 + 25 = 35 deg.
    let find = |dpsi: &str, dtheta: &str| {
        rows.iter()
            .find(|r| r[0] == dpsi && r[1] == dtheta)
            .expect("on the grid")
            .clone()
    };
    assert_eq!(find("0.0", "0.0")[4..8], ["1", "1", "1", "ok"]);
    let target = find("15.0", "25.0");
    assert_eq!(target[2..8], ["0.0", "35.0", "1", "1", "1", "ok"]);
    assert!(target[8].parse::<f64>().expect("margin") > 0.0);
    // Infeasible cells say why, with a negative margin.
    let outside: Vec<_> = rows.iter().filter(|r| r[4] == "0").collect();
    assert!(!outside.is_empty());
    for r in outside {
        assert_ne!(r[7], "ok");
        assert!(r[8].parse::<f64>().expect("margin") < 0.0, "{r:?}");
        assert_eq!(r[5..7], ["0", "0"]);
    }
    // No temporary file left beside it.
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 1);
}

#[test]
fn the_summary_names_the_extent_and_the_limiting_constraints() {
    let text = ok(&["reach", "--step", "5"]);
    assert!(text.contains("reachable region: dpsi"), "{text}");
    assert!(text.contains("dtheta alone:"), "{text}");
    assert!(text.contains("limiting constraints on the reachable region's boundary:"));
    assert!(text.contains("module1.parallel_singular"), "{text}");
    assert!(text.contains("module 1: assumed geometry"), "{text}");
}

#[test]
fn pictures_are_written_as_png_and_svg() {
    let dir = tempfile::tempdir().expect("temp dir");
    for name in ["map.png", "map.svg"] {
        let path = dir.path().join(name);
        ok(&["reach", "--step", "5", "-o", path.to_str().expect("path")]);
        let bytes = std::fs::read(&path).expect("written");
        if name.ends_with("png") {
            assert_eq!(&bytes[1..4], b"PNG");
        } else {
            let text = String::from_utf8(bytes).expect("SVG text");
            assert!(text.contains("module1.parallel_singular"));
            assert!(text.contains("dpsi, deg from the start"));
        }
    }
}

#[test]
fn the_shared_flags_and_bad_grids() {
    // Another start pose: the map follows it.
    let text = ok(&[
        "reach",
        "--step",
        "15",
        "--no-line",
        "--pose=15,20,-500,-5,0,-60",
    ]);
    assert!(text.contains("from psi = -5 deg, theta = 0 deg"), "{text}");
    let err = parasils(&["reach", "--psi-range=5,10"]).run().fails();
    assert!(err.contains("must be finite and contain 0"), "{err}");
    parasils(&["reach", "-o", "map.txt"]).run().fails();
}

#[test]
fn a_calibrated_robot_is_labelled_so_in_the_reach_summary_and_the_mcap_metadata() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = ok(&["robot"]).replace(
        "assumed = true",
        "assumed = false\ncalibration = { poses = 40, rms_mm = 0.0125 }",
    );
    let robot = dir.path().join("fitted.toml");
    std::fs::write(&robot, text).expect("write");
    let robot_s = robot.to_str().expect("path");
    let summary = ok(&["reach", "--step", "10", "--no-line", "--robot", robot_s]);
    assert!(
        summary.contains("module 1: calibrated (RMS 0.0125 mm over 40 poses)"),
        "{summary}"
    );
    let mcap = dir.path().join("run.mcap");
    let mcap_s = mcap.to_str().expect("path");
    ok(&["simulate", "--rate", "50", "--robot", robot_s, "-o", mcap_s]);
    let bytes = std::fs::read(&mcap).expect("written");
    let needle = b"calibrated (RMS 0.0125 mm over 40 poses)";
    assert!(bytes.windows(needle.len()).any(|w| w == needle));
}
