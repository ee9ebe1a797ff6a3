//! The live server over loopback, measured: the control loop's timing (its
//! worst cycle, its latest start, its late starts and overruns) and the
//! share of the messages a client receives, with a client that reads
//! everything and with one that subscribes to everything and then stops
//! reading; first, the wake-up jitter the loop's spin margin is chosen
//! from (10,000 sleeps to 1 ms deadlines, without a spin); and before each
//! session, side by side, the machine's floor (an empty loop with the same
//! scheduling, and the gaps a spinning thread sees).
//!
//! `cargo bench -p parasils-live --bench live` (about 3 min: the jitter,
//! then four floors of 2 x 10 s and four 10 s sessions at 1 kHz); the results are in BENCHMARKS.md
//! (*Live*). Times are measured, never asserted. `PARASILS_LIVE_PRIORITY`
//! (a `SCHED_FIFO` priority, or `none`) and `PARASILS_LIVE_MARGIN_US`
//! change the sessions' scheduling and spin margin.

#[path = "../tests/common/mod.rs"]
mod common;

use core::time::Duration;
use std::collections::BTreeSet;
use std::time::Instant;

use common::{Client, drive, session_options};
use parasils_live::{LiveOptions, schedule_current_thread, wait_until};

/// The sessions' options from the environment.
fn options(publish_hz: f64, duration_s: f64) -> LiveOptions {
    let mut o = LiveOptions {
        port: 0,
        publish_hz,
        duration_s: Some(duration_s),
        ..LiveOptions::default()
    };
    if let Ok(p) = std::env::var("PARASILS_LIVE_PRIORITY") {
        o.realtime_priority = p.parse().ok();
    }
    if let Ok(m) = std::env::var("PARASILS_LIVE_MARGIN_US") {
        o.spin_margin_s = m.parse::<f64>().expect("PARASILS_LIVE_MARGIN_US: a number") * 1e-6;
    }
    o
}

/// How late a thread wakes from a sleep to an absolute deadline, with
/// `priority`: 10,000 deadlines 1 ms apart, no spin, 8 us of work each.
fn jitter(priority: Option<u8>) {
    let (scheduling, mut late) = std::thread::spawn(move || {
        let scheduling = schedule_current_thread(priority);
        let start = Instant::now();
        let mut late = Vec::with_capacity(10_000);
        for k in 1..=10_000u64 {
            let due = start + Duration::from_millis(k);
            if let Some(w) = due.checked_duration_since(Instant::now()) {
                std::thread::sleep(w);
            }
            late.push(Instant::now().saturating_duration_since(due).as_secs_f64() * 1e6);
            let work = Instant::now();
            while work.elapsed() < Duration::from_micros(8) {
                core::hint::spin_loop();
            }
        }
        (scheduling, late)
    })
    .join()
    .expect("join");
    late.sort_by(f64::total_cmp);
    let q = |p: f64| late[((late.len() - 1) as f64 * p).round() as usize];
    println!(
        "wake-up after a sleep, {scheduling}: median {:.1} us, 90 % {:.1} us, 99 % {:.1} us, 99.9 % {:.1} us, worst {:.1} us; {} of 10,000 more than 50 us late",
        q(0.5),
        q(0.9),
        q(0.99),
        q(0.999),
        late[late.len() - 1],
        late.iter().filter(|&&l| l > 50.0).count()
    );
}

/// The machine's floor for the loop, measured beside each session, in two
/// runs of 10,000 cycles of 1 ms by a thread with the sessions'
/// scheduling, with no work, no server and no client. First it waits for
/// each deadline as the loop does ([`wait_until`], the same margin) and
/// does nothing else, so that it sleeps as much of each cycle as the loop
/// does: its late starts (over 5 % of a period) are what this machine
/// gives the loop. Then it waits the same way and spins 0.8 ms of each
/// cycle reading the clock: a gap over 50 us between two reads is time the
/// processor was taken away (at `SCHED_FIFO` no thread of this machine can
/// take it, and the rest of each cycle is asleep, so the kernel's
/// real-time limit never throttles it), by an interrupt or by the
/// hypervisor, which no program can prevent; its late starts are counted
/// too (a thread that sleeps 0.1 ms a cycle instead of 0.9).
fn floor(priority: Option<u8>, margin: Duration) {
    let (scheduling, idle_late, late, gaps, worst_gap_us) = std::thread::spawn(move || {
        let scheduling = schedule_current_thread(priority);
        let cycles = |spin: bool| {
            let start = Instant::now() + Duration::from_millis(1);
            let (mut late, mut gaps, mut worst) = (0u32, 0u32, Duration::ZERO);
            for k in 0..10_000u32 {
                let due = start + Duration::from_millis(u64::from(k));
                let woke = wait_until(due, margin);
                if woke.saturating_duration_since(due) > Duration::from_micros(50) {
                    late += 1;
                }
                let mut before = Instant::now();
                while spin && before < due + Duration::from_micros(800) {
                    let now = Instant::now();
                    let gap = now - before;
                    if gap > Duration::from_micros(50) {
                        gaps += 1;
                    }
                    worst = worst.max(gap);
                    before = now;
                }
            }
            (late, gaps, worst)
        };
        let (idle_late, _, _) = cycles(false);
        let (late, gaps, worst) = cycles(true);
        (scheduling, idle_late, late, gaps, worst.as_secs_f64() * 1e6)
    })
    .join()
    .expect("join");
    println!(
        "the machine's floor, {scheduling}: an empty loop started {idle_late} of 10,000 cycles more than 50 us late (asleep as the loop is); spinning 0.8 ms of each cycle, {late} late starts, and the processor was taken away {gaps} times for more than 50 us (longest {worst_gap_us:.1} us)"
    );
}

/// One 10 s session at 1 kHz control and `publish_hz`; `reading` says
/// whether the client keeps reading after it subscribed.
fn run(publish_hz: f64, reading: bool) {
    let duration_s = 10.0;
    let s = session_options(1000.0, &options(publish_hz, duration_s));
    let scheduling = s.scheduling().to_string();
    let topics = s.topics().len();
    let (received, report) = drive(s, async |address| {
        let mut c = Client::new(address).await;
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
        "{publish_hz:>6} Hz publishing, client {}, {scheduling}: {} cycles, {} deadline misses ({} late starts, {} overruns), worst cycle {:.1} us, mean {:.2} us, latest start {:.1} us; {} frames dropped; published {} messages on {topics} topics, received {got}; /platform {} of {} ({:.3} %)",
        if reading { "reading" } else { "not reading" },
        st.cycles,
        st.deadline_misses,
        st.late_starts,
        st.overruns,
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
    jitter(None);
    jitter(Some(80));
    let o = options(100.0, 10.0);
    for (publish_hz, reading) in [
        (100.0, true),
        (1000.0, true),
        (100.0, false),
        (1000.0, false),
    ] {
        floor(
            o.realtime_priority,
            Duration::from_secs_f64(o.spin_margin_s),
        );
        run(publish_hz, reading);
    }
}
