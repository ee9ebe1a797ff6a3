//! The live server over loopback, measured: the control loop's timing (its
//! worst cycle, its latest start, its deadline misses) and the share of the
//! messages a client receives, with a client that reads everything and
//! with one that subscribes to everything and then stops reading.
//!
//! `cargo bench -p parasils-live --bench live` (about 40 s: four 10 s
//! sessions at 1 kHz); the results are in BENCHMARKS.md (*Live*). Times
//! are measured, never asserted.

#[path = "../tests/common/mod.rs"]
mod common;

use core::time::Duration;
use std::collections::BTreeSet;

use common::{Client, session};

/// One 10 s session at 1 kHz control and `publish_hz`; `reading` says
/// whether the client keeps reading after it subscribed.
fn run(publish_hz: f64, reading: bool) {
    let duration_s = 10.0;
    let s = session(1000.0, publish_hz, duration_s);
    let address = s.address().to_string();
    let topics = s.topics().len();
    let waiter = std::thread::spawn(move || s.wait());
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    let received = rt.block_on(async {
        let mut c = Client::new(&address).await;
        c.subscribe(|_| true).await;
        if reading {
            c.read_to_end(Duration::from_secs_f64(duration_s + 15.0))
                .await;
        } else {
            // Subscribed, then silent: the socket's buffers and the
            // server's queue for this client fill up.
            tokio::time::sleep(Duration::from_secs_f64(duration_s + 0.5)).await;
        }
        c.received
    });
    let report = waiter.join().expect("join").expect("session");
    let st = &report.stats;
    let got: usize = received.values().map(Vec::len).sum();
    let first = received
        .values()
        .filter_map(|v| v.first().map(|(ns, _)| *ns))
        .max()
        .unwrap_or(0);
    // Distinct times on /platform from its first message, against the
    // frames published since then.
    let platform: BTreeSet<u64> = received
        .get("/platform")
        .map(|v| v.iter().map(|(ns, _)| *ns).collect())
        .unwrap_or_default();
    let every = (1000.0 / publish_hz).round() as u64;
    let published_since = (0..=10_000u64)
        .filter(|k| k % every == 0)
        .filter(|k| k * 1_000_000 >= platform.first().copied().unwrap_or(first))
        .count();
    println!(
        "{publish_hz:>6} Hz publishing, client {}: {} cycles, {} deadline misses, worst cycle {:.1} us, mean {:.2} us, latest start {:.1} us; {} frames dropped; published {} messages on {topics} topics, received {got}; /platform {} of {} ({:.3} %)",
        if reading { "reading  " } else { "not reading" },
        st.cycles,
        st.deadline_misses,
        st.worst_cycle_s * 1e6,
        st.mean_cycle_s() * 1e6,
        st.worst_late_s * 1e6,
        st.dropped_frames,
        report.published.messages,
        platform.len(),
        published_since,
        100.0 * platform.len() as f64 / published_since.max(1) as f64,
    );
}

fn main() {
    // `cargo test --benches` runs each bench once with `--bench` absent:
    // nothing to measure then.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    for (publish_hz, reading) in [
        (100.0, true),
        (1000.0, true),
        (100.0, false),
        (1000.0, false),
    ] {
        run(publish_hz, reading);
    }
}
