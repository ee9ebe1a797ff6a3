//! The tolerance study against independent truths: the nominal robot
//! replays its own commands exactly, the first-order model (analytic
//! derivatives, no shared code) predicts small deviations, any chunking
//! gives the same bits, and bad inputs are clear errors.

use parasils_sim::Scenario;
use parasils_tolerance::{
    Distribution, Family, Perturbation, Report, Spec, Study, StudyError, Trace,
};

fn paper_trace(rate_hz: f64) -> Trace {
    let mut scenario = Scenario::paper();
    scenario.rate_hz = rate_hz;
    Trace::from_scenario(scenario).expect("the paper's motion")
}

#[test]
fn the_nominal_robot_replays_its_own_commands_to_rounding() {
    let study = Study::new(Spec::none(), paper_trace(100.0), 5).expect("valid");
    // The paper's 4.5 s at 100 Hz.
    assert_eq!(study.trace().len(), 451);
    let results = study.run(0..4, 2, &|_| true).expect("not interrupted");
    for i in 0..4 {
        assert!(!results.failed[i]);
        for col in [
            &results.left_tip_dev_mm,
            &results.right_tip_dev_mm,
            &results.pose_position_err_mm,
        ] {
            assert!(col[i] < 1e-9, "{i}: {}", col[i]);
        }
        assert!(results.pose_rotation_err_deg[i] < 1e-9);
    }
    // A zero width is no perturbation either.
    let zero = Spec::default().scaled(0.0);
    let study = Study::new(zero, paper_trace(20.0), 5).expect("valid");
    assert!(study.sample(17).expect("nominal").tip_dev_mm() < 1e-9);
}

#[test]
fn any_chunking_and_any_threads_give_the_same_bits() {
    let study = Study::new(Spec::default(), paper_trace(20.0), 123).expect("valid");
    let whole = study.run(0..70, 1, &|_| true).expect("not interrupted");
    let mut parts = study.run(0..23, 2, &|_| true).expect("not interrupted");
    parts.append(study.run(23..41, 3, &|_| true).expect("not interrupted"));
    parts.append(study.run(41..70, 2, &|_| true).expect("not interrupted"));
    assert_eq!(parts.sample, whole.sample);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&parts.left_tip_dev_mm), bits(&whole.left_tip_dev_mm));
    assert_eq!(bits(&parts.right_tip_dev_mm), bits(&whole.right_tip_dev_mm));
    assert_eq!(
        bits(&parts.pose_rotation_err_deg),
        bits(&whole.pose_rotation_err_deg)
    );
    // A study built again from scratch (a worker elsewhere) agrees too.
    let again = Study::new(Spec::default(), paper_trace(20.0), 123).expect("valid");
    assert_eq!(
        again
            .sample(55)
            .expect("followed")
            .left_tip_dev_mm
            .to_bits(),
        whole.left_tip_dev_mm[55].to_bits()
    );
    // Another seed: other robots.
    let other = Study::new(Spec::default(), paper_trace(20.0), 124).expect("valid");
    assert_ne!(
        other.sample(55).expect("followed"),
        study.sample(55).expect("followed")
    );
}

#[test]
fn small_tolerances_match_the_first_order_model_within_two_percent() {
    // The default tolerances divided by 100: second-order terms are about
    // 1e-6 of the first-order ones.
    let spec = Spec::default().scaled(0.01);
    let study = Study::new(spec, paper_trace(50.0), 9).expect("valid");
    let linear = study.linearisation().expect("regular motion");
    let mut worst: f64 = 0.0;
    for i in 0..40 {
        let real = study.sample(i).expect("followed");
        let predicted = linear.predict(&study.perturbation(i));
        for (r, p) in [
            (real.left_tip_dev_mm, predicted.left_tip_dev_mm),
            (real.right_tip_dev_mm, predicted.right_tip_dev_mm),
            (real.pose_position_err_mm, predicted.pose_position_err_mm),
            (real.pose_rotation_err_deg, predicted.pose_rotation_err_deg),
        ] {
            assert!(p > 0.0);
            worst = worst.max((r / p - 1.0).abs());
        }
    }
    assert!(worst < 0.02, "largest relative difference {worst}");
    // The first-order model is not trivially right: at the default
    // tolerances times 300 the two part ways by more than rounding.
    let wide = Study::new(Spec::default().scaled(3.0), paper_trace(20.0), 9).expect("valid");
    let linear = wide.linearisation().expect("regular motion");
    let r = wide.sample(3).expect("followed").left_tip_dev_mm;
    let p = linear.predict(&wide.perturbation(3)).left_tip_dev_mm;
    assert!((r / p - 1.0).abs() > 1e-6, "{r} {p}");
}

#[test]
fn the_ranking_agrees_with_one_family_at_a_time() {
    let trace = paper_trace(20.0);
    let spec = Spec::default();
    let study = Study::new(spec, trace.clone(), 1).expect("valid");
    let ranking = study.linearisation().expect("regular").sensitivity(&spec);
    assert_eq!(ranking.len(), 8);
    let total: f64 = ranking.iter().map(|s| s.share).sum();
    assert!((total - 1.0).abs() < 1e-12);
    let (top, bottom) = (ranking[0], ranking[7]);
    assert!(top.share > bottom.share);
    // Monte Carlo with one family alone: the top family moves the tips
    // more than the bottom one.
    let alone = |f: Family| {
        let s = Spec::none().with(f, spec.get(f));
        let study = Study::new(s, trace.clone(), 2).expect("valid");
        let r = study.run(0..64, 2, &|_| true).expect("not interrupted");
        let ms: f64 = r
            .left_tip_dev_mm
            .iter()
            .chain(&r.right_tip_dev_mm)
            .map(|d| d * d)
            .sum::<f64>()
            / 128.0;
        ms.sqrt()
    };
    let (a, b) = (alone(top.family), alone(bottom.family));
    assert!(
        a > 2.0 * b,
        "{:?} {a} vs {:?} {b}",
        top.family,
        bottom.family
    );
}

#[test]
fn a_tolerance_that_takes_a_leg_out_of_reach_is_refused() {
    let spec = Spec::none().with(Family::LegNode, Some(Distribution::Normal { sigma: 40.0 }));
    let err = Study::new(spec, paper_trace(10.0), 0).expect_err("too wide");
    assert!(
        matches!(
            err,
            StudyError::Unreachable {
                key: "module1.legs.node_mm",
                ..
            }
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(text.contains("legs[0].node_mm.x"), "{text}");
    assert!(text.contains("too wide for this robot"), "{text}");
    let spec = Spec::none().with(
        Family::Beta,
        Some(Distribution::Uniform { half_width: 15.0 }),
    );
    let err = Study::new(spec, paper_trace(10.0), 0).expect_err("beta below 0");
    assert!(err.to_string().contains("instruments.beta_deg"), "{err}");
}

#[test]
fn robots_that_cannot_be_followed_are_counted_and_reported() {
    // Encoder offsets of up to 250 mm: every leg still reaches (an offset
    // only shifts the reading), but many perturbed platforms cannot be
    // followed from the commanded pose.
    let spec = Spec::none().with(
        Family::EncoderOffset,
        Some(Distribution::Uniform { half_width: 250.0 }),
    );
    let study = Study::new(spec, paper_trace(10.0), 4).expect("valid");
    let results = study.run(0..48, 2, &|_| true).expect("not interrupted");
    let failed = results.failed.iter().filter(|&&f| f).count();
    assert!(failed > 0 && failed < 48, "{failed}");
    assert_eq!(results.failures.len(), failed);
    for (i, f) in results.failed.iter().enumerate() {
        assert_eq!(*f, results.left_tip_dev_mm[i].is_nan(), "{i}");
    }
    let report = Report::new(&results, None, study.spec());
    assert_eq!(report.failed, failed);
    assert!(
        report
            .to_string()
            .contains(&format!("48 perturbed robots, {failed} failed"))
    );
    assert!(report.tip.max.is_finite());
}

#[test]
fn an_interrupted_run_says_so() {
    let study = Study::new(Spec::default(), paper_trace(10.0), 0).expect("valid");
    assert!(study.run(0..200, 2, &|_| false).is_err());
}

#[test]
fn a_perturbation_moves_the_members_it_names() {
    let trace = paper_trace(10.0);
    let spec = Spec::none().with(Family::Rcm, Some(Distribution::Normal { sigma: 0.1 }));
    let study = Study::new(spec, trace.clone(), 3).expect("valid");
    let p: Perturbation = study.perturbation(0);
    let robot = study.robot(0);
    let nominal = trace.robot();
    let moved = robot.left.rcm - nominal.left.rcm;
    assert!((moved.x - p.left.rcm_mm[0]).abs() < 1e-15 && moved.norm() > 0.0);
    assert_eq!(robot.module1, nominal.module1);
    // A port moved alone moves the tip by the same vector (rotated): the
    // tip deviation is constant along the motion and equals its length.
    let d = study.sample(0).expect("followed");
    assert!((d.left_tip_dev_mm - moved.norm()).abs() < 1e-9, "{d:?}");
    assert!(d.pose_position_err_mm < 1e-9);
}

#[test]
fn listed_indices_give_the_rows_of_the_range() {
    let study = Study::new(Spec::default(), paper_trace(10.0), 8).expect("valid");
    let range = study.run(10..30, 2, &|_| true).expect("not interrupted");
    let listed: Vec<u64> = (10..30).rev().collect();
    let rows = study
        .run_indices(&listed, 3, &|_| true)
        .expect("not interrupted");
    assert_eq!(rows.sample, listed);
    for (k, i) in listed.iter().enumerate() {
        let j = (*i - 10) as usize;
        assert_eq!(
            rows.right_tip_dev_mm[k].to_bits(),
            range.right_tip_dev_mm[j].to_bits()
        );
    }
}
