//! The control loop allocates nothing per cycle: the allocations its
//! thread makes are counted (`allocation-counter`'s global allocator, which
//! counts per thread) for a short and a long run fed the same inputs and
//! commands, and they are the same number, whatever the number of cycles.

use core::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

use parasils::teleop::{Command, TeleopParams};
use parasils_live::{
    CommandRequest, DeviceInput, Event, InputDevice, LiveCommand, LoopSettings, PENDING_COMMANDS,
    Queues, Reply, run_loop,
};
use parasils_sim::{Scenario, TeleopRun};

/// The allocations of `run_loop`'s thread over `cycles` cycles at 2 kHz,
/// with an input and commands waiting before it starts.
fn allocations(cycles: u64) -> u64 {
    let scenario = Scenario {
        rate_hz: 2000.0,
        ..Scenario::paper()
    };
    let run = TeleopRun::new(scenario, TeleopParams::assumed()).expect("run");
    let (events_in, events) = sync_channel(1024);
    let (frames, frames_out) = sync_channel(4 * usize::try_from(cycles).expect("small"));
    let (acks, acks_out) = sync_channel(PENDING_COMMANDS);
    let now = Instant::now();
    for command in [Command::Enable, Command::Pause, Command::Resume] {
        events_in
            .try_send(Event::Command(
                CommandRequest {
                    command: LiveCommand::Core(command),
                    id: Some(1),
                },
                Reply::Status(1),
                now,
            ))
            .expect("room");
    }
    let input = DeviceInput {
        device: InputDevice::Left,
        axes: [0.5, 0.0, 0.0, 0.0, 0.0, 0.0],
        buttons: 1,
        id: Some(2),
        hold_s: Some(0.01),
    };
    events_in.try_send(Event::Input(input, now)).expect("room");
    let stop = Arc::new(AtomicBool::new(false));
    let (count, stats) = std::thread::spawn(move || {
        let queues = Queues {
            events,
            frames,
            acks,
        };
        let settings = LoopSettings {
            publish_every: 2,
            cycles: Some(cycles),
            spin_margin: core::time::Duration::from_micros(100),
        };
        let mut stats = None;
        let info = allocation_counter::measure(|| {
            stats = Some(run_loop(run, settings, &queues, &stop, Instant::now()));
        });
        (info.count_total, stats.expect("ran").expect("loop"))
    })
    .join()
    .expect("thread");
    drop(events_in);
    assert_eq!(stats.cycles, cycles);
    assert_eq!(acks_out.try_iter().count(), 3);
    assert!(frames_out.try_iter().count() >= usize::try_from(cycles / 2).expect("small"));
    count
}

#[test]
fn the_control_loop_allocates_nothing_per_cycle() {
    let short = allocations(20);
    let long = allocations(400);
    println!("allocations on the control thread: {short} in 20 cycles, {long} in 400");
    assert_eq!(short, long);
}
