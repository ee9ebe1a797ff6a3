//! The command line: arguments (clap) and what each command does.

use std::fs::File;
use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};
use nalgebra::Vector3;
use parasils_kin::Pose;
use parasils_kin::controller::RobotGeometry;
use parasils_traj::Synchronization;

use crate::csv::CsvSink;
use crate::mcap::McapSink;
use crate::plot::PlotSink;
use crate::robot_file;
use crate::sample::{Sample, Sink};
use crate::scenario::Scenario;
use crate::simulate::Simulation;
use crate::summary::Summary;

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
pub enum Command {
    /// Simulate an endoscope reorientation (motion type 4): the platform turns
    /// about the endoscope's RCM and both instruments keep their tips still.
    /// Defaults reproduce the paper's section 4.
    Simulate(SimulateArgs),
    /// Inverse kinematics at one platform pose: module 1's actuators and both
    /// instrument modules' joints (both assembly modes).
    Ik(IkArgs),
    /// Forward kinematics: module 1's pose from its actuators, and the
    /// instrument tips from their joints at that pose.
    Fk(FkArgs),
    /// Print the default robot geometry as TOML, to copy and edit.
    Robot,
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

impl From<SyncArg> for Synchronization {
    fn from(s: SyncArg) -> Self {
        match s {
            SyncArg::Phase => Synchronization::Phase,
            SyncArg::Time => Synchronization::Time,
            SyncArg::None => Synchronization::None,
        }
    }
}

/// Output formats of `simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// One row per sample, every column named with its unit.
    Csv,
    /// MCAP for Foxglove: one channel per group, /tf and /scene.
    Mcap,
}

/// Arguments of `parasils simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// psi: increment from the start pose (final value with --absolute), deg.
    #[arg(long, default_value_t = 15.0, allow_hyphen_values = true)]
    pub psi: f64,
    /// theta: increment from the start pose (final value with --absolute), deg.
    #[arg(long, default_value_t = 25.0, allow_hyphen_values = true)]
    pub theta: f64,
    /// Take --psi and --theta as final angles instead of increments.
    #[arg(long)]
    pub absolute: bool,
    /// Velocity limit of each Euler angle, deg/s.
    #[arg(
        long,
        value_name = "DEG_PER_S",
        default_value_t = 10.0,
        allow_hyphen_values = true
    )]
    pub omega_max: f64,
    /// Acceleration limit of each Euler angle, deg/s^2.
    #[arg(
        long,
        value_name = "DEG_PER_S2",
        default_value_t = 5.0,
        allow_hyphen_values = true
    )]
    pub eps_max: f64,
    /// Synchronisation of psi and theta.
    #[arg(long, value_enum, default_value_t = SyncArg::Phase)]
    pub sync: SyncArg,
    /// Samples per second, Hz.
    #[arg(
        long,
        value_name = "HZ",
        default_value_t = 1000.0,
        allow_hyphen_values = true
    )]
    pub rate: f64,
    /// Start pose X,Y,Z,PSI,THETA,PHI (mm, deg). Default: the paper's P0.
    #[arg(long, value_name = "X,Y,Z,PSI,THETA,PHI", value_parser = parse_floats::<6>, allow_hyphen_values = true)]
    pub pose: Option<[f64; 6]>,
    /// Left tip X,Y,Z (mm, fixed frame), held still. Default: (50, -50, -620).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_left: Option<[f64; 3]>,
    /// Right tip X,Y,Z (mm, fixed frame), held still. Default: the mirror image
    /// of the left tip across the platform's Y'Z' plane at the start pose.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_floats::<3>, allow_hyphen_values = true)]
    pub tip_right: Option<[f64; 3]>,
    /// Robot geometry (module 1 and both instrument modules) as TOML; see `parasils robot`.
    #[arg(long, value_name = "FILE.toml")]
    pub robot: Option<PathBuf>,
    /// Write every sample to FILE (format from the extension: .csv, .mcap), or
    /// CSV to standard output with `-o -`. Without it, print a summary.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// The output format, overriding the extension.
    #[arg(long, value_enum)]
    pub format: Option<Format>,
    /// Plot the paper's three figures to FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
}

/// Parses `N` comma-separated floats.
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

impl SimulateArgs {
    /// The scenario these arguments describe (loading the robot file if any).
    pub fn scenario(&self) -> Result<(Scenario, bool)> {
        let mut s = Scenario::paper();
        if let Some(path) = &self.robot {
            s.robot = robot_file::load(path)?;
        }
        let assumed = s.robot.module1.assumed;
        if let Some(p) = self.pose {
            s.start = Pose::from_mm_deg(p[0], p[1], p[2], p[3], p[4], p[5]);
        }
        s.psi = self.psi.to_radians();
        s.theta = self.theta.to_radians();
        s.absolute = self.absolute;
        s.omega_max = self.omega_max.to_radians();
        s.eps_max = self.eps_max.to_radians();
        s.sync = self.sync.into();
        s.rate_hz = self.rate;
        if let Some(t) = self.tip_left {
            s.tip_left = Vector3::from(t);
        }
        s.tip_right = self.tip_right.map(Vector3::from);
        Ok((s, assumed))
    }

    /// The output format for `path`: `--format` if given, else from the
    /// extension (`.csv`, `.mcap`, any case); an error otherwise.
    pub fn format(&self, path: &Path) -> Result<Format> {
        if let Some(f) = self.format {
            return Ok(f);
        }
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("csv") => Ok(Format::Csv),
            Some(e) if e.eq_ignore_ascii_case("mcap") => Ok(Format::Mcap),
            _ => bail!(
                "cannot tell the output format of {}: use a .csv or .mcap extension, or --format",
                path.display()
            ),
        }
    }
}

/// Runs the command line; returns the process's exit code.
pub fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // One line: the chain of causes, outermost first.
            let msg: Vec<String> = e.chain().map(ToString::to_string).collect();
            eprintln!("parasils: error: {}", msg.join(": "));
            std::process::ExitCode::FAILURE
        }
    }
}

/// Runs one parsed command.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Simulate(args) => simulate(&args),
        Command::Ik(args) => crate::pose_cmd::ik(&args),
        Command::Fk(args) => crate::pose_cmd::fk(&args),
        Command::Robot => {
            print!("{}", robot_file::to_toml_string(&RobotGeometry::paper())?);
            Ok(())
        }
    }
}

pub use crate::pose_cmd::{FkArgs, IkArgs};

enum Writer {
    Csv(Box<CsvSink<BufWriter<Box<dyn Write>>>>),
    Mcap(Box<McapSink<BufWriter<File>>>),
}

impl Writer {
    fn push(&mut self, s: &Sample) -> Result<()> {
        match self {
            Writer::Csv(w) => w.push(s)?,
            Writer::Mcap(w) => w.push(s)?,
        }
        Ok(())
    }

    /// Flushes everything written.
    fn finish(self) -> Result<()> {
        match self {
            Writer::Csv(w) => {
                w.finish()?.flush()?;
            }
            Writer::Mcap(w) => {
                w.finish()?.flush()?;
            }
        }
        Ok(())
    }
}

/// A CSV or MCAP file that a simulation's samples stream into, as
/// `parasils simulate -o FILE` writes it (the Python bindings'
/// `simulate(out=...)` too).
///
/// The samples go to a temporary file beside the target, which
/// [`OutputFile::finish`] renames to it: a failed run (the file dropped
/// unfinished) leaves nothing behind, not even a truncated file.
pub struct OutputFile {
    writer: Writer,
    tmp: tempfile::NamedTempFile,
    path: PathBuf,
}

impl core::fmt::Debug for OutputFile {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("OutputFile")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

/// An [`OutputFile`] flushed, still under its temporary name.
struct Flushed {
    tmp: tempfile::NamedTempFile,
    path: PathBuf,
}

impl Flushed {
    fn persist(self) -> Result<PathBuf> {
        let Flushed { tmp, path } = self;
        tmp.persist(&path)
            .with_context(|| format!("writing {}", path.display()))?;
        Ok(path)
    }
}

impl OutputFile {
    /// Starts writing `sim`'s samples to `path` in `format` (see
    /// [`SimulateArgs::format`]): the CSV header, or the MCAP file's header,
    /// channels and scenario.
    pub fn create(path: &Path, format: Format, sim: &Simulation) -> Result<Self> {
        let tmp = temp_beside(path)?;
        let file = tmp.reopen()?;
        let writer = match format {
            Format::Csv => {
                let f: Box<dyn Write> = Box::new(file);
                Writer::Csv(Box::new(CsvSink::new(BufWriter::new(f))?))
            }
            Format::Mcap => Writer::Mcap(Box::new(McapSink::new(
                BufWriter::new(file),
                sim.scenario(),
            )?)),
        };
        Ok(Self {
            writer,
            tmp,
            path: path.to_owned(),
        })
    }

    /// The file's final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn flush(self) -> Result<Flushed> {
        self.writer.finish()?;
        Ok(Flushed {
            tmp: self.tmp,
            path: self.path,
        })
    }

    /// Flushes the file and renames it to its path; returns the path.
    pub fn finish(self) -> Result<PathBuf> {
        self.flush()?.persist()
    }
}

impl Sink for OutputFile {
    type Error = anyhow::Error;

    fn push(&mut self, sample: &Sample) -> Result<()> {
        self.writer.push(sample)
    }
}

fn simulate(args: &SimulateArgs) -> Result<()> {
    let (scenario, assumed) = args.scenario()?;
    let sim = Simulation::new(scenario)?;
    let mut summary = Summary::default();
    summary.module1_assumed = assumed;
    // Output files are written to a temporary file beside the target and
    // renamed on success: a failed run leaves nothing behind.
    let mut out_file = None;
    let mut writer = match &args.output {
        None => None,
        Some(p) if p.as_os_str() == "-" => {
            if args.format == Some(Format::Mcap) {
                bail!("MCAP cannot go to standard output: give a file name");
            }
            let stdout: Box<dyn Write> = Box::new(io::stdout().lock());
            Some(Writer::Csv(Box::new(CsvSink::new(BufWriter::new(stdout))?)))
        }
        Some(p) => {
            let format = args.format(p)?;
            out_file = Some(OutputFile::create(p, format, &sim)?);
            None
        }
    };
    let mut plot = args
        .plot
        .as_ref()
        .map(|_| PlotSink::new(sim.sample_count(), assumed));

    let progress = progress_bar(sim.sample_count() as u64);
    for (k, sample) in sim.samples().enumerate() {
        let s: Sample = sample?;
        let _ = summary.push(&s);
        if let Some(w) = &mut writer {
            w.push(&s)?;
        }
        if let Some(f) = &mut out_file {
            f.push(&s)?;
        }
        if let Some(p) = &mut plot {
            p.push(&s)?;
        }
        if let Some(pb) = &progress
            && k % 4096 == 0
        {
            pb.set_position(k as u64);
        }
    }
    if let Some(pb) = progress {
        pb.finish_and_clear();
    }

    if let Some(w) = writer {
        w.finish()?;
    }
    let out_file = out_file.map(OutputFile::flush).transpose()?;
    if let (Some(p), Some(path)) = (plot, &args.plot) {
        let tmp = temp_beside(path)?;
        p.finish(tmp.path(), path)?;
        tmp.persist(path)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if let Some(f) = out_file {
        let path = f.persist()?;
        eprintln!(
            "parasils: wrote {} samples ({:.3} s) to {}",
            summary.count(),
            sim.duration(),
            path.display()
        );
    }
    if args.output.is_none() {
        println!("{summary}");
    }
    Ok(())
}

/// A temporary file in the folder of `path`, so that the final rename stays
/// on one file system.
fn temp_beside(path: &Path) -> Result<tempfile::NamedTempFile> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".parasils-").suffix(".part");
    // The finished file gets the usual permissions, not a temporary file's 0600.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    builder
        .tempfile_in(dir)
        .with_context(|| format!("cannot write in {}", dir.display()))
}

fn progress_bar(len: u64) -> Option<indicatif::ProgressBar> {
    // Only worth it on a terminal and for long runs.
    if !io::stderr().is_terminal() || len < 200_000 {
        return None;
    }
    let pb = indicatif::ProgressBar::new(len);
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} simulating {bar:40} {percent:>3}% {pos}/{len} samples, eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(pb)
}
