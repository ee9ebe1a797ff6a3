//! The online controller and forbidden regions: a sphere in the way of the
//! endoscope's tip during a turn stops the platform with the gap still at
//! or above the stop threshold, a retarget away from it is accepted, and
//! random retarget sequences towards random spheres near the path never go
//! below the threshold nor give a NaN.
//!
//! The regions here are the test's own ([`Spheres`]): the gap from a
//! capsule to a sphere in closed form, the distance from the centre to the
//! capsule's axis (projection clamped to the segment) minus both radii,
//! written independently of `parasils-anatomy` (whose `Anatomy` implements
//! the same trait and is tested in its crate) and of the kinematics'
//! segment kernel.
//!
//! The robot is the paper's with the right tip moved by `(60, -40, 40)` mm
//! (as in `online_clearance.rs`), thin bodies (shafts of 1 mm, the
//! endoscope of 4 mm, so that the pairs of bodies stay apart over the turns
//! and what stops the platform is the region), the endoscope 40 mm in, and
//! the assumed thresholds (warning 2.0, stop 0.5 mm).

use parasils::kin::nalgebra::Vector3;
use parasils::kin::{BodyGeometry, Capsule, Controller, PlatformState, Pose, TipTargets};
use parasils::supervisor::ClearanceThresholds;
use parasils::traj::Limits;
use parasils::{
    ClearanceWatch, Error, ForbiddenRegions, InBodyCapsules, MotionKind, NearestRegion,
    OnlineController, RegionQueryError, Setpoint,
};
use parasils_io::Rng;

const RATE_HZ: f64 = 1000.0;
const STOP_MM: f64 = 0.5;
const DEPTH_MM: f64 = 40.0;

/// Spheres `(centre, radius)`, mm, fixed frame.
struct Spheres(Vec<(Vector3<f64>, f64)>);

/// The distance from `p` to the segment `a`-`b`.
fn point_segment(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let s = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * s)).norm()
}

impl ForbiddenRegions<f64> for Spheres {
    fn nearest(
        &self,
        bodies: &InBodyCapsules<f64>,
    ) -> Result<Option<NearestRegion<f64>>, RegionQueryError> {
        let mut best: Option<NearestRegion<f64>> = None;
        for (region, (centre, radius)) in self.0.iter().enumerate() {
            for capsule in bodies.all().iter().flatten() {
                let gap = point_segment(centre, &capsule.axis.start, &capsule.axis.end)
                    - radius
                    - capsule.radius;
                if best.is_none_or(|b| gap < b.gap_mm) {
                    best = Some(NearestRegion {
                        region,
                        gap_mm: gap,
                    });
                }
            }
        }
        Ok(best)
    }
}

fn watch() -> ClearanceWatch<f64> {
    ClearanceWatch {
        bodies: BodyGeometry {
            instrument_diameter: 1.0,
            instrument_length: 400.0,
            endoscope_diameter: 4.0,
            endoscope_length: 400.0,
        },
        endoscope_depth: DEPTH_MM,
        thresholds: ClearanceThresholds {
            warn: 2.0,
            stop: STOP_MM,
        },
    }
}

fn online(limits_deg: [f64; 2]) -> Result<OnlineController<f64>, Error> {
    let mut tips = TipTargets::paper();
    tips.right += Vector3::new(60.0, -40.0, 40.0);
    OnlineController::new(
        Controller::paper(),
        tips,
        Pose::paper_start(),
        [Limits::new(limits_deg[0].to_radians(), limits_deg[1].to_radians()); 2],
        Default::default(),
    )?
    .with_clearance(watch())
}

/// `P0` turned by `[psi, theta]` deg.
fn turned(deg: [f64; 2]) -> [f64; 2] {
    let p0 = Pose::<f64>::paper_start();
    [p0.psi + deg[0].to_radians(), p0.theta + deg[1].to_radians()]
}

/// The endoscope's tip at the angles `[psi, theta]` (rad), `phi` and `P`
/// of `P0`: `P + R (0, 0, -depth)`.
fn endoscope_tip(angles: [f64; 2]) -> Vector3<f64> {
    let pose = Pose {
        psi: angles[0],
        theta: angles[1],
        ..Pose::paper_start()
    };
    pose.position() + pose.rotation() * Vector3::new(0.0, 0.0, -DEPTH_MM)
}

/// The cycle's region gap, checked finite.
fn region_gap(s: &Setpoint<f64>) -> Result<f64, String> {
    let n = s.region.ok_or(format!("no region gap at t = {}", s.t))?;
    if n.gap_mm.is_finite() {
        Ok(n.gap_mm)
    } else {
        Err(format!("gap {} at t = {}", n.gap_mm, s.t))
    }
}

/// Every number a cycle gives the drives is finite.
fn all_finite(s: &Setpoint<f64>) -> bool {
    let p = &s.state.pose;
    let (l, r) = (&s.step.left, &s.step.right);
    [p.psi, p.theta, s.state.velocity.psi, s.state.velocity.theta]
        .into_iter()
        .chain(s.step.module1.q.0)
        .chain(s.step.module1.q_dot.0)
        .chain([l.q.qs1, l.q.qs2, l.q.qs3, r.q.qs1, r.q.qs2, r.q.qs3])
        .chain([l.q_dot.qs1, l.q_dot.qs2, l.q_dot.qs3])
        .chain([r.q_dot.qs1, r.q_dot.qs2, r.q_dot.qs3])
        .all(f64::is_finite)
}

type Outcome = Result<(), Box<dyn core::error::Error>>;

#[test]
fn a_sphere_in_the_endoscopes_way_stops_the_turn_above_the_threshold() -> Outcome {
    let goal = turned([15.0, 25.0]);
    // A sphere of 3 mm where the endoscope's tip would be at 70 % of the
    // turn, and a far one (index 0) that never matters.
    let p0 = turned([0.0, 0.0]);
    let at = [0, 1].map(|i| p0[i] + 0.7 * (goal[i] - p0[i]));
    let regions = Spheres(vec![
        (Vector3::new(0.0, 0.0, 100.0), 1.0),
        (endoscope_tip(at), 3.0),
    ]);
    let mut c = online([10.0, 5.0])?;
    c.command(0.0, goal)?;
    let (mut k, mut lowest, mut stopped_at) = (0u32, f64::INFINITY, None);
    loop {
        let t = f64::from(k) / RATE_HZ;
        let s = c.tick_with(t, &regions)?;
        assert!(all_finite(&s));
        assert!(s.clearance_stop.is_empty(), "a pair stopped at {t} s");
        let gap = region_gap(&s)?;
        assert_eq!(s.region.map(|n| n.region), Some(1));
        assert!(gap >= STOP_MM, "t = {t}: gap {gap} mm");
        lowest = lowest.min(gap);
        if s.region_stop && stopped_at.is_none() {
            stopped_at = Some(t);
        }
        k += 1;
        if c.is_at_rest(t) {
            break;
        }
    }
    // The supervisor stopped it, short of the goal.
    assert_eq!(c.kind(), MotionKind::SupervisorStop);
    assert!(stopped_at.is_some());
    let end = c.state_at(f64::from(k) / RATE_HZ).pose;
    assert!((end.theta - goal[1]).abs() > 0.05);
    // Not far early either: within the warning band.
    assert!(lowest < 2.0, "lowest {lowest} mm");
    // A retarget away (back to 30 % of the way) is accepted and runs to
    // its goal.
    let t = f64::from(k) / RATE_HZ;
    let back = [0, 1].map(|i| p0[i] + 0.3 * (goal[i] - p0[i]));
    c.command(t, back)?;
    let mut last;
    loop {
        let t = f64::from(k) / RATE_HZ;
        let s = c.tick_with(t, &regions)?;
        assert!(!s.region_stop && s.stop.is_empty());
        last = region_gap(&s)?;
        assert!(last >= STOP_MM);
        k += 1;
        if c.is_at_rest(t) {
            break;
        }
    }
    assert_eq!(c.kind(), MotionKind::Command);
    assert_eq!(c.goal(), back);
    assert!(last > lowest + 1.0, "back at 30 % the gap is {last} mm");
    // The regions need the bodies' sizes.
    let mut bare = OnlineController::new(
        Controller::paper(),
        TipTargets::paper(),
        Pose::paper_start(),
        [Limits::paper(); 2],
        Default::default(),
    )?;
    assert_eq!(bare.tick_with(0.0, &regions), Err(Error::NoClearanceWatch));
    Ok(())
}

/// A region set whose query fails, or gives NaN.
struct Failing(bool);

impl ForbiddenRegions<f64> for Failing {
    fn nearest(
        &self,
        _: &InBodyCapsules<f64>,
    ) -> Result<Option<NearestRegion<f64>>, RegionQueryError> {
        if self.0 {
            Err(RegionQueryError { region: 3 })
        } else {
            Ok(Some(NearestRegion {
                region: 2,
                gap_mm: f64::NAN,
            }))
        }
    }
}

#[test]
fn a_region_that_cannot_be_measured_fails_the_tick_and_changes_nothing() -> Outcome {
    let mut c = online([10.0, 5.0])?;
    c.command(0.0, turned([5.0, 5.0]))?;
    c.tick(0.0)?;
    let before = c;
    assert_eq!(
        c.tick_with(0.001, &Failing(true)),
        Err(Error::Region(RegionQueryError { region: 3 }))
    );
    assert_eq!(c, before);
    assert_eq!(
        c.tick_with(0.001, &Failing(false)),
        Err(Error::Region(RegionQueryError { region: 2 }))
    );
    assert_eq!(c, before);
    // The in-body parts: the endoscope's is its first 40 mm from its tip.
    let s = c.tick(0.001)?;
    let inside = InBodyCapsules::of(
        &parasils::kin::Bodies::at(
            &watch().bodies,
            &PlatformState::at_rest(s.state.pose).frame()?,
            &c.controller().left,
            &s.step.left.q,
            &c.controller().right,
            &s.step.right.q,
            DEPTH_MM,
        )?,
        s.step.left.q.qs3,
        s.step.right.q.qs3,
        DEPTH_MM,
    );
    let e: Capsule<f64> = inside.endoscope.ok_or("no endoscope inside")?;
    assert!((e.axis.start - endoscope_tip([s.state.pose.psi, s.state.pose.theta])).norm() < 1e-9);
    assert!(((e.axis.end - e.axis.start).norm() - DEPTH_MM).abs() < 1e-9);
    assert!((e.axis.end - s.state.pose.position()).norm() < 1e-9);
    let left = inside.left.ok_or("no left shaft inside")?;
    assert!(((left.axis.end - left.axis.start).norm() - s.step.left.q.qs3).abs() < 1e-9);
    Ok(())
}

/// What a batch of random sequences saw.
#[derive(Debug, Default)]
struct Tally {
    sequences: u64,
    cycles: u64,
    region_stops: u64,
    lowest_mm: f64,
}

/// Sequence `seed`: limits drawn from 10 to 40 deg/s and 20 to 80 deg/s^2;
/// a first goal in the paper's range and a sphere of 1 to 6 mm near the
/// endoscope tip's way to it (its tip's position somewhere from 30 % to
/// 120 % of the way, moved up to 4 mm each way), drawn again until the
/// start is clear of it by the warning threshold; then one to four goals,
/// each after the one before at a random cycle of its motion (or at its
/// rest), at 1 kHz until rest. Every cycle's gap must be finite and at or
/// above the stop threshold, and every number of the cycle finite.
fn sequence(seed: u64, tally: &mut Tally) -> Result<(), Box<dyn core::error::Error>> {
    let mut rng = Rng::new(seed);
    let limits = [rng.uniform(10.0, 40.0), rng.uniform(20.0, 80.0)];
    let mut c = online(limits)?;
    let p0 = turned([0.0, 0.0]);
    let mut goal = turned([rng.uniform(-15.0, 15.0), rng.uniform(-25.0, 25.0)]);
    let regions = loop {
        let s = rng.uniform(0.3, 1.2);
        let at = [0, 1].map(|i| p0[i] + s * (goal[i] - p0[i]));
        let offset = Vector3::new(
            rng.uniform(-4.0, 4.0),
            rng.uniform(-4.0, 4.0),
            rng.uniform(-4.0, 4.0),
        );
        let regions = Spheres(vec![(endoscope_tip(at) + offset, rng.uniform(1.0, 6.0))]);
        let mut probe = c;
        if region_gap(&probe.tick_with(0.0, &regions)?)? > 2.0 {
            break regions;
        }
        goal = turned([rng.uniform(-15.0, 15.0), rng.uniform(-25.0, 25.0)]);
    };
    let goals = 1 + rng.below(4);
    let mut k = 0u32;
    for g in 0..goals {
        let t = f64::from(k) / RATE_HZ;
        if g > 0 {
            goal = turned([rng.uniform(-15.0, 15.0), rng.uniform(-25.0, 25.0)]);
        }
        c.command(t, goal)?;
        if std::env::var("DEBUG_SEED").is_ok_and(|v| v == seed.to_string()) {
            eprintln!("command at {t}: goal {goal:?}");
        }
        let stop_at = if g + 1 == goals {
            u32::MAX
        } else {
            let span = (c.motion_end() - t) * RATE_HZ;
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let cycles = (rng.unit() * span) as u32;
            k + cycles
        };
        loop {
            let t = f64::from(k) / RATE_HZ;
            let s = c.tick_with(t, &regions)?;
            tally.cycles += 1;
            assert!(all_finite(&s), "seed {seed}, t = {t}");
            if s.region_stop && s.kind != MotionKind::SupervisorStop {
                tally.region_stops += 1;
            }
            let gap = region_gap(&s)?;
            if std::env::var("DEBUG_SEED").is_ok_and(|v| v == seed.to_string()) && t > 1.5 {
                eprintln!(
                    "{t:.3} {gap:.6} {:?} stop {} vel {:.5} {:.5} acc {:.5} {:.5}",
                    s.kind,
                    s.region_stop,
                    s.state.velocity.psi,
                    s.state.velocity.theta,
                    s.state.acceleration.psi,
                    s.state.acceleration.theta
                );
            }
            assert!(gap >= STOP_MM, "seed {seed}, t = {t}: gap {gap} mm");
            tally.lowest_mm = tally.lowest_mm.min(gap);
            k += 1;
            if k >= stop_at || c.is_at_rest(t) {
                break;
            }
        }
    }
    tally.sequences += 1;
    Ok(())
}

fn sequences(n: u64) -> Result<Tally, Box<dyn core::error::Error>> {
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
fn random_commands_towards_random_spheres_never_go_below_the_stop_threshold() -> Outcome {
    let tally = sequences(200)?;
    // The sequences do run into the spheres: a good share is stopped.
    assert!(tally.region_stops * 5 > tally.sequences, "{tally:?}");
    assert!(tally.lowest_mm < STOP_MM + 0.2, "{tally:?}");
    Ok(())
}

/// The 10^5 sequences (`cargo test --test online_regions --
/// --ignored`, a few minutes).
#[test]
#[ignore = "10^5 sequences, minutes: run by hand"]
fn random_commands_towards_random_spheres_many() -> Outcome {
    let tally = sequences(100_000)?;
    println!("{tally:?}");
    Ok(())
}
