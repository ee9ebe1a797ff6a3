//! The gap of each in-body part to each forbidden region, certified over
//! each whole motion, against the true minimum found by evaluating every
//! motion 100 times more densely than its samples (with the anatomy crate's
//! own in-body parts, `InBody::of`, and its gap); and a fast pass by a
//! region between samples that the samples miss and the certificate
//! catches.

use std::sync::Arc;

use nalgebra::Vector3;
use parasils::kin::{Bodies, MarginTracker};
use parasils_anatomy::{Anatomy, Body, InBody, Mesh, Region, Shape};
use parasils_sim::{
    CERTIFY_TOLERANCE_MM, MotionClearance, PlannedMotion, Scenario, Simulation, procedure,
};

/// The in-body parts of `motion` at `t` (s from its start), as a record
/// has them (`None` for a body with nothing inside).
fn parts_at(sim: &Simulation, motion: &PlannedMotion, t: f64) -> [Option<InBody>; 3] {
    let s = motion.sample(t);
    let c = sim.controller();
    let step = c
        .step_commanded(&s.platform, &s.left, &s.right, &mut MarginTracker::new())
        .expect("regular between samples");
    let bodies = Bodies::at(
        &sim.scenario().bodies,
        &step.frame,
        &c.left,
        &step.left.q,
        &c.right,
        &step.right.q,
        s.endoscope.position,
    )
    .expect("finite");
    InBody::of(
        &bodies,
        step.left.q.qs3,
        step.right.q.qs3,
        s.endoscope.position,
    )
}

/// Per motion, per region, per body: the smallest gap (mm) and its time (s
/// from the motion's start).
type Truth = Vec<Vec<[(f64, f64); 3]>>;

/// Each motion's smallest gap per region and body (`[region][body]`, `+inf`
/// while the body is outside) at `factor` evaluations per period, and the
/// time of each (s from the motion's start).
fn dense_minimum(sim: &Simulation, factor: usize) -> Truth {
    let plan = sim.timeline().expect("a planned run");
    let anatomy = sim.scenario().anatomy.clone().expect("an anatomy");
    let rate = sim.scenario().rate_hz;
    plan.motions
        .iter()
        .map(|m| {
            let mut min = vec![[(f64::INFINITY, 0.0); 3]; anatomy.regions.len()];
            for i in 0..=m.periods * factor {
                let t = i as f64 / (rate * factor as f64);
                let parts = parts_at(sim, m, t);
                for (r, region) in anatomy.regions.iter().enumerate() {
                    for (b, part) in parts.iter().enumerate() {
                        let Some(part) = part else { continue };
                        let gap = Anatomy::gap(region, part).expect("a gap");
                        if gap < min[r][b].0 {
                            min[r][b] = (gap, t);
                        }
                    }
                }
            }
            min
        })
        .collect()
}

/// Certified never above the dense truth, and within the tolerance of it
/// wherever the refinement converged; the sampled minimum never below it.
/// Returns the certificates and the truth.
fn certified_brackets_the_truth(sim: &Simulation, factor: usize) -> (Vec<MotionClearance>, Truth) {
    let certified = sim.certify_clearance().expect("certifies");
    let truth = dense_minimum(sim, factor);
    let regions = &sim.scenario().anatomy.as_ref().expect("an anatomy").regions;
    assert_eq!(certified.len(), truth.len());
    for (c, want) in certified.iter().zip(&truth) {
        assert_eq!(c.no_go.len(), 3 * regions.len());
        for g in &c.no_go {
            let (r, b) = (g.region, Body::ALL.iter().position(|x| *x == g.body));
            let (want, _) = want[r][b.expect("a body")];
            assert_eq!(g.name, regions[r].name);
            let at = format!(
                "motion {}, {} to {}: {g:?}, truth {want}",
                c.motion, g.body, g.name
            );
            assert!(g.certified_mm <= want + 1e-12, "above the truth: {at}");
            assert!(
                g.sampled_mm >= want - 1e-12,
                "sampled below the truth: {at}"
            );
            assert!(g.evaluated_mm <= g.sampled_mm, "{at}");
            if want.is_infinite() {
                // Outside over the whole motion: nothing to certify.
                assert!(g.certified_mm.is_infinite(), "{at}");
            } else {
                assert!(g.converged, "{at}");
                assert!(
                    g.certified_mm >= want.min(g.evaluated_mm) - CERTIFY_TOLERANCE_MM,
                    "more than the tolerance below: {at}"
                );
            }
        }
        // The per-region summary is the smallest over the bodies.
        for r in 0..regions.len() {
            let smallest = c
                .no_go
                .iter()
                .filter(|g| g.region == r)
                .map(|g| g.certified_mm)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(c.no_go_certified_mm(r), smallest);
        }
    }
    (certified, truth)
}

fn region(name: &str, shape: Shape) -> Region {
    Region::new(name.into(), shape).expect("valid")
}

fn sphere(centre: Vector3<f64>, radius_mm: f64) -> Shape {
    Shape::Sphere {
        centre_mm: centre.into(),
        radius_mm,
    }
}

/// A ball beside where `body`'s in-body part is at `t` of the first
/// motion: `clear_mm` from its `end` (the tip, or the port), off the axis
/// and off that end's velocity (by finite differences), so that the gap is
/// smallest near `t`.
fn ball_beside(sim: &Simulation, b: usize, tip: bool, t: f64, clear_mm: f64) -> Shape {
    let motion = &sim.timeline().expect("planned").motions[0];
    let at = |t: f64| {
        let p = parts_at(sim, motion, t)[b].expect("inside");
        (
            if tip { p.tip } else { p.port },
            (p.port - p.tip).normalize(),
        )
    };
    let h = 1e-5;
    let (end, axis) = at(t);
    let velocity = (at(t + h).0 - at(t - h).0) / (2.0 * h);
    let off = axis.cross(&velocity).normalize();
    let radius = 4.0;
    sphere(end + off * (radius + 2.5 + clear_mm), radius)
}

/// The paper's turn at 20 Hz with a ball 1 mm beside the left port half
/// way between two samples: the gap is smallest between samples, and the
/// certificate is below the truth and within the tolerance of it.
#[test]
fn a_ball_by_the_left_shaft_in_the_paper_turn_is_certified() {
    let coarse = Scenario {
        rate_hz: 20.0,
        ..Scenario::paper()
    };
    let sim = Simulation::new(coarse.clone()).expect("valid");
    let t_star = 40.5 / 20.0;
    let ball = ball_beside(&sim, 0, false, t_star, 1.0);
    let sim = Simulation::new(Scenario {
        anatomy: Some(Arc::new(Anatomy {
            file: "test.toml".into(),
            regions: vec![region("ball", ball)],
        })),
        ..coarse
    })
    .expect("clear of the ball");
    let (c, truth) = certified_brackets_the_truth(&sim, 100);
    let left = &c[0].no_go[0];
    let (want, at) = truth[0][0][0];
    assert_eq!(left.body, Body::Left);
    // The dense minimum is about 1 mm and falls between two samples.
    assert!((want - 1.0).abs() < 0.05, "truth {want} at {at}");
    let period = at * 20.0;
    assert!((period - period.round()).abs() > 0.1, "at {at} s");
    assert!(want < left.sampled_mm, "{left:?}");
    assert!(left.evaluations > 0, "{left:?}");
}

fn demo() -> Scenario {
    procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))
    .expect("the demo loads")
}

/// The demo procedure with the shipped anatomy (its organ a 720-triangle
/// STL mesh) and a small closed ellipsoid mesh 12 mm below the left tip's
/// goal in "left tip to the tissue": every motion, region and body
/// certified within the tolerance of the dense truth, the endoscope outside
/// while it is not inserted.
#[test]
fn the_demo_with_meshes_is_certified_within_the_tolerance_of_the_truth() {
    let mut anatomy = Anatomy::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/anatomy/demo.toml"
    ))
    .expect("the shipped anatomy loads");
    let mesh = Mesh::ellipsoid([60.0, -40.0, -642.0], [6.0, 6.0, 4.0], 12, 16).expect("a mesh");
    assert!(mesh.is_closed());
    anatomy.regions.push(region(
        "nodule",
        Shape::Mesh {
            file: "nodule.stl".into(),
            translation_mm: [0.0; 3],
            mesh,
            solid: true,
        },
    ));
    let sim = Simulation::new(Scenario {
        anatomy: Some(Arc::new(anatomy)),
        ..demo()
    })
    .expect("the demo clears every region");
    let (c, truth) = certified_brackets_the_truth(&sim, 100);
    assert_eq!(c.len(), 6);
    // The nodule is the nearest region to the left shaft in motion 2, a
    // few mm away.
    let nodule = c[2]
        .no_go
        .iter()
        .find(|g| g.name == "nodule" && g.body == Body::Left);
    let nodule = nodule.expect("certified");
    assert!(
        nodule.certified_mm > 1.0 && nodule.certified_mm < 10.0,
        "{nodule:?}"
    );
    // The endoscope is outside in the first motion (depth 0) and inside
    // from the second's first period on.
    assert!(truth[0].iter().all(|r| r[2].0.is_infinite()));
    assert!(truth[1].iter().all(|r| r[2].0.is_finite()));
    // The sampled minima are the check's, region by region.
    let check = sim.procedure_check().expect("checked");
    for (m, c) in check.motions.iter().zip(&c) {
        for (r, sampled) in m.no_go_mm.iter().enumerate() {
            let smallest = c
                .no_go
                .iter()
                .filter(|g| g.region == r)
                .map(|g| g.sampled_mm)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(smallest, *sampled, "motion {}, region {r}", c.motion);
        }
    }
}

/// The right tip swept at 40 mm/s past a ball, sampled at 5 Hz: the tip
/// passes 1 mm from the ball half way between two samples, 8 mm apart, so
/// the samples see more than 1.5 mm of gap; the certificate is below the
/// truth and within the tolerance of it.
#[test]
fn a_fast_pass_by_a_region_between_samples_is_caught() {
    let text = r#"
pose = [15, 20, -500, -15, 10, -60]
tip_left_mm = [50, -50, -620]
tip_right_mm = [92.9107, 68.3284, -659.5392]

[[motion]]
type = "manipulate"
instrument = "right"
tip_mm = [-60.7824, 27.3465, -620.5019]
velocity_mm_s = 40
acceleration_mm_s2 = 40
"#;
    let mut scenario = procedure::parse(text, "test", std::path::Path::new(".")).expect("reads");
    scenario.rate_hz = 5.0;
    let sim = Simulation::new(scenario.clone()).expect("valid");
    // Half way through the motion, in the middle of a period.
    let motion = &sim.timeline().expect("planned").motions[0];
    let t_star = ((motion.periods / 2) as f64 + 0.5) / 5.0;
    let ball = ball_beside(&sim, 1, true, t_star, 1.0);
    scenario.anatomy = Some(Arc::new(Anatomy {
        file: "test.toml".into(),
        regions: vec![region("ball", ball)],
    }));
    let sim = Simulation::new(scenario).expect("valid");
    let (c, truth) = certified_brackets_the_truth(&sim, 1000);
    let right = &c[0].no_go[1];
    let (want, _) = truth[0][0][1];
    assert_eq!(right.body, Body::Right);
    assert!((want - 1.0).abs() < 0.05, "truth {want}");
    assert!(
        want < right.sampled_mm - 0.5,
        "the dip is between samples: truth {want}, sampled {}",
        right.sampled_mm
    );
    assert!(right.certified_mm <= want);
    assert!(right.certified_mm >= want.min(right.evaluated_mm) - CERTIFY_TOLERANCE_MM);
    assert!(right.evaluations > 10, "{right:?}");
}
