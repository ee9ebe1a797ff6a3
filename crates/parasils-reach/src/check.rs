//! The check of one orientation: the controller's own per-cycle call, its
//! typed error turned into a stable [`Constraint`] code, the bodies'
//! clearance and forbidden regions, and the normalised margin.

use std::borrow::Cow;

use parasils::kin::{
    Bodies, BodyGeometry, ClearancePair, ControlStep, Controller, Error, InstrumentSingularity,
    Interval, Joint, JointLimits, MarginTracker, Pose, Side, TipTargets,
};

use parasils_sim::{Scenario, SimulationError};

use crate::no_go::NoGoCheck;

/// The constraint that makes an orientation infeasible, or [`Constraint::Ok`].
///
/// [`Constraint::code`] is its stable name, as the CSV's `limiting` column
/// and Python's codes write it: `ok`, `left.qs2.limit`,
/// `right.out_of_reach`, `module1.q4.stroke`, `module1.q2.serial_singular`,
/// `module1.parallel_singular`, `clearance.left_right`, ..., and
/// `no_go.<region name>` ([`Constraint::code_in`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Constraint {
    /// Feasible: every module solved within every limit and threshold.
    Ok,
    /// Module 1: the leg of actuator `q1..q6` (index 0 to 5) cannot reach its
    /// node: `module1.qN.out_of_reach`.
    LegOutOfReach(u8),
    /// Module 1: actuator `qN`'s serial margin below its threshold:
    /// `module1.qN.serial_singular`.
    SerialSingular(u8),
    /// Module 1: actuator `qN` beyond its stroke: `module1.qN.stroke`.
    Stroke(u8),
    /// Module 1: the parallel margin below the per-cycle threshold
    /// (`parallel_command`): `module1.parallel_singular`.
    ParallelSingular,
    /// An instrument module's tip out of its cone of reach:
    /// `left.out_of_reach`, `right.out_of_reach`.
    OutOfReach(Side),
    /// An instrument module's `|cos qs2|` below its threshold:
    /// `left.cos_qs2.singular`, `right.cos_qs2.singular`.
    CosQs2Singular(Side),
    /// An instrument module's `qs3` below its threshold (the tip at the
    /// RCM): `left.qs3.singular`, `right.qs3.singular`.
    Qs3Singular(Side),
    /// An instrument joint beyond its limit: `left.qs1.limit`, ...,
    /// `right.qs3.limit`.
    JointLimit(Side, Joint),
    /// Two bodies closer than the robot file's clearance stop threshold
    /// (`[supervisor]`'s `clearance_stop_mm`; checked only when the file
    /// gives a clearance threshold): `clearance.left_right`,
    /// `clearance.left_endoscope`, `clearance.right_endoscope`.
    Clearance(ClearancePair),
    /// Any other error of the kinematics (a non-finite number): `error`.
    Other,
    /// The in-body part of a shaft or of the endoscope closer to a
    /// forbidden region than the stop threshold (the scenario's anatomy,
    /// `--anatomy`; the robot file's `clearance_stop_mm`, 0.5 mm by
    /// default), as a run there would fail: the region's index in the
    /// anatomy file, its code `no_go.<region name>`
    /// ([`Constraint::code_in`]; [`Constraint::code`] alone says `no_go`).
    NoGo(u16),
}

const MODULE1: [[&str; 6]; 3] = [
    [
        "module1.q1.out_of_reach",
        "module1.q2.out_of_reach",
        "module1.q3.out_of_reach",
        "module1.q4.out_of_reach",
        "module1.q5.out_of_reach",
        "module1.q6.out_of_reach",
    ],
    [
        "module1.q1.serial_singular",
        "module1.q2.serial_singular",
        "module1.q3.serial_singular",
        "module1.q4.serial_singular",
        "module1.q5.serial_singular",
        "module1.q6.serial_singular",
    ],
    [
        "module1.q1.stroke",
        "module1.q2.stroke",
        "module1.q3.stroke",
        "module1.q4.stroke",
        "module1.q5.stroke",
        "module1.q6.stroke",
    ],
];

const INSTRUMENT: [[&str; 6]; 2] = [
    [
        "left.out_of_reach",
        "left.cos_qs2.singular",
        "left.qs3.singular",
        "left.qs1.limit",
        "left.qs2.limit",
        "left.qs3.limit",
    ],
    [
        "right.out_of_reach",
        "right.cos_qs2.singular",
        "right.qs3.singular",
        "right.qs1.limit",
        "right.qs2.limit",
        "right.qs3.limit",
    ],
];

impl Constraint {
    /// Every constraint, in the order the controller checks them (module 1's
    /// legs, serial margins, strokes, parallel margin; then the left module,
    /// then the right one; then the clearance of the three pairs, checked
    /// once the kinematics solve), [`Constraint::Ok`] first and
    /// [`Constraint::Other`] last. The forbidden regions, which depend on
    /// the anatomy, follow in [`Constraint::with_regions`].
    pub fn all() -> Vec<Constraint> {
        let mut out = vec![Constraint::Ok];
        for make in [
            Constraint::LegOutOfReach as fn(u8) -> Constraint,
            Constraint::SerialSingular,
            Constraint::Stroke,
        ] {
            out.extend((0..6).map(make));
        }
        out.push(Constraint::ParallelSingular);
        for side in [Side::Left, Side::Right] {
            out.extend([
                Constraint::OutOfReach(side),
                Constraint::CosQs2Singular(side),
                Constraint::Qs3Singular(side),
                Constraint::JointLimit(side, Joint::Qs1),
                Constraint::JointLimit(side, Joint::Qs2),
                Constraint::JointLimit(side, Joint::Qs3),
            ]);
        }
        out.extend(ClearancePair::ALL.map(Constraint::Clearance));
        out.push(Constraint::Other);
        out
    }

    /// [`Constraint::all`], then [`Constraint::NoGo`] of each of `regions`
    /// forbidden regions, in the anatomy file's order (the order of
    /// [`Constraint::index`]).
    pub fn with_regions(regions: usize) -> Vec<Constraint> {
        let mut out = Constraint::all();
        let count = u16::try_from(regions).unwrap_or(u16::MAX);
        out.extend((0..count).map(Constraint::NoGo));
        out
    }

    /// The place of the constraint in [`Constraint::all`].
    pub fn index(self) -> usize {
        let side = |s: Side| match s {
            Side::Left => 0,
            Side::Right => 6,
        };
        let joint = |j: Joint| match j {
            Joint::Qs1 => 3,
            Joint::Qs2 => 4,
            Joint::Qs3 => 5,
        };
        match self {
            Constraint::Ok => 0,
            Constraint::LegOutOfReach(j) => 1 + usize::from(j.min(5)),
            Constraint::SerialSingular(j) => 7 + usize::from(j.min(5)),
            Constraint::Stroke(j) => 13 + usize::from(j.min(5)),
            Constraint::ParallelSingular => 19,
            Constraint::OutOfReach(s) => 20 + side(s),
            Constraint::CosQs2Singular(s) => 21 + side(s),
            Constraint::Qs3Singular(s) => 22 + side(s),
            Constraint::JointLimit(s, j) => 20 + side(s) + joint(j),
            Constraint::Clearance(ClearancePair::LeftRight) => 32,
            Constraint::Clearance(ClearancePair::LeftEndoscope) => 33,
            Constraint::Clearance(ClearancePair::RightEndoscope) => 34,
            Constraint::Other => 35,
            Constraint::NoGo(i) => 36 + usize::from(i),
        }
    }

    /// The stable code; `no_go` for any forbidden region, whose own code,
    /// `no_go.<region name>`, is [`Constraint::code_in`]'s.
    pub fn code(self) -> &'static str {
        let side = |s: Side| match s {
            Side::Left => 0,
            Side::Right => 1,
        };
        let actuator = |k: usize, j: u8| MODULE1[k].get(usize::from(j)).copied().unwrap_or("error");
        match self {
            Constraint::Ok => "ok",
            Constraint::LegOutOfReach(j) => actuator(0, j),
            Constraint::SerialSingular(j) => actuator(1, j),
            Constraint::Stroke(j) => actuator(2, j),
            Constraint::ParallelSingular => "module1.parallel_singular",
            Constraint::OutOfReach(s) => INSTRUMENT[side(s)][0],
            Constraint::CosQs2Singular(s) => INSTRUMENT[side(s)][1],
            Constraint::Qs3Singular(s) => INSTRUMENT[side(s)][2],
            Constraint::JointLimit(s, Joint::Qs1) => INSTRUMENT[side(s)][3],
            Constraint::JointLimit(s, Joint::Qs2) => INSTRUMENT[side(s)][4],
            Constraint::JointLimit(s, Joint::Qs3) => INSTRUMENT[side(s)][5],
            Constraint::Clearance(ClearancePair::LeftRight) => "clearance.left_right",
            Constraint::Clearance(ClearancePair::LeftEndoscope) => "clearance.left_endoscope",
            Constraint::Clearance(ClearancePair::RightEndoscope) => "clearance.right_endoscope",
            Constraint::Other => "error",
            Constraint::NoGo(_) => "no_go",
        }
    }

    /// The code with the forbidden regions' names, `regions` (the anatomy
    /// file's, in order: [`ReachMap::regions`](crate::ReachMap::regions)):
    /// `no_go.<name>` for [`Constraint::NoGo`], [`Constraint::code`] for
    /// the others (and for a region index beyond `regions`).
    pub fn code_in(self, regions: &[String]) -> Cow<'static, str> {
        match self {
            Constraint::NoGo(i) => match regions.get(usize::from(i)) {
                Some(name) => Cow::Owned(format!("no_go.{name}")),
                None => Cow::Borrowed(self.code()),
            },
            _ => Cow::Borrowed(self.code()),
        }
    }

    /// The constraint of a code ([`Constraint::code`]'s inverse).
    pub fn from_code(code: &str) -> Option<Constraint> {
        Constraint::all().into_iter().find(|c| c.code() == code)
    }

    /// The constraint of a code among `regions`' as well
    /// ([`Constraint::code_in`]'s inverse).
    pub fn from_code_in(code: &str, regions: &[String]) -> Option<Constraint> {
        Constraint::with_regions(regions.len())
            .into_iter()
            .find(|c| c.code_in(regions) == code)
    }

    /// The constraint an error of the controller names.
    pub fn of_error(error: &Error) -> Constraint {
        let index = |actuator: u8| actuator.saturating_sub(1);
        match *error {
            Error::LegOutOfReach { actuator, .. } => Constraint::LegOutOfReach(index(actuator)),
            Error::SerialSingular { actuator, .. } => Constraint::SerialSingular(index(actuator)),
            Error::ActuatorLimit { actuator, .. } => Constraint::Stroke(index(actuator)),
            Error::ParallelSingular { .. } => Constraint::ParallelSingular,
            Error::OutOfReach { side, .. } => Constraint::OutOfReach(side),
            Error::Singular {
                side,
                margin: InstrumentSingularity::CosQs2,
                ..
            } => Constraint::CosQs2Singular(side),
            Error::Singular {
                side,
                margin: InstrumentSingularity::Qs3,
                ..
            } => Constraint::Qs3Singular(side),
            Error::JointLimit { side, joint, .. } => Constraint::JointLimit(side, joint),
            _ => Constraint::Other,
        }
    }
}

impl core::fmt::Display for Constraint {
    /// The code; a forbidden region, whose name the constraint does not
    /// hold, as `no_go[<index>]`.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Constraint::NoGo(i) => f.pad(&format!("no_go[{i}]")),
            _ => f.pad(self.code()),
        }
    }
}

/// The verdict on one orientation: the first constraint violated (or
/// [`Constraint::Ok`]) and the normalised margin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verdict {
    /// The first constraint the controller found violated, or `Ok`.
    pub limiting: Constraint,
    /// The normalised margin (see the [module docs](crate), *Margin*):
    /// on a feasible orientation the smallest over every constraint, on an
    /// infeasible one the violated constraint's (negative).
    pub margin: f64,
    /// On a feasible orientation, the constraint with the smallest margin
    /// (the nearest one); on an infeasible one, `limiting`.
    pub nearest: Constraint,
}

impl Verdict {
    /// Whether the orientation is feasible.
    pub fn feasible(&self) -> bool {
        self.limiting == Constraint::Ok
    }
}

/// `value`'s distance inside `range` over its width: 0.5 in the middle, 0 on
/// a bound, negative beyond; `None` for an unbounded range.
fn relative(range: &Interval<f64>, value: f64) -> Option<f64> {
    relative_in(range, width(range), value)
}

/// The width of `range`, `None` when it is unbounded (or empty).
fn width(range: &Interval<f64>) -> Option<f64> {
    let width = range.max - range.min;
    (width.is_finite() && width > 0.0).then_some(width)
}

/// [`relative`] with `range`'s [`width`] known.
fn relative_in(range: &Interval<f64>, width: Option<f64>, value: f64) -> Option<f64> {
    width.map(|width| range.margin(value) / width)
}

/// The scale of an instrument's `qs3` singular margin: the width of
/// `qs3`'s range, or 1 mm when it is unbounded.
fn qs3_scale(limits: &JointLimits<f64>) -> f64 {
    width(&limits.qs3).unwrap_or(1.0)
}

/// The widths the normalised margins divide by, taken once from the
/// controller's geometry: each actuator's stroke ([`width`]), each
/// instrument joint's range (left, right), each instrument's `qs3` scale
/// ([`qs3_scale`]).
#[derive(Debug, Clone, Copy)]
struct Scales {
    stroke: [Option<f64>; 6],
    joints: [[Option<f64>; 3]; 2],
    qs3: [f64; 2],
}

/// The bodies a [`Checker`] measures: their sizes and the endoscope's
/// depth, mm; the clearance stop threshold when the robot file gives
/// clearance thresholds; the forbidden regions when the scenario has an
/// anatomy.
#[derive(Debug, Clone)]
struct BodyCheck {
    bodies: BodyGeometry<f64>,
    depth_mm: f64,
    clearance_stop_mm: Option<f64>,
    no_go: Option<NoGoCheck>,
}

/// One orientation's check, as the controller runs it every cycle.
///
/// Holds a [`Controller`] and a margin tracker of its own (the parallel
/// margin tracked from one call to the next, as in a control loop), the
/// tips, and the start pose; and, when the scenario's robot file gives
/// clearance thresholds (`[supervisor]`'s `clearance_warn_mm` or
/// `clearance_stop_mm`), the bodies: an orientation where a gap between the
/// shafts and the endoscope is below the stop threshold is infeasible
/// ([`Constraint::Clearance`]), as a planned run there would fail. With an
/// anatomy (`Scenario::anatomy`), likewise an orientation where the in-body
/// part of a shaft or of the endoscope comes closer to a forbidden region
/// than the stop threshold ([`Constraint::NoGo`]). The bodies are built
/// once per orientation for both.
#[derive(Debug, Clone)]
pub struct Checker {
    controller: Controller<f64>,
    tracker: MarginTracker<f64>,
    tips: TipTargets<f64>,
    start: Pose<f64>,
    bodies: Option<BodyCheck>,
    scales: Scales,
}

impl Checker {
    /// The checker of `scenario`'s robot, tips and start pose (its
    /// reorientation, limits and rate are not used).
    ///
    /// # Errors
    /// [`SimulationError::Geometry`] for an invalid robot,
    /// [`SimulationError::Kinematics`] for a non-finite start pose or tip.
    pub fn new(scenario: &Scenario) -> Result<Self, SimulationError> {
        let controller =
            Controller::from_geometry(&scenario.robot).map_err(SimulationError::Geometry)?;
        let start = scenario.start();
        let tips = scenario.tips();
        let fail = |error| SimulationError::Kinematics {
            t: 0.0,
            sample: None,
            error,
        };
        start.check_finite().map_err(fail)?;
        for (what, v) in [("left tip", tips.left), ("right tip", tips.right)] {
            if let Some(value) = v.iter().copied().find(|x| !x.is_finite()) {
                return Err(fail(Error::NonFinite { what, value }));
            }
        }
        let clearance_stop_mm = scenario.supervisor.clearance().map(|[_, stop_mm]| stop_mm);
        let no_go = NoGoCheck::of(scenario);
        let bodies = (clearance_stop_mm.is_some() || no_go.is_some()).then_some(BodyCheck {
            bodies: scenario.bodies,
            depth_mm: scenario.endoscope_depth_mm,
            clearance_stop_mm,
            no_go,
        });
        let joints = |limits: &JointLimits<f64>| {
            [width(&limits.qs1), width(&limits.qs2), width(&limits.qs3)]
        };
        let scales = Scales {
            stroke: controller
                .module1
                .geometry()
                .guides
                .each_ref()
                .map(|g| width(&g.stroke)),
            joints: [
                joints(&controller.left.geometry().limits),
                joints(&controller.right.geometry().limits),
            ],
            qs3: [
                qs3_scale(&controller.left.geometry().limits),
                qs3_scale(&controller.right.geometry().limits),
            ],
        };
        Ok(Self {
            controller,
            tracker: MarginTracker::new(),
            tips,
            start,
            bodies,
            scales,
        })
    }

    /// The forbidden regions' names, in the anatomy file's order (empty
    /// without an anatomy): [`Constraint::NoGo`]`(i)` is the `i`-th.
    pub fn regions(&self) -> Vec<String> {
        self.bodies
            .as_ref()
            .and_then(|b| b.no_go.as_ref())
            .map(NoGoCheck::names)
            .unwrap_or_default()
    }

    /// The start pose, mm and rad.
    pub fn start(&self) -> &Pose<f64> {
        &self.start
    }

    /// The tips held still, mm, fixed frame.
    pub fn tips(&self) -> &TipTargets<f64> {
        &self.tips
    }

    /// The controller.
    pub fn controller(&self) -> &Controller<f64> {
        &self.controller
    }

    /// Module 1's weakest direction after the last check (see
    /// [`MarginTracker::weakest`]).
    pub(crate) fn weakest(&self) -> Option<[f64; 6]> {
        self.tracker.weakest()
    }

    /// How many parallel margins the checker's tracker has computed: a
    /// check that raises it found module 1's weakest direction at its own
    /// orientation (one that fails before the margin leaves the last).
    pub(crate) fn margins(&self) -> u64 {
        self.tracker.counts().0
    }

    /// The margin tracker restarted from `direction` (a neighbouring
    /// check's [`weakest`](Self::weakest), or a guess from several): the
    /// next margin starts from it instead of the last check's direction,
    /// and is certified as any tracked margin.
    pub(crate) fn start_from(&mut self, direction: [f64; 6]) {
        self.tracker = MarginTracker::from_direction(direction);
    }

    /// The pose at the increments `dpsi`, `dtheta` (rad) from the start,
    /// `P` and `phi` unchanged.
    pub fn pose(&self, dpsi: f64, dtheta: f64) -> Pose<f64> {
        Pose {
            psi: self.start.psi + dpsi,
            theta: self.start.theta + dtheta,
            ..self.start
        }
    }

    /// The controller's step with the platform at rest at `(dpsi, dtheta)`
    /// from the start (rad) and the tips held ([`Controller::step_at_rest`]:
    /// [`Controller::step`]'s numbers, the rates and accelerations zero
    /// without being evaluated).
    ///
    /// # Errors
    /// The controller's, unchanged.
    pub fn step(&mut self, dpsi: f64, dtheta: f64) -> Result<ControlStep<f64>, Error> {
        self.controller
            .step_at_rest(&self.pose(dpsi, dtheta), &self.tips, &mut self.tracker)
    }

    /// Whether `(dpsi, dtheta)` (rad from the start) is feasible.
    pub fn feasible(&mut self, dpsi: f64, dtheta: f64) -> bool {
        // Matched in place: the step is not moved out of the result.
        match &self.step(dpsi, dtheta) {
            Ok(step) => self
                .gaps(step)
                .is_some_and(|gaps| gaps.iter().all(|g| g.1 >= 0.0)),
            Err(_) => false,
        }
    }

    /// The verdict at `(dpsi, dtheta)` (rad from the start).
    pub fn check(&mut self, dpsi: f64, dtheta: f64) -> Verdict {
        match &self.step(dpsi, dtheta) {
            Ok(step) => self.verdict(step),
            Err(error) => self.refusal(error),
        }
    }

    /// The verdict at `(dpsi, dtheta)` (rad from the start), with the
    /// controller's step there when the orientation is feasible.
    pub fn check_step(&mut self, dpsi: f64, dtheta: f64) -> (Verdict, Option<ControlStep<f64>>) {
        match self.step(dpsi, dtheta) {
            Ok(step) => {
                let verdict = self.verdict(&step);
                (verdict, verdict.feasible().then_some(step))
            }
            Err(error) => (self.refusal(&error), None),
        }
    }

    /// The verdict on a step the controller made: the bodies' first gap
    /// below its threshold, or the smallest margin of all.
    fn verdict(&self, step: &ControlStep<f64>) -> Verdict {
        match self.gaps(step) {
            Some(gaps) => match gaps.iter().find(|g| !(g.1 >= 0.0)) {
                Some(&(limiting, margin)) => Verdict {
                    limiting,
                    margin,
                    nearest: limiting,
                },
                None => self.margin_of(step, &gaps),
            },
            None => Verdict {
                limiting: Constraint::Other,
                margin: f64::NAN,
                nearest: Constraint::Other,
            },
        }
    }

    /// The verdict on a step the controller refused with `error`.
    fn refusal(&self, error: &Error) -> Verdict {
        let limiting = Constraint::of_error(error);
        Verdict {
            limiting,
            margin: self.violation(error),
            nearest: limiting,
        }
    }

    /// The scale of an instrument's `qs3` singular margin (see
    /// [`qs3_scale`]).
    fn qs3_scale(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.scales.qs3[0],
            Side::Right => self.scales.qs3[1],
        }
    }

    /// The normalised margins of the bodies at `step`: each pair's
    /// clearance when the robot file gives clearance thresholds (in the
    /// order of [`ClearancePair::ALL`]: the gap's distance above the stop
    /// threshold over the two bodies' radii, 0 on the threshold, negative
    /// below, 1 when the gap exceeds the threshold by both radii), then
    /// each forbidden region's when the scenario has an anatomy (in the
    /// file's order; see `NoGoCheck::margins`); none when neither is
    /// checked. `None` for a body's non-finite end or a failed query.
    fn gaps(&self, step: &ControlStep<f64>) -> Option<Vec<(Constraint, f64)>> {
        let Some(check) = &self.bodies else {
            return Some(Vec::new());
        };
        let bodies = Bodies::at(
            &check.bodies,
            &step.frame,
            &self.controller.left,
            &step.left.q,
            &self.controller.right,
            &step.right.q,
            check.depth_mm,
        )
        .ok()?;
        let mut out = Vec::new();
        if let Some(stop_mm) = check.clearance_stop_mm {
            let gaps = bodies.clearance().ok()?;
            let radii = |pair| match pair {
                ClearancePair::LeftRight => bodies.left.radius + bodies.right.radius,
                ClearancePair::LeftEndoscope => bodies.left.radius + bodies.endoscope.radius,
                ClearancePair::RightEndoscope => bodies.right.radius + bodies.endoscope.radius,
            };
            out.extend(ClearancePair::ALL.into_iter().map(|pair| {
                let scale = radii(pair);
                let scale = if scale > 0.0 { scale } else { 1.0 };
                (
                    Constraint::Clearance(pair),
                    (gaps.get(pair).gap - stop_mm) / scale,
                )
            }));
        }
        if let Some(no_go) = &check.no_go {
            let margins = no_go.margins(&bodies, step, check.depth_mm)?;
            out.extend(margins.into_iter().map(|(region, margin)| {
                let index = u16::try_from(region).unwrap_or(u16::MAX);
                (Constraint::NoGo(index), margin)
            }));
        }
        Some(out)
    }

    /// The smallest normalised margin of a successful step, the bodies'
    /// margins `gaps` included.
    fn margin_of(&self, step: &ControlStep<f64>, gaps: &[(Constraint, f64)]) -> Verdict {
        let mut best = (f64::INFINITY, Constraint::Ok);
        let mut consider = |value: Option<f64>, c: Constraint| {
            if let Some(v) = value
                && v < best.0
            {
                best = (v, c);
            }
        };
        let m1 = self.controller.module1.geometry();
        let margins = &step.module1.margins;
        for (j, (g, w)) in m1.guides.iter().zip(self.scales.stroke).enumerate() {
            let index = u8::try_from(j).unwrap_or(u8::MAX);
            consider(
                relative_in(&g.stroke, w, step.module1.q[j]),
                Constraint::Stroke(index),
            );
            consider(
                margins.serial.get(j).map(|s| s - m1.thresholds.serial),
                Constraint::SerialSingular(index),
            );
        }
        consider(
            Some(margins.parallel - m1.thresholds.parallel_command),
            Constraint::ParallelSingular,
        );
        for (side, module, sol, [w1, w2, w3]) in [
            (
                Side::Left,
                &self.controller.left,
                &step.left,
                self.scales.joints[0],
            ),
            (
                Side::Right,
                &self.controller.right,
                &step.right,
                self.scales.joints[1],
            ),
        ] {
            let g = module.geometry();
            let q = &sol.q;
            consider(
                relative_in(&g.limits.qs1, w1, q.qs1),
                Constraint::JointLimit(side, Joint::Qs1),
            );
            consider(
                relative_in(&g.limits.qs2, w2, q.qs2),
                Constraint::JointLimit(side, Joint::Qs2),
            );
            consider(
                relative_in(&g.limits.qs3, w3, q.qs3),
                Constraint::JointLimit(side, Joint::Qs3),
            );
            consider(
                Some(sol.margins.cos_qs2 - g.thresholds.cos_qs2),
                Constraint::CosQs2Singular(side),
            );
            consider(
                Some((q.qs3 - g.thresholds.qs3) / self.qs3_scale(side)),
                Constraint::Qs3Singular(side),
            );
        }
        for &(constraint, margin) in gaps {
            consider(Some(margin), constraint);
        }
        Verdict {
            limiting: Constraint::Ok,
            margin: best.0,
            nearest: best.1,
        }
    }

    /// The normalised (negative) margin of the constraint an error names.
    fn violation(&self, error: &Error) -> f64 {
        let m1 = self.controller.module1.geometry();
        let span = |value: f64, min: f64, max: f64| {
            relative(&Interval::new(min, max), value).unwrap_or(f64::NAN)
        };
        match *error {
            Error::LegOutOfReach {
                actuator,
                discriminant,
            } => {
                // The serial margin |e.u| / l continued below 0: sqrt of the
                // (negative) discriminant over the link.
                let l = m1
                    .guides
                    .get(usize::from(actuator.saturating_sub(1)))
                    .map_or(f64::NAN, |g| g.link_length);
                -(-discriminant).max(0.0).sqrt() / l - m1.thresholds.serial
            }
            Error::SerialSingular {
                margin, threshold, ..
            }
            | Error::ParallelSingular { margin, threshold } => margin - threshold,
            Error::ActuatorLimit {
                value, min, max, ..
            }
            | Error::JointLimit {
                value, min, max, ..
            } => span(value, min, max),
            Error::OutOfReach { side, sin_qs2 } => {
                let th = match side {
                    Side::Left => self.controller.left.geometry().thresholds.cos_qs2,
                    Side::Right => self.controller.right.geometry().thresholds.cos_qs2,
                };
                (1.0 - sin_qs2) - th
            }
            Error::Singular {
                margin: InstrumentSingularity::CosQs2,
                value,
                threshold,
                ..
            } => value - threshold,
            Error::Singular {
                side,
                margin: InstrumentSingularity::Qs3,
                value,
                threshold,
            } => (value - threshold) / self.qs3_scale(side),
            _ => f64::NAN,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unique_and_indexed_in_order() {
        let all = Constraint::all();
        for (i, c) in all.iter().enumerate() {
            assert_eq!(c.index(), i, "{c}");
            assert_eq!(Constraint::from_code(c.code()), Some(*c));
        }
        assert_eq!(Constraint::Stroke(3).code(), "module1.q4.stroke");
        assert_eq!(
            Constraint::SerialSingular(1).code(),
            "module1.q2.serial_singular"
        );
        assert_eq!(
            Constraint::JointLimit(Side::Left, Joint::Qs2).code(),
            "left.qs2.limit"
        );
        assert_eq!(
            Constraint::OutOfReach(Side::Right).code(),
            "right.out_of_reach"
        );
    }

    #[test]
    fn the_regions_follow_in_the_files_order_with_their_names() {
        let names = ["liver".to_string(), "aorta".to_string()];
        let all = Constraint::with_regions(names.len());
        assert_eq!(all.len(), Constraint::all().len() + 2);
        for (i, c) in all.iter().enumerate() {
            assert_eq!(c.index(), i, "{c}");
            assert_eq!(
                Constraint::from_code_in(&c.code_in(&names), &names),
                Some(*c)
            );
        }
        assert_eq!(Constraint::NoGo(1).code_in(&names), "no_go.aorta");
        assert_eq!(Constraint::NoGo(1).code(), "no_go");
        assert_eq!(Constraint::NoGo(5).code_in(&names), "no_go");
        assert_eq!(Constraint::NoGo(0).to_string(), "no_go[0]");
        assert_eq!(Constraint::Other.index(), 35);
        assert_eq!(Constraint::from_code("no_go"), None);
    }
}
