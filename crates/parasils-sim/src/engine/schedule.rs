//! The commands of a run on the sample grid: each at the first sample at or
//! after its time, validated, and given to the online controller there.

use parasils::OnlineController;
use parasils::traj::Synchronization;

use crate::scenario::{Command, CommandKind, Online, Scenario};

use super::error::{CommandError, CommandName, SimulationError};

/// A command with the sample it takes effect at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scheduled {
    /// The command as given.
    pub command: Command,
    /// Its goal `[psi, theta]` as final angles, rad; `None` for the stop.
    pub goal_rad: Option<[f64; 2]>,
    /// The first sample at or after its time: where it takes effect.
    pub sample: usize,
    /// That sample's time, `sample / rate`, s.
    pub t_s: f64,
}

/// The first sample index `k >= from` whose time `k / rate` satisfies
/// `ready` (monotone: false, then true), starting the search near `guess`
/// s; `None` when it does not fit `usize`.
pub(super) fn first_sample(
    rate: f64,
    from: usize,
    guess: f64,
    ready: impl Fn(f64) -> bool,
) -> Option<usize> {
    let x = (guess * rate).ceil();
    // From 2^53 on, not every index is an f64 of its own: refuse them.
    if !(x.is_finite() && x < 9.007_199_254_740_992e15) {
        return None;
    }
    // In range: checked just above (and `max(0)`).
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let mut k = (x.max(0.0) as usize).max(from);
    let time = |k: usize| k as f64 / rate;
    // The guess is within a sample or two of the answer (rounding): a few
    // steps back, then forward until `ready` holds (a step or two in
    // practice; `ready` is true from the guess's time on, up to rounding).
    for _ in 0..4 {
        if k > from && ready(time(k - 1)) {
            k -= 1;
        }
    }
    while !ready(time(k)) {
        k = k.checked_add(1)?;
    }
    Some(k)
}

/// The commands of `scenario`'s online `run`, validated, with their
/// samples.
pub(super) fn schedule(
    scenario: &Scenario,
    run: &Online,
) -> Result<Vec<Scheduled>, SimulationError> {
    let fail = SimulationError::Commands;
    let finite = |command, what, value: f64| {
        if value.is_finite() {
            Ok(())
        } else {
            Err(fail(CommandError::NonFinite {
                command,
                what,
                value,
            }))
        }
    };
    let mut previous: Option<(CommandName, f64)> = None;
    for (k, r) in run.retargets.iter().enumerate() {
        let name = CommandName::Retarget(k + 1);
        finite(name, "t", r.t_s)?;
        finite(name, "psi", r.psi_deg)?;
        finite(name, "theta", r.theta_deg)?;
        if r.t_s < 0.0 {
            return Err(fail(CommandError::BeforeStart {
                command: name,
                t: r.t_s,
            }));
        }
        if let Some((p, t)) = previous
            && r.t_s < t
        {
            return Err(fail(CommandError::OutOfOrder {
                command: name,
                t: r.t_s,
                previous: p,
                previous_t: t,
            }));
        }
        previous = Some((name, r.t_s));
    }
    if let Some(t) = run.stop_at_s {
        finite(CommandName::Stop, "t", t)?;
        if t < 0.0 {
            return Err(fail(CommandError::BeforeStart {
                command: CommandName::Stop,
                t,
            }));
        }
    }
    let rate = scenario.rate_hz;
    let start = scenario.start();
    let mut out: Vec<Scheduled> = Vec::with_capacity(run.retargets.len() + 2);
    let mut retargets = 0;
    let mut names = Vec::with_capacity(out.capacity());
    for command in scenario.commands() {
        let name = match command.kind {
            CommandKind::Reorient => CommandName::Reorientation,
            CommandKind::Retarget => {
                retargets += 1;
                CommandName::Retarget(retargets)
            }
            _ => CommandName::Stop,
        };
        let from = out.last().map_or(0, |s| s.sample);
        let sample = first_sample(rate, from, command.t_s, |t| t >= command.t_s).ok_or(
            SimulationError::Trajectory(parasils::traj::Error::TooManySamples {
                duration: command.t_s,
                rate,
            }),
        )?;
        let t_s = sample as f64 / rate;
        if let (Some(p), Some(&pname)) = (out.last(), names.last())
            && p.sample == sample
        {
            return Err(fail(CommandError::SameSample {
                command: name,
                t: command.t_s,
                previous: pname,
                previous_t: p.command.t_s,
                sample_t: t_s,
                rate,
            }));
        }
        names.push(name);
        out.push(Scheduled {
            command,
            goal_rad: command.goal_deg.map(|g| run.turn.angles_rad(&start, g)),
            sample,
            t_s,
        });
    }
    Ok(out)
}

/// Gives `s`'s command to `online` at its sample's time, its two angles
/// timed together by `sync`.
pub(super) fn apply(
    online: &mut OnlineController<f64>,
    s: &Scheduled,
    sync: Synchronization,
) -> Result<(), parasils::Error> {
    match s.goal_rad {
        Some(goal) => online.command_synchronized(s.t_s, goal, sync).map(|_| ()),
        None => online.stop(s.t_s),
    }
}
