//! Procedures under `--timing optimal`: motion types 1 to 3 (and 4) timed
//! by the actuators' limits and the limits the procedure states, against
//! hand-derived bang-bang durations, their own paths, every actuator's
//! limits at every sample, rest at both ends of each motion, finite
//! differences of the positions, and optimality (some limit is reached,
//! so no uniform time-scaling is shorter).

#![allow(
    clippy::needless_range_loop,
    reason = "the twelve actuators compared index by index"
)]

use nalgebra::Vector3;
use parasils::Port;
use parasils::kin::{ActuatorLimits, Pose};
use parasils_sim::procedure;
use parasils_sim::scenario::Timing;
use parasils_sim::timing::Binding;
use parasils_sim::{MotionGoal, MotionLimits, MotionSpec};
use parasils_sim::{Motions, Run, Timeline};
use parasils_sim::{Record, Scenario, Simulation};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

const OPTIMAL: Timing = Timing::Optimal { angular: false };

/// As the procedure tests' start: a little above the paper's P0.
fn start() -> Scenario {
    Scenario {
        start_mm_deg: [15.0, 20.0, -460.0, -15.0, 10.0, -60.0],
        tip_left_mm: [50.0, -50.0, -580.0],
        ..Scenario::paper()
    }
}

fn run(scenario: Scenario) -> Result<(Simulation, Vec<Record>)> {
    let sim = Simulation::new(scenario)?;
    let records = sim.samples().collect::<core::result::Result<Vec<_>, _>>()?;
    Ok((sim, records))
}

fn optimal(motions: Vec<MotionSpec>) -> Result<(Simulation, Vec<Record>)> {
    run(Scenario {
        run: Run::Planned(Timeline {
            motions: Motions::Procedure(motions),
            timing: OPTIMAL,
        }),
        ..start()
    })
}

/// The twelve actuators' positions, rates and accelerations of a record,
/// in the order of `Actuator::ALL` (mm, rad).
fn actuators(r: &Record) -> [[f64; 12]; 3] {
    let join = |m: [f64; 6], l: [f64; 3], rr: [f64; 3]| {
        let mut out = [0.0; 12];
        out[..6].copy_from_slice(&m);
        out[6..9].copy_from_slice(&l);
        out[9..].copy_from_slice(&rr);
        out
    };
    [
        join(r.module1.q, r.left.q, r.right.q),
        join(r.module1.q_dot, r.left.q_dot, r.right.q_dot),
        join(r.module1.q_ddot, r.left.q_ddot, r.right.q_ddot),
    ]
}

/// Every actuator within its limits at every record, to 1e-9 relative;
/// the largest fraction of a limit used.
fn peak_usage(records: &[Record], limits: &ActuatorLimits<f64>) -> f64 {
    let mut peak: f64 = 0.0;
    for r in records {
        let [_, v, a] = actuators(r);
        for j in 0..12 {
            let (uv, ua) = (
                v[j].abs() / limits.velocity[j],
                a[j].abs() / limits.acceleration[j],
            );
            assert!(
                uv <= 1.0 + 1e-9,
                "actuator {j} velocity {uv} of its limit at t = {}",
                r.t
            );
            assert!(
                ua <= 1.0 + 1e-9,
                "actuator {j} acceleration {ua} of its limit at t = {}",
                r.t
            );
            peak = peak.max(uv).max(ua);
        }
    }
    peak
}

/// The least fraction of a limit an optimal law still reaches once each
/// motion is stretched onto the control cycle: the law reaches a limit
/// (velocity or acceleration), and the stretch by `r = T / T'` scales
/// velocities by `r` and accelerations by `r^2`, so at least the smallest
/// `r^2`.
fn reached(sim: &Simulation) -> f64 {
    let plan = sim.procedure().expect("a procedure");
    let r = plan
        .motions
        .iter()
        .filter(|m| m.stretch.planned() > 0.0)
        .map(|m| m.stretch.ratio())
        .fold(1.0, f64::min);
    assert!(r > 0.99 && r <= 1.0, "{r}");
    r * r - 1e-6
}

/// The duration of a rest-to-rest bang-bang (or trapezoid) over `d`
/// within `v` and `a`.
fn bang_bang(d: f64, v: f64, a: f64) -> f64 {
    if d * a >= v * v {
        d / v + v / a
    } else {
        2.0 * (d / a).sqrt()
    }
}

#[test]
fn type_1_is_timed_by_the_sliders_and_stays_on_its_segment() -> Result {
    // 40 mm straight down: the six vertical sliders move 40 mm each at
    // 50 mm/s and 100 mm/s^2 (the motion's own 20 mm/s, not stated, do not
    // bind): 0.8 + 0.5 = 1.3 s against the trapezoid's 3 s.
    let goal = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];
    let (sim, records) = optimal(vec![MotionSpec::new(MotionGoal::Position {
        pose_mm_deg: goal,
    })])?;
    let expected = bang_bang(40.0, 50.0, 100.0);
    assert!((expected - 1.3).abs() < 1e-12);
    assert!(
        (sim.duration() - expected).abs() < 1e-3 * expected,
        "{}",
        sim.duration()
    );
    let limits = sim.controller().limits;
    assert!(peak_usage(&records, &limits) > reached(&sim));
    let a = sim.scenario().start().to_array();
    let b =
        Pose::<f64>::from_mm_deg(goal[0], goal[1], goal[2], goal[3], goal[4], goal[5]).to_array();
    for r in &records {
        for i in 0..6 {
            assert!(
                (r.pose[i] - (a[i] + (r.pose[2] - a[2]) / (b[2] - a[2]) * (b[i] - a[i]))).abs()
                    < 1e-9
            );
        }
        assert_eq!(r.left.q, records[0].left.q);
    }
    let last = &records[records.len() - 1];
    for i in 0..6 {
        assert!((last.pose[i] - b[i]).abs() < 1e-9);
    }
    // Stated, the motion's linear limit binds: its own trapezoid, 3 s.
    let (sim, _) = optimal(vec![MotionSpec {
        stated: [true, false],
        ..MotionSpec::new(MotionGoal::Position { pose_mm_deg: goal })
    }])?;
    assert!((sim.duration() - 3.0).abs() < 3e-3, "{}", sim.duration());
    let plan = sim.procedure().expect("a procedure");
    let law = plan.motions[0].optimal.as_ref().expect("timed optimally");
    assert!(
        law.phases()
            .iter()
            .all(|p| p.binding == Binding::Translation)
    );
    Ok(())
}

#[test]
fn type_2_is_a_bang_bang_in_qs3_or_in_the_endoscope_s_own_limits() -> Result {
    for (port, depth) in [
        (Port::Left, 30.0),
        (Port::Right, 80.0),
        (Port::Endoscope, 60.0),
    ] {
        let (sim, records) = optimal(vec![MotionSpec::new(MotionGoal::Insert {
            port,
            depth_mm: depth,
        })])?;
        // qs3 at 60 mm/s, 60 mm/s^2; the endoscope, which moves no
        // actuator, at the motion's default 20 mm/s and 20 mm/s^2.
        let expected = match port {
            Port::Endoscope => bang_bang(depth, 20.0, 20.0),
            _ => bang_bang(depth, 60.0, 60.0),
        };
        assert!(
            (sim.duration() - expected).abs() < 1e-3 * expected,
            "{port:?}: {} against {expected}",
            sim.duration()
        );
        peak_usage(&records, &sim.controller().limits);
        let last = &records[records.len() - 1];
        match port {
            Port::Left => assert!((last.left.q[2] - records[0].left.q[2] - depth).abs() < 1e-9),
            Port::Right => assert!((last.right.q[2] - records[0].right.q[2] - depth).abs() < 1e-9),
            Port::Endoscope => assert!((last.endoscope_depth - depth).abs() < 1e-9),
        }
        for r in &records {
            assert_eq!(r.module1.q, records[0].module1.q);
        }
        let law = sim.procedure().expect("procedure").motions[0]
            .optimal
            .clone()
            .expect("timed optimally");
        let binding = law.phases()[0].binding;
        match port {
            Port::Endoscope => assert_eq!(binding, Binding::Depth),
            _ => assert_eq!(binding.to_string(), format!("{} qs3", port.name())),
        }
    }
    Ok(())
}

#[test]
fn type_3_keeps_the_tip_on_its_line_and_reaches_an_actuator_limit() -> Result {
    let target = Vector3::new(62.0, -35.0, -610.0);
    let goal = MotionGoal::Manipulate {
        tip_left_mm: Some(target.into()),
        tip_right_mm: None,
    };
    let (sim, records) = optimal(vec![MotionSpec::new(goal)])?;
    let from = records[0].left.tip;
    let u = (target - from).normalize();
    let controller = *sim.controller();
    let pose = sim.scenario().start();
    for r in &records {
        let d = r.left.tip - from;
        assert!(
            (d - u * d.dot(&u)).norm() < 1e-9,
            "off the line at t = {}",
            r.t
        );
        // The joints are the instrument's own IK of the tip.
        let q = controller
            .left
            .ik(&pose, &r.left.tip, controller.modes[0])?;
        assert!((q.to_array()[0] - r.left.q[0]).abs() < 1e-9);
        assert!((q.to_array()[2] - r.left.q[2]).abs() < 1e-9);
        assert_eq!(r.right.q, records[0].right.q);
    }
    assert!((records[records.len() - 1].left.tip - target).norm() < 1e-9);
    // Optimal: an actuator limit is reached, so that no uniform
    // time-scaling is shorter by more than the grid's resolution (and the
    // stretch onto the control cycle).
    let peak = peak_usage(&records, &controller.limits);
    assert!(peak > reached(&sim), "{peak}");
    // The trapezoid at the motion's default limits uses less than every
    // actuator limit: the optimal law is shorter.
    let (trapezoid, trapezoid_records) = run(Scenario {
        run: Run::procedure(vec![MotionSpec::new(goal)]),
        ..start()
    })?;
    assert!(peak_usage(&trapezoid_records, &controller.limits) < 1.0);
    assert!(sim.duration() < trapezoid.duration());
    Ok(())
}

/// The shipped demo, sampled at 10 kHz, from its file.
fn demo(timing: Timing) -> Result<(Simulation, Vec<Record>)> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    );
    run(Scenario {
        rate_hz: 10_000.0,
        ..procedure::load(std::path::Path::new(path))?
    }
    .with_timing(timing))
}

#[test]
fn the_demo_is_shorter_within_every_limit_at_rest_between_motions() -> Result {
    let (sim, records) = demo(OPTIMAL)?;
    let (trapezoid, _) = demo(Timing::Trapezoid)?;
    assert!(sim.duration() < trapezoid.duration() - 1.0);
    let limits = sim.controller().limits;
    assert!(peak_usage(&records, &limits) > reached(&sim));
    // Rates are the derivatives of the positions: central differences over
    // two samples, within what a jump of the acceleration (at most twice
    // its limit) can make of them.
    let h = 1.0 / 10_000.0;
    for k in 1..records.len() - 1 {
        let [q0, _, _] = actuators(&records[k - 1]);
        let [_, v, _] = actuators(&records[k]);
        let [q1, _, _] = actuators(&records[k + 1]);
        for j in 0..12 {
            let fd = (q1[j] - q0[j]) / (2.0 * h);
            assert!(
                (fd - v[j]).abs() <= h * limits.acceleration[j] + 1e-9,
                "actuator {j} at t = {}: {fd} against {}",
                records[k].t,
                v[j]
            );
        }
    }
    // At rest where each motion starts and ends; the tips held during the
    // turn.
    let plan = sim.procedure().expect("procedure");
    for m in &plan.motions {
        for t in [m.start_s, m.start_s + m.length_s] {
            let r = records
                .iter()
                .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
                .expect("records");
            if (r.t - t).abs() < 1e-12 {
                let [_, v, _] = actuators(r);
                assert!(v.iter().all(|x| x.abs() < 1e-9), "moving at t = {t}: {v:?}");
            }
        }
        if m.name.motion_type.number() == 4 {
            for r in records
                .iter()
                .filter(|r| r.t > m.start_s && r.t < m.start_s + m.length_s)
            {
                assert!(r.left.tip_err < 1e-9 && r.right.tip_err < 1e-9);
            }
        }
    }
    Ok(())
}

#[test]
fn a_motion_cut_short_is_refused_and_a_rest_after_the_end_is_kept() {
    let insert = MotionSpec::new(MotionGoal::Insert {
        port: Port::Left,
        depth_mm: 30.0,
    });
    let cut = MotionSpec {
        until_s: Some(0.5),
        ..insert.clone()
    };
    let e = optimal(vec![cut, MotionSpec::new(MotionGoal::Stop)])
        .map(|_| ())
        .expect_err("cut short");
    let text = e.to_string();
    assert!(
        text.starts_with(
            "motion 0 (insert), 0.000 s into it: until_s = 0.5 s cuts the motion short"
        ),
        "{text}"
    );
    assert!(text.contains("from rest to rest"), "{text}");
    let rest = MotionSpec {
        until_s: Some(3.0),
        ..insert
    };
    // Each rests to its 3 s (rows 0 to 3000); the second starts on the
    // cycle after the first one's last row, at 3.001 s.
    let (sim, _) = optimal(vec![rest.clone(), rest]).expect("rests");
    assert_eq!(sim.duration(), 6.001);
}

#[test]
fn limits_the_trapezoid_exceeds_fail_it_and_slow_the_optimal_law() -> Result {
    // qs3 at 10 mm/s: the insertion's 20 mm/s trapezoid exceeds it.
    let mut scenario = Scenario {
        run: Run::procedure(vec![MotionSpec {
            limits: MotionLimits::default(),
            ..MotionSpec::new(MotionGoal::Insert {
                port: Port::Left,
                depth_mm: 40.0,
            })
        }]),
        ..start()
    };
    scenario.robot.limits.velocity[8] = 10.0;
    let e = Simulation::new(scenario.clone())
        .and_then(|sim| sim.samples().try_for_each(|r| r.map(|_| ())).map(|()| sim))
        .map(|_| ())
        .expect_err("left qs3 at 20 mm/s");
    assert!(e.to_string().contains("left qs3"), "{e}");
    let (sim, records) = run(scenario.with_timing(OPTIMAL))?;
    // 40 mm at 10 mm/s, 60 mm/s^2: 4 + 1/6 s, longer than the 3 s
    // trapezoid, within every limit.
    let expected = bang_bang(40.0, 10.0, 60.0);
    assert!(
        (sim.duration() - expected).abs() < 1e-3 * expected,
        "{}",
        sim.duration()
    );
    assert!(peak_usage(&records, &sim.controller().limits) > reached(&sim));
    Ok(())
}
