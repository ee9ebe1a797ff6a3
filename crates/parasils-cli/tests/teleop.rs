//! `parasils teleop`: the shipped session `inputs/teleop-demo.csv` replayed,
//! its output read back and checked against what the session commands
//! (the state sequence, the clutch, the hold at a joint limit, the image
//! directions), and the command's errors (no device, a bad file).

mod common;

use std::path::PathBuf;

use common::files::{names, s};
use common::process::{fails, parasils};
use common::table::Table;

fn teleop_demo() -> String {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "inputs",
        "teleop-demo.csv",
    ]
    .iter()
    .collect();
    path.to_string_lossy().into_owned()
}

/// The row of time `t_s` at 1 kHz.
fn row(t_s: f64) -> usize {
    (t_s * 1000.0).round() as usize
}

#[test]
fn the_demo_session_replays_as_commanded() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let out = dir.path().join("demo.csv");
    parasils(&["teleop", "--input", &teleop_demo(), "-o", s(&out)])
        .run()
        .ok();
    let t = Table::read(&out);
    // The recording's last row at 18.5 s, then the 1 s settle, at 1 kHz.
    assert_eq!(t.rows(), 19_501);

    // The states: ENABLED at once, PAUSED at 5.0 s, ENABLED at 5.5 s,
    // DISABLED at 18.5 s (codes 1, 2, 1, 0).
    let state = t.col("teleop_state");
    let mut visited = vec![(0, state[0])];
    for (k, w) in state.windows(2).enumerate() {
        if w[1] != w[0] {
            visited.push((k + 1, w[1]));
        }
    }
    assert_eq!(
        visited,
        [(0, 1.0), (row(5.0), 2.0), (row(5.5), 1.0), (row(18.5), 0.0)]
    );

    // The clutch (the left device's bit 1) pressed at 2.2 s and released at
    // 2.5 s: not one bit of either tip changes across either cycle.
    let tips = [
        "left_tip_x_mm",
        "left_tip_y_mm",
        "left_tip_z_mm",
        "right_tip_x_mm",
        "right_tip_y_mm",
        "right_tip_z_mm",
    ]
    .map(|c| t.col(c));
    let buttons = t.col("left_buttons");
    let changes: Vec<usize> = (1..t.rows())
        .filter(|&k| (buttons[k] as u8 & 2) != (buttons[k - 1] as u8 & 2))
        .collect();
    assert_eq!(changes, [row(2.2), row(2.5)]);
    for &k in &changes {
        for tip in &tips {
            assert_eq!(tip[k].to_bits(), tip[k - 1].to_bits(), "row {k}");
        }
    }

    // The left hand drives the tip on the left of the picture at enable:
    // here the right module's (the instruments cross), code 1.
    let (lu, ru) = (t.col("left_tip_u"), t.col("right_tip_u"));
    assert!(ru[0] < lu[0], "the right module's tip is left in the image");
    assert_eq!(t.at("left_hand_module", 0), 1.0);
    assert_eq!(t.at("right_hand_module", 0), 0.0);
    // From 0.1 s to 1.1 s the left hand pushes +u (right in the picture)
    // and the right hand +v (up the picture): measured at rest, 2.0 s,
    // before the camera turns.
    let (lv, rv) = (t.col("left_tip_v"), t.col("right_tip_v"));
    let (a, b) = (row(0.1), row(2.0));
    let du_driven = ru[b] - ru[a];
    assert!(du_driven > 0.01, "left hand's tip moved +u by {du_driven}");
    assert!((rv[b] - rv[a]).abs() < 0.1 * du_driven);
    let dv_other = lv[b] - lv[a];
    assert!(dv_other > 0.01, "right hand's tip moved +v by {dv_other}");
    assert!((lu[b] - lu[a]).abs() < 0.1 * dv_other);

    // The camera turns from 3.0 s (psi changes) while both tips stay put.
    let psi = t.col("psi_deg");
    assert!((psi[row(5.0)] - psi[row(3.0)]).abs() > 1.0);
    for tip in &tips {
        assert!((tip[row(5.0)] - tip[row(3.0)]).abs() < 1e-9);
    }

    // The push into the right module's stroke (the left hand's +tz from
    // 6.0 s): held at `right.qs3_limits` (code 8), and qs3 never past its
    // upper limit 300 mm minus the supervisor's 2 mm stop threshold.
    let hold = t.col("teleop_hold");
    let held = hold.iter().filter(|h| **h == 8.0).count();
    assert!(held > 1000, "{held} cycles held");
    assert!(hold.iter().all(|h| *h == 0.0 || *h == 8.0));
    let qs3 = t.col("right_qs3_mm");
    let top = qs3.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!(top <= 300.0 - 2.0, "{top}");
    assert!(top > 297.9, "{top}: the push reached the threshold");
    assert!(t.col("teleop_fault").iter().all(|f| *f == 0.0));
}

#[test]
fn the_summary_has_a_teleoperation_block() {
    let text = parasils(&["teleop", "--input", &teleop_demo()]).run().ok();
    assert!(text.contains("largest tip drift"), "{text}");
    assert!(
        text.contains("states: ENABLED (0.000 s) -> PAUSED (5.000 s) -> ENABLED (5.500 s) -> DISABLED (18.500 s)"),
        "{text}"
    );
    assert!(text.contains("held at margin right.qs3_limits:"), "{text}");
    assert!(
        text.contains(
            "clutch: 2 presses and releases, largest tip change across one 0 mm (exactly)"
        ),
        "{text}"
    );
}

#[test]
fn without_a_device_live_teleoperation_fails_in_one_line() {
    let e = fails(&["teleop", "--device", "auto", "-o", "live.csv"]);
    assert!(e.contains("no SpaceMouse found"), "{e}");
}

#[test]
fn a_bad_session_names_its_line_and_leaves_no_file() {
    let dir = tempfile::tempdir().expect("temporary folder");
    let input = dir.path().join("bad.csv");
    std::fs::write(
        &input,
        "t_s,device,tx,ty,tz,rx,ry,rz,buttons,command\n0,left,0,0,0,0,0,0,0,enable\n0.5,left,2,0,0,0,0,0,1,\n",
    )
    .expect("write");
    let e = parasils(&["teleop", "--input", s(&input), "-o", "out.csv"])
        .dir(dir.path())
        .run()
        .error_line();
    assert!(
        e.contains("bad.csv: line 3: tx: 2 is outside [-1, 1]"),
        "{e}"
    );
    assert_eq!(names(dir.path()), ["bad.csv"]);
}
