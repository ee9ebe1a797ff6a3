//! The clearance columns against an independent computation, the robot
//! file's `[bodies]`, and the supervisor's clearance stop.
//!
//! The independent computation: each shaft is the segment from its tip
//! (the record's) through its port (`P + R rcm`, with `R` built here from
//! the Euler angles) on for the shaft's length, the endoscope the segment
//! from `P + R (0, 0, -depth)` along `+Z'`; the distance of two segments is
//! the minimum over the first of the distance from its point to the second
//! (a point-segment projection), a convex function of the parameter,
//! minimised by ternary search to 1e-12. None of it calls the kernel.

use nalgebra::{Matrix3, Vector3};
use parasils_sim::robot_file::{parse_robot, robot_to_toml_string};
use parasils_sim::{
    ClearanceRecord, CommandKind, Input, Record, Retarget, RobotSource, Scenario, Simulation,
    SimulationError, TimingKind, procedure,
};

type V = Vector3<f64>;

/// `R = R_X(psi) R_Y(theta) R_Z(phi)`, written out.
fn rotation(psi: f64, theta: f64, phi: f64) -> Matrix3<f64> {
    let (sx, cx) = psi.sin_cos();
    let (sy, cy) = theta.sin_cos();
    let (sz, cz) = phi.sin_cos();
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx);
    let ry = Matrix3::new(cy, 0.0, sy, 0.0, 1.0, 0.0, -sy, 0.0, cy);
    let rz = Matrix3::new(cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0);
    rx * ry * rz
}

fn point_segment(p: &V, a: &V, b: &V) -> f64 {
    let d = b - a;
    let s = if d.norm_squared() > 0.0 {
        ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * s)).norm()
}

fn segment_segment(a: (V, V), b: (V, V)) -> f64 {
    let f = |s: f64| point_segment(&(a.0 + (a.1 - a.0) * s), &b.0, &b.1);
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0))
}

/// The three gaps of `r` with the endoscope at `depth`, sizes
/// `[instrument diameter, length, endoscope diameter, length]`.
fn independent(r: &Record, depth: f64, sizes: [f64; 4]) -> [f64; 3] {
    let [id, il, ed, el] = sizes;
    let p = V::new(r.pose[0], r.pose[1], r.pose[2]);
    let rot = rotation(r.pose[3], r.pose[4], r.pose[5]);
    let shaft = |tip: V, rcm_x: f64| {
        let port = p + rot * V::new(rcm_x, 0.0, 0.0);
        let u = (port - tip).normalize();
        (tip, tip + u * il)
    };
    let left = shaft(r.left.tip, -10.0);
    let right = shaft(r.right.tip, 10.0);
    let endo = (
        p + rot * V::new(0.0, 0.0, -depth),
        p + rot * V::new(0.0, 0.0, el - depth),
    );
    [
        segment_segment(left, right) - id,
        segment_segment(left, endo) - 0.5 * (id + ed),
        segment_segment(right, endo) - 0.5 * (id + ed),
    ]
}

fn gaps(c: &ClearanceRecord) -> [f64; 3] {
    [c.left_right, c.left_endoscope, c.right_endoscope]
}

fn records(sim: &Simulation) -> Vec<Record> {
    sim.samples().map(|r| r.expect("runs")).collect()
}

#[test]
fn the_paper_runs_gaps_match_the_independent_computation() {
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    let rs = records(&sim);
    for r in rs.iter().step_by(150) {
        let want = independent(r, 0.0, [5.0, 400.0, 10.0, 400.0]);
        let got = gaps(&r.clearance);
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 1e-9,
                "t = {}: {got:?} vs {want:?}",
                r.t
            );
        }
        assert_eq!(
            r.clearance.min(),
            got.iter().copied().fold(f64::INFINITY, f64::min)
        );
    }
}

/// The paper's scenario with the right tip the left one's exact mirror
/// image (the default before it was moved).
fn mirrored() -> Scenario {
    Scenario {
        tip_right_mm: Some(parasils::kin::TipTargets::<f64>::mirrored().right.into()),
        ..Scenario::paper()
    }
}

/// The right tip at the left one's mirror across the platform's `Y'Z'`
/// plane at the start pose puts the right shaft on the left one's mirror
/// image: the two axes meet on the mirror plane, so the shafts overlap by
/// both radii (the gap is -5 mm with 5 mm shafts) at `t = 0`. As the
/// platform turns the tips stay put and the mirror relation is lost; the gap
/// stays negative over the whole paper's run.
#[test]
fn the_mirror_right_tip_makes_the_shafts_intersect() {
    let sim = Simulation::new(mirrored()).expect("valid");
    let rs = records(&sim);
    let first = &rs[0];
    assert!(
        (first.clearance.left_right + 5.0).abs() < 1e-9,
        "{:?}",
        first.clearance
    );
    let worst_last = rs
        .iter()
        .map(|r| r.clearance.left_right)
        .fold(f64::MIN, f64::max);
    assert!(worst_last < 0.0, "largest left-right gap {worst_last}");
    // And the paper's run with the assumed bodies also has the left shaft
    // touching the endoscope above the ports by the end of the turn.
    let left_endo = rs
        .iter()
        .map(|r| r.clearance.left_endoscope)
        .fold(f64::MAX, f64::min);
    assert!(left_endo < 0.0, "{left_endo}");
}

/// The check values of `docs/model.md`, *Clearance*: each pair's gap at
/// the start, its smallest over the run and at the end, to the printed
/// three decimals.
#[test]
fn the_paper_runs_gaps_are_the_documented_ones() {
    // The default right tip: the left-right pair clears by more than the
    // assumed 2 mm warning over the whole turn, and so does the right
    // shaft against the endoscope; the left shaft still meets the
    // endoscope (the left module's motion is the paper's).
    documented_gaps(
        Scenario::paper(),
        [
            [6.932, 2.723, 2.723],
            [1.287, -1.373, -1.373],
            [2.315, 2.315, 2.370],
        ],
    );
    // The mirror.
    documented_gaps(
        mirrored(),
        [
            [-5.000, -5.000, -3.939],
            [1.287, -1.373, -1.373],
            [1.287, 1.287, 2.475],
        ],
    );
}

/// Each pair's gap at the start, its smallest and at the end, to the
/// printed three decimals.
fn documented_gaps(scenario: Scenario, expected: [[f64; 3]; 3]) {
    let sim = Simulation::new(scenario).expect("valid");
    let rs = records(&sim);
    let last = rs.last().expect("records");
    for (k, want) in expected.iter().enumerate() {
        let of = |r: &Record| gaps(&r.clearance)[k];
        let min = rs.iter().map(of).fold(f64::INFINITY, f64::min);
        let got = [of(&rs[0]), min, of(last)];
        for i in 0..3 {
            assert!(
                (got[i] - want[i]).abs() < 5e-4,
                "pair {k}: {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn a_procedures_gaps_match_with_the_endoscope_inserted() {
    let scenario = procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))
    .expect("the demo loads");
    let sim = Simulation::new(scenario).expect("valid");
    let rs = records(&sim);
    let mut deepest: f64 = 0.0;
    for r in rs.iter().step_by(97) {
        deepest = deepest.max(r.endoscope_depth);
        let want = independent(r, r.endoscope_depth, [5.0, 400.0, 10.0, 400.0]);
        let got = gaps(&r.clearance);
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 1e-9,
                "t = {}: {got:?} vs {want:?}",
                r.t
            );
        }
    }
    assert!(deepest > 10.0, "the endoscope goes in: {deepest}");
}

const BODIES: &str = "\n[bodies]\ninstrument_diameter_mm = 3.0\nendoscope_diameter_mm = 8.0\n";

fn default_robot_text() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../robots/default.toml"
    ))
    .expect("robots/default.toml")
}

#[test]
fn bodies_from_the_robot_file_shift_the_gaps_by_the_radii() {
    let robot = parse_robot(&(default_robot_text() + BODIES)).expect("valid");
    assert_eq!(robot.bodies.instrument_diameter, 3.0);
    assert_eq!(robot.bodies.instrument_length, 400.0); // not given: assumed
    assert_eq!(robot.bodies.endoscope_diameter, 8.0);
    // Written and read back.
    let text = robot_to_toml_string(&robot).expect("writes");
    assert_eq!(parse_robot(&text).expect("reads back"), robot);
    // A thinner shaft: 1 mm more on each side of each shaft pair, the
    // endoscope 1 mm thinner on its side.
    let base = Simulation::new(Scenario::paper()).expect("valid");
    let thin = Simulation::new(Scenario {
        bodies: robot.bodies,
        ..Scenario::paper()
    })
    .expect("valid");
    for (a, b) in records(&base).iter().zip(records(&thin)).step_by(500) {
        assert!((b.clearance.left_right - a.clearance.left_right - 2.0).abs() < 1e-12);
        assert!((b.clearance.left_endoscope - a.clearance.left_endoscope - 2.0).abs() < 1e-12);
        assert!((b.clearance.right_endoscope - a.clearance.right_endoscope - 2.0).abs() < 1e-12);
    }
}

#[test]
fn bad_bodies_are_refused_with_their_key() {
    for bad in [
        "instrument_diameter_mm = -1.0",
        "endoscope_length_mm = nan",
        "shaft_mm = 3.0",
    ] {
        let text = default_robot_text() + "\n[bodies]\n" + bad + "\n";
        let e = parse_robot(&text).expect_err(bad);
        let key = bad.split(' ').next().unwrap_or_default();
        assert!(e.to_string().contains(key), "{bad}: {e}");
    }
}

#[test]
fn the_clearance_stop_fails_the_paper_run_naming_the_pair() {
    let robot = parse_robot(&(default_robot_text() + "\n[supervisor]\nclearance_stop_mm = 0.5\n"))
        .expect("valid");
    assert_eq!(robot.supervisor.clearance(), Some([2.0, 0.5]));
    let sim = Simulation::new(Scenario {
        supervisor: robot.supervisor,
        ..mirrored()
    })
    .expect("planned");
    let e = sim
        .samples()
        .find_map(Result::err)
        .expect("the shafts overlap at once");
    match &e {
        SimulationError::Clearance {
            t,
            sample,
            pair,
            gap_mm,
            stop_mm,
            depth_mm,
        } => {
            assert_eq!((*t, *sample), (0.0, Some(0)));
            assert_eq!(*pair, parasils::kin::ClearancePair::LeftRight);
            assert!((gap_mm + 5.0).abs() < 1e-9);
            assert_eq!(*stop_mm, 0.5);
            // The axes meet inside the patient, below the ports.
            assert!(*depth_mm > 0.0 && *depth_mm < 100.0, "{depth_mm}");
        }
        other => panic!("{other}"),
    }
    let text = e.to_string();
    assert!(
        text.starts_with("at t = 0.000 s: clearance left shaft - right shaft = -5.000 mm"),
        "{text}"
    );
    // Without the key the same run is not supervised on clearance.
    assert!(
        Simulation::new(mirrored())
            .expect("valid")
            .samples()
            .all(|r| r.is_ok())
    );
}

#[test]
fn a_clearance_stop_in_a_procedure_fails_before_output_naming_the_motion() {
    let mut scenario = procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))
    .expect("the demo loads");
    scenario.supervisor.clearance_stop_mm = Some(0.5);
    let e = Simulation::new(scenario).expect_err("checked while planned");
    let SimulationError::Motion { error, .. } = &e else {
        panic!("{e}")
    };
    assert!(matches!(**error, SimulationError::Clearance { .. }), "{e}");
    assert!(e.to_string().contains("clearance"), "{e}");
}

#[test]
fn a_warning_below_the_stop_is_refused() {
    let text =
        default_robot_text() + "\n[supervisor]\nclearance_warn_mm = 0.2\nclearance_stop_mm = 0.5\n";
    let e = parse_robot(&text).expect_err("warn < stop");
    assert!(e.to_string().contains("clearance"), "{e}");
}

#[test]
fn the_check_gives_each_motions_smallest_sampled_gaps() {
    let scenario = procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))
    .expect("the demo loads");
    let sim = Simulation::new(scenario).expect("valid");
    let check = sim.procedure_check().expect("a procedure is checked");
    let rs = records(&sim);
    for (k, m) in check.motions.iter().enumerate() {
        let mine: Vec<&Record> = rs.iter().filter(|r| r.motion as usize == k).collect();
        assert!(!mine.is_empty());
        for pair in 0..3 {
            let min = mine
                .iter()
                .map(|r| gaps(&r.clearance)[pair])
                .fold(f64::INFINITY, f64::min);
            assert_eq!(gaps(&m.clearance_mm)[pair], min, "motion {k}, pair {pair}");
        }
    }
}

/// An online run (the paper's turn, then the same goal commanded again at
/// 0.5 s) with the right tip moved by `(60, -40, 40)` mm from the mirror, so
/// that the shafts clear each other: what the turn runs into is the left
/// shaft against the endoscope (1.287 mm at `P0`, -1.373 mm at the goal).
fn online_run(clearance_stop: Option<f64>) -> Vec<Record> {
    let mut robot = parse_robot(&default_robot_text()).expect("valid");
    robot.supervisor.clearance_stop_mm = clearance_stop;
    let right = parasils::kin::TipTargets::<f64>::paper().right + V::new(60.0, -40.0, 40.0);
    let scenario = Input {
        tip_right_mm: Some([right.x, right.y, right.z]),
        robot: Some(RobotSource::Loaded(Box::new(robot))),
        retarget: Some(vec![Retarget {
            t_s: 0.5,
            psi_deg: 15.0,
            theta_deg: 25.0,
        }]),
        ..Input::default()
    }
    .resolve()
    .expect("an online run");
    records(&Simulation::new(scenario).expect("planned"))
}

#[test]
fn an_online_run_stops_ahead_of_the_clearance_stop_threshold() {
    // Unsupervised, the left shaft runs into the endoscope.
    let free = online_run(None);
    let lowest = free
        .iter()
        .map(|r| r.clearance.left_endoscope)
        .fold(f64::INFINITY, f64::min);
    assert!(lowest < -1.3, "{lowest}");
    assert!(free.iter().all(|r| r.kind != CommandKind::SupervisorStop));
    // With the robot file's threshold, the online controller stops it, and
    // every gap (computed apart from the kernel) stays at or above 0.5 mm.
    let held = online_run(Some(0.5));
    assert!(held.iter().any(|r| r.kind == CommandKind::SupervisorStop));
    let sizes = [5.0, 400.0, 10.0, 400.0];
    for r in held.iter().step_by(7).chain(held.last()) {
        let g = independent(r, 0.0, sizes);
        assert!(g.iter().all(|&x| x >= 0.5), "t = {}: {g:?}", r.t);
        assert!((gaps(&r.clearance)[1] - g[1]).abs() < 1e-9);
    }
    let end = held.last().expect("records").clearance.left_endoscope;
    assert!((0.5..0.7).contains(&end), "{end}");
}

/// The paper's turn with the right tip moved as in [`online_run`], timed
/// `timing`, with the robot file's clearance stop threshold or without.
fn turn(timing: TimingKind, clearance_stop: Option<f64>) -> Simulation {
    let mut robot = parse_robot(&default_robot_text()).expect("valid");
    robot.supervisor.clearance_stop_mm = clearance_stop;
    let right = parasils::kin::TipTargets::<f64>::paper().right + V::new(60.0, -40.0, 40.0);
    let scenario = Input {
        tip_right_mm: Some([right.x, right.y, right.z]),
        robot: Some(RobotSource::Loaded(Box::new(robot))),
        timing: Some(timing),
        ..Input::default()
    }
    .resolve()
    .expect("a planned turn");
    Simulation::new(scenario).expect("planned")
}

/// The gaps along the turn's path computed once from its geometry alone:
/// the platform at `s` of the straight line from the start to the goal in
/// `(psi, theta)`, `P` and `phi` fixed, the tips held; no timing enters.
/// Returns the smallest left shaft - endoscope gap over 20001 points.
fn path_minimum(start: &Record, goal: &Record) -> f64 {
    (0..=20_000)
        .map(|i| {
            let s = f64::from(i) / 20_000.0;
            let mut r = *start;
            for k in 3..5 {
                r.pose[k] = start.pose[k] + s * (goal.pose[k] - start.pose[k]);
            }
            independent(&r, 0.0, [5.0, 400.0, 10.0, 400.0])[1]
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn the_optimal_timing_sees_the_gaps_of_the_same_geometry() {
    let optimal = records(&turn(TimingKind::Optimal, None));
    let trapezoid = records(&turn(TimingKind::Trapezoid, None));
    // Faster, but over the same path.
    assert!(optimal.last().expect("records").t < trapezoid.last().expect("records").t);
    // Every sample's gaps are those of its pose and tips alone: the
    // independent computation takes no rate.
    for r in optimal.iter().step_by(11) {
        let g = independent(r, 0.0, [5.0, 400.0, 10.0, 400.0]);
        for (a, b) in gaps(&r.clearance).iter().zip(g) {
            assert!((a - b).abs() < 1e-9, "t = {}: {a} vs {b}", r.t);
        }
    }
    // So the path's smallest gap, found once from the geometry, is what
    // both timings' samples reach (to within their sampling).
    let once = path_minimum(&optimal[0], optimal.last().expect("records"));
    for run in [&optimal, &trapezoid] {
        let lowest = run
            .iter()
            .map(|r| r.clearance.left_endoscope)
            .fold(f64::INFINITY, f64::min);
        assert!(
            lowest >= once - 1e-9 && lowest < once + 1e-6,
            "{lowest} vs {once}"
        );
    }
}

#[test]
fn the_optimal_timing_is_checked_against_the_clearance_stop() {
    let fail = |timing| {
        let sim = turn(timing, Some(0.5));
        let e = sim
            .samples()
            .find_map(Result::err)
            .expect("the turn runs in");
        match e {
            SimulationError::Clearance {
                t, pair, gap_mm, ..
            } => {
                assert_eq!(pair, parasils::kin::ClearancePair::LeftEndoscope);
                assert!(gap_mm < 0.5);
                // The record before is above the threshold.
                let before = sim
                    .samples()
                    .map_while(Result::ok)
                    .last()
                    .expect("samples before");
                assert!(before.clearance.left_endoscope >= 0.5);
                (t, before.pose[3], before.pose[4])
            }
            other => panic!("{other}"),
        }
    };
    let (t_opt, psi_opt, theta_opt) = fail(TimingKind::Optimal);
    let (t_trap, psi_trap, theta_trap) = fail(TimingKind::Trapezoid);
    // Earlier in time, at the same place of the path (to within a sample's
    // travel, well under 0.01 deg).
    assert!(t_opt < t_trap);
    assert!((psi_opt - psi_trap).abs() < 2e-4 && (theta_opt - theta_trap).abs() < 2e-4);
}
