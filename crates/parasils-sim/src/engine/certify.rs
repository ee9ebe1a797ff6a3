//! The smallest clearance of each pair of bodies over each whole motion of a
//! planned run, certified between samples: the driver of
//! [`parasils::kin::certify`] over a timeline's motions.
//!
//! Each motion is probed at its rows (the samples of the run) and, where the
//! bound between two rows is loose, at midpoints of the motion's law. A
//! probe is one controller step of the law's state at that time: the gap of
//! each pair and each body's [`AxisState`] (the platform's speed and angular
//! speed, each shaft's `qs3` with its rate and `|qs1'| + |qs2'|`, the
//! endoscope's depth and its rate). The rates' own bounds between rows
//! ([`AxisAccelerations`]) are twice the largest of each at the motion's
//! rows, and for the joints at least the actuators' acceleration limits
//! (`docs/model.md`, *Clearance*, says why and what that assumes).

use parasils::kin::{
    AxisAccelerations, AxisState, Bodies, ClearancePair, MarginTracker, Probe, certify,
};
use parasils::motions::MotionSample;

use super::error::SimulationError;
use super::procedure::PlannedMotion;
use super::simulation::Simulation;
use crate::record::ClearanceRecord;

/// The tolerance of the certificate, mm: refinement stops where the lower
/// bound is within this of the smallest gap evaluated.
pub const CERTIFY_TOLERANCE_MM: f64 = 1e-3;

/// How many times an interval between two rows may be halved.
pub const CERTIFY_MAX_DEPTH: u32 = 24;

/// The certified clearance of one motion.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionClearance {
    /// The motion's index in the timeline.
    pub motion: usize,
    /// The smallest gap of each pair at the motion's rows, mm (for a motion
    /// cut short, its rows and the row the next one starts from).
    pub sampled_mm: ClearanceRecord,
    /// A lower bound of each pair's gap over the whole motion, mm: never
    /// above the true minimum, and within [`CERTIFY_TOLERANCE_MM`] of it
    /// when `converged`.
    pub certified_mm: ClearanceRecord,
    /// The smallest gap evaluated (rows and midpoints), mm: the true
    /// minimum lies between this and `certified_mm`.
    pub evaluated_mm: ClearanceRecord,
    /// Whether every interval was certified within the tolerance before
    /// [`CERTIFY_MAX_DEPTH`] halvings.
    pub converged: bool,
    /// How many midpoints were evaluated.
    pub evaluations: u64,
}

/// One probe of the three bodies: the gaps and the three axes' states
/// `[left, right, endoscope]`.
#[derive(Debug, Clone, Copy)]
struct Sample {
    gaps: [f64; 3],
    axes: [AxisState<f64>; 3],
    /// `|P''|`, `|alpha|`, each shaft's `|qs1''| + |qs2''|` and `|qs3''|`,
    /// the endoscope's `|d''|`.
    acc: [f64; 7],
}

/// The bodies of each pair, as indices into [`Sample::axes`].
const PAIRS: [(ClearancePair, [usize; 2]); 3] = [
    (ClearancePair::LeftRight, [0, 1]),
    (ClearancePair::LeftEndoscope, [0, 2]),
    (ClearancePair::RightEndoscope, [1, 2]),
];

impl Simulation {
    /// The certified smallest clearance of every motion of a planned run
    /// (the paper's turn, a procedure), in order; empty for an online run,
    /// which is not planned ahead.
    ///
    /// # Errors
    /// The kinematics' error at a probe between rows (a state that a
    /// sample does not show, placed in its motion), or a gap that is not a
    /// number.
    pub fn certify_clearance(&self) -> Result<Vec<MotionClearance>, SimulationError> {
        let Some(plan) = self.timeline() else {
            return Ok(Vec::new());
        };
        plan.motions
            .iter()
            .enumerate()
            .map(|(m, motion)| {
                self.certify_motion(motion, m)
                    .map_err(|(t, error)| plan.in_motion(m, t - motion.start_s, error))
            })
            .collect()
    }

    /// One motion's certificate; an error with its time from the run's
    /// start.
    fn certify_motion(
        &self,
        motion: &PlannedMotion,
        m: usize,
    ) -> Result<MotionClearance, (f64, SimulationError)> {
        let rate = self.scenario().rate_hz;
        let rows: Vec<Sample> = (0..=motion.periods)
            .map(|j| {
                let t = j as f64 / rate;
                self.probe(&motion.sample_index(j), motion.start_s + t)
            })
            .collect::<Result<_, _>>()?;
        let mut acc = [0.0_f64; 7];
        for s in &rows {
            for (a, x) in acc.iter_mut().zip(&s.acc) {
                *a = a.max(2.0 * x);
            }
        }
        let limits = &self.controller().limits.acceleration;
        // Actuators 6..9 are the left module's qs1, qs2, qs3; 9..12 the right's.
        let tilt_floor = [limits[6] + limits[7], limits[9] + limits[10]];
        let qs3_floor = [limits[8], limits[11]];
        let axis_acc = |body: usize| AxisAccelerations {
            platform: acc[0],
            omega: acc[1],
            depth: match body {
                0 | 1 => acc[3 + 2 * body].max(qs3_floor[body]),
                _ => acc[6],
            },
            tilt: match body {
                0 | 1 => acc[2 + 2 * body].max(tilt_floor[body]),
                _ => 0.0,
            },
        };
        let mut out = MotionClearance {
            motion: m,
            sampled_mm: ClearanceRecord::splat(f64::INFINITY),
            certified_mm: ClearanceRecord::splat(f64::INFINITY),
            evaluated_mm: ClearanceRecord::splat(f64::INFINITY),
            converged: true,
            evaluations: 0,
        };
        for (k, (pair, [a, b])) in PAIRS.iter().enumerate() {
            let acc = [axis_acc(*a), axis_acc(*b)];
            let to_probe = |s: &Sample| Probe {
                gap: s.gaps[k],
                axes: [s.axes[*a], s.axes[*b]],
            };
            let mut sampled = f64::INFINITY;
            let mut evaluated = f64::INFINITY;
            let mut certified = f64::INFINITY;
            for s in &rows {
                sampled = sampled.min(s.gaps[k]);
            }
            // The smallest gap seen so far is the reference every interval
            // is certified against; start from the rows'.
            for (j, pair_rows) in rows.windows(2).enumerate() {
                let [r0, r1] = [&pair_rows[0], &pair_rows[1]];
                let (t0, t1) = (j as f64 / rate, (j + 1) as f64 / rate);
                let c = certify_between(
                    self,
                    motion,
                    (t0, to_probe(r0)),
                    (t1, to_probe(r1)),
                    &acc,
                    sampled.min(evaluated),
                    k,
                    *a,
                    *b,
                )?;
                evaluated = evaluated.min(c.sampled);
                certified = certified.min(c.certified);
                out.converged &= c.converged;
                out.evaluations += u64::from(c.evaluations);
            }
            if rows.len() == 1 {
                certified = sampled;
            }
            evaluated = evaluated.min(sampled);
            if certified.is_nan() {
                return Err((
                    motion.start_s,
                    SimulationError::Kinematics {
                        t: motion.start_s,
                        sample: None,
                        error: parasils::kin::Error::NonFinite {
                            what: "certified clearance",
                            value: certified,
                        },
                    },
                ));
            }
            out.sampled_mm.set(*pair, sampled);
            out.certified_mm.set(*pair, certified);
            out.evaluated_mm.set(*pair, evaluated);
        }
        Ok(out)
    }

    /// The bodies at `sample` (at `t`, s from the run's start).
    fn probe(&self, sample: &MotionSample<f64>, t: f64) -> Result<Sample, (f64, SimulationError)> {
        let fail = |error| {
            (
                t,
                SimulationError::Kinematics {
                    t,
                    sample: None,
                    error,
                },
            )
        };
        let controller = self.controller();
        let step = controller
            .step_commanded(
                &sample.platform,
                &sample.left,
                &sample.right,
                &mut MarginTracker::new(),
            )
            .map_err(fail)?;
        let bodies = &self.scenario().bodies;
        let depth = sample.endoscope.position;
        let gaps = Bodies::at(
            bodies,
            &step.frame,
            &controller.left,
            &step.left.q,
            &controller.right,
            &step.right.q,
            depth,
        )
        .and_then(|b| b.clearance())
        .map_err(fail)?;
        let frame = &step.frame;
        let (speed, omega) = (frame.velocity.norm(), frame.omega.norm());
        let shaft = |rcm: f64, s: &parasils::kin::InstrumentSolution<f64>| AxisState {
            platform_speed: speed,
            omega,
            port_offset: rcm,
            depth: s.q.qs3,
            depth_rate: s.q_dot.qs3.abs(),
            tilt_rate: s.q_dot.qs1.abs() + s.q_dot.qs2.abs(),
            length: bodies.instrument_length,
        };
        let (l, r) = (&step.left, &step.right);
        Ok(Sample {
            gaps: [
                gaps.left_right.gap,
                gaps.left_endoscope.gap,
                gaps.right_endoscope.gap,
            ],
            axes: [
                shaft(controller.left.geometry().rcm.norm(), l),
                shaft(controller.right.geometry().rcm.norm(), r),
                AxisState {
                    platform_speed: speed,
                    omega,
                    port_offset: 0.0,
                    depth,
                    depth_rate: sample.endoscope.velocity.abs(),
                    tilt_rate: 0.0,
                    length: bodies.endoscope_length,
                },
            ],
            acc: [
                frame.acceleration.norm(),
                frame.alpha.norm(),
                l.q_ddot.qs1.abs() + l.q_ddot.qs2.abs(),
                l.q_ddot.qs3.abs(),
                r.q_ddot.qs1.abs() + r.q_ddot.qs2.abs(),
                r.q_ddot.qs3.abs(),
                sample.endoscope.acceleration.abs(),
            ],
        })
    }
}

/// The certificate of pair `k` (bodies `a`, `b`) between two rows of
/// `motion` (times from its start), refined against `reference`, the
/// smallest gap known so far.
#[allow(clippy::too_many_arguments)]
fn certify_between(
    sim: &Simulation,
    motion: &PlannedMotion,
    (t0, p0): (f64, Probe<f64>),
    (t1, p1): (f64, Probe<f64>),
    acc: &[AxisAccelerations<f64>; 2],
    reference: f64,
    k: usize,
    a: usize,
    b: usize,
) -> Result<parasils::kin::Certificate<f64>, (f64, SimulationError)> {
    certify(
        (t0, p0),
        (t1, p1),
        reference,
        acc,
        CERTIFY_TOLERANCE_MM,
        CERTIFY_MAX_DEPTH,
        |t| {
            let s = sim.probe(&motion.sample(t), motion.start_s + t)?;
            Ok(Probe {
                gap: s.gaps[k],
                axes: [s.axes[a], s.axes[b]],
            })
        },
    )
}
