//! The model error of one perturbed robot: the nominal commands replayed on
//! it. Module 1's forward kinematics gives where the platform really is;
//! each instrument module's forward kinematics with its own perturbed
//! parameters gives where its tip really is.
//!
//! Two implementations of the same replay. [`replay()`] solves module 1 by
//! Newton's method from the previous sample's pose at every sample, as any
//! forward kinematics would: the reference. [`ReplayPlan::replay`], what a
//! [`Study`](crate::Study) runs, uses what the nominal robot already knows:
//! the scaled Jacobian at every commanded pose, inverted once for the whole
//! study ([`FkChord`]), drives a chord iteration (simplified Newton) from
//! the commanded pose shifted by the pose error extrapolated (quadratically)
//! from the three previous samples, to the same residual tolerance; a
//! sample where the chord does not contract falls back to Newton. The tips
//! come from the rotation of module 1's last iterate and the joints' sines
//! and cosines computed once for all robots. Both reach poses that meet the
//! same tolerance, so their deviations agree to about 1e-10 mm (the tests
//! hold them within 1e-9 mm over random robots); the plan is about 15 times
//! faster (see `BENCHMARKS.md`).

use nalgebra::{Matrix3, Vector3};
use parasils_kin::{
    Actuators, Error, FkChord, Instrument, Joints, JointsTrig, ParallelRobot, Pose, RobotGeometry,
};

use crate::trace::Trace;

/// The largest deviations of one robot along the motion.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Deviation {
    /// The largest distance of the real left tip from the commanded one, mm.
    pub left_tip_dev_mm: f64,
    /// The same for the right tip, mm.
    pub right_tip_dev_mm: f64,
    /// The largest distance of the platform's real position from the
    /// commanded one, mm.
    pub pose_position_err_mm: f64,
    /// The largest angle of the rotation from the commanded platform
    /// orientation to the real one, deg.
    pub pose_rotation_err_deg: f64,
}

impl Deviation {
    /// The larger of the two tip deviations, mm.
    pub fn tip_dev_mm(&self) -> f64 {
        self.left_tip_dev_mm.max(self.right_tip_dev_mm)
    }

    fn max(&mut self, other: &Deviation) {
        self.left_tip_dev_mm = self.left_tip_dev_mm.max(other.left_tip_dev_mm);
        self.right_tip_dev_mm = self.right_tip_dev_mm.max(other.right_tip_dev_mm);
        self.pose_position_err_mm = self.pose_position_err_mm.max(other.pose_position_err_mm);
        self.pose_rotation_err_deg = self.pose_rotation_err_deg.max(other.pose_rotation_err_deg);
    }
}

/// Why a perturbed robot could not be followed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplayFailure {
    /// The trace's sample where it failed, `None` when the perturbed
    /// geometry itself is invalid.
    pub index: Option<usize>,
    /// The time of that sample, s.
    pub t_s: f64,
    /// The kinematics' error.
    pub error: Error,
}

impl core::fmt::Display for ReplayFailure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.index {
            Some(k) => write!(f, "at sample {k} (t = {} s): {}", self.t_s, self.error),
            None => write!(f, "invalid perturbed geometry: {}", self.error),
        }
    }
}

/// The angle between two rotations, rad: `2 asin(|A - B|_F / sqrt(8))`,
/// accurate down to the smallest angles (where `acos` of the trace is not).
pub(crate) fn rotation_angle(a: &nalgebra::Matrix3<f64>, b: &nalgebra::Matrix3<f64>) -> f64 {
    let s = (a - b).norm() / 8f64.sqrt();
    2.0 * s.min(1.0).asin()
}

/// Module 1, the left and the right instrument module of a robot.
type Modules = (ParallelRobot<f64>, Instrument<f64>, Instrument<f64>);

/// Module 1 and both instrument modules of `robot`, `(module1, left,
/// right)`, each validated; an invalid one is the replay's failure before
/// any sample.
fn modules(robot: &RobotGeometry<f64>) -> Result<Modules, ReplayFailure> {
    let invalid = |error| ReplayFailure {
        index: None,
        t_s: 0.0,
        error,
    };
    Ok((
        ParallelRobot::new(robot.module1).map_err(invalid)?,
        Instrument::new(robot.left).map_err(invalid)?,
        Instrument::new(robot.right).map_err(invalid)?,
    ))
}

/// The commands of `trace` replayed on `robot`.
///
/// # Errors
/// A [`ReplayFailure`]: the geometry is invalid, or module 1's forward
/// kinematics fails at a sample (no convergence, a singular Jacobian, a link
/// on the other branch), or a tip overflows.
pub fn replay(robot: &RobotGeometry<f64>, trace: &Trace) -> Result<Deviation, ReplayFailure> {
    let (module1, left, right) = modules(robot)?;
    let mut worst = Deviation::default();
    let mut guess: Option<Pose<f64>> = None;
    for (k, c) in trace.commands().iter().enumerate() {
        let fail = |error| ReplayFailure {
            index: Some(k),
            t_s: c.t_s,
            error,
        };
        let from = guess.unwrap_or(c.pose);
        let pose = module1.fk(&Actuators(c.q_mm), &from).map_err(fail)?.pose;
        let tip_left = left.fk(&pose, &c.left).map_err(fail)?;
        let tip_right = right.fk(&pose, &c.right).map_err(fail)?;
        worst.max(&Deviation {
            left_tip_dev_mm: (tip_left - c.tip_left_mm).norm(),
            right_tip_dev_mm: (tip_right - c.tip_right_mm).norm(),
            pose_position_err_mm: (pose.position() - c.pose.position()).norm(),
            pose_rotation_err_deg: rotation_angle(&pose.rotation(), &c.pose.rotation())
                .to_degrees(),
        });
        guess = Some(pose);
    }
    Ok(worst)
}

/// What every robot's replay of one trace shares: the trace, the nominal
/// robot's inverted Jacobian at each commanded pose (`None` where the
/// nominal robot is too near a parallel singularity for the chord method),
/// each commanded rotation and the sines and cosines of each command's
/// instrument joints.
#[derive(Debug, Clone)]
pub struct ReplayPlan {
    trace: Trace,
    chords: Vec<Option<FkChord<f64>>>,
    rotations: Vec<Matrix3<f64>>,
    joints: Vec<[JointsTrig<f64>; 2]>,
}

impl ReplayPlan {
    /// The plan of `trace`: one decomposition of the nominal Jacobian per
    /// sample (about 3 us each).
    pub fn new(trace: Trace) -> Self {
        let nominal = ParallelRobot::new(trace.robot().module1).ok();
        let chords = trace
            .commands()
            .iter()
            .map(|c| nominal.and_then(|m| m.fk_chord_at(&c.pose).ok()))
            .collect();
        let rotations = trace.commands().iter().map(|c| c.pose.rotation()).collect();
        let joints = trace
            .commands()
            .iter()
            .map(|c| [JointsTrig::of(&c.left), JointsTrig::of(&c.right)])
            .collect();
        Self {
            trace,
            chords,
            rotations,
            joints,
        }
    }

    /// The trace.
    pub fn trace(&self) -> &Trace {
        &self.trace
    }

    /// The number of samples where the chord method is not available and
    /// every robot is solved by Newton's method.
    pub fn newton_samples(&self) -> usize {
        self.chords.iter().filter(|c| c.is_none()).count()
    }

    /// The commands of the trace replayed on `robot`: [`replay()`]'s
    /// results, module 1 solved by the chord method from the nominal
    /// Jacobian (Newton's method from the previous pose where it does not
    /// contract), both tips from one rotation of the platform per sample.
    ///
    /// # Errors
    /// [`replay()`]'s: the chord method never fails a sample on its own.
    pub fn replay(&self, robot: &RobotGeometry<f64>) -> Result<Deviation, ReplayFailure> {
        let (module1, left, right) = modules(robot)?;
        let options = module1.geometry().fk;
        let mut worst = Deviation::default();
        let mut guess: Option<Pose<f64>> = None;
        // The pose errors (real minus commanded) of the three previous samples.
        let mut errors: [Option<[f64; 6]>; 3] = [None, None, None];
        let samples = self
            .trace
            .commands()
            .iter()
            .zip(&self.chords)
            .zip(&self.rotations)
            .zip(&self.joints);
        for (k, (((c, chord), commanded), [trig_left, trig_right])) in samples.enumerate() {
            let fail = |error| ReplayFailure {
                index: Some(k),
                t_s: c.t_s,
                error,
            };
            let nominal = c.pose.to_array();
            let start = match errors {
                [Some(e1), Some(e2), Some(e3)] => Pose::from_array(core::array::from_fn(|i| {
                    nominal[i] + (3.0 * e1[i] - 3.0 * e2[i] + e3[i])
                })),
                [Some(e1), Some(e2), None] => {
                    Pose::from_array(core::array::from_fn(|i| nominal[i] + (2.0 * e1[i] - e2[i])))
                }
                [Some(e1), None, None] => {
                    Pose::from_array(core::array::from_fn(|i| nominal[i] + e1[i]))
                }
                _ => c.pose,
            };
            let q = Actuators(c.q_mm);
            let by_chord = chord
                .as_ref()
                .and_then(|chord| module1.fk_chord(&q, &start, chord, &options));
            let (pose, rotation) = match by_chord {
                Some((solution, rotation)) => (solution.pose, rotation),
                None => {
                    let from = guess.unwrap_or(c.pose);
                    let pose = module1.fk(&q, &from).map_err(fail)?.pose;
                    (pose, pose.rotation())
                }
            };
            let position = pose.position();
            let tip_left =
                tip(&left, &rotation, &position, &pose, &c.left, trig_left).map_err(fail)?;
            let tip_right =
                tip(&right, &rotation, &position, &pose, &c.right, trig_right).map_err(fail)?;
            worst.max(&Deviation {
                left_tip_dev_mm: (tip_left - c.tip_left_mm).norm(),
                right_tip_dev_mm: (tip_right - c.tip_right_mm).norm(),
                pose_position_err_mm: (position - c.pose.position()).norm(),
                pose_rotation_err_deg: rotation_angle(&rotation, commanded).to_degrees(),
            });
            let real = pose.to_array();
            errors = [
                Some(core::array::from_fn(|i| real[i] - nominal[i])),
                errors[0],
                errors[1],
            ];
            guess = Some(pose);
        }
        Ok(worst)
    }
}

/// [`Instrument::fk`] from the platform's rotation and the joints' sines
/// and cosines computed beforehand: the same expressions, so the same bits;
/// a non-finite tip is reported by `Instrument::fk` itself.
fn tip(
    instrument: &Instrument<f64>,
    rotation: &Matrix3<f64>,
    position: &Vector3<f64>,
    pose: &Pose<f64>,
    q: &Joints<f64>,
    trig: &JointsTrig<f64>,
) -> Result<Vector3<f64>, Error> {
    let tip = rotation * instrument.fk_platform_trig(trig) + position;
    if tip.iter().all(|v| v.is_finite()) && q.check_finite().is_ok() {
        Ok(tip)
    } else {
        instrument.fk(pose, q)
    }
}
