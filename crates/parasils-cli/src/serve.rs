//! `parasils serve`: the robot live, through the live crate's [`Session`]:
//! the teleoperation core at the control rate, every channel served to
//! Foxglove over WebSocket and recorded to MCAP (`-o`), until
//! `--duration-s` has run or Ctrl-C (SIGINT or SIGTERM), which ends the
//! session cleanly: the last cycle published, the recording finished.
//!
//! The bound address is printed on standard output, on one line
//! (`parasils: serving on ws://127.0.0.1:8765`), then flushed: `--port 0`
//! lets the system pick a free port, and a test or a script reads it there.
//! The protocol spoken (and the one refused) is on standard error.

use core::time::Duration;
use std::io::Write;

use anyhow::{Context, Result};
use parasils::teleop::TeleopParams;
use parasils_live::{LEGACY_SUBPROTOCOL, LiveOptions, SUBPROTOCOL, Session};
use parasils_sim::{Input, TeleopRun};

use crate::args::{ServeArgs, resolve};
use crate::interrupt;
use crate::stdout;

/// `parasils serve`.
pub fn serve(args: &ServeArgs) -> Result<()> {
    interrupt::install().context("cannot handle signals")?;
    let scenario = resolve(args.place.fill(Input {
        robot: args.robot.source(),
        rate_hz: args.rate,
        ..Input::default()
    }))?;
    let run = TeleopRun::new(scenario, TeleopParams::assumed())?;
    let rate_hz = run.rate_hz();
    let options = LiveOptions {
        bind: args.bind.clone(),
        port: args.port,
        publish_hz: args.publish_hz,
        duration_s: args.duration_s,
        record: args.output.clone(),
        token: args.token.clone(),
        // The default spin margin (100 us), within half the period at
        // rates past 5 kHz (the most a session takes).
        spin_margin_s: LiveOptions::default().spin_margin_s.min(0.5 / rate_hz),
        ..LiveOptions::default()
    };
    if !options.is_loopback() {
        let who = if options.token.is_some() {
            "anyone who can reach this port can watch the robot, and anyone who also has the token can drive it"
        } else {
            "anyone who can reach this port can drive the robot (give --token to require one)"
        };
        eprintln!(
            "parasils: warning: serving on {}, not loopback: {who}",
            options.bind
        );
    }
    let session = Session::start(run, &options)?;
    let mut out = stdout::stdout();
    writeln!(out, "parasils: serving on ws://{}", session.address())
        .and_then(|()| out.flush())
        .context("writing to standard output")?;
    eprintln!(
        "parasils: protocol {SUBPROTOCOL} (the legacy {LEGACY_SUBPROTOCOL} is refused); control {rate_hz} Hz, publishing {} Hz; {} topics; inputs on /left/servo_input, /right/servo_input, /camera/servo_input, commands on /command",
        options.publish_hz,
        session.topics().len()
    );
    let scheduling = session.scheduling();
    if scheduling.is_realtime() {
        eprintln!("parasils: control thread at {scheduling}");
    } else {
        eprintln!(
            "parasils: control thread at {scheduling}: deadlines may be missed when the machine is loaded"
        );
    }
    while !session.is_finished() {
        if let Some(signal) = interrupt::received() {
            eprintln!("parasils: signal {signal}: ending the session");
            session.stop();
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let report = session.wait()?;
    let s = &report.stats;
    eprintln!(
        "parasils: {} cycles, {} deadline misses ({} late starts, {} overruns), worst cycle {:.1} us, mean {:.1} us, worst start {:.1} us late, {} frames dropped; {} messages published",
        s.cycles,
        s.deadline_misses,
        s.late_starts,
        s.overruns,
        s.worst_cycle_s * 1e6,
        s.mean_cycle_s() * 1e6,
        s.worst_late_s * 1e6,
        s.dropped_frames,
        report.published.messages
    );
    if let Some(path) = &report.record {
        eprintln!("parasils: recorded to {}", path.display());
    }
    Ok(())
}
