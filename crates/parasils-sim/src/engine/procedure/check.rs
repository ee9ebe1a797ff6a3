//! The check of a planned procedure, sample by sample, before any output:
//! per motion its durations, peak rates, smallest margins and tip error, and
//! the supervisor's warnings.

use nalgebra::Vector3;
use parasils::Supervisor;
use parasils::kin::{
    ActuatorLimits, Camera, Controller, ImagePoint, Instrument, ModuleCommand, PlatformFrame,
    PlatformState, Pose, TipTargets,
};
use parasils::motions::MotionSample;
use parasils::supervisor::{Margin, Margins};

use super::plan::ProcedurePlan;
use crate::motion::{Inside, MotionName};
use crate::record::{ClearanceRecord, Record};
use parasils_anatomy::NoGoClearance;

/// What the check of a procedure found in one motion: its duration, its
/// peak rates and its smallest margins.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionCheck {
    /// The motion.
    pub name: MotionName,
    /// When it starts, s.
    pub start_s: f64,
    /// How long it lasts on the time line, s (its stretched duration, or
    /// its `until_s` rounded up to a whole period).
    pub duration_s: f64,
    /// Its law's duration as planned, s.
    pub planned_s: f64,
    /// That duration stretched to a whole number of periods, s.
    pub stretched_s: f64,
    /// The largest `|q_dot|` of module 1's actuators, mm/s.
    pub peak_module1_mm_s: f64,
    /// The largest `|qs1_dot|`, `|qs2_dot|` of either instrument module,
    /// rad/s.
    pub peak_joint_rad_s: f64,
    /// The largest `|qs3_dot|` of either instrument module, mm/s.
    pub peak_qs3_mm_s: f64,
    /// The smallest value of each margin over the motion.
    pub smallest: Margins<f64>,
    /// The largest distance between a tip by forward kinematics and its
    /// command, mm.
    pub tip_err_mm: f64,
    /// What is inside the patient when it starts.
    pub inside: Inside,
    /// The smallest surface gap of each pair of bodies over the motion's
    /// samples, mm (sampled; [`Simulation::certify_clearance`](crate::Simulation::certify_clearance)
    /// bounds it between samples).
    pub clearance_mm: ClearanceRecord,
    /// What the camera saw, for a motion whose camera follows the tips
    /// (`None` otherwise).
    pub camera: Option<CameraCheck>,
    /// Each port's largest distance from where it was at the motion's first
    /// sample, mm, fixed frame, in the order of [`Record::PORTS`] (left,
    /// right, endoscope).
    pub port_motion_mm: [f64; 3],
    /// The smallest sampled gap of the in-body parts to each forbidden
    /// region, in the order of [`ProcedureCheck::no_go_regions`], mm
    /// (`+inf` while nothing is inside; empty without an anatomy).
    pub no_go_mm: Vec<f64>,
}

/// What the camera saw during a motion that follows the tips, from each
/// sample's platform pose, endoscope depth and tips by forward kinematics
/// (see `docs/model.md`, *The camera follows the tips*).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CameraCheck {
    /// The motion's samples.
    pub samples: usize,
    /// Those with both tips in view (ahead, `|u|, |v| <= 1`).
    pub in_view: usize,
    /// Those with both tips within the central 80 % of the image
    /// (`|u|, |v| <= 0.8`, ahead).
    pub central: usize,
    /// How many times the platform came to rest after turning (a recentring
    /// settled).
    pub settles: usize,
    /// The largest angle between the view axis and the direction to the
    /// tips' midpoint at a sample where the platform came to rest after
    /// turning, deg (`None` when it never turned).
    pub settled_aim_error_deg: Option<f64>,
    /// Whether the platform turned at the previous sample.
    turning: bool,
}

impl CameraCheck {
    /// The share of samples with both tips in view, 0 to 1.
    pub fn in_view_share(&self) -> f64 {
        share(self.in_view, self.samples)
    }

    /// The share of samples with both tips in the central 80 %, 0 to 1.
    pub fn central_share(&self) -> f64 {
        share(self.central, self.samples)
    }

    /// Takes one sample into account.
    fn push(&mut self, camera: &Camera<f64>, record: &Record) {
        let [x, y, z, psi, theta, phi] = record.pose;
        let frame =
            PlatformFrame::new(&PlatformState::at_rest(Pose::new(x, y, z, psi, theta, phi)));
        let depth = record.endoscope_depth;
        let seen = [&record.left.tip, &record.right.tip].map(|p| camera.project(&frame, depth, p));
        self.samples += 1;
        self.in_view += usize::from(seen.iter().all(ImagePoint::in_view));
        let central = |p: &ImagePoint<f64>| p.in_front && p.u.abs() <= 0.8 && p.v.abs() <= 0.8;
        self.central += usize::from(seen.iter().all(central));
        let turning = record.euler_dot[0] != 0.0 || record.euler_dot[1] != 0.0;
        if self.turning && !turning {
            let midpoint = (record.left.tip + record.right.tip) * 0.5;
            let error = camera.aim_error(&frame, depth, &midpoint).to_degrees();
            self.settles += 1;
            self.settled_aim_error_deg =
                Some(self.settled_aim_error_deg.map_or(error, |e| e.max(error)));
        }
        self.turning = turning;
    }
}

#[allow(
    clippy::cast_precision_loss,
    reason = "counts of samples, far below 2^52"
)]
fn share(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        part as f64 / whole as f64
    }
}

/// A margin below its warning threshold during a motion: from when, until
/// when, and how low it went.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    /// The margin.
    pub margin: Margin,
    /// The motion's index.
    pub motion: usize,
    /// The first sample below the threshold, s from the procedure's start.
    pub from_s: f64,
    /// The last sample below it, s.
    pub until_s: f64,
    /// The smallest value, in the margin's unit.
    pub smallest: f64,
    /// The warning threshold.
    pub threshold: f64,
}

/// The check of a whole procedure: one [`MotionCheck`] per motion and the
/// warnings of its supervisor, in time order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ProcedureCheck {
    /// Per motion.
    pub motions: Vec<MotionCheck>,
    /// Every episode of a margin below its warning threshold.
    pub warnings: Vec<Warning>,
    /// Each actuator's largest fraction of its velocity limit (`[0]`) and
    /// of its acceleration limit (`[1]`) over the procedure, in the order of
    /// [`parasils::kin::Actuator::ALL`].
    pub usage: [[f64; 12]; 2],
    /// Each actuator's largest fraction of its force limit over the
    /// procedure (0 without tip loads), in the same order.
    pub force_usage: [f64; 12],
    /// The forbidden regions' names, in the anatomy file's order (empty
    /// without an anatomy).
    pub no_go_regions: Vec<String>,
    /// Per margin, the warning under way: its place in `warnings` and the
    /// last sample's index.
    open: [Option<(usize, usize)>; Margin::COUNT],
    /// The endoscope's camera, for the motions that follow the tips.
    camera: Option<Camera<f64>>,
    /// The motion under way and its ports at its first sample.
    port_start: Option<(usize, [Vector3<f64>; 3])>,
}

impl ProcedureCheck {
    /// An empty check of `plan`'s motions, seen through `camera`.
    pub(crate) fn new(plan: &ProcedurePlan, camera: &Camera<f64>) -> Self {
        Self {
            motions: plan
                .motions
                .iter()
                .map(|m| MotionCheck {
                    name: m.name.clone(),
                    start_s: m.start_s,
                    duration_s: m.length_s,
                    planned_s: m.planned_s(),
                    stretched_s: m.duration(),
                    peak_module1_mm_s: 0.0,
                    peak_joint_rad_s: 0.0,
                    peak_qs3_mm_s: 0.0,
                    smallest: Margins::splat(f64::INFINITY),
                    tip_err_mm: 0.0,
                    inside: m.inside,
                    clearance_mm: ClearanceRecord {
                        left_right: f64::INFINITY,
                        left_endoscope: f64::INFINITY,
                        right_endoscope: f64::INFINITY,
                    },
                    camera: m.follow.is_some().then(CameraCheck::default),
                    port_motion_mm: [0.0; 3],
                    no_go_mm: Vec::new(),
                })
                .collect(),
            warnings: Vec::new(),
            usage: [[0.0; 12]; 2],
            force_usage: [0.0; 12],
            no_go_regions: Vec::new(),
            open: [None; Margin::COUNT],
            camera: Some(*camera),
            port_start: None,
        }
    }

    /// Takes one record's gaps to each forbidden region into account
    /// (nothing without an anatomy).
    pub(crate) fn push_no_go(&mut self, record: &Record, no_go: Option<&NoGoClearance>) {
        let (Some(gaps), Some(m)) = (no_go, self.motions.get_mut(record.motion as usize)) else {
            return;
        };
        if m.no_go_mm.len() < gaps.regions.len() {
            m.no_go_mm.resize(gaps.regions.len(), f64::INFINITY);
        }
        for (smallest, gap) in m.no_go_mm.iter_mut().zip(&gaps.regions) {
            *smallest = smallest.min(gap.gap_mm);
        }
    }

    /// Takes one record and its margins into account.
    pub(crate) fn push(
        &mut self,
        record: &Record,
        margins: &Margins<f64>,
        supervisor: &Supervisor<f64>,
        limits: &ActuatorLimits<f64>,
    ) {
        record.widen_usage(&mut self.usage, limits);
        record.widen_force_usage(&mut self.force_usage, limits);
        let k = record.motion as usize;
        let Some(m) = self.motions.get_mut(k) else {
            return;
        };
        let amax = |v: &[f64]| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        m.peak_module1_mm_s = m.peak_module1_mm_s.max(amax(&record.module1.q_dot));
        for side in [&record.left, &record.right] {
            m.peak_joint_rad_s = m.peak_joint_rad_s.max(amax(&side.q_dot[..2]));
            m.peak_qs3_mm_s = m.peak_qs3_mm_s.max(side.q_dot[2].abs());
            m.tip_err_mm = m.tip_err_mm.max(side.tip_err);
        }
        for margin in Margin::ALL {
            m.smallest[margin] = m.smallest[margin].min(margins[margin]);
        }
        if let (Some(seen), Some(camera)) = (&mut m.camera, &self.camera) {
            seen.push(camera, record);
        }
        let (c, r) = (&mut m.clearance_mm, &record.clearance);
        c.left_right = c.left_right.min(r.left_right);
        c.left_endoscope = c.left_endoscope.min(r.left_endoscope);
        c.right_endoscope = c.right_endoscope.min(r.right_endoscope);
        let from = match self.port_start {
            Some((j, from)) if j == k => from,
            _ => {
                self.port_start = Some((k, record.ports));
                record.ports
            }
        };
        for ((largest, now), from) in m.port_motion_mm.iter_mut().zip(&record.ports).zip(&from) {
            *largest = largest.max((now - from).norm());
        }
        for (slot, margin) in self.open.iter_mut().zip(Margin::ALL) {
            if !record.warnings.contains(margin) {
                *slot = None;
                continue;
            }
            let going = slot
                .and_then(|(w, last)| (last + 1 == record.index).then_some(w))
                .filter(|&w| self.warnings.get(w).is_some_and(|w| w.motion == k));
            let w = match going {
                Some(w) => w,
                None => {
                    self.warnings.push(Warning {
                        margin,
                        motion: k,
                        from_s: record.t,
                        until_s: record.t,
                        smallest: margins[margin],
                        threshold: supervisor.warn[margin],
                    });
                    self.warnings.len() - 1
                }
            };
            if let Some(x) = self.warnings.get_mut(w) {
                x.until_s = record.t;
                x.smallest = x.smallest.min(margins[margin]);
            }
            *slot = Some((w, record.index));
        }
    }
}

/// The command for tip targets of a sample: where each module's tip is
/// commanded (by its tip, or by forward kinematics of its commanded joints).
pub(crate) fn commanded_tips(
    controller: &Controller<f64>,
    sample: &MotionSample<f64>,
    frame: &PlatformFrame<f64>,
) -> TipTargets<f64> {
    let tip = |m: &Instrument<f64>, c: &ModuleCommand<f64>| match c {
        ModuleCommand::Tip(t) => t.position,
        ModuleCommand::Joints(j) => frame.to_fixed(&m.fk_platform(&j.q)),
    };
    TipTargets {
        left: tip(&controller.left, &sample.left),
        right: tip(&controller.right, &sample.right),
    }
}
