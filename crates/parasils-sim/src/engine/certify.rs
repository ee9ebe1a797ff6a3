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
//!
//! With an anatomy, each in-body part (left shaft, right shaft, endoscope)
//! is certified against each forbidden region the same way, over the same
//! rows and with the same tolerance and depth cap: a region is still, so
//! the second body of the pair is an axis with no speed at all
//! ([`RegionCertificate`]; `docs/model.md`, *Forbidden regions*, says why
//! the first body's bound also bounds its in-body part).

use parasils::kin::{
    AxisAccelerations, AxisState, Bodies, Capsule, ClearancePair, MarginTracker, Probe, certify,
    rate_over,
};
use parasils::motions::MotionSample;
use parasils_anatomy::{Anatomy, Body, InBody};

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
    /// Whether every interval of every pair was certified within the
    /// tolerance before [`CERTIFY_MAX_DEPTH`] halvings.
    pub converged: bool,
    /// How many midpoints were evaluated for the pairs.
    pub evaluations: u64,
    /// With an anatomy, the certificate of each in-body part against each
    /// forbidden region: region by region in the anatomy file's order, and
    /// for each the bodies in [`Body::ALL`]'s order (empty without one).
    pub no_go: Vec<RegionCertificate>,
}

impl MotionClearance {
    /// The smallest certified gap of any body to region `region` (its index
    /// in the anatomy file), mm; `+inf` when no body is inside the patient
    /// during the motion, or there is no such region.
    pub fn no_go_certified_mm(&self, region: usize) -> f64 {
        self.no_go
            .iter()
            .filter(|c| c.region == region)
            .fold(f64::INFINITY, |m, c| m.min(c.certified_mm))
    }
}

/// The certified gap of one in-body part to one forbidden region over one
/// motion.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionCertificate {
    /// The region's index in the anatomy file.
    pub region: usize,
    /// The region's name.
    pub name: String,
    /// Which body's in-body part.
    pub body: Body,
    /// The smallest gap at the motion's rows, mm (`+inf` at rows where
    /// nothing of the body is inside, as the records have it).
    pub sampled_mm: f64,
    /// A lower bound of the gap over the whole motion, mm: never above the
    /// true minimum, and within [`CERTIFY_TOLERANCE_MM`] of the smallest
    /// gap evaluated when `converged`; `+inf` when the body is outside the
    /// patient over the whole motion.
    pub certified_mm: f64,
    /// The smallest gap evaluated (rows and midpoints; where the body is
    /// retracted, the gap of its port), mm.
    pub evaluated_mm: f64,
    /// Whether every interval was certified within the tolerance before
    /// [`CERTIFY_MAX_DEPTH`] halvings.
    pub converged: bool,
    /// How many midpoints were evaluated.
    pub evaluations: u64,
}

/// One probe of the three bodies: the gaps and the three axes' states
/// `[left, right, endoscope]`.
#[derive(Debug, Clone)]
struct Sample {
    gaps: [f64; 3],
    axes: [AxisState<f64>; 3],
    /// `|P''|`, `|alpha|`, each shaft's `|qs1''| + |qs2''|` and `|qs3''|`,
    /// the endoscope's `|d''|`.
    acc: [f64; 7],
    /// Per forbidden region, the gap of each body's in-body part
    /// (`[left, right, endoscope]`), or of its port where nothing is
    /// inside, mm (empty without an anatomy).
    no_go: Vec<[f64; 3]>,
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
            no_go: Vec::new(),
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
        if let Some(anatomy) = &self.scenario().anatomy {
            for (r, region) in anatomy.regions.iter().enumerate() {
                for (b, body) in Body::ALL.into_iter().enumerate() {
                    let c = self.certify_region(motion, &rows, (r, b), axis_acc(b))?;
                    out.no_go.push(RegionCertificate {
                        region: r,
                        name: region.name.clone(),
                        body,
                        ..c
                    });
                }
            }
        }
        Ok(out)
    }

    /// The certificate of body `b`'s in-body part against region `r` over
    /// `motion`, from its `rows`; `acc` bounds the body's rates' rates. The
    /// region is the still second body of each probe.
    fn certify_region(
        &self,
        motion: &PlannedMotion,
        rows: &[Sample],
        (r, b): (usize, usize),
        acc: AxisAccelerations<f64>,
    ) -> Result<RegionCertificate, (f64, SimulationError)> {
        let rate = self.scenario().rate_hz;
        let still = AxisState::default();
        let accs = [acc, AxisAccelerations::default()];
        let to_probe = |s: &Sample| Probe {
            gap: s.no_go[r][b],
            axes: [s.axes[b], still],
        };
        let inside = |s: &Sample| s.axes[b].depth > 0.0;
        let mut out = RegionCertificate {
            region: r,
            name: String::new(),
            body: Body::ALL[b],
            sampled_mm: f64::INFINITY,
            certified_mm: f64::INFINITY,
            evaluated_mm: f64::INFINITY,
            converged: true,
            evaluations: 0,
        };
        for s in rows {
            if inside(s) {
                out.sampled_mm = out.sampled_mm.min(s.no_go[r][b]);
            }
            out.evaluated_mm = out.evaluated_mm.min(s.no_go[r][b]);
        }
        for (j, w) in rows.windows(2).enumerate() {
            let [r0, r1] = [&w[0], &w[1]];
            let (t0, t1) = (j as f64 / rate, (j + 1) as f64 / rate);
            // Outside at both rows and unable to reach the port between
            // them: nothing of the body is inside over the interval.
            let (a0, a1) = (&r0.axes[b], &r1.axes[b]);
            let swing = rate_over(a0.depth_rate, a1.depth_rate, acc.depth, t1 - t0) * (t1 - t0);
            if !inside(r0) && !inside(r1) && a0.depth + a1.depth + swing <= 0.0 {
                continue;
            }
            let c = certify(
                (t0, to_probe(r0)),
                (t1, to_probe(r1)),
                out.evaluated_mm,
                &accs,
                CERTIFY_TOLERANCE_MM,
                CERTIFY_MAX_DEPTH,
                |t| {
                    let s = self.probe(&motion.sample(t), motion.start_s + t)?;
                    Ok(to_probe(&s))
                },
            )?;
            out.evaluated_mm = out.evaluated_mm.min(c.sampled);
            out.certified_mm = out.certified_mm.min(c.certified);
            out.converged &= c.converged;
            out.evaluations += u64::from(c.evaluations);
        }
        if rows.len() == 1 {
            out.certified_mm = out.sampled_mm;
        }
        if out.certified_mm.is_nan() {
            return Err((
                motion.start_s,
                SimulationError::Kinematics {
                    t: motion.start_s,
                    sample: None,
                    error: parasils::kin::Error::NonFinite {
                        what: "certified gap to a forbidden region",
                        value: out.certified_mm,
                    },
                },
            ));
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
        let placed = Bodies::at(
            bodies,
            &step.frame,
            &controller.left,
            &step.left.q,
            &controller.right,
            &step.right.q,
            depth,
        )
        .map_err(fail)?;
        let gaps = placed.clearance().map_err(fail)?;
        let no_go = match &self.scenario().anatomy {
            None => Vec::new(),
            Some(anatomy) => {
                region_gaps(anatomy, &placed, [step.left.q.qs3, step.right.q.qs3, depth]).map_err(
                    |error| {
                        (
                            t,
                            SimulationError::Anatomy {
                                t,
                                sample: None,
                                error: Box::new(error),
                            },
                        )
                    },
                )?
            }
        };
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
            no_go,
        })
    }
}

/// The in-body part of `capsule` (`inserted_mm` of its axis from the tip),
/// or, with nothing inside, its port alone: the point where the in-body
/// part starts to grow, so that the gap stays continuous as the body
/// enters and leaves.
fn in_body_or_port(body: Body, capsule: &Capsule<f64>, inserted_mm: f64) -> InBody {
    InBody::from_tip(body, capsule, inserted_mm).unwrap_or_else(|| {
        let axis = capsule.axis.end - capsule.axis.start;
        let length = axis.norm();
        let port = if length > 0.0 {
            capsule.axis.start + axis * (inserted_mm / length)
        } else {
            capsule.axis.start
        };
        InBody {
            body,
            tip: port,
            port,
            radius: capsule.radius,
        }
    })
}

/// The gap of each body's in-body part (or port) to each region of
/// `anatomy`; `inserted_mm` is each body's insertion, `[left, right,
/// endoscope]`.
fn region_gaps(
    anatomy: &Anatomy,
    bodies: &Bodies<f64>,
    inserted_mm: [f64; 3],
) -> Result<Vec<[f64; 3]>, parasils_anatomy::AnatomyError> {
    let capsules = [&bodies.left, &bodies.right, &bodies.endoscope];
    let parts: [InBody; 3] =
        core::array::from_fn(|b| in_body_or_port(Body::ALL[b], capsules[b], inserted_mm[b]));
    let mut out = Vec::with_capacity(anatomy.regions.len());
    for region in &anatomy.regions {
        let mut gaps = [0.0; 3];
        for (g, part) in gaps.iter_mut().zip(&parts) {
            *g = Anatomy::gap(region, part)?;
        }
        out.push(gaps);
    }
    Ok(out)
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
