//! `parasils reach`: the map of the orientations reachable from the start
//! pose with both tips held, as CSV, a picture, or a summary.

use std::io::{BufWriter, Write};
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use parasils_sim::Scenario;
use parasils_sim::output;
use parasils_sim::plot::ImageFormat;
use parasils_sim::reach::summary::ReachSummary;
use parasils_sim::reach::{self, ReachMap, ReachOptions};

use crate::args::{PlaceArgs, RobotArg, parse_floats};
use crate::stdout;

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
    /// check evaluates every segment from the start at points a quarter of a
    /// step apart, so its cost grows with the cube of the grid's side: most
    /// of the default map's time, and minutes on a 0.1 deg grid.
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
    /// Write the map to FILE: .csv (one row per cell; `-` for standard
    /// output), .png or .svg (a picture). Without it, print a summary.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
}

impl ReachArgs {
    /// The scenario: the paper's, with the pose, tips and robot given.
    pub fn scenario(&self) -> Result<Scenario> {
        let paper = Scenario::paper();
        Ok(Scenario {
            start_mm_deg: self.place.pose.unwrap_or(paper.start_mm_deg),
            tip_left_mm: self.place.tip_left.unwrap_or(paper.tip_left_mm),
            tip_right_mm: self.place.tip_right,
            robot: self.robot.geometry()?,
            ..paper
        })
    }

    /// The map's options.
    pub fn options(&self) -> ReachOptions {
        ReachOptions {
            psi_range_deg: self.psi_range,
            theta_range_deg: self.theta_range,
            step_deg: self.step,
            line: !self.no_line,
            threads: self.threads,
        }
    }
}

/// What `-o` asks for.
enum Target {
    Csv,
    Image(ImageFormat),
}

/// `parasils reach`.
pub fn reach(args: &ReachArgs) -> Result<()> {
    let target = match &args.output {
        None => None,
        Some(path) if path.as_os_str() == "-" => Some(Target::Csv),
        Some(path) => match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("csv") => Some(Target::Csv),
            _ => match ImageFormat::from_path(path) {
                Ok(f) => Some(Target::Image(f)),
                Err(_) => bail!(
                    "cannot tell the output format of {}: use a .csv, .png or .svg extension",
                    path.display()
                ),
            },
        },
    };
    let map = ReachMap::compute(&args.scenario()?, &args.options())?;
    let (Some(path), Some(target)) = (&args.output, target) else {
        let mut out = stdout::stdout();
        out.write_all(ReachSummary::of(&map).text(&map).as_bytes())?;
        out.flush()?;
        return Ok(());
    };
    if path.as_os_str() == "-" {
        let mut out = BufWriter::new(stdout::stdout());
        reach::csv::write(&map, &mut out)?;
        return Ok(());
    }
    // Written beside the target and renamed on success: a failure leaves
    // nothing behind.
    let tmp = output::temp_beside(path)?;
    match target {
        Target::Csv => {
            let mut out = BufWriter::new(tmp.as_file());
            reach::csv::write(&map, &mut out)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Target::Image(format) => reach::plot::render(&map, tmp.path(), format)?,
    }
    output::persist(tmp, path)?;
    Ok(())
}
