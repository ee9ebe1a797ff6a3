//! Random input streams through the teleoperation core: full-scale rates,
//! masters moving fast, clutch and dead-man presses, the camera's rate and
//! follow modes, commands, non-finite inputs and silent devices, all at
//! random. Over every cycle: no setpoint beyond a limit (every supervised
//! margin and gap at or above its stop threshold, or no lower than the
//! cycle before), no change of a tip's setpoint beyond what the speed and
//! acceleration limits allow, no NaN, and every fault followed by a stop
//! within the acceleration limits.

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{
    ACTUATOR_COUNT, ActuatorLimits, BodyGeometry, Controller, Pose, TipTargets, step_rates,
};
use parasils::supervisor::{ClearanceThresholds, Margin};
use parasils::teleop::{
    BUTTON_CLUTCH, BUTTON_ENABLE, CameraCommand, Command, Fault, HandCommand, HoldAt, Inputs,
    OperatingState, Teleop, TeleopCycle, TeleopParams,
};
use parasils::{Supervisor, kin::ClearancePair};
use parasils_io::Rng;

type R<T = ()> = Result<T, Box<dyn core::error::Error>>;

const DT: f64 = 1e-3;
const STOP_MM: f64 = 0.5;

/// A device's random behaviour, changed now and then.
#[derive(Clone, Copy)]
struct HandPlan {
    rate: Option<[f64; 6]>,
    /// A master's position and velocity, mm and mm/s.
    master: (Vector3<f64>, Vector3<f64>),
    buttons: u8,
    silent_until: u32,
    stamp: f64,
}

fn axes(rng: &mut Rng) -> [f64; 6] {
    let mut a = [0.0; 6];
    for x in &mut a {
        *x = match rng.below(3) {
            0 => 1.0,
            1 => -1.0,
            _ => rng.uniform(-1.0, 1.0),
        };
    }
    a
}

fn buttons(rng: &mut Rng) -> u8 {
    match rng.below(10) {
        0..=5 => BUTTON_ENABLE,
        6 | 7 => BUTTON_ENABLE | BUTTON_CLUTCH,
        8 => 0,
        _ => BUTTON_CLUTCH,
    }
}

fn new_plan(rng: &mut Rng, at: Vector3<f64>) -> HandPlan {
    let v = Vector3::new(rng.normal(), rng.normal(), rng.normal()) * 100.0;
    HandPlan {
        rate: (rng.below(10) < 7).then(|| axes(rng)),
        master: (at, v),
        buttons: buttons(rng),
        silent_until: 0,
        stamp: 0.0,
    }
}

/// What a run saw.
#[derive(Debug, Default)]
struct Tally {
    cycles: u64,
    holds: u64,
    /// Cycles held at an actuator's velocity or acceleration limit.
    actuator_holds: u64,
    faults: u64,
    stops_checked: u64,
    /// The largest share of its velocity and of its acceleration limit any
    /// actuator used, from the setpoints' first and second differences.
    rate_use: [f64; 2],
}

/// The share of its velocity and of its acceleration limit each actuator
/// uses at `c`, after `b` and `a` (the setpoints' differences over `DT`).
fn rate_use(a: Option<&TeleopCycle<f64>>, b: &TeleopCycle<f64>, c: &TeleopCycle<f64>) -> [f64; 2] {
    let limits = ActuatorLimits::<f64>::assumed();
    let mut worst = [0.0f64; 2];
    for k in 0..ACTUATOR_COUNT {
        let d1 = c.setpoints[k] - b.setpoints[k];
        worst[0] = worst[0].max(d1.abs() / DT / limits.velocity[k]);
        if let Some(a) = a {
            let d0 = b.setpoints[k] - a.setpoints[k];
            worst[1] = worst[1].max((d1 - d0).abs() / (DT * DT) / limits.acceleration[k]);
        }
    }
    worst
}

/// The paper's start, every margin above its stop threshold. Watching the
/// clearance, the right tip moved by `(60, -40, 40)` mm and the endoscope
/// at depth 0 (as `tests/online_clearance.rs` has them): then every gap
/// starts above the stop threshold too (the paper's tips at depth 60 start
/// with the left shaft 2.9 mm into the endoscope).
fn teleop(watched: bool, params: TeleopParams<f64>) -> R<Teleop<f64>> {
    let mut tips = TipTargets::paper();
    let mut depth = 60.0;
    if watched {
        tips.right += Vector3::new(60.0, -40.0, 40.0);
        depth = 0.0;
    }
    let t = Teleop::new(
        Controller::paper(),
        Pose::paper_start(),
        tips,
        depth,
        params,
    )?;
    Ok(if watched {
        t.with_clearance(
            BodyGeometry::assumed(),
            ClearanceThresholds {
                warn: 2.0,
                stop: STOP_MM,
            },
        )?
    } else {
        t
    })
}

fn check_cycle(
    prev: &[TeleopCycle<f64>],
    c: &TeleopCycle<f64>,
    sup: &Supervisor<f64>,
    p: &TeleopParams<f64>,
) {
    assert!(
        c.setpoints.iter().all(|q| q.is_finite()),
        "NaN setpoint at {}",
        c.t
    );
    assert!(c.tips.iter().all(|x| x.iter().all(|v| v.is_finite())));
    assert!(
        !matches!(c.fault, Some(Fault::Unsolvable(_))),
        "unsolvable at {}",
        c.t
    );
    let Some(b) = prev.last() else { return };
    // Every margin and gap starts above its stop threshold and stays there
    // (to rounding: a tip held at a threshold creeps towards it by
    // fractions of a cycle, and the margin's last digits are rounding).
    for m in Margin::ALL {
        let (x, before) = (c.margins[m], b.margins[m]);
        assert!(
            x >= sup.stop[m] - 1e-12 * sup.stop[m].abs().max(1.0),
            "{m}: {x} from {before} (stop {}) at {}: {:?} {} {:?} {:?} {} after {:?} {:?}; v {:?} {:?} from {:?} {:?}",
            sup.stop[m],
            c.t,
            c.state,
            c.busy,
            c.hold,
            c.command,
            c.following,
            b.state,
            b.hold,
            c.tip_velocity,
            c.angle_rates,
            b.tip_velocity,
            b.angle_rates
        );
    }
    if let (Some(g), Some(gb)) = (&c.clearance, &b.clearance) {
        for pair in ClearancePair::ALL {
            let (x, before) = (g.get(pair).gap, gb.get(pair).gap);
            assert!(x >= STOP_MM - 1e-12, "{pair}: {x} from {before} at {}", c.t);
        }
    }
    // Rounding: the angles (about 1 rad) and the tips (about 600 mm) are
    // differenced twice, and the home move samples its profile at
    // `t - start`, whose rounding at t = 1000 s (1e-13 s) moves an angle by
    // up to 1e-14 rad and a tip by 3e-12 mm: 1e-13 rad and 5e-12 mm.
    let tol = 1.0 + 1e-9;
    for m in 0..2 {
        let d1 = c.tips[m] - b.tips[m];
        assert!(
            d1.norm() <= p.tip_speed_mm_s * DT * tol + 5e-12,
            "speed at {}",
            c.t
        );
        if let Some(a) = prev.get(prev.len().wrapping_sub(2)) {
            let d0 = b.tips[m] - a.tips[m];
            let jump = (d1 - d0).norm();
            assert!(
                jump <= p.tip_accel_mm_s2 * DT * DT * tol + 5e-12,
                "a jump of {jump} mm at {}: {:?} {} {:?} {:?} after {:?} {} {:?} {:?}, v {:?} {:?}",
                c.t,
                c.state,
                c.busy,
                c.hold,
                c.command,
                b.state,
                b.busy,
                b.hold,
                b.command,
                c.tip_velocity[m],
                b.tip_velocity[m]
            );
        }
    }
    for i in 0..2 {
        let d1 = c.angles[i] - b.angles[i];
        assert!(d1.abs() <= p.camera.v_max * DT * tol + 1e-13);
        if let Some(a) = prev.get(prev.len().wrapping_sub(2)) {
            let d0 = b.angles[i] - a.angles[i];
            assert!(
                (d1 - d0).abs() <= p.camera.a_max * DT * DT * tol + 1e-13,
                "view jump of {} rad at {}: {:?} {} {:?} {:?} following {} after {:?} {} {:?} following {}; rates {:?} from {:?}",
                d1 - d0,
                c.t,
                c.state,
                c.busy,
                c.hold,
                c.command,
                c.following,
                b.state,
                b.busy,
                b.hold,
                b.following,
                c.angle_rates,
                b.angle_rates
            );
        }
    }
}

fn run(seed: u64, cycles: u32, watched: bool, params: TeleopParams<f64>) -> R<Tally> {
    let mut rng = Rng::new(seed);
    let mut t = teleop(watched, params)?;
    // Stop thresholds a random walk reaches: 15 mm, 0.15 rad or 0.15 inside
    // the start's margins (never below the default ones).
    let start = t.step(0.0, &Inputs::idle(0.0))?.margins;
    let mut sup = Supervisor::<f64>::default();
    for m in Margin::ALL {
        let inside = if m.unit() == "mm" { 15.0 } else { 0.15 };
        sup.stop[m] = sup.stop[m].max(start[m] - inside);
        sup.warn[m] = sup.stop[m];
    }
    let mut t = t.with_supervisor(sup)?;
    let first = t.step(0.0, &Inputs::idle(0.0))?;
    for m in Margin::ALL {
        assert!(first.margins[m] > sup.stop[m]);
    }
    if let Some(g) = first.clearance {
        assert!(g.min().1 > STOP_MM, "{:?}", g.min());
    }
    let p = *t.params();
    let mut tally = Tally::default();
    let mut hands = [
        new_plan(&mut rng, Vector3::zeros()),
        new_plan(&mut rng, Vector3::zeros()),
    ];
    let mut camera = (Some(axes(&mut rng)), BUTTON_ENABLE, 0u32, 0.0);
    let mut recent: Vec<TeleopCycle<f64>> = Vec::new();
    // A fault's cycle and the cycles its stop may take.
    let mut stopping: Option<(u32, u32)> = None;
    let mut command = Some(Command::Enable);
    for k in 0..cycles {
        let now = f64::from(k) * DT;
        let mut inputs = Inputs::idle(now);
        inputs.command = command.take();
        for (h, plan) in hands.iter_mut().enumerate() {
            if rng.below(150) == 0 {
                *plan = new_plan(&mut rng, plan.master.0);
            }
            if rng.below(5000) == 0 {
                plan.silent_until = k + 30 + rng.below(120) as u32;
            }
            plan.master.0 += plan.master.1 * DT;
            if k >= plan.silent_until {
                plan.stamp = now;
            }
            let input = if h == 0 {
                &mut inputs.left
            } else {
                &mut inputs.right
            };
            input.command = match plan.rate {
                Some(a) => HandCommand::Rate(a),
                None => HandCommand::Position(plan.master.0),
            };
            input.buttons = plan.buttons;
            input.stamp_s = plan.stamp;
            if rng.below(5000) == 0 {
                input.command = HandCommand::Rate([0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0]);
            }
        }
        if rng.below(300) == 0 {
            camera.0 = (rng.below(5) > 0).then(|| axes(&mut rng));
            camera.1 = if rng.below(2) == 0 { BUTTON_ENABLE } else { 0 };
        }
        if rng.below(8000) == 0 {
            camera.2 = k + 30 + rng.below(120) as u32;
        }
        if k >= camera.2 {
            camera.3 = now;
        }
        inputs.camera.command = camera.0.map_or(CameraCommand::Follow, CameraCommand::Rate);
        inputs.camera.buttons = camera.1;
        inputs.camera.stamp_s = camera.3;
        if rng.below(700) == 0 {
            command = Some(match rng.below(10) {
                0..=3 => Command::Enable,
                4 => Command::Disable,
                5 => Command::Pause,
                6 | 7 => Command::Resume,
                _ => Command::Home,
            });
        }
        let before = t.state();
        let speed = recent.last().map_or(0.0, |c| {
            c.tip_velocity[0].norm().max(c.tip_velocity[1].norm())
        });
        let turn = recent
            .last()
            .map_or(0.0, |c| c.angle_rates[0].abs().max(c.angle_rates[1].abs()));
        // The stop the actuators allow: each joint's rate over 90 % of its
        // acceleration limit (the share the core's stop plans with).
        let joints = recent.last().map_or(0.0, |c| {
            let (q_dot, _) = step_rates(&c.step);
            let limits = ActuatorLimits::<f64>::assumed();
            (0..ACTUATOR_COUNT).fold(0.0f64, |m, k| {
                m.max(q_dot[k].abs() / (0.9 * limits.acceleration[k]))
            })
        });
        let c = t.step(now, &inputs)?;
        check_cycle(&recent, &c, &sup, &p);
        if let Some(b) = recent.last() {
            let used = rate_use(
                recent.len().checked_sub(2).and_then(|i| recent.get(i)),
                b,
                &c,
            );
            for (w, u) in tally.rate_use.iter_mut().zip(used) {
                *w = w.max(u);
            }
        }
        tally.cycles += 1;
        tally.holds += u64::from(c.hold.is_some());
        tally.actuator_holds += u64::from(matches!(c.hold, Some(HoldAt::Actuator { .. })));
        if before != OperatingState::Fault && c.state == OperatingState::Fault {
            tally.faults += 1;
            let need = (speed / (p.tip_accel_mm_s2 * DT))
                .max(turn / (p.camera.a_max * DT))
                .max(joints / DT);
            stopping = Some((k, need.ceil() as u32 + 2));
        }
        if let Some((k0, n)) = stopping {
            if c.state != OperatingState::Fault {
                stopping = None;
            } else if t.is_at_rest() {
                tally.stops_checked += 1;
                stopping = None;
            } else {
                assert!(
                    k - k0 <= n,
                    "seed {seed}: no stop {} cycles after the fault at {k0}",
                    k - k0
                );
            }
        }
        if recent.len() == 2 {
            recent.remove(0);
        }
        recent.push(c);
        // Leave FAULT now and then (the retry succeeds once inputs are good).
        if c.state == OperatingState::Fault && command.is_none() && rng.below(200) == 0 {
            command = Some(if rng.below(2) == 0 {
                Command::Disable
            } else {
                Command::Enable
            });
        }
    }
    Ok(tally)
}

/// `runs` runs of `cycles` cycles from seed 0, every other one watching
/// the clearance; the tallies summed, the rates' use the largest.
fn campaign(runs: u64, cycles: u32, params: TeleopParams<f64>) -> R<Tally> {
    let mut total = Tally::default();
    for seed in 0..runs {
        let tally = run(seed, cycles, seed % 2 == 1, params)?;
        total.cycles += tally.cycles;
        total.holds += tally.holds;
        total.actuator_holds += tally.actuator_holds;
        total.faults += tally.faults;
        total.stops_checked += tally.stops_checked;
        for (w, u) in total.rate_use.iter_mut().zip(tally.rate_use) {
            *w = w.max(u);
        }
    }
    eprintln!("{total:?}");
    Ok(total)
}

#[test]
fn random_streams_never_cross_a_limit_jump_or_fail_to_stop() -> R {
    // 10^5 cycles over five seeds, two of them watching the clearance.
    let total = campaign(5, 20_000, TeleopParams::assumed())?;
    assert_eq!(total.cycles, 100_000);
    assert!(total.faults >= 5, "too few faults exercised: {total:?}");
    assert!(total.holds > 0, "no limit reached: {total:?}");
    // The actuators within their limits, by the setpoints' own differences.
    assert!(
        total.rate_use[0] <= 1.0 && total.rate_use[1] <= 1.0,
        "{total:?}"
    );
    Ok(())
}

#[test]
fn a_fast_mapping_is_held_at_the_actuators_limits() -> R {
    // Tips allowed 60 mm/s and 400 mm/s^2, far beyond what qs1..qs3 can
    // follow: the cycles hold at the actuators' limits instead.
    let params = TeleopParams {
        rate_scale_mm_s: 60.0,
        tip_speed_mm_s: 60.0,
        tip_accel_mm_s2: 400.0,
        ..TeleopParams::assumed()
    };
    let total = campaign(5, 20_000, params)?;
    assert!(total.actuator_holds > 100, "{total:?}");
    assert!(total.rate_use[0] <= 1.0, "{total:?}");
    // A commanded cycle is held within every acceleration limit; a stop
    // planned at 90 % of them keeps the end its first cycle was checked
    // with, which at these speeds can ask a few percent more of an
    // actuator (the position limits come first; measured 1.063).
    assert!(total.rate_use[1] <= 1.1, "{total:?}");
    Ok(())
}

/// The long campaign: 10^6 cycles on each of 20 seeds
/// (`cargo test -p parasils --test teleop_random -- --ignored`).
#[test]
#[ignore = "long: 2 x 10^7 cycles"]
fn random_streams_long() -> R {
    let seeds: Vec<u64> = match std::env::var("TELEOP_SEED") {
        Ok(s) => vec![s.parse()?],
        Err(_) => (100..120).collect(),
    };
    for seed in seeds {
        let tally = run(seed, 1_000_000, seed % 2 == 0, TeleopParams::assumed())?;
        eprintln!("seed {seed}: {tally:?}");
    }
    Ok(())
}
