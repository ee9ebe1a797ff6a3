//! Pose planning: which poses to measure so that the identified parameters
//! are seen best.
//!
//! A large set of random candidate poses is drawn around a centre
//! (uniformly, within `+-position_range_mm` on each axis and
//! `+-angle_range_deg` on each Euler angle) and kept when the nominal robot
//! reaches it with every actuator at least `stroke_margin_mm` inside its
//! stroke, every serial margin at least `serial_margin_min` and the parallel
//! margin at least `parallel_margin_min`. From them, `poses` are chosen
//! greedily, each maximising the determinant of the information matrix
//! `J^T J` of the scaled identification Jacobian over the identifiable
//! parameters (D-optimality, with a small ridge so that the first poses
//! count), then improved by exchange: each chosen pose is replaced by the
//! candidate, among some drawn at random, that most increases the smallest
//! singular value. The report compares the result with random sets of the
//! same size drawn from the same candidates.

use nalgebra::{DMatrix, SymmetricEigen};
use parasils_io::Rng;
use parasils_kin::presets::START_POSE_MM_DEG;
use parasils_kin::{Actuators, ParallelGeometry, ParallelRobot, Pose};
use serde::Serialize;

use crate::error::CalibError;
use crate::fit::{STRUCTURAL_DEFICIENCY, observability, scaled_jacobian};
use crate::identify;
use crate::model::{Model, PoseEval, PoseMmDeg};
use crate::params::{PARAMETERS, ParameterMap};
use crate::report::Observability;

/// The planner's options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanOptions {
    /// The poses to choose.
    pub poses: usize,
    /// The admissible random candidates to choose from.
    pub candidates: usize,
    /// The random generator's seed.
    pub seed: u64,
    /// The centre of the candidates; `None`: the pose at which every
    /// actuator is at mid-stroke (by the forward kinematics from the paper's
    /// start pose), or the start pose itself when a stroke is infinite.
    pub center: Option<PoseMmDeg>,
    /// Half the range of each coordinate about the centre, mm.
    pub position_range_mm: f64,
    /// Half the range of each Euler angle about the centre, deg.
    pub angle_range_deg: f64,
    /// The least distance of every actuator from its stroke's ends, mm.
    pub stroke_margin_mm: f64,
    /// The least serial margin `|e.u| / l`.
    pub serial_margin_min: f64,
    /// The least parallel margin.
    pub parallel_margin_min: f64,
    /// Exchange rounds over the chosen poses.
    pub exchange_rounds: usize,
    /// Candidates tried per chosen pose and round.
    pub exchange_tries: usize,
    /// Random sets drawn for the comparison.
    pub random_sets: usize,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            poses: 50,
            candidates: 2000,
            seed: 1,
            center: None,
            position_range_mm: 120.0,
            angle_range_deg: 25.0,
            stroke_margin_mm: 5.0,
            serial_margin_min: 0.3,
            parallel_margin_min: 0.05,
            exchange_rounds: 4,
            exchange_tries: 40,
            random_sets: 21,
        }
    }
}

/// The planner's comparison of its choice with random ones.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanReport {
    /// Poses chosen.
    pub poses: usize,
    /// Admissible candidates drawn.
    pub candidates: usize,
    /// Random draws made to find them.
    pub draws: usize,
    /// The centre of the candidates.
    pub center: PoseMmDeg,
    /// The identifiable parameters the indices are of.
    pub parameters: usize,
    /// The chosen poses' observability.
    pub planned: Observability,
    /// The median of the random sets' smallest singular values.
    pub random_singular_value_min_median: f64,
    /// The random sets' smallest singular values, sorted.
    pub random_singular_value_min: Vec<f64>,
    /// The median random set's noise amplification index.
    pub random_noise_amplification_index_median: f64,
    /// Planned smallest singular value over the random median.
    pub ratio_singular_value_min: f64,
}

/// The chosen poses, their nominal readings, and the comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The poses.
    pub poses: Vec<PoseMmDeg>,
    /// The nominal robot's readings at each.
    pub q_mm: Vec<[f64; 6]>,
    /// The comparison with random poses.
    pub report: PlanReport,
}

fn pose_of(p: &PoseMmDeg) -> Pose<f64> {
    Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5])
}

/// The pose at mid-stroke, or the paper's start pose.
fn default_center(robot: &ParallelRobot<f64>) -> PoseMmDeg {
    let start = START_POSE_MM_DEG;
    let mid = robot
        .geometry()
        .guides
        .map(|g| 0.5 * (g.stroke.min + g.stroke.max));
    if mid.iter().all(|v| v.is_finite())
        && let Ok(fk) = robot.fk(&Actuators(mid), &pose_of(&start))
    {
        let p = fk.pose;
        return [
            p.x,
            p.y,
            p.z,
            p.psi.to_degrees(),
            p.theta.to_degrees(),
            p.phi.to_degrees(),
        ];
    }
    start
}

fn check_options(o: &PlanOptions) -> Result<(), CalibError> {
    let positive = [
        ("poses", o.poses as f64),
        ("candidates", o.candidates as f64),
        ("position_range_mm", o.position_range_mm),
        ("angle_range_deg", o.angle_range_deg),
    ];
    for (what, value) in positive {
        if !(value > 0.0 && value.is_finite()) {
            return Err(CalibError::Option {
                what,
                value,
                reason: "must be > 0",
            });
        }
    }
    if o.candidates < o.poses {
        return Err(CalibError::Option {
            what: "candidates",
            value: o.candidates as f64,
            reason: "must be at least the poses to choose",
        });
    }
    for (what, value) in [
        ("stroke_margin_mm", o.stroke_margin_mm),
        ("serial_margin_min", o.serial_margin_min),
        ("parallel_margin_min", o.parallel_margin_min),
    ] {
        if !(value >= 0.0 && value.is_finite()) {
            return Err(CalibError::Option {
                what,
                value,
                reason: "must be >= 0",
            });
        }
    }
    Ok(())
}

/// Admissible random poses, their readings, and the draws made.
type Candidates = (Vec<PoseMmDeg>, Vec<[f64; 6]>, usize);

/// Admissible random poses: `(pose, readings, draws made)`.
fn candidates(
    robot: &ParallelRobot<f64>,
    center: &PoseMmDeg,
    o: &PlanOptions,
    rng: &mut Rng,
) -> Result<Candidates, CalibError> {
    let max_draws = 200 * o.candidates;
    let (mut poses, mut qs) = (Vec::new(), Vec::new());
    let mut draws = 0;
    while poses.len() < o.candidates && draws < max_draws {
        draws += 1;
        let p: PoseMmDeg = core::array::from_fn(|k| {
            let range = if k < 3 {
                o.position_range_mm
            } else {
                o.angle_range_deg
            };
            center[k] + rng.uniform(-range, range)
        });
        let pose = pose_of(&p);
        let (Ok(q), Ok(m)) = (robot.ik(&pose), robot.margins(&pose)) else {
            continue;
        };
        let inside = robot.geometry().guides.iter().zip(&q.0).all(|(g, &qj)| {
            qj >= g.stroke.min + o.stroke_margin_mm && qj <= g.stroke.max - o.stroke_margin_mm
        });
        if inside && m.serial_min >= o.serial_margin_min && m.parallel >= o.parallel_margin_min {
            poses.push(p);
            qs.push(q.0);
        }
    }
    if poses.len() < o.candidates {
        return Err(CalibError::TooFewCandidates {
            found: poses.len(),
            attempts: draws,
            needed: o.candidates,
        });
    }
    Ok((poses, qs, draws))
}

/// The smallest eigenvalue of a symmetric matrix.
fn min_eigenvalue(a: &DMatrix<f64>) -> f64 {
    SymmetricEigen::new(a.clone()).eigenvalues.min()
}

/// Chooses `options.poses` poses for the calibration of `nominal`.
///
/// Errors: invalid options or robot, too few admissible candidates
/// ([`CalibError::TooFewCandidates`]).
pub fn plan(nominal: &ParallelGeometry<f64>, options: &PlanOptions) -> Result<Plan, CalibError> {
    check_options(options)?;
    let robot = ParallelRobot::new(*nominal)?;
    let map = ParameterMap::new(nominal)?;
    let center = options.center.unwrap_or_else(|| default_center(&robot));
    let mut rng = Rng::new(options.seed);
    let (poses, qs, draws) = candidates(&robot, &center, options, &mut rng)?;
    let model = Model::new(&map, &map.nominal_vector());
    let evals: Vec<PoseEval> = poses
        .iter()
        .filter_map(|p| model.eval(p, true).ok())
        .collect();
    let scales = map.scales();
    let all: Vec<usize> = (0..PARAMETERS).collect();
    let tolerance = crate::fit::FitOptions::default().rank_tolerance;
    let selection = identify::select(&scaled_jacobian(&evals, &all, &scales), tolerance, &scales);
    let kept = selection.kept;
    let n = kept.len();
    let blocks: Vec<DMatrix<f64>> = evals
        .iter()
        .map(|e| DMatrix::from_fn(6, n, |j, c| e.d_params[j][kept[c]] * scales[kept[c]]))
        .collect();
    // Greedy D-optimal choice with Woodbury updates of the inverse.
    let ridge = 1e-6;
    let mut inverse = DMatrix::<f64>::identity(n, n) / ridge;
    let mut chosen: Vec<usize> = Vec::with_capacity(options.poses);
    let mut used = vec![false; blocks.len()];
    for _ in 0..options.poses {
        let mut best = (f64::NEG_INFINITY, 0);
        for (c, b) in blocks.iter().enumerate() {
            if used[c] {
                continue;
            }
            let s = DMatrix::<f64>::identity(6, 6) + b * &inverse * b.transpose();
            let gain = s.cholesky().map_or(f64::NEG_INFINITY, |ch| {
                ch.l().diagonal().iter().map(|v| 2.0 * v.ln()).sum()
            });
            if gain > best.0 {
                best = (gain, c);
            }
        }
        let c = best.1;
        used[c] = true;
        chosen.push(c);
        let b = &blocks[c];
        let mb = &inverse * b.transpose();
        let s = DMatrix::<f64>::identity(6, 6) + b * &mb;
        if let Some(s_inv) = s.try_inverse() {
            inverse -= &mb * s_inv * mb.transpose();
        }
    }
    // Exchange on the smallest eigenvalue of the information matrix.
    let info = |set: &[usize]| -> DMatrix<f64> {
        set.iter().fold(DMatrix::zeros(n, n), |acc, &c| {
            acc + blocks[c].transpose() * &blocks[c]
        })
    };
    let mut a = info(&chosen);
    let mut current = min_eigenvalue(&a);
    for _ in 0..options.exchange_rounds {
        for slot in 0..chosen.len() {
            let out = &blocks[chosen[slot]];
            let without = &a - out.transpose() * out;
            for _ in 0..options.exchange_tries {
                let c = rng.below(blocks.len());
                if used[c] {
                    continue;
                }
                let with = &without + blocks[c].transpose() * &blocks[c];
                let value = min_eigenvalue(&with);
                if value > current {
                    used[chosen[slot]] = false;
                    used[c] = true;
                    chosen[slot] = c;
                    a = with;
                    current = value;
                    break;
                }
            }
        }
    }
    let chosen_evals: Vec<PoseEval> = chosen.iter().map(|&c| evals[c].clone()).collect();
    let planned = observability(&scaled_jacobian(&chosen_evals, &kept, &scales));
    // Random sets of the same size, for the comparison.
    let mut random: Vec<(f64, f64)> = (0..options.random_sets.max(1))
        .map(|_| {
            let mut pool: Vec<usize> = (0..evals.len()).collect();
            let set: Vec<PoseEval> = (0..options.poses)
                .map(|_| {
                    let k = rng.below(pool.len());
                    evals[pool.swap_remove(k)].clone()
                })
                .collect();
            let o = observability(&scaled_jacobian(&set, &kept, &scales));
            (o.singular_value_min, o.noise_amplification_index)
        })
        .collect();
    random.sort_by(|x, y| x.0.total_cmp(&y.0));
    let median = random[random.len() / 2];
    let report = PlanReport {
        poses: options.poses,
        candidates: poses.len(),
        draws,
        center,
        parameters: n,
        planned,
        random_singular_value_min_median: median.0,
        random_singular_value_min: random.iter().map(|r| r.0).collect(),
        random_noise_amplification_index_median: median.1,
        ratio_singular_value_min: planned.singular_value_min / median.0,
    };
    let _ = STRUCTURAL_DEFICIENCY;
    Ok(Plan {
        poses: chosen.iter().map(|&c| poses[c]).collect(),
        q_mm: chosen.iter().map(|&c| qs[c]).collect(),
        report,
    })
}

impl PlanReport {
    /// The report as indented JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}
