//! Inside or outside the patient: the state each planned motion starts in,
//! and the paper's rules while anything is inside (no move of the incision
//! point `P`, no turn of `phi`), refused before any output.

use parasils::Port;
use parasils_sim::Run;
use parasils_sim::procedure;
use parasils_sim::{Inside, InsideRule, MotionGoal, MotionSpec, Scenario, Simulation};
use parasils_sim::{ProcedurePlan, SimulationError};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// The demo's start, at 100 Hz to keep the checks short.
fn start() -> Scenario {
    Scenario {
        start_mm_deg: [15.0, 20.0, -460.0, -15.0, 10.0, -60.0],
        tip_left_mm: [50.0, -50.0, -580.0],
        rate_hz: 100.0,
        ..Scenario::paper()
    }
}

fn position(pose_mm_deg: [f64; 6]) -> MotionSpec {
    MotionSpec::new(MotionGoal::Position { pose_mm_deg })
}

fn insert(port: Port, depth_mm: f64) -> MotionSpec {
    MotionSpec::new(MotionGoal::Insert { port, depth_mm })
}

fn reorient(psi_deg: f64, theta_deg: f64) -> MotionSpec {
    MotionSpec::new(MotionGoal::Reorient {
        psi_deg,
        theta_deg,
        absolute: false,
    })
}

/// Over the port, as the demo's first motion puts the platform.
const PORT: [f64; 6] = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];

fn simulate(motions: Vec<MotionSpec>) -> core::result::Result<Simulation, SimulationError> {
    Simulation::new(Scenario {
        run: Run::procedure(motions),
        ..start()
    })
}

fn plan(sim: &Simulation) -> Result<&ProcedurePlan> {
    sim.procedure().ok_or_else(|| "no procedure plan".into())
}

/// The fields of a refusal: (index, rule, inside, moved mm, turned deg).
fn refusal(e: &SimulationError) -> Option<(usize, InsideRule, Inside, f64, f64)> {
    match e {
        SimulationError::Inside {
            motion,
            rule,
            inside,
            moved_mm,
            turned_deg,
        } => Some((motion.index, *rule, *inside, *moved_mm, *turned_deg)),
        _ => None,
    }
}

#[test]
fn the_issues_turn_about_the_endoscopes_axis_is_refused_naming_motion_2() -> Result {
    let mut last = PORT;
    last[5] = -30.0;
    let error = simulate(vec![
        position(PORT),
        insert(Port::Endoscope, 60.0),
        position(last),
    ])
    .err()
    .ok_or("the turn inside was accepted")?;
    let (index, rule, inside, moved, turned) = refusal(&error).ok_or("not a refusal")?;
    assert_eq!((index, rule), (2, InsideRule::TurnsAboutAxis));
    assert!(inside.endoscope && !inside.left && !inside.right);
    // The incision is P where the insertion began: the port pose's origin.
    assert_eq!(inside.incision_mm, Some([15.0, 20.0, -500.0]));
    // phi from -60 to -30 deg; x, y, z unchanged.
    assert!((turned - 30.0).abs() < 1e-9, "{turned}");
    assert!(moved.abs() < 1e-9, "{moved}");
    let text = error.to_string();
    assert!(
        text.starts_with("motion 2 (position): turns about the endoscope's axis while the endoscope is inside: phi would turn by 30.000 deg"),
        "{text}"
    );
    Ok(())
}

#[test]
fn moving_only_x_with_the_endoscope_inside_moves_the_incision_point() -> Result {
    let mut last = PORT;
    last[0] += 10.0;
    let error = simulate(vec![
        position(PORT),
        insert(Port::Endoscope, 60.0),
        position(last),
    ])
    .err()
    .ok_or("the move inside was accepted")?;
    let (index, rule, _, moved, turned) = refusal(&error).ok_or("not a refusal")?;
    assert_eq!((index, rule), (2, InsideRule::MovesIncision));
    // The largest distance from the incision over the motion: its end, 10 mm.
    assert!((moved - 10.0).abs() < 1e-9, "{moved}");
    assert_eq!(turned, 0.0);
    let text = error.to_string();
    assert!(
        text.contains("moves the incision point while the endoscope is inside: P would leave the incision point by 10.000 mm"),
        "{text}"
    );
    Ok(())
}

#[test]
fn a_pivot_about_p_at_fixed_phi_is_allowed_inside() -> Result {
    // psi and theta change, P and phi do not: a type 1 that only pivots
    // about the incision, like a type 4.
    let mut pivot = PORT;
    pivot[3] += 5.0;
    pivot[4] -= 3.0;
    let sim = simulate(vec![
        position(PORT),
        insert(Port::Endoscope, 40.0),
        position(pivot),
    ])?;
    let p = plan(&sim)?;
    assert!(!p.motions[0].inside.any());
    assert!(!p.motions[1].inside.any());
    assert!(p.motions[2].inside.endoscope);
    Ok(())
}

#[test]
fn an_endoscope_that_starts_inside_holds_its_incision_from_the_start() -> Result {
    let scenario = Scenario {
        endoscope_depth_mm: 30.0,
        run: Run::procedure(vec![position(PORT)]),
        ..start()
    };
    let error = Simulation::new(scenario)
        .err()
        .ok_or("a positioning with the endoscope in was accepted")?;
    let (index, rule, inside, moved, _) = refusal(&error).ok_or("not a refusal")?;
    assert_eq!((index, rule), (0, InsideRule::MovesIncision));
    assert_eq!(inside.incision_mm, Some([15.0, 20.0, -460.0]));
    // From z = -460 to -500 mm.
    assert!((moved - 40.0).abs() < 1e-9, "{moved}");
    Ok(())
}

#[test]
fn an_instrument_is_inside_until_an_insertion_brings_it_back_to_its_start_depth() -> Result {
    let elsewhere = [25.0, 10.0, -500.0, -15.0, 10.0, -40.0];
    // In by 20 mm, with the endoscope out: the left instrument alone is in.
    let error = simulate(vec![
        position(PORT),
        insert(Port::Left, 20.0),
        position(elsewhere),
    ])
    .err()
    .ok_or("a positioning with the left instrument in was accepted")?;
    let (index, rule, inside, _, _) = refusal(&error).ok_or("not a refusal")?;
    assert_eq!((index, rule), (2, InsideRule::MovesIncision));
    assert!(inside.left && !inside.endoscope && !inside.right);
    assert!(
        error
            .to_string()
            .contains("while the left instrument is inside"),
        "{error}"
    );
    // Back out by 20 mm (nothing moved its qs3 between): outside, and the
    // positioning is free; the next insertion cuts a new incision at the
    // new P.
    let sim = simulate(vec![
        position(PORT),
        insert(Port::Left, 20.0),
        insert(Port::Left, -20.0),
        position(elsewhere),
        insert(Port::Endoscope, 30.0),
        reorient(3.0, 3.0),
    ])?;
    let p = plan(&sim)?;
    let states: Vec<String> = p.motions.iter().map(|m| m.inside.to_string()).collect();
    assert_eq!(
        states,
        [
            "outside",
            "outside",
            "inside: left",
            "outside",
            "outside",
            "inside: endoscope"
        ]
    );
    assert_eq!(p.motions[2].inside.incision_mm, Some([15.0, 20.0, -500.0]));
    assert_eq!(p.motions[5].inside.incision_mm, Some([25.0, 10.0, -500.0]));
    Ok(())
}

#[test]
fn the_shipped_procedures_keep_to_the_rules() -> Result {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../procedures/");
    let demo = Simulation::new(procedure::load(format!("{dir}sils-demo.toml"))?)?;
    let states: Vec<String> = plan(&demo)?
        .motions
        .iter()
        .map(|m| m.inside.to_string())
        .collect();
    assert_eq!(
        states,
        [
            "outside",
            "outside",
            "inside: endoscope",
            "inside: endoscope",
            "inside: endoscope",
            "inside: endoscope"
        ]
    );
    let out_and_in = Simulation::new(procedure::load(format!("{dir}retract-reposition.toml"))?)?;
    let states: Vec<String> = plan(&out_and_in)?
        .motions
        .iter()
        .map(|m| m.inside.to_string())
        .collect();
    assert_eq!(
        states,
        [
            "outside",
            "outside",
            "inside: endoscope",
            "inside: endoscope, left",
            "inside: endoscope, left",
            "inside: endoscope",
            "outside",
            "outside"
        ]
    );
    Ok(())
}
