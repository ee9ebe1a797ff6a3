//! `parasils tolerance` run as a process: the specification it prints
//! reads back to the same study, the rows are the same whatever the
//! threads, CSV and Parquet hold the same numbers (Parquet read by the
//! format's own reader), and bad input is one line, a non-zero exit and no
//! file.

mod common;

use std::path::Path;

use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;

use common::files::s;
use common::process::{fails, ok, parasils};
use common::table::Table;

/// The rows of a study's CSV as numbers, in its columns' order (`sample`,
/// the four deviations, `failed`).
fn rows(csv: &str) -> Vec<Vec<f64>> {
    let table = Table::parse(csv);
    (0..table.rows()).map(|k| table.row(k)).collect()
}

#[test]
fn the_printed_specification_is_the_default_study() {
    let dir = tempfile::tempdir().expect("temp dir");
    let spec = dir.path().join("tol.toml");
    std::fs::write(&spec, ok(&["tolerance", "--print-spec"])).expect("written");
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    ok(&[
        "tolerance",
        "-n",
        "24",
        "--rate",
        "20",
        "--threads",
        "1",
        "-o",
        s(&a),
    ]);
    let text = ok(&[
        "tolerance",
        "--spec",
        s(&spec),
        "-n",
        "24",
        "--rate",
        "20",
        "--threads",
        "2",
        "-o",
        s(&b),
    ]);
    let a = std::fs::read_to_string(&a).expect("a");
    assert_eq!(a, std::fs::read_to_string(&b).expect("b"));
    assert!(a.starts_with(
        "sample,left_tip_dev_mm,right_tip_dev_mm,pose_position_err_mm,pose_rotation_err_deg,failed\n"
    ));
    let rows = rows(&a);
    assert_eq!(rows.len(), 24);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r[0], i as f64);
        // Tenths of a millimetre at the default tolerances, no failure.
        assert!(r[1] > 0.01 && r[1] < 2.0 && r[5] == 0.0, "{r:?}");
    }
    assert!(text.contains("24 perturbed robots, 0 failed"), "{text}");
    assert!(text.contains("p99.9"), "{text}");
    assert!(text.contains("module1.legs.node_mm"), "{text}");
    // Another seed: other robots.
    let c = dir.path().join("c.csv");
    ok(&[
        "tolerance",
        "-n",
        "24",
        "--rate",
        "20",
        "--seed",
        "1",
        "-o",
        s(&c),
    ]);
    assert_ne!(a, std::fs::read_to_string(&c).expect("c"));
}

#[test]
fn parquet_holds_the_csv_numbers() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (csv, pq) = (dir.path().join("r.csv"), dir.path().join("r.parquet"));
    // Wide encoder offsets: some robots cannot be followed, and are kept.
    let spec = dir.path().join("wide.toml");
    std::fs::write(
        &spec,
        "[module1.guides]\nencoder_offset_mm = { half_width = 250.0 }\n",
    )
    .expect("written");
    let args = |out: &Path| {
        vec![
            "tolerance".to_string(),
            "--spec".into(),
            s(&spec).into(),
            "-n".into(),
            "40".into(),
            "--rate".into(),
            "10".into(),
            "--seed".into(),
            "4".into(),
            "-o".into(),
            s(out).into(),
        ]
    };
    let run = |out: &Path| {
        let a = args(out);
        ok(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let text = run(&csv);
    run(&pq);
    let want = rows(&std::fs::read_to_string(&csv).expect("csv"));
    let failed = want.iter().filter(|r| r[5] == 1.0).count();
    assert!(failed > 0 && failed < 40, "{failed}");
    assert!(
        text.contains(&format!("40 perturbed robots, {failed} failed")),
        "{text}"
    );
    let reader = SerializedFileReader::new(std::fs::File::open(&pq).expect("parquet"))
        .expect("a Parquet file");
    assert_eq!(reader.metadata().file_metadata().num_rows(), 40);
    let got: Vec<Vec<Field>> = reader
        .get_row_iter(None)
        .expect("rows")
        .map(|r| {
            r.expect("row")
                .into_columns()
                .into_iter()
                .map(|(_, f)| f)
                .collect()
        })
        .collect();
    for (g, w) in got.iter().zip(&want) {
        assert_eq!(g[0], Field::Long(w[0] as i64));
        for k in 1..5 {
            let Field::Double(v) = g[k] else {
                panic!("column {k} is not a double: {:?}", g[k]);
            };
            // The CSV's shortest round-trip decimals give back the bits.
            assert!(
                v.to_bits() == w[k].to_bits() || (v.is_nan() && w[k].is_nan()),
                "{k}"
            );
        }
        assert_eq!(g[5], Field::Bool(w[5] == 1.0));
    }
}

#[test]
fn a_procedure_and_a_picture() {
    let dir = tempfile::tempdir().expect("temp dir");
    let png = dir.path().join("hist.png");
    let procedure = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    );
    let text = ok(&[
        "tolerance",
        "--procedure",
        procedure,
        "--rate",
        "5",
        "-n",
        "8",
        "--plot",
        s(&png),
    ]);
    assert!(text.contains("sils-demo.toml at 5 Hz"), "{text}");
    let bytes = std::fs::read(&png).expect("picture");
    assert!(bytes.starts_with(b"\x89PNG"));
}

#[test]
fn bad_input_is_one_line_and_no_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("r.csv");
    let spec = dir.path().join("bad.toml");
    std::fs::write(&spec, "[instruments]\ngamma_deg = { sigma = 0.1 }\n").expect("written");
    let err = fails(&["tolerance", "--spec", s(&spec), "-n", "4", "-o", s(&out)]);
    assert!(err.contains("unknown key `instruments.gamma_deg`"), "{err}");
    std::fs::write(&spec, "[module1.legs]\nnode_mm = { sigma = 40.0 }\n").expect("written");
    let err = fails(&["tolerance", "--spec", s(&spec), "-n", "4", "-o", s(&out)]);
    assert!(err.contains("too wide for this robot"), "{err}");
    std::fs::write(&spec, "[module1.legs]\nnode_mm = { half_width = -1 }\n").expect("written");
    let err = fails(&["tolerance", "--spec", s(&spec), "-n", "4", "-o", s(&out)]);
    assert!(err.contains("must be finite and >= 0, got -1"), "{err}");
    let err = fails(&["tolerance", "-n", "4", "-o", s(&dir.path().join("r.xlsx"))]);
    assert!(err.contains("use a .csv or .parquet extension"), "{err}");
    let err = fails(&["tolerance", "-n", "0"]);
    assert!(err.contains("-n must be at least 1"), "{err}");
    let err = fails(&["tolerance", "-n", "200000000"]);
    assert!(err.contains("split the study"), "{err}");
    // Above the output cap: refused before the first robot, unless --force.
    let over = |force: &[&str]| {
        parasils(&["tolerance", "-n", "3", "--rate", "5", "-o", s(&out)])
            .args(force)
            .env("PARASILS_OUTPUT_CAP_BYTES", "1000")
            .run()
    };
    let err = over(&[]).fails();
    assert!(
        err.contains("more than the 1.0 kB cap: give --force"),
        "{err}"
    );
    assert!(!out.exists());
    over(&["--force"]).ok();
    std::fs::remove_file(&out).expect("written with --force");
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("listing")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("bad.toml")]);
}

#[test]
fn an_interrupted_study_exits_130_and_leaves_the_previous_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("r.csv");
    std::fs::write(&out, "previous\n").expect("previous");
    // A million robots take minutes: the signal arrives mid-run. Should it
    // come before the handler is installed (a very slow start), the child
    // dies of it instead; try again, waiting longer.
    for wait_ms in [400, 1600, 6400] {
        let child = parasils(&[
            "tolerance",
            "-n",
            "1000000",
            "--threads",
            "1",
            "-o",
            s(&out),
        ])
        .spawn();
        std::thread::sleep(core::time::Duration::from_millis(wait_ms));
        child.signal("-INT");
        let done = child.finish();
        if done.status.code().is_none() {
            continue;
        }
        let err = done.fails_with(130);
        assert_eq!(err.trim(), "parasils: interrupted");
        assert_eq!(std::fs::read_to_string(&out).expect("kept"), "previous\n");
        let names: Vec<_> = std::fs::read_dir(dir.path()).expect("listing").collect();
        assert_eq!(names.len(), 1);
        return;
    }
    panic!("the signal never arrived after the handler was installed");
}
