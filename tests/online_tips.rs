//! The online controller with tips that move: every cycle puts both tips
//! exactly where they were last commanded while the platform turns, the
//! modules' rates carry the tips' own velocity, a tip that leaps, is not a
//! number or is out of reach is refused with the controller unchanged, and
//! with the follow mode on the camera keeps both tips in the picture.
//!
//! Where the tips are is checked by forward kinematics of each module's
//! joints at the cycle's pose (`Instrument::fk`, a map the controller does
//! not use), the rates against central differences of the joints, and
//! what the camera sees by a pinhole projection written here from the
//! platform's rotation matrix.

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{Controller, Pose, Side, TipMotion, TipTargets};
use parasils::traj::{Limits, Trapezoid};
use parasils::{Error, FollowParams, FollowPhase, MotionKind, OnlineController, Setpoint};

type Outcome = Result<(), Box<dyn core::error::Error>>;

const RATE_HZ: f64 = 1000.0;

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// The paper's controller at `P0` with the paper's tips, the right one
/// moved clear of the left shaft (as in `online_clearance.rs`).
fn paper_online() -> Result<OnlineController<f64>, Error> {
    let mut tips = TipTargets::paper();
    tips.right += Vector3::new(60.0, -40.0, 40.0);
    OnlineController::new(
        Controller::paper(),
        tips,
        Pose::paper_start(),
        [Limits::new(deg(10.0), deg(5.0)); 2],
        Default::default(),
    )
}

/// The largest distance (mm) of either module's tip, by forward kinematics
/// of its joints at the cycle's pose, from the tips the cycle commanded.
fn tip_error(online: &OnlineController<f64>, s: &Setpoint<f64>) -> Result<f64, Error> {
    let c = online.controller();
    let left = c.left.fk(&s.state.pose, &s.step.left.q)?;
    let right = c.right.fk(&s.state.pose, &s.step.right.q)?;
    Ok((left - s.tips.left)
        .norm()
        .max((right - s.tips.right).norm()))
}

/// Each tip on a circle of 4 mm about where it started (periods 2.0 and
/// 2.6 s, in two different planes), with its velocity and acceleration.
fn circling(start: &TipTargets<f64>, t: f64) -> [TipMotion<f64>; 2] {
    let circle = |centre: Vector3<f64>, a: Vector3<f64>, b: Vector3<f64>, period: f64| {
        let w = core::f64::consts::TAU / period;
        let (s, c) = (w * t).sin_cos();
        // Starts at the centre + 0: the circle goes through the start.
        TipMotion {
            position: centre + (a * (c - 1.0) + b * s) * 4.0,
            velocity: (-a * s + b * c) * 4.0 * w,
            acceleration: (-a * c - b * s) * 4.0 * w * w,
        }
    };
    [
        circle(start.left, Vector3::x(), Vector3::y(), 2.0),
        circle(start.right, Vector3::y(), Vector3::z(), 2.6),
    ]
}

#[test]
fn tips_that_move_are_exactly_where_commanded_while_the_platform_turns() -> Outcome {
    let mut online = paper_online()?;
    let start = *online.tips();
    let p0 = Pose::<f64>::paper_start();
    online.command(0.0, [p0.psi + deg(15.0), p0.theta + deg(25.0)])?;
    let mut cycles: Vec<Setpoint<f64>> = Vec::new();
    let mut worst = 0.0f64;
    for k in 0..4000u32 {
        let t = f64::from(k) / RATE_HZ;
        online.move_tips(t, circling(&start, t))?;
        let s = online.tick(t)?;
        worst = worst.max(tip_error(&online, &s)?);
        cycles.push(s);
    }
    assert!(worst < 1e-9, "a tip {worst} mm from where it was commanded");
    // The platform did turn meanwhile, and the tips did move.
    let last = cycles.last().ok_or("no cycle")?;
    assert_eq!(
        last.kind,
        MotionKind::Command,
        "{:?} {:?}",
        last.stop,
        last.margins
    );
    assert!(last.state.pose.psi - p0.psi > deg(5.0), "{:?}", last.state);
    let moved = cycles
        .iter()
        .map(|s| {
            (s.tips.left - start.left)
                .norm()
                .min((s.tips.right - start.right).norm())
        })
        .fold(0.0, f64::max);
    assert!(moved > 5.0, "the tips moved {moved} mm at most");
    // The modules' rates are the joints' derivatives (central differences,
    // O(h^2), about 2e-5 here, away from the platform's steps of
    // acceleration: the tips' own velocity is in them, not only the
    // platform's).
    let mut rate_error = 0.0f64;
    for w in cycles.windows(3) {
        let [a, b, c] = [&w[0], &w[1], &w[2]];
        if a.state.acceleration != c.state.acceleration {
            // The platform's acceleration steps here (a phase of its
            // trapezoid ends): the difference is first order.
            continue;
        }
        let h = c.t - a.t;
        for (qa, qb, qc) in [
            (&a.step.left, &b.step.left, &c.step.left),
            (&a.step.right, &b.step.right, &c.step.right),
        ] {
            for (pa, pb, pc) in [
                (qa.q.qs1, qb.q_dot.qs1, qc.q.qs1),
                (qa.q.qs2, qb.q_dot.qs2, qc.q.qs2),
                (qa.q.qs3, qb.q_dot.qs3, qc.q.qs3),
            ] {
                rate_error = rate_error.max(((pc - pa) / h - pb).abs());
            }
        }
    }
    // Rates of the order of 1 (rad/s, mm/s): a difference of 1e-4 would be
    // a tip's velocity left out (about 25 mm/s here).
    assert!(rate_error < 1e-4, "rates off by {rate_error}");
    Ok(())
}

#[test]
fn a_tip_that_leaps_is_not_finite_or_out_of_reach_is_refused() -> Outcome {
    let mut online = paper_online()?;
    online.command(0.0, [deg(20.0), deg(30.0)])?;
    online.tick(0.5)?;
    let before = online;
    let mut tips = *online.tips();
    // A leap of 1.5 mm in one call, with the default largest step of 1 mm.
    tips.right.x += 1.5;
    match online.set_tips(0.5, tips) {
        Err(Error::TipStep {
            side: Side::Right,
            step_mm,
            max_mm,
        }) => {
            assert!((step_mm - 1.5).abs() < 1e-12);
            assert_eq!(max_mm, parasils::MAX_TIP_STEP_MM);
        }
        other => return Err(format!("expected a tip step error, got {other:?}").into()),
    }
    assert_eq!(online, before);
    // The same move in two steps is accepted.
    let mut half = *online.tips();
    half.right.x += 0.75;
    online.set_tips(0.5, half)?;
    online.set_tips(0.5, tips)?;
    assert_eq!(online.tips().right, tips.right);
    let after = online.tick(0.501)?;
    assert!(tip_error(&online, &after)? < 1e-9);
    // A NaN velocity, named.
    let mut bad = *online.tip_motion();
    bad[1].velocity.y = f64::NAN;
    let before = online;
    match online.move_tips(0.502, bad) {
        Err(Error::Kinematics(parasils::kin::Error::NonFinite { what, .. })) => {
            assert_eq!(what, "tips.right.vy");
        }
        other => return Err(format!("expected a non-finite error, got {other:?}").into()),
    }
    assert_eq!(online, before);
    // A tip 400 mm up (inside the platform): no module reaches it.
    let mut far = online.with_max_tip_step(1000.0)?;
    let before = far;
    let mut up = *far.tips();
    up.left.z += 400.0;
    assert!(matches!(far.set_tips(0.502, up), Err(Error::Kinematics(_))));
    assert_eq!(far, before);
    // No largest step of 0, and the clock never runs backwards.
    assert!(online.with_max_tip_step(0.0).is_err());
    assert!(matches!(
        online.set_tips(0.1, *online.tips()),
        Err(Error::TimeReversed { .. })
    ));
    Ok(())
}

/// The follow demo's scene (`procedures/follow-demo.toml`): the platform at
/// `[15, 20, -500] mm, [-15, 10, -60] deg`, the endoscope 30 mm in, the tips
/// together, then through five targets at 10 mm/s.
const POSE: [f64; 6] = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];
const DEPTH_MM: f64 = 30.0;
const TOGETHER: [[f64; 3]; 2] = [[35.0, -15.0, -640.0], [5.0, 25.0, -640.0]];
const WANDERS: [[[f64; 3]; 2]; 5] = [
    [[55.0, -5.0, -650.0], [25.0, 35.0, -650.0]],
    [[55.0, -35.0, -660.0], [25.0, 5.0, -660.0]],
    [[15.0, -35.0, -640.0], [-15.0, 5.0, -640.0]],
    [[25.0, -5.0, -620.0], [-5.0, 30.0, -620.0]],
    [[35.0, -15.0, -640.0], [5.0, 25.0, -640.0]],
];

fn v(p: [f64; 3]) -> Vector3<f64> {
    Vector3::new(p[0], p[1], p[2])
}

/// What the test's own pinhole camera sees of `p` from the cycle `s`: the
/// straight scope at `E = P - depth Z'`, looking along `-Z'`, `u` along
/// `X'`, `v` along `Y'`, 70 deg across and 16:9 (the assumed camera).
/// `None` behind the eye.
fn pinhole(s: &Setpoint<f64>, p: &Vector3<f64>) -> Option<(f64, f64)> {
    let r = s.state.pose.rotation();
    let (x, y, z) = (r.column(0), r.column(1), r.column(2));
    let eye = s.state.pose.position() - z * DEPTH_MM;
    let d = p - eye;
    let ahead = -z.dot(&d);
    if ahead <= 0.0 {
        return None;
    }
    let half = deg(35.0).tan();
    Some((
        x.dot(&d) / ahead / half,
        y.dot(&d) / ahead / (half / (16.0 / 9.0)),
    ))
}

/// The angle (deg) between the view axis and the direction to `p`.
fn aim_deg(s: &Setpoint<f64>, p: &Vector3<f64>) -> f64 {
    let r = s.state.pose.rotation();
    let z = r.column(2).into_owned();
    let d = p - (s.state.pose.position() - z * DEPTH_MM);
    let view = -z;
    view.cross(&d).norm().atan2(view.dot(&d)).to_degrees()
}

#[test]
fn the_camera_follows_tips_that_wander_with_both_in_view() -> Outcome {
    let pose = Pose::new(
        POSE[0],
        POSE[1],
        POSE[2],
        deg(POSE[3]),
        deg(POSE[4]),
        deg(POSE[5]),
    );
    let tips = TipTargets {
        left: v(TOGETHER[0]),
        right: v(TOGETHER[1]),
    };
    let mut online = OnlineController::new(
        Controller::paper(),
        tips,
        pose,
        [Limits::new(deg(10.0), deg(5.0)); 2],
        Default::default(),
    )?
    .with_endoscope_depth(DEPTH_MM)?;
    // The camera aimed at the tips first ("camera on the tips").
    let mut k = 0u32;
    let time = |k: u32| f64::from(k) / RATE_HZ;
    online.command_look_at(0.0, (tips.left + tips.right) / 2.0)?;
    while !online.is_at_rest(time(k)) {
        online.tick(time(k))?;
        k += 1;
    }
    online.follow(time(k), FollowParams::assumed())?;
    assert_eq!(online.kind(), MotionKind::Follow);
    assert_eq!(online.follow_phase(), Some(FollowPhase::Idle));
    let (mut samples, mut in_view, mut central) = (0u32, 0u32, 0u32);
    let (mut settles, mut worst_aim, mut worst_tip) = (0u32, 0.0f64, 0.0f64);
    let (mut turning, mut recentrings) = (false, 0u32);
    let mut from = tips;
    for goal in WANDERS {
        let to = TipTargets {
            left: v(goal[0]),
            right: v(goal[1]),
        };
        // Both tips on straight lines, one trapezoid in the way (10 mm/s,
        // 20 mm/s^2, the procedure's defaults).
        let length = (to.left - from.left)
            .norm()
            .max((to.right - from.right).norm());
        let law = Trapezoid::new(0.0, 1.0, Limits::new(10.0 / length, 20.0 / length))?;
        let t0 = time(k);
        loop {
            let t = time(k);
            let s = law.sample(t - t0);
            let at = |a: Vector3<f64>, b: Vector3<f64>| TipMotion {
                position: a + (b - a) * s.position,
                velocity: (b - a) * s.velocity,
                acceleration: (b - a) * s.acceleration,
            };
            online.move_tips(t, [at(from.left, to.left), at(from.right, to.right)])?;
            let cycle = online.tick(t)?;
            assert_eq!(cycle.kind, MotionKind::Follow);
            assert!(cycle.stop.is_empty(), "the supervisor stopped at {t} s");
            worst_tip = worst_tip.max(tip_error(&online, &cycle)?);
            let seen = [cycle.tips.left, cycle.tips.right].map(|p| pinhole(&cycle, &p));
            samples += 1;
            let within = |limit: f64| {
                seen.iter()
                    .all(|x| x.is_some_and(|(u, v)| u.abs() <= limit && v.abs() <= limit))
            };
            in_view += u32::from(within(1.0));
            central += u32::from(within(0.8));
            let moving = cycle.state.velocity.psi != 0.0 || cycle.state.velocity.theta != 0.0;
            if turning && !moving {
                settles += 1;
                let midpoint = (cycle.tips.left + cycle.tips.right) / 2.0;
                worst_aim = worst_aim.max(aim_deg(&cycle, &midpoint));
            }
            if moving && !turning {
                recentrings += 1;
            }
            turning = moving;
            k += 1;
            let arrived = t - t0 >= law.duration();
            if arrived && online.follow_phase() == Some(FollowPhase::Idle) && !moving {
                break;
            }
            assert!(t - t0 < law.duration() + 60.0, "the camera never settled");
        }
        from = to;
    }
    let share = |n: u32| f64::from(n) / f64::from(samples);
    println!(
        "{samples} cycles: both in view {:.4} %, central 80 % {:.4} %, {settles} settles, \
         aim after settling {worst_aim:.4} deg at most, tips {worst_tip:.3e} mm at most",
        100.0 * share(in_view),
        100.0 * share(central)
    );
    // The figures `procedures/follow-demo.toml` meets in the simulation
    // (docs/model.md: 100 %, 100 %, 0.043 deg at most).
    assert_eq!(in_view, samples, "both tips in view in every cycle");
    assert!(share(central) >= 0.999, "central 80 %: {}", share(central));
    assert!(settles >= 3 && recentrings >= 3, "{settles} settles");
    assert!(worst_aim < 0.5, "aim error after settling {worst_aim} deg");
    assert!(worst_tip < 1e-9, "a tip {worst_tip} mm off");
    // A plain command ends the follow mode.
    let t = time(k);
    let goal = online.goal();
    online.command(t, goal)?;
    assert_eq!(
        (online.follow_phase(), online.kind()),
        (None, MotionKind::Command)
    );
    assert_eq!(online.tick(t)?.follow, None);
    Ok(())
}

#[test]
fn the_follow_mode_needs_the_endoscope_depth_and_valid_parameters() -> Outcome {
    let mut online = paper_online()?;
    assert_eq!(
        online.follow(0.0, FollowParams::assumed()),
        Err(Error::NoEndoscopeDepth)
    );
    let mut online = online.with_endoscope_depth(60.0)?;
    let bad = FollowParams {
        outer_radius: 0.05,
        ..FollowParams::assumed()
    };
    let before = online;
    assert!(matches!(online.follow(0.0, bad), Err(Error::Follow(_))));
    assert_eq!(online, before);
    // Taken over while turning: the law recentres at once on the tips'
    // midpoint from the moving state, within the controller's limits.
    let p0 = Pose::<f64>::paper_start();
    online.command(0.0, [p0.psi + deg(15.0), p0.theta + deg(25.0)])?;
    online.tick(0.0)?;
    online.tick(1.0)?;
    let fast = FollowParams {
        limits: Limits::new(deg(90.0), deg(90.0)),
        ..FollowParams::assumed()
    };
    online.follow(1.0, fast)?;
    assert_eq!(online.follow_phase(), Some(FollowPhase::Recentring));
    let law = online.follow_law().ok_or("no law")?;
    assert_eq!(law.params().limits, Limits::new(deg(10.0), deg(5.0)));
    let mut k = 1001u32;
    let mut s = online.tick(1.001)?;
    while online.follow_phase() != Some(FollowPhase::Idle) {
        k += 1;
        s = online.tick(f64::from(k) / RATE_HZ)?;
        assert!(k < 60_000, "never settled");
    }
    let tips = online.tips();
    let midpoint = (tips.left + tips.right) / 2.0;
    let aim = online
        .controller()
        .endoscope
        .camera
        .aim_error(&s.state.frame()?, 60.0, &midpoint);
    assert!(aim < 1e-3, "aim error {aim} rad");
    Ok(())
}
