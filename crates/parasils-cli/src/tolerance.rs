//! `parasils tolerance`: a Monte Carlo over robots built within tolerances,
//! each driven by the nominal model's commands; the percentiles, the
//! failures and the sensitivity ranking on standard output, the rows as CSV
//! or Parquet, the histogram as a picture.

use std::io::{IsTerminal, Write};
use std::path::Path;

use anyhow::{Context, Result, bail};
use parasils_io::ImageFormat;
use parasils_io::file::{persist, temp_beside};
use parasils_tolerance::output::TableFormat;
use parasils_tolerance::{Report, Spec, Study, Trace};

use crate::args::ToleranceArgs;
use crate::simulate::force_hint;
use crate::{interrupt, stdout};

/// The most robots one run holds: 4 GB of rows in memory.
const MAX_SAMPLES: u64 = 100_000_000;

/// `parasils tolerance`.
pub fn tolerance(args: &ToleranceArgs) -> Result<()> {
    let spec = match &args.spec {
        Some(path) => Spec::load(path)?,
        None => Spec::default(),
    };
    if args.print_spec {
        let mut out = stdout::stdout();
        out.write_all(spec.to_toml().as_bytes())?;
        out.flush()?;
        return Ok(());
    }
    // Every argument is checked before the first robot runs.
    let format = match &args.output {
        Some(path) => Some(TableFormat::from_path(path).with_context(|| {
            format!(
                "cannot tell the output format of {}: use a .csv or .parquet extension",
                path.display()
            )
        })?),
        None => None,
    };
    let image = args
        .plot
        .as_deref()
        .map(ImageFormat::from_path)
        .transpose()?;
    if args.samples == 0 {
        bail!("-n must be at least 1");
    }
    if args.samples > MAX_SAMPLES {
        bail!(
            "-n {} is more than the {MAX_SAMPLES} robots one process holds (about 41 bytes each \
             in memory): split the study over processes or machines with parasils.tolerance(..., \
             client=...), whose rows are the same",
            args.samples
        );
    }
    if let (Some(path), Some(format)) = (&args.output, format) {
        parasils_tolerance::output::check_size(path, format, args.samples, args.force)
            .map_err(|e| force_hint(e.into()))?;
    }
    if !(args.rate > 0.0 && args.rate.is_finite()) {
        bail!("--rate must be a positive number of Hz, got {}", args.rate);
    }
    interrupt::install().context("cannot handle signals")?;
    let scenario = args.scenario()?;
    let assumed = scenario.robot.module1.provenance().to_string();
    let trace = Trace::from_scenario(scenario).context("the nominal motion")?;
    let study = Study::new(spec, trace, args.seed)?;
    let threads = if args.threads > 0 {
        args.threads
    } else {
        std::thread::available_parallelism().map_or(1, usize::from)
    };
    let bar = progress_bar(args.samples);
    let tick = |n: u64| {
        if let Some(bar) = &bar {
            bar.inc(n);
        }
        interrupt::received().is_none()
    };
    let run = study.run(0..args.samples, threads, &tick);
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let Ok(results) = run else {
        return Err(interrupt::Interrupted {
            signal: interrupt::received().unwrap_or(2),
            removed: Vec::new(),
        }
        .into());
    };
    let linear = study.linearisation();
    let report = Report::new(&results, linear.as_ref().ok(), study.spec());
    if let (Some(path), Some(format)) = (&args.output, format) {
        parasils_tolerance::output::write(&results, path, format)?;
    }
    if let (Some(path), Some(format)) = (&args.plot, image) {
        let source = args.spec.as_deref().map_or_else(
            || "default tolerances".to_string(),
            |p| p.display().to_string(),
        );
        let motion = args.procedure.as_deref().map_or_else(
            || "the paper's reorientation".to_string(),
            |p| p.display().to_string(),
        );
        let note = format!(
            "{source}; {motion} at {} Hz; seed {}; module 1 {assumed}",
            args.rate, args.seed
        );
        render(&report, &note, path, format)?;
    }
    let mut out = stdout::stdout();
    writeln!(
        out,
        "tolerance study: {} at {} Hz ({} samples), module 1 {assumed}, seed {}",
        args.procedure.as_deref().map_or_else(
            || "the paper's reorientation".to_string(),
            |p| p.display().to_string()
        ),
        args.rate,
        study.trace().len(),
        args.seed
    )?;
    write!(out, "{report}")?;
    if let Err(e) = &linear {
        writeln!(out, "no sensitivity ranking: {e}")?;
    }
    out.flush()?;
    Ok(())
}

/// The picture, written beside its target and renamed on success.
fn render(report: &Report, note: &str, path: &Path, format: ImageFormat) -> Result<()> {
    let tmp = temp_beside(path)?;
    parasils_tolerance::plot::render(report, note, tmp.path(), format)?;
    persist(tmp, path)?;
    Ok(())
}

/// A progress bar on a terminal.
fn progress_bar(samples: u64) -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(samples);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} robots {bar:40} {percent:>3}% {pos}/{len}, {per_sec}, eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(bar)
}
