//! The clearance certified over each whole motion against the true minimum,
//! found by evaluating every motion 100 times more densely than its samples;
//! and a fast approach between samples that the samples miss and the
//! certificate catches.

use parasils::kin::{Bodies, ClearancePair, MarginTracker};
use parasils_sim::{
    CERTIFY_TOLERANCE_MM, MotionClearance, PlannedMotion, Scenario, Simulation, procedure,
};

/// The three gaps of `motion` at `t` (s from its start), through the
/// controller and the bodies, as a record has them.
fn gaps_at(sim: &Simulation, motion: &PlannedMotion, t: f64) -> [f64; 3] {
    let s = motion.sample(t);
    let c = sim.controller();
    let step = c
        .step_commanded(&s.platform, &s.left, &s.right, &mut MarginTracker::new())
        .expect("regular between samples");
    let g = Bodies::at(
        &sim.scenario().bodies,
        &step.frame,
        &c.left,
        &step.left.q,
        &c.right,
        &step.right.q,
        s.endoscope.position,
    )
    .and_then(|b| b.clearance())
    .expect("finite");
    ClearancePair::ALL.map(|p| g.get(p).gap)
}

/// Each motion's smallest gap per pair at `factor` evaluations per period
/// of the run's samples.
fn dense_minimum(sim: &Simulation, factor: usize) -> Vec<[f64; 3]> {
    let plan = sim.timeline().expect("a planned run");
    let rate = sim.scenario().rate_hz;
    plan.motions
        .iter()
        .map(|m| {
            let n = m.periods * factor;
            let mut min = [f64::INFINITY; 3];
            for i in 0..=n {
                let t = i as f64 / (rate * factor as f64);
                let g = gaps_at(sim, m, t);
                for k in 0..3 {
                    min[k] = min[k].min(g[k]);
                }
            }
            min
        })
        .collect()
}

fn pairs(c: &MotionClearance) -> [[f64; 3]; 3] {
    let g = |r: &parasils_sim::ClearanceRecord| [r.left_right, r.left_endoscope, r.right_endoscope];
    [g(&c.sampled_mm), g(&c.certified_mm), g(&c.evaluated_mm)]
}

/// Certified never above the dense truth, and within the tolerance of it
/// wherever the refinement converged; the sampled minimum never below it.
fn certified_brackets_the_truth(sim: &Simulation, factor: usize) -> Vec<MotionClearance> {
    let certified = sim.certify_clearance().expect("certifies");
    let truth = dense_minimum(sim, factor);
    assert_eq!(certified.len(), truth.len());
    for (c, want) in certified.iter().zip(&truth) {
        let [sampled, lower, evaluated] = pairs(c);
        for k in 0..3 {
            assert!(
                lower[k] <= want[k] + 1e-12,
                "motion {}, pair {k}: certified {} above the truth {}",
                c.motion,
                lower[k],
                want[k]
            );
            assert!(sampled[k] >= want[k] - 1e-12, "motion {}", c.motion);
            assert!(evaluated[k] <= sampled[k]);
            // The refinement's own evaluations can find a lower point than
            // the dense grid (a kink between its points).
            if c.converged {
                assert!(
                    lower[k] >= want[k].min(evaluated[k]) - CERTIFY_TOLERANCE_MM,
                    "motion {}, pair {k}: certified {} vs truth {}",
                    c.motion,
                    lower[k],
                    want[k]
                );
            }
        }
    }
    certified
}

fn demo() -> Scenario {
    procedure::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../procedures/sils-demo.toml"
    ))
    .expect("the demo loads")
}

#[test]
fn the_paper_turn_is_certified_within_the_tolerance() {
    let sim = Simulation::new(Scenario::paper()).expect("valid");
    let c = certified_brackets_the_truth(&sim, 100);
    assert_eq!(c.len(), 1);
    assert!(c[0].converged);
}

#[test]
fn the_paper_turn_at_a_coarse_rate_is_still_bounded() {
    // 20 Hz: 90 samples over the 4.5 s turn, each interval 50 times longer.
    let sim = Simulation::new(Scenario {
        rate_hz: 20.0,
        ..Scenario::paper()
    })
    .expect("valid");
    let c = certified_brackets_the_truth(&sim, 100);
    assert!(c[0].converged && c[0].evaluations > 0, "{:?}", c[0]);
}

#[test]
fn the_demo_is_certified_within_the_tolerance_of_the_truth() {
    let sim = Simulation::new(demo()).expect("valid");
    let c = certified_brackets_the_truth(&sim, 100);
    assert_eq!(c.len(), 6);
    assert!(c.iter().all(|m| m.converged), "{c:?}");
    // The sampled minimum per motion is the check's.
    let check = sim.procedure_check().expect("checked");
    for (m, c) in check.motions.iter().zip(&c) {
        assert_eq!(c.sampled_mm.left_right, m.clearance_mm.left_right);
        assert_eq!(c.sampled_mm.right_endoscope, m.clearance_mm.right_endoscope);
    }
}

/// The right tip swept across the left shaft, sampled at 5 Hz: its shaft's
/// axis passes through the left one's between two samples (the axes meet:
/// the truth is -5 mm, both radii), so the gap's
/// true minimum (a kink where the axes cross) falls between samples, well
/// below the smallest sampled gap; the certificate is below the truth and
/// within the tolerance of it.
#[test]
fn a_fast_approach_between_samples_is_caught() {
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
    let sim = Simulation::new(scenario).expect("valid");
    let c = certified_brackets_the_truth(&sim, 1000);
    let truth = dense_minimum(&sim, 1000)[0][0];
    let [sampled, certified, evaluated] = pairs(&c[0]);
    assert!(
        truth < sampled[0] - 0.25,
        "the dip is between samples: truth {truth}, sampled {}",
        sampled[0]
    );
    assert!(certified[0] <= truth);
    assert!(certified[0] >= truth.min(evaluated[0]) - CERTIFY_TOLERANCE_MM);
    assert!(c[0].evaluations > 10);
}
