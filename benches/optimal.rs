//! The time-optimal timing of the paper's reorientation under the assumed
//! actuator limits: the solver alone on a grid whose derivatives are
//! already evaluated (`solve`, 100 to 3000 knots, `f64` and `f32`), the
//! path's derivatives at 1000 knots (`fill`), and the whole plan (`plan`:
//! fill, solve, the check 10 times denser and its correction).
//!
//! `cargo bench -p parasils --bench optimal`; results in `BENCHMARKS.md`.

mod common;

use core::hint::black_box;

use criterion::Criterion;
use parasils::Real;
use parasils::geometry::RobotState;
use parasils::kin::{ActuatorLimits, Controller, Pose, TipTargets};
use parasils::path::{MotionPath, PATH_ROWS, row_limits};
use parasils::traj::optimal::{self, Knot};

fn paper_path<T: Real>() -> MotionPath<T> {
    let lit = T::lit;
    let c = Controller::paper();
    let tips = TipTargets::paper();
    let start = RobotState::solved(&c, Pose::paper_start(), &tips, T::zero())
        .expect("the paper's start is in reach");
    let goal = [
        start.pose.psi + lit(15f64.to_radians()),
        start.pose.theta + lit(25f64.to_radians()),
    ];
    MotionPath::turning(&c, &start, goal, [tips.left, tips.right])
}

fn bench_solve<T: Real>(c: &mut Criterion, name: &str, sizes: &[usize]) {
    let path = paper_path::<T>();
    let limits = row_limits(&ActuatorLimits::<T>::assumed(), None);
    for &n in sizes {
        let mut knots = vec![Knot::<T, PATH_ROWS>::default(); n];
        optimal::fill_uniform(&path, &mut knots).expect("the paper's path is in reach");
        c.bench_function(&format!("optimal/solve_{n}/{name}"), |b| {
            b.iter(|| {
                optimal::solve(black_box(&limits), &mut knots)
                    .map(|s| s.duration())
                    .expect("solvable")
            })
        });
    }
}

fn bench_plan(c: &mut Criterion) {
    let path = paper_path::<f64>();
    let limits = row_limits(&ActuatorLimits::assumed(), None);
    let mut knots = vec![Knot::default(); 1000];
    c.bench_function("optimal/fill_1000/f64", |b| {
        b.iter(|| optimal::fill_uniform(black_box(&path), &mut knots).expect("in reach"))
    });
    c.bench_function("optimal/plan_1000/f64", |b| {
        b.iter(|| {
            optimal::plan(black_box(&path), &limits, &mut knots, 10)
                .map(|(s, _)| s.duration())
                .expect("solvable")
        })
    });
}

/// The fastest of `runs` solves at each grid size, printed: the same
/// statistic as `benches/python/toppra_compare.py` takes of toppra's time
/// (the best of a few runs), which a loaded machine disturbs least.
fn best_of(runs: usize) {
    let path = paper_path::<f64>();
    let limits = row_limits(&ActuatorLimits::<f64>::assumed(), None);
    println!("best of {runs} solves (the solver alone):");
    for n in [100, 300, 1000, 3000] {
        let mut knots = vec![Knot::<f64, PATH_ROWS>::default(); n];
        optimal::fill_uniform(&path, &mut knots).expect("the paper's path is in reach");
        let mut best = f64::INFINITY;
        for _ in 0..runs {
            let t0 = std::time::Instant::now();
            let d = optimal::solve(black_box(&limits), &mut knots).map(|s| s.duration());
            best = best.min(t0.elapsed().as_secs_f64());
            black_box(d).expect("solvable");
        }
        println!("  {n:5} knots: {:8.1} us", best * 1e6);
    }
}

fn main() {
    best_of(200);
    let mut c = common::criterion();
    bench_solve::<f64>(&mut c, "f64", &[100, 300, 1000, 3000]);
    bench_solve::<f32>(&mut c, "f32", &[1000]);
    bench_plan(&mut c);
    c.final_summary();
}
