//! A run's summary for people: ranges and peak rates of every actuator and
//! joint, the largest tip drift, the smallest margins, and in a run with
//! commands, each command with the time it took effect and the supervisor's
//! warnings. Accumulated record by record, in constant memory (one entry per
//! command), over the CSV's columns; the text reads them through the
//! [column table](crate::columns)'s named columns.

use core::fmt;

use parasils::supervisor::MarginSet;

use crate::columns::{self, CSV_COUNT, Column};
use parasils::kin::{ACTUATOR_COUNT, Actuator, ActuatorLimits};

use crate::engine::procedure::ProcedureCheck;
use crate::engine::{MotionClearance, Scheduled, Simulation, SimulationError};
use crate::motion::MotionName;
use crate::record::Record;
use crate::scenario::CommandKind;
use crate::sink::Sink;
use crate::timing::{OptimalMotion, PhaseSummary};
use parasils_io::Fixed;

/// Running extremes of every CSV column ([`columns::CSV`]), and the
/// commands as they took effect.
#[derive(Debug, Clone)]
pub struct Summary {
    count: usize,
    min: [f64; CSV_COUNT],
    max: [f64; CSV_COUNT],
    /// Whether module 1 runs on the assumed default geometry (the text says
    /// so).
    pub module1_assumed: bool,
    /// Where module 1's dimensions come from, when known (a calibrated
    /// geometry is labelled with its record).
    module1_provenance: Option<parasils::kin::Provenance>,
    /// The commands scheduled, in a run with commands (else empty), and
    /// whether their angles are final ones.
    schedule: Vec<Scheduled>,
    absolute: bool,
    /// The commands as they took effect: index, kind, first time.
    effective: Vec<(u32, CommandKind, f64)>,
    /// Samples with a supervisor warning, the first one's time, and the
    /// margins warned about.
    warned: usize,
    first_warning: Option<f64>,
    warnings: MarginSet,
    /// A procedure's check (its motions and warnings), listed after the
    /// margins.
    procedure: Option<ProcedureCheck>,
    /// The actuators' limits, and each actuator's largest fraction of its
    /// velocity and of its acceleration limit so far.
    limits: ActuatorLimits<f64>,
    usage: [[f64; ACTUATOR_COUNT]; 2],
    /// With tip loads, each actuator's largest fraction of its force limit.
    force_usage: Option<[f64; ACTUATOR_COUNT]>,
    /// The time-optimal law's phases, for a run timed with it.
    phases: Vec<NamedPhase>,
    /// A single planned turn's law duration before it was stretched onto
    /// the control cycle, s, when the stretch changed it.
    planned_s: Option<f64>,
}

impl Default for Summary {
    fn default() -> Self {
        Self::new(false)
    }
}

impl Sink for Summary {
    type Error = core::convert::Infallible;

    fn push(&mut self, record: &Record) -> Result<(), Self::Error> {
        self.count += 1;
        if self.effective.last().is_none_or(|c| c.0 != record.command) {
            self.effective.push((record.command, record.kind, record.t));
        }
        if !record.warnings.is_empty() {
            self.warned += 1;
            self.first_warning.get_or_insert(record.t);
            self.warnings = self.warnings.union(record.warnings);
        }
        record.widen_usage(&mut self.usage, &self.limits);
        if let Some(usage) = &mut self.force_usage {
            record.widen_force_usage(usage, &self.limits);
        }
        for (i, column) in columns::CSV.iter().enumerate() {
            let v = column.value(record);
            self.min[i] = self.min[i].min(v);
            self.max[i] = self.max[i].max(v);
        }
        Ok(())
    }
}

impl Summary {
    /// An empty summary; `module1_assumed` says whether module 1's geometry
    /// is the assumed one.
    pub fn new(module1_assumed: bool) -> Self {
        Self {
            count: 0,
            min: [f64::INFINITY; CSV_COUNT],
            max: [f64::NEG_INFINITY; CSV_COUNT],
            module1_assumed,
            module1_provenance: None,
            schedule: Vec::new(),
            absolute: false,
            effective: Vec::new(),
            warned: 0,
            first_warning: None,
            warnings: MarginSet::EMPTY,
            procedure: None,
            limits: ActuatorLimits::assumed(),
            usage: [[0.0; ACTUATOR_COUNT]; 2],
            force_usage: None,
            phases: Vec::new(),
            planned_s: None,
        }
    }

    /// An empty summary of `sim`'s run: whether module 1's geometry is
    /// assumed and, in a run with commands, the commands, which the text
    /// lists with the times they took effect.
    pub fn for_simulation(sim: &Simulation) -> Self {
        let mut s = Self::new(sim.module1_assumed());
        s.module1_provenance = Some(sim.scenario().robot.module1.provenance());
        if sim.scenario().has_commands() {
            s.schedule = sim.schedule().to_vec();
            s.absolute = sim.scenario().turn().is_some_and(|t| t.absolute);
        }
        s.procedure = sim.procedure_check().cloned();
        if has_loads(sim) {
            s.force_usage = Some([0.0; ACTUATOR_COUNT]);
        }
        s.limits = sim.controller().limits;
        s.phases = optimal_phases(sim);
        s.planned_s = planned_turn(sim).filter(|&t| t != sim.duration());
        s
    }

    /// The commands as they took effect, in order: the index (the `command`
    /// column), what it is, and the time of the first record it was active
    /// at, s.
    pub fn commands(&self) -> &[(u32, CommandKind, f64)] {
        &self.effective
    }

    /// The number of records with a margin below its supervisor warning
    /// threshold, and the margins that were.
    pub fn warnings(&self) -> (usize, MarginSet) {
        (self.warned, self.warnings)
    }

    /// The number of records seen.
    pub fn count(&self) -> usize {
        self.count
    }

    /// `(min, max)` of a column, in its unit; `None` before the first record
    /// or for a column the CSV does not have.
    pub fn range(&self, column: &Column) -> Option<(f64, f64)> {
        let i = columns::csv_index(column)?;
        (self.count > 0).then_some((self.min[i], self.max[i]))
    }

    /// The largest absolute value of a column.
    pub fn peak(&self, column: &Column) -> Option<f64> {
        self.range(column).map(|(lo, hi)| lo.abs().max(hi.abs()))
    }

    /// The largest distance of each tip from its target, `[left, right]`, mm.
    pub fn tip_drift(&self) -> [f64; 2] {
        [&columns::LEFT, &columns::RIGHT].map(|m| self.range(&m.tip_err).map_or(f64::NAN, |r| r.1))
    }

    /// The largest tip drift of both modules, mm.
    pub fn largest_tip_drift(&self) -> f64 {
        let [l, r] = self.tip_drift();
        l.max(r)
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = |c: &Column| self.range(c).unwrap_or((f64::NAN, f64::NAN));
        let p = |c: &Column| Fixed(self.peak(c).unwrap_or(f64::NAN), 4);
        let (t0, t1) = r(&columns::T_S);
        write!(
            f,
            "duration {} s, {} samples ({} to {} s)",
            Fixed(t1 - t0, 3),
            self.count,
            Fixed(t0, 3),
            Fixed(t1, 3)
        )?;
        match self.planned_s {
            Some(planned) => writeln!(
                f,
                "; the law's {} s stretched to whole periods",
                Fixed(planned, 4)
            )?,
            None => writeln!(f)?,
        }
        writeln!(f, "platform")?;
        for (a, angle, rate, acc) in [
            (
                "psi",
                &columns::PSI_DEG,
                &columns::PSI_RATE_DEG_S,
                &columns::PSI_ACC_DEG_S2,
            ),
            (
                "theta",
                &columns::THETA_DEG,
                &columns::THETA_RATE_DEG_S,
                &columns::THETA_ACC_DEG_S2,
            ),
        ] {
            let (lo, hi) = r(angle);
            writeln!(
                f,
                "  {a:<6} {:>9} .. {:>9} deg    peak rate {:>8} deg/s    peak acc {:>8} deg/s^2",
                Fixed(lo, 4),
                Fixed(hi, 4),
                p(rate),
                p(acc)
            )?;
        }
        writeln!(f, "module 1 actuators")?;
        if self.module1_assumed {
            writeln!(
                f,
                "  (module 1 uses the ASSUMED default geometry: the real robot's dimensions are not published; pass --robot FILE.toml)"
            )?;
        } else if let Some(p @ parasils::kin::Provenance::Calibrated(_)) = self.module1_provenance {
            writeln!(f, "  (module 1 {p})")?;
        }
        for j in 0..6 {
            let (lo, hi) = r(&columns::Q_MM[j]);
            writeln!(
                f,
                "  q{}     {:>9} .. {:>9} mm     peak rate {:>8} mm/s     peak acc {:>8} mm/s^2",
                j + 1,
                Fixed(lo, 4),
                Fixed(hi, 4),
                p(&columns::Q_RATE_MM_S[j]),
                p(&columns::Q_ACC_MM_S2[j])
            )?;
        }
        for (side, m) in [("left", &columns::LEFT), ("right", &columns::RIGHT)] {
            writeln!(f, "{side} instrument")?;
            for (k, (joint, unit, rate_unit)) in [
                ("qs1", "deg", "deg/s"),
                ("qs2", "deg", "deg/s"),
                ("qs3", "mm", "mm/s"),
            ]
            .into_iter()
            .enumerate()
            {
                let (lo, hi) = r(&m.q[k]);
                writeln!(
                    f,
                    "  {joint}    {:>9} .. {:>9} {unit:<3}    peak rate {:>8} {rate_unit}",
                    Fixed(lo, 4),
                    Fixed(hi, 4),
                    p(&m.q_rate[k])
                )?;
            }
        }
        let [left, right] = self.tip_drift();
        writeln!(
            f,
            "largest tip drift {:.3e} mm (left {left:.3e}, right {right:.3e})",
            self.largest_tip_drift(),
        )?;
        let cos_l = r(&columns::LEFT.cos_qs2);
        let cos_r = r(&columns::RIGHT.cos_qs2);
        write!(
            f,
            "smallest margins: |cos qs2| left {}, right {}; module 1 serial {}, parallel {}",
            Fixed(cos_l.0.abs().min(cos_l.1.abs()), 4),
            Fixed(cos_r.0.abs().min(cos_r.1.abs()), 4),
            Fixed(r(&columns::MODULE1_SERIAL_MARGIN).0, 4),
            Fixed(r(&columns::MODULE1_PARALLEL_MARGIN).0, 4)
        )?;
        write!(f, "\n{}", Usage(&self.usage))?;
        if let Some(usage) = &self.force_usage {
            write!(f, "\n{}", ForceUsage(usage))?;
        }
        if !self.phases.is_empty() {
            write!(f, "\n{}", Phases(&self.phases))?;
        }
        if !self.schedule.is_empty() {
            self.write_commands(f)?;
        }
        if let Some(check) = &self.procedure {
            write!(f, "\n{}", MotionTable(check, None))?;
        }
        Ok(())
    }
}

/// Each actuator's peak use of its limits, velocity and acceleration.
struct Usage<'a>(&'a [[f64; ACTUATOR_COUNT]; 2]);

impl fmt::Display for Usage<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "actuator limits, peak use (velocity, acceleration):")?;
        for (k, a) in Actuator::ALL.iter().enumerate() {
            let name = a.to_string().replace("module 1 ", "");
            if k % 6 == 0 {
                write!(f, "\n ")?;
            }
            write!(
                f,
                " {name} {} {}",
                Fixed(self.0[0][k], 3),
                Fixed(self.0[1][k], 3)
            )?;
        }
        Ok(())
    }
}

/// Whether `sim`'s run has forces (tip loads or the platform's dynamics).
fn has_loads(sim: &Simulation) -> bool {
    sim.scenario().has_forces()
}

/// Each actuator's peak use of its force limit.
struct ForceUsage<'a>(&'a [f64; ACTUATOR_COUNT]);

impl fmt::Display for ForceUsage<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "force limits, peak use:")?;
        for (k, a) in Actuator::ALL.iter().enumerate() {
            let name = a.to_string().replace("module 1 ", "");
            if k % 6 == 0 {
                write!(f, "\n ")?;
            }
            write!(f, " {name} {}", Fixed(self.0[k], 3))?;
        }
        Ok(())
    }
}

/// A procedure's motions as a table (type, name, start, duration on the
/// time line, the law's planned and stretched durations, peak
/// rates, smallest margins, largest tip error, what is inside the patient
/// when it starts), the smallest sampled clearance of each pair of bodies
/// per motion (with its certified lower bound, when given), each port's
/// largest displacement per motion, what the camera saw in the motions that
/// follow the tips, each motion's smallest sampled gap to each forbidden
/// region (with its certified lower bound, when given), then every
/// supervisor warning with its motion and times.
struct MotionTable<'a>(&'a ProcedureCheck, Option<&'a [MotionClearance]>);

impl fmt::Display for MotionTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use parasils::supervisor::Margin;
        writeln!(
            f,
            "motion type        name                         start_s duration_s planned_s stretched_s q_rate_mm_s qs12_rate_deg_s qs3_rate_mm_s min_cos_qs2 min_serial min_parallel min_stroke_mm tip_err_mm inside"
        )?;
        for m in &self.0.motions {
            let s = &m.smallest;
            let name: String = m
                .name
                .name
                .as_deref()
                .unwrap_or("-")
                .chars()
                .take(28)
                .collect();
            writeln!(
                f,
                "{:>6} {}:{:<10} {:<28} {:>7} {:>10} {:>9} {:>11} {:>11} {:>15} {:>13} {:>11} {:>10} {:>12} {:>13} {:>10.3e} {}",
                m.name.index,
                m.name.motion_type.number(),
                m.name.type_name(),
                name,
                Fixed(m.start_s, 3),
                Fixed(m.duration_s, 3),
                Fixed(m.planned_s, 4),
                Fixed(m.stretched_s, 4),
                Fixed(m.peak_module1_mm_s, 3),
                Fixed(m.peak_joint_rad_s.to_degrees(), 3),
                Fixed(m.peak_qs3_mm_s, 3),
                Fixed(s[Margin::LeftCosQs2].min(s[Margin::RightCosQs2]), 4),
                Fixed(s[Margin::Serial], 4),
                Fixed(s[Margin::Parallel], 4),
                Fixed(s[Margin::Stroke], 3),
                m.tip_err_mm,
                m.inside
            )?;
        }
        match self.1 {
            None => {
                writeln!(
                    f,
                    "clearance per motion, smallest sampled gap, mm: left_right left_endoscope right_endoscope"
                )?;
                for m in &self.0.motions {
                    let c = &m.clearance_mm;
                    writeln!(
                        f,
                        "{:>6} {:>10} {:>14} {:>15}",
                        m.name.index,
                        Fixed(c.left_right, 3),
                        Fixed(c.left_endoscope, 3),
                        Fixed(c.right_endoscope, 3)
                    )?;
                }
            }
            Some(certified) => write!(f, "{}", CertifiedTable(self.0, certified))?,
        }
        writeln!(
            f,
            "ports per motion, largest displacement from the motion's start, mm: left right endoscope"
        )?;
        for m in &self.0.motions {
            let [l, r, e] = m.port_motion_mm;
            writeln!(
                f,
                "{:>6} {:>10} {:>10} {:>10}",
                m.name.index,
                Fixed(l, 3),
                Fixed(r, 3),
                Fixed(e, 3)
            )?;
        }
        if self.0.motions.iter().any(|m| m.camera.is_some()) {
            writeln!(
                f,
                "camera following the tips, per motion: both_in_view_pct central_80_pct settles settled_aim_error_deg"
            )?;
            for m in &self.0.motions {
                let Some(c) = &m.camera else { continue };
                writeln!(
                    f,
                    "{:>6} {:>16} {:>14} {:>7} {:>21}",
                    m.name.index,
                    Fixed(100.0 * c.in_view_share(), 3),
                    Fixed(100.0 * c.central_share(), 3),
                    c.settles,
                    c.settled_aim_error_deg
                        .map_or_else(|| String::from("-"), |e| format!("{e:.3e}")),
                )?;
            }
        }
        if !self.0.no_go_regions.is_empty() {
            let what = if self.1.is_some() {
                "smallest sampled gap / certified minimum between samples to each forbidden region"
            } else {
                "smallest sampled gap to each forbidden region"
            };
            let names = self.0.no_go_regions.join(" ");
            writeln!(f, "no-go clearance per motion, {what}, mm: {names}")?;
            let shown = |gap: f64| {
                if gap.is_finite() {
                    Fixed(gap, 3).to_string()
                } else {
                    String::from("outside")
                }
            };
            for (i, m) in self.0.motions.iter().enumerate() {
                write!(f, "{:>6}", m.name.index)?;
                let certified = self.1.and_then(|c| c.get(i));
                for (k, name) in self.0.no_go_regions.iter().enumerate() {
                    let gap = shown(m.no_go_mm.get(k).copied().unwrap_or(f64::INFINITY));
                    let cell = match certified {
                        Some(c) => format!("{gap} / {}", shown(c.no_go_certified_mm(k))),
                        None => gap,
                    };
                    let width = name.len().max(if certified.is_some() { 20 } else { 10 });
                    write!(f, " {cell:>width$}")?;
                }
                if certified.is_some_and(|c| c.no_go.iter().any(|r| !r.converged)) {
                    write!(f, "  (refinement capped: the bound is loose)")?;
                }
                writeln!(f)?;
            }
        }
        if self.0.warnings.is_empty() {
            write!(f, "supervisor: no margin below its warning threshold")
        } else {
            write!(f, "supervisor warnings ({}):", self.0.warnings.len())?;
            for w in &self.0.warnings {
                let name = self.0.motions.get(w.motion).map(|m| m.name.to_string());
                write!(
                    f,
                    "\n  {}: {} below {} {} from t = {} to {} s (smallest {})",
                    name.as_deref().unwrap_or("?"),
                    w.margin.name(),
                    parasils_io::Shortest(w.threshold),
                    w.margin.unit(),
                    Fixed(w.from_s, 3),
                    Fixed(w.until_s, 3),
                    parasils_io::Shortest(w.smallest),
                )?;
            }
            Ok(())
        }
    }
}

/// Per motion and pair, the smallest sampled gap and its certified lower
/// bound over the whole motion.
struct CertifiedTable<'a>(&'a ProcedureCheck, &'a [MotionClearance]);

impl fmt::Display for CertifiedTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "clearance per motion, mm, smallest sampled gap / certified minimum between samples: left_right left_endoscope right_endoscope"
        )?;
        for (m, c) in self.0.motions.iter().zip(self.1) {
            let (s, l) = (&m.clearance_mm, &c.certified_mm);
            let pair = |a: f64, b: f64| format!("{} / {}", Fixed(a, 3), Fixed(b, 3));
            writeln!(
                f,
                "{:>6} {:>20} {:>20} {:>20}{}",
                m.name.index,
                pair(s.left_right, l.left_right),
                pair(s.left_endoscope, l.left_endoscope),
                pair(s.right_endoscope, l.right_endoscope),
                if c.converged {
                    ""
                } else {
                    "  (refinement capped: the bound is loose)"
                }
            )?;
        }
        Ok(())
    }
}

/// What `parasils simulate --procedure FILE --check` prints of a procedure
/// that passed its check: the verdict, then the motions' table with each
/// motion's certified clearance, and the warnings. (A procedure that fails
/// does not get this far: its error names the motion, the time inside it
/// and what failed.)
#[derive(Debug)]
pub struct CheckReport<'a> {
    sim: &'a Simulation,
    check: &'a ProcedureCheck,
    certified: Result<Vec<MotionClearance>, SimulationError>,
}

impl<'a> CheckReport<'a> {
    /// The report of `sim`'s `check`, with its clearance certified between
    /// samples ([`Simulation::certify_clearance`]).
    pub fn new(sim: &'a Simulation, check: &'a ProcedureCheck) -> Self {
        Self {
            sim,
            check,
            certified: sim.certify_clearance(),
        }
    }

    /// The certified clearance per motion, or why it could not be computed
    /// (a probe between samples that the kinematics refuse).
    pub fn certified(&self) -> Result<&[MotionClearance], &SimulationError> {
        self.certified.as_deref()
    }
}

impl fmt::Display for CheckReport<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "procedure OK: {} motions, {} s, {} samples at {} Hz, every sample within the joint limits, strokes, actuator rate limits, reach and singularity thresholds; {} supervisor warnings",
            self.check.motions.len(),
            Fixed(self.sim.duration(), 3),
            self.sim.sample_count(),
            parasils_io::Shortest(self.sim.scenario().rate_hz),
            self.check.warnings.len()
        )?;
        if self.sim.module1_assumed() {
            writeln!(
                f,
                "(module 1 uses the ASSUMED default geometry: the real robot's dimensions are not published)"
            )?;
        }
        match &self.certified {
            Ok(c) => writeln!(f, "{}", MotionTable(self.check, Some(c)))?,
            Err(e) => {
                writeln!(f, "{}", MotionTable(self.check, None))?;
                writeln!(f, "clearance not certified between samples: {e}")?;
            }
        }
        write!(f, "{}", Usage(&self.check.usage))?;
        if has_loads(self.sim) {
            write!(f, "\n{}", ForceUsage(&self.check.force_usage))?;
        }
        let phases = optimal_phases(self.sim);
        if !phases.is_empty() {
            write!(f, "\n{}", Phases(&phases))?;
        }
        Ok(())
    }
}

/// The law's own duration of `sim`'s single planned turn (trapezoid or
/// time-optimal), before its stretch onto the control cycle; `None` for a
/// procedure or a run with commands.
fn planned_turn(sim: &Simulation) -> Option<f64> {
    if sim.scenario().is_procedure() {
        return None;
    }
    Some(sim.timeline()?.motions.first()?.planned_s())
}

/// A phase of a time-optimal law, with the motion it belongs to in a
/// procedure.
type NamedPhase = (Option<MotionName>, PhaseSummary);

/// The phases of `sim`'s time-optimal laws (none for a trapezoid run), on
/// the timeline: for a procedure, every motion's, named.
fn optimal_phases(sim: &Simulation) -> Vec<NamedPhase> {
    let Some(plan) = sim.timeline() else {
        return Vec::new();
    };
    let named = sim.scenario().is_procedure();
    let mut out = Vec::new();
    for m in &plan.motions {
        // The law's times, stretched onto the control cycle.
        let r = m.stretch.ratio();
        for p in m.optimal.iter().flat_map(OptimalMotion::phases) {
            let phase = PhaseSummary {
                start_s: p.start_s / r + m.start_s,
                end_s: p.end_s / r + m.start_s,
                ..p
            };
            out.push((named.then(|| m.name.clone()), phase));
        }
    }
    out
}

/// What limits each phase of a time-optimal law.
struct Phases<'a>(&'a [NamedPhase]);

impl fmt::Display for Phases<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "time-optimal timing, what limits each phase:")?;
        for (motion, p) in self.0 {
            match motion {
                Some(m) => write!(f, "\n  {m}: {p}")?,
                None => write!(f, "\n  {p}")?,
            }
        }
        Ok(())
    }
}

impl Summary {
    /// The commands and the supervisor's warnings, after the margins.
    fn write_commands(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "\ncommands (each active from the first sample at or after its time)"
        )?;
        let goal = |s: &Scheduled| match s.command.goal_deg {
            Some([psi, theta]) if self.absolute => {
                format!(": psi = {psi:.4}, theta = {theta:.4} deg")
            }
            Some([psi, theta]) => format!(": psi {psi:+.4}, theta {theta:+.4} deg"),
            None => String::new(),
        };
        let mut planned = self.schedule.iter();
        for (index, kind, t) in &self.effective {
            if *kind == CommandKind::SupervisorStop {
                write!(
                    f,
                    "\n  {index:<3} {:<15} {:<15}active from {:>8} s",
                    kind.name(),
                    "demanded,",
                    Fixed(*t, 3)
                )?;
            } else if let Some(s) = planned.next() {
                write!(
                    f,
                    "\n  {index:<3} {:<15} at {:>8} s, active from {:>8} s{}",
                    kind.name(),
                    Fixed(s.command.t_s, 3),
                    Fixed(*t, 3),
                    goal(s)
                )?;
            }
        }
        for s in planned {
            write!(
                f,
                "\n      {:<15} at {:>8} s, not reached{}",
                s.command.kind.name(),
                Fixed(s.command.t_s, 3),
                goal(s)
            )?;
        }
        match self.first_warning {
            None => write!(f, "\nsupervisor warnings: none"),
            Some(t) => {
                let names: Vec<&str> = self.warnings.iter().map(|m| m.name()).collect();
                write!(
                    f,
                    "\nsupervisor warnings on {} samples, the first at {} s: {}",
                    self.warned,
                    Fixed(t, 3),
                    names.join(", ")
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_peaks_and_the_text() {
        let mut s = Summary::new(true);
        assert_eq!(s.range(&columns::T_S), None);
        for k in 0..3 {
            let mut r = Record {
                t: f64::from(k),
                angles_deg: [-15.0 + f64::from(k), 10.0, -60.0],
                ..Record::default()
            };
            r.module1.q_dot[2] = -2.0 * f64::from(k);
            r.right.tip_err = 1e-13 * f64::from(k);
            s.push(&r).expect("infallible");
        }
        assert_eq!(s.count(), 3);
        assert_eq!(s.range(&columns::PSI_DEG), Some((-15.0, -13.0)));
        assert_eq!(s.peak(&columns::Q_RATE_MM_S[2]), Some(4.0));
        assert_eq!(s.range(&columns::LEFT.tip[0]), None, "MCAP only");
        assert_eq!(s.largest_tip_drift(), 2e-13);
        let text = s.to_string();
        assert!(
            text.starts_with("duration 2.000 s, 3 samples (0.000 to 2.000 s)\n"),
            "{text}"
        );
        assert!(
            text.contains("  psi     -15.0000 ..  -13.0000 deg"),
            "{text}"
        );
        assert!(text.contains("ASSUMED"));
        assert!(text.contains("largest tip drift 2.000e-13 mm (left 0.000e0, right 2.000e-13)"));
    }

    #[test]
    fn huge_values_stay_readable() {
        let mut s = Summary::new(false);
        for t in [0.0, 1e300] {
            s.push(&Record {
                t,
                ..Record::default()
            })
            .expect("infallible");
        }
        let text = s.to_string();
        assert!(
            text.starts_with("duration 1.000e300 s, 2 samples (0.000 to 1.000e300 s)"),
            "{text}"
        );
        assert!(text.len() < 2000, "{text}");
    }
}
