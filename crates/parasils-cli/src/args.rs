//! The command line's arguments (clap): the commands, and the flags they
//! share, defined once.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow};
use clap::{Args, Parser, Subcommand, ValueEnum};
use parasils_calib::FitOptions;
use parasils_calib::plan::PlanOptions;
use parasils_reach::ReachOptions;
use parasils_sim::input::{ProcedureSource, RobotSource, TimingKind};
use parasils_sim::robot_file;
use parasils_sim::scenario::Retarget;
use parasils_sim::{Format, Input, InputError, LookAt, Scenario};

/// Kinematics and motion of PARA-SILSROB, the parallel robot for
/// single-incision laparoscopic surgery.
#[derive(Debug, Parser)]
#[command(name = "parasils", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
#[allow(
    clippy::large_enum_variant,
    reason = "parsed once per process, never in a collection"
)]
pub enum Command {
    /// Simulate an endoscope reorientation (motion type 4): the platform turns
    /// about the endoscope's RCM and both instruments keep their tips still.
    /// Defaults reproduce the paper's section 4.
    Simulate(SimulateArgs),
    /// Map the orientations reachable from the start pose with both tips
    /// held: a grid of (dpsi, dtheta) increments, each checked as the
    /// per-cycle controller checks it, with the boundary refined. Without
    /// -o, a summary.
    Reach(ReachArgs),
    /// Inverse kinematics at one platform pose: module 1's actuators and both
    /// instrument modules' joints (both assembly modes).
    Ik(IkArgs),
    /// Forward kinematics: module 1's pose from its actuators, and the
    /// instrument tips from their joints at that pose.
    Fk(FkArgs),
    /// Print the default robot geometry as TOML, to copy and edit.
    Robot,
    /// Calibrate module 1: fit its geometry to actuator readings at measured
    /// poses (--measurements), or choose the poses to measure (--plan N).
    Calibrate(CalibrateArgs),
    /// Tolerance analysis: how far the instrument tips really move along a
    /// motion when the controller drives the nominal model of a robot built
    /// within tolerances (Monte Carlo over perturbed robots, with the
    /// first-order sensitivity of each parameter family).
    Tolerance(ToleranceArgs),
    /// Teleoperation: the surgeon's console driving the robot cycle by
    /// cycle, from a recorded session (--input FILE.csv) or live SpaceMouse
    /// devices (--device auto); the same output and summary as simulate,
    /// with each device's inputs and the operating state.
    Teleop(TeleopArgs),
    /// Serve the robot live to Foxglove (WebSocket, foxglove.sdk.v1) at the
    /// control rate, driven by clients' inputs and commands; record to MCAP.
    Serve(ServeArgs),
}

/// `--robot`, shared by `simulate`, `ik` and `fk`.
#[derive(Debug, Args)]
pub struct RobotArg {
    /// Robot geometry (module 1 and both instrument modules) as TOML; see
    /// `parasils robot`. Default: the paper's robot, module 1 assumed.
    #[arg(long, value_name = "FILE.toml")]
    pub robot: Option<PathBuf>,
}

impl RobotArg {
    /// The robot file given, for an [`Input`].
    pub fn source(&self) -> Option<RobotSource> {
        self.robot.clone().map(RobotSource::File)
    }

    /// The robot file's geometry, or the paper's.
    pub fn geometry(&self) -> Result<parasils::kin::RobotGeometry<f64>> {
        Ok(match &self.robot {
            Some(path) => robot_file::load(path)?,
            None => parasils::kin::RobotGeometry::paper(),
        })
    }
}

/// `--pose`, `--tip-left`, `--tip-right`: where the platform is and where
/// the tips are, shared by `simulate` (the start) and `ik`.
#[derive(Debug, Args)]
pub struct PlaceArgs {
    /// Platform pose X,Y,Z,PSI,THETA,PHI (mm, deg); for `simulate`, the
    /// start. Default: the paper's P0 = 15,20,-500,-15,10,-60.
    #[arg(long, value_name = "X,Y,Z,PSI,THETA,PHI", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub pose: Option<[f64; 6]>,
    /// Left tip X,Y,Z (mm, fixed frame), held still. Default: 50,-50,-620.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_left: Option<[f64; 3]>,
    /// Right tip X,Y,Z (mm, fixed frame), held still, or `mirror`: the left
    /// tip's mirror image across the platform's Y'Z' plane at the pose (the
    /// two shafts then intersect). Default: that mirror image moved 35 mm
    /// along X' and 100 mm along Y', clear of the left shaft.
    #[arg(long, value_name = "X,Y,Z|mirror", value_parser = parse_right_tip, allow_hyphen_values = true)]
    pub tip_right: Option<RightTip>,
}

/// `--tip-right`: a point, or the mirror of the left tip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RightTip {
    /// X, Y, Z, mm, fixed frame.
    Mm([f64; 3]),
    /// The left tip's mirror image across the platform's Y'Z' plane.
    Mirror,
}

/// `mirror` or three comma-separated numbers.
pub fn parse_right_tip(s: &str) -> Result<RightTip, String> {
    if s.trim() == "mirror" {
        return Ok(RightTip::Mirror);
    }
    parse_floats::<3>(s).map(RightTip::Mm)
}

impl PlaceArgs {
    /// `input` with the place's pose and tips: the right tip `mirror`
    /// resolved against the input's pose and left tip.
    pub fn fill(&self, mut input: Input) -> Input {
        input.pose_mm_deg = self.pose;
        input.tip_left_mm = self.tip_left;
        input.tip_right_mm = match self.tip_right {
            Some(RightTip::Mm(tip)) => Some(tip),
            Some(RightTip::Mirror) => Some(input.mirrored_right_tip_mm()),
            None => None,
        };
        input
    }
}

/// How the two Euler angles are timed together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SyncArg {
    /// A straight line in (psi, theta): the slower axis sets the timing.
    Phase,
    /// The same duration for both; the faster axis lowers its peak velocity.
    Time,
    /// Each axis on its own minimum-time profile.
    None,
}

impl From<SyncArg> for parasils::traj::Synchronization {
    fn from(s: SyncArg) -> Self {
        match s {
            SyncArg::Phase => Self::Phase,
            SyncArg::Time => Self::Time,
            SyncArg::None => Self::None,
        }
    }
}

/// How `simulate` times the reorientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TimingArg {
    /// Synchronised trapezoids in psi and theta within --omega-max and --eps-max.
    Trapezoid,
    /// Time-optimal under the actuators' limits.
    Optimal,
}

/// Output formats of `simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// One row per sample, every column named with its unit.
    Csv,
    /// MCAP for Foxglove: one channel per group, /tf and /scene.
    Mcap,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Csv => Format::Csv,
            FormatArg::Mcap => Format::Mcap,
        }
    }
}

/// Arguments of `parasils simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// psi: increment from the start pose (final value with --absolute), deg
    /// [default: 15, the paper's].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub psi: Option<f64>,
    /// theta: increment from the start pose (final value with --absolute),
    /// deg [default: 25, the paper's].
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub theta: Option<f64>,
    /// Take --psi and --theta as final angles instead of increments.
    #[arg(long)]
    pub absolute: bool,
    /// Turn the endoscope to look at a point X,Y,Z (mm, fixed frame), or at
    /// the tips: `tips` (their midpoint), `left` or `right`, instead of
    /// --psi and --theta: the turn (phi held, both tips held) that puts it
    /// on the camera's view axis, the one nearest the start pose. Every
    /// timing applies; no --retarget or --stop-at with it.
    #[arg(long, value_name = "X,Y,Z|tips|left|right", value_parser = parse_look_at, allow_hyphen_values = true)]
    pub look_at: Option<LookAt>,
    /// Velocity limit of each Euler angle, deg/s [default: 10, the paper's].
    /// With --timing optimal it binds only when given.
    #[arg(long, value_name = "DEG_PER_S", allow_hyphen_values = true)]
    pub omega_max: Option<f64>,
    /// Acceleration limit of each Euler angle, deg/s^2 [default: 5, the
    /// paper's]. With --timing optimal it binds only when given.
    #[arg(long, value_name = "DEG_PER_S2", allow_hyphen_values = true)]
    pub eps_max: Option<f64>,
    /// Synchronisation of psi and theta [default: phase].
    #[arg(long, value_enum)]
    pub sync: Option<SyncArg>,
    /// How the turn is timed: the paper's trapezoid in psi and theta, or
    /// the fastest law along the same straight line whose twelve actuators
    /// stay within their velocity and acceleration limits (the robot
    /// file's; --omega-max and --eps-max bind as well when given), from
    /// rest to rest, so with no --retarget or --stop-at. With --procedure,
    /// every motion is timed so, from rest to rest; the limits the
    /// procedure states for a motion bind as well [default: trapezoid].
    #[arg(long, value_enum)]
    pub timing: Option<TimingArg>,
    /// Samples per second, Hz [default: 1000, the paper's].
    #[arg(long, value_name = "HZ", allow_hyphen_values = true)]
    pub rate: Option<f64>,
    /// A new goal commanded at T s while the platform moves: PSI,THETA read
    /// like --psi and --theta (increments from the start pose, final angles
    /// with --absolute), deg. It takes effect at the first sample at or after
    /// T, replanned from the state of that sample. Repeatable, in time order.
    /// With --retarget or --stop-at the run goes through the online
    /// controller, whose margin supervisor stops the platform short of a
    /// singularity or a limit; it ends once every command has taken effect
    /// and the platform rests, and the output gets a `command` column (the
    /// index of the active command).
    #[arg(long, value_name = "T:PSI,THETA", value_parser = parse_retarget, allow_hyphen_values = true)]
    pub retarget: Vec<Retarget>,
    /// A controlled stop commanded at T s: psi and theta brought to rest
    /// together at the acceleration limit, along their current direction. A
    /// later --retarget replans from wherever the stop has got to.
    #[arg(long, value_name = "T", value_parser = parse_finite, allow_hyphen_values = true)]
    pub stop_at: Option<f64>,
    /// The force the left tip exerts on the tissue, N, fixed frame
    /// [default: none]. With a tip load the output gets every actuator's
    /// force holding it: q1_force_n..q6_force_n (positive pushing the
    /// slider along its guide's direction), left_/right_qs1_torque_nmm,
    /// _qs2_torque_nmm (N mm) and _qs3_force_n (N), and each tip's
    /// deflection under the tissue's push, left_/right_tip_deflection_mm
    /// (the robot file's [stiffness], assumed by default). A robot file
    /// with a [dynamics] table gives these columns without a load, with the
    /// platform body's weight and inertia.
    #[arg(long, value_name = "FX,FY,FZ", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_load_left: Option<[f64; 3]>,
    /// The force the right tip exerts on the tissue, N, fixed frame
    /// [default: none]; see --tip-load-left.
    #[arg(long, value_name = "FX,FY,FZ", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_load_right: Option<[f64; 3]>,
    /// Forbidden regions: an anatomy file (spheres, boxes, capsules, STL or
    /// OBJ meshes in the fixed frame, mm). Every cycle checks the in-body
    /// part of each shaft and of the endoscope against each region; the
    /// output gets no_go_clearance_mm, and a planned run or procedure that
    /// comes closer than the clearance stop threshold (0.5 mm by default)
    /// fails before any output, naming the region. With --procedure, only
    /// when the procedure names none itself.
    #[arg(long, value_name = "FILE.toml")]
    pub anatomy: Option<PathBuf>,
    /// The start pose and the tips.
    #[command(flatten)]
    pub place: PlaceArgs,
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Write every sample to FILE (format from the extension: .csv, .mcap), or
    /// CSV to standard output with `-o -`. Without it, print a summary.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// The output format, overriding the extension.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Plot the paper's three figures to FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Write the output file even when its estimated size is above the
    /// 10 GB cap (it must still fit in the free space).
    #[arg(long)]
    pub force: bool,
    /// Run a procedure: the motions of FILE.toml (positioning, insertion,
    /// tip manipulation, reorientation), each from where the previous one
    /// ended; its start pose, tips and robot come from the file. The whole
    /// procedure is planned and checked before any output; the output gets
    /// the columns motion, motion_type, endoscope_depth_mm and the three
    /// tips. Only --rate, --timing and the tip loads may be given with it.
    #[arg(long, value_name = "FILE.toml")]
    pub procedure: Option<PathBuf>,
    /// Plan and check the procedure, print the verdict and a table per
    /// motion (duration, peak rates, smallest margins, warnings), write
    /// nothing; exit non-zero when it fails.
    #[arg(long, requires = "procedure", conflicts_with_all = ["output", "plot"])]
    pub check: bool,
}

impl SimulateArgs {
    /// What these arguments ask for, each flag given or not: the syntax
    /// translated, no rule applied ([`Input::resolve`] applies them).
    pub fn input(&self) -> Input {
        self.place.fill(Input {
            procedure: self.procedure.clone().map(ProcedureSource::File),
            psi_deg: self.psi,
            theta_deg: self.theta,
            absolute: self.absolute.then_some(true),
            omega_max_deg_s: self.omega_max,
            eps_max_deg_s2: self.eps_max,
            sync: self.sync.map(Into::into),
            timing: self.timing.map(|t| match t {
                TimingArg::Trapezoid => TimingKind::Trapezoid,
                TimingArg::Optimal => TimingKind::Optimal,
            }),
            rate_hz: self.rate,
            pose_mm_deg: None,
            tip_left_mm: None,
            tip_right_mm: None,
            robot: self.robot.source(),
            retarget: (!self.retarget.is_empty()).then(|| self.retarget.clone()),
            stop_at_s: self.stop_at,
            tip_load_left_n: self.tip_load_left,
            tip_load_right_n: self.tip_load_right,
            look_at: self.look_at,
            anatomy: self.anatomy.clone(),
        })
    }

    /// The scenario these arguments describe: [`Self::input`] resolved.
    pub fn scenario(&self) -> Result<Scenario> {
        resolve(self.input())
    }

    /// The output format for `path`: `--format` if given, else from the
    /// extension (`.csv`, `.mcap`, any case).
    pub fn format(&self, path: &Path) -> Result<Format> {
        match self.format {
            Some(f) => Ok(f.into()),
            None => Ok(Format::from_path(path)?),
        }
    }
}

/// Arguments of `parasils ik`.
#[derive(Debug, Args)]
pub struct IkArgs {
    /// The pose and the tips.
    #[command(flatten)]
    pub place: PlaceArgs,
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `parasils fk`.
#[derive(Debug, Args)]
pub struct FkArgs {
    /// Module 1's actuators Q1,...,Q6, mm.
    #[arg(long, value_name = "Q1,Q2,Q3,Q4,Q5,Q6", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub q: [f64; 6],
    /// Starting guess X,Y,Z,PSI,THETA,PHI (mm, deg); it picks the assembly
    /// mode. Default: the paper's P0.
    #[arg(long, value_name = "X,Y,Z,PSI,THETA,PHI", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub guess: Option<[f64; 6]>,
    /// Left module joints QS1,QS2,QS3 (deg, deg, mm): print its tip.
    #[arg(long, value_name = "QS1,QS2,QS3", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub qs_left: Option<[f64; 3]>,
    /// Right module joints QS1,QS2,QS3 (deg, deg, mm): print its tip.
    #[arg(long, value_name = "QS1,QS2,QS3", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub qs_right: Option<[f64; 3]>,
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `input` resolved, its errors in the command line's words (flags, not
/// field names).
pub(crate) fn resolve(input: Input) -> Result<Scenario> {
    input.resolve().map_err(|e| match e {
        InputError::WithProcedure(field) => anyhow!(
            "{} cannot be given with --procedure: a procedure has its own start, robot and motions",
            field.flag()
        ),
        InputError::OptimalOnline(field) => anyhow!(
            "{} cannot be given with --timing optimal: it plans one motion from rest to rest, while commands are taken online",
            field.flag()
        ),
        InputError::Conflict { field, with, why } => {
            anyhow!("{} cannot be given with {}: {why}", field.flag(), with.flag())
        }
        e => e.into(),
    })
}

/// Parses `N` comma-separated finite floats.
pub fn parse_floats<const N: usize>(s: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!(
            "expected {N} comma-separated numbers, got {}",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (o, p) in out.iter_mut().zip(&parts) {
        *o = p
            .parse::<f64>()
            .map_err(|e| format!("`{p}` is not a number: {e}"))?;
        if !o.is_finite() {
            return Err(format!("`{p}` is not a finite number"));
        }
    }
    Ok(out)
}

/// Parses `--look-at`: `tips`, `left`, `right` or `X,Y,Z` (mm).
pub fn parse_look_at(s: &str) -> Result<LookAt, String> {
    parasils_sim::input::look_at_named(s)
        .map_err(|_| format!("expected tips, left, right or a point X,Y,Z in mm, got {s:?}"))
}

/// Parses one finite float.
pub fn parse_finite(s: &str) -> Result<f64, String> {
    let [v] = parse_floats::<1>(s)?;
    Ok(v)
}

/// Parses `T:PSI,THETA` (s; deg, deg), three finite floats.
pub fn parse_retarget(s: &str) -> Result<Retarget, String> {
    let Some((t, angles)) = s.split_once(':') else {
        return Err(
            "expected T:PSI,THETA (time in s, then the angles in deg), e.g. 1.2:5,10".into(),
        );
    };
    let t_s = parse_finite(t)?;
    let [psi_deg, theta_deg] = parse_floats::<2>(angles)?;
    Ok(Retarget {
        t_s,
        psi_deg,
        theta_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_paper_s_scenario() {
        let cli = Cli::try_parse_from(["parasils", "simulate"]).expect("parses");
        let Command::Simulate(args) = cli.command else {
            panic!("simulate expected");
        };
        assert_eq!(args.scenario().expect("paper"), Scenario::paper());
    }

    #[test]
    fn floats_are_counted_and_finite() {
        assert_eq!(parse_floats::<3>("1, -2.5,3e2"), Ok([1.0, -2.5, 300.0]));
        assert!(parse_floats::<3>("1,2").is_err());
        assert!(parse_floats::<2>("1,nan").is_err());
        assert!(parse_floats::<1>("x").is_err());
    }

    #[test]
    fn retargets_and_stops_parse_into_the_scenario() {
        let cli = Cli::try_parse_from([
            "parasils",
            "simulate",
            "--retarget",
            "1.2:5,-10",
            "--retarget",
            "2: -1 , 2.5",
            "--stop-at",
            "3",
        ])
        .expect("parses");
        let Command::Simulate(args) = cli.command else {
            panic!("simulate expected");
        };
        let s = args.scenario().expect("scenario");
        let online = s.online().expect("an online run");
        assert_eq!(
            online.retargets,
            [
                Retarget {
                    t_s: 1.2,
                    psi_deg: 5.0,
                    theta_deg: -10.0
                },
                Retarget {
                    t_s: 2.0,
                    psi_deg: -1.0,
                    theta_deg: 2.5
                }
            ]
        );
        assert_eq!(online.stop_at_s, Some(3.0));
        for bad in [
            "1.2",
            "1.2:5",
            "1.2:5,6,7",
            "x:5,6",
            "1:nan,2",
            "inf:1,2",
            "",
        ] {
            assert!(parse_retarget(bad).is_err(), "{bad}");
        }
        assert!(parse_finite("nan").is_err());
        assert_eq!(parse_finite("-1"), Ok(-1.0));
    }
}

/// Arguments of `parasils reach`.
#[derive(Debug, Args)]
pub struct ReachArgs {
    /// The range of dpsi, the increment of psi from the start pose, deg.
    #[arg(long, value_name = "MIN,MAX", default_value = "-45,45", value_parser = parse_floats::<2>, allow_hyphen_values = true)]
    pub psi_range: [f64; 2],
    /// The range of dtheta, the increment of theta from the start pose, deg.
    #[arg(long, value_name = "MIN,MAX", default_value = "-45,45", value_parser = parse_floats::<2>, allow_hyphen_values = true)]
    pub theta_range: [f64; 2],
    /// The grid step, deg: the cells are at whole multiples of it.
    #[arg(long, value_name = "DEG", default_value_t = 0.5)]
    pub step: f64,
    /// Skip the straight-line check (the `line` column is left empty). The
    /// check covers every segment from the start at points a quarter of a
    /// step apart (most cleared by a neighbour's margin): about a third of
    /// the default map's time.
    #[arg(long)]
    pub no_line: bool,
    /// Threads to use (0: every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// The start pose and the tips.
    #[command(flatten)]
    pub place: PlaceArgs,
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Forbidden regions: an anatomy file (spheres, boxes, capsules, STL or
    /// OBJ meshes in the fixed frame, mm). A cell where the in-body part of
    /// a shaft or of the endoscope comes closer to a region than the
    /// clearance stop threshold (0.5 mm by default) is infeasible, its
    /// limiting constraint no_go.<region name>.
    #[arg(long, value_name = "FILE.toml")]
    pub anatomy: Option<PathBuf>,
    /// The stiffness map: the force each tip exerts on the tissue, N,
    /// fixed frame (e.g. 0,0,-10). Each feasible cell then gets how far
    /// each tip gives way pressing with it, the other unloaded, with the
    /// robot file's actuator stiffnesses ([stiffness], assumed by
    /// default): CSV columns left_tip_deflection_mm and
    /// right_tip_deflection_mm, their range in the summary.
    #[arg(long, value_name = "FX,FY,FZ", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub deflection_load: Option<[f64; 3]>,
    /// Write the map to FILE: .csv (one row per cell; `-` for standard
    /// output), .png or .svg (a picture). Without it, print a summary.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
}

impl ReachArgs {
    /// The scenario: the paper's, with the pose, tips, robot and anatomy
    /// given.
    pub fn scenario(&self) -> Result<Scenario> {
        resolve(self.place.fill(Input {
            robot: self.robot.source(),
            anatomy: self.anatomy.clone(),
            ..Input::default()
        }))
    }

    /// The map's options.
    pub fn options(&self) -> ReachOptions {
        ReachOptions {
            psi_range_deg: self.psi_range,
            theta_range_deg: self.theta_range,
            step_deg: self.step,
            line: !self.no_line,
            threads: self.threads,
            deflection_load_n: self.deflection_load,
        }
    }
}

/// Arguments of `parasils calibrate`.
#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// The nominal robot: the start of the fit, and the values of the
    /// parameters the measurements cannot see.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Measurements as CSV, one row per pose, with the columns of
    /// `simulate`'s CSV: q1_mm..q6_mm (the readings), x_mm, y_mm, z_mm,
    /// psi_deg, theta_deg, phi_deg (the measured pose); optional per-row
    /// standard deviations sigma_q_mm, sigma_position_mm, sigma_angle_deg.
    #[arg(
        long,
        value_name = "FILE.csv",
        required_unless_present = "plan",
        conflicts_with = "plan"
    )]
    pub measurements: Option<PathBuf>,
    /// Instead of fitting, choose N poses to measure (written to -o as CSV
    /// with the nominal readings), compared with N random poses.
    #[arg(long, value_name = "N")]
    pub plan: Option<usize>,
    /// The fitted robot file (TOML), or with --plan the poses (CSV).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Also write the report as JSON to FILE.
    #[arg(long, value_name = "FILE.json")]
    pub report: Option<PathBuf>,
    /// Standard deviation of the readings for rows without sigma_q_mm, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0)]
    pub sigma_q_mm: f64,
    /// Standard deviation of each measured coordinate for rows without
    /// sigma_position_mm, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0)]
    pub sigma_position_mm: f64,
    /// Standard deviation of each measured Euler angle for rows without
    /// sigma_angle_deg, deg.
    #[arg(long, value_name = "DEG", default_value_t = 0.0)]
    pub sigma_angle_deg: f64,
    /// Levenberg-Marquardt iterations at most.
    #[arg(long, value_name = "N", default_value_t = FitOptions::default().max_iterations)]
    pub max_iterations: u32,
    /// --plan: the random candidates to choose from.
    #[arg(long, value_name = "N", default_value_t = PlanOptions::default().candidates, requires = "plan")]
    pub candidates: usize,
    /// --plan: the random generator's seed.
    #[arg(long, default_value_t = PlanOptions::default().seed, requires = "plan")]
    pub seed: u64,
}

/// Arguments of `parasils tolerance`.
#[derive(Debug, Args)]
pub struct ToleranceArgs {
    /// The tolerance specification (TOML; see --print-spec). Default: the
    /// default tolerances that --print-spec prints.
    #[arg(long, value_name = "FILE.toml")]
    pub spec: Option<PathBuf>,
    /// Print the specification (the default one, or --spec's) as TOML and
    /// exit.
    #[arg(long)]
    pub print_spec: bool,
    /// The number of perturbed robots.
    #[arg(
        short = 'n',
        long = "samples",
        value_name = "N",
        default_value_t = 1000
    )]
    pub samples: u64,
    /// The seed: robot i depends only on it and on i.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// The motion: a procedure file (its robot and start come from the
    /// file). Default: the paper's reorientation.
    #[arg(long, value_name = "FILE.toml")]
    pub procedure: Option<PathBuf>,
    /// The rate the motion is sampled at, Hz.
    #[arg(long, value_name = "HZ", default_value_t = 100.0)]
    pub rate: f64,
    /// The nominal robot.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Threads to use (0: every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Write one row per robot to FILE: .csv or .parquet (columns sample,
    /// left_tip_dev_mm, right_tip_dev_mm, pose_position_err_mm,
    /// pose_rotation_err_deg, failed).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Draw the histogram of the tip deviations and the sensitivity ranking
    /// to FILE.png or FILE.svg.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
    /// Write the output file even when its estimated size is above the
    /// 10 GB cap (it must still fit in the free space).
    #[arg(long)]
    pub force: bool,
}

impl ToleranceArgs {
    /// The motion's scenario: the paper's reorientation, or the procedure.
    pub fn scenario(&self) -> Result<Scenario> {
        resolve(Input {
            procedure: self.procedure.clone().map(ProcedureSource::File),
            rate_hz: Some(self.rate),
            robot: self.robot.source(),
            ..Input::default()
        })
    }
}

/// Where the live inputs come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DeviceArg {
    /// The SpaceMouse devices attached: two for the hands, a third (if any) for the camera.
    Auto,
}

/// Arguments of `parasils teleop`.
#[derive(Debug, Args)]
pub struct TeleopArgs {
    /// A recorded session to replay: CSV with the columns t_s, device, tx,
    /// ty, tz, rx, ry, rz, buttons, command (one row per input event; an
    /// input holds until the device's next row).
    #[arg(
        long,
        value_name = "FILE.csv",
        conflicts_with = "device",
        required_unless_present = "device"
    )]
    pub input: Option<PathBuf>,
    /// Read live devices instead, at the control rate, until Ctrl-C.
    #[arg(long, value_enum)]
    pub device: Option<DeviceArg>,
    /// Cycles per second, Hz [default: 1000].
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// How long the replay runs on after the recording's last row, s [default: 1].
    #[arg(long, value_name = "S")]
    pub settle: Option<f64>,
    /// The start pose and the tips.
    #[command(flatten)]
    pub place: PlaceArgs,
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArg,
    /// Write the cycles to FILE: .csv or .mcap. Without it, print the summary.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// The output's format, when the extension does not say it.
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
}

impl TeleopArgs {
    /// The scenario: the paper's start, tips and robot unless given, at the rate given.
    pub fn scenario(&self) -> Result<Scenario> {
        resolve(self.place.fill(Input {
            robot: self.robot.source(),
            rate_hz: self.rate,
            ..Input::default()
        }))
    }
}

/// `parasils serve`'s flags; the command is `serve.rs`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// The address to serve on: loopback unless told otherwise.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: String,
    /// The port; 0 picks a free one (the address is printed).
    #[arg(long, default_value_t = 8765)]
    pub port: u16,
    /// Control cycles per second, Hz [default: 1000].
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// The data channels' publishing rate, Hz (at most the control rate).
    #[arg(long, value_name = "HZ", default_value_t = 100.0)]
    pub publish_hz: f64,
    /// End the session after S seconds [default: at Ctrl-C].
    #[arg(long, value_name = "S")]
    pub duration_s: Option<f64>,
    /// Record the session's messages to FILE.mcap.
    #[arg(short = 'o', long = "output", value_name = "FILE.mcap")]
    pub output: Option<PathBuf>,
    /// A token clients must publish on /auth before they drive.
    #[arg(long, env = "PARASILS_TOKEN", hide_env_values = true)]
    pub token: Option<String>,
    /// The start pose and the tips.
    #[command(flatten)]
    pub place: PlaceArgs,
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArg,
}
