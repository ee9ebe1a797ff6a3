//! `parasils simulate`: the scenario from the arguments, the library's run
//! loop into the sinks asked for (summary, CSV to standard output, an output
//! file, a plot, a progress bar), then the files renamed into place.
//!
//! An output file's estimated size is checked before the run (the free
//! space, and the cap that `--force` lifts); SIGINT and SIGTERM stop the run
//! between two records and remove the unfinished files (see `interrupt`).

use core::convert::Infallible;
use std::io::{BufWriter, IsTerminal, Write};

use anyhow::{Context, Result, bail};
use parasils_io::Fixed;
use parasils_sim::csv::CsvSink;
use parasils_sim::output::{self, OutputFile};
use parasils_sim::plot::PlotSink;
use parasils_sim::summary::{CheckReport, Summary};
use parasils_sim::{Record, Simulation, Sink, Tee};

use crate::args::{FormatArg, SimulateArgs};
use crate::interrupt::{self, Interrupted};
use crate::stdout::{self, Stdout};

/// CSV rows to standard output (`-o -`).
struct StdoutCsv(CsvSink<BufWriter<Stdout>>);

/// An error writing to standard output.
#[derive(Debug)]
struct StdoutError(String);

impl core::fmt::Display for StdoutError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "writing to standard output: {}", self.0)
    }
}

impl core::error::Error for StdoutError {}

impl Sink for StdoutCsv {
    type Error = StdoutError;

    fn push(&mut self, record: &Record) -> Result<(), StdoutError> {
        self.0.push(record).map_err(|e| StdoutError(e.to_string()))
    }
}

/// A progress bar on the terminal, for long runs only.
struct Progress(indicatif::ProgressBar);

impl Progress {
    fn new(len: usize) -> Option<Self> {
        // Only worth it on a terminal and for long runs.
        if !std::io::stderr().is_terminal() || len < 200_000 {
            return None;
        }
        let bar = indicatif::ProgressBar::new(len as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} simulating {bar:40} {percent:>3}% {pos}/{len} samples, eta {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(Self(bar))
    }
}

impl Sink for Progress {
    type Error = Infallible;

    fn push(&mut self, record: &Record) -> Result<(), Infallible> {
        if record.index.is_multiple_of(4096) {
            self.0.set_position(record.index as u64);
        }
        Ok(())
    }
}

/// A size check's error; over the cap, it says how to write anyway.
pub(crate) fn force_hint(e: output::OutputError) -> anyhow::Error {
    match e {
        e @ output::OutputError::File(parasils_io::WriteError::OverCap { .. }) => {
            anyhow::anyhow!("{e}: give --force to write it anyway")
        }
        e => e.into(),
    }
}

/// `parasils simulate`.
pub fn simulate(args: &SimulateArgs) -> Result<()> {
    interrupt::install().context("cannot handle signals")?;
    let sim = Simulation::new(args.scenario()?)?;
    if args.check {
        let mut out = stdout::stdout();
        if let Some(check) = sim.procedure_check() {
            writeln!(out, "{}", CheckReport::new(&sim, check))
                .and_then(|()| out.flush())
                .context("writing to standard output")?;
        }
        return Ok(());
    }
    let assumed = sim.module1_assumed();
    let mut summary = Summary::for_simulation(&sim);
    // Files are written to a temporary file beside the target and renamed
    // on success: a failed run leaves nothing behind.
    let mut to_stdout = None;
    let mut file = None;
    match &args.output {
        None => {}
        Some(p) if p.as_os_str() == "-" => {
            if args.format == Some(FormatArg::Mcap) {
                bail!("MCAP cannot go to standard output: give a file name");
            }
            let sink = CsvSink::for_scenario(BufWriter::new(stdout::stdout()), sim.scenario())
                .map_err(|e| StdoutError(e.to_string()))?;
            to_stdout = Some(StdoutCsv(sink));
        }
        Some(p) => {
            if p.is_dir() {
                bail!("{} is a folder: give a file name", p.display());
            }
            let format = args.format(p)?;
            output::check_size(p, format, sim.sample_count(), args.force).map_err(force_hint)?;
            file = Some(OutputFile::create(p, format, sim.scenario())?);
        }
    }
    if let Some(path) = &args.plot
        && path.is_dir()
    {
        bail!("{} is a folder: give a file name", path.display());
    }
    // The files whose temporary files a signal would remove.
    let partial = |file: &Option<OutputFile>| -> Vec<std::path::PathBuf> {
        file.iter()
            .filter(|f| f.is_replaced())
            .map(|f| f.path().to_owned())
            .collect()
    };
    let mut plot = args.plot.as_ref().map(|_| {
        let mut plot = PlotSink::new(sim.sample_count(), assumed);
        if let p @ parasils::kin::Provenance::Calibrated(_) =
            sim.scenario().robot.module1.provenance()
        {
            plot = plot.calibrated(p.to_string());
        }
        if let Some(optimal) = sim.optimal() {
            plot = plot.with_phase_plane(optimal.phase_plane());
        }
        if sim.procedure().is_some() {
            plot.marking_motions()
        } else {
            plot
        }
    });
    let mut progress = Progress::new(sim.sample_count());

    let run = sim.run(
        &mut Tee::new()
            .with(&mut interrupt::Watch)
            .with(&mut summary)
            .with_some(to_stdout.as_mut())
            .with_some(file.as_mut())
            .with_some(plot.as_mut())
            .with_some(progress.as_mut()),
    );
    if let Some(p) = progress {
        p.0.finish_and_clear();
    }
    if let Some(signal) = interrupt::received() {
        let removed = partial(&file);
        drop(file);
        return Err(Interrupted { signal, removed }.into());
    }
    run?;

    if let Some(StdoutCsv(sink)) = to_stdout {
        sink.finish()
            .and_then(|mut w| w.flush())
            .map_err(|e| StdoutError(e.to_string()))?;
    }
    let removed = partial(&file);
    let file = file.map(OutputFile::flush).transpose()?;
    let mut plot_tmp = None;
    if let (Some(p), Some(path)) = (plot, &args.plot) {
        let tmp = parasils_io::file::temp_beside(path)?;
        p.finish(tmp.path(), path)?;
        plot_tmp = Some((tmp, path));
    }
    // The last moment to stop: past it, the files are renamed into place.
    if let Some(signal) = interrupt::received() {
        let mut removed = removed;
        removed.extend(plot_tmp.as_ref().map(|(_, path)| path.to_path_buf()));
        drop((file, plot_tmp));
        return Err(Interrupted { signal, removed }.into());
    }
    if let Some((tmp, path)) = plot_tmp {
        parasils_io::file::persist(tmp, path)?;
    }
    if let Some(f) = file {
        let path = f.persist()?;
        // The motion's duration; with commands, the time of the last record
        // (a stop the supervisor demanded may end the run before the plan).
        let seconds = match summary.range(&parasils_sim::columns::T_S) {
            Some((_, last)) if sim.scenario().has_commands() => last,
            _ => sim.duration(),
        };
        eprintln!(
            "parasils: wrote {} samples ({} s) to {}",
            summary.count(),
            Fixed(seconds, 3),
            path.display()
        );
    }
    if args.output.is_none() {
        let mut out = stdout::stdout();
        writeln!(out, "{summary}")
            .and_then(|()| out.flush())
            .context("writing to standard output")?;
    }
    Ok(())
}
