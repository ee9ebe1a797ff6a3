//! Runs with commands: new goals and a stop while the platform moves, through
//! the online controller. The acceptance run is the paper's reorientation
//! commanded at 0 s, a new goal at 1.2 s while turning (`psi` +25, `theta`
//! +15 deg from the start), a stop at 3.0 s while turning again, and a last
//! goal at 3.5 s while stopping (`psi` +5, `theta` +30 deg).

use std::collections::HashMap;
use std::io::Cursor;

use parasils_sim::csv::CsvSink;
use parasils_sim::mcap::{MOTION_TOPIC, McapSink, RUN_METADATA, SCENARIO_METADATA};
use parasils_sim::scenario::{CommandKind, Retarget};
use parasils_sim::summary::Summary;
use parasils_sim::{Online, Run, Turn};
use parasils_sim::{Record, Scenario, Simulation, SimulationError, Tee};

/// The acceptance scenario (see the file's docs).
fn scenario() -> Scenario {
    Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            retargets: vec![
                Retarget {
                    t_s: 1.2,
                    psi_deg: 25.0,
                    theta_deg: 15.0,
                },
                Retarget {
                    t_s: 3.5,
                    psi_deg: 5.0,
                    theta_deg: 30.0,
                },
            ],
            stop_at_s: Some(3.0),
        }),
        ..Scenario::paper()
    }
}

/// The samples the commands take effect at (1 kHz).
const COMMAND_SAMPLES: [usize; 3] = [1200, 3000, 3500];

/// Every record of `sim`, and its CSV.
fn run(sim: &Simulation) -> (Vec<Record>, String) {
    let mut records = Vec::new();
    let mut keep = |r: &Record| {
        records.push(*r);
        Ok::<(), core::convert::Infallible>(())
    };
    let mut csv = CsvSink::for_scenario(Vec::new(), sim.scenario()).expect("header");
    sim.run(&mut Tee::new().with(&mut keep).with(&mut csv))
        .expect("runs");
    let text = String::from_utf8(csv.finish().expect("flush")).expect("utf8");
    (records, text)
}

/// The CSV as a header and rows of numbers.
fn parse(text: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

#[test]
fn two_retargets_and_a_stop_stay_continuous_within_limits_with_the_tips_still() {
    let sc = scenario();
    let sim = Simulation::new(sc.clone()).expect("valid");
    let (records, text) = run(&sim);
    assert_eq!(records.len(), sim.sample_count());
    let (header, rows) = parse(&text);
    assert_eq!(header.len(), 75);
    assert_eq!(header[74], "command");
    let col = |name: &str| {
        let i = header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        rows.iter().map(|r| r[i]).collect::<Vec<f64>>()
    };

    // Limits in the CSV's units: 10 deg/s, 5 deg/s^2, sampled every 1 ms.
    let turn = sc.turn().copied().unwrap_or_default();
    let (omega, eps, dt) = (turn.omega_max_deg_s, turn.eps_max_deg_s2, 1.0 / sc.rate_hz);
    let within = |x: f64, limit: f64| x.abs() <= limit * (1.0 + 1e-9);
    for axis in ["psi", "theta"] {
        let angle = col(&format!("{axis}_deg"));
        let rate = col(&format!("{axis}_rate_deg_s"));
        let acc = col(&format!("{axis}_acc_deg_s2"));
        for k in 0..rows.len() {
            assert!(within(rate[k], omega), "{axis} rate {} at {k}", rate[k]);
            assert!(within(acc[k], eps), "{axis} acc {} at {k}", acc[k]);
        }
        // Continuity at every command: the sample before and the sample it
        // takes effect at differ by no more than the limits allow in one
        // period (the angle by the velocity limit, the rate by the
        // acceleration limit), and the platform was moving.
        for k in COMMAND_SAMPLES {
            let (d_angle, d_rate) = (angle[k] - angle[k - 1], rate[k] - rate[k - 1]);
            assert!(
                within(d_angle, omega * dt),
                "{axis} jumps by {d_angle} deg at {k}"
            );
            assert!(
                within(d_rate, eps * dt),
                "{axis} rate jumps by {d_rate} deg/s at {k}"
            );
        }
    }
    for k in COMMAND_SAMPLES {
        let speed = records[k - 1].euler_dot[0].hypot(records[k - 1].euler_dot[1]);
        assert!(speed.to_degrees() > 1.0, "at rest before sample {k}");
    }

    // The tips held still along the whole run (f64).
    for side in ["left", "right"] {
        let worst = col(&format!("{side}_tip_err_mm"))
            .into_iter()
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{side} tip drifts {worst} mm");
    }

    // Every command in the `command` column, from its sample on.
    let command = col("command");
    for (k, c) in command.iter().enumerate() {
        let want = COMMAND_SAMPLES.iter().filter(|s| k >= **s).count();
        assert_eq!(*c, want as f64, "command at sample {k}");
    }
    assert!(text.lines().nth(1).is_some_and(|r| r.ends_with(",0")));
    assert!(text.lines().last().is_some_and(|r| r.ends_with(",3")));
    let kinds: Vec<CommandKind> = COMMAND_SAMPLES.map(|k| records[k].kind).to_vec();
    assert_eq!(
        kinds,
        [
            CommandKind::Retarget,
            CommandKind::Stop,
            CommandKind::Retarget
        ]
    );
    assert_eq!(records[0].kind, CommandKind::Reorient);
    assert!(records.iter().all(|r| r.warnings.is_empty()));

    // The run ends at rest on the last goal: psi -15 + 5, theta 10 + 30 deg.
    let last = records.last().expect("records");
    assert_eq!(last.index, rows.len() - 1);
    assert!(
        (last.angles_deg[0] + 10.0).abs() < 1e-9,
        "{:?}",
        last.angles_deg
    );
    assert!(
        (last.angles_deg[1] - 40.0).abs() < 1e-9,
        "{:?}",
        last.angles_deg
    );
    assert_eq!((last.euler_dot[0], last.euler_dot[1]), (0.0, 0.0));
    assert!(
        (last.t - sim.duration()).abs() <= dt,
        "{} {}",
        last.t,
        sim.duration()
    );
}

#[test]
fn the_schedule_and_the_summary_name_every_command() {
    let sim = Simulation::new(scenario()).expect("valid");
    let schedule: Vec<(CommandKind, usize)> = sim
        .schedule()
        .iter()
        .map(|s| (s.command.kind, s.sample))
        .collect();
    assert_eq!(
        schedule,
        [
            (CommandKind::Reorient, 0),
            (CommandKind::Retarget, 1200),
            (CommandKind::Stop, 3000),
            (CommandKind::Retarget, 3500)
        ]
    );
    let mut summary = Summary::for_simulation(&sim);
    sim.run(&mut summary).expect("runs");
    assert_eq!(
        summary.commands(),
        [
            (0, CommandKind::Reorient, 0.0),
            (1, CommandKind::Retarget, 1.2),
            (2, CommandKind::Stop, 3.0),
            (3, CommandKind::Retarget, 3.5)
        ]
    );
    let text = summary.to_string();
    assert!(
        text.contains(
            "\n  1   retarget        at    1.200 s, active from    1.200 s: psi +25.0000, theta +15.0000 deg"
        ),
        "{text}"
    );
    assert!(
        text.contains("\n  2   stop            at    3.000 s, active from    3.000 s\n"),
        "{text}"
    );
    assert!(text.ends_with("\nsupervisor warnings: none"), "{text}");
    // The paper's summary has no such section.
    let paper = Simulation::new(Scenario::paper()).expect("valid");
    let mut summary = Summary::for_simulation(&paper);
    paper.run(&mut summary).expect("runs");
    assert!(!summary.to_string().contains("commands"));
}

#[test]
fn the_mcap_file_has_every_command_on_motion() {
    let sc = Scenario {
        rate_hz: 100.0,
        ..scenario()
    };
    let sim = Simulation::new(sc.clone()).expect("valid");
    let mut sink = McapSink::new(Cursor::new(Vec::new()), &sc).expect("new");
    sim.run(&mut sink).expect("runs");
    let bytes = sink.finish().expect("finish").into_inner();

    let mut motion = Vec::new();
    let mut platform = 0;
    for m in mcap::MessageStream::new(&bytes).expect("stream") {
        let m = m.expect("message");
        match m.channel.topic.as_str() {
            MOTION_TOPIC => {
                let schema = m.channel.schema.as_ref().expect("schema");
                assert_eq!(schema.name, "parasils.Motion");
                let s: serde_json::Value = serde_json::from_slice(&schema.data).expect("JSON");
                assert_eq!(s["additionalProperties"], false);
                let v: serde_json::Value = serde_json::from_slice(&m.data).expect("JSON");
                let t = v["t_s"].as_f64().expect("t_s");
                assert_eq!(m.log_time, (t * 1e9).round() as u64);
                motion.push((
                    t,
                    v["command"].as_u64().expect("command"),
                    v["kind"].as_str().expect("kind").to_owned(),
                ));
            }
            "/platform" => platform += 1,
            _ => {}
        }
    }
    assert_eq!(motion.len(), sim.sample_count());
    assert_eq!(motion.len(), platform);
    let mut changes = Vec::new();
    for (t, command, kind) in &motion {
        if changes.last().is_none_or(|(_, c, _)| c != command) {
            changes.push((*t, *command, kind.as_str()));
        }
    }
    assert_eq!(
        changes,
        [
            (0.0, 0, "reorient"),
            (1.2, 1, "retarget"),
            (3.0, 2, "stop"),
            (3.5, 3, "retarget")
        ]
    );

    let summary = mcap::Summary::read(&bytes)
        .expect("readable")
        .expect("summary");
    let meta: HashMap<String, _> = summary
        .metadata_indexes
        .iter()
        .map(|i| {
            let m = mcap::read::metadata(&bytes, i).expect("metadata");
            (m.name.clone(), m.metadata)
        })
        .collect();
    let commands: serde_json::Value =
        serde_json::from_str(&meta[RUN_METADATA]["commands"]).expect("JSON");
    assert_eq!(commands[1]["kind"], "retarget");
    assert_eq!(commands[2]["t_s"], 3.0);
    assert_eq!(commands.as_array().map(Vec::len), Some(4));
    let scen: serde_json::Value =
        serde_json::from_str(&meta[SCENARIO_METADATA]["scenario"]).expect("JSON");
    assert_eq!(scen["stop_at"], 3.0);
    assert_eq!(scen["retargets"][1]["theta"], 30f64.to_radians());

    // The paper's file has neither the channel nor the keys.
    let paper = Simulation::new(Scenario {
        rate_hz: 10.0,
        ..Scenario::paper()
    })
    .expect("valid");
    let mut sink = McapSink::new(Cursor::new(Vec::new()), paper.scenario()).expect("new");
    paper.run(&mut sink).expect("runs");
    let bytes = sink.finish().expect("finish").into_inner();
    let summary = mcap::Summary::read(&bytes)
        .expect("readable")
        .expect("summary");
    assert!(summary.channels.values().all(|c| c.topic != MOTION_TOPIC));
    assert_eq!(summary.channels.len(), 11);
    let scenario_meta = summary
        .metadata_indexes
        .iter()
        .map(|i| mcap::read::metadata(&bytes, i).expect("metadata"))
        .find(|m| m.name == SCENARIO_METADATA)
        .expect("scenario");
    assert!(!scenario_meta.metadata["scenario"].contains("retargets"));
    assert!(!scenario_meta.metadata["scenario"].contains("stop_at"));
}

#[test]
fn the_paper_csv_has_its_74_columns_and_no_command() {
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    let (records, text) = run(&sim);
    let header = text.lines().next().expect("header");
    assert_eq!(header.split(',').count(), 74);
    assert!(!header.contains("command"));
    assert_eq!(records.len(), 4501);
    assert!(
        records
            .iter()
            .all(|r| r.command == 0 && r.kind == CommandKind::Reorient)
    );
    assert_eq!(sim.schedule().len(), 1);
}

#[test]
fn a_command_after_the_motion_waits_for_its_time_at_rest() {
    let sim = Simulation::new(Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            stop_at_s: Some(6.0),
            ..Online::default()
        }),
        rate_hz: 100.0,
        ..Scenario::paper()
    })
    .expect("valid");
    assert_eq!(sim.sample_count(), 601);
    let (records, _) = run(&sim);
    assert_eq!(records.len(), 601);
    let at_rest = &records[450..600];
    assert!(
        at_rest
            .iter()
            .all(|r| r.euler_dot == [0.0; 3] && r.command == 0)
    );
    let last = records.last().expect("records");
    assert_eq!(
        (last.t, last.command, last.kind),
        (6.0, 1, CommandKind::Stop)
    );
    // The reorientation alone, planned online, ends where the rest-to-rest
    // one does.
    assert!((last.angles_deg[0] - 0.0).abs() < 1e-9);
    assert!((last.angles_deg[1] - 35.0).abs() < 1e-9);
}

#[test]
fn the_supervisor_stops_short_of_the_parallel_singularity() {
    // Without commands this turn fails at the hard threshold (module 1's
    // parallel singularity near theta = 49.7 deg, see the CLI's tests); with
    // a command, the online controller's supervisor stops it first.
    let sim = Simulation::new(Scenario {
        run: Run::Online(Online {
            turn: Turn {
                psi_deg: 0.0,
                theta_deg: 60.0,
                ..Turn::paper()
            },
            stop_at_s: Some(8.0),
            ..Online::default()
        }),
        rate_hz: 100.0,
        ..Scenario::paper()
    })
    .expect("valid");
    let (records, _) = run(&sim);
    let stop = records
        .iter()
        .find(|r| r.kind == CommandKind::SupervisorStop)
        .expect("a stop demanded");
    assert_eq!(stop.command, 1);
    let last = records.last().expect("records");
    assert_eq!(
        (last.t, last.command, last.kind),
        (8.0, 2, CommandKind::Stop)
    );
    let lowest = records
        .iter()
        .map(|r| r.module1.parallel_margin)
        .fold(f64::INFINITY, f64::min);
    assert!(lowest > 0.03, "{lowest}");
    assert!(records.iter().any(|r| !r.warnings.is_empty()));
    let mut summary = Summary::for_simulation(&sim);
    sim.run(&mut summary).expect("runs");
    let text = summary.to_string();
    assert!(text.contains("supervisor_stop demanded,"), "{text}");
    assert!(text.contains("module1.parallel"), "{text}");
}

#[test]
fn commands_that_cannot_be_scheduled_are_named() {
    let err = |retargets: &[(f64, f64, f64)], stop_at_s: Option<f64>| {
        Simulation::new(Scenario {
            run: Run::Online(Online {
                turn: Turn::paper(),
                retargets: retargets
                    .iter()
                    .map(|&(t_s, psi_deg, theta_deg)| Retarget {
                        t_s,
                        psi_deg,
                        theta_deg,
                    })
                    .collect(),
                stop_at_s,
            }),
            ..Scenario::paper()
        })
        .expect_err("refused")
        .to_string()
    };
    assert_eq!(
        err(&[(1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)], None),
        "commands: retarget 2: t = -1 s is before the start (t = 0)"
    );
    assert_eq!(
        err(&[(2.0, 0.0, 0.0), (1.0, 0.0, 0.0)], None),
        "commands: retarget 2 at t = 1 s comes before retarget 1 at t = 2 s: give the retargets in time order"
    );
    assert_eq!(
        err(&[(1.0, f64::NAN, 0.0)], None),
        "commands: retarget 1: psi = NaN is not a finite number"
    );
    assert_eq!(
        err(&[], Some(f64::INFINITY)),
        "commands: the stop: t = inf is not a finite number"
    );
    assert_eq!(
        err(&[], Some(-0.5)),
        "commands: the stop: t = -0.5 s is before the start (t = 0)"
    );
    assert_eq!(
        err(&[(1.2001, 0.0, 0.0), (1.2004, 0.0, 0.0)], None),
        "commands: retarget 2 at t = 1.2004 s takes effect at the same sample as retarget 1 at t = 1.2001 s (t = 1.201 s at 1000 Hz): give each command a sample of its own"
    );
    assert_eq!(
        err(&[(3.0, 0.0, 0.0)], Some(3.0)),
        "commands: retarget 1 at t = 3 s takes effect at the same sample as the stop at t = 3 s (t = 3 s at 1000 Hz): give each command a sample of its own"
    );
    assert_eq!(
        err(&[(0.0, 0.0, 0.0)], None),
        "commands: retarget 1 at t = 0 s takes effect at the same sample as the reorientation at t = 0 s (t = 0 s at 1000 Hz): give each command a sample of its own"
    );
    let e = Simulation::new(Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            stop_at_s: Some(1e300),
            ..Online::default()
        }),
        ..Scenario::paper()
    })
    .expect_err("too long");
    assert!(matches!(e, SimulationError::Trajectory(_)), "{e}");
    assert!(e.to_string().contains("more samples than usize"), "{e}");
}

#[test]
fn the_supervisor_stops_short_of_a_joint_limit() {
    // Without commands, psi +40 drives the left module's qs2 past -80 deg
    // (the CLI's tests); a retarget there is stopped short of it.
    let sim = Simulation::new(Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            retargets: vec![Retarget {
                t_s: 1.0,
                psi_deg: 40.0,
                theta_deg: 25.0,
            }],
            ..Online::default()
        }),
        rate_hz: 1000.0,
        ..Scenario::paper()
    })
    .expect("plans");
    let (records, _) = run(&sim);
    assert!(
        records
            .iter()
            .any(|r| r.kind == CommandKind::SupervisorStop)
    );
    let lowest = records
        .iter()
        .map(|r| r.left.q[1].to_degrees())
        .fold(f64::INFINITY, f64::min);
    // The stop is predicted to first order (see `parasils::supervisor`):
    // qs2 ends within its stop threshold (1 deg) of the limit, but short
    // of it.
    assert!(lowest > -80.0, "{lowest}");
}

#[test]
fn an_unreachable_start_fails_at_the_first_sample() {
    let e = Simulation::new(Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            stop_at_s: Some(1.0),
            ..Online::default()
        }),
        tip_left_mm: [-400.0, 0.0, -500.0],
        ..Scenario::paper()
    })
    .expect_err("unreachable");
    assert!(
        e.to_string().starts_with("at t = 0.000 s: left instrument"),
        "{e}"
    );
    assert!(matches!(
        e,
        SimulationError::Kinematics {
            sample: Some(0),
            ..
        }
    ));
}
