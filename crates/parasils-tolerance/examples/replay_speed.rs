//! A tolerance study two ways in one run: the study's replay (module 1 by
//! the chord method from the nominal Jacobians, `Study::run`) and the
//! reference replay (Newton's method from the previous pose at every
//! sample, `replay`), on the same robots and the same threads, in
//! alternating rounds so that both see the same machine load. Prints each
//! round's wall time, the median ratio, the extrapolation to 10^5 robots,
//! the largest difference of any row, and both reports' percentiles.
//!
//! ```sh
//! cargo run --release -p parasils-tolerance --example replay_speed -- [ROBOTS] [THREADS] [ROUNDS] [RATE_HZ] [chord]
//! ```
//!
//! Defaults: 10,000 robots, 2 threads, 1 round, the paper's turn at 100 Hz;
//! a fifth argument `chord` runs the chord replay only (for a profiler).

use core::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use parasils_sim::Scenario;
use parasils_tolerance::{Report, Results, Spec, Study, Trace, replay};

/// The reference replay of robots `0..robots` on `threads` threads, rows in
/// sample order.
fn reference(study: &Study, robots: usize, threads: usize) -> Results {
    let next = AtomicUsize::new(0);
    let rows: Mutex<Vec<(usize, [f64; 4], bool)>> = Mutex::new(Vec::with_capacity(robots));
    let work = || {
        loop {
            let start = next.fetch_add(16, Ordering::Relaxed);
            if start >= robots {
                return;
            }
            let mut local = Vec::with_capacity(16);
            for k in start..(start + 16).min(robots) {
                let row = match replay(&study.robot(k as u64), study.trace()) {
                    Ok(d) => (
                        k,
                        [
                            d.left_tip_dev_mm,
                            d.right_tip_dev_mm,
                            d.pose_position_err_mm,
                            d.pose_rotation_err_deg,
                        ],
                        false,
                    ),
                    Err(_) => (k, [f64::NAN; 4], true),
                };
                local.push(row);
            }
            if let Ok(mut r) = rows.lock() {
                r.extend(local);
            }
        }
    };
    std::thread::scope(|scope| {
        for _ in 1..threads {
            scope.spawn(work);
        }
        work();
    });
    let mut rows = rows.into_inner().unwrap_or_else(|e| e.into_inner());
    rows.sort_by_key(|r| r.0);
    let mut out = Results::default();
    for (k, v, failed) in rows {
        out.sample.push(k as u64);
        out.left_tip_dev_mm.push(v[0]);
        out.right_tip_dev_mm.push(v[1]);
        out.pose_position_err_mm.push(v[2]);
        out.pose_rotation_err_deg.push(v[3]);
        out.failed.push(failed);
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() -> Result<(), Box<dyn core::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: f64| -> Result<f64, Box<dyn core::error::Error>> {
        Ok(args
            .get(i)
            .map(|s| s.parse::<f64>())
            .transpose()?
            .unwrap_or(default))
    };
    let robots = arg(0, 10_000.0)? as usize;
    let threads = (arg(1, 2.0)? as usize).max(1);
    let rounds = (arg(2, 1.0)? as usize).max(1);
    let mut scenario = Scenario::paper();
    scenario.rate_hz = arg(3, 100.0)?;
    let trace = Trace::from_scenario(scenario)?;
    let samples = trace.len();
    let t0 = Instant::now();
    let study = Study::new(Spec::default(), trace, 0)?;
    println!(
        "{robots} robots x {samples} samples, {threads} threads, {rounds} round(s); \
         the study's set-up (nominal Jacobians included) {:.3} s",
        t0.elapsed().as_secs_f64()
    );
    let (mut old_s, mut new_s) = (Vec::new(), Vec::new());
    let (mut old, mut new) = (Results::default(), Results::default());
    if args.get(4).is_some_and(|a| a == "chord") {
        let t = Instant::now();
        let results = study.run(0..robots as u64, threads, &|_| true)?;
        println!(
            "chord only: {:.3} s, {} rows",
            t.elapsed().as_secs_f64(),
            results.len()
        );

        return Ok(());
    }
    for round in 0..rounds {
        let t = Instant::now();
        old = reference(&study, robots, threads);
        old_s.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        new = study.run(0..robots as u64, threads, &|_| true)?;
        new_s.push(t.elapsed().as_secs_f64());
        println!(
            "round {round}: Newton (reference) {:.3} s, chord {:.3} s, ratio {:.2}",
            old_s[round],
            new_s[round],
            old_s[round] / new_s[round]
        );
    }
    let (old_m, new_m) = (median(old_s), median(new_s));
    println!(
        "median: Newton {old_m:.3} s ({:.1} us a robot), chord {new_m:.3} s ({:.1} us a robot), \
         ratio {:.2}",
        1e6 * old_m / robots as f64,
        1e6 * new_m / robots as f64,
        old_m / new_m
    );
    println!(
        "extrapolated to 10^5 robots on these threads: Newton {:.1} s, chord {:.1} s",
        old_m * 1e5 / robots as f64,
        new_m * 1e5 / robots as f64
    );
    let mut worst: f64 = 0.0;
    let columns = [
        (&old.left_tip_dev_mm, &new.left_tip_dev_mm),
        (&old.right_tip_dev_mm, &new.right_tip_dev_mm),
        (&old.pose_position_err_mm, &new.pose_position_err_mm),
        (&old.pose_rotation_err_deg, &new.pose_rotation_err_deg),
    ];
    for (a, b) in columns {
        for (x, y) in a.iter().zip(b.iter()) {
            if x.is_finite() || y.is_finite() {
                worst = worst.max((x - y).abs());
            }
        }
    }
    println!(
        "largest difference of any row: {worst:.3e} (mm or deg); failures {} / {}",
        old.failed.iter().filter(|&&f| f).count(),
        new.failed.iter().filter(|&&f| f).count()
    );
    let (old_r, new_r) = (
        Report::new(&old, None, study.spec()).to_string(),
        Report::new(&new, None, study.spec()).to_string(),
    );
    println!(
        "\nthe reference's report:\n{old_r}\nthe chord's report:\n{new_r}\nthe printed reports \
         are {}",
        if old_r == new_r {
            "identical"
        } else {
            "DIFFERENT"
        }
    );
    Ok(())
}
