//! SIGINT and SIGTERM end a run through its normal error path: the handlers
//! only set a flag, which the run loop checks at every record ([`Watch`]);
//! the run then stops with an error, the output file's temporary file is
//! removed as it is dropped, on the main thread, and the command exits with
//! 128 + the signal's number (130, 143). A second SIGINT or SIGTERM while
//! the first is handled ends the process at once with that status.
//!
//! SIGXFSZ, which the kernel sends when a write would go past the
//! file-size limit (`ulimit -f`) and whose default action kills the
//! process, is caught and ignored: the write then fails with EFBIG, which
//! ends the run as any other write error does.

use core::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::path::PathBuf;

use parasils_sim::{Record, Sink};
use signal_hook::consts::{SIGINT, SIGTERM, SIGXFSZ};

/// Set by the first SIGINT or SIGTERM.
static RAISED: AtomicBool = AtomicBool::new(false);
/// That signal's number.
static SIGNAL: AtomicUsize = AtomicUsize::new(0);
/// Set by SIGXFSZ; nothing reads it.
static FILE_TOO_LARGE: AtomicBool = AtomicBool::new(false);

/// Installs the handlers.
///
/// # Errors
/// The operating system's error if a handler cannot be installed.
pub fn install() -> std::io::Result<()> {
    for signal in [SIGINT, SIGTERM] {
        // Registered first, so it runs before the flag is set: only a
        // second signal finds the flag set.
        signal_hook::flag::register_conditional_shutdown(signal, 128 + signal, &RAISED)?;
        signal_hook::flag::register_usize(signal, &SIGNAL, signal as usize)?;
        signal_hook::flag::register(signal, &RAISED)?;
    }
    signal_hook::flag::register(SIGXFSZ, &FILE_TOO_LARGE)?;
    Ok(())
}

/// The SIGINT or SIGTERM received, if any.
pub fn received() -> Option<i32> {
    if RAISED.load(Ordering::SeqCst) {
        i32::try_from(SIGNAL.load(Ordering::SeqCst)).ok()
    } else {
        None
    }
}

/// A run stopped by a signal.
#[derive(Debug)]
pub struct Interrupted {
    /// The signal's number.
    pub signal: i32,
    /// The files whose unfinished temporary files were removed.
    pub removed: Vec<PathBuf>,
}

impl Interrupted {
    /// The exit status: 128 + the signal's number.
    pub fn status(&self) -> u8 {
        u8::try_from(128 + self.signal).unwrap_or(1)
    }
}

impl core::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("interrupted")?;
        for (i, path) in self.removed.iter().enumerate() {
            let lead = if i == 0 {
                ": removed the partial "
            } else {
                " and "
            };
            write!(f, "{lead}{}", path.display())?;
        }
        if !self.removed.is_empty() {
            f.write_str(" (any previous file there is unchanged)")?;
        }
        Ok(())
    }
}

impl core::error::Error for Interrupted {}

/// The error of [`Watch`]: a signal arrived.
#[derive(Debug)]
pub struct Stop;

impl core::fmt::Display for Stop {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("interrupted")
    }
}

impl core::error::Error for Stop {}

/// A sink that fails once SIGINT or SIGTERM has arrived, ending the run.
#[derive(Debug)]
pub struct Watch;

impl Sink for Watch {
    type Error = Stop;

    fn push(&mut self, _: &Record) -> Result<(), Stop> {
        if RAISED.load(Ordering::Relaxed) {
            Err(Stop)
        } else {
            Ok(())
        }
    }
}
