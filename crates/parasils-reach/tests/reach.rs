//! Reach maps against `simulate` and against a brute-force evaluation of
//! every constraint written out here, from the kinematics' public solvers.

use std::collections::VecDeque;

use parasils::kin::{
    AssemblyMode, Controller, Error, Instrument, MarginTracker, ParallelRobot, PlatformState, Pose,
    RobotGeometry, TipTargets,
};
use parasils_reach::{Checker, Constraint, ReachMap, ReachOptions, TOLERANCE_RAD};
use parasils_sim::{Run, Turn};
use parasils_sim::{Scenario, Simulation, SimulationError};

/// A small, fast generator of numbers in `[0, 1)` (xorshift64*).
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The paper's setup on a 2.5 deg grid of the default range, with lines.
fn paper_map() -> ReachMap {
    let options = ReachOptions {
        step_deg: 2.5,
        ..ReachOptions::default()
    };
    ReachMap::compute(&Scenario::paper(), &options).expect("map")
}

/// The index of the cell `(dpsi, dtheta)` in multiples of the step.
fn cell_at(map: &ReachMap, k_psi: i64, k_theta: i64) -> usize {
    let c = map.psi.index(k_psi).expect("on the grid");
    let r = map.theta.index(k_theta).expect("on the grid");
    map.index(c, r)
}

/// `simulate` of the paper's setup to `(dpsi, dtheta)`, deg, without the
/// actuators' rate limits: a reach map is about poses (joint limits,
/// strokes, reach, singularities), which hold whatever the timing, while the
/// rates depend on how fast the turn is made.
fn simulate(dpsi: f64, dtheta: f64) -> Result<(), Error> {
    let mut robot = parasils::kin::RobotGeometry::paper();
    robot.limits = parasils::kin::ActuatorLimits::unlimited();
    let sim = Simulation::new(Scenario {
        run: Run::turn(Turn {
            psi_deg: dpsi,
            theta_deg: dtheta,
            ..Turn::paper()
        }),
        robot,
        ..Scenario::paper()
    })
    .expect("plans");
    for record in sim.samples() {
        match record {
            Ok(_) => {}
            Err(SimulationError::Kinematics { error, .. }) => return Err(error),
            Err(e) => panic!("unexpected failure: {e}"),
        }
    }
    Ok(())
}

#[test]
fn the_paper_target_is_straight_ahead_and_the_boundary_is_what_simulate_meets() {
    let map = paper_map();
    // (15, 25) deg: 6 and 10 steps.
    let target = &map.cells[cell_at(&map, 6, 10)];
    assert!(target.feasible && target.reachable);
    assert_eq!(target.line, Some(true));
    assert!(map.cells[map.start_index()].line == Some(true));
    assert!(!map.boundary.points.is_empty());
    assert!(!map.boundary.polylines.is_empty());
    // Boundary points whose feasible cell is reached in a straight line:
    // one per constraint met.
    let mut tried: Vec<Constraint> = Vec::new();
    for p in &map.boundary.points {
        if tried.contains(&p.limiting) || map.cells[p.cell].line != Some(true) {
            continue;
        }
        let gap = (p.outside[0] - p.inside[0]).hypot(p.outside[1] - p.inside[1]);
        assert!(gap <= TOLERANCE_RAD, "{gap}");
        tried.push(p.limiting);
        let [ip, it] = p.inside.map(f64::to_degrees);
        let [op, ot] = p.outside.map(f64::to_degrees);
        simulate(ip, it).unwrap_or_else(|e| panic!("inside ({ip}, {it}) fails: {e}"));
        let e = simulate(op, ot).expect_err("outside fails");
        assert_eq!(
            Constraint::of_error(&e),
            p.limiting,
            "outside ({op}, {ot}): {e}"
        );
    }
    assert!(tried.len() >= 3, "{tried:?}");
}

#[test]
fn line_agrees_with_simulate_away_from_the_boundary() {
    let map = paper_map();
    let mut random = Random(0x5eed_1234_abcd_0001);
    let (mut yes, mut no) = (0, 0);
    while yes < 6 || no < 6 {
        let i = (random.next() * map.len() as f64) as usize;
        let cell = &map.cells[i];
        if cell.margin.abs() <= 1e-3 || !cell.margin.is_finite() {
            continue;
        }
        let line = cell.line == Some(true);
        if (line && yes >= 6) || (!line && no >= 6) {
            continue;
        }
        let [dpsi, dtheta] = map.increments_deg(i);
        // An infeasible goal fails at the end; skip the long far-away runs.
        let ok = simulate(dpsi, dtheta).is_ok();
        assert_eq!(ok, line, "({dpsi}, {dtheta}): {cell:?}");
        if line {
            yes += 1;
        } else {
            no += 1;
        }
    }
}

/// The code of an error, written out here.
fn code(e: &Error) -> String {
    match e {
        Error::LegOutOfReach { actuator, .. } => format!("module1.q{actuator}.out_of_reach"),
        Error::SerialSingular { actuator, .. } => format!("module1.q{actuator}.serial_singular"),
        Error::ActuatorLimit { actuator, .. } => format!("module1.q{actuator}.stroke"),
        Error::ParallelSingular { .. } => "module1.parallel_singular".into(),
        Error::OutOfReach { side, .. } => format!("{}.out_of_reach", side.name()),
        Error::Singular { side, margin, .. } => match margin {
            parasils::kin::InstrumentSingularity::CosQs2 => {
                format!("{}.cos_qs2.singular", side.name())
            }
            parasils::kin::InstrumentSingularity::Qs3 => format!("{}.qs3.singular", side.name()),
        },
        Error::JointLimit { side, joint, .. } => format!("{}.{joint}.limit", side.name()),
        other => panic!("unexpected error {other}"),
    }
}

/// Every constraint of the per-cycle check at `pose`, in the controller's
/// order, from the public solvers: module 1's IK (reach, serial margins,
/// strokes) and its parallel margin against `parallel_command`, then each
/// instrument module's IK in mode A with its joint limits.
fn brute_force(robot: &RobotGeometry<f64>, tips: &TipTargets<f64>, pose: &Pose<f64>) -> String {
    let m1 = ParallelRobot::new(robot.module1).expect("module 1");
    if let Err(e) = m1.ik(pose) {
        return code(&e);
    }
    let margins = m1.margins(pose).expect("margins");
    if margins.parallel < robot.module1.thresholds.parallel_command {
        return "module1.parallel_singular".into();
    }
    for (g, tip) in [(robot.left, tips.left), (robot.right, tips.right)] {
        let m = Instrument::new(g).expect("instrument");
        if let Err(e) = m.ik(pose, &tip, AssemblyMode::A) {
            return code(&e);
        }
    }
    "ok".into()
}

#[test]
fn ten_thousand_cells_agree_with_a_brute_force_evaluation() {
    let scenario = Scenario::paper();
    // 101 x 101 = 10,201 cells, 0.9 deg apart, over the default range.
    let options = ReachOptions {
        step_deg: 0.9,
        line: false,
        ..ReachOptions::default()
    };
    let map = ReachMap::compute(&scenario, &options).expect("map");
    assert!(map.len() >= 10_000);
    let start = scenario.start();
    let tips = scenario.tips();
    let mut feasible = vec![false; map.len()];
    let mut kinds = std::collections::HashSet::new();
    for (i, cell) in map.cells.iter().enumerate() {
        let [dpsi, dtheta] = map.increments_deg(i);
        let pose = Pose {
            psi: start.psi + dpsi.to_radians(),
            theta: start.theta + dtheta.to_radians(),
            ..start
        };
        let expected = brute_force(&scenario.robot, &tips, &pose);
        assert_eq!(cell.limiting.code(), expected, "({dpsi}, {dtheta})");
        feasible[i] = expected == "ok";
        assert_eq!(cell.feasible, feasible[i]);
        assert_eq!(cell.margin >= 0.0, cell.feasible, "({dpsi}, {dtheta})");
        assert_eq!(cell.line, None);
        kinds.insert(expected);
    }
    assert!(kinds.len() >= 4, "{kinds:?}");
    // The reachable region, by a flood fill written out here.
    let cols = map.psi.count;
    let mut reachable = vec![false; map.len()];
    let s = map.start_index();
    let mut queue = VecDeque::new();
    if feasible[s] {
        reachable[s] = true;
        queue.push_back(s);
    }
    while let Some(i) = queue.pop_front() {
        let (c, r) = (i % cols, i / cols);
        let mut near = Vec::new();
        if c > 0 {
            near.push(i - 1);
        }
        if c + 1 < cols {
            near.push(i + 1);
        }
        if r > 0 {
            near.push(i - cols);
        }
        if i + cols < map.len() {
            near.push(i + cols);
        }
        for j in near {
            if feasible[j] && !reachable[j] {
                reachable[j] = true;
                queue.push_back(j);
            }
        }
    }
    for (i, cell) in map.cells.iter().enumerate() {
        assert_eq!(cell.reachable, reachable[i], "{:?}", map.increments_deg(i));
    }
}

/// The greatest common divisor of `a` and `b`.
fn gcd(a: i64, b: i64) -> i64 {
    if b == 0 { a.abs() } else { gcd(b, a % b) }
}

/// Every cell's `line`, point by point: for the cell `(p, q)` (in steps),
/// `g = gcd(p, q)`, `(a, b) = (p, q) / g` and `n = ceil(4 |(a, b)|)`, the
/// points `(j / n) (a, b)` for `j = 1..=g n` (a quarter step apart at most,
/// the cell last), each through the controller's per-cycle step at rest from
/// a fresh controller, walked from the start until one fails.
fn lines_point_by_point(scenario: &Scenario, map: &ReachMap) -> Vec<bool> {
    let start = scenario.start();
    let tips = scenario.tips();
    let step = map.options.step_deg;
    let fresh = Controller::from_geometry(&scenario.robot).expect("robot");
    let line = |i: usize| -> bool {
        let [dpsi, dtheta] = map.increments_deg(i);
        let (p, q) = ((dpsi / step).round() as i64, (dtheta / step).round() as i64);
        let controller = fresh;
        let mut tracker = MarginTracker::new();
        let mut passes = |dpsi: f64, dtheta: f64| {
            let pose = Pose {
                psi: start.psi + dpsi,
                theta: start.theta + dtheta,
                ..start
            };
            controller
                .step(&PlatformState::at_rest(pose), &tips, &mut tracker)
                .is_ok()
        };
        if (p, q) == (0, 0) {
            return passes(0.0, 0.0);
        }
        let g = gcd(p, q);
        let (a, b) = (p / g, q / g);
        let n = (4.0 * ((a * a + b * b) as f64).sqrt()).ceil() as i64;
        (1..=g * n).all(|j| {
            let t = j as f64 / n as f64;
            passes(
                (t * a as f64 * step).to_radians(),
                (t * b as f64 * step).to_radians(),
            )
        })
    };
    let cells: Vec<usize> = (0..map.len()).collect();
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = cells.len().div_ceil(threads);
    std::thread::scope(|s| {
        let handles: Vec<_> = cells
            .chunks(chunk)
            .map(|part| s.spawn(move || part.iter().map(|&i| line(i)).collect::<Vec<_>>()))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("no panic"))
            .collect()
    })
}

/// Asserts that every cell's `line` is the point-by-point one.
fn assert_lines_point_by_point(scenario: &Scenario, options: &ReachOptions) {
    let map = ReachMap::compute(scenario, options).expect("map");
    let expected = lines_point_by_point(scenario, &map);
    let mut differ = Vec::new();
    for (i, cell) in map.cells.iter().enumerate() {
        if cell.line != Some(expected[i]) {
            differ.push((map.increments_deg(i), cell.line, expected[i]));
        }
    }
    assert!(
        differ.is_empty(),
        "{} cells differ: {:?}",
        differ.len(),
        &differ[..differ.len().min(20)]
    );
    let straight = expected.iter().filter(|&&l| l).count();
    let feasible = map.cells.iter().filter(|c| c.feasible).count();
    // Both kinds, and feasible cells off the line among them.
    assert!(
        straight > 1 && straight < feasible,
        "{straight} of {feasible}"
    );
}

/// Every cell of the default map against its check from a fresh checker
/// (whose parallel margin is the full singular value decomposition, the
/// path every cell took before the margin tracker recovered a direction
/// across grid steps): the same verdict, constraint and nearest
/// constraint, and the normalised margin within 1e-11 (1.6e-12 at worst,
/// next to the parallel singularity).
#[test]
fn the_default_map_agrees_with_a_fresh_check_of_every_cell() {
    let scenario = Scenario::paper();
    let map = ReachMap::compute(&scenario, &ReachOptions::default()).expect("map");
    let fresh = Checker::new(&scenario).expect("checker");
    let mut worst = 0f64;
    for (i, cell) in map.cells.iter().enumerate() {
        let [dpsi, dtheta] = map.increments_deg(i);
        let v = fresh.clone().check(dpsi.to_radians(), dtheta.to_radians());
        let at = (dpsi, dtheta);
        assert_eq!(cell.feasible, v.feasible(), "{at:?}");
        assert_eq!(cell.limiting, v.limiting, "{at:?}");
        assert_eq!(cell.nearest, v.nearest, "{at:?}");
        let d = (cell.margin - v.margin).abs();
        assert!(d <= 1e-11, "{at:?}: {} vs {}", cell.margin, v.margin);
        worst = worst.max(d);
    }
    println!("default map against fresh checks: largest margin difference {worst:.2e}");
}

#[test]
fn the_default_map_has_the_lines_of_every_point_checked() {
    assert_lines_point_by_point(&Scenario::paper(), &ReachOptions::default());
}

#[test]
fn another_start_and_other_tips_have_the_lines_of_every_point_checked() {
    // Theta 15 deg higher and another left tip (the right one its mirror
    // image), on a 0.75 deg grid: the feasible region is not convex from
    // there, and about a sixth of it is off the straight lines.
    let paper = Scenario::paper();
    let mut start = paper.start_mm_deg;
    start[4] += 15.0;
    let scenario = Scenario {
        start_mm_deg: start,
        tip_left_mm: [60.0, -40.0, -610.0],
        ..paper
    };
    let options = ReachOptions {
        step_deg: 0.75,
        ..ReachOptions::default()
    };
    assert_lines_point_by_point(&scenario, &options);
}

#[test]
fn a_finer_step_near_the_parallel_singularity_has_the_lines_of_every_point_checked() {
    // A 0.2 deg grid of +-10 deg around a start 35 deg above the paper's in
    // theta, a few degrees from module 1's parallel singularity.
    let paper = Scenario::paper();
    let mut start = paper.start_mm_deg;
    start[4] += 35.0;
    let scenario = Scenario {
        start_mm_deg: start,
        ..paper
    };
    let options = ReachOptions {
        psi_range_deg: [-10.0, 10.0],
        theta_range_deg: [-10.0, 10.0],
        step_deg: 0.2,
        ..ReachOptions::default()
    };
    assert_lines_point_by_point(&scenario, &options);
}

#[test]
fn the_map_does_not_depend_on_the_threads() {
    let options = ReachOptions {
        step_deg: 5.0,
        threads: 1,
        ..ReachOptions::default()
    };
    let one = ReachMap::compute(&Scenario::paper(), &options).expect("map");
    let two = ReachMap::compute(
        &Scenario::paper(),
        &ReachOptions {
            threads: 2,
            ..options
        },
    )
    .expect("map");
    assert_eq!(one.cells, two.cells);
    assert_eq!(one.boundary, two.boundary);
}

#[test]
fn bad_grids_are_refused() {
    let paper = Scenario::paper();
    for options in [
        ReachOptions {
            step_deg: 0.0,
            ..ReachOptions::default()
        },
        ReachOptions {
            psi_range_deg: [5.0, 10.0],
            ..ReachOptions::default()
        },
        ReachOptions {
            theta_range_deg: [f64::NAN, 10.0],
            ..ReachOptions::default()
        },
        ReachOptions {
            step_deg: 1e-6,
            ..ReachOptions::default()
        },
    ] {
        let e = ReachMap::compute(&paper, &options).expect_err("refused");
        assert!(e.to_string().starts_with("reach map: "), "{e}");
    }
}
