//! The teleoperation core's operating states (CRTK's table, every state by
//! every command), the home move, the limits it holds at, and its faults.

use parasils::Supervisor;
use parasils::kin::{Controller, Pose, TipTargets};
use parasils::supervisor::Margin;
use parasils::teleop::{
    BUTTON_ENABLE, CameraCommand, Command, Device, Fault, HandCommand, HoldAt, Inputs,
    OperatingState, Teleop, TeleopCycle, TeleopError, TeleopParams,
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
    // CRTK's table (enable, disable, pause, resume), then home; `true` where
    // the command is valid. A fault with fresh inputs at rest is cleared.
    let table = [
        (
            S::Disabled,
            [
                (S::Enabled, true),
                (S::Disabled, true),
                (S::Disabled, false),
                (S::Disabled, false),
                (S::Disabled, false),
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
            ],
        ),
    ];
    for (state, row) in table {
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
            // (A home move from home ends at once.)
            assert!(!t.is_busy());
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
