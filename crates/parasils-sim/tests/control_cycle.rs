//! Motions on the control cycle: a procedure whose motions' planned
//! durations are not whole numbers of periods, under both timings. Every
//! motion is stretched to a whole number of periods; its first and last rows
//! are at rest, its last row is its target exactly, and the motion column
//! changes only between such rows.

use nalgebra::Vector3;
use parasils::Port;
use parasils::kin::{ModuleCommand, Pose};
use parasils_sim::columns::ALL;
use parasils_sim::scenario::Timing;
use parasils_sim::{MotionGoal, MotionSpec};
use parasils_sim::{Motions, Run, Timeline};
use parasils_sim::{Record, Scenario, Simulation};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// As the procedure tests' start: a little above the paper's P0.
fn start() -> Scenario {
    Scenario {
        start_mm_deg: [15.0, 20.0, -460.0, -15.0, 10.0, -60.0],
        tip_left_mm: [50.0, -50.0, -580.0],
        ..Scenario::paper()
    }
}

const TIP: [f64; 3] = [62.0, -35.0, -610.0];
const DEPTH_MM: f64 = 13.3;
const POSE: [f64; 6] = [22.0, 14.0, -483.456, -8.0, 11.5, -59.0];
const TURN_DEG: [f64; 2] = [4.1, -3.3];

/// Types 3, 1, 2 and 4 (the positioning before the insertion: once the
/// instrument is inside, the platform's `P` stays on the incision), each
/// with a duration that is no whole number of milliseconds under the
/// trapezoids: the manipulation's arc length `|(12, 15, -30)| = sqrt(1269)`
/// mm; the positioning's `psi` by 7 deg, a triangle of `2 sqrt(7 / 5)` s,
/// slower than its `z` (2.1728 s); the insertion's triangle
/// `2 sqrt(13.3 / 20)` s; the turn's triangle `2 sqrt(4.1 / 5)` s.
fn motions() -> Vec<MotionSpec> {
    vec![
        MotionSpec::new(MotionGoal::Manipulate {
            tip_left_mm: Some(TIP),
            tip_right_mm: None,
        }),
        MotionSpec::new(MotionGoal::Position { pose_mm_deg: POSE }),
        MotionSpec::new(MotionGoal::Insert {
            port: Port::Left,
            depth_mm: DEPTH_MM,
        }),
        MotionSpec::new(MotionGoal::Reorient {
            psi_deg: TURN_DEG[0],
            theta_deg: TURN_DEG[1],
            absolute: false,
        }),
    ]
}

fn rates(r: &Record) -> Vec<(&'static str, f64)> {
    ALL.iter()
        .filter(|c| c.name.contains("_rate_"))
        .map(|c| (c.name, c.value(r)))
        .collect()
}

fn assert_at_rest(r: &Record, what: &str) {
    for (name, v) in rates(r) {
        assert!(v == 0.0, "{what}: {name} = {v} at t = {}", r.t);
    }
}

fn check(timing: Timing) -> Result {
    let sim = Simulation::new(Scenario {
        run: Run::Planned(Timeline {
            motions: Motions::Procedure(motions()),
            timing,
        }),
        ..start()
    })?;
    let records = sim.samples().collect::<core::result::Result<Vec<_>, _>>()?;
    let plan = sim.procedure().ok_or("a procedure")?;
    let rate = sim.scenario().rate_hz;
    assert_eq!(rate, 1000.0);
    assert_eq!(plan.motions.len(), 4);
    assert_eq!(records.len(), plan.sample_count());
    let mut next = 0;
    for m in &plan.motions {
        let s = &m.stretch;
        // Not a whole number of periods as planned: stretched to the next.
        let periods = s.planned() * rate;
        assert!(periods.fract() > 1e-6, "{} lasts {} s", m.name, s.planned());
        assert_eq!(s.periods() as f64, periods.ceil());
        assert_eq!(m.periods, s.periods());
        assert_eq!(m.duration(), s.periods() as f64 / rate);
        assert!((s.ratio() - s.planned() / m.duration()).abs() < 1e-15);
        assert!(s.ratio() < 1.0 && s.ratio() > 1.0 - 1.0 / periods);
        // On the time line: one after the other, the next one a cycle after
        // the last row of the one before.
        assert_eq!(m.first_sample, next);
        assert_eq!(m.start_s, m.first_sample as f64 / rate);
        next = m.first_sample + m.periods + 1;
        let (first, last) = (
            &records[m.first_sample],
            &records[m.first_sample + m.periods],
        );
        assert_eq!(first.motion as usize, m.name.index);
        assert_eq!(last.motion as usize, m.name.index);
        assert_at_rest(first, "first row");
        assert_at_rest(last, "last row");
    }
    assert_eq!(next, records.len());
    // The motion column changes only between a last row and a first row.
    for w in records.windows(2) {
        assert_eq!(w[1].t, w[1].index as f64 / rate);
        assert!(w[1].t > w[0].t);
        if w[1].motion != w[0].motion {
            assert_eq!(w[1].motion, w[0].motion + 1);
            let m = &plan.motions[w[1].motion as usize];
            assert_eq!(w[1].index, m.first_sample);
            assert_at_rest(&w[0], "before a change");
            assert_at_rest(&w[1], "after a change");
        }
    }
    // Each last row is its target itself, not a sum short of it.
    let last_of = |k: usize| {
        let m = &plan.motions[k];
        (
            &records[m.first_sample + m.periods],
            m.first_sample + m.periods,
        )
    };
    // Type 3: the commanded tip is the target; the tip by FK within 1e-9.
    let (r, row) = last_of(0);
    let (_, sample) = plan.sample_index(row);
    let ModuleCommand::Tip(tip) = sample.left else {
        return Err("the left tip commanded".into());
    };
    assert_eq!(tip.position, Vector3::from(TIP));
    assert!((r.left.tip - Vector3::from(TIP)).norm() < 1e-9);
    // Type 1: the pose.
    let goal = Pose::<f64>::from_mm_deg(POSE[0], POSE[1], POSE[2], POSE[3], POSE[4], POSE[5]);
    let (r, _) = last_of(1);
    assert_eq!(r.pose, goal.to_array());
    // Type 2: qs3 deeper by the depth, from where the manipulation left it
    // (the positioning holds the joints).
    let (r, _) = last_of(2);
    let before = last_of(0).0;
    assert_eq!(r.left.q[2], before.left.q[2] + DEPTH_MM);
    // Type 4: the angles turned from the positioning's goal.
    let (r, _) = last_of(3);
    assert_eq!(r.pose[3], goal.psi + TURN_DEG[0].to_radians());
    assert_eq!(r.pose[4], goal.theta + TURN_DEG[1].to_radians());
    assert_eq!(r.pose[..3], goal.to_array()[..3]);
    // The stretch is a time scaling: at every row, the rates are the
    // planned law's at `t r`, times `r`; its accelerations times `r^2`.
    for m in &plan.motions {
        let r = m.stretch.ratio();
        for j in [1, m.periods / 3, m.periods / 2, m.periods - 1] {
            let t = j as f64 / rate;
            let on_cycle = plan.sample_index(m.first_sample + j).1;
            let law = match &m.optimal {
                Some(o) => o.sample_at(t * r),
                None => m.motion.sample(t * r),
            };
            assert_eq!(on_cycle.platform.pose, law.platform.pose);
            let (a, b) = (on_cycle.platform.velocity, law.platform.velocity);
            for (x, y) in [(a.z, b.z), (a.psi, b.psi), (a.theta, b.theta)] {
                assert!(
                    (x - y * r).abs() <= 1e-15 * y.abs().max(1e-300),
                    "{x} vs {y}"
                );
            }
            let (a, b) = (on_cycle.platform.acceleration, law.platform.acceleration);
            assert!((a.psi - b.psi * r * r).abs() <= 1e-15 * b.psi.abs());
            assert_eq!(on_cycle.endoscope.position, law.endoscope.position);
        }
    }
    // The summary and the check report both durations.
    let report = sim.procedure_check().ok_or("a check")?;
    for (c, m) in report.motions.iter().zip(&plan.motions) {
        assert_eq!(c.planned_s, m.stretch.planned());
        assert_eq!(c.stretched_s, m.duration());
        assert_eq!(c.duration_s, m.duration());
    }
    let text = parasils_sim::summary::CheckReport::new(&sim, report).to_string();
    assert!(text.contains("planned_s stretched_s"), "{text}");
    Ok(())
}

#[test]
fn trapezoid_motions_are_stretched_onto_the_cycle_and_join_at_rest() -> Result {
    check(Timing::Trapezoid)
}

#[test]
fn optimal_motions_are_stretched_onto_the_cycle_and_join_at_rest() -> Result {
    check(Timing::Optimal { angular: false })
}

#[test]
fn a_motion_of_1_2345_s_lasts_1_235_s_at_1_khz() -> Result {
    // A left insertion of d = 20 * 1.2345^2 / 4 mm on a triangle at 20 mm/s^2
    // lasts 2 sqrt(d / 20) = 1.2345 s (to rounding).
    let d = 20.0 * 1.2345_f64.powi(2) / 4.0;
    let sim = Simulation::new(Scenario {
        run: Run::procedure(vec![MotionSpec::new(MotionGoal::Insert {
            port: Port::Left,
            depth_mm: d,
        })]),
        ..start()
    })?;
    let plan = sim.procedure().ok_or("a procedure")?;
    let m = &plan.motions[0];
    assert!((m.stretch.planned() - 1.2345).abs() < 1e-12);
    assert_eq!(m.periods, 1235);
    assert_eq!(m.duration(), 1.235);
    assert_eq!(sim.duration(), 1.235);
    assert_eq!(sim.sample_count(), 1236);
    // The peak rate is the planned one times 1.2345 / 1.235.
    let peak = 2.0 * d / 1.2345;
    let records = sim.samples().collect::<core::result::Result<Vec<_>, _>>()?;
    let fastest = records.iter().map(|r| r.left.q_dot[2]).fold(0.0, f64::max);
    let expected = peak * m.stretch.ratio();
    // The triangle's peak falls at 0.6175 s, half a period from a sample,
    // where the rate is at most half a period's acceleration below it.
    let a = 20.0 * m.stretch.ratio().powi(2);
    assert!(fastest <= expected + 1e-12, "{fastest} vs {expected}");
    assert!(
        fastest >= expected - a * 0.0005 - 1e-12,
        "{fastest} vs {expected}"
    );
    assert!((expected - peak * 1.2345 / 1.235).abs() < 1e-9);
    let last = &records[1235];
    assert_eq!(last.left.q[2], records[0].left.q[2] + d);
    assert_eq!(last.left.q_dot[2], 0.0);
    Ok(())
}
