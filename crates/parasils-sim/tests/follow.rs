//! Type-3 motions with `camera = "follow"`: the tips go exactly where the
//! same motions take them with the camera fixed while the platform turns,
//! and the keys that go with the mode are read and refused where they do
//! not apply.

use std::path::Path;

use parasils_sim::procedure;
use parasils_sim::{
    CameraMode, Record, Run, Scenario, Simulation, SimulationError, Timeline, Timing,
};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

fn demo() -> Result<Scenario> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../procedures/follow-demo.toml");
    Ok(procedure::load(path)?)
}

fn records(scenario: Scenario) -> Result<Vec<Record>> {
    let sim = Simulation::new(scenario)?;
    Ok(sim.samples().collect::<core::result::Result<Vec<_>, _>>()?)
}

/// `scenario` with every motion's camera fixed.
fn fixed(mut scenario: Scenario) -> Scenario {
    if let Run::Planned(Timeline { motions, .. }) = &mut scenario.run
        && let parasils_sim::Motions::Procedure(list) = motions
    {
        for m in list {
            m.camera = CameraMode::Fixed;
        }
    }
    scenario
}

/// The records of motion `m`, in order.
fn of(records: &[Record], m: u32) -> Vec<&Record> {
    records.iter().filter(|r| r.motion == m).collect()
}

#[test]
fn the_tips_go_where_the_fixed_camera_run_takes_them_while_the_platform_turns() -> Result {
    let follow = records(demo()?)?;
    let still = records(fixed(demo()?))?;
    let mut turned_deg: f64 = 0.0;
    let mut compared = 0;
    for m in 4..=8 {
        let (a, b) = (of(&follow, m), of(&still, m));
        assert!(
            a.len() >= b.len(),
            "motion {m}: a follow motion lasts until the camera settles"
        );
        for (j, ra) in a.iter().enumerate() {
            // Past the fixed run's last row its tips rest on their targets.
            let rb = b.get(j).or(b.last()).ok_or("no rows")?;
            for (x, y) in [(&ra.left, &rb.left), (&ra.right, &rb.right)] {
                let gap = (x.tip - y.tip).norm();
                assert!(
                    gap <= 1e-9,
                    "motion {m} row {j}: {gap} mm off the fixed run's tip"
                );
                // By forward kinematics, within 1e-9 mm of the command.
                assert!(x.tip_err <= 1e-9);
            }
            // The fixed run's platform does not turn in a type-3 motion.
            assert_eq!(rb.pose[3..], b[0].pose[3..]);
            turned_deg = turned_deg
                .max((ra.pose[3] - rb.pose[3]).abs().to_degrees())
                .max((ra.pose[4] - rb.pose[4]).abs().to_degrees());
            compared += 1;
        }
    }
    // The platform did turn under the tips, by degrees, not by rounding.
    assert!(turned_deg > 5.0, "turned by {turned_deg} deg");
    assert!(compared > 20_000);
    Ok(())
}

#[test]
fn the_check_reports_what_the_camera_saw() -> Result {
    let sim = Simulation::new(demo()?)?;
    let check = sim.procedure_check().ok_or("no check")?;
    for m in &check.motions {
        let following = m.name.index >= 4;
        assert_eq!(m.camera.is_some(), following, "{}", m.name);
        if let Some(c) = &m.camera {
            assert_eq!(c.in_view_share(), 1.0);
            assert!(c.central_share() >= 0.999);
            assert!(c.settled_aim_error_deg.is_none_or(|e| e < 0.5));
        }
    }
    // The last wander stays inside the trigger zone: no turn at all.
    assert_eq!(check.motions[8].camera.map(|c| c.settles), Some(0));
    Ok(())
}

fn parse(motion: &str) -> core::result::Result<Scenario, procedure::ProcedureError> {
    let text = format!("[[motion]]\n{motion}\n");
    procedure::parse(&text, "p.toml", Path::new("."))
}

#[test]
fn the_camera_key_is_read_and_refused_where_it_does_not_apply() -> Result {
    let manipulate = "type = \"manipulate\"\ninstrument = \"left\"\ntip_mm = [1, 2, 3]";
    let s = parse(&format!(
        "{manipulate}\ncamera = \"follow\"\nvelocity_deg_s = 4"
    ))?;
    let Run::Planned(Timeline {
        motions: parasils_sim::Motions::Procedure(list),
        ..
    }) = &s.run
    else {
        return Err("not a procedure".into());
    };
    assert_eq!(list[0].camera, CameraMode::Follow);
    assert_eq!(list[0].limits.velocity_deg_s, 4.0);
    let error = |text: &str| parse(text).map(|_| ()).expect_err(text).to_string();
    assert!(
        error(&format!("{manipulate}\ncamera = \"wander\""))
            .contains("key `camera`: \"wander\" is not one of \"fixed\", \"follow\"")
    );
    assert!(
        error(&format!("{manipulate}\nvelocity_deg_s = 4")).contains(
            "key `velocity_deg_s`: applies to a \"manipulate\" motion only with camera = \"follow\""
        )
    );
    assert!(
        error(&format!("{manipulate}\ncamera = \"follow\"\nuntil_s = 1"))
            .contains("key `until_s`: does not apply with camera = \"follow\"")
    );
    assert!(
        error("type = \"reorient\"\npsi_deg = 1\ntheta_deg = 1\ncamera = \"follow\"")
            .contains("key `camera`: does not apply to a \"reorient\" motion")
    );
    Ok(())
}

#[test]
fn the_time_optimal_timing_refuses_a_following_camera() -> Result {
    let mut scenario = demo()?;
    if let Run::Planned(t) = &mut scenario.run {
        t.timing = Timing::Optimal { angular: false };
    }
    let e = Simulation::new(scenario).expect_err("optimal with follow");
    assert!(matches!(e, SimulationError::Motion { .. }), "{e}");
    assert!(
        e.to_string()
            .contains("camera = \"follow\" needs a motion planned from rest"),
        "{e}"
    );
    Ok(())
}
