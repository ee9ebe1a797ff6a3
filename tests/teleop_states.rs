//! The teleoperation core's operating states (CRTK's table, every state by
//! every command), the planned moves (home, look at a point or the tips,
//! move to a pose) and the stop, the limits it holds at, and its faults.

use parasils::Supervisor;
use parasils::kin::nalgebra::Vector3;
use parasils::kin::{Controller, Pose, TipTargets};
use parasils::supervisor::Margin;
use parasils::teleop::{
    BUTTON_ENABLE, CameraCommand, Command, Device, Fault, Goal, HandCommand, HoldAt, Inputs,
    MoveRefused, OperatingState, Teleop, TeleopCycle, TeleopError, TeleopParams,
};

type R<T = ()> = Result<T, Box<dyn core::error::Error>>;

const DT: f64 = 1e-3;
/// The assumed tip acceleration limit, mm/s^2.
fn a_tip() -> f64 {
    TeleopParams::<f64>::assumed().tip_accel_mm_s2
}

fn teleop() -> R<Teleop<f64>> {
    Ok(Teleop::new(
        Controller::paper(),
        Pose::paper_start(),
        TipTargets::paper(),
        60.0,
        TeleopParams::assumed(),
    )?)
}

fn t_of(k: u32) -> f64 {
    f64::from(k) * DT
}

/// Both hands pushing `axes` with the enable button, the camera idle.
fn pushing(k: u32, axes: [f64; 6]) -> Inputs<f64> {
    let mut i = Inputs::idle(t_of(k));
    for hand in [&mut i.left, &mut i.right] {
        hand.command = HandCommand::Rate(axes);
        hand.buttons = BUTTON_ENABLE;
    }
    i
}

/// The core in `state`, at rest, at cycle `k`.
fn in_state(state: OperatingState) -> R<(Teleop<f64>, u32)> {
    let mut t = teleop()?;
    let mut k = 0;
    let mut go = |t: &mut Teleop<f64>, inputs: Inputs<f64>| -> R<TeleopCycle<f64>> {
        k += 1;
        Ok(t.step(t_of(k), &inputs)?)
    };
    match state {
        OperatingState::Disabled => {}
        OperatingState::Enabled => {
            go(&mut t, Inputs::idle(t_of(1)).with_command(Command::Enable))?;
        }
        OperatingState::Paused => {
            go(&mut t, Inputs::idle(t_of(1)).with_command(Command::Enable))?;
            go(&mut t, Inputs::idle(t_of(2)).with_command(Command::Pause))?;
        }
        OperatingState::Fault => {
            go(&mut t, Inputs::idle(t_of(1)).with_command(Command::Enable))?;
            let mut bad = Inputs::idle(t_of(2));
            bad.right.command = HandCommand::Rate([0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]);
            let c = go(&mut t, bad)?;
            assert!(matches!(
                c.fault,
                Some(Fault::NonFinite {
                    device: Device::Right,
                    what: "ty",
                    ..
                })
            ));
        }
    }
    assert_eq!(t.state(), state);
    assert!(t.is_at_rest());
    Ok((t, k))
}

#[test]
fn every_state_by_every_command_follows_the_crtk_table() -> R {
    use Command as C;
    use OperatingState as S;
    // CRTK's table (enable, disable, pause, resume), then home, look_at_tips
    // and stop; `true` where the command is valid. A fault with fresh
    // inputs at rest is cleared. A stop is valid in every state and leaves
    // it as it is.
    let table = [
        (
            S::Disabled,
            [
                (S::Enabled, true),
                (S::Disabled, true),
                (S::Disabled, false),
                (S::Disabled, false),
                (S::Disabled, false),
                (S::Disabled, false),
                (S::Disabled, true),
            ],
        ),
        (
            S::Enabled,
            [
                (S::Enabled, true),
                (S::Disabled, true),
                (S::Paused, true),
                (S::Enabled, false),
                (S::Enabled, true),
                (S::Enabled, true),
                (S::Enabled, true),
            ],
        ),
        (
            S::Paused,
            [
                (S::Paused, false),
                (S::Disabled, true),
                (S::Paused, true),
                (S::Enabled, true),
                (S::Paused, false),
                (S::Paused, false),
                (S::Paused, true),
            ],
        ),
        (
            S::Fault,
            [
                (S::Enabled, true),
                (S::Disabled, true),
                (S::Fault, false),
                (S::Fault, false),
                (S::Fault, false),
                (S::Fault, false),
                (S::Fault, true),
            ],
        ),
    ];
    for (state, row) in table {
        assert_eq!(row.len(), C::ALL.len());
        for (command, (expected, valid)) in C::ALL.into_iter().zip(row) {
            let (mut t, k) = in_state(state)?;
            let c = t.step(
                t_of(k + 1),
                &Inputs::idle(t_of(k + 1)).with_command(command),
            )?;
            let outcome = c.command.ok_or("no outcome")?;
            assert_eq!(
                (c.state, outcome.accepted),
                (expected, valid),
                "{state} by {command}"
            );
            assert_eq!(outcome.command, command);
            // The pure table says the same.
            let tr = state.after(command, true);
            assert_eq!((tr.state, tr.accepted), (expected, valid));
            // CRTK's queries.
            assert_eq!(t.is_ready(), expected == S::Enabled);
            // (A home move from home ends at once, and so does a stop at
            // rest; the view may turn to the tips.)
            assert!(!t.is_busy() || command == C::LookAtTips);
            assert!(t.is_homed());
        }
    }
    // A fault is not cleared while an input is stale: the retry is refused.
    let (mut t, k) = in_state(S::Fault)?;
    let stale = Inputs::idle(t_of(k)); // stamped one cycle before...
    let later = t_of(k + 100); // ...and read 0.1 s later
    let c = t.step(later, &stale.with_command(C::Enable))?;
    assert_eq!(c.state, S::Fault);
    assert_eq!(c.command.map(|o| o.accepted), Some(false));
    Ok(())
}

/// Checks the tips' setpoint change from cycle to cycle against the
/// acceleration limit: `|dx_k - dx_(k-1)| <= a dt^2`.
fn check_steps(cycles: &[TeleopCycle<f64>]) {
    for w in cycles.windows(3) {
        for m in 0..2 {
            let d0 = w[1].tips[m] - w[0].tips[m];
            let d1 = w[2].tips[m] - w[1].tips[m];
            assert!(
                (d1 - d0).norm() <= a_tip() * DT * DT * (1.0 + 1e-9) + 5e-12,
                "a jump of {} mm at t = {}",
                (d1 - d0).norm(),
                w[2].t
            );
            assert!(d1.norm() <= 25.0 * DT * (1.0 + 1e-9));
        }
    }
}

#[test]
fn home_is_a_planned_move_back_and_busy_while_it_runs() -> R {
    let (mut t, mut k) = in_state(OperatingState::Enabled)?;
    let home = t.tips();
    let angles = [t.pose().psi, t.pose().theta];
    let mut cycles = Vec::new();
    // Move both tips and turn the view.
    for _ in 0..800 {
        k += 1;
        let mut i = pushing(k, [0.7, -0.5, 0.6, 0.0, 0.0, 0.0]);
        i.camera.command = CameraCommand::Rate([0.0, 0.0, 0.0, 1.0, -1.0, 0.0]);
        i.camera.buttons = BUTTON_ENABLE;
        cycles.push(t.step(t_of(k), &i)?);
    }
    let away = (t.tips()[0] - home[0]).norm();
    assert!(away > 5.0, "{away}");
    k += 1;
    let c = t.step(t_of(k), &pushing(k, [0.7; 6]).with_command(Command::Home))?;
    assert!(c.busy && t.is_busy());
    cycles.push(c);
    // The hands are ignored while it runs.
    while t.is_busy() {
        k += 1;
        cycles.push(t.step(t_of(k), &pushing(k, [-1.0; 6]))?);
        assert!(k < 20_000, "the home move does not end");
    }
    check_steps(&cycles);
    let end = cycles.last().ok_or("no cycle")?;
    assert!(end.hold.is_none());
    for (tip, home) in end.tips.iter().zip(home) {
        assert!((tip - home).norm() < 1e-9);
    }
    assert!((end.angles[0] - angles[0]).abs() < 1e-12 && (end.angles[1] - angles[1]).abs() < 1e-12);
    // The next cycle rests (the hands re-anchor after the move).
    k += 1;
    let next = t.step(t_of(k), &pushing(k, [-1.0; 6]))?;
    assert_eq!(next.setpoints, end.setpoints);
    assert!(t.is_at_rest() && t.is_ready());
    Ok(())
}

#[test]
fn a_push_into_a_limit_stops_short_and_holds_there() -> R {
    // A supervisor whose qs3 stop thresholds are 8 mm inside the start: a
    // push along the view reaches one of them within a second.
    let start = teleop()?.step(0.0, &Inputs::idle(0.0))?.margins;
    let mut sup = Supervisor::default();
    for m in [
        Margin::LeftQs3,
        Margin::LeftQs3Limits,
        Margin::RightQs3,
        Margin::RightQs3Limits,
    ] {
        sup.stop[m] = start[m] - 8.0;
        sup.warn[m] = sup.stop[m];
    }
    for direction in [1.0, -1.0] {
        let mut t = teleop()?.with_supervisor(sup)?;
        let mut k = 0;
        t.step(0.0, &Inputs::idle(0.0).with_command(Command::Enable))?;
        let mut cycles = Vec::new();
        let mut held = None;
        for _ in 0..3000 {
            k += 1;
            let c = t.step(t_of(k), &pushing(k, [0.0, 0.0, direction, 0.0, 0.0, 0.0]))?;
            for m in Margin::ALL {
                // The checks' rounding allowance: 64 units in the last place.
                let floor = sup.stop[m] - sup.stop[m].abs().max(1.0) * 64.0 * f64::EPSILON;
                assert!(c.margins[m] >= floor, "{m} below its stop at {}", c.t);
            }
            if let Some(h) = c.hold {
                held = Some(h);
            }
            cycles.push(c);
        }
        check_steps(&cycles);
        let Some(HoldAt::Margin(m)) = held else {
            return Err(format!("no margin held: {held:?}").into());
        };
        assert!(matches!(
            m,
            Margin::LeftQs3 | Margin::LeftQs3Limits | Margin::RightQs3 | Margin::RightQs3Limits
        ));
        // Stopped short: still pushing, the hold reported every cycle, the
        // tips still (each cycle's search may creep on by a fraction of
        // what one cycle of acceleration would move).
        let last = &cycles[cycles.len() - 100..];
        assert!(last.iter().all(|c| c.hold.is_some()));
        let creep = (0..2)
            .map(|m| (last[99].tips[m] - last[0].tips[m]).norm())
            .fold(0.0, f64::max);

        assert!(creep < 1e-6, "crept {creep} mm in 0.1 s");
        assert!(
            // Within a micrometre: each held cycle's predicted fraction
            // takes the robot most of the remaining way to the threshold.
            last[0].margins[m] - sup.stop[m] < 1e-3,
            "stopped {} mm short",
            last[0].margins[m] - sup.stop[m]
        );
        // One module's limit held that tip; the other went on.
        let first = cycles
            .iter()
            .position(|c| c.hold.is_some())
            .ok_or("no hold")?;
        let Some(HoldAt::Margin(m0)) = cycles[first].hold else {
            return Err("the first hold is not a margin".into());
        };
        let other = usize::from(m0.name().starts_with("left"));
        let went_on = (last[0].tips[other] - cycles[first].tips[other]).norm();
        assert!(
            went_on > 1.0,
            "the other tip moved {went_on} mm after {m0} held"
        );
        // Backing off is free.
        for _ in 0..300 {
            k += 1;
            let c = t.step(t_of(k), &pushing(k, [0.0, 0.0, -direction, 0.0, 0.0, 0.0]))?;
            assert!(c.hold.is_none(), "{direction}: {:?} at {}", c.hold, c.t);
        }
        assert!(!t.is_at_rest());
    }
    Ok(())
}

#[test]
fn a_silent_device_or_a_nan_is_a_fault_and_a_controlled_stop() -> R {
    for fault in 0..3 {
        let (mut t, mut k) = in_state(OperatingState::Enabled)?;
        let mut cycles = Vec::new();
        for _ in 0..400 {
            k += 1;
            cycles.push(t.step(t_of(k), &pushing(k, [1.0, 1.0, 0.0, 0.0, 0.0, 0.0]))?);
        }
        let speed = t
            .step(t_of(k), &pushing(k, [1.0, 1.0, 0.0, 0.0, 0.0, 0.0]))?
            .tip_velocity[0]
            .norm();
        assert!(speed > 15.0, "{speed}");
        let stamp = t_of(k);
        let mut faulted = None;
        let mut stopped_at = None;
        for _ in 0..1000 {
            k += 1;
            let mut i = pushing(k, [1.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
            match fault {
                0 => i.camera.stamp_s = stamp, // the camera's device went silent
                1 => i.left.command = HandCommand::Rate([f64::INFINITY, 0.0, 0.0, 0.0, 0.0, 0.0]),
                _ => {
                    i.right.command = HandCommand::Position(parasils::kin::nalgebra::Vector3::new(
                        0.0,
                        f64::NAN,
                        0.0,
                    ))
                }
            }
            let c = t.step(t_of(k), &i)?;
            if faulted.is_none() && c.state == OperatingState::Fault {
                // The tips' speed when the fault struck (the cycle before).
                let before = cycles.last().map_or(0.0, |b: &TeleopCycle<f64>| {
                    b.tip_velocity[0].norm().max(b.tip_velocity[1].norm())
                });
                faulted = Some((k, c.fault, before));
            }
            if stopped_at.is_none() && t.is_at_rest() {
                stopped_at = Some(k);
            }
            cycles.push(c);
        }
        check_steps(&cycles);
        let (k_fault, why, speed) = faulted.ok_or("no fault")?;
        match (fault, why) {
            (
                0,
                Some(Fault::Timeout {
                    device: Device::Camera,
                    age_s,
                }),
            ) => assert!(age_s > 0.05 && age_s < 0.0515),
            (
                1,
                Some(Fault::NonFinite {
                    device: Device::Left,
                    what: "tx",
                    ..
                }),
            ) => {}
            (
                2,
                Some(Fault::NonFinite {
                    device: Device::Right,
                    what: "y",
                    ..
                }),
            ) => {}
            other => return Err(format!("fault {fault}: {other:?}").into()),
        }
        // At rest within the time the acceleration limit needs, plus a cycle.
        let stop_cycles = (speed / (a_tip() * DT)).ceil() as u32 + 2;
        let k_stop = stopped_at.ok_or("never stopped")?;
        assert!(
            k_stop - k_fault <= stop_cycles,
            "{} > {stop_cycles}",
            k_stop - k_fault
        );
        // Held in FAULT; a disable and an enable with good inputs resume.
        k += 1;
        let c = t.step(
            t_of(k),
            &Inputs::idle(t_of(k)).with_command(Command::Disable),
        )?;
        assert_eq!(c.state, OperatingState::Disabled);
        assert_eq!(c.fault, None);
        k += 1;
        let c = t.step(
            t_of(k),
            &Inputs::idle(t_of(k)).with_command(Command::Enable),
        )?;
        assert_eq!(c.state, OperatingState::Enabled);
    }
    Ok(())
}

#[test]
fn a_bad_clock_is_an_error_that_changes_nothing() -> R {
    let (mut t, k) = in_state(OperatingState::Enabled)?;
    let before = t;
    let nan = t.step(f64::NAN, &Inputs::idle(0.0));
    assert!(matches!(nan, Err(TeleopError::NonFiniteTime { .. })));
    let back = t.step(t_of(k) - 0.5, &Inputs::idle(0.0));
    assert!(matches!(back, Err(TeleopError::TimeReversed { .. })));
    assert_eq!(t, before);
    let bad = TeleopParams {
        cutoff_hz: 6.0,
        ..TeleopParams::assumed()
    };
    let e = Teleop::new(
        Controller::paper(),
        Pose::paper_start(),
        TipTargets::paper(),
        60.0,
        bad,
    );
    assert!(matches!(
        e,
        Err(TeleopError::InvalidParameter {
            what: "cutoff_hz",
            ..
        })
    ));
    Ok(())
}

/// The distance (mm) from `point` to the endoscope's axis, and how far
/// along the view (from the port `P`, mm) its foot is, computed apart from
/// the library: `R = R_X(psi) R_Y(theta) R_Z(phi)`, so the shaft's
/// direction `R e3 = (sin theta, -sin psi cos theta, cos psi cos theta)`;
/// the straight scope looks along `-R e3`.
fn off_axis(t: &Teleop<f64>, point: &Vector3<f64>) -> (f64, f64) {
    let pose = t.pose();
    let (psi, theta) = (pose.psi, pose.theta);
    let axis = Vector3::new(
        theta.sin(),
        -psi.sin() * theta.cos(),
        psi.cos() * theta.cos(),
    );
    let r = point - Vector3::new(pose.x, pose.y, pose.z);
    (r.cross(&axis).norm(), -r.dot(&axis))
}

/// Runs the move under way to its end with the hands pushing (ignored),
/// every cycle's tips checked against `tips` when given.
fn run_move(
    t: &mut Teleop<f64>,
    k: &mut u32,
    tips: Option<[Vector3<f64>; 2]>,
) -> R<Vec<TeleopCycle<f64>>> {
    let mut cycles = Vec::new();
    while t.is_busy() {
        *k += 1;
        let c = t.step(t_of(*k), &pushing(*k, [1.0, -1.0, 0.5, 0.0, 0.0, 0.0]))?;
        assert!(c.hold.is_none(), "held at {:?}", c.hold);
        if let Some(tips) = tips {
            for (a, b) in c.tips.iter().zip(&tips) {
                assert!(
                    (a - b).norm() < 1e-9,
                    "a tip moved by {} mm",
                    (a - b).norm()
                );
            }
        }
        cycles.push(c);
        assert!(*k < 30_000, "the move does not end");
    }
    Ok(cycles)
}

#[test]
fn look_at_a_point_puts_it_on_the_view_axis_with_the_tips_held() -> R {
    let (mut t, mut k) = in_state(OperatingState::Enabled)?;
    let tips = t.tips();
    let pose = t.pose();
    // A point 15 mm off the current axis, 100 mm below the port.
    let point = Vector3::new(pose.x + 12.0, pose.y - 9.0, pose.z - 100.0);
    let (before, _) = off_axis(&t, &point);
    assert!(before > 10.0, "{before}");
    t.start_move(Goal::LookAt(point))?;
    assert!(t.is_busy());
    let cycles = run_move(&mut t, &mut k, Some(tips))?;
    assert!(cycles.len() > 100, "{} cycles", cycles.len());
    let (after, along) = off_axis(&t, &point);
    assert!(after < 1e-9, "{after} mm off the axis");
    assert!(along > t.depth(), "the point is behind the camera: {along}");
    // The view turned within its limits (the angles' second differences).
    let alpha = TeleopParams::<f64>::assumed().camera.a_max;
    for w in cycles.windows(3) {
        for a in 0..2 {
            let dd = w[2].angles[a] - 2.0 * w[1].angles[a] + w[0].angles[a];
            assert!(dd.abs() <= alpha * DT * DT * (1.0 + 1e-6) + 1e-15, "{dd}");
        }
    }
    // The next cycle rests (the hands re-anchor), ENABLED; then the hands
    // drive again.
    k += 1;
    t.step(t_of(k), &pushing(k, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]))?;
    assert!(t.is_at_rest() && t.is_ready());
    for _ in 0..20 {
        k += 1;
        t.step(t_of(k), &pushing(k, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]))?;
    }
    assert!(!t.is_at_rest());
    Ok(())
}

#[test]
fn look_at_the_tips_centres_their_midpoint() -> R {
    let (mut t, mut k) = in_state(OperatingState::Enabled)?;
    // Move the tips apart from where the view looks, then centre them.
    for _ in 0..600 {
        k += 1;
        let mut i = pushing(k, [0.0; 6]);
        i.left.command = HandCommand::Rate([0.8, 0.6, 0.0, 0.0, 0.0, 0.0]);
        t.step(t_of(k), &i)?;
    }
    // Brake to rest.
    k += 1;
    t.step(t_of(k), &Inputs::idle(t_of(k)).with_command(Command::Stop))?;
    run_move(&mut t, &mut k, None)?;
    let tips = t.tips();
    let mid = (tips[0] + tips[1]) * 0.5;
    let (before, _) = off_axis(&t, &mid);
    assert!(before > 1.0, "{before}");
    k += 1;
    let c = t.step(
        t_of(k),
        &Inputs::idle(t_of(k)).with_command(Command::LookAtTips),
    )?;
    assert_eq!(c.command.map(|o| o.accepted), Some(true));
    assert!(c.busy);
    run_move(&mut t, &mut k, Some(tips))?;
    let (after, along) = off_axis(&t, &mid);
    assert!(after < 1e-9, "{after} mm off the axis");
    assert!(along > t.depth());
    Ok(())
}

#[test]
fn a_move_to_a_pose_ends_at_the_pose() -> R {
    let (mut t, mut k) = in_state(OperatingState::Enabled)?;
    let pose = t.pose();
    let start = t.tips();
    let angles = [pose.psi + 3f64.to_radians(), pose.theta - 2f64.to_radians()];
    let tips = [
        start[0] + Vector3::new(2.0, -1.5, 1.0),
        start[1] + Vector3::new(-1.0, 2.5, -2.0),
    ];
    t.start_move(Goal::Pose { angles, tips })?;
    let cycles = run_move(&mut t, &mut k, None)?;
    check_steps(&cycles);
    let end = cycles.last().ok_or("no cycle")?;
    for (a, b) in end.tips.iter().zip(&tips) {
        assert!((a - b).norm() < 1e-9, "{}", (a - b).norm());
    }
    for (a, b) in end.angles.iter().zip(&angles) {
        assert!((a - b).abs() < 1e-12, "{}", (a - b).abs());
    }
    // The setpoints are the inverse kinematics of that pose and those tips,
    // solved again apart from the move.
    let ik = Controller::<f64>::paper().step(
        &parasils::kin::PlatformState::at_rest(Pose {
            psi: angles[0],
            theta: angles[1],
            ..pose
        }),
        &TipTargets {
            left: tips[0],
            right: tips[1],
        },
        &mut parasils::kin::MarginTracker::new(),
    )?;
    let q = parasils::kin::step_positions(&ik);
    for (a, b) in end.setpoints.iter().zip(&q) {
        assert!((a - b).abs() < 1e-9, "{a} against {b}");
    }
    Ok(())
}

#[test]
fn stop_brings_the_robot_to_rest_within_its_limits_and_ends_a_move() -> R {
    let (mut t, mut k) = in_state(OperatingState::Enabled)?;
    let mut cycles = Vec::new();
    for _ in 0..400 {
        k += 1;
        cycles.push(t.step(t_of(k), &pushing(k, [0.9, 0.4, -0.3, 0.0, 0.0, 0.0]))?);
    }
    assert!(!t.is_at_rest());
    k += 1;
    // The hands keep pushing: a stop ignores them until it is at rest.
    let c = t.step(
        t_of(k),
        &pushing(k, [0.9, 0.4, -0.3, 0.0, 0.0, 0.0]).with_command(Command::Stop),
    )?;
    assert_eq!(c.command.map(|o| o.accepted), Some(true));
    assert!(c.busy && c.state == OperatingState::Enabled);
    cycles.push(c);
    let stopping = run_move(&mut t, &mut k, None)?;
    // The controlled stop: every speed falls, never rises, to exactly 0.
    for w in stopping.windows(2) {
        for m in 0..2 {
            assert!(w[1].tip_velocity[m].norm() <= w[0].tip_velocity[m].norm() + 1e-12);
        }
    }
    cycles.extend(stopping);
    check_steps(&cycles);
    assert!(t.is_at_rest() && t.is_ready() && !t.is_busy());
    // A stop ends a planned move under way.
    t.start_move(Goal::Home)?;
    for _ in 0..50 {
        k += 1;
        t.step(t_of(k), &Inputs::idle(t_of(k)))?;
    }
    k += 1;
    t.step(t_of(k), &Inputs::idle(t_of(k)).with_command(Command::Stop))?;
    run_move(&mut t, &mut k, None)?;
    assert!(t.is_at_rest());
    let away = (t.tips()[0] - TipTargets::<f64>::paper().left).norm();
    assert!(away > 1.0, "the move went on home: {away}");
    Ok(())
}

#[test]
fn a_move_is_refused_outside_enabled_and_for_a_bad_goal_and_changes_nothing() -> R {
    let goal = Goal::LookAt(Vector3::new(0.0, 0.0, -700.0));
    for state in [
        OperatingState::Disabled,
        OperatingState::Paused,
        OperatingState::Fault,
    ] {
        let (mut t, _) = in_state(state)?;
        // (Debug's text: a fault's NaN is not equal to itself.)
        let before = format!("{t:?}");
        assert_eq!(t.start_move(goal), Err(MoveRefused::State(state)));
        assert_eq!(format!("{t:?}"), before);
    }
    let (mut t, _) = in_state(OperatingState::Enabled)?;
    let before = t;
    let nan = Goal::LookAt(Vector3::new(0.0, f64::NAN, -700.0));
    assert!(matches!(
        t.start_move(nan),
        Err(MoveRefused::NonFinite {
            what: "point.y",
            ..
        })
    ));
    let pose = t.pose();
    let behind = Goal::LookAt(Vector3::new(pose.x, pose.y, pose.z - 10.0)); // nearer than the 60 mm tip
    assert!(matches!(t.start_move(behind), Err(MoveRefused::Camera(_))));
    let bad_tip = Goal::Pose {
        angles: [0.0, 0.0],
        tips: [Vector3::zeros(), Vector3::new(0.0, 0.0, f64::INFINITY)],
    };
    assert!(matches!(
        t.start_move(bad_tip),
        Err(MoveRefused::NonFinite {
            what: "tips[1].z",
            ..
        })
    ));
    assert_eq!(t, before);
    Ok(())
}
