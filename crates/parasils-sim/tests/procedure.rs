//! Procedures: each motion type against an independent truth along the
//! whole motion, continuity between motions, the shipped demo, and failures
//! that name their motion.

#![allow(
    clippy::needless_range_loop,
    reason = "coordinates of two records compared index by index"
)]

use nalgebra::Vector3;
use parasils::Port;
use parasils::kin::{
    AssemblyMode, Controller, Joints, MarginTracker, ParallelRobot, PlatformState, Pose,
};
use parasils::motions::{Motion, Moving};
use parasils_sim::Run;
use parasils_sim::procedure;
use parasils_sim::{MotionGoal, MotionLimits, MotionSpec, ProcedurePlan};
use parasils_sim::{Record, Scenario, Simulation, SimulationError};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

/// The start pose a little above the paper's P0, and the tips closer to the
/// ports, so that there is room to move in every direction.
fn start() -> Scenario {
    Scenario {
        start_mm_deg: [15.0, 20.0, -460.0, -15.0, 10.0, -60.0],
        tip_left_mm: [50.0, -50.0, -580.0],
        ..Scenario::paper()
    }
}

fn run(motions: Vec<MotionSpec>) -> Result<(Simulation, Vec<Record>)> {
    let sim = Simulation::new(Scenario {
        run: Run::procedure(motions),
        ..start()
    })?;
    let records = sim.samples().collect::<core::result::Result<Vec<_>, _>>()?;
    assert_eq!(records.len(), sim.sample_count());
    Ok((sim, records))
}

fn pose_of(r: &Record) -> Pose<f64> {
    Pose::from_array(r.pose)
}

#[test]
fn type_1_moves_the_pose_on_its_segment_with_module_1_at_its_ik() -> Result {
    let goal = [25.0, 5.0, -500.0, -10.0, 14.0, -58.0];
    let (sim, records) = run(vec![MotionSpec::new(MotionGoal::Position {
        pose_mm_deg: goal,
    })])?;
    let a = sim.scenario().start().to_array();
    let b =
        Pose::<f64>::from_mm_deg(goal[0], goal[1], goal[2], goal[3], goal[4], goal[5]).to_array();
    let module1 = ParallelRobot::new(sim.scenario().robot.module1)?;
    let (first, last) = (&records[0], &records[records.len() - 1]);
    for r in &records {
        // On the segment: every coordinate at the same fraction of its way.
        let lambda = (r.pose[2] - a[2]) / (b[2] - a[2]);
        assert!((-1e-12..=1.0 + 1e-12).contains(&lambda));
        for i in 0..6 {
            let expected = a[i] + lambda * (b[i] - a[i]);
            assert!(
                (r.pose[i] - expected).abs() < 1e-9,
                "coordinate {i} at t = {}",
                r.t
            );
        }
        // Module 1 at its own inverse kinematics of the pose.
        let q = module1.ik(&pose_of(r))?;
        for j in 0..6 {
            assert!((r.module1.q[j] - q.0[j]).abs() < 1e-9);
        }
        // Instrument joints held; the tips ride along (forward kinematics).
        assert_eq!(r.left.q, first.left.q);
        assert_eq!(r.right.q, first.right.q);
        assert_eq!(r.left.q_dot, [0.0; 3]);
        let tip = sim.controller().left.fk(
            &pose_of(r),
            &Joints::new(r.left.q[0], r.left.q[1], r.left.q[2]),
        )?;
        assert!((tip - r.left.tip).norm() < 1e-9);
        assert_eq!(r.motion_type, 1);
    }
    for i in 0..6 {
        assert!((last.pose[i] - b[i]).abs() < 1e-12);
    }
    // The z coordinate binds (40 mm at 20 mm/s, 20 mm/s^2: 1 + 1 + 1 s).
    assert!((sim.duration() - 3.0).abs() < 1e-12);
    Ok(())
}

#[test]
fn type_2_moves_qs3_alone_and_the_tip_on_the_tool_axis() -> Result {
    for (port, depth) in [(Port::Left, 25.0), (Port::Right, -15.0)] {
        let (sim, records) = run(vec![MotionSpec::new(MotionGoal::Insert {
            port,
            depth_mm: depth,
        })])?;
        let side = |r: &Record| if port == Port::Left { r.left } else { r.right };
        let (first, last) = (side(&records[0]), side(&records[records.len() - 1]));
        let geometry = if port == Port::Left {
            sim.scenario().robot.left
        } else {
            sim.scenario().robot.right
        };
        let pose = sim.scenario().start();
        let rcm = pose.rotation() * geometry.rcm + pose.position();
        let axis = (first.tip - rcm).normalize();
        for r in &records {
            let m = side(r);
            assert_eq!(m.q[0], first.q[0]);
            assert_eq!(m.q[1], first.q[1]);
            assert_eq!(r.pose, records[0].pose);
            assert_eq!(r.module1.q, records[0].module1.q);
            // On the axis through the RCM, at distance qs3 from it.
            let d = m.tip - rcm;
            assert!(
                (d - axis * d.dot(&axis)).norm() < 1e-9,
                "off the axis at t = {}",
                r.t
            );
            assert!((d.norm() - m.q[2]).abs() < 1e-9);
        }
        assert_eq!(last.q[2], first.q[2] + depth);
        assert!(((last.tip - first.tip).norm() - depth.abs()).abs() < 1e-9);
        // Inwards is away from the RCM.
        assert_eq!(
            (last.tip - rcm).norm() > (first.tip - rcm).norm(),
            depth > 0.0
        );
    }
    Ok(())
}

#[test]
fn the_endoscope_goes_in_along_the_platform_axis() -> Result {
    let (sim, records) = run(vec![MotionSpec::new(MotionGoal::Insert {
        port: Port::Endoscope,
        depth_mm: 60.0,
    })])?;
    let pose = sim.scenario().start();
    let down = pose.rotation() * Vector3::new(0.0, 0.0, -1.0);
    for r in &records {
        let expected = pose.position() + down * r.endoscope_depth;
        assert!((r.endoscope_tip - expected).norm() < 1e-9);
        assert_eq!(r.left.q, records[0].left.q);
    }
    assert_eq!(records[records.len() - 1].endoscope_depth, 60.0);
    // Beyond the robot file's range: refused, naming the endoscope.
    let e = Simulation::new(Scenario {
        run: Run::procedure(vec![MotionSpec::new(MotionGoal::Insert {
            port: Port::Endoscope,
            depth_mm: 300.0,
        })]),
        ..start()
    })
    .map(|_| ())
    .expect_err("250 mm is the deepest");
    assert!(e.to_string().contains("motion 0 (insert)"), "{e}");
    assert!(e.to_string().contains("endoscope: insertion depth"), "{e}");
    Ok(())
}

/// The instrument joints and their rates at `t` of motion 0, solved by a
/// fresh controller.
fn joints_at(plan: &ProcedurePlan, controller: &Controller<f64>, t: f64) -> Result<[[f64; 3]; 3]> {
    let s = plan.motions[0].motion.sample(t);
    let out =
        controller.step_commanded(&s.platform, &s.left, &s.right, &mut MarginTracker::new())?;
    Ok([
        out.left.q.to_array(),
        out.left.q_dot.to_array(),
        out.left.q_ddot.to_array(),
    ])
}

#[test]
fn type_3_moves_the_tip_on_a_straight_line_with_the_joints_of_its_ik() -> Result {
    let target = Vector3::new(62.0, -35.0, -610.0);
    let (sim, records) = run(vec![MotionSpec {
        limits: MotionLimits {
            velocity_mm_s: 10.0,
            ..MotionLimits::default()
        },
        ..MotionSpec::new(MotionGoal::Manipulate {
            tip_left_mm: Some(target.into()),
            tip_right_mm: None,
        })
    }])?;
    let from = records[0].left.tip;
    let u = (target - from).normalize();
    let controller = *sim.controller();
    for r in &records {
        let d = r.left.tip - from;
        assert!(
            (d - u * d.dot(&u)).norm() < 1e-9,
            "off the line at t = {}",
            r.t
        );
        // The joints are the IK of the commanded tip, which lies on the line.
        let q = controller
            .left
            .ik(&pose_of(r), &r.left.tip, AssemblyMode::A)?;
        for k in 0..3 {
            assert!((q.to_array()[k] - r.left.q[k]).abs() < 1e-9);
        }
        assert!(r.left.tip_err < 1e-9);
        assert_eq!(r.right.q, records[0].right.q);
    }
    assert!((records[records.len() - 1].left.tip - target).norm() < 1e-9);

    // Rates and accelerations against central differences of the closed
    // form, away from the profile's switching instants.
    let plan = sim.procedure().ok_or("a procedure")?;
    let Motion::Manipulate(m) = plan.motions[0].motion else {
        return Err("a manipulation".into());
    };
    let h = 1e-5;
    let duration = m.duration();
    let mut checked = 0;
    for k in 1..200 {
        let t = duration * f64::from(k) / 200.0;
        let [_, rate, acc] = joints_at(plan, &controller, t)?;
        let [q_plus, rate_plus, _] = joints_at(plan, &controller, t + h)?;
        let [q_minus, rate_minus, _] = joints_at(plan, &controller, t - h)?;
        let switch = [1.0_f64, duration - 1.0]
            .iter()
            .any(|s| (t - s).abs() < 1e-3);
        if switch {
            continue;
        }
        let scale = |v: [f64; 3]| v.iter().fold(0.0_f64, |a, x| a.max(x.abs())).max(1e-3);
        for j in 0..3 {
            let fd_rate = (q_plus[j] - q_minus[j]) / (2.0 * h);
            let fd_acc = (rate_plus[j] - rate_minus[j]) / (2.0 * h);
            assert!(
                (fd_rate - rate[j]).abs() < 1e-6 * scale(rate),
                "rate {j} at t = {t}"
            );
            assert!(
                (fd_acc - acc[j]).abs() < 1e-6 * scale(acc),
                "acc {j} at t = {t}"
            );
        }
        checked += 1;
    }
    assert!(checked > 150);
    Ok(())
}

#[test]
fn both_tips_move_together() -> Result {
    let (left, right) = ([58.0, -45.0, -600.0], [-5.0, 50.0, -590.0]);
    let (sim, records) = run(vec![MotionSpec::new(MotionGoal::Manipulate {
        tip_left_mm: Some(left),
        tip_right_mm: Some(right),
    })])?;
    let last = &records[records.len() - 1];
    assert!((last.left.tip - Vector3::from(left)).norm() < 1e-9);
    assert!((last.right.tip - Vector3::from(right)).norm() < 1e-9);
    // Phase-synchronised: each tip the same fraction of its way at every
    // sample.
    let (l0, r0) = (records[0].left.tip, records[0].right.tip);
    let (ll, rl) = (
        (Vector3::from(left) - l0).norm(),
        (Vector3::from(right) - r0).norm(),
    );
    for r in &records {
        let fl = (r.left.tip - l0).norm() / ll;
        let fr = (r.right.tip - r0).norm() / rl;
        assert!((fl - fr).abs() < 1e-9, "at t = {}", r.t);
    }
    assert!(sim.duration() > 0.0);
    Ok(())
}

#[test]
fn type_4_in_a_procedure_is_the_paper_s_reorientation() -> Result {
    let paper = Simulation::new(Scenario::paper())?;
    let procedure = Simulation::new(Scenario {
        run: Run::procedure(vec![MotionSpec::new(MotionGoal::Reorient {
            psi_deg: 15.0,
            theta_deg: 25.0,
            absolute: false,
        })]),
        ..Scenario::paper()
    })?;
    assert_eq!(procedure.sample_count(), paper.sample_count());
    for (a, b) in paper.samples().zip(procedure.samples()) {
        let (a, b) = (a?, b?);
        assert_eq!(a.t, b.t);
        let row = |r: &Record| parasils_sim::columns::csv_row(r);
        for (x, y) in row(&a).iter().zip(row(&b).iter()) {
            assert!(
                (x - y).abs() < 1e-9 * x.abs().max(1.0),
                "{x} vs {y} at t = {}",
                a.t
            );
        }
        assert_eq!(b.motion_type, 4);
    }
    Ok(())
}

#[test]
fn motions_join_at_rest_where_the_previous_one_ended() -> Result {
    let scenario = procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))?;
    let sim = Simulation::new(scenario)?;
    let plan = sim.procedure().ok_or("a procedure")?;
    assert_eq!(plan.motions.len(), 6);
    let controller = *sim.controller();
    let mut tracker = MarginTracker::new();
    for pair in plan.motions.windows(2) {
        let end = pair[0].motion.sample(pair[0].duration());
        let start = pair[1].motion.sample(0.0);
        assert_eq!(end.platform.pose, start.platform.pose);
        assert_eq!(end.endoscope.position, start.endoscope.position);
        for s in [&end, &start] {
            assert_eq!(s.platform.velocity, parasils::kin::PoseRate::zero());
            assert_eq!(s.endoscope.velocity, 0.0);
        }
        let a = controller.step_commanded(&end.platform, &end.left, &end.right, &mut tracker)?;
        let b =
            controller.step_commanded(&start.platform, &start.left, &start.right, &mut tracker)?;
        for (x, y) in [(a.left, b.left), (a.right, b.right)] {
            for k in 0..3 {
                assert!((x.q.to_array()[k] - y.q.to_array()[k]).abs() < 1e-9);
                assert!(x.q_dot.to_array()[k].abs() < 1e-9 && y.q_dot.to_array()[k].abs() < 1e-9);
            }
        }
        // On the control cycle: the next motion starts on the cycle after
        // the last row of the one before.
        assert_eq!(
            pair[1].first_sample,
            pair[0].first_sample + pair[0].periods + 1
        );
        assert_eq!(pair[0].periods, pair[0].stretch.periods());
    }
    // Sample to sample, positions never jump more than the fastest rate
    // allows.
    let records = sim.samples().collect::<core::result::Result<Vec<_>, _>>()?;
    for w in records.windows(2) {
        let dt = w[1].t - w[0].t;
        for j in 0..6 {
            assert!((w[1].module1.q[j] - w[0].module1.q[j]).abs() < 60.0 * dt);
        }
        for (a, b) in [(w[0].left, w[1].left), (w[0].right, w[1].right)] {
            assert!((b.q[2] - a.q[2]).abs() < 30.0 * dt);
            assert!((b.tip - a.tip).norm() < 30.0 * dt);
        }
        assert!(w[1].motion >= w[0].motion);
    }
    let last = &records[records.len() - 1];
    assert_eq!(last.motion, 5);
    assert_eq!(last.endoscope_depth, 0.0);
    // Every motion was checked, and the paper's turn has no warning.
    let check = sim.procedure_check().ok_or("a check")?;
    assert_eq!(check.motions.len(), 6);
    assert!(check.motions.iter().all(|m| m.tip_err_mm < 1e-9));
    let _ = PlatformState::at_rest(sim.scenario().start());
    Ok(())
}

#[test]
fn a_motion_that_crosses_a_joint_limit_is_named_before_any_output() {
    // The fourth motion (index 3) pushes the left instrument past the end of
    // its qs3 range, [10, 300] mm.
    let mut motions = vec![
        MotionSpec::new(MotionGoal::Insert {
            port: Port::Endoscope,
            depth_mm: 20.0,
        }),
        MotionSpec::new(MotionGoal::Manipulate {
            tip_left_mm: Some([55.0, -45.0, -600.0]),
            tip_right_mm: None,
        }),
        MotionSpec::new(MotionGoal::Reorient {
            psi_deg: 5.0,
            theta_deg: 5.0,
            absolute: false,
        }),
        MotionSpec::new(MotionGoal::Insert {
            port: Port::Left,
            depth_mm: 250.0,
        }),
        MotionSpec::new(MotionGoal::Insert {
            port: Port::Endoscope,
            depth_mm: -20.0,
        }),
    ];
    motions[3].name = Some(String::from("too deep"));
    let e = Simulation::new(Scenario {
        run: Run::procedure(motions),
        ..start()
    })
    .map(|_| ())
    .expect_err("the fourth motion fails");
    let text = e.to_string();
    assert!(
        text.starts_with("motion 3 (insert \"too deep\"), "),
        "{text}"
    );
    assert!(text.contains("left instrument: joint qs3 = 300"), "{text}");
    assert!(text.contains("is outside [10, 300] mm"), "{text}");
    assert!(matches!(e, SimulationError::Motion { ref motion, .. } if motion.index == 3));
    // The time inside the motion is the first sample past the limit.
    let SimulationError::Motion { t_motion, .. } = e else {
        return;
    };
    assert!(t_motion > 0.0 && t_motion < 250.0 / 20.0 + 1.0, "{text}");
}

#[test]
fn the_robot_file_s_supervisor_thresholds_mark_warnings_with_their_motion() -> Result {
    use parasils::supervisor::Margin;
    use parasils_sim::SupervisorTable;
    let demo = procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))?;
    // The default thresholds: no warning along the demo (its smallest
    // |cos qs2| is 0.48, above 0.1).
    let quiet = Simulation::new(demo.clone())?;
    assert!(
        quiet
            .procedure_check()
            .ok_or("a check")?
            .warnings
            .is_empty()
    );
    // Warn below |cos qs2| = 0.5: the left module, from the turn on.
    let sim = Simulation::new(Scenario {
        supervisor: SupervisorTable {
            cos_qs2_warn: Some(0.5),
            ..SupervisorTable::default()
        },
        ..demo.clone()
    })?;
    let check = sim.procedure_check().ok_or("a check")?;
    assert!(!check.warnings.is_empty());
    let records = sim.samples().collect::<core::result::Result<Vec<_>, _>>()?;
    for w in &check.warnings {
        assert_eq!(w.margin, Margin::LeftCosQs2);
        assert_eq!(w.threshold, 0.5);
        assert!(w.smallest < 0.5 && w.from_s <= w.until_s);
        // Every record inside the episode warns, and its motion is the
        // warning's; the record just before does not warn (or belongs to
        // another motion).
        for r in records
            .iter()
            .filter(|r| r.t >= w.from_s && r.t <= w.until_s)
        {
            assert!(r.warnings.contains(Margin::LeftCosQs2));
            assert_eq!(r.motion as usize, w.motion);
            assert!(r.left.cos_qs2.abs() < 0.5);
        }
    }
    // Every record below the threshold is in one episode.
    for r in records.iter().filter(|r| r.left.cos_qs2.abs() < 0.5) {
        assert!(
            check
                .warnings
                .iter()
                .any(|w| r.t >= w.from_s && r.t <= w.until_s)
        );
    }
    let summary = {
        let mut s = parasils_sim::summary::Summary::for_simulation(&sim);
        sim.run(&mut s)?;
        s.to_string()
    };
    assert!(summary.contains("supervisor warnings"), "{summary}");
    assert!(summary.contains("left.cos_qs2 below 0.5"), "{summary}");
    // A warning below its stop threshold is refused.
    let e = Simulation::new(Scenario {
        supervisor: SupervisorTable {
            cos_qs2_warn: Some(0.01),
            ..SupervisorTable::default()
        },
        ..demo
    })
    .map(|_| ())
    .expect_err("warning below the stop threshold");
    assert!(matches!(e, SimulationError::Supervisor(_)), "{e}");
    Ok(())
}

fn reorient(psi_deg: f64, theta_deg: f64, absolute: bool) -> MotionSpec {
    MotionSpec::new(MotionGoal::Reorient {
        psi_deg,
        theta_deg,
        absolute,
    })
}

fn until(mut m: MotionSpec, t: f64) -> MotionSpec {
    m.until_s = Some(t);
    m
}

#[test]
fn a_turn_cut_short_and_retargeted_matches_the_online_controller() -> Result {
    // The procedure: the paper's turn, cut at 1.2 s by a new goal given as
    // final angles; the same as `--retarget 1.2:...` through the online
    // controller (a second implementation: it plans the first motion with
    // the online profiles too).
    let start = Scenario::paper().start();
    let goal = [
        start.psi.to_degrees() + 25.0,
        start.theta.to_degrees() + 15.0,
    ];
    let procedure = Simulation::new(Scenario {
        run: Run::procedure(vec![
            until(reorient(15.0, 25.0, false), 1.2),
            reorient(goal[0], goal[1], true),
        ]),
        ..Scenario::paper()
    })?;
    let online = Simulation::new(Scenario {
        run: Run::Online(parasils_sim::Online {
            retargets: vec![parasils_sim::scenario::Retarget {
                t_s: 1.2,
                psi_deg: 25.0,
                theta_deg: 15.0,
            }],
            ..parasils_sim::Online::default()
        }),
        ..Scenario::paper()
    })?;
    let a = procedure
        .samples()
        .collect::<core::result::Result<Vec<_>, _>>()?;
    let b = online
        .samples()
        .collect::<core::result::Result<Vec<_>, _>>()?;
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.t, y.t);
        for i in 0..6 {
            assert!(
                (x.pose[i] - y.pose[i]).abs() < 1e-9,
                "pose {i} at t = {}",
                x.t
            );
        }
        for i in 0..3 {
            assert!((x.euler_dot[i] - y.euler_dot[i]).abs() < 1e-9);
        }
        assert!((x.module1.q[0] - y.module1.q[0]).abs() < 1e-7);
        assert!(x.left.tip_err < 1e-9 && x.right.tip_err < 1e-9);
        assert_eq!(x.motion, u32::from(x.t >= 1.2));
    }
    Ok(())
}

#[test]
fn a_stop_brings_the_cut_motion_to_rest_at_its_own_limits() -> Result {
    for first in [
        until(reorient(15.0, 25.0, false), 2.0),
        until(
            MotionSpec::new(MotionGoal::Position {
                pose_mm_deg: [35.0, 0.0, -500.0, -15.0, 10.0, -60.0],
            }),
            1.5,
        ),
        until(
            MotionSpec::new(MotionGoal::Insert {
                port: Port::Right,
                depth_mm: 40.0,
            }),
            1.5,
        ),
        until(
            MotionSpec::new(MotionGoal::Manipulate {
                tip_left_mm: Some([62.0, -35.0, -600.0]),
                tip_right_mm: None,
            }),
            0.8,
        ),
    ] {
        let kind = first.motion_type().map(|t| t.number());
        let (sim, records) = run(vec![first, MotionSpec::new(MotionGoal::Stop)])?;
        let plan = sim.procedure().ok_or("a procedure")?;
        let cut = plan.motions[1].start_s;
        assert!(plan.motions[0].cut, "the first motion is cut");
        assert!(plan.motions[0].duration() > cut);
        // The stop starts on the row the cut motion stops at, from its
        // moving state there.
        assert_eq!(
            plan.motions[1].first_sample,
            plan.motions[0].first_sample + plan.motions[0].periods
        );
        // The stop keeps the type of what it stops, and ends at rest.
        assert_eq!(Some(plan.motions[1].motion.motion_type().number()), kind);
        assert!(plan.motions[1].name.stop);
        let last = &records[records.len() - 1];
        assert_eq!(last.euler_dot, [0.0; 3]);
        assert!(last.module1.q_dot.iter().all(|v| v.abs() < 1e-9));
        assert!(
            last.left
                .q_dot
                .iter()
                .chain(&last.right.q_dot)
                .all(|v| v.abs() < 1e-9)
        );
        // Continuous across the cut: positions move by at most one
        // sample's travel, and nothing jumps in velocity (the acceleration
        // may).
        for w in records.windows(2) {
            let dt = w[1].t - w[0].t;
            for j in 0..6 {
                assert!((w[1].module1.q[j] - w[0].module1.q[j]).abs() < 60.0 * dt);
                assert!((w[1].module1.q_dot[j] - w[0].module1.q_dot[j]).abs() < 200.0 * dt);
            }
            assert!((w[1].left.tip - w[0].left.tip).norm() < 30.0 * dt);
        }
        // The tips: held, or on their line, by the closed form.
        assert!(
            records
                .iter()
                .all(|r| r.left.tip_err < 1e-9 && r.right.tip_err < 1e-9)
        );
        // The stop decelerates at the stopped motion's limits (20 mm/s^2,
        // 5 deg/s^2 by default): it lasts max |v_i| / a_i over its
        // coordinates at the cut.
        let (lin, ang) = (20.0, 5f64.to_radians());
        let expected = match plan.motions[0].moving_at_row(plan.motions[0].periods) {
            Moving::Pose(s) => s
                .iter()
                .enumerate()
                .map(|(i, a)| a.velocity.abs() / if i < 3 { lin } else { ang })
                .fold(0.0, f64::max),
            Moving::Depth(_, s) => s.velocity.abs() / lin,
            Moving::Tips(s) => s.iter().map(|a| a.velocity.abs() / lin).fold(0.0, f64::max),
            Moving::Angles(s) => s.iter().map(|a| a.velocity.abs() / ang).fold(0.0, f64::max),
        };
        assert!(expected > 0.1, "moving at the cut");
        let stop = &plan.motions[1];
        assert!((stop.planned_s() - expected).abs() < 1e-12 * expected.max(1.0));
        // It starts moving, so it is held at its end to the next whole
        // period rather than stretched.
        assert_eq!(stop.stretch.ratio(), 1.0);
        assert_eq!(stop.periods, (expected * 1000.0).ceil() as usize);
    }
    Ok(())
}

#[test]
fn until_s_after_the_end_rests_and_cut_motions_need_a_matching_successor() -> Result {
    // A dwell: the insertion lasts 3 s and rests to its `until_s`, its last
    // row at 5 s; the reorientation starts on the next cycle, 5.001 s.
    let (sim, records) = run(vec![
        until(
            MotionSpec::new(MotionGoal::Insert {
                port: Port::Endoscope,
                depth_mm: 40.0,
            }),
            5.0,
        ),
        reorient(5.0, 5.0, false),
    ])?;
    let plan = sim.procedure().ok_or("a procedure")?;
    assert_eq!(plan.motions[1].start_s, 5.001);
    assert_eq!(plan.motions[0].periods, 5000);
    for r in records.iter().filter(|r| r.t > 3.0 && r.t <= 5.0) {
        assert_eq!(r.endoscope_depth, 40.0);
        assert_eq!(r.motion, 0);
        assert_eq!(r.euler_dot, [0.0; 3]);
    }
    // A cut turn followed by an insertion: refused, naming the motion.
    let e = Simulation::new(Scenario {
        run: Run::procedure(vec![
            until(reorient(15.0, 25.0, false), 1.0),
            MotionSpec::new(MotionGoal::Insert {
                port: Port::Left,
                depth_mm: 5.0,
            }),
        ]),
        ..start()
    })
    .map(|_| ())
    .expect_err("an insertion cannot start while the platform turns");
    let text = e.to_string();
    assert!(text.starts_with("motion 1 (insert), "), "{text}");
    assert!(
        text.contains("only a stop or another \"reorient\" motion"),
        "{text}"
    );
    // A cut last motion, and a stop first: refused.
    for motions in [
        vec![until(reorient(15.0, 25.0, false), 1.0)],
        vec![MotionSpec::new(MotionGoal::Stop)],
    ] {
        let e = Simulation::new(Scenario {
            run: Run::procedure(motions),
            ..start()
        })
        .map(|_| ())
        .expect_err("refused");
        assert!(e.to_string().starts_with("motion 0 ("), "{e}");
    }
    Ok(())
}
