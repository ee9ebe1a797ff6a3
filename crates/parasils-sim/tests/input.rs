//! The one input model: a robot file read once carries its supervisor
//! thresholds into the run, whichever way the robot is given; "given" and
//! "not given" stay distinct through the resolution.

use std::path::PathBuf;

use parasils::supervisor::Margin;
use parasils_sim::input::{Input, ProcedureSource, RobotSource, TimingKind};
use parasils_sim::scenario::{Retarget, Timing};
use parasils_sim::{Record, Simulation, robot_file};

fn default_robot_text() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots/default.toml");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A robot file: the default geometry with a `[supervisor]` table.
fn robot_file_with(supervisor: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("parasils-input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
    let path = dir.join(format!("robot-{:x}.toml", fxhash(supervisor)));
    let text = format!("{}\n[supervisor]\n{supervisor}", default_robot_text());
    std::fs::write(&path, text).unwrap_or_else(|e| panic!("{e}"));
    path
}

fn fxhash(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    })
}

/// A run through the online controller (a retarget to the same goal makes
/// it one: the supervisor watches every cycle).
fn online(robot: RobotSource) -> Vec<Record> {
    let scenario = Input {
        robot: Some(robot),
        rate_hz: Some(200.0),
        retarget: Some(vec![Retarget {
            t_s: 0.5,
            psi_deg: 15.0,
            theta_deg: 25.0,
        }]),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    let sim = Simulation::new(scenario).unwrap_or_else(|e| panic!("{e}"));
    sim.samples()
        .collect::<Result<Vec<_>, _>>()
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_warning_threshold_from_the_file_fires_where_the_margin_is_below_it() {
    // The paper's turn takes the left |cos qs2| from 0.778 down to 0.472:
    // a warning at 0.6 fires on part of it; the stop at 0.45 never does.
    let path = robot_file_with("cos_qs2_warn = 0.6\ncos_qs2_stop = 0.45\n");
    let loaded = robot_file::load_robot(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.supervisor.cos_qs2_warn, Some(0.6));
    let by_path = online(RobotSource::File(path.clone()));
    let by_value = online(RobotSource::Loaded(Box::new(loaded)));
    assert_eq!(by_path, by_value, "a robot read once or given as a value");
    let mut warned = 0;
    for r in &by_path {
        let below = r.left.cos_qs2.abs() < 0.6;
        assert_eq!(
            r.warnings.contains(Margin::LeftCosQs2),
            below,
            "t = {} s, |cos qs2| = {}",
            r.t,
            r.left.cos_qs2.abs()
        );
        warned += usize::from(below);
    }
    assert!(warned > 10 && warned < by_path.len() - 10, "{warned}");
    // Without the file's table the default thresholds (0.1 for |cos qs2|)
    // never warn on this turn.
    let plain = online(RobotSource::Loaded(Box::default()));
    assert!(plain.iter().all(|r| r.warnings.is_empty()));
    let _ = std::fs::remove_file(path);
}

#[test]
fn a_procedure_s_robot_file_brings_its_thresholds() {
    let path = robot_file_with("serial_margin_warn = 0.9\n");
    let json = format!(
        r#"{{"robot": {:?}, "motion": [{{"type": "reorient", "psi_deg": 5, "theta_deg": 5}}]}}"#,
        path.display().to_string()
    );
    let scenario = Input {
        procedure: Some(ProcedureSource::Json(json)),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scenario.supervisor.serial_margin_warn, Some(0.9));
    let _ = std::fs::remove_file(path);
}

#[test]
fn the_optimal_timing_binds_the_angular_limits_only_when_given() {
    let run = |omega: Option<f64>| {
        let scenario = Input {
            timing: Some(TimingKind::Optimal),
            omega_max_deg_s: omega,
            rate_hz: Some(200.0),
            ..Input::default()
        }
        .resolve()
        .unwrap_or_else(|e| panic!("{e}"));
        let sim = Simulation::new(scenario).unwrap_or_else(|e| panic!("{e}"));
        (sim.scenario().timing(), sim.duration())
    };
    let (free, free_s) = run(None);
    let (given, given_s) = run(Some(10.0));
    assert_eq!(free, Timing::Optimal { angular: false });
    assert_eq!(given, Timing::Optimal { angular: true });
    // 10 deg/s is the paper's value, and it binds: the given law is slower.
    assert!(given_s > free_s + 0.1, "{given_s} vs {free_s}");
}
