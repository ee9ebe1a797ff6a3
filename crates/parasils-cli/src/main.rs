//! The `parasils` command: simulations to CSV, MCAP, plots or a summary
//! (`simulate`), the kinematics at one pose (`ik`, `fk`), the robot file
//! (`robot`). The work is done by the simulation library, `parasils-sim`,
//! and the kinematics; this binary parses the arguments and prints.
//!
//! Modules: `args` (the arguments, the shared flags defined once),
//! `simulate`, `reach`, `pose`, `calibrate`, `tolerance`, `teleop` and `serve` (the commands), `stdout` (standard output that
//! notices a closed pipe), `interrupt` (SIGINT and SIGTERM end a run
//! through its error path).

mod args;
mod calibrate;
mod interrupt;
mod pose;
mod reach;
mod serve;
mod simulate;
mod stdout;
mod teleop;
mod tolerance;

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<interrupt::Interrupted>() => {
            eprintln!("parasils: {e}");
            let status = e
                .downcast_ref::<interrupt::Interrupted>()
                .map_or(1, interrupt::Interrupted::status);
            ExitCode::from(status)
        }
        // The reader of standard output went away (`| head`): its choice, so
        // stop quietly, with success, as if the output had been read.
        Err(_) if stdout::closed() => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("parasils: error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// Runs one parsed command.
fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Simulate(args) => simulate::simulate(&args),
        Command::Reach(args) => reach::reach(&args),
        Command::Ik(args) => pose::ik(&args),
        Command::Calibrate(args) => calibrate::calibrate_command(&args),
        Command::Fk(args) => pose::fk(&args),
        Command::Tolerance(args) => tolerance::tolerance(&args),
        Command::Teleop(args) => teleop::teleop(&args),
        Command::Serve(args) => serve::serve(&args),
        Command::Robot => {
            let text =
                parasils_sim::robot_file::to_toml_string(&parasils::kin::RobotGeometry::paper())?;
            let mut out = stdout::stdout();
            out.write_all(text.as_bytes())?;
            out.flush()?;
            Ok(())
        }
    }
}

/// The error and its causes on one line, outermost first, each subject
/// once: a cause whose text the message before it already holds is left
/// out, and a message that a cause repeats in full gives way to it.
fn one_line(e: &anyhow::Error) -> String {
    let mut parts: Vec<String> = Vec::new();
    for cause in e.chain() {
        let text = cause.to_string();
        match parts.last_mut() {
            Some(last) if last.contains(&text) => {}
            Some(last) if text.starts_with(last.as_str()) => *last = text,
            _ => parts.push(text),
        }
    }
    parts.join(": ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_names_each_subject_once() {
        let io = std::io::Error::other("disk full");
        let e = anyhow::Error::new(io).context("writing run.csv: disk full");
        assert_eq!(one_line(&e), "writing run.csv: disk full");
        let e = anyhow::anyhow!("module 1: actuator q1 = 400 mm").context("module 1");
        assert_eq!(one_line(&e), "module 1: actuator q1 = 400 mm");
        let e = anyhow::anyhow!("no such file").context("robot.toml");
        assert_eq!(one_line(&e), "robot.toml: no such file");
    }
}
