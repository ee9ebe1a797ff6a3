//! The time-optimal solver against independent truths: the closed-form
//! trapezoid of a straight path, time scaling, grid refinement, and, on
//! random paths and limits, feasibility 10 times denser than the grid and
//! at a fixed rate in time, rest to rest, and no shorter uniform time scaling.

#![allow(
    clippy::needless_range_loop,
    reason = "rows indexed alike in several arrays"
)]

use core::convert::Infallible;

use parasils_traj::optimal::{self, Derivatives, Error, Knot, Path, RowLimits, Schedule};
use parasils_traj::{Motion, Real};
use proptest::prelude::*;

/// `q_j(s) = a_j s + b_j sin(w_j s + p_j)`, rows of a smooth path with exact derivatives.
#[derive(Debug, Clone, Copy)]
struct Waves<const M: usize> {
    a: [f64; M],
    b: [f64; M],
    w: [f64; M],
    p: [f64; M],
}

impl<T: Real, const M: usize> Path<T, M> for Waves<M> {
    type Error = Infallible;
    fn derivatives(&self, s: T) -> Result<Derivatives<T, M>, Infallible> {
        let s = s.to_f64();
        let mut d = Derivatives::default();
        for j in 0..M {
            let phase = self.w[j] * s + self.p[j];
            d.first[j] = T::lit(self.a[j] + self.b[j] * self.w[j] * phase.cos());
            d.second[j] = T::lit(-self.b[j] * self.w[j] * self.w[j] * phase.sin());
        }
        Ok(d)
    }
}

/// The largest use of any limit, as a time stretch `max(|v| / v_max, sqrt(|a| / a_max))`.
fn stretch_at<const M: usize>(
    d: &Derivatives<f64, M>,
    limits: &[RowLimits<f64>; M],
    x: f64,
    u: f64,
) -> f64 {
    let v = x.max(0.0).sqrt();
    let mut worst = 0.0_f64;
    for j in 0..M {
        worst = worst
            .max((d.first[j] * v).abs() / limits[j].velocity)
            .max(((d.first[j] * u + d.second[j] * x).abs() / limits[j].acceleration).sqrt());
    }
    worst
}

/// The worst stretch 10 times denser than the knots (in `s`), and at
/// `rate` samples per second of the schedule's time.
fn dense_worst<const M: usize>(
    path: &Waves<M>,
    limits: &[RowLimits<f64>; M],
    schedule: &Schedule<'_, f64, M>,
    rate: f64,
) -> (f64, f64) {
    let mut in_s = 0.0_f64;
    for pair in schedule.knots().windows(2) {
        let (k0, k1) = (&pair[0], &pair[1]);
        for j in 0..=10 {
            let s = k0.s + (k1.s - k0.s) * f64::from(j) / 10.0;
            let x = if j == 10 {
                k1.x()
            } else {
                k0.x() + 2.0 * k0.s_ddot() * (s - k0.s)
            };
            let d = Path::<f64, M>::derivatives(path, s).unwrap_or_default();
            in_s = in_s.max(stretch_at(&d, limits, x, k0.s_ddot()));
        }
    }
    let mut in_t = 0.0_f64;
    for sample in schedule.sampler(rate).expect("a valid rate") {
        let st = sample.state;
        let d = Path::<f64, M>::derivatives(path, st.position).unwrap_or_default();
        in_t = in_t.max(stretch_at(
            &d,
            limits,
            st.velocity * st.velocity,
            st.acceleration,
        ));
    }
    (in_s, in_t)
}

#[test]
fn a_straight_path_gets_the_closed_form_trapezoid() -> Result<(), Error> {
    // Two rows moving 3 and -1.5 units: s limited by min(v_j / |q_j'|) =
    // min(2/3, 0.5/1.5) = 1/3 per s and min(a_j / |q_j'|) = min(1/3, 1/1.5) = 1/3 per s^2.
    let path = Waves::<2> {
        a: [3.0, -1.5],
        b: [0.0; 2],
        w: [0.0; 2],
        p: [0.0; 2],
    };
    let limits: [RowLimits<f64>; 2] = [RowLimits::new(2.0, 1.0), RowLimits::new(0.5, 1.0)];
    let (v, a) = (1.0 / 3.0, 1.0 / 3.0);
    let exact = v / a + 1.0 / v; // 4 s: 1 s up, 2 s cruising, 1 s down
    for n in [11, 101, 1001] {
        let mut knots = vec![Knot::default(); n];
        let (sched, cert) = optimal::plan(&path, &limits, &mut knots, 10)?;
        let t = sched.duration();
        assert!(
            t >= exact * (1.0 - 1e-12),
            "{n} knots: {t} below the optimum {exact}"
        );
        assert!(
            t <= exact * (1.0 + 2.0 / n as f64),
            "{n} knots: {t} vs {exact}"
        );
        // Constant derivatives: nothing between knots to correct, only the
        // headroom against rounding left below the limits.
        assert!(
            cert.stretch - 1.0 < 1.01e-12 && cert.passes == 0,
            "constant derivatives: nothing between knots: {cert:?}"
        );
        // Row 1 binds the velocity in the middle, row 0 the acceleration.
        let phases: Vec<_> = sched.phases(&limits).collect();
        assert!(
            phases
                .iter()
                .any(|p| p.row == 1 && p.limit == parasils_traj::LimitKind::Velocity)
        );
    }
    Ok(())
}

#[test]
fn scaling_the_limits_scales_time_exactly() -> Result<(), Error> {
    let path = Waves::<3> {
        a: [2.0, -1.0, 0.5],
        b: [0.3, 0.5, 0.2],
        w: [3.0, 5.0, 7.0],
        p: [0.1, 0.7, 2.0],
    };
    let limits: [RowLimits<f64>; 3] = [
        RowLimits::new(1.0, 2.0),
        RowLimits::new(0.8, 1.0),
        RowLimits::new(0.5, 3.0),
    ];
    // Velocities times c and accelerations times c^2: the same law, c times faster.
    let c = 2.5_f64;
    let fast = limits.map(|l| RowLimits::new(l.velocity * c, l.acceleration * c * c));
    let mut k1 = vec![Knot::default(); 400];
    let mut k2 = vec![Knot::default(); 400];
    let (s1, _) = optimal::plan(&path, &limits, &mut k1, 10)?;
    let (s2, _) = optimal::plan(&path, &fast, &mut k2, 10)?;
    let (t1, t2) = (s1.duration(), s2.duration());
    assert!((t1 / t2 - c).abs() < 1e-12 * c, "{t1} / {t2} should be {c}");
    Ok(())
}

#[test]
fn refining_the_grid_converges() -> Result<(), Error> {
    let path = Waves::<3> {
        a: [2.0, -1.0, 0.5],
        b: [0.3, 0.5, 0.2],
        w: [3.0, 5.0, 7.0],
        p: [0.1, 0.7, 2.0],
    };
    let limits: [RowLimits<f64>; 3] = [
        RowLimits::new(1.0, 2.0),
        RowLimits::new(0.8, 1.0),
        RowLimits::new(0.5, 3.0),
    ];
    let mut durations: Vec<f64> = Vec::new();
    for n in [250, 1000, 4000] {
        let mut knots = vec![Knot::default(); n];
        durations.push(optimal::plan(&path, &limits, &mut knots, 10)?.0.duration());
    }
    let (a, b, c) = (durations[0], durations[1], durations[2]);
    // First order in 1/N: each refinement by 4 cuts the change about 4 times.
    assert!((b - c).abs() < (a - b).abs() / 2.0 + 1e-12, "{durations:?}");
    assert!((b - c).abs() / c < 1e-3, "{durations:?}");
    Ok(())
}

#[test]
fn f32_agrees_with_f64() -> Result<(), Error> {
    let path = Waves::<3> {
        a: [2.0, -1.0, 0.5],
        b: [0.3, 0.5, 0.2],
        w: [3.0, 5.0, 7.0],
        p: [0.1, 0.7, 2.0],
    };
    let l64: [RowLimits<f64>; 3] = [
        RowLimits::new(1.0, 2.0),
        RowLimits::new(0.8, 1.0),
        RowLimits::new(0.5, 3.0),
    ];
    let l32 = l64.map(|l| RowLimits::new(l.velocity as f32, l.acceleration as f32));
    let mut k64 = vec![Knot::<f64, 3>::default(); 500];
    let mut k32 = vec![Knot::<f32, 3>::default(); 500];
    let t64 = optimal::plan(&path, &l64, &mut k64, 10)?.0.duration();
    let t32 = optimal::plan(&path, &l32, &mut k32, 10)?.0.duration();
    assert!((f64::from(t32) - t64).abs() < 1e-4 * t64, "{t32} vs {t64}");
    Ok(())
}

#[test]
fn invalid_input_is_a_typed_error() {
    let path = Waves::<1> {
        a: [1.0],
        b: [0.0],
        w: [0.0],
        p: [0.0],
    };
    let good: [RowLimits<f64>; 1] = [RowLimits::new(1.0, 1.0)];
    let mut one = [Knot::default(); 1];
    assert_eq!(
        optimal::plan(&path, &good, &mut one, 10).map(|_| ()),
        Err(Error::TooFewKnots { count: 1 })
    );
    let mut knots = [Knot::default(); 5];
    let bad: [RowLimits<f64>; 1] = [RowLimits::new(1.0, f64::NAN)];
    assert!(matches!(
        optimal::plan(&path, &bad, &mut knots, 10).map(|_| ()),
        Err(Error::InvalidLimit { row: 0, .. })
    ));
    assert_eq!(
        optimal::plan(&path, &good, &mut knots, 1).map(|_| ()),
        Err(Error::TooFewChecks { count: 1 })
    );
    // A path that moves no limited row: nothing bounds its speed.
    let still = Waves::<1> {
        a: [0.0],
        b: [0.0],
        w: [0.0],
        p: [0.0],
    };
    assert!(matches!(
        optimal::plan(&still, &good, &mut knots, 10).map(|_| ()),
        Err(Error::Unconstrained { .. })
    ));
    // Knots not increasing.
    let mut knots = [Knot::default(); 3];
    assert!(matches!(
        optimal::solve(&good, &mut knots).map(|_| ()),
        Err(Error::Grid { index: 1, .. })
    ));
    // Infinite limits are no limits, and are accepted.
    let free: [RowLimits<f64>; 1] = [RowLimits::new(f64::INFINITY, 1.0)];
    let mut knots = [Knot::default(); 11];
    assert!(optimal::plan(&path, &free, &mut knots, 10).is_ok());
}

fn waves() -> impl Strategy<Value = Waves<4>> {
    (
        prop::array::uniform4(-3.0..3.0f64),
        prop::array::uniform4(0.0..1.0f64),
        prop::array::uniform4(0.0..12.0f64),
        prop::array::uniform4(0.0..6.3f64),
    )
        .prop_map(|(mut a, b, w, p)| {
            // Row 0 always moves: a path that moves no row has no finite optimum.
            a[0] = a[0].signum() * (0.3 + a[0].abs());
            Waves { a, b, w, p }
        })
}

fn limits() -> impl Strategy<Value = [RowLimits<f64>; 4]> {
    prop::array::uniform4((0.05..5.0f64, 0.05..5.0f64))
        .prop_map(|l| l.map(|(v, a)| RowLimits::new(v, a)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_paths_are_feasible_at_rest_at_both_ends_and_tight(
        path in waves(),
        limits in limits(),
        n in 50usize..400,
    ) {
        let mut knots = vec![Knot::default(); n];
        let (sched, cert) = optimal::plan(&path, &limits, &mut knots, 10).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let t = sched.duration();
        prop_assert!(t.is_finite() && t > 0.0);
        // Rest to rest, from s = 0 to s = 1.
        let (start, end) = (sched.state(0.0), sched.state(t));
        prop_assert_eq!((start.position, start.velocity), (0.0, 0.0));
        prop_assert_eq!((end.position, end.velocity), (1.0, 0.0));
        prop_assert_eq!(knots[0].x(), 0.0);
        prop_assert_eq!(knots[n - 1].x(), 0.0);
        let sched = Schedule::view(&knots);
        // Feasible 10 times denser than the knots, and at 10 samples per knot interval in time.
        let rate = 10.0 * n as f64 / t;
        let (in_s, in_t) = dense_worst(&path, &limits, &sched, rate);
        prop_assert!(in_s <= 1.0 + 1e-9, "10x in s: worst {}", in_s);
        prop_assert!(in_t <= 1.0 + 1e-9, "in time: worst {}", in_t);
        // Optimal under uniform time scaling: the shortest feasible scaling
        // of the law (duration t * worst) is not shorter by more than the
        // grid's resolution 1/N.
        prop_assert!(in_s.max(in_t) >= 1.0 - 1.0 / n as f64, "slack {}", in_s.max(in_t));
        prop_assert!(cert.stretch >= 1.0 && cert.stretch < 1.0 + 1e-2, "stretch {}", cert.stretch);
    }

    #[test]
    fn every_interval_is_at_a_limit_or_at_the_controllable_bound(
        path in waves(),
        limits in limits(),
        n in 20usize..200,
    ) {
        let mut knots = vec![Knot::default(); n];
        optimal::fill_uniform(&path, &mut knots).map_err(|e| TestCaseError::fail(e.to_string()))?;
        optimal::solve(&limits, &mut knots).map_err(|e| TestCaseError::fail(e.to_string()))?;
        for i in 0..n - 1 {
            let (k0, k1) = (&knots[i], &knots[i + 1]);
            let u = k0.s_ddot();
            let mut use_ = 0.0_f64;
            for (d, x) in [(&k0.derivatives, k0.x()), (&k1.derivatives, k1.x())] {
                for j in 0..4 {
                    use_ = use_
                        .max((d.first[j] * u + d.second[j] * x).abs() / limits[j].acceleration)
                        .max((d.first[j] * x.sqrt()).abs() / limits[j].velocity);
                }
            }
            // Either a limit binds on this interval (the acceleration could
            // not be larger), or the next knot is as fast as it can be while
            // the end stays reachable.
            prop_assert!(
                use_ >= 1.0 - 1e-9 || k1.x() >= k1.x_max() * (1.0 - 1e-12),
                "interval {}: use {}, x {} of {}", i, use_, k1.x(), k1.x_max()
            );
            prop_assert!(use_ <= 1.0 + 1e-9, "interval {}: use {}", i, use_);
        }
    }
}
