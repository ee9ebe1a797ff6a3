//! The online controller: goals and stops accepted while the platform moves,
//! the supervisor's stop before a singularity, and the controller's errors.
//!
//! The scenario of the firmware (`examples/firmware`): from `P0`, the
//! paper's goal (`psi` +15, `theta` +25 deg) commanded at 0 s, a new goal
//! (`psi` -10, `theta` +15 deg from `P0`: `psi` turns back) at 1.2 s while
//! turning, a stop at 3.0 s while moving towards it, a third goal (`psi` +5,
//! `theta` +10 deg from `P0`) at 3.5 s, run at 1 kHz until rest.
#![allow(clippy::float_cmp, reason = "exactness is what these tests check")]

use parasils::kin::{Controller, PlatformState, Pose, TipTargets};
use parasils::supervisor::{Margin, Margins, Supervisor};
use parasils::traj::{Limits, Synchronization};
use parasils::{Error, MotionKind, OnlineController, Real, Setpoint};

const RATE_HZ: f64 = 1000.0;

/// One command of a scenario: at cycle `k`, a goal (deg from `P0`) or a stop.
#[derive(Clone, Copy)]
enum Command {
    Goal(u32, [f64; 2]),
    Stop(u32),
}

/// The firmware's command stream.
const STREAM: [Command; 4] = [
    Command::Goal(0, [15.0, 25.0]),
    Command::Goal(1200, [-10.0, 15.0]),
    Command::Stop(3000),
    Command::Goal(3500, [5.0, 10.0]),
];

fn online<T: Real>() -> Result<OnlineController<T>, Error> {
    let deg = |x: f64| T::lit(x.to_radians());
    OnlineController::new(
        Controller::paper(),
        TipTargets::paper(),
        Pose::paper_start(),
        [Limits::new(deg(10.0), deg(5.0)); 2],
        Supervisor::default(),
    )
}

fn goal<T: Real>(deg: [f64; 2]) -> [T; 2] {
    let p0 = Pose::<f64>::paper_start();
    let lit = |x: f64| T::lit(x);
    [
        lit(p0.psi + deg[0].to_radians()),
        lit(p0.theta + deg[1].to_radians()),
    ]
}

/// What a run recorded: every cycle, and for each command the state just
/// before it (the previous cycle's motion sampled at the command's time)
/// and the first cycle after it.
struct Run<T: Real> {
    cycles: Vec<Setpoint<T>>,
    /// `(cycle, state of the old motion at t, synchronisation)` per command.
    commands: Vec<(usize, PlatformState<T>, Option<Synchronization>)>,
}

/// Runs `stream` at 1 kHz until rest after its last command (at most
/// `max_cycles`).
fn run<T: Real>(
    c: &mut OnlineController<T>,
    stream: &[Command],
    max_cycles: u32,
) -> Result<Run<T>, Error> {
    let mut cycles = Vec::new();
    let mut commands = Vec::new();
    let last = stream.iter().fold(0, |m, c| match *c {
        Command::Goal(k, _) | Command::Stop(k) => m.max(k),
    });
    for k in 0..max_cycles {
        let t = T::from_index(k as usize) / T::lit(RATE_HZ);
        for cmd in stream {
            match *cmd {
                Command::Goal(at, deg) if at == k => {
                    let before = c.state_at(t);
                    let sync = c.command(t, goal(deg))?;
                    commands.push((cycles.len(), before, Some(sync)));
                }
                Command::Stop(at) if at == k => {
                    let before = c.state_at(t);
                    c.stop(t)?;
                    commands.push((cycles.len(), before, None));
                }
                _ => {}
            }
        }
        cycles.push(c.tick(t)?);
        if k >= last && c.is_at_rest(t) {
            break;
        }
    }
    Ok(Run { cycles, commands })
}

fn tip_drift(c: &OnlineController<f64>, s: &Setpoint<f64>) -> f64 {
    let k = c.controller();
    let left = s.step.frame.to_fixed(&k.left.fk_platform(&s.step.left.q));
    let right = s.step.frame.to_fixed(&k.right.fk_platform(&s.step.right.q));
    (left - c.tips().left)
        .norm()
        .max((right - c.tips().right).norm())
}

#[test]
fn two_retargets_and_a_stop_keep_the_tips_still_and_the_motion_continuous() -> Result<(), Error> {
    let mut c = online::<f64>()?;
    let r = run(&mut c, &STREAM, 20_000)?;
    let limits = *c.limits();
    // Every command took effect at its cycle, position and velocity
    // continuous: the new motion starts from the old one's state.
    assert_eq!(r.commands.len(), 4);
    for &(i, before, _) in &r.commands {
        let s = &r.cycles[i].state;
        assert_eq!(s.pose, before.pose, "position at cycle {i}");
        assert_eq!(s.velocity, before.velocity, "velocity at cycle {i}");
    }
    // The retarget at 1.2 s turns: its velocity is not along the new way.
    assert_eq!(r.commands[0].2, Some(Synchronization::Phase));
    assert_eq!(r.commands[1].2, Some(Synchronization::Time));
    // The stop at 3.0 s: the second motion had not ended.
    assert!(r.commands[2].1.velocity.psi != 0.0 || r.commands[2].1.velocity.theta != 0.0);
    let mut tip = 0.0f64;
    let mut previous: Option<&Setpoint<f64>> = None;
    for s in &r.cycles {
        tip = tip.max(tip_drift(&c, s));
        for (a, v, l) in [
            (s.state.acceleration.psi, s.state.velocity.psi, limits[0]),
            (
                s.state.acceleration.theta,
                s.state.velocity.theta,
                limits[1],
            ),
        ] {
            assert!(a.abs() <= l.a_max * (1.0 + 16.0 * f64::EPSILON), "{a}");
            assert!(v.abs() <= l.v_max * (1.0 + 16.0 * f64::EPSILON), "{v}");
        }
        // Between cycles the angles move by at most v_max dt (plus the
        // acceleration's share): no jump anywhere, commands included.
        if let Some(p) = previous {
            let dt = s.t - p.t;
            let jump = (s.state.pose.psi - p.state.pose.psi)
                .abs()
                .max((s.state.pose.theta - p.state.pose.theta).abs());
            assert!(jump <= limits[0].v_max * dt * 1.0001, "{}", s.t);
            let dv = (s.state.velocity.psi - p.state.velocity.psi)
                .abs()
                .max((s.state.velocity.theta - p.state.velocity.theta).abs());
            assert!(dv <= limits[0].a_max * dt * 1.0001, "{}", s.t);
        }
        assert!(s.warnings.is_empty() && s.stop.is_empty(), "{}", s.t);
        previous = Some(s);
    }
    assert!(tip < 1e-9, "tip drift {tip} mm");
    // The command index of each cycle, and the kind of motion.
    let index: Vec<(u32, MotionKind)> = r.cycles.iter().map(|s| (s.command, s.kind)).collect();
    assert_eq!(index[0], (0, MotionKind::Command));
    assert_eq!(index[1199], (0, MotionKind::Command));
    assert_eq!(index[1200], (1, MotionKind::Command));
    assert_eq!(index[2999], (1, MotionKind::Command));
    assert_eq!(index[3000], (2, MotionKind::Stop));
    assert_eq!(index[3500], (3, MotionKind::Command));
    assert_eq!(c.command_index(), 3);
    // The stop brakes along a straight line (the velocity keeps its
    // direction) and is still braking when the third goal comes at 3.5 s.
    let (v0, v1) = (r.cycles[3000].state.velocity, r.cycles[3499].state.velocity);
    assert!((v0.psi * v1.theta - v0.theta * v1.psi).abs() < 1e-15);
    assert!(v1.psi * v0.psi > 0.0 && v1.psi.abs() < v0.psi.abs());
    // The run ends at rest on the third goal.
    let end = r
        .cycles
        .last()
        .map(|s| s.state)
        .unwrap_or_else(|| c.state_at(0.0));
    assert_eq!([end.pose.psi, end.pose.theta], goal::<f64>([5.0, 10.0]));
    assert_eq!((end.velocity.psi, end.velocity.theta), (0.0, 0.0));
    Ok(())
}

/// The same stream in f32 follows the f64 run within f32's budget.
#[test]
fn f32_run_follows_f64() -> Result<(), Error> {
    let r64 = run(&mut online::<f64>()?, &STREAM, 20_000)?;
    let r32 = run(&mut online::<f32>()?, &STREAM, 20_000)?;
    assert_eq!(r64.cycles.len(), r32.cycles.len());
    for (a, b) in r64.cycles.iter().zip(&r32.cycles) {
        assert!((a.state.pose.psi - f64::from(b.state.pose.psi)).abs() < 1e-5);
        assert!((a.state.pose.theta - f64::from(b.state.pose.theta)).abs() < 1e-5);
        assert_eq!(a.command, b.command);
        for (x, y) in a.step.module1.q.0.iter().zip(b.step.module1.q.0) {
            assert!((x - f64::from(y)).abs() < 2e-3, "{} {x} {y}", a.t);
        }
    }
    Ok(())
}

/// The paper's goal commanded at rest at 0 s is the paper's reorientation:
/// the same states as [`parasils::Reorientation::paper`] at every sample.
#[test]
fn paper_goal_from_rest_is_the_paper_reorientation() -> Result<(), Error> {
    let mut c = online::<f64>()?;
    let r = run(&mut c, &[STREAM[0]], 10_000)?;
    let paper = parasils::Reorientation::<f64>::paper()?;
    assert_eq!(r.cycles.len(), 4501);
    for s in &r.cycles {
        let p = paper.state_at(s.t);
        assert!((s.state.pose.psi - p.pose.psi).abs() < 1e-13, "{}", s.t);
        assert!((s.state.pose.theta - p.pose.theta).abs() < 1e-13);
        assert!((s.state.velocity.theta - p.velocity.theta).abs() < 1e-13);
    }
    Ok(())
}

/// A goal past the parallel singularity (near `theta` = 49.7 deg with `psi`
/// at `P0`): the supervisor stops the platform before module 1's hard
/// threshold, and the platform rests with every margin above its hard one.
#[test]
fn supervisor_stops_short_of_the_parallel_singularity() -> Result<(), Error> {
    for rate in [RATE_HZ, 250.0] {
        let mut c = online::<f64>()?;
        let hard = Margins::hard(c.controller());
        let stop = c.supervisor().stop;
        let p0 = Pose::<f64>::paper_start();
        c.command(0.0, [p0.psi, 55f64.to_radians()])?;
        let mut demanded = None;
        let mut last = None;
        for k in 0..20_000u32 {
            let t = f64::from(k) / rate;
            let s = c.tick(t)?;
            if !s.stop.is_empty() && demanded.is_none() {
                demanded = Some(s);
                assert_eq!(s.stop.first(), Some(Margin::Parallel));
                assert_eq!(c.kind(), MotionKind::SupervisorStop);
                assert_eq!(c.command_index(), 1);
            }
            last = Some(s);
            if c.is_at_rest(t) {
                break;
            }
        }
        let (Some(d), Some(end)) = (demanded, last) else {
            panic!("no stop demanded at {rate} Hz");
        };
        assert_eq!(end.kind, MotionKind::SupervisorStop);
        assert_eq!(end.command, 1);
        assert_eq!(
            (end.state.velocity.psi, end.state.velocity.theta),
            (0.0, 0.0)
        );
        for m in Margin::ALL {
            assert!(end.margins[m] > hard[m], "{m} at rest: {}", end.margins[m]);
        }
        // It rests near the stop threshold: the prediction is good, not
        // merely conservative.
        let at_rest = end.margins[Margin::Parallel];
        assert!(
            at_rest > 0.8 * stop[Margin::Parallel],
            "{rate} Hz: {at_rest}"
        );
        assert!(
            at_rest < 1.5 * stop[Margin::Parallel],
            "{rate} Hz: {at_rest}"
        );
        assert!(d.state.pose.theta < end.state.pose.theta);
        // A new goal back away from the singularity is accepted and runs
        // without a stop: the margin grows.
        let t = end.t + 0.5;
        c.command(t, [p0.psi, p0.theta])?;
        let mut k = 0u32;
        loop {
            let s = c.tick(t + f64::from(k) / rate)?;
            assert!(s.stop.is_empty(), "{}", s.t);
            if c.is_at_rest(s.t) {
                break;
            }
            k += 1;
        }
        assert_eq!(c.kind(), MotionKind::Command);
        assert_eq!(c.command_index(), 2);
        // Heading there again is stopped again.
        c.command(c.last_time().unwrap_or(0.0), [p0.psi, 55f64.to_radians()])?;
        let t0 = c.last_time().unwrap_or(0.0);
        for k in 0..20_000u32 {
            let s = c.tick(t0 + f64::from(k) / rate)?;
            if c.is_at_rest(s.t) {
                assert!(s.margins[Margin::Parallel] > hard[Margin::Parallel]);
                break;
            }
        }
        assert_eq!(c.kind(), MotionKind::SupervisorStop);
        assert_eq!(c.command_index(), 4);
    }
    Ok(())
}

#[test]
fn typed_errors_leave_the_controller_unchanged() -> Result<(), Error> {
    let mut c = online::<f64>()?;
    c.command(0.0, goal([15.0, 25.0]))?;
    c.tick(1.0)?;
    let before = c;
    assert!(matches!(
        c.command(1.5, [f64::NAN, 0.0]),
        Err(Error::Trajectory(
            parasils::traj::Error::NonFinitePosition { axis: 0, .. }
        ))
    ));
    assert!(matches!(
        c.command(1.5, [0.0, f64::INFINITY]),
        Err(Error::Trajectory(
            parasils::traj::Error::NonFinitePosition { axis: 1, .. }
        ))
    ));
    assert!(matches!(
        c.tick(f64::NAN),
        Err(Error::NonFiniteTime { value }) if value.is_nan()
    ));
    assert!(matches!(
        c.stop(f64::INFINITY),
        Err(Error::NonFiniteTime { .. })
    ));
    assert_eq!(
        c.tick(0.5).err(),
        Some(Error::TimeReversed { t: 0.5, last: 1.0 })
    );
    assert_eq!(
        c.command(0.999, goal([0.0, 0.0])).err(),
        Some(Error::TimeReversed {
            t: 0.999,
            last: 1.0
        })
    );
    assert_eq!(c, before);
    // Invalid limits and supervisor thresholds at construction.
    let bad = OnlineController::new(
        Controller::<f64>::paper(),
        TipTargets::paper(),
        Pose::paper_start(),
        [Limits::new(0.1, 0.0), Limits::paper()],
        Supervisor::default(),
    );
    assert!(matches!(
        bad,
        Err(Error::Trajectory(parasils::traj::Error::InvalidLimit {
            axis: 0,
            ..
        }))
    ));
    let mut supervisor = Supervisor::<f64>::default();
    supervisor.stop[Margin::Parallel] = 0.005; // below the hard 1e-2
    let bad = OnlineController::new(
        Controller::<f64>::paper(),
        TipTargets::paper(),
        Pose::paper_start(),
        [Limits::paper(); 2],
        supervisor,
    );
    assert_eq!(
        bad.err(),
        Some(Error::InvalidThreshold {
            what: "stop",
            margin: Margin::Parallel,
            value: 0.005,
            min: 0.01
        })
    );
    Ok(())
}

/// A stop at rest is a stop of zero duration; a command to where the
/// platform rests, a motion of zero duration; both count.
#[test]
fn command_index_counts_every_command_and_stop() -> Result<(), Error> {
    let mut c = online::<f32>()?;
    assert_eq!((c.command_index(), c.kind()), (0, MotionKind::Rest));
    assert!(c.is_at_rest(0.0));
    c.tick(0.0)?;
    c.stop(0.0)?;
    assert_eq!((c.command_index(), c.kind()), (0, MotionKind::Stop));
    assert!(c.is_at_rest(0.0));
    c.command(0.1, goal([0.0, 0.0]))?;
    assert_eq!((c.command_index(), c.kind()), (1, MotionKind::Command));
    assert!(c.is_at_rest(0.1));
    c.command(0.2, goal([1.0, 1.0]))?;
    assert!(!c.is_at_rest(0.2));
    assert!(!c.is_at_rest(f32::NAN));
    assert_eq!(c.command_index(), 2);
    assert_eq!(c.goal(), goal([1.0, 1.0]));
    assert_eq!(c.motion_start(), 0.2);
    Ok(())
}

/// The first tick, and the tick of every command, track module 1's margin
/// from the previous cycle: the full decomposition ran once, in `new`.
#[test]
fn no_cycle_takes_the_full_decomposition() -> Result<(), Error> {
    let mut c = online::<f32>()?;
    assert_eq!(c.margin_tracker().counts(), (1, 1));
    let r = run(&mut c, &STREAM, 20_000)?;
    assert_eq!(c.margin_tracker().counts(), (r.cycles.len() as u64 + 1, 1));
    let mut c = online::<f64>()?;
    let r = run(&mut c, &STREAM, 20_000)?;
    assert_eq!(c.margin_tracker().counts(), (r.cycles.len() as u64 + 1, 1));
    Ok(())
}

/// Rebasing the clock mid-motion changes nothing but the times: the states
/// are those of the same run.
#[test]
fn rebase_moves_the_clock_origin() -> Result<(), Error> {
    let mut a = online::<f64>()?;
    let mut b = online::<f64>()?;
    a.command(0.0, goal([15.0, 25.0]))?;
    b.command(0.0, goal([15.0, 25.0]))?;
    a.tick(1.0)?;
    b.tick(1.0)?;
    b.rebase(1.0)?;
    assert_eq!(b.motion_start(), -1.0);
    assert_eq!(b.last_time(), Some(0.0));
    for k in 1..=10u32 {
        let dt = f64::from(k) * 1e-3;
        let (x, y) = (a.tick(1.0 + dt)?, b.tick(dt)?);
        assert!((x.state.pose.theta - y.state.pose.theta).abs() < 1e-15);
        assert_eq!(x.command, y.command);
    }
    assert_eq!(
        b.tick(-0.5).err(),
        Some(Error::TimeReversed {
            t: -0.5,
            last: 0.01
        })
    );
    assert!(matches!(
        b.rebase(f64::NAN),
        Err(Error::NonFiniteTime { .. })
    ));
    Ok(())
}

/// The supervisor's stop in `f32`, as the firmware would run it.
#[test]
fn supervisor_stops_in_f32_too() -> Result<(), Error> {
    let mut c = online::<f32>()?;
    let hard = Margins::hard(c.controller());
    let p0 = Pose::<f32>::paper_start();
    c.command(0.0, [p0.psi, 55f32.to_radians()])?;
    let mut end = None;
    for k in 0..20_000u16 {
        let t = f32::from(k) / 1000.0;
        let s = c.tick(t)?;
        if c.is_at_rest(t) {
            end = Some(s);
            break;
        }
    }
    let end = end.ok_or(Error::NonFiniteTime { value: 0.0 })?;
    assert_eq!((end.kind, end.command), (MotionKind::SupervisorStop, 1));
    for m in Margin::ALL {
        assert!(end.margins[m] > hard[m], "{m}: {}", end.margins[m]);
    }
    assert!(end.margins[Margin::Parallel] > 0.8 * c.supervisor().stop[Margin::Parallel]);
    Ok(())
}
