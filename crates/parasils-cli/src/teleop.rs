//! `parasils teleop`: the teleoperation core driven by a recorded session
//! (`--input FILE.csv`) or by live SpaceMouse devices (`--device auto`),
//! through the simulation library's teleoperation run, into the same
//! output file and summary as `simulate`, with the teleoperation columns
//! and a teleoperation block.
//!
//! Live devices are read once per cycle, at the control rate, until Ctrl-C
//! (SIGINT or SIGTERM); the core is enabled at the first cycle, and the
//! output written up to the last cycle run. Errors are one line and a
//! non-zero exit; a failed run leaves no file (it is written to a temporary
//! file renamed at the end).

use core::time::Duration;
use std::io::Write;
use std::time::Instant;

use anyhow::{Context, Result, bail};
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
        let mut devices = SpaceMouse::open_all(2)?;
        if let Ok(mut third) = SpaceMouse::open_all(3)
            && let Some(camera) = third.pop()
        {
            devices.push(camera);
        }
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
            let mut tee = Tee::new()
                .with(&mut s)
                .with(&mut teleop_summary)
                .with_some(out.as_mut());
            if tee.push(&record).is_err() {
                bail!("writing the output failed");
            }
            // Paced at the control rate against the wall clock.
            let due = Duration::from_secs_f64(run.next_time_s());
            if let Some(wait) = due.checked_sub(start.elapsed()) {
                std::thread::sleep(wait);
            }
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
