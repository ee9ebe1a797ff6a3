//! `parasils calibrate` run as a process: a plan, a fit of a perturbed
//! robot's readings (from the kinematics and from `simulate`), the fitted
//! file loaded by the other commands, and bad input refused with one line
//! and no file.

mod common;

use parasils::kin::{ParallelRobot, Pose, RobotGeometry};
use parasils_sim::robot_file;

use common::files::s;
use common::process::{fails, ok};
use common::table::Table;

/// The paper's robot with module 1 moved by up to about 1.5 mm and 0.5 deg
/// and encoder offsets, as a robot file.
fn perturbed() -> RobotGeometry<f64> {
    let mut g = RobotGeometry::<f64>::paper();
    let m = &mut g.module1;
    m.assumed = false;
    for (j, guide) in m.guides.iter_mut().enumerate() {
        let t = j as f64;
        guide.point.x += 1.5 * (1.3 * t).sin();
        guide.point.y += 1.2 * (0.7 * t + 1.0).cos();
        guide.point.z += 0.8 * (2.1 * t).sin();
        guide.direction.x += 0.008 * (t + 0.5).sin();
        guide.direction.y -= 0.006 * (1.7 * t).cos();
        guide.link_length += 1.1 * (0.9 * t + 0.3).sin();
        guide.encoder_offset = 1.4 * (1.1 * t + 0.2).cos();
    }
    for (i, a) in m.nodes.iter_mut().enumerate() {
        let t = i as f64;
        a.x += 0.9 * (t + 1.0).sin();
        a.y -= 1.3 * (2.0 * t).cos();
        a.z += 0.7 * (0.5 * t).sin();
    }
    g
}

fn readings(robot: &ParallelRobot<f64>, p: &[f64; 6]) -> [f64; 6] {
    robot
        .ik(&Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]))
        .expect("in reach")
        .0
}

#[test]
fn plan_measure_fit_and_load_the_fitted_robot() {
    let dir = tempfile::tempdir().expect("temp dir");
    let poses = dir.path().join("poses.csv");
    let plan_json = dir.path().join("plan.json");
    let said = ok(&[
        "calibrate",
        "--plan",
        "40",
        "--candidates",
        "400",
        "-o",
        s(&poses),
        "--report",
        s(&plan_json),
    ]);
    assert!(said.contains("40 poses from 400 candidates"), "{said}");
    let plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plan_json).expect("report")).expect("JSON");
    assert!(plan["ratio_singular_value_min"].as_f64().expect("ratio") > 1.0);
    // The planned poses, measured on the perturbed robot.
    let truth_geometry = perturbed();
    let truth = ParallelRobot::new(truth_geometry.module1).expect("valid");
    let planned = Table::read(&poses);
    let header = planned.header().join(",");
    assert_eq!(
        header,
        "q1_mm,q2_mm,q3_mm,q4_mm,q5_mm,q6_mm,x_mm,y_mm,z_mm,psi_deg,theta_deg,phi_deg"
    );
    let mut measured = header;
    measured.push('\n');
    let mut rows = Vec::new();
    let columns = ["x_mm", "y_mm", "z_mm", "psi_deg", "theta_deg", "phi_deg"];
    let planned_q: Vec<Vec<f64>> = (1..=6).map(|j| planned.col(&format!("q{j}_mm"))).collect();
    for k in 0..planned.rows() {
        // The plan's readings are numbers too.
        assert!(planned_q.iter().all(|q| q[k].is_finite()), "row {k}");
        let pose: [f64; 6] = core::array::from_fn(|i| planned.at(columns[i], k));
        let q = readings(&truth, &pose);
        let cells: Vec<String> = q.iter().chain(&pose).map(f64::to_string).collect();
        measured.push_str(&cells.join(","));
        measured.push('\n');
        rows.push(pose);
    }
    assert_eq!(rows.len(), 40);
    let data = dir.path().join("measured.csv");
    std::fs::write(&data, measured).expect("write");
    let fitted = dir.path().join("fitted.toml");
    let report = dir.path().join("report.json");
    let said = ok(&[
        "calibrate",
        "--measurements",
        s(&data),
        "-o",
        s(&fitted),
        "--report",
        s(&report),
    ]);
    assert!(said.contains("module 1 calibrated (RMS"), "{said}");
    assert!(said.contains("over 40 poses"), "{said}");
    assert!(said.contains("45 identified, 6 fixed"), "{said}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).expect("report")).expect("JSON");
    assert!(r["rms_before_mm"].as_f64().expect("rms") > 0.5);
    assert!(r["rms_after_mm"].as_f64().expect("rms") < 1e-9);
    assert_eq!(r["fixed"].as_array().expect("fixed").len(), 6);
    assert_eq!(r["fixed"][0]["name"], "guides[0].point_mm.z");
    // The fitted file loads and predicts the perturbed robot's readings.
    let loaded = robot_file::load(&fitted).expect("loads");
    assert!(!loaded.module1.assumed);
    let c = loaded.module1.calibration.expect("recorded");
    assert_eq!(c.poses, 40);
    let text = std::fs::read_to_string(&fitted).expect("fitted");
    assert!(text.contains("[module1.calibration]"), "{text}");
    assert!(text.contains("encoder_offset_mm = "), "{text}");
    let robot = ParallelRobot::new(loaded.module1).expect("valid");
    let pose = [10.0, -15.0, -560.0, 5.0, -8.0, -58.0];
    let (a, b) = (readings(&robot, &pose), readings(&truth, &pose));
    for j in 0..6 {
        assert!(
            (a[j] - b[j]).abs() < 1e-8,
            "q{}: {} vs {}",
            j + 1,
            a[j],
            b[j]
        );
    }
    // `ik` takes it like any robot file and prints the same readings.
    let out = ok(&[
        "ik",
        "--robot",
        s(&fitted),
        "--pose",
        "10,-15,-560,5,-8,-58",
    ]);
    assert!(out.contains(&format!("{:.3}", b[0])), "{out}\n{b:?}");
    // The summary of a run labels module 1's numbers with the calibration.
    let summary = ok(&["simulate", "--robot", s(&fitted), "--rate", "20"]);
    assert!(
        summary.contains("(module 1 calibrated (RMS ") && summary.contains(" mm over 40 poses)"),
        "{summary}"
    );
}

#[test]
fn a_simulated_run_of_a_perturbed_robot_is_a_data_set() {
    let dir = tempfile::tempdir().expect("temp dir");
    let robot = dir.path().join("perturbed.toml");
    robot_file::save(&robot, &perturbed()).expect("save");
    let run = dir.path().join("run.csv");
    ok(&[
        "simulate",
        "--robot",
        s(&robot),
        "--rate",
        "20",
        "-o",
        s(&run),
    ]);
    let fitted = dir.path().join("fitted.toml");
    let said = ok(&["calibrate", "--measurements", s(&run), "-o", s(&fitted)]);
    // One reorientation about a fixed point sees few combinations: the
    // rest are fixed and said so.
    assert!(said.contains("fixed"), "{said}");
    assert!(said.contains("poorly observable") || said.contains("not observable"));
    robot_file::load(&fitted).expect("loads");
}

#[test]
fn bad_input_is_one_line_and_no_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("fitted.toml");
    let nominal = ParallelRobot::<f64>::assumed();
    let poses: Vec<[f64; 6]> = (0..12)
        .map(|k| {
            let t = f64::from(k);
            [
                40.0 * (0.7 * t).sin(),
                40.0 * (1.3 * t).cos(),
                -540.0 + 30.0 * (0.4 * t).sin(),
                10.0 * (0.9 * t).cos(),
                10.0 * (1.1 * t).sin(),
                -60.0 + 8.0 * (0.5 * t).cos(),
            ]
        })
        .collect();
    let csv = |rows: &[[f64; 6]], edit: &dyn Fn(usize, &mut [f64; 12])| -> String {
        let mut text = String::from(
            "q1_mm,q2_mm,q3_mm,q4_mm,q5_mm,q6_mm,x_mm,y_mm,z_mm,psi_deg,theta_deg,phi_deg\n",
        );
        for (k, p) in rows.iter().enumerate() {
            let q = readings(&nominal, p);
            let mut v: [f64; 12] = core::array::from_fn(|i| if i < 6 { q[i] } else { p[i - 6] });
            edit(k, &mut v);
            let cells: Vec<String> = v.iter().map(f64::to_string).collect();
            text.push_str(&cells.join(","));
            text.push('\n');
        }
        text
    };
    let run = |name: &str, text: String| -> String {
        let path = dir.path().join(name);
        std::fs::write(&path, text).expect("write");
        let err = fails(&["calibrate", "--measurements", s(&path), "-o", s(&out)]);
        assert!(!out.exists(), "{name}: an output file was left");
        err
    };
    let err = run(
        "missing.csv",
        csv(&poses, &|_, _| {}).replacen(",theta_deg", ",theta", 1),
    );
    assert!(err.contains("missing column `theta_deg`"), "{err}");
    let err = run(
        "nan.csv",
        csv(&poses, &|k, v| {
            if k == 6 {
                v[2] = f64::NAN;
            }
        }),
    );
    assert!(err.contains("row 7, `q3_mm` = NaN"), "{err}");
    let err = run(
        "far.csv",
        csv(&poses, &|k, v| {
            if k == 3 {
                v[6] += 900.0;
            }
        }),
    );
    assert!(err.contains("row 4: the pose is out of reach"), "{err}");
    let err = run("few.csv", csv(&poses[..5], &|_, _| {}));
    assert!(err.contains("5 measured poses give 30 equations"), "{err}");
    let err = run(
        "garbage.csv",
        csv(&poses, &|k, v| {
            for (j, q) in v.iter_mut().take(6).enumerate() {
                *q = 160.0 + 150.0 * ((k * 7 + j * 3) as f64).sin();
            }
        }),
    );
    assert!(err.contains("the fit diverged at iteration"), "{err}");
    assert_eq!(
        std::fs::read_dir(dir.path()).expect("dir").count(),
        5,
        "only the five inputs remain"
    );
}
