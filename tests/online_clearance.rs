//! The online controller watching the clearance between the instrument
//! shafts and the endoscope: a retarget heading into a collision is stopped
//! with every gap still at or above the stop threshold, and random retarget
//! sequences never go below it.
//!
//! The robot is the paper's with the assumed bodies (shafts of 5 mm, the
//! endoscope of 10 mm, at depth 0) and the assumed thresholds (warning 2.0,
//! stop 0.5 mm). The paper's default right tip (the mirror) puts the two
//! shafts' axes through one point (`docs/model.md`, *Clearance*), so the
//! right tip here is moved by `(60, -40, 40)` mm: then the shafts clear
//! each other and the endoscope by more than 1.2 mm over the paper's range
//! of `(psi, theta)`, and what the paper's goal runs into is the left
//! shaft against the endoscope (1.287 mm at `P0`, -1.373 mm at the goal).

use nalgebra::Vector3;
use parasils::kin::{BodyGeometry, Controller, Pose, TipTargets};
use parasils::supervisor::ClearanceThresholds;
use parasils::traj::Limits;
use parasils::{ClearanceWatch, Error, MotionKind, OnlineController, Real, Setpoint};
use parasils_io::Rng;
use parasils_kin::ClearancePair;

const RATE_HZ: f64 = 1000.0;
const STOP_MM: f64 = 0.5;

fn tips<T: Real>() -> TipTargets<T> {
    let mut tips = TipTargets::paper();
    tips.right += Vector3::new(T::lit(60.0), T::lit(-40.0), T::lit(40.0));
    tips
}

fn watch<T: Real>() -> ClearanceWatch<T> {
    ClearanceWatch {
        bodies: BodyGeometry::assumed(),
        endoscope_depth: T::zero(),
        thresholds: ClearanceThresholds {
            warn: T::lit(2.0),
            stop: T::lit(STOP_MM),
        },
    }
}

/// At rest at `P0` with `limits` (deg/s, deg/s^2), watching the clearance
/// or not.
fn online<T: Real>(limits_deg: [f64; 2], watched: bool) -> Result<OnlineController<T>, Error> {
    let deg = |x: f64| T::lit(x.to_radians());
    let c = OnlineController::new(
        Controller::paper(),
        tips(),
        Pose::paper_start(),
        [Limits::new(deg(limits_deg[0]), deg(limits_deg[1])); 2],
        Default::default(),
    )?;
    if watched {
        c.with_clearance(watch())
    } else {
        Ok(c)
    }
}

fn goal<T: Real>(deg: [f64; 2]) -> [T; 2] {
    let p0 = Pose::<f64>::paper_start();
    [
        T::lit(p0.psi + deg[0].to_radians()),
        T::lit(p0.theta + deg[1].to_radians()),
    ]
}

/// The smallest distance between the segments `a0 + s u` and `b0 + t v`
/// (`s, t` in `[0, 1]`) by nested ternary searches: the squared distance is
/// jointly convex, so its minimum over `t` is convex in `s`. Independent of
/// the kinematics' kernel.
fn ternary_distance(a0: Vector3<f64>, u: Vector3<f64>, b0: Vector3<f64>, v: Vector3<f64>) -> f64 {
    fn search(f: impl Fn(f64) -> f64) -> f64 {
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for _ in 0..100 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if f(m1) <= f(m2) { hi = m2 } else { lo = m1 }
        }
        f(0.5 * (lo + hi))
    }
    search(|s| search(|t| (a0 + u * s - b0 - v * t).norm()))
}

/// The three gaps of a setpoint computed apart from the controller: each
/// shaft from its tip (the instrument's FK) for 400 mm through its port
/// (the RCM placed by the pose), the endoscope from `P` for 400 mm along
/// `+Z'`, minus the radii 2.5 and 5 mm.
fn independent_gaps(c: &OnlineController<f64>, s: &Setpoint<f64>) -> [f64; 3] {
    let k = c.controller();
    let pose = &s.state.pose;
    let shaft = |m: &parasils::kin::Instrument<f64>, q| {
        let tip = m.fk(pose, q).expect("the setpoint's joints");
        let rcm = pose.rotation() * m.geometry().rcm + pose.position();
        (tip, (rcm - tip).normalize() * 400.0)
    };
    let (l0, lu) = shaft(&k.left, &s.step.left.q);
    let (r0, ru) = shaft(&k.right, &s.step.right.q);
    let e0 = pose.position();
    let eu = pose.rotation() * Vector3::new(0.0, 0.0, 400.0);
    [
        ternary_distance(l0, lu, r0, ru) - 5.0,
        ternary_distance(l0, lu, e0, eu) - 7.5,
        ternary_distance(r0, ru, e0, eu) - 7.5,
    ]
}

fn gaps<T: Real>(s: &Setpoint<T>) -> [f64; 3] {
    let c = s.clearance.expect("the controller watches the clearance");
    [
        c.left_right.gap,
        c.left_endoscope.gap,
        c.right_endoscope.gap,
    ]
    .map(|g| g.to_f64())
}

/// Ticks at 1 kHz from `t0` (s) until rest, at most `max` cycles.
fn until_rest<T: Real>(
    c: &mut OnlineController<T>,
    t0: f64,
    max: u32,
) -> Result<Vec<Setpoint<T>>, Error> {
    let mut out = Vec::new();
    for k in 0..max {
        let t = T::lit(t0 + f64::from(k) / RATE_HZ);
        out.push(c.tick(t)?);
        if c.is_at_rest(t) {
            break;
        }
    }
    Ok(out)
}

#[test]
fn gaps_match_an_independent_computation() -> Result<(), Error> {
    let mut c = online::<f64>([10.0, 5.0], true)?;
    c.command(0.0, goal([15.0, 25.0]))?;
    let run = until_rest(&mut c, 0.0, 20_000)?;
    for s in run.iter().step_by(97) {
        let (ours, truth) = (gaps(s), independent_gaps(&c, s));
        for (a, b) in ours.iter().zip(truth) {
            assert!((a - b).abs() < 1e-9, "t = {}: {ours:?} vs {truth:?}", s.t);
        }
    }
    Ok(())
}

#[test]
fn a_retarget_into_a_collision_is_stopped_above_the_threshold() -> Result<(), Error> {
    // Unwatched, the paper's goal takes the left shaft into the endoscope.
    let mut free = online::<f64>([10.0, 5.0], false)?.with_clearance(ClearanceWatch {
        thresholds: ClearanceThresholds {
            warn: -1e9,
            stop: -1e9,
        },
        ..watch()
    })?;
    free.command(0.0, goal([15.0, 25.0]))?;
    let unwatched = until_rest(&mut free, 0.0, 20_000)?;
    let lowest = unwatched
        .iter()
        .map(|s| gaps(s)[1])
        .fold(f64::INFINITY, f64::min);
    assert!(lowest < -1.3, "{lowest}");
    assert!(unwatched.iter().all(|s| s.clearance_stop.is_empty()));

    // Watched, the supervisor stops it, on that pair, above 0.5 mm.
    let mut c = online::<f64>([10.0, 5.0], true)?;
    c.command(0.0, goal([15.0, 25.0]))?;
    let run = until_rest(&mut c, 0.0, 20_000)?;
    let first = run
        .iter()
        .position(|s| !s.clearance_stop.is_empty())
        .expect("a clearance stop");
    assert_eq!(
        run[first].clearance_stop.first(),
        Some(ClearancePair::LeftEndoscope)
    );
    assert!(run[first].stop.is_empty(), "no margin is near its stop");
    assert_eq!(run[first + 1].kind, MotionKind::SupervisorStop);
    let end = run.last().expect("cycles");
    assert_eq!(c.kind(), MotionKind::SupervisorStop);
    assert_eq!(
        (end.state.velocity.psi, end.state.velocity.theta),
        (0.0, 0.0)
    );
    for s in &run {
        let g = independent_gaps(&c, s);
        assert!(g.iter().all(|&x| x >= STOP_MM), "t = {}: {g:?}", s.t);
    }
    // It rests near the threshold: the prediction is good, not merely
    // conservative.
    let at_rest = independent_gaps(&c, end)[1];
    assert!((STOP_MM..STOP_MM + 0.2).contains(&at_rest), "{at_rest}");
    // Warned before the stop: the gap passed 2 mm at P0 already below.
    assert!(
        run[first]
            .clearance_warnings
            .contains(ClearancePair::LeftEndoscope)
    );

    // Backing away is accepted and runs without a stop.
    let t = end.t + 0.5;
    c.command(t, goal([0.0, 0.0]))?;
    let back = until_rest(&mut c, t, 20_000)?;
    assert!(
        back.iter()
            .all(|s| s.clearance_stop.is_empty() && s.stop.is_empty())
    );
    assert_eq!(c.kind(), MotionKind::Command);
    Ok(())
}

/// Regression (random sequence 28699 of the full run): a command from a
/// rest just above the stop threshold, heading inwards, moved a cycle
/// before any rate showed it and ended 2e-6 mm below. Its own tick now
/// looks one cycle ahead, and the platform holds.
#[test]
fn a_command_inwards_from_a_rest_at_the_threshold_holds() -> Result<(), Error> {
    let mut c = online::<f64>([40.0, 80.0], true)?;
    c.command(0.0, goal([15.0, 25.0]))?;
    until_rest(&mut c, 0.0, 20_000)?;
    assert_eq!(c.kind(), MotionKind::SupervisorStop);
    for again in 1..=5 {
        let t = c.last_time().unwrap_or(0.0) + 0.01;
        c.command(t, goal([15.0, 25.0]))?;
        let run = until_rest(&mut c, t, 20_000)?;
        assert_eq!(c.kind(), MotionKind::SupervisorStop, "command {again}");
        for s in &run {
            assert!(
                gaps(s).iter().all(|&g| g >= STOP_MM),
                "command {again}, t = {}: {:?}",
                s.t,
                gaps(s)
            );
        }
    }
    Ok(())
}

/// Regression: sequence 28699 of the full run, a command during a
/// supervisor stop that was ending just above the threshold, ended 2e-6 mm
/// below it with an allowance of 10 % on the predicted fall.
#[test]
fn random_sequence_28699_stays_above_the_threshold() -> Result<(), Error> {
    let mut tally = Tally {
        lowest_mm: f64::INFINITY,
        ..Tally::default()
    };
    sequence(28_699, &mut tally)?;
    assert!(
        tally.clearance_stops > 0 && tally.lowest_mm >= STOP_MM,
        "{tally:?}"
    );
    Ok(())
}

#[test]
fn f32_stops_above_the_threshold_too() -> Result<(), Error> {
    let mut c = online::<f32>([10.0, 5.0], true)?;
    c.command(0.0, goal([15.0, 25.0]))?;
    let run = until_rest(&mut c, 0.0, 20_000)?;
    assert_eq!(c.kind(), MotionKind::SupervisorStop);
    // In f32 the rates and bends are differences of gaps rounded to about
    // 1e-4 mm at these coordinates (600 mm), so the bend is noise that
    // only ever stops earlier: above the threshold, not near it.
    let lowest = run.iter().map(|s| gaps(s)[1]).fold(f64::INFINITY, f64::min);
    assert!((STOP_MM..1.287).contains(&lowest), "{lowest}");
    Ok(())
}

#[test]
fn invalid_thresholds_and_sizes_are_typed_errors() -> Result<(), Error> {
    let c = online::<f64>([10.0, 5.0], false)?;
    let bad = |warn: f64, stop: f64| ClearanceWatch {
        thresholds: ClearanceThresholds { warn, stop },
        ..watch()
    };
    assert!(matches!(
        c.with_clearance(bad(1.0, 2.0)),
        Err(Error::InvalidClearanceThreshold {
            what: "warning",
            ..
        })
    ));
    assert!(matches!(
        c.with_clearance(bad(1.0, f64::NAN)),
        Err(Error::InvalidClearanceThreshold { what: "stop", .. })
    ));
    let mut sizes = watch();
    sizes.bodies.instrument_diameter = -1.0;
    assert!(matches!(c.with_clearance(sizes), Err(Error::Kinematics(_))));
    let mut depth = watch();
    depth.endoscope_depth = f64::INFINITY;
    assert!(matches!(c.with_clearance(depth), Err(Error::Kinematics(_))));
    Ok(())
}

#[test]
fn the_prediction_is_the_documented_one() {
    let th = ClearanceThresholds {
        warn: 2.0,
        stop: 0.5,
    };
    let check = |x: f64, rate: f64, bend: f64| {
        let v = th.check_ahead(
            &[x, 5.0, 5.0],
            &[rate, 0.0, 0.0],
            &[bend, 0.0, 0.0],
            0.5,
            1e-3,
        );
        assert!(v.stop.len() <= 1 && v.warnings.len() <= 1);
        (
            v.warnings.contains(ClearancePair::LeftRight),
            v.stop.contains(ClearancePair::LeftRight),
        )
    };
    // L = 1.5 ms + (0.5 s + 1 ms) / 2 = 0.252 s; falling at 1 mm/s the
    // predicted fall is 1.25 * 0.252 = 0.315 mm.
    assert_eq!(check(0.816, -1.0, 0.0), (true, false));
    assert_eq!(check(0.814, -1.0, 0.0), (true, true));
    // A bend of -2 mm/s^2 adds 1.25 * 2 * 0.252^2 / 2 = 0.0794 mm.
    assert_eq!(check(0.896, -1.0, -2.0), (true, false));
    assert_eq!(check(0.893, -1.0, -2.0), (true, true));
    // A positive bend counts for nothing; a gap that grows demands nothing,
    // however low.
    assert_eq!(check(0.814, -1.0, 5.0), (true, true));
    assert_eq!(check(0.1, 1.0, -100.0), (true, false));
    assert_eq!(check(3.0, -1.0, 0.0), (false, false));
    // NaN demands a stop.
    for (x, rate, bend) in [
        (f64::NAN, 0.0, 0.0),
        (1.0, f64::NAN, 0.0),
        (1.0, 0.0, f64::NAN),
    ] {
        assert!(check(x, rate, bend).1, "{x} {rate} {bend}");
    }
}

/// What a batch of random retarget sequences saw.
#[derive(Debug, Default)]
struct Tally {
    sequences: u64,
    cycles: u64,
    clearance_stops: u64,
    lowest_mm: f64,
}

/// Sequence `seed`: limits drawn from 10 to 40 deg/s and 20 to 80 deg/s^2,
/// one to four goals drawn in the paper's range (`psi` within 15 deg and
/// `theta` within 25 deg of `P0`), each after the one before at a random
/// cycle of its motion (or at its rest), run at 1 kHz until rest. Every
/// cycle's gaps must be finite and at or above the stop threshold.
fn sequence(seed: u64, tally: &mut Tally) -> Result<(), Error> {
    let mut rng = Rng::new(seed);
    let limits = [rng.uniform(10.0, 40.0), rng.uniform(20.0, 80.0)];
    let mut c = online::<f64>(limits, true)?;
    let goals = 1 + rng.below(4);
    let mut k = 0u32;
    for g in 0..goals {
        let t = f64::from(k) / RATE_HZ;
        c.command(
            t,
            goal([rng.uniform(-15.0, 15.0), rng.uniform(-25.0, 25.0)]),
        )?;
        let stop_at = if g + 1 == goals {
            u32::MAX
        } else {
            let span = (c.motion_end() - t) * RATE_HZ;
            k + (rng.unit() * span) as u32
        };
        loop {
            let t = f64::from(k) / RATE_HZ;
            let s = c.tick(t)?;
            tally.cycles += 1;
            if !s.clearance_stop.is_empty() && s.kind != MotionKind::SupervisorStop {
                tally.clearance_stops += 1;
            }
            for x in gaps(&s) {
                assert!(x.is_finite(), "seed {seed}, t = {t}: {x}");
                assert!(x >= STOP_MM, "seed {seed}, t = {t}: gap {x} mm");
                tally.lowest_mm = tally.lowest_mm.min(x);
            }
            k += 1;
            if k >= stop_at || c.is_at_rest(t) {
                break;
            }
        }
    }
    tally.sequences += 1;
    Ok(())
}

fn sequences(n: u64) -> Result<Tally, Error> {
    let mut tally = Tally {
        lowest_mm: f64::INFINITY,
        ..Tally::default()
    };
    for seed in 0..n {
        sequence(seed, &mut tally)?;
    }
    Ok(tally)
}

#[test]
fn random_retarget_sequences_never_go_below_the_stop_threshold() -> Result<(), Error> {
    let tally = sequences(300)?;
    // The sequences do run into the threshold: a good share is stopped.
    assert!(tally.clearance_stops * 10 > tally.sequences, "{tally:?}");
    assert!(tally.lowest_mm < STOP_MM + 0.2, "{tally:?}");
    Ok(())
}

/// The full 10^5 sequences (`cargo test --test online_clearance --
/// --ignored`, a few minutes): the target, reported in
/// `BENCHMARKS.md`.
#[test]
#[ignore = "10^5 sequences, minutes: run by hand (see BENCHMARKS.md)"]
fn random_retarget_sequences_full() -> Result<(), Error> {
    let tally = sequences(100_000)?;
    println!("{tally:?}");
    Ok(())
}
