//! The unit tests of [`input`](crate::input) (a module of their own:
//! `input.rs` is near the size limit).

use parasils::traj::Synchronization;

use crate::input::*;
use crate::motion::{LookAt, LookAtTips};
use crate::robot::Robot;
use crate::scenario::{Retarget, Run, Timing};

#[test]
fn every_field_but_rate_and_timing_is_refused_with_a_procedure() {
    let procedure = Some(ProcedureSource::Json("{}".into()));
    let base = Input {
        procedure,
        ..Input::default()
    };
    // Each case gives one field.
    type Give = fn(&mut Input);
    let cases: [(Give, InputField); 13] = [
        (
            |i| i.look_at = Some(LookAt::Tips(LookAtTips::Tips)),
            InputField::LookAt,
        ),
        (|i| i.psi_deg = Some(15.0), InputField::PsiDeg),
        (|i| i.theta_deg = Some(25.0), InputField::ThetaDeg),
        (|i| i.absolute = Some(false), InputField::Absolute),
        (|i| i.omega_max_deg_s = Some(10.0), InputField::OmegaMaxDegS),
        (|i| i.eps_max_deg_s2 = Some(5.0), InputField::EpsMaxDegS2),
        (|i| i.sync = Some(Synchronization::Phase), InputField::Sync),
        (|i| i.pose_mm_deg = Some([0.0; 6]), InputField::PoseMmDeg),
        (|i| i.tip_left_mm = Some([0.0; 3]), InputField::TipLeftMm),
        (|i| i.tip_right_mm = Some([0.0; 3]), InputField::TipRightMm),
        (
            |i| i.robot = Some(RobotSource::Loaded(Box::default())),
            InputField::Robot,
        ),
        (|i| i.retarget = Some(Vec::new()), InputField::Retarget),
        (|i| i.stop_at_s = Some(1.0), InputField::StopAtS),
    ];
    for (set, field) in cases {
        let mut input = base.clone();
        set(&mut input);
        match input.resolve() {
            Err(InputError::WithProcedure(f)) => assert_eq!(f, field),
            other => panic!("{field}: {other:?}"),
        }
    }
}

#[test]
fn a_procedure_takes_the_rate_and_the_timing() {
    let json = r#"{"motion": [{"type": "insert", "instrument": "endoscope", "depth_mm": 40}]}"#;
    let s = Input {
        procedure: Some(ProcedureSource::Json(json.into())),
        rate_hz: Some(250.0),
        timing: Some(TimingKind::Optimal),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.rate_hz, 250.0);
    assert_eq!(s.timing(), Timing::Optimal { angular: false });
    assert_eq!(s.motions().len(), 1);
    assert!(s.is_procedure());
}

#[test]
fn either_angular_limit_given_makes_both_bind() {
    let eps = Input {
        timing: Some(TimingKind::Optimal),
        eps_max_deg_s2: Some(5.0),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(eps.timing(), Timing::Optimal { angular: true });
    // The trapezoid always binds them: the flag is not its business.
    let trapezoid = Input {
        omega_max_deg_s: Some(7.0),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(trapezoid.timing(), Timing::Trapezoid);
    assert_eq!(trapezoid.limits().v_max, 7f64.to_radians());
}

#[test]
fn commands_make_an_online_run_and_refuse_the_optimal_timing() {
    let retarget = Some(vec![Retarget {
        t_s: 1.0,
        psi_deg: 5.0,
        theta_deg: 5.0,
    }]);
    let online = Input {
        retarget: retarget.clone(),
        stop_at_s: Some(3.0),
        psi_deg: Some(-10.0),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    match &online.run {
        Run::Online(o) => {
            assert_eq!(o.turn.psi_deg, -10.0);
            assert_eq!(o.retargets.len(), 1);
            assert_eq!(o.stop_at_s, Some(3.0));
        }
        other => panic!("{other:?}"),
    }
    // No retarget at all is no command: the planned turn.
    let none = Input {
        retarget: Some(Vec::new()),
        timing: Some(TimingKind::Optimal),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(none.run, Run::Planned(_)));
    for (input, field) in [
        (
            Input {
                retarget,
                ..Input::default()
            },
            InputField::Retarget,
        ),
        (
            Input {
                stop_at_s: Some(1.0),
                ..Input::default()
            },
            InputField::StopAtS,
        ),
    ] {
        let optimal = Input {
            timing: Some(TimingKind::Optimal),
            ..input.clone()
        };
        match optimal.resolve() {
            Err(e @ InputError::OptimalOnline(f)) => {
                assert_eq!((f, e.field()), (field, field));
                assert!(e.to_string().starts_with(field.name()), "{e}");
            }
            other => panic!("{field}: {other:?}"),
        }
        // The trapezoid, given or not, takes commands.
        let trapezoid = Input {
            timing: Some(TimingKind::Trapezoid),
            ..input
        };
        assert!(trapezoid.resolve().is_ok_and(|s| s.has_commands()));
    }
}

#[test]
fn a_look_at_excludes_the_angles_and_the_commands() {
    let tips = Some(LookAt::Tips(LookAtTips::Tips));
    let s = Input {
        look_at: tips,
        timing: Some(TimingKind::Optimal),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    let turn = s.turn().copied().unwrap_or_default();
    assert_eq!(
        (turn.look_at, turn.psi_deg, turn.theta_deg),
        (tips, 0.0, 0.0)
    );
    assert_eq!(s.timing(), Timing::Optimal { angular: false });
    for (input, with) in [
        (
            Input {
                psi_deg: Some(15.0),
                ..Input::default()
            },
            InputField::PsiDeg,
        ),
        (
            Input {
                absolute: Some(true),
                ..Input::default()
            },
            InputField::Absolute,
        ),
        (
            Input {
                stop_at_s: Some(1.0),
                ..Input::default()
            },
            InputField::StopAtS,
        ),
    ] {
        let e = Input {
            look_at: tips,
            ..input
        }
        .resolve()
        .map(|_| ())
        .map_err(|e| (e.field(), e.to_string()));
        let Err((field, text)) = e else {
            panic!("{with}: resolved");
        };
        assert_eq!(field, InputField::LookAt);
        assert!(
            text.starts_with(&format!("look_at cannot be given with {with}")),
            "{text}"
        );
    }
}

#[test]
fn look_at_reads_the_tips_or_a_point() {
    assert_eq!(
        look_at_named("left").ok(),
        Some(LookAt::Tips(LookAtTips::Left))
    );
    assert_eq!(
        look_at_named("40, 50,-650").ok(),
        Some(LookAt::Point([40.0, 50.0, -650.0]))
    );
    for bad in ["middle", "1,2", "1,2,3,4", "1,nan,3", "1,,3"] {
        assert!(
            matches!(
                look_at_named(bad),
                Err(InputError::Unknown {
                    field: InputField::LookAt,
                    ..
                })
            ),
            "{bad}"
        );
    }
}

#[test]
fn a_loaded_robot_brings_its_supervisor_thresholds() {
    let mut robot = Robot::paper();
    robot.supervisor.cos_qs2_warn = Some(0.5);
    let s = Input {
        robot: Some(RobotSource::Loaded(Box::new(robot))),
        ..Input::default()
    }
    .resolve()
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.supervisor.cos_qs2_warn, Some(0.5));
}

#[test]
fn names_are_read_or_refused_naming_the_field() {
    assert_eq!(sync_named("time").ok(), Some(Synchronization::Time));
    assert_eq!(timing_named("optimal").ok(), Some(TimingKind::Optimal));
    let e = sync_named("both").map(|_| ()).map_err(|e| e.to_string());
    assert_eq!(
        e,
        Err("sync must be 'phase', 'time' or 'none', got \"both\"".into())
    );
    assert_eq!(InputField::OmegaMaxDegS.flag(), "--omega-max");
    assert_eq!(InputField::OmegaMaxDegS.name(), "omega_max_deg_s");
}
