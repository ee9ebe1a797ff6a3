//! The control loop: the teleoperation core stepped at the control rate on
//! a thread of its own, against absolute deadlines, never waiting on the
//! network.
//!
//! Clients' messages reach it through a bounded queue that it empties
//! without waiting at the start of each cycle: a device's input is held
//! until its next one, commands take effect one per cycle in the order they
//! came. What it computes leaves through another bounded queue, one frame
//! per published cycle: when the publisher is behind, the frame is dropped
//! and counted, and the loop goes on. Acknowledgements go through a third
//! bounded queue (one per command, and the commands waiting are bounded by
//! [`PENDING_COMMANDS`]). Every hand-off is a `try_send` or a `try_recv`
//! on a queue allocated before the loop: the loop never allocates, never
//! blocks on a lock another thread holds, and never wakes the publisher
//! (which polls its queue), so a cycle's only system calls are its sleep
//! and its clock reads.
//!
//! Each cycle waits for its deadline with [`wait_until`]: a sleep to
//! [`LoopSettings::spin_margin`] before it, then a spin, so that the
//! wake-up's jitter does not make it late.

use core::sync::atomic::{AtomicBool, Ordering};
use core::time::Duration;
use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, SyncSender, TrySendError};
use std::time::Instant;

use nalgebra::Vector3;
use parasils::teleop::{Goal, MoveRefused, OperatingState};
use parasils_device::Held;
use parasils_sim::{Record, TeleopRun};

use crate::message::{CommandRequest, DeviceInput, InputDevice, LiveCommand};
use crate::timing::{CycleStats, wait_until};

/// The commands that may wait for their cycle (one is taken per cycle);
/// when that many wait, the loop leaves the rest in the input queue, whose
/// bound then refuses a client's next message.
pub const PENDING_COMMANDS: usize = 256;

/// Who sent a message: the WebSocket client's id.
pub type ClientTag = u32;

/// How a command's acknowledgement reaches the client that sent it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reply {
    /// Published on `/command`: a status message to this client.
    Status(ClientTag),
    /// A call of the `/command` service: the response to the call the
    /// session keeps under this number.
    Service(u32),
}

/// A client's message on its way to the control loop, with the instant
/// it arrived.
#[derive(Debug, Clone, Copy)]
pub enum Event {
    /// A device's input.
    Input(DeviceInput, Instant),
    /// A command, with how its acknowledgement reaches its client.
    Command(CommandRequest, Reply, Instant),
}

/// The last input applied: which device, the client's number, when it
/// arrived and the cycle that first used it (session time, s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AppliedInput {
    /// The device.
    pub device: InputDevice,
    /// The client's number for it.
    pub id: Option<u64>,
    /// When it arrived, s since the session's start.
    pub arrival_s: f64,
    /// The time of the cycle that first used it, s (its nominal time,
    /// `k / rate`).
    pub applied_t_s: f64,
    /// When that cycle read it, s since the session's start (the cycle's
    /// deadline plus its lateness): `applied_s - arrival_s` is the wait
    /// between the input's arrival and its first use.
    pub applied_s: f64,
    /// When the cycle before it read its queue, s since the session's
    /// start (0 for the first cycle): the input arrived after this, so the
    /// cycle that read it was the first that could.
    pub previous_read_s: f64,
}

/// A command's outcome, for the client that sent it.
#[derive(Debug, Clone, PartialEq)]
pub struct Ack {
    /// How it reaches the client that sent it.
    pub reply: Reply,
    /// The command and its number.
    pub request: CommandRequest,
    /// The state before it.
    pub before: OperatingState,
    /// The state after its cycle.
    pub after: OperatingState,
    /// Whether it was accepted: CRTK's table for the core's commands, the
    /// core's answer for a planned move.
    pub accepted: bool,
    /// Why a planned move was refused (the core's reason).
    pub refusal: Option<MoveRefused>,
    /// The cycle's time, s.
    pub t_s: f64,
}

/// What one published cycle hands the publisher.
#[derive(Debug, Clone, Copy)]
pub struct Frame {
    /// The cycle's record.
    pub record: Record,
    /// Whether the core is busy (the home move).
    pub busy: bool,
    /// The timing so far.
    pub stats: CycleStats,
    /// The last input applied.
    pub input: Option<AppliedInput>,
}

/// The loop's settings.
#[derive(Debug, Clone, Copy)]
pub struct LoopSettings {
    /// Hand every `publish_every`-th cycle to the publisher (and the last).
    pub publish_every: u64,
    /// Cycles to run (`None`: until stopped).
    pub cycles: Option<u64>,
    /// How long before each deadline the loop stops sleeping and spins
    /// (see [`wait_until`]).
    pub spin_margin: Duration,
}

/// The queues the loop talks through.
#[derive(Debug)]
pub struct Queues {
    /// Clients' messages in.
    pub events: Receiver<Event>,
    /// Frames out (bounded: full means dropped).
    pub frames: SyncSender<Frame>,
    /// Acknowledgements out (bounded: at least [`PENDING_COMMANDS`]).
    pub acks: SyncSender<Ack>,
}

/// The core's goal for a planned move on `/command` (`tips`: where the
/// tips are, for those a `move_to` does not give; a core command, which is
/// not a move here, maps to home).
fn goal(command: LiveCommand, tips: [Vector3<f64>; 2]) -> Goal<f64> {
    match command {
        LiveCommand::LookAtTips => Goal::LookAtTips,
        LiveCommand::LookAt(p) => Goal::LookAt(Vector3::from(p)),
        LiveCommand::MoveTo {
            angles_deg,
            tips_mm,
        } => Goal::Pose {
            angles: angles_deg.map(f64::to_radians),
            tips: [0, 1].map(|m| tips_mm[m].map_or(tips[m], Vector3::from)),
        },
        LiveCommand::Core(_) => Goal::Home,
    }
}

/// Runs `run` until `cycles` are done or `stop` is set; the final timing.
///
/// # Errors
/// The cycle's error ([`parasils_sim::SimulationError`]) when the core
/// fails; the loop stops there.
pub fn run_loop(
    mut run: TeleopRun,
    settings: LoopSettings,
    queues: &Queues,
    stop: &Arc<AtomicBool>,
    start: Instant,
) -> Result<CycleStats, parasils_sim::SimulationError> {
    let period = Duration::from_secs_f64(1.0 / run.rate_hz());
    let mut stats = CycleStats::default();
    let mut held = [Held::REST; 3];
    let mut pending: VecDeque<(CommandRequest, Reply)> = VecDeque::with_capacity(PENDING_COMMANDS);
    let mut fresh: [Option<(DeviceInput, Instant)>; 3] = [None; 3];
    // When each device's input lapses (a twist's), back to rest with
    // enable held.
    let mut lapse: [Option<Instant>; 3] = [None; 3];
    let mut applied = None;
    let mut last_read = start;
    let mut k: u64 = 0;
    // The last cycle run, if it was not published: stopped between two
    // published cycles, the session still ends on its last cycle.
    let mut unpublished = None;
    loop {
        let last = settings.cycles.is_some_and(|n| k + 1 >= n);
        if settings.cycles.is_some_and(|n| k >= n) || stop.load(Ordering::Relaxed) {
            break;
        }
        // Absolute deadlines: `start + k / rate`, so that a late cycle does
        // not push every later one.
        let due = start + Duration::from_secs_f64(k as f64 / run.rate_hz());
        let woke = wait_until(due, settings.spin_margin);
        // A full list of commands leaves the rest queued (no allocation).
        while pending.len() < PENDING_COMMANDS
            && let Ok(event) = queues.events.try_recv()
        {
            match event {
                Event::Input(input, at) => {
                    let d = input.device.index();
                    held[d] = Held {
                        axes: input.axes,
                        buttons: input.buttons,
                    };
                    fresh[d] = Some((input, at));
                    lapse[d] = input
                        .hold_s
                        .and_then(|h| Duration::try_from_secs_f64(h).ok())
                        .map(|h| at + h);
                }
                Event::Command(request, reply, _) => pending.push_back((request, reply)),
            }
        }
        // After the queue is emptied: every input read arrived before it.
        let read = Instant::now();
        for (h, l) in held.iter_mut().zip(lapse.iter_mut()) {
            if l.is_some_and(|end| read >= end) {
                *l = None;
                h.axes = [0.0; 6];
            }
        }
        let t = run.next_time_s();
        for (input, at) in fresh.iter_mut().filter_map(Option::take) {
            applied = Some(AppliedInput {
                device: input.device,
                id: input.id,
                arrival_s: at.saturating_duration_since(start).as_secs_f64(),
                applied_t_s: t,
                applied_s: read.saturating_duration_since(start).as_secs_f64(),
                previous_read_s: last_read.saturating_duration_since(start).as_secs_f64(),
            });
        }
        last_read = read;
        let before = run.teleop().state();
        let command = pending.pop_front();
        // The core's commands go through the cycle; a planned move starts
        // from the last cycle's setpoint, and this cycle is its first.
        let (core, refusal) = match command.map(|(r, _)| r.command) {
            Some(LiveCommand::Core(c)) => (Some(c), None),
            Some(other) => (None, run.start_move(goal(other, run.teleop().tips())).err()),
            None => (None, None),
        };
        let record = run.step(held, core)?;
        let busy = run.teleop().is_busy();
        if let Some((request, reply)) = command {
            let after = record.teleop.state;
            let accepted = match request.command {
                LiveCommand::Core(c) => before.after(c, after == OperatingState::Enabled).accepted,
                _ => refusal.is_none(),
            };
            // Full cannot be (one per command, bounded like them); the
            // receiver gone means the session is ending: nothing to tell.
            let _ = queues.acks.try_send(Ack {
                reply,
                request,
                before,
                after,
                accepted,
                refusal,
                t_s: t,
            });
        }
        let frame = Frame {
            record,
            busy,
            stats,
            input: applied,
        };
        unpublished = None;
        if k.is_multiple_of(settings.publish_every) || last {
            match queues.frames.try_send(frame) {
                Ok(()) => {}
                Err(TrySendError::Full(frame)) => {
                    stats.dropped_frames += 1;
                    unpublished = Some(frame);
                }
                Err(TrySendError::Disconnected(_)) => break,
            }
        } else {
            unpublished = Some(frame);
        }
        stats.count(woke.saturating_duration_since(due), woke.elapsed(), period);
        k += 1;
    }
    if let Some(frame) = unpublished {
        // The loop is over: waiting for the publisher costs no cycle, and
        // the session ends on its last cycle even when the publisher was
        // behind (that frame, counted as dropped, is delivered after all).
        if frame.stats.dropped_frames < stats.dropped_frames {
            stats.dropped_frames -= 1;
        }
        let _ = queues.frames.send(frame);
    }
    Ok(stats)
}
