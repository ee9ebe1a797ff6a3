//! `parasils simulate --procedure`: the shipped demo, the pre-flight check,
//! and procedures that fail before writing anything.

mod common;

use common::files::{demo, names};
use common::process::parasils;
use common::table::Table;

#[test]
fn the_demo_runs_and_its_csv_has_the_procedure_columns() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = parasils(&[
        "simulate",
        "--procedure",
        &demo(),
        "--rate",
        "100",
        "-o",
        "demo.csv",
    ])
    .dir(dir.path())
    .run();
    let stderr = out.stderr();
    out.ok();
    let table = Table::read(&dir.path().join("demo.csv"));
    let header = table.header();
    assert_eq!(header.len(), 74 + 12);
    assert_eq!(
        header[74..77],
        ["motion", "motion_type", "endoscope_depth_mm"]
    );
    assert_eq!(header[85], "endoscope_tip_z_mm");
    // The motions' types in order, as the file gives them.
    let mut types: Vec<(&str, &str)> = table
        .text("motion")
        .into_iter()
        .zip(table.text("motion_type"))
        .collect();
    types.dedup();
    assert_eq!(
        types,
        [
            ("0", "1"),
            ("1", "2"),
            ("2", "3"),
            ("3", "4"),
            ("4", "3"),
            ("5", "2")
        ]
    );
    // The endoscope goes in by 60 mm and comes back out.
    let depth = table.col("endoscope_depth_mm");
    assert_eq!(depth.iter().copied().fold(0.0, f64::max), 60.0);
    assert_eq!(depth[depth.len() - 1], 0.0);
    // The summary line names the samples and the duration: at 100 Hz each
    // motion stretched to whole 10 ms periods (the left tip's 2.2321 s to
    // 2.24 s) and the next one a period after it: 3 + 4 + 2.24 + 4.5 + 2.5
    // + 4 + 5 x 0.01 s (20.232 s before).
    assert!(stderr.contains("2030 samples (20.290 s)"), "{stderr}");
}

#[test]
fn check_prints_the_verdict_and_a_table_and_writes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let stdout = parasils(&["simulate", "--procedure", &demo(), "--check"])
        .dir(dir.path())
        .run()
        .ok();
    assert!(
        stdout.starts_with("procedure OK: 6 motions, 20.238 s, 20239 samples at 1000 Hz"),
        "{stdout}"
    );
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains(':') && l.trim_start().starts_with(char::is_numeric))
        .collect();
    assert_eq!(rows.len(), 6, "{stdout}");
    assert!(rows[3].contains("4:reorient") && rows[3].contains("camera to the target"));
    assert!(stdout.contains("supervisor: no margin below its warning threshold"));
    // Each actuator's peak as a fraction of its limits: module 1's q6 at
    // 0.715 of its velocity limit during the turn (35.7 of 50 mm/s).
    assert!(stdout.contains("actuator limits, peak use (velocity, acceleration):"));
    assert!(stdout.contains(" q6 0.715 0.205"), "{stdout}");
    assert_eq!(names(dir.path()), Vec::<String>::new());
}

/// Runs a procedure written into a fresh folder; expects a failure whose
/// single stderr line contains `needle` and no file left in the folder.
fn fails_cleanly(procedure: &str, extra: &[&str], needle: &str) {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("p.toml"), procedure).expect("write");
    let mut args = vec!["simulate", "--procedure", "p.toml"];
    args.extend_from_slice(extra);
    let err = parasils(&args).dir(dir.path()).run().error_line();
    assert!(err.contains(needle), "{err:?} lacks {needle:?}");
    assert_eq!(names(dir.path()), ["p.toml"], "a file was left");
}

const START: &str = "pose = [15, 20, -460, -15, 10, -60]\ntip_left_mm = [50, -50, -580]\n";

#[test]
fn the_fourth_motion_crossing_a_joint_limit_is_named_before_any_output() {
    let procedure = format!(
        "{START}\
         [[motion]]\ntype = \"insert\"\ninstrument = \"endoscope\"\ndepth_mm = 20\n\
         [[motion]]\ntype = \"manipulate\"\ninstrument = \"left\"\ntip_mm = [55, -45, -600]\n\
         [[motion]]\ntype = \"reorient\"\npsi_deg = 5\ntheta_deg = 5\n\
         [[motion]]\nname = \"too deep\"\ntype = \"insert\"\ninstrument = \"left\"\ndepth_mm = 250\n\
         [[motion]]\ntype = \"insert\"\ninstrument = \"endoscope\"\ndepth_mm = -20\n"
    );
    for extra in [
        &["-o", "out.csv"][..],
        &["-o", "out.mcap"],
        &["--check"],
        &["--plot", "p.svg", "-o", "o.csv"],
    ] {
        fails_cleanly(&procedure, extra, "motion 3 (insert \"too deep\"), ");
    }
    fails_cleanly(
        &procedure,
        &["-o", "out.csv"],
        "left instrument: joint qs3 = 300",
    );
}

#[test]
fn bad_procedure_files_name_the_line_the_motion_and_the_key() {
    fails_cleanly(
        &format!(
            "{START}[[motion]]\ntype = \"insert\"\ninstrument = \"left\"\ndepth_mm = \"deep\"\n"
        ),
        &[],
        "p.toml, line 6, motion 0: invalid type: string \"deep\", expected f64",
    );
    fails_cleanly(
        &format!(
            "{START}[[motion]]\ntype = \"position\"\npose = [1, 2, 3, 4, 5, 6]\nvelocity_deg_s = 0\n"
        ),
        &[],
        "p.toml, line 6, motion 0, key `velocity_deg_s`: 0 is not a positive number",
    );
    fails_cleanly(
        "robot = \"missing.toml\"\n[[motion]]\ntype = \"reorient\"\npsi_deg = 1\ntheta_deg = 1\n",
        &[],
        "missing.toml",
    );
    fails_cleanly(
        &format!(
            "{START}[[motion]]\ntype = \"manipulate\"\ninstrument = \"both\"\ntip_mm = [1, 2, 3]\n"
        ),
        &[],
        "key `tip_mm`: does not apply with instrument = \"both\"",
    );
}

#[test]
fn procedures_do_not_mix_with_the_single_reorientation_s_options() {
    let dir = tempfile::tempdir().expect("tempdir");
    for extra in [["--psi", "3"], ["--robot", "r.toml"], ["--stop-at", "1"]] {
        let mut args = vec!["simulate", "--procedure", "p.toml"];
        args.extend_from_slice(&extra);
        // The library's input model refuses them (the same rule Python
        // applies), naming the flag, before the file is read.
        let err = parasils(&args).dir(dir.path()).run().fails();
        assert!(
            err.contains(&format!(
                "{} cannot be given with --procedure: a procedure has its own start, robot and motions",
                extra[0]
            )),
            "{extra:?}: {err}"
        );
    }
    let err = parasils(&["simulate", "--check"])
        .dir(dir.path())
        .run()
        .fails();
    assert!(err.contains("--procedure"), "{err}");
}

#[test]
fn a_motion_cut_short_and_a_stop_in_the_check_table() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(
        dir.path().join("p.toml"),
        "[[motion]]\ntype = \"reorient\"\npsi_deg = 15\ntheta_deg = 25\nuntil_s = 2\n\
         [[motion]]\ntype = \"stop\"\nname = \"pedal released\"\n\
         [[motion]]\ntype = \"reorient\"\npsi_deg = -5\ntheta_deg = 0\nuntil_s = 4\n\
         [[motion]]\ntype = \"insert\"\ninstrument = \"endoscope\"\ndepth_mm = 10\n",
    )
    .expect("write");
    let stdout = parasils(&["simulate", "--procedure", "p.toml", "--check"])
        .dir(dir.path())
        .run()
        .ok();
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.contains(':') && l.trim_start().starts_with(char::is_numeric))
        .collect();
    assert_eq!(rows.len(), 4, "{stdout}");
    // The stop keeps the turn's type number, 4, and is named a stop.
    assert!(
        rows[1].contains("4:stop") && rows[1].contains("pedal released"),
        "{}",
        rows[1]
    );
    // The cut turn lasts its until_s; the third motion rests until 4 s.
    assert!(rows[0].contains(" 2.000 "), "{}", rows[0]);
    assert!(rows[2].contains(" 4.000 "), "{}", rows[2]);
}
