//! The control thread's scheduling: a real-time priority (`SCHED_FIFO`)
//! where the system allows it, the ordinary policy otherwise, and the
//! timer slack that decides how late a sleeping thread may be woken.
//!
//! Both system calls go through well-kept crates (`thread-priority` for
//! `pthread_setschedparam`, `nix` for `prctl(PR_SET_TIMERSLACK)`), so the
//! crate keeps the workspace's `forbid(unsafe_code)`. Neither needs root:
//! a process without the right (no `CAP_SYS_NICE`, `ulimit -r` 0) gets
//! `EPERM`, and the thread keeps the ordinary policy.

/// How the control thread is scheduled.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Scheduling {
    /// `SCHED_FIFO` at this priority (1 to 99): the thread runs as soon as
    /// it is runnable, ahead of every ordinary thread.
    Fifo {
        /// The priority.
        priority: u8,
    },
    /// The ordinary policy: asked for none, or the system refused.
    Ordinary {
        /// Why: `"not asked"`, or the system's refusal (`EPERM`: the
        /// process may not raise its priority).
        reason: String,
    },
}

impl Scheduling {
    /// Whether the thread runs at a real-time priority.
    pub fn is_realtime(&self) -> bool {
        matches!(self, Scheduling::Fifo { .. })
    }
}

impl core::fmt::Display for Scheduling {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Scheduling::Fifo { priority } => write!(f, "SCHED_FIFO priority {priority}"),
            Scheduling::Ordinary { reason } => write!(f, "the ordinary policy ({reason})"),
        }
    }
}

/// Asks for `SCHED_FIFO` at `priority` (clamped to 1..=99) for the calling
/// thread, and a timer slack of 1 ns (the ordinary policy's default, 50 us,
/// lets the kernel wake a sleeping thread that much after its time); the
/// scheduling it got. `None` asks for nothing.
pub fn schedule_current_thread(priority: Option<u8>) -> Scheduling {
    set_timer_slack_ns(1);
    let Some(priority) = priority else {
        return Scheduling::Ordinary {
            reason: "not asked".to_owned(),
        };
    };
    let priority = priority.clamp(1, 99);
    match set_fifo(priority) {
        Ok(()) => Scheduling::Fifo { priority },
        Err(reason) => Scheduling::Ordinary { reason },
    }
}

#[cfg(unix)]
fn set_fifo(priority: u8) -> Result<(), String> {
    use thread_priority::{
        RealtimeThreadSchedulePolicy, ThreadPriority, ThreadPriorityValue, ThreadSchedulePolicy,
        set_thread_priority_and_policy, thread_native_id,
    };
    let value = ThreadPriorityValue::try_from(priority)
        .map_err(|e| format!("SCHED_FIFO priority {priority}: {e}"))?;
    set_thread_priority_and_policy(
        thread_native_id(),
        ThreadPriority::Crossplatform(value),
        ThreadSchedulePolicy::Realtime(RealtimeThreadSchedulePolicy::Fifo),
    )
    .map_err(|e| match e {
        thread_priority::Error::OS(code) => format!(
            "SCHED_FIFO refused: {}",
            std::io::Error::from_raw_os_error(code)
        ),
        other => format!("SCHED_FIFO refused: {other:?}"),
    })
}

#[cfg(not(unix))]
fn set_fifo(_priority: u8) -> Result<(), String> {
    Err("SCHED_FIFO is not available on this system".to_owned())
}

/// A failure leaves the slack as it was, which is only slower wake-ups
/// (the spin before each deadline absorbs them), so it is not reported.
#[cfg(target_os = "linux")]
fn set_timer_slack_ns(ns: u64) {
    let _ = nix::sys::prctl::set_timerslack(ns);
}

#[cfg(not(target_os = "linux"))]
fn set_timer_slack_ns(_ns: u64) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asking_for_nothing_keeps_the_ordinary_policy() {
        let s = std::thread::spawn(|| schedule_current_thread(None))
            .join()
            .expect("thread");
        assert_eq!(
            s,
            Scheduling::Ordinary {
                reason: "not asked".to_owned()
            }
        );
        assert!(!s.is_realtime());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn the_policy_reported_is_the_thread_s_own() {
        // Whatever the system allows, what is reported is what the
        // thread then has, read back from /proc (field 41 of `stat`).
        let (s, policy) = std::thread::spawn(|| {
            let s = schedule_current_thread(Some(10));
            let stat = std::fs::read_to_string("/proc/thread-self/stat").expect("stat");
            let after_name = stat.rsplit_once(')').expect("comm").1;
            // Fields after the name start at field 3; the policy is 41.
            let policy: u32 = after_name
                .split_whitespace()
                .nth(41 - 3)
                .expect("policy")
                .parse()
                .expect("number");
            (s, policy)
        })
        .join()
        .expect("thread");
        // SCHED_FIFO is policy 1 (`include/uapi/linux/sched.h`).
        let fifo = 1;
        assert_eq!(s.is_realtime(), policy == fifo, "{s}, policy {policy}");
        if let Scheduling::Fifo { priority } = s {
            assert_eq!(priority, 10);
        }
    }
}
