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

/// `--deflection-load`: two more columns, empty where infeasible, the same
/// map otherwise; the robot file's `[stiffness]` reaches them (every spring
/// twice as stiff, every deflection half); the summary gives their range.
#[test]
fn the_stiffness_map_adds_each_tip_s_deflection() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = |extra: &[&str], name: &str| {
        let path = dir.path().join(name);
        let mut args = vec!["reach", "--step", "7.5", "--no-line", "-o"];
        args.push(path.to_str().expect("path"));
        args.extend_from_slice(extra);
        ok(&args);
        Table::read(&path)
    };
    let load = ["--deflection-load", "0,0,-10"];
    let map = run(&load, "stiff.csv");
    let plain = run(&[], "plain.csv");
    assert_eq!(
        map.header()[9..],
        ["left_tip_deflection_mm", "right_tip_deflection_mm"]
    );
    assert_eq!(map.header()[..9], plain.header()[..]);
    let text = std::fs::read_to_string(dir.path().join("stiff.csv")).expect("csv");
    let stiffer = dir.path().join("stiffer.toml");
    let robot = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../robots/default.toml"
    ))
    .expect("robots/default.toml")
        + "\n[stiffness]\nslider_n_mm = [400.0, 400.0, 400.0, 400.0, 400.0, 400.0]\n\
           left_qs1_nmm_rad = 4e5\nleft_qs2_nmm_rad = 4e5\nleft_qs3_n_mm = 100.0\n\
           right_qs1_nmm_rad = 4e5\nright_qs2_nmm_rad = 4e5\nright_qs3_n_mm = 100.0\n";
    std::fs::write(&stiffer, robot).expect("write");
    let stiff = run(
        &[&load[..], &["--robot", stiffer.to_str().expect("path")]].concat(),
        "stiffer.csv",
    );
    let mut feasible = 0;
    for k in 0..map.rows() {
        let (cells, base) = (map.cells(k), plain.cells(k));
        assert_eq!(cells[..9], base[..]);
        let half = stiff.cells(k);
        if cells[4] == "1" {
            feasible += 1;
            for c in 9..11 {
                let d: f64 = cells[c].parse().expect("deflection");
                let h: f64 = half[c].parse().expect("deflection");
                assert!(d > 0.0 && (h - d / 2.0).abs() <= 1e-12 * d, "{d} {h}");
            }
        } else {
            assert_eq!(cells[9..], ["", ""]);
        }
    }
    assert!(feasible > 20 && feasible < map.rows(), "{feasible}");
    // An infeasible cell's row ends with its two empty fields.
    assert!(text.lines().any(|l| l.ends_with(",,")));
    let summary = ok(&[
        "reach",
        "--step",
        "7.5",
        "--no-line",
        "--deflection-load",
        "0,0,-10",
    ]);
    assert!(
        summary.contains(
            "tip deflection pressing with (0, 0, -10) N, over the reachable cells: left "
        ),
        "{summary}"
    );
}
