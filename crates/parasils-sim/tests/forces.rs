//! Runs with tip loads: every record's actuator forces checked by the
//! balance of power against the record's own rates, with the tips'
//! velocities from central differences of the forward kinematics (no
//! Jacobian), on the paper's turn, a run with commands and the shipped
//! demo procedure.

use nalgebra::Vector3;
use parasils::kin::{Instrument, Joints, Pose};
use parasils_sim::input::{Input, ProcedureSource};
use parasils_sim::scenario::Retarget;
use parasils_sim::{Online, Record, Run, Scenario, Simulation, Turn, columns};

#[path = "common/turn.rs"]
mod turn;
use turn::{records, turn_state};

const LEFT_N: [f64; 3] = [4.0, -6.0, 9.0];
const RIGHT_N: [f64; 3] = [-3.0, 2.5, -12.0];

fn loaded(scenario: Scenario) -> Scenario {
    Scenario {
        tip_load_left_n: Some(LEFT_N),
        tip_load_right_n: Some(RIGHT_N),
        ..scenario
    }
}

/// The twelve actuators' power at `r` (N mm/s), and the sum of the terms'
/// magnitudes (the scale of the balance).
fn actuator_power(r: &Record) -> (f64, f64) {
    let f = &r.forces;
    let terms = (0..6)
        .map(|j| f.module1[j] * r.module1.q_dot[j])
        .chain((0..3).map(|k| f.left[k] * r.left.q_dot[k]))
        .chain((0..3).map(|k| f.right[k] * r.right.q_dot[k]));
    terms.fold((0.0, 0.0), |(s, m), t| (s + t, m + t.abs()))
}

/// The tip's velocity at `r` (mm/s, fixed frame) by central differences of
/// the forward kinematics along the record's Euler and joint rates, `P`
/// still.
fn tip_velocity(
    module: &Instrument<f64>,
    r: &Record,
    q: [f64; 3],
    q_dot: [f64; 3],
) -> Vector3<f64> {
    let h = 1e-4;
    let at = |s: f64| {
        let mut pose = r.pose;
        for i in 0..3 {
            pose[3 + i] += s * r.euler_dot[i];
        }
        let j = Joints::new(
            q[0] + s * q_dot[0],
            q[1] + s * q_dot[1],
            q[2] + s * q_dot[2],
        );
        module.fk(&Pose::from_array(pose), &j).expect("finite")
    };
    (at(h) - at(-h)) / (2.0 * h)
}

/// The balance at every record where `P` is still: the actuators' power is
/// the power the tips deliver, `F_L . v_L + F_R . v_R`.
fn check_balance(sim: &Simulation, records: &[Record], tolerance: f64) -> usize {
    let c = sim.controller();
    let mut checked = 0;
    for w in records.windows(3) {
        let r = &w[1];
        if w[0].pose[..3] != r.pose[..3] || w[2].pose[..3] != r.pose[..3] {
            continue;
        }
        let (power, scale) = actuator_power(r);
        let v_l = tip_velocity(&c.left, r, r.left.q, r.left.q_dot);
        let v_r = tip_velocity(&c.right, r, r.right.q, r.right.q_dot);
        let delivered = Vector3::from(LEFT_N).dot(&v_l) + Vector3::from(RIGHT_N).dot(&v_r);
        if scale < 1e-9 {
            assert!(delivered.abs() < 1e-6, "t = {}: {delivered}", r.t);
            continue;
        }
        // The differences' rounding, about 1e-16 * 600 mm / h (1e-4 s)
        // times the forces, bounds the absolute error from below.
        assert!(
            (power - delivered).abs() < tolerance * scale + 1e-8,
            "t = {}: {power} vs {delivered}",
            r.t
        );
        checked += 1;
    }
    checked
}

#[test]
fn the_paper_turn_under_tip_loads_balances_power() {
    let (sim, records) = records(loaded(Scenario::paper()));
    assert!(check_balance(&sim, &records, 1e-7) > 4000);
    // Module 1 alone carries the tips' forces to the platform: its power is
    // the wrench's on the platform's twist, from the record's Euler rates.
    let tips = sim.scenario().tips();
    for r in records.iter().step_by(37) {
        let state = turn_state(r, false);
        let frame = state.frame().expect("finite");
        let p = frame.position;
        let wrench_force = Vector3::from(LEFT_N) + Vector3::from(RIGHT_N);
        let moment = (tips.left - p).cross(&Vector3::from(LEFT_N))
            + (tips.right - p).cross(&Vector3::from(RIGHT_N));
        let platform =
            wrench_force.dot(&frame.velocity) + moment.dot(&(frame.rotation * frame.omega));
        let module1: f64 = (0..6)
            .map(|j| r.forces.module1[j] * r.module1.q_dot[j])
            .sum();
        let scale: f64 = (0..6)
            .map(|j| (r.forces.module1[j] * r.module1.q_dot[j]).abs())
            .sum();
        if scale > 0.0 {
            assert!((module1 - platform).abs() / scale < 1e-9, "t = {}", r.t);
        }
    }
    // The paper's columns are those of the run without loads, to the bit.
    let (_, plain) = turn::records(Scenario::paper());
    for (a, b) in plain.iter().zip(&records) {
        assert_eq!(columns::csv_row(a), columns::csv_row(b));
        assert_eq!(a.forces, Default::default());
    }
}

#[test]
fn a_run_with_commands_under_tip_loads_balances_power() {
    let scenario = Scenario {
        run: Run::Online(Online {
            turn: Turn::paper(),
            retargets: vec![Retarget {
                t_s: 1.2,
                psi_deg: 25.0,
                theta_deg: 15.0,
            }],
            stop_at_s: Some(3.0),
        }),
        ..loaded(Scenario::paper())
    };
    let (sim, records) = records(scenario);
    assert!(check_balance(&sim, &records, 1e-7) > 2000);
}

#[test]
fn the_demo_procedure_under_tip_loads_balances_power() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    );
    let scenario = Input {
        procedure: Some(ProcedureSource::File(path.into())),
        tip_load_left_n: Some(LEFT_N),
        tip_load_right_n: Some(RIGHT_N),
        ..Input::default()
    }
    .resolve()
    .expect("resolves");
    let (sim, records) = records(scenario);
    // The instruments move as well as the platform turns: the tips deliver
    // power, which the twelve actuators supply. The rows where `P` moves
    // (the positioning) are left out: a record has no `Pdot`.
    let checked = check_balance(&sim, &records, 1e-7);
    assert!(checked > 9000, "{checked} of {}", records.len());
    assert_eq!(columns::csv_columns_of(sim.scenario()).len(), 74 + 12 + 14);
}

#[test]
fn one_load_given_loads_that_tip_alone() {
    let (_, records) = records(Scenario {
        tip_load_left_n: Some([0.0, 0.0, -10.0]),
        ..Scenario::paper()
    });
    let r = &records[2000];
    assert_eq!(r.forces.right, [0.0; 3]);
    assert_eq!(r.forces.deflection[1], 0.0);
    // The left tip gives way under the tissue's push (0, 0, 10) N: its
    // deflection is the library's, and upwards.
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    let step = sim
        .controller()
        .step(
            &turn_state(r, true),
            &sim.scenario().tips(),
            &mut parasils::kin::MarginTracker::new(),
        )
        .expect("regular");
    let d = sim
        .controller()
        .tip_deflection(
            &step,
            parasils::kin::Side::Left,
            &Vector3::new(0.0, 0.0, 10.0),
            &parasils::kin::ActuatorStiffness::assumed(),
        )
        .expect("regular");
    assert!((d.norm() - r.forces.deflection[0]).abs() < 1e-12 * d.norm());
    assert!(d.z > 0.0);
    assert!(r.forces.left.iter().any(|v| v.abs() > 1.0));
    assert!(r.forces.module1.iter().all(|v| v.abs() > 1e-3));
}

#[test]
fn a_force_beyond_its_limit_stops_the_run_naming_the_actuator() {
    // 50 N along the left tool, outwards, at the start: by hand, the whole
    // force on the insertion (beyond the assumed 40 N) and no torque.
    let paper = Scenario::paper();
    let start = paper.start();
    let rcm = start.rotation() * Vector3::new(-10.0, 0.0, 0.0) + start.position();
    let along = (paper.tips().left - rcm).normalize() * 50.0;
    let sim = Simulation::new(Scenario {
        tip_load_left_n: Some(along.into()),
        ..paper
    })
    .expect("valid");
    let e = sim.samples().find_map(Result::err).expect("a limit");
    let text = e.to_string();
    assert!(
        text.ends_with("left qs3: force 50 N is beyond its limit 40 N"),
        "{text}"
    );
    assert_eq!(e.time_s(), Some(0.0));
}

#[test]
fn the_summary_gives_each_actuator_s_peak_use_of_its_force_limit() {
    let (sim, records) = records(loaded(Scenario::paper()));
    let mut summary = parasils_sim::Summary::for_simulation(&sim);
    for r in &records {
        parasils_sim::Sink::push(&mut summary, r).expect("infallible");
    }
    let text = summary.to_string();
    let line = text
        .lines()
        .skip_while(|l| !l.starts_with("force limits, peak use:"))
        .nth(1)
        .expect("the force line");
    // q1's peak use, from the records: max |tau_1| / 200 N.
    let peak = records
        .iter()
        .map(|r| r.forces.module1[0].abs())
        .fold(0.0, f64::max);
    assert!(line.contains(&format!("q1 {:.3}", peak / 200.0)), "{line}");
    let (plain_sim, plain) = turn::records(Scenario::paper());
    let mut summary = parasils_sim::Summary::for_simulation(&plain_sim);
    for r in &plain {
        parasils_sim::Sink::push(&mut summary, r).expect("infallible");
    }
    assert!(!summary.to_string().contains("force limits"));
}
