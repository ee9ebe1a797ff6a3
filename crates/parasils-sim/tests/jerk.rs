//! Jerk-limited procedure motions: `jerk_mm_s3` and `jerk_deg_s3` time a
//! motion by the double S along its straight line.

use std::path::Path;

use parasils::traj::{DoubleS, JerkLimits};
use parasils_sim::Simulation;

mod common;

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

const START: &str = r#"
pose = [15, 20, -460, -15, 10, -60]
tip_left_mm = [50, -50, -580]
"#;

fn simulate(motions: &str) -> Result<Simulation> {
    common::simulate_text(&format!("{START}{motions}"), Path::new("."))
}

fn error(motions: &str) -> String {
    common::refusal(&format!("{START}{motions}"))
}

const INSERT: &str = r#"
[[motion]]
type = "insert"
instrument = "left"
depth_mm = 30
velocity_mm_s = 20
acceleration_mm_s2 = 20
"#;

/// The largest change of the left `qs3` acceleration from one row to the
/// next within motion 0, mm/s^2, and the rows' period, s.
fn largest_step(sim: &Simulation) -> Result<(f64, f64)> {
    let mut previous: Option<(f64, f64)> = None;
    let (mut largest, mut dt) = (0.0_f64, 0.0);
    for r in sim.samples() {
        let r = r?;
        if r.motion != 0 {
            break;
        }
        if let Some((t, a)) = previous {
            largest = largest.max((r.left.q_ddot[2] - a).abs());
            dt = r.t - t;
        }
        previous = Some((r.t, r.left.q_ddot[2]));
    }
    Ok((largest, dt))
}

#[test]
fn a_jerk_limit_times_an_insertion_by_the_double_s() -> Result {
    let sim = simulate(&format!("{INSERT}jerk_mm_s3 = 40\n"))?;
    let plan = sim.procedure().ok_or("no plan")?;
    // By hand: a^2 / j = 10 mm/s < 20 mm/s, so the acceleration reaches
    // 20 mm/s^2: t_j = a / j = 0.5 s, t_a = v / a + t_j = 1.5 s, and the
    // 30 mm are covered with no cruise: 3 s.
    assert!((plan.motions[0].planned_s() - 3.0).abs() < 1e-12);
    let (step, dt) = largest_step(&sim)?;
    assert!(step <= 40.0 * dt * (1.0 + 1e-9), "{step}");
    assert!(step > 0.9 * 40.0 * dt, "{step}");
    // The trapezoid of the same motion jumps to its acceleration at once.
    let trapezoid = simulate(INSERT)?;
    let (jump, _) = largest_step(&trapezoid)?;
    assert!((jump - 20.0).abs() < 1e-9, "{jump}");
    // Both end on the target, at rest.
    for sim in [&sim, &trapezoid] {
        let last = sim
            .samples()
            .filter_map(core::result::Result::ok)
            .take_while(|r| r.motion == 0)
            .last()
            .ok_or("no rows")?;
        assert_eq!(last.left.q[2] - 30.0, first_qs3(sim)?);
        assert_eq!((last.left.q_dot[2], last.left.q_ddot[2]), (0.0, 0.0));
    }
    Ok(())
}

fn first_qs3(sim: &Simulation) -> Result<f64> {
    let first = sim.samples().next().ok_or("no rows")??;
    Ok(first.left.q[2])
}

#[test]
fn a_jerk_limited_turn_lasts_what_its_larger_angle_needs() -> Result {
    let sim = simulate(
        r#"
[[motion]]
type = "reorient"
psi_deg = 6
theta_deg = 4
velocity_deg_s = 10
acceleration_deg_s2 = 5
jerk_deg_s3 = 10
"#,
    )?;
    let plan = sim.procedure().ok_or("no plan")?;
    // The same limits on each angle: psi's 6 deg binds; in s the limits are
    // those over 6 deg, so the law lasts what the double S of psi alone does.
    let psi = DoubleS::new(0.0, 6.0, JerkLimits::new(10.0, 5.0, 10.0))?;
    assert!(
        (plan.motions[0].planned_s() - psi.duration()).abs() < 1e-9,
        "{} vs {}",
        plan.motions[0].planned_s(),
        psi.duration()
    );
    // theta follows in phase: both angles' rates in the ratio 6 : 4.
    for r in sim.samples().step_by(97) {
        let r = r?;
        let [psi_dot, theta_dot, _] = r.euler_dot;
        assert!(
            (4.0 * psi_dot - 6.0 * theta_dot).abs() < 1e-12,
            "{psi_dot} {theta_dot}"
        );
    }
    Ok(())
}

#[test]
fn jerk_keys_that_cannot_apply_are_errors_naming_the_key() {
    let stop = error(&format!(
        "{INSERT}until_s = 1\n[[motion]]\ntype = \"stop\"\njerk_mm_s3 = 40\n"
    ));
    assert!(
        stop.contains("jerk_mm_s3") && stop.contains("does not apply"),
        "{stop}"
    );
    let position = error(
        "[[motion]]\ntype = \"position\"\npose = [15, 20, -470, -15, 10, -60]\njerk_mm_s3 = 40\n",
    );
    assert!(
        position.contains("jerk_deg_s3") && position.contains("together"),
        "{position}"
    );
    let insert = error(&format!("{INSERT}jerk_deg_s3 = 40\n"));
    assert!(
        insert.contains("jerk_deg_s3") && insert.contains("does not apply"),
        "{insert}"
    );
    let negative = error(&format!("{INSERT}jerk_mm_s3 = -4\n"));
    assert!(
        negative.contains("jerk_mm_s3") && negative.contains("-4"),
        "{negative}"
    );
    let continued = error(&format!(
        "{INSERT}until_s = 1\n{}jerk_mm_s3 = 40\n",
        INSERT.replace("depth_mm = 30", "depth_mm = 5")
    ));
    assert!(continued.contains("takes no jerk limit"), "{continued}");
}
