//! The command line's arguments to a planned simulation: the `parasils`
//! command's own argument definitions (its `args.rs`, compiled unchanged
//! at this crate's root, see `lib.rs`) parse arbitrary argument lists; `simulate`'s arguments become
//! a scenario, the scenario a validated, planned simulation, and its first
//! records are computed. No call may panic; an error has a message; an
//! accepted run's records are finite.

use core::cell::RefCell;

use clap::{CommandFactory, FromArgMatches};
use parasils_sim::Simulation;

use crate::args::{Cli, Command};

thread_local! {
    /// The command's definition, built once and reused by every input
    /// (`Cli::try_parse_from` builds, checks and drops it each time, which
    /// cost more than the parse itself): the same definition, the same
    /// parse.
    static DEFINITION: RefCell<clap::Command> = RefCell::new(Cli::command());
}

/// `Cli::try_parse_from(argv)`, on the definition built once.
fn parse(argv: &[String]) -> Result<Cli, clap::Error> {
    DEFINITION.with_borrow_mut(|definition| {
        let mut matches = definition.try_get_matches_from_mut(argv)?;
        Cli::from_arg_matches_mut(&mut matches).map_err(|e| e.format(definition))
    })
}

/// The arguments in an input: one per line. With the first byte odd, the
/// list is the whole command line after `parasils` (any command, parsed
/// only); otherwise it follows `parasils simulate` and the run is planned.
pub fn arguments(data: &[u8]) -> (bool, Vec<String>) {
    let (whole, rest) = match data.split_first() {
        Some((&b, rest)) => (b & 1 == 1, rest),
        None => (false, data),
    };
    let list = if rest.is_empty() {
        Vec::new()
    } else {
        rest.split(|&b| b == b'\n')
            .map(|a| String::from_utf8_lossy(a).into_owned())
            .collect()
    };
    (whole, list)
}

/// The target's check.
pub fn cli_simulate(data: &[u8]) {
    let (whole, list) = arguments(data);
    let mut argv = vec![String::from("parasils")];
    if !whole {
        argv.push(String::from("simulate"));
    }
    argv.extend(list);
    let cli = match parse(&argv) {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version texts come this way too.
            assert!(!e.to_string().is_empty(), "an empty message for {argv:?}");
            return;
        }
    };
    let Command::Simulate(mut args) = cli.command else {
        return;
    };
    // No file named by the input is read here: a robot file is the robot
    // file target's, a procedure file (`--procedure`, which names the
    // robot, the start and the motions) the procedure file target's. Without
    // them the run is the paper's scenario with the other arguments given
    // (clap already refused any that conflict with `--procedure`).
    args.robot.robot = None;
    args.procedure = None;
    if let Some(path) = &args.output {
        // The format from the extension or --format: a value or an error.
        let _ = args.format(path);
    }
    let scenario = match args.scenario() {
        Ok(scenario) => scenario,
        Err(e) => {
            // No file is read, so only the input's own rules can refuse it
            // (a retarget or a stop with the optimal timing), naming the
            // flag.
            let text = e.to_string();
            assert!(
                text.starts_with("--") && text.contains(" cannot be given with "),
                "no file to read, yet the scenario failed: {text}"
            );
            return;
        }
    };
    let sim = match Simulation::new(scenario) {
        Ok(sim) => sim,
        Err(e) => {
            assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
            return;
        }
    };
    let d = sim.duration();
    assert!(
        d.is_finite() && d >= 0.0,
        "a planned duration of {d} s for {argv:?}"
    );
    assert!(sim.sample_count() >= 1, "no sample for {argv:?}");
    // The first records: finite, numbered from 0.
    for (k, record) in sim.samples().take(3).enumerate() {
        match record {
            Ok(r) => {
                assert_eq!(r.index, k);
                let row = parasils_sim::columns::csv_row(&r);
                assert!(
                    row.iter().all(|v| v.is_finite()),
                    "a non-finite record {r:?} for {argv:?}"
                );
            }
            Err(e) => {
                assert!(!e.to_string().is_empty(), "an empty message for {e:?}");
                break;
            }
        }
    }
}
