//! Standard output that notices when its reader goes away.
//!
//! `parasils simulate -o - | head` closes the pipe after ten lines; the next
//! write fails with `BrokenPipe`. That is the reader's choice, not an error
//! of the command: [`closed`] tells `main` to stop quietly (exit status 0)
//! instead of reporting it.

use core::sync::atomic::{AtomicBool, Ordering};
use std::io::{self, Write};

static CLOSED: AtomicBool = AtomicBool::new(false);

/// Whether a write to standard output found the pipe closed.
pub fn closed() -> bool {
    CLOSED.load(Ordering::Relaxed)
}

fn watch<T>(result: io::Result<T>) -> io::Result<T> {
    if let Err(e) = &result
        && e.kind() == io::ErrorKind::BrokenPipe
    {
        CLOSED.store(true, Ordering::Relaxed);
    }
    result
}

/// Standard output (locked), noting a closed pipe.
#[derive(Debug)]
pub struct Stdout(io::StdoutLock<'static>);

/// Standard output, for the whole command.
pub fn stdout() -> Stdout {
    Stdout(io::stdout().lock())
}

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        watch(self.0.write(buf))
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        watch(self.0.write_all(buf))
    }

    fn flush(&mut self) -> io::Result<()> {
        watch(self.0.flush())
    }
}
