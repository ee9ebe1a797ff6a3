//! The control loop's timing: how it waits for a deadline (a sleep to a
//! margin before it, then a spin), each cycle's lateness (how long after
//! its deadline it started) and its work, the deadlines it missed, and the
//! frames it dropped because the publisher was behind.
//!
//! # What a miss is
//! Cycle `k` is due at `start + k T` (`T` the period). It is
//! - *late* when it starts more than [`LATE_TOLERANCE`] of a period after
//!   its deadline (50 us at 1 kHz): its inputs were read and its setpoint
//!   sent that much late;
//! - an *overrun* when its work ends after the next cycle is due (its
//!   lateness plus its work is more than `T`): the next cycle cannot start
//!   on time.
//!
//! A *deadline miss* is a cycle that is late, an overrun, or both; the
//! three counts are kept apart.

use core::time::Duration;
use std::time::Instant;

/// The share of a period a cycle may start after its deadline and still
/// be on time.
pub const LATE_TOLERANCE: f64 = 0.05;

/// The timing statistics of the cycles run so far.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CycleStats {
    /// Cycles run.
    pub cycles: u64,
    /// Cycles that were late, overran, or both: a start more than
    /// [`LATE_TOLERANCE`] of a period after the deadline, work that ends
    /// after the next deadline.
    pub deadline_misses: u64,
    /// Cycles that started more than [`LATE_TOLERANCE`] of a period after
    /// their deadline.
    pub late_starts: u64,
    /// Cycles whose work ended after the next cycle was due.
    pub overruns: u64,
    /// The longest cycle's work, s.
    pub worst_cycle_s: f64,
    /// The sum of every cycle's work, s (the mean is this over `cycles`).
    pub total_cycle_s: f64,
    /// The latest start after a deadline, s.
    pub worst_late_s: f64,
    /// Frames not handed to the publisher because its queue was full.
    pub dropped_frames: u64,
}

impl CycleStats {
    /// Counts one cycle that started `late` after its deadline and worked
    /// for `work`, in a period of `period`.
    pub fn count(&mut self, late: Duration, work: Duration, period: Duration) {
        self.cycles += 1;
        let (late_s, work_s) = (late.as_secs_f64(), work.as_secs_f64());
        self.worst_late_s = self.worst_late_s.max(late_s);
        self.worst_cycle_s = self.worst_cycle_s.max(work_s);
        self.total_cycle_s += work_s;
        let is_late = late > period.mul_f64(LATE_TOLERANCE);
        let overrun = late + work > period;
        self.late_starts += u64::from(is_late);
        self.overruns += u64::from(overrun);
        self.deadline_misses += u64::from(is_late || overrun);
    }

    /// The mean cycle's work, s (0 before the first cycle).
    pub fn mean_cycle_s(&self) -> f64 {
        if self.cycles == 0 {
            0.0
        } else {
            self.total_cycle_s / self.cycles as f64
        }
    }
}

/// Waits until `due`: sleeps until `margin` before it, then spins
/// (`std::hint::spin_loop`) to it, so that the wake-up's jitter (the
/// scheduler's and the timer's, up to `margin`) does not make the cycle
/// late. Returns at once when `due` has passed. The instant it returned.
pub fn wait_until(due: Instant, margin: Duration) -> Instant {
    let now = Instant::now();
    if let Some(sleep) = due
        .checked_sub(margin)
        .and_then(|w| w.checked_duration_since(now))
    {
        std::thread::sleep(sleep);
    }
    loop {
        let now = Instant::now();
        if now >= due {
            return now;
        }
        core::hint::spin_loop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn late_starts_and_overruns_are_counted_apart() {
        let ms = Duration::from_millis;
        let us = Duration::from_micros;
        let mut s = CycleStats::default();
        // On time, short.
        s.count(us(0), us(200), ms(1));
        // 50 us late is the tolerance itself: on time; ends at 1 ms exactly.
        s.count(us(50), us(950), ms(1));
        // 51 us late: late, and ends within the period.
        s.count(us(51), us(100), ms(1));
        // On time, but its work ends 1 us after the next deadline.
        s.count(us(10), us(991), ms(1));
        // Both.
        s.count(us(900), us(101), ms(1));
        assert_eq!(s.cycles, 5);
        assert_eq!(s.late_starts, 2);
        assert_eq!(s.overruns, 2);
        assert_eq!(s.deadline_misses, 3);
        assert!((s.worst_cycle_s - 991e-6).abs() < 1e-15);
        assert!((s.worst_late_s - 0.9e-3).abs() < 1e-15);
        let sum = (200.0 + 950.0 + 100.0 + 991.0 + 101.0) * 1e-6;
        assert!((s.mean_cycle_s() - sum / 5.0).abs() < 1e-15);
    }

    #[test]
    fn the_wait_never_returns_before_its_deadline() {
        // Past deadlines return at once; future ones never early, whatever
        // the margin (a margin longer than the wait spins all of it).
        let start = Instant::now();
        for (k, margin_us) in [(1u64, 0u64), (2, 100), (3, 5_000), (4, 300)] {
            let due = start + Duration::from_millis(k);
            let woke = wait_until(due, Duration::from_micros(margin_us));
            assert!(woke >= due);
        }
        let past = Instant::now();
        let woke = wait_until(start, Duration::from_micros(100));
        assert!(woke >= past);
    }
}
