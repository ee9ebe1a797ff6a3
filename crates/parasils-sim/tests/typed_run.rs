//! A run is a type: the paper's turn is a timeline of one motion, planned
//! on the same path as a procedure's motions. Its records are checked here
//! against a second implementation, the turn as the engine planned it
//! before: a `Reorientation` (or the time-optimal law of the turn alone,
//! `OptimalMotion::turn`) placed on the control cycle by `OnCycle`, each sample stepped through
//! `Controller::step` with the scenario's tips. The trapezoid's records
//! agree to the bit; the time-optimal law's within 1e-12 relative (they
//! agree to the bit today, but the path's geometry is free to move its last
//! digits).

use parasils::geometry::MotionSample;
use parasils::kin::{Controller, MarginTracker, PlatformState};
use parasils::traj::{Motion, Sampler, Synchronization};
use parasils::{OnCycle, Reorientation};
use parasils_sim::timing::{OptimalMotion, TimingOptions};
use parasils_sim::{
    CommandKind, MotionGoal, MotionSpec, Online, Record, Retarget, Run, Scenario, Simulation,
    Timing, Turn,
};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// The platform's part of a motion's samples.
struct Platform<M>(M);

impl<M: Motion<f64, Output = MotionSample<f64>>> Motion<f64> for Platform<M> {
    type Output = PlatformState<f64>;

    fn duration(&self) -> f64 {
        self.0.duration()
    }

    fn sample(&self, t: f64) -> PlatformState<f64> {
        self.0.sample(t).platform
    }
}

/// The paper's scenario with `turn` at `rate_hz`, timed by `timing`.
fn turned(turn: Turn, rate_hz: f64, timing: Timing) -> Scenario {
    Scenario {
        rate_hz,
        run: Run::turn(turn),
        ..Scenario::paper()
    }
    .with_timing(timing)
}

/// The turns checked: the paper's, and each option of a turn changed.
fn turns() -> Vec<(Turn, f64)> {
    let paper = Turn::paper();
    vec![
        (paper, 1000.0),
        (
            Turn {
                psi_deg: -10.0,
                theta_deg: 5.0,
                sync: Synchronization::Time,
                ..paper
            },
            250.0,
        ),
        (
            Turn {
                psi_deg: 20.0,
                theta_deg: 3.0,
                sync: Synchronization::None,
                ..paper
            },
            1000.0,
        ),
        (
            Turn {
                psi_deg: -5.0,
                theta_deg: 20.0,
                absolute: true,
                omega_max_deg_s: 7.0,
                eps_max_deg_s2: 4.0,
                ..paper
            },
            333.0,
        ),
    ]
}

/// Every record of `scenario`'s run against the states of `states`, each
/// stepped through the controller with the scenario's tips: the same
/// numbers, to the bit with `rel = 0`, else within `rel` relative (of the
/// larger magnitude, at least 1).
fn same_as<M: Motion<f64, Output = PlatformState<f64>>>(
    scenario: &Scenario,
    states: Sampler<f64, M>,
    rel: f64,
) -> Result {
    let close = |got: &[f64], want: &[f64], what: &str| {
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(want) {
            let ok = if rel == 0.0 {
                g.to_bits() == w.to_bits()
            } else {
                (g - w).abs() <= rel * g.abs().max(w.abs()).max(1.0)
            };
            assert!(ok, "{what}: {g} vs {w}");
        }
    };
    let sim = Simulation::new(scenario.clone())?;
    let controller = Controller::from_geometry(&scenario.robot)?;
    let tips = scenario.tips();
    let mut tracker = MarginTracker::new();
    let records = sim
        .samples()
        .collect::<core::result::Result<Vec<Record>, _>>()?;
    assert_eq!(records.len(), states.sample_count());
    assert_eq!(sim.sample_count(), states.sample_count());
    for (r, s) in records.iter().zip(states) {
        let out = controller.step(&s.state, &tips, &mut tracker)?;
        let at = format!("sample {} at {} Hz", r.index, scenario.rate_hz);
        assert_eq!((r.index, r.t), (s.index, s.time), "{at}");
        close(&r.pose, &s.state.pose.to_array(), &at);
        let v = s.state.velocity;
        let a = s.state.acceleration;
        close(&r.euler_dot, &[v.psi, v.theta, v.phi], &at);
        close(&r.euler_ddot, &[a.psi, a.theta, a.phi], &at);
        let m1 = &out.module1;
        close(&r.module1.q, &m1.q.to_array(), &at);
        close(&r.module1.q_dot, &m1.q_dot.to_array(), &at);
        close(&r.module1.q_ddot, &m1.q_ddot.to_array(), &at);
        close(&[r.module1.parallel_margin], &[m1.margins.parallel], &at);
        for (got, want) in [(&r.left, &out.left), (&r.right, &out.right)] {
            close(&got.q, &want.q.to_array(), &at);
            close(&got.q_dot, &want.q_dot.to_array(), &at);
            close(&got.q_ddot, &want.q_ddot.to_array(), &at);
        }
        assert_eq!((r.motion, r.motion_type), (0, 4), "{at}");
        assert_eq!((r.command, r.kind), (0, CommandKind::Reorient), "{at}");
    }
    Ok(())
}

#[test]
fn the_planned_turn_is_the_reorientation_on_the_cycle_to_the_bit() -> Result {
    for (turn, rate) in turns() {
        let scenario = turned(turn, rate, Timing::Trapezoid);
        let start = scenario.start();
        let reorientation =
            Reorientation::new(start, turn.goal_rad(&start), [turn.limits(); 2], turn.sync)?;
        let states = Sampler::new(OnCycle::new(reorientation, rate)?, rate)?;
        same_as(&scenario, states, 0.0)?;
    }
    Ok(())
}

#[test]
fn the_optimal_turn_is_the_optimal_reorientation_on_the_cycle() -> Result {
    for (turn, rate) in turns().into_iter().take(2) {
        for angular in [false, true] {
            let scenario = turned(turn, rate, Timing::Optimal { angular });
            let start = scenario.start();
            let controller = Controller::from_geometry(&scenario.robot)?;
            let options = TimingOptions {
                angular: angular.then(|| [turn.limits(); 2]),
                ..TimingOptions::default()
            };
            let law = OptimalMotion::turn(
                &controller,
                start,
                turn.goal_rad(&start),
                scenario.tips(),
                &controller.limits,
                &options,
            )?;
            let sim = Simulation::new(scenario.clone())?;
            let engine = sim.optimal().ok_or("the turn's optimal law")?;
            assert!((engine.duration() - law.duration()).abs() < 1e-12);
            let phases = |p: Vec<parasils_sim::timing::PhaseSummary>| -> Vec<_> {
                p.iter().map(|p| (p.binding, p.kind)).collect()
            };
            assert_eq!(phases(engine.phases()), phases(law.phases()));
            let states = Sampler::new(Platform(OnCycle::new(law, rate)?), rate)?;
            same_as(&scenario, states, 1e-12)?;
        }
    }
    Ok(())
}

#[test]
fn each_kind_of_run_lists_its_own_commands() -> Result {
    let paper = Scenario::paper();
    let start = paper.start();
    // The planned turn: its reorientation at 0, with its goal.
    let commands = paper.commands();
    assert_eq!(commands.len(), 1);
    assert_eq!(commands[0].goal_deg, Some([15.0, 25.0]));
    assert_eq!(paper.goal_rad(), Turn::paper().goal_rad(&start));
    assert!(!paper.has_commands() && !paper.is_procedure());
    // A procedure: the command without a goal, no turn of its own.
    let procedure = Scenario {
        run: Run::procedure(vec![MotionSpec::new(MotionGoal::Reorient {
            psi_deg: 15.0,
            theta_deg: 25.0,
            absolute: false,
        })]),
        ..Scenario::paper()
    };
    assert_eq!(procedure.commands()[0].goal_deg, None);
    assert!(procedure.turn().is_none() && procedure.is_procedure());
    assert_eq!(procedure.goal_rad(), [start.psi, start.theta]);
    // Its MCAP metadata keeps the fields it always had.
    let units = serde_json::to_value(procedure.library_units())?;
    assert_eq!(units["psi"], 15f64.to_radians());
    assert_eq!(units["motions"][0]["type"], "reorient");
    // Online: the turn, then the stop before a retarget of the same time.
    let online = Scenario {
        run: Run::Online(Online {
            turn: Turn {
                psi_deg: 5.0,
                ..Turn::paper()
            },
            retargets: vec![Retarget {
                t_s: 2.0,
                psi_deg: 1.0,
                theta_deg: 2.0,
            }],
            stop_at_s: Some(2.0),
        }),
        ..Scenario::paper()
    };
    let kinds: Vec<_> = online
        .commands()
        .iter()
        .map(|c| (c.index, c.kind))
        .collect();
    assert_eq!(
        kinds,
        [
            (0, CommandKind::Reorient),
            (1, CommandKind::Stop),
            (2, CommandKind::Retarget)
        ]
    );
    assert_eq!(online.commands()[0].goal_deg, Some([5.0, 25.0]));
    assert!(online.has_commands());
    // An online run is timed by the trapezoids whatever is asked.
    assert_eq!(
        online
            .clone()
            .with_timing(Timing::Optimal { angular: false }),
        online
    );
    Ok(())
}
