//! One geometry per motion type, several timings: the timed motions, the
//! paths the optimal timing solves over and the jerk-limited double S all
//! reach the robot through `Geometry::at`, on the same straight line.

#![allow(clippy::float_cmp, reason = "exact ends are what these tests check")]

use parasils::geometry::{Geometry, Moving, Port, RobotState};
use parasils::kin::nalgebra::Vector3;
use parasils::kin::{Controller, MarginTracker, Pose, TipTargets};
use parasils::motions::{Insertion, Manipulation, Motion, Positioning, Turning};
use parasils::path::MotionPath;
use parasils::traj::{JerkLimits, Limits, State, Synchronization};

type Result<T = ()> = core::result::Result<T, Box<dyn core::error::Error>>;

const LINEAR: Limits<f64> = Limits::new(20.0, 20.0);

fn angular() -> Limits<f64> {
    Limits::new(10f64.to_radians(), 5f64.to_radians())
}

fn jerk() -> [JerkLimits<f64>; 2] {
    [
        JerkLimits::from_limits(LINEAR, 40.0),
        JerkLimits::from_limits(angular(), 10f64.to_radians()),
    ]
}

/// The controller, a start state 40 mm above the paper's with the endoscope
/// 20 mm in, and the tips there.
type Start = (Controller<f64>, RobotState<f64>, [Vector3<f64>; 2]);

fn start() -> Result<Start> {
    let c = Controller::paper();
    let tips = TipTargets::paper();
    let mut pose = Pose::paper_start();
    pose.z += 40.0;
    let state = RobotState::solved(&c, pose, &tips, 20.0)?;
    let at = c.step(
        &parasils::kin::PlatformState::at_rest(pose),
        &tips,
        &mut MarginTracker::new(),
    )?;
    let tip = |q, m: &parasils::kin::Instrument<f64>| at.frame.to_fixed(&m.fk_platform(q));
    Ok((
        c,
        state,
        [tip(&at.left.q, &c.left), tip(&at.right.q, &c.right)],
    ))
}

/// One geometry of each type, from `state`.
fn geometries(state: &RobotState<f64>, tips: [Vector3<f64>; 2]) -> [Geometry<f64>; 4] {
    let mut goal = state.pose;
    goal.x += 12.0;
    goal.z -= 30.0;
    goal.phi += 4f64.to_radians();
    [
        Geometry::positioning(state, goal),
        Geometry::insertion(state, Port::Left, 25.0),
        Geometry::manipulation(
            state,
            tips,
            [Some(tips[0] + Vector3::new(6.0, -4.0, -8.0)), None],
        ),
        Geometry::turning(
            state,
            [
                state.pose.psi + 12f64.to_radians(),
                state.pose.theta - 9f64.to_radians(),
            ],
            tips,
        ),
    ]
}

/// The trapezoid of each geometry, as a procedure plans it.
fn trapezoids(
    state: &RobotState<f64>,
    tips: [Vector3<f64>; 2],
    g: &[Geometry<f64>; 4],
) -> Result<[Motion<f64>; 4]> {
    let end = |g: &Geometry<f64>| g.along(1.0, 0.0, 0.0);
    let Moving::Pose(p) = end(&g[0]) else {
        return Err("not a pose".into());
    };
    let Moving::Tips(t) = end(&g[2]) else {
        return Err("not tips".into());
    };
    let Moving::Angles(a) = end(&g[3]) else {
        return Err("not angles".into());
    };
    Ok([
        Motion::Position(Positioning::new(
            state,
            Pose::from_array(p.map(|s| s.position)),
            LINEAR,
            angular(),
        )?),
        Motion::Insert(Insertion::new(state, Port::Left, 25.0, LINEAR)?),
        Motion::Manipulate(Manipulation::new(
            state,
            tips,
            [
                Some(Vector3::new(t[0].position, t[1].position, t[2].position)),
                None,
            ],
            LINEAR,
        )?),
        Motion::Reorient(Turning::new(
            state,
            a.map(|s| s.position),
            [angular(); 2],
            Synchronization::Phase,
            tips,
        )?),
    ])
}

/// The coordinates as one flat list.
fn flat(m: &Moving<f64>) -> Vec<State<f64>> {
    match m {
        Moving::Pose(s) | Moving::Tips(s) => s.to_vec(),
        Moving::Depth(_, s) => vec![*s],
        Moving::Angles(s) => s.to_vec(),
    }
}

/// Where `m` is along `g`'s line: the fraction of the largest displacement.
fn fraction(g: &Geometry<f64>, m: &Moving<f64>) -> f64 {
    let (a, b) = (flat(&g.along(0.0, 0.0, 0.0)), flat(&g.along(1.0, 0.0, 0.0)));
    let now = flat(m);
    let k = (0..a.len())
        .max_by(|&i, &j| {
            let di = (b[i].position - a[i].position).abs();
            let dj = (b[j].position - a[j].position).abs();
            di.total_cmp(&dj)
        })
        .unwrap_or(0);
    (now[k].position - a[k].position) / (b[k].position - a[k].position)
}

#[test]
fn the_trapezoid_from_rest_runs_on_the_line_the_path_describes() -> Result {
    let (c, state, tips) = start()?;
    let g = geometries(&state, tips);
    for (g, m) in g.iter().zip(trapezoids(&state, tips, &g)?) {
        assert_eq!(m.geometry(), g, "{:?}", g.motion_type());
        let path = MotionPath::new(&c, *g);
        let n = 40;
        for j in 0..=n {
            let t = m.duration() * f64::from(j) / f64::from(n);
            let now = m.moving_at(t);
            // The trapezoid's coordinates are the line's at some s ...
            let s = fraction(g, &now);
            let on_line = flat(&g.along(s, 0.0, 0.0));
            for (x, y) in flat(&now).iter().zip(&on_line) {
                assert!(
                    (x.position - y.position).abs() < 1e-9,
                    "{:?} at t = {t}: {} off the line {}",
                    g.motion_type(),
                    x.position,
                    y.position
                );
            }
            // ... and the robot the timed motion commands is the path's at
            // that s, moving at the same rates.
            let timed = m.sample(t);
            let a = flat(&now);
            let d = flat(&g.along(1.0, 1.0, 0.0));
            let k = (0..a.len())
                .max_by(|&i, &j| d[i].velocity.abs().total_cmp(&d[j].velocity.abs()))
                .unwrap_or(0);
            let (s_dot, s_ddot) = (
                a[k].velocity / d[k].velocity,
                a[k].acceleration / d[k].velocity,
            );
            let along = path.sample(s, s_dot, s_ddot);
            let (x, y) = (timed.platform, along.platform);
            assert!(
                (x.pose
                    .to_array()
                    .iter()
                    .zip(y.pose.to_array())
                    .all(|(a, b)| (a - b).abs() < 1e-9))
            );
            assert!((x.velocity.psi - y.velocity.psi).abs() < 1e-9);
            assert!((x.velocity.z - y.velocity.z).abs() < 1e-9);
        }
        // Both end on the target exactly.
        assert_eq!(
            m.sample(m.duration()),
            g.sample(1.0, 0.0, 0.0),
            "{:?}",
            g.motion_type()
        );
    }
    Ok(())
}

#[test]
fn the_double_s_keeps_every_coordinate_within_its_limits_and_its_jerk_bounded() -> Result {
    let (c, state, tips) = start()?;
    let [lj, aj] = jerk();
    for g in geometries(&state, tips) {
        let m = Motion::jerk_limited(g, lj, aj)?;
        let name = g.motion_type().name();
        assert!(m.moving_at(0.0).at_rest() && m.moving_at(m.duration()).at_rest());
        assert_eq!(m.sample(m.duration()), g.sample(1.0, 0.0, 0.0), "{name}");
        assert_eq!(m.sample(0.0), g.sample(0.0, 0.0, 0.0), "{name}");
        // Every quantity within its own limits (a tip's speed along its
        // line for type 3, each coordinate otherwise), and the slowest one
        // reaches at least one of them (the law is as fast as they allow).
        let groups: &[(usize, usize, JerkLimits<f64>)] = match g.motion_type().number() {
            1 => &[
                (0, 1, lj),
                (1, 1, lj),
                (2, 1, lj),
                (3, 1, aj),
                (4, 1, aj),
                (5, 1, aj),
            ],
            2 => &[(0, 1, lj)],
            3 => &[(0, 3, lj), (3, 3, lj)],
            _ => &[(0, 1, aj), (1, 1, aj)],
        };
        let norm = |x: &[State<f64>], f: fn(&State<f64>) -> f64| {
            x.iter().map(|a| f(a) * f(a)).sum::<f64>().sqrt()
        };
        let dt = 1e-3;
        let steps = (m.duration() / dt).ceil() as usize;
        let mut used = 0.0_f64;
        let mut previous: Option<Vec<State<f64>>> = None;
        let mut tracker = MarginTracker::new();
        for j in 0..=steps {
            let t = (j as f64 * dt).min(m.duration());
            let now = flat(&m.moving_at(t));
            for &(k, n, l) in groups {
                let x = &now[k..k + n];
                let v = norm(x, |a| a.velocity) / l.v_max;
                let a = norm(x, |a| a.acceleration) / l.a_max;
                assert!(
                    v <= 1.0 + 1e-9 && a <= 1.0 + 1e-9,
                    "{name} quantity {k} at {t}: {v} {a}"
                );
                used = used.max(v).max(a);
                if let Some(p) = &previous {
                    // The jerk: the change of acceleration over one step.
                    let change: f64 = x
                        .iter()
                        .zip(&p[k..k + n])
                        .map(|(a, b)| (a.acceleration - b.acceleration).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    let jerk = change / dt;
                    assert!(
                        jerk <= l.j_max * (1.0 + 1e-6),
                        "{name} quantity {k} at {t}: jerk {jerk}"
                    );
                }
            }
            previous = Some(now);
            let s = m.sample(t);
            c.step_commanded(&s.platform, &s.left, &s.right, &mut tracker)?;
        }
        assert!(used > 0.999, "{name}: the binding limit reached, {used}");
    }
    Ok(())
}

#[test]
fn the_double_s_of_a_turn_holds_both_tips() -> Result {
    let (c, state, tips) = start()?;
    let [lj, aj] = jerk();
    let g = geometries(&state, tips)[3];
    let m = Motion::jerk_limited(g, lj, aj)?;
    let mut tracker = MarginTracker::new();
    let mut drift = 0.0_f64;
    for j in 0..=200 {
        let s = m.sample(m.duration() * f64::from(j) / 200.0);
        let out = c.step_commanded(&s.platform, &s.left, &s.right, &mut tracker)?;
        let left = out.frame.to_fixed(&c.left.fk_platform(&out.left.q));
        let right = out.frame.to_fixed(&c.right.fk_platform(&out.right.q));
        drift = drift
            .max((left - tips[0]).norm())
            .max((right - tips[1]).norm());
    }
    assert!(drift < 1e-9, "{drift}");
    Ok(())
}

#[test]
fn a_still_geometry_takes_no_time_and_bad_limits_are_errors() -> Result {
    let (_, state, tips) = start()?;
    let [lj, aj] = jerk();
    let still = Motion::jerk_limited(Geometry::insertion(&state, Port::Right, 0.0), lj, aj)?;
    assert_eq!(still.duration(), 0.0);
    assert!(Geometry::insertion(&state, Port::Right, 0.0).is_still());
    assert!(Geometry::manipulation(&state, tips, [None, None]).is_still());
    let g = Geometry::insertion(&state, Port::Endoscope, 10.0);
    for bad in [-1.0, 0.0, f64::NAN, f64::INFINITY] {
        let e = Motion::jerk_limited(g, JerkLimits::new(20.0, 20.0, bad), aj);
        assert!(e.is_err(), "jerk {bad} accepted");
        let e = Motion::jerk_limited(g, lj, JerkLimits::new(bad, 1.0, 1.0));
        assert!(e.is_err(), "angular velocity {bad} accepted");
    }
    // Coordinates of another type leave the robot at its start.
    let other = Moving::Angles([State::rest(1.0); 2]);
    assert_eq!(g.at(&other), g.sample(0.0, 0.0, 0.0));
    Ok(())
}
