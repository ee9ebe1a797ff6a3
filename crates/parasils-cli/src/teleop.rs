//! `parasils teleop`: the teleoperation core driven by a recorded session
//! (`--input FILE.csv`) or by live SpaceMouse devices (`--device auto`),
//! through the simulation library's teleoperation run, into the same
//! output file and summary as `simulate`, with the teleoperation columns
//! and a teleoperation block.
//!
//! Live devices are read once per cycle, at the control rate, until Ctrl-C
//! (SIGINT or SIGTERM); the core is enabled at the first cycle. On Ctrl-C
//! it is disabled and run on until its controlled stop has ended, and the
//! output is written up to that last cycle. Errors are one line and a
//! non-zero exit; a failed run leaves no file (it is written to a temporary
//! file renamed at the end).

use core::time::Duration;
use std::io::Write;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use parasils::teleop::{Command, TeleopParams};
use parasils_device::{Held, Recording, SpaceMouse};
use parasils_io::Fixed;
use parasils_sim::output::{self, OutputFile};
use parasils_sim::summary::Summary;
use parasils_sim::teleop::CSV_WITH_TELEOP;
use parasils_sim::{Replay, SETTLE_S, Sink, Tee, TeleopRun, TeleopSummary};

use crate::args::TeleopArgs;
use crate::interrupt;
use crate::stdout;

/// The longest a live session runs on after Ctrl-C for its controlled
/// stop, s (a tip at its speed limit stops in 0.5 s).
const STOP_S: f64 = 5.0;

/// One cycle's record into the summaries and the output file.
fn push(
    record: &parasils_sim::Record,
    summary: &mut Summary,
    teleop: &mut TeleopSummary,
    out: Option<&mut OutputFile>,
) -> Result<()> {
    let mut tee = Tee::new().with(summary).with(teleop).with_some(out);
    tee.push(record)
        .map_err(|e| anyhow!("writing the output failed: {e}"))
}

/// `parasils teleop`.
pub fn teleop(args: &TeleopArgs) -> Result<()> {
    interrupt::install().context("cannot handle signals")?;
    let scenario = args.scenario()?;
    let params = TeleopParams::assumed();
    let mut file = match &args.output {
        None => None,
        Some(p) => {
            if p.is_dir() {
                bail!("{} is a folder: give a file name", p.display());
            }
            let format = match args.format {
                Some(f) => f.into(),
                None => output::Format::from_path(p)?,
            };
            Some((p.clone(), format))
        }
    };
    let summary;
    let mut teleop_summary = TeleopSummary::new();
    let mut out = None;
    if let Some(path) = &args.input {
        let recording = Recording::read(path)?;
        let replay = Replay::new(scenario, params, recording, args.settle.unwrap_or(SETTLE_S))?;
        if let Some((p, format)) = file.take() {
            out = Some(OutputFile::create_with(
                &p,
                format,
                replay.scenario(),
                &CSV_WITH_TELEOP,
            )?);
        }
        let mut s = Summary::for_simulation(replay.simulation());
        replay.run(
            &mut Tee::new()
                .with(&mut interrupt::Watch)
                .with(&mut s)
                .with(&mut teleop_summary)
                .with_some(out.as_mut()),
        )?;
        summary = Some(s);
    } else {
        // Fails here, as one line, when no device is attached.
        let mut devices = match SpaceMouse::open_all(3) {
            Ok(three) => three,
            Err(_) => SpaceMouse::open_all(2)?,
        };
        let mut run = TeleopRun::new(scenario, params)?;
        if let Some((p, format)) = file.take() {
            out = Some(OutputFile::create_with(
                &p,
                format,
                run.scenario(),
                &CSV_WITH_TELEOP,
            )?);
        }
        let mut s = Summary::for_simulation(run.simulation());
        let start = Instant::now();
        let pace = |run: &TeleopRun| {
            // Paced at the control rate against the wall clock.
            let due = Duration::from_secs_f64(run.next_time_s());
            if let Some(wait) = due.checked_sub(start.elapsed()) {
                std::thread::sleep(wait);
            }
        };
        let mut command = Some(Command::Enable);
        while interrupt::received().is_none() {
            let mut held = [Held::REST; 3];
            for (slot, device) in held.iter_mut().zip(devices.iter_mut()) {
                let state = device.poll()?;
                *slot = Held {
                    axes: state.axes,
                    buttons: u8::try_from(state.buttons & 0xff).unwrap_or(0),
                };
            }
            let record = run.step(held, command.take())?;
            push(&record, &mut s, &mut teleop_summary, out.as_mut())?;
            pace(&run);
        }
        // Interrupted: disable, and run on (the devices no longer read)
        // until the controlled stop has ended, at most `STOP_S`.
        let mut command = Some(Command::Disable);
        let until = run.next_time_s() + STOP_S;
        loop {
            let record = run.step([Held::REST; 3], command.take())?;
            push(&record, &mut s, &mut teleop_summary, out.as_mut())?;
            if run.teleop().is_at_rest() || run.next_time_s() > until {
                break;
            }
            pace(&run);
        }
        summary = Some(s);
    }
    if let Some(signal) = interrupt::received()
        && args.input.is_some()
    {
        let removed = out
            .iter()
            .filter(|f| f.is_replaced())
            .map(|f| f.path().to_owned())
            .collect();
        drop(out);
        return Err(interrupt::Interrupted { signal, removed }.into());
    }
    if let Some(f) = out {
        let path = f.finish()?;
        eprintln!(
            "parasils: wrote {} cycles ({} s) to {}",
            teleop_summary.cycles,
            Fixed(
                teleop_summary.cycles.saturating_sub(1) as f64 / args.rate.unwrap_or(1000.0),
                3
            ),
            path.display()
        );
    } else if let Some(s) = summary {
        let mut o = stdout::stdout();
        writeln!(o, "{s}\n{teleop_summary}")
            .and_then(|()| o.flush())
            .context("writing to standard output")?;
    }
    Ok(())
}
