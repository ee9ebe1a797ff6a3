//! The control loop's timing: each cycle's lateness (how long after its
//! deadline it started) and its duration, the deadlines it missed, and the
//! frames it dropped because the publisher was behind.

use core::time::Duration;

/// The timing statistics of the cycles run so far.
///
/// A cycle `k` is due at `start + k / rate`; it *misses its deadline* when
/// it ends after the next cycle is due (its lateness plus its duration is
/// more than one period), so that the next cycle starts late.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CycleStats {
    /// Cycles run.
    pub cycles: u64,
    /// Cycles that ended after the next one was due.
    pub deadline_misses: u64,
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
        if late + work > period {
            self.deadline_misses += 1;
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cycle_that_ends_after_the_next_deadline_is_a_miss() {
        let ms = Duration::from_millis;
        let us = Duration::from_micros;
        let mut s = CycleStats::default();
        s.count(us(0), us(200), ms(1));
        s.count(us(900), us(100), ms(1));
        s.count(us(900), us(101), ms(1));
        s.count(us(50), us(1500), ms(1));
        assert_eq!(s.cycles, 4);
        assert_eq!(s.deadline_misses, 2);
        assert!((s.worst_cycle_s - 1.5e-3).abs() < 1e-15);
        assert!((s.worst_late_s - 0.9e-3).abs() < 1e-15);
        assert!((s.mean_cycle_s() - (200.0 + 100.0 + 101.0 + 1500.0) * 1e-6 / 4.0).abs() < 1e-15);
    }
}
