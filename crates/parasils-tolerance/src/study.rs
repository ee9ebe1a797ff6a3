//! A tolerance study: a nominal robot, a motion's commands, a
//! specification and a seed; any range of its samples, run on threads.

use core::ops::Range;
use core::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use parasils_calib::model::Model;
use parasils_calib::{PARAMETERS, Parameter, ParameterMap};
use parasils_kin::{Error as KinError, RobotGeometry};
use thiserror::Error;

use crate::linear::{LinearError, Linearisation, family_of};
use crate::perturbation::Perturbation;
use crate::replay::{Deviation, ReplayFailure, ReplayPlan};
use crate::spec::{Family, Spec};
use crate::trace::Trace;

/// Why a study cannot start.
#[derive(Debug, Error, PartialEq)]
pub enum StudyError {
    /// The motion has no sample.
    #[error("the motion has no sample")]
    EmptyTrace,
    /// The nominal robot is invalid.
    #[error("the nominal robot is invalid: {0}")]
    Nominal(KinError),
    /// A single deviation at its extreme takes a leg out of reach somewhere
    /// along the motion: the specification is too wide for this robot.
    #[error(
        "`{key}`: a deviation of {extreme} {unit} of `{parameter}` (its extreme) leaves actuator \
         q{actuator}'s link unable to reach its node at t = {t_s} s: the tolerance is too wide for \
         this robot"
    )]
    Unreachable {
        /// The family's key.
        key: &'static str,
        /// The member's parameter, in the calibration's vocabulary.
        parameter: String,
        /// The signed deviation tried.
        extreme: f64,
        /// Its unit.
        unit: &'static str,
        /// The actuator, 1 to 6.
        actuator: u8,
        /// When, s.
        t_s: f64,
    },
    /// A deviation at its extreme makes an instrument module invalid (a
    /// `beta` outside `[0, 90)` deg).
    #[error("`{key}`: a deviation of {extreme} deg makes the {side} module invalid: {error}")]
    Instrument {
        /// The family's key.
        key: &'static str,
        /// `"left"` or `"right"`.
        side: &'static str,
        /// The signed deviation tried, deg.
        extreme: f64,
        /// The kinematics' error.
        error: KinError,
    },
}

/// A run stopped before its end by its progress callback.
#[derive(Debug, Error, PartialEq, Eq)]
#[error("the run was interrupted")]
pub struct Interrupted;

/// The result of a range of samples: one row per sample, as columns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Results {
    /// The sample's index.
    pub sample: Vec<u64>,
    /// [`Deviation::left_tip_dev_mm`]; NaN on a failed sample.
    pub left_tip_dev_mm: Vec<f64>,
    /// [`Deviation::right_tip_dev_mm`]; NaN on a failed sample.
    pub right_tip_dev_mm: Vec<f64>,
    /// [`Deviation::pose_position_err_mm`]; NaN on a failed sample.
    pub pose_position_err_mm: Vec<f64>,
    /// [`Deviation::pose_rotation_err_deg`]; NaN on a failed sample.
    pub pose_rotation_err_deg: Vec<f64>,
    /// Whether the perturbed robot could not be followed.
    pub failed: Vec<bool>,
    /// Every failed sample and why, in sample order.
    pub failures: Vec<(u64, ReplayFailure)>,
}

impl Results {
    /// The number of rows.
    pub fn len(&self) -> usize {
        self.sample.len()
    }

    /// `true` when there is no row.
    pub fn is_empty(&self) -> bool {
        self.sample.is_empty()
    }

    fn push(&mut self, sample: u64, outcome: Result<Deviation, ReplayFailure>) {
        self.sample.push(sample);
        let d = match outcome {
            Ok(d) => {
                self.failed.push(false);
                d
            }
            Err(f) => {
                self.failed.push(true);
                self.failures.push((sample, f));
                Deviation {
                    left_tip_dev_mm: f64::NAN,
                    right_tip_dev_mm: f64::NAN,
                    pose_position_err_mm: f64::NAN,
                    pose_rotation_err_deg: f64::NAN,
                }
            }
        };
        self.left_tip_dev_mm.push(d.left_tip_dev_mm);
        self.right_tip_dev_mm.push(d.right_tip_dev_mm);
        self.pose_position_err_mm.push(d.pose_position_err_mm);
        self.pose_rotation_err_deg.push(d.pose_rotation_err_deg);
    }

    /// The rows of `other` after these.
    pub fn append(&mut self, other: Results) {
        self.sample.extend(other.sample);
        self.left_tip_dev_mm.extend(other.left_tip_dev_mm);
        self.right_tip_dev_mm.extend(other.right_tip_dev_mm);
        self.pose_position_err_mm.extend(other.pose_position_err_mm);
        self.pose_rotation_err_deg
            .extend(other.pose_rotation_err_deg);
        self.failed.extend(other.failed);
        self.failures.extend(other.failures);
    }
}

/// Samples per chunk taken by a thread: about 20 ms of work on the paper's
/// motion at 100 Hz, so that the threads end together and the progress
/// moves.
const CHUNK: usize = 16;

/// A tolerance study.
///
/// ```
/// use parasils_sim::Scenario;
/// use parasils_tolerance::{Spec, Study, Trace};
///
/// let mut scenario = Scenario::paper();
/// scenario.rate_hz = 20.0;
/// let trace = Trace::from_scenario(scenario)?;
/// let study = Study::new(Spec::default(), trace, 1)?;
/// let results = study.run(0..8, 2, &|_| true)?;
/// assert_eq!(results.sample, (0..8).collect::<Vec<u64>>());
/// // Any range, any number of threads: the same numbers, bit for bit.
/// let again = study.run(4..8, 1, &|_| true)?;
/// assert_eq!(again.left_tip_dev_mm[..], results.left_tip_dev_mm[4..]);
/// assert!(results.left_tip_dev_mm.iter().all(|&d| d > 0.0 && d < 5.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Study {
    spec: Spec,
    plan: ReplayPlan,
    seed: u64,
    map: ParameterMap,
}

impl Study {
    /// A study of `trace`'s commands (on its nominal robot) under `spec`,
    /// the samples drawn with `seed`.
    ///
    /// Checks that each single deviation at its extreme (the half width,
    /// or [`NORMAL_EXTREME_SIGMAS`](crate::spec::NORMAL_EXTREME_SIGMAS)
    /// sigma, either sign) keeps every leg of module 1 able to reach its node
    /// at every commanded pose, and every instrument module valid.
    ///
    /// # Errors
    /// [`StudyError`].
    pub fn new(spec: Spec, trace: Trace, seed: u64) -> Result<Self, StudyError> {
        if trace.is_empty() {
            return Err(StudyError::EmptyTrace);
        }
        let robot = *trace.robot();
        let map = ParameterMap::new(&robot.module1).map_err(StudyError::Nominal)?;
        check_extremes(&spec, &trace, &map, &robot)?;
        Ok(Self {
            spec,
            plan: ReplayPlan::new(trace),
            seed,
            map,
        })
    }

    /// The specification.
    pub fn spec(&self) -> &Spec {
        &self.spec
    }

    /// The motion's commands.
    pub fn trace(&self) -> &Trace {
        self.plan.trace()
    }

    /// What every sample's replay shares (the nominal Jacobians).
    pub fn plan(&self) -> &ReplayPlan {
        &self.plan
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The deviations of sample `sample`.
    pub fn perturbation(&self, sample: u64) -> Perturbation {
        Perturbation::draw(&self.spec, self.seed, sample)
    }

    /// The perturbed robot of sample `sample`.
    pub fn robot(&self, sample: u64) -> RobotGeometry<f64> {
        self.perturbation(sample)
            .apply(&self.map, self.trace().robot())
    }

    /// The model error of sample `sample`.
    ///
    /// # Errors
    /// Its [`ReplayFailure`].
    pub fn sample(&self, sample: u64) -> Result<Deviation, ReplayFailure> {
        self.plan.replay(&self.robot(sample))
    }

    /// The first-order model of this study's motion.
    ///
    /// # Errors
    /// [`LinearError`].
    pub fn linearisation(&self) -> Result<Linearisation, LinearError> {
        Linearisation::new(self.trace().robot(), self.trace())
    }

    /// The samples `samples`, on `threads` threads (the calling one and
    /// `threads - 1` scoped helpers). `progress` is called with the number
    /// of samples each finished chunk adds; returning `false` stops the run.
    /// The result does not depend on `threads`, bit for bit.
    ///
    /// # Errors
    /// [`Interrupted`] when `progress` returned `false`.
    pub fn run(
        &self,
        samples: Range<u64>,
        threads: usize,
        progress: &(dyn Fn(u64) -> bool + Sync),
    ) -> Result<Results, Interrupted> {
        let count =
            usize::try_from(samples.end.saturating_sub(samples.start)).unwrap_or(usize::MAX);
        self.run_with(count, &|k| samples.start + k as u64, threads, progress)
    }

    /// The samples listed in `indices` (any order, repeats allowed), as
    /// [`Study::run`] does a range: the rows in the order of `indices`.
    ///
    /// # Errors
    /// [`Interrupted`] when `progress` returned `false`.
    pub fn run_indices(
        &self,
        indices: &[u64],
        threads: usize,
        progress: &(dyn Fn(u64) -> bool + Sync),
    ) -> Result<Results, Interrupted> {
        self.run_with(indices.len(), &|k| indices[k], threads, progress)
    }

    fn run_with(
        &self,
        count: usize,
        index: &(dyn Fn(usize) -> u64 + Sync),
        threads: usize,
        progress: &(dyn Fn(u64) -> bool + Sync),
    ) -> Result<Results, Interrupted> {
        let next = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let done: Mutex<Vec<(usize, Results)>> = Mutex::new(Vec::new());
        let work = || {
            loop {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                let start = next.fetch_add(CHUNK, Ordering::Relaxed);
                if start >= count {
                    return;
                }
                let end = (start + CHUNK).min(count);
                let mut chunk = Results::default();
                for k in start..end {
                    let i = index(k);
                    chunk.push(i, self.sample(i));
                }
                if let Ok(mut d) = done.lock() {
                    d.push((start, chunk));
                }
                if !progress((end - start) as u64) {
                    stop.store(true, Ordering::Relaxed);
                }
            }
        };
        std::thread::scope(|scope| {
            for _ in 1..threads.max(1) {
                scope.spawn(work);
            }
            work();
        });
        if stop.load(Ordering::Relaxed) {
            return Err(Interrupted);
        }
        let mut chunks = done.into_inner().unwrap_or_else(|e| e.into_inner());
        chunks.sort_by_key(|(start, _)| *start);
        let mut out = Results::default();
        for (_, chunk) in chunks {
            out.append(chunk);
        }
        Ok(out)
    }
}

/// The check of [`Study::new`]: each single deviation at its extreme.
fn check_extremes(
    spec: &Spec,
    trace: &Trace,
    map: &ParameterMap,
    robot: &RobotGeometry<f64>,
) -> Result<(), StudyError> {
    let poses: Vec<([f64; 6], f64)> = trace
        .commands()
        .iter()
        .map(|c| {
            let p = c.pose;
            let deg = [p.psi, p.theta, p.phi].map(f64::to_degrees);
            ([p.x, p.y, p.z, deg[0], deg[1], deg[2]], c.t_s)
        })
        .collect();
    for k in 0..PARAMETERS {
        let family = family_of(k);
        let Some(d) = spec.get(family) else {
            continue;
        };
        let extreme = d.extreme();
        if extreme == 0.0 {
            continue;
        }
        for sign in [1.0, -1.0] {
            let mut x = map.nominal_vector();
            x[k] += match family {
                Family::GuideDirection => (sign * extreme).to_radians().tan(),
                _ => sign * extreme,
            };
            let model = Model::new(map, &x);
            for (pose, t_s) in &poses {
                if let Err(e) = model.eval(pose, false) {
                    return Err(StudyError::Unreachable {
                        key: family.key(),
                        parameter: Parameter::from_index(k)
                            .map_or_else(String::new, Parameter::name),
                        extreme: sign * extreme,
                        unit: family.unit(),
                        actuator: e.actuator,
                        t_s: *t_s,
                    });
                }
            }
        }
    }
    for family in [Family::Alpha, Family::Beta] {
        let Some(d) = spec.get(family) else {
            continue;
        };
        for sign in [1.0, -1.0] {
            let delta = (sign * d.extreme()).to_radians();
            for (side, g) in [("left", robot.left), ("right", robot.right)] {
                let mut g = g;
                match family {
                    Family::Alpha => g.alpha += delta,
                    _ => g.beta += delta,
                }
                g.validate().map_err(|error| StudyError::Instrument {
                    key: family.key(),
                    side,
                    extreme: sign * d.extreme(),
                    error,
                })?;
            }
        }
    }
    Ok(())
}
