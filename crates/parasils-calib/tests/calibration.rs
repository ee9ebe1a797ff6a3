//! The calibration against independent truths: finite differences for the
//! identification Jacobian, synthetic robots (perturbed by up to 2 mm and
//! 1 deg per parameter) for the fit, with and without noise, and the
//! planner against random poses.

use parasils_calib::error::CalibError;
use parasils_calib::fit::STRUCTURAL_DEFICIENCY;
use parasils_calib::model::{Model, PoseMmDeg};
use parasils_calib::plan::{PlanOptions, plan};
use parasils_calib::{
    FitOptions, Measurement, PARAMETERS, Parameter, ParameterMap, Sigma, calibrate,
};
use parasils_io::Rng;
use parasils_kin::{ParallelGeometry, ParallelRobot, Pose};

const NOISE: Sigma = Sigma {
    q_mm: 0.01,
    position_mm: 0.02,
    angle_deg: 0.01,
};

/// A vector perturbed by up to 2 mm (lengths) and 1 deg (directions).
fn perturbed(map: &ParameterMap, rng: &mut Rng) -> [f64; PARAMETERS] {
    let mut x = map.nominal_vector();
    for (k, v) in x.iter_mut().enumerate() {
        let bound = match Parameter::from_index(k) {
            Some(Parameter::GuideDirection { .. }) => 1f64.to_radians().tan(),
            _ => 2.0,
        };
        *v += rng.uniform(-bound, bound);
    }
    x
}

fn planned(poses: usize, seed: u64) -> Vec<PoseMmDeg> {
    let options = PlanOptions {
        poses,
        candidates: 1000,
        seed,
        ..Default::default()
    };
    plan(&ParallelGeometry::assumed(), &options)
        .expect("plan")
        .poses
}

/// Random poses about the planner's centre, well inside the workspace
/// (every actuator 20 mm inside its stroke for the nominal robot), for
/// held-out predictions.
fn held_out(n: usize, seed: u64) -> Vec<PoseMmDeg> {
    let robot = ParallelRobot::<f64>::assumed();
    let center = plan(
        &ParallelGeometry::assumed(),
        &PlanOptions {
            poses: 1,
            candidates: 1,
            random_sets: 1,
            ..Default::default()
        },
    )
    .expect("plan")
    .report
    .center;
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let p: PoseMmDeg = core::array::from_fn(|k| {
            center[k] + if k < 3 { 80.0 } else { 15.0 } * rng.uniform(-1.0, 1.0)
        });
        let q = robot.ik(&Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]));
        if q.is_ok_and(|q| q.0.iter().all(|v| (20.0..=300.0).contains(v))) {
            out.push(p);
        }
    }
    out
}

fn readings(robot: &ParallelRobot<f64>, p: &PoseMmDeg) -> [f64; 6] {
    robot
        .ik_unchecked(&Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]))
        .expect("in reach")
        .0
}

/// Noise-free or noisy measurements of the robot `truth` at `poses`.
fn measure(
    truth: &ParallelRobot<f64>,
    poses: &[PoseMmDeg],
    noise: Option<(&mut Rng, Sigma)>,
) -> Vec<Measurement> {
    let mut noise = noise;
    poses
        .iter()
        .map(|p| {
            let mut q = readings(truth, p);
            let mut pose = *p;
            let mut sigma = Sigma::default();
            if let Some((rng, s)) = noise.as_mut() {
                for v in q.iter_mut() {
                    *v += s.q_mm * rng.normal();
                }
                for (k, v) in pose.iter_mut().enumerate() {
                    *v += if k < 3 { s.position_mm } else { s.angle_deg } * rng.normal();
                }
                sigma = *s;
            }
            Measurement {
                q_mm: q,
                pose,
                sigma,
            }
        })
        .collect()
}

/// The truth in the fit's gauge: each guide point slid along its direction
/// (and the encoder offset with it, which no reading can tell apart) until
/// the coordinate the fit fixed is back at its nominal value.
fn gauge(map: &ParameterMap, truth: &[f64; PARAMETERS], fixed: &[String]) -> [f64; PARAMETERS] {
    let mut x = *truth;
    let g = map.geometry(truth);
    for name in fixed {
        let Some(Parameter::GuidePoint { guide, axis }) = Parameter::from_name(name) else {
            panic!("unexpected fixed parameter {name}");
        };
        let u = g.guides[guide].direction;
        let i = Parameter::GuidePoint { guide, axis }.index();
        let delta = (map.nominal_vector()[i] - truth[i]) / u[axis];
        for a in 0..3 {
            x[Parameter::GuidePoint { guide, axis: a }.index()] += delta * u[a];
        }
        x[Parameter::EncoderOffset { guide }.index()] += delta;
    }
    x
}

#[test]
fn identification_jacobian_matches_central_differences() {
    let nominal = ParallelGeometry::<f64>::assumed();
    let map = ParameterMap::new(&nominal).expect("valid");
    let mut rng = Rng::new(11);
    let x = perturbed(&map, &mut rng);
    let model = Model::new(&map, &x);
    let scales = map.scales();
    for pose in planned(8, 5) {
        let eval = model.eval(&pose, true).expect("in reach");
        for k in 0..PARAMETERS {
            let h = 1e-5 * scales[k];
            let (mut xp, mut xm) = (x, x);
            xp[k] += h;
            xm[k] -= h;
            let qp = Model::new(&map, &xp).eval(&pose, false).expect("in reach");
            let qm = Model::new(&map, &xm).eval(&pose, false).expect("in reach");
            for j in 0..6 {
                let fd = (qp.q_mm[j] - qm.q_mm[j]) / (2.0 * h);
                let an = eval.d_params[j][k];
                // Central differences err by h^2 q''' / 6, about 1e-10 mm
                // per unit here, and by rounding eps q / h, 1e-9.
                assert!(
                    (fd - an).abs() * scales[k] < 1e-7,
                    "q{} d/d {}: analytic {an}, differences {fd}",
                    j + 1,
                    Parameter::from_index(k).expect("index").name()
                );
            }
        }
        for k in 0..6 {
            let h = 1e-5;
            let (mut pp, mut pm) = (pose, pose);
            pp[k] += h;
            pm[k] -= h;
            let qp = model.eval(&pp, false).expect("in reach");
            let qm = model.eval(&pm, false).expect("in reach");
            for j in 0..6 {
                let fd = (qp.q_mm[j] - qm.q_mm[j]) / (2.0 * h);
                let an = eval.d_pose[j][k];
                assert!(
                    (fd - an).abs() < 1e-7,
                    "q{} d/d pose[{k}]: {an} vs {fd}",
                    j + 1
                );
            }
        }
    }
}

#[test]
fn zero_noise_recovers_the_identifiable_parameters() {
    let nominal = ParallelGeometry::<f64>::assumed();
    let map = ParameterMap::new(&nominal).expect("valid");
    let poses = planned(50, 1);
    let held_out = held_out(20, 99);
    for seed in [1u64, 2, 3] {
        let mut rng = Rng::new(seed);
        let truth_x = perturbed(&map, &mut rng);
        let truth = ParallelRobot::new(map.geometry(&truth_x)).expect("valid");
        let data = measure(&truth, &poses, None);
        let fit = calibrate(&nominal, &data, &FitOptions::default()).expect("fit");
        let r = &fit.report;
        // Exactly the structural deficiency is fixed: each guide's point
        // along its (vertical) direction, against its encoder offset.
        let fixed: Vec<String> = r.fixed.iter().map(|f| f.name.clone()).collect();
        let want: Vec<String> = (0..6).map(|j| format!("guides[{j}].point_mm.z")).collect();
        assert_eq!(fixed, want);
        assert_eq!(r.identified.len(), PARAMETERS - STRUCTURAL_DEFICIENCY);
        for f in &r.fixed {
            assert!(f.reason.contains("encoder_offset_mm"), "{}", f.reason);
        }
        let equivalent = gauge(&map, &truth_x, &fixed);
        for p in &r.identified {
            let k = Parameter::from_name(&p.name).expect("name").index();
            let err = (p.fitted - equivalent[k]).abs();
            let tol = if p.unit == "mm" { 1e-8 } else { 1e-10 };
            assert!(err < tol, "seed {seed}, {}: error {err:e}", p.name);
        }
        assert!(r.rms_before_mm > 0.1, "{}", r.rms_before_mm);
        assert!(r.rms_after_mm < 1e-9, "{}", r.rms_after_mm);
        let fitted = ParallelRobot::new(fit.geometry).expect("valid");
        for p in &held_out {
            let (a, b) = (readings(&fitted, p), readings(&truth, p));
            for j in 0..6 {
                assert!(
                    (a[j] - b[j]).abs() < 1e-8,
                    "held out q{}: {}",
                    j + 1,
                    a[j] - b[j]
                );
            }
        }
        assert!(!fit.geometry.assumed);
        assert_eq!(fit.geometry.calibration.map(|c| c.poses), Some(50));
    }
}

/// `trials` noisy fits: the held-out RMS against the noise-free truth, and
/// per parameter the share of trials with the true error within 3 standard
/// deviations.
fn noisy_trials(trials: u64) {
    let nominal = ParallelGeometry::<f64>::assumed();
    let map = ParameterMap::new(&nominal).expect("valid");
    let poses = planned(50, 1);
    let held_out = held_out(30, 77);
    let mut within = vec![0u32; PARAMETERS];
    let mut worst_rms: f64 = 0.0;
    for trial in 0..trials {
        let mut rng = Rng::new(1000 + trial);
        let truth_x = perturbed(&map, &mut rng);
        let truth = ParallelRobot::new(map.geometry(&truth_x)).expect("valid");
        let data = measure(&truth, &poses, Some((&mut rng, NOISE)));
        let fit = calibrate(&nominal, &data, &FitOptions::default()).expect("fit");
        let fixed: Vec<String> = fit.report.fixed.iter().map(|f| f.name.clone()).collect();
        let equivalent = gauge(&map, &truth_x, &fixed);
        for p in &fit.report.identified {
            let k = Parameter::from_name(&p.name).expect("name").index();
            if (p.fitted - equivalent[k]).abs() <= 3.0 * p.std_dev {
                within[k] += 1;
            }
        }
        let fitted = ParallelRobot::new(fit.geometry).expect("valid");
        let mut sum = 0.0;
        for p in &held_out {
            let (a, b) = (readings(&fitted, p), readings(&truth, p));
            sum += (0..6).map(|j| (a[j] - b[j]).powi(2)).sum::<f64>();
        }
        let rms = (sum / (6 * held_out.len()) as f64).sqrt();
        worst_rms = worst_rms.max(rms);
        assert!(rms < 0.04, "trial {trial}: held-out RMS {rms} mm");
        assert!(
            (0.5..2.0).contains(&fit.report.variance_factor),
            "trial {trial}: variance factor {}",
            fit.report.variance_factor
        );
    }
    let fixed_z: Vec<usize> = (0..6)
        .map(|guide| Parameter::GuidePoint { guide, axis: 2 }.index())
        .collect();
    for (k, &n) in within.iter().enumerate() {
        if fixed_z.contains(&k) {
            continue;
        }
        let share = f64::from(n) / trials as f64;
        assert!(
            share >= 0.95,
            "{}: true error within 3 sigma in {share} of the trials",
            Parameter::from_index(k).expect("index").name()
        );
    }
    eprintln!("worst held-out RMS over {trials} trials: {worst_rms:.4} mm");
}

#[test]
fn noisy_fits_predict_within_0_04_mm_and_cover_the_truth_in_100_trials() {
    noisy_trials(100);
}

#[test]
fn planned_poses_see_at_least_twice_as_well_as_random_ones() {
    let options = PlanOptions {
        poses: 50,
        candidates: 1000,
        ..Default::default()
    };
    let plan = plan(&ParallelGeometry::assumed(), &options).expect("plan");
    let r = &plan.report;
    assert_eq!(plan.poses.len(), 50);
    assert_eq!(r.parameters, PARAMETERS - STRUCTURAL_DEFICIENCY);
    assert!(
        r.ratio_singular_value_min >= 2.0,
        "planned {} vs random median {}",
        r.planned.singular_value_min,
        r.random_singular_value_min_median
    );
    // The planned readings are the nominal robot's, inside the strokes by
    // the margin.
    let robot = ParallelRobot::<f64>::assumed();
    for (p, q) in plan.poses.iter().zip(&plan.q_mm) {
        let want = readings(&robot, p);
        for j in 0..6 {
            assert!((q[j] - want[j]).abs() < 1e-12);
            assert!(q[j] >= 5.0 && q[j] <= 315.0, "{}", q[j]);
        }
    }
    eprintln!("{}", r.to_json());
}

/// Readings of the nominal robot itself: nothing to fit, and the residual
/// at the rounding floor is convergence, not divergence.
#[test]
fn the_nominal_robots_own_readings_need_no_change() {
    let nominal = ParallelGeometry::<f64>::assumed();
    let robot = ParallelRobot::<f64>::assumed();
    let mut rng = Rng::new(1);
    let poses: Vec<PoseMmDeg> = (0..60)
        .map(|_| {
            let half = [30.0, 30.0, 20.0, 8.6, 8.6, 8.6];
            let p0 = [15.0, 20.0, -500.0, -15.0, 10.0, -60.0];
            core::array::from_fn(|k| p0[k] + half[k] * rng.uniform(-1.0, 1.0))
        })
        .collect();
    let fit = calibrate(
        &nominal,
        &measure(&robot, &poses, None),
        &FitOptions::default(),
    )
    .expect("fit");
    assert!(
        fit.report.rms_after_mm < 1e-12,
        "{}",
        fit.report.rms_after_mm
    );
    for p in &fit.report.identified {
        assert!(p.change.abs() < 1e-9, "{}: {}", p.name, p.change);
    }
}

#[test]
fn bad_input_is_refused_with_the_row_or_the_problem() {
    let nominal = ParallelGeometry::<f64>::assumed();
    let robot = ParallelRobot::<f64>::assumed();
    let poses = planned(12, 4);
    let good = measure(&robot, &poses, None);
    let options = FitOptions::default();

    let too_few = calibrate(&nominal, &good[..7], &options).expect_err("7 poses");
    assert!(matches!(
        too_few,
        CalibError::TooFewPoses {
            poses: 7,
            needed: 8,
            ..
        }
    ));
    assert!(
        too_few.to_string().contains("at least 8 poses"),
        "{too_few}"
    );

    let mut nan = good.clone();
    nan[4].pose[3] = f64::NAN;
    let e = calibrate(&nominal, &nan, &options).expect_err("NaN");
    assert_eq!(e.to_string(), "row 5, `psi_deg` = NaN: not a finite number");

    let mut far = good.clone();
    far[2].pose[0] += 800.0;
    let e = calibrate(&nominal, &far, &options).expect_err("out of reach");
    assert!(matches!(e, CalibError::OutOfReach { row: 3, .. }), "{e}");
    assert!(
        e.to_string().starts_with("row 3: the pose is out of reach"),
        "{e}"
    );

    let mut sigma = good.clone();
    sigma[0].sigma.q_mm = 0.01;
    let e = calibrate(&nominal, &sigma, &options).expect_err("sigma in one row");
    assert!(matches!(e, CalibError::ZeroSigma { row: 2 }), "{e}");

    // Readings unrelated to the poses: no plausible geometry explains them.
    let mut rng = Rng::new(5);
    let mut garbage = measure(&robot, &planned(30, 6), None);
    for m in garbage.iter_mut() {
        for q in m.q_mm.iter_mut() {
            *q = rng.uniform(0.0, 320.0);
        }
    }
    let e = calibrate(&nominal, &garbage, &options).expect_err("diverges");
    assert!(matches!(e, CalibError::Diverged { .. }), "{e}");
    assert!(
        e.to_string().starts_with("the fit diverged at iteration"),
        "{e}"
    );

    let mut rng = Rng::new(8);
    let map = ParameterMap::new(&nominal).expect("valid");
    let truth = ParallelRobot::new(map.geometry(&perturbed(&map, &mut rng))).expect("valid");
    let data = measure(&truth, &planned(30, 6), None);
    let one = FitOptions {
        max_iterations: 1,
        ..options
    };
    let e = calibrate(&nominal, &data, &one).expect_err("one iteration");
    assert!(
        matches!(e, CalibError::MaxIterations { iterations: 1, .. }),
        "{e}"
    );
}

#[test]
fn csv_round_trip_and_missing_columns() {
    let robot = ParallelRobot::<f64>::assumed();
    let mut rng = Rng::new(2);
    let data = measure(&robot, &planned(9, 3), Some((&mut rng, NOISE)));
    let text = parasils_calib::data::to_csv_string(&data);
    let back = parasils_calib::data::read_csv(text.as_bytes(), "m.csv", Sigma::default())
        .expect("reads back");
    assert_eq!(back, data);
    let no_psi = text.replacen("psi_deg", "psi", 1);
    let e = parasils_calib::data::read_csv(no_psi.as_bytes(), "m.csv", Sigma::default())
        .expect_err("missing psi_deg");
    assert!(
        e.to_string().starts_with("m.csv: missing column `psi_deg`"),
        "{e}"
    );
    let mut lines: Vec<&str> = text.lines().collect();
    let bad = lines[3].replacen(|c: char| c.is_ascii_digit(), "x", 1);
    lines[3] = &bad;
    let e = parasils_calib::data::read_csv(lines.join("\n").as_bytes(), "m.csv", Sigma::default())
        .expect_err("not a number");
    assert!(
        e.to_string().starts_with("m.csv: row 3, column `q1_mm`"),
        "{e}"
    );
}
