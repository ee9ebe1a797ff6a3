//! A publisher that falls behind costs frames, never cycles, and never the
//! session's last cycle: the loop runs every cycle, counts each frame it
//! could not hand over, and delivers the last cycle's frame once the loop
//! is over, so that a recording always ends where the session did.

use core::sync::atomic::AtomicBool;
use core::time::Duration;
use std::sync::Arc;
use std::sync::mpsc::sync_channel;
use std::time::Instant;

use parasils::teleop::TeleopParams;
use parasils_live::{LoopSettings, PENDING_COMMANDS, Queues, run_loop};
use parasils_sim::{Scenario, TeleopRun};

#[test]
fn a_publisher_that_reads_nothing_loses_frames_but_not_the_last_cycle() {
    let rate_hz = 2000.0;
    let cycles = 200;
    let scenario = Scenario {
        rate_hz,
        ..Scenario::paper()
    };
    let run = TeleopRun::new(scenario, TeleopParams::assumed()).expect("run");
    let (_events_in, events) = sync_channel(16);
    // Room for two frames; nobody reads until the loop has run (0.1 s).
    let (frames, frames_out) = sync_channel(2);
    let (acks, _acks_out) = sync_channel(PENDING_COMMANDS);
    let stop = Arc::new(AtomicBool::new(false));
    let looped = std::thread::spawn(move || {
        let queues = Queues {
            events,
            frames,
            acks,
        };
        let settings = LoopSettings {
            publish_every: 1,
            cycles: Some(cycles),
            spin_margin: Duration::from_micros(100),
        };
        run_loop(run, settings, &queues, &stop, Instant::now())
    });
    std::thread::sleep(Duration::from_secs(2));
    let received: Vec<f64> = frames_out.iter().map(|f| f.record.t).collect();
    let stats = looped.join().expect("thread").expect("loop");
    println!(
        "{} of {cycles} frames handed over, {} dropped",
        received.len(),
        stats.dropped_frames
    );
    assert_eq!(stats.cycles, cycles);
    // Every cycle was published (`publish_every` 1): handed over or dropped.
    assert_eq!(
        received.len() as u64 + stats.dropped_frames,
        cycles,
        "{received:?}"
    );
    assert!(stats.dropped_frames > 0, "the queue never filled");
    // The first two filled the queue; the last came after the loop.
    let last_t = (cycles - 1) as f64 / rate_hz;
    assert_eq!(received.first().copied(), Some(0.0));
    assert!(
        (received[received.len() - 1] - last_t).abs() < 1e-12,
        "{received:?}"
    );
    assert!(received.windows(2).all(|w| w[0] < w[1]), "{received:?}");
}
