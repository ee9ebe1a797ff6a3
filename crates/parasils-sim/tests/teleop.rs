//! A teleoperation replay against the teleoperation core stepped by hand
//! (the same inputs, stamped at each cycle's time): the records carry the
//! core's setpoints to the bit, and the columns' codes are those the
//! module documents.

use parasils::kin::Controller;
use parasils::supervisor::Margin;
use parasils::teleop::{
    BUTTON_ENABLE, Command, HandCommand, HoldAt, Inputs, OperatingState, Teleop, TeleopParams,
};
use parasils_device::Recording;
use parasils_sim::teleop::{TELEOP, hold_code, state_code};
use parasils_sim::{Record, Replay, Scenario};

const SESSION: &str = "t_s,device,tx,ty,tz,rx,ry,rz,buttons,command
0.0,left,0,0,0,0,0,0,0,enable
0.01,left,0.5,0,-0.25,0,0,0,1,
0.2,left,0,0,0,0,0,0,1,
0.25,right,0,0,0,0,0,0,0,pause
";

#[test]
fn a_replay_is_the_core_stepped_by_hand() {
    let recording = Recording::parse(SESSION, "session.csv").expect("session");
    let scenario = Scenario::paper();
    let replay =
        Replay::new(scenario.clone(), TeleopParams::assumed(), recording, 0.05).expect("replay");
    // 0 to 0.30 s at 1 kHz, both ends included.
    assert_eq!(replay.cycle_count(), 301);
    let mut records: Vec<Record> = Vec::new();
    let mut keep = |r: &Record| {
        records.push(*r);
        Ok::<(), core::convert::Infallible>(())
    };
    replay.run(&mut keep).expect("run");
    assert_eq!(records.len(), 301);

    // The same core, by hand: the scenario's controller, start, tips,
    // depth and camera (the motion stays far from every supervised
    // threshold, so the supervisor's thresholds do not matter here).
    let controller = Controller::from_geometry(&scenario.robot).expect("robot");
    let mut core = Teleop::new(
        controller,
        scenario.start(),
        scenario.tips(),
        scenario.endoscope_depth_mm,
        TeleopParams::assumed(),
    )
    .and_then(|t| t.with_camera(controller.endoscope.camera))
    .expect("core");
    for (k, record) in records.iter().enumerate() {
        let t = k as f64 / 1000.0;
        let mut inputs = Inputs::idle(t);
        if (10..200).contains(&k) {
            inputs.left.command = HandCommand::Rate([0.5, 0.0, -0.25, 0.0, 0.0, 0.0]);
        }
        if k >= 10 {
            inputs.left.buttons = BUTTON_ENABLE;
        }
        inputs.command = match k {
            0 => Some(Command::Enable),
            250 => Some(Command::Pause),
            _ => None,
        };
        let cycle = core.step(t, &inputs).expect("cycle");
        assert_eq!(record.t, t);
        assert_eq!(record.teleop.state, cycle.state, "cycle {k}");
        assert_eq!(record.teleop.command, inputs.command, "cycle {k}");
        // The tips by forward kinematics from the core's joints.
        assert_eq!(record.left.q, cycle.step.left.q.to_array(), "cycle {k}");
        assert_eq!(record.right.q, cycle.step.right.q.to_array(), "cycle {k}");
        assert_eq!(
            record.module1.q,
            cycle.step.module1.q.to_array(),
            "cycle {k}"
        );
        assert!(record.left.tip_err < 1e-9 && record.right.tip_err < 1e-9);
    }
    assert_eq!(records[300].teleop.state, OperatingState::Paused);
    // The left hand moved a tip (whichever module it drives).
    let moved = |r: &Record| {
        (r.left.tip - records[0].left.tip).norm() + (r.right.tip - records[0].right.tip).norm()
    };
    assert!(moved(&records[300]) > 1.0, "{}", moved(&records[300]));
}

#[test]
fn the_codes_are_the_documented_ones() {
    assert_eq!(hold_code(None), 0);
    let margins: Vec<u8> = Margin::ALL
        .iter()
        .map(|m| hold_code(Some(HoldAt::Margin(*m))))
        .collect();
    assert_eq!(margins, (1..=11).collect::<Vec<u8>>());
    assert_eq!(hold_code(Some(HoldAt::Margin(Margin::RightQs3Limits))), 8);
    let states: Vec<u8> = OperatingState::ALL.iter().map(|s| state_code(*s)).collect();
    assert_eq!(states, [0, 1, 2, 3]);
    let names: Vec<&str> = TELEOP.iter().map(|c| c.name).collect();
    assert_eq!(names.len(), 33);
    assert_eq!(names[6], "left_tx");
    assert_eq!(
        names[27..],
        [
            "teleop_command",
            "teleop_state",
            "teleop_hold",
            "teleop_fault",
            "left_hand_module",
            "right_hand_module",
        ]
    );
}
