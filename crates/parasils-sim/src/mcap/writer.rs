//! The writer thread: it owns the `mcap` writer, turns batches of formatted
//! messages into records (headers, indexes, checksums) and feeds the
//! compressor, while the caller's thread formats the next batch.
//!
//! Batches travel through a bounded channel and come back to be reused, so
//! memory stays flat; the file is the same, byte for byte, as one written on
//! a single thread.

use std::io::{Seek, Write};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use mcap::Writer;
use mcap::records::MessageHeader;

use super::error::McapError;

/// The size at which a batch goes to the writer thread, bytes.
pub(crate) const BATCH_BYTES: usize = 64 << 10;

/// The most batches queued for the writer thread (2 MiB of JSON): enough for
/// the formatting to go on while the writer waits at a chunk's end for zstd
/// to finish compressing it (see `BENCHMARKS.md`).
const BATCHES_IN_FLIGHT: usize = 32;

/// Messages formatted and not yet written: each header with the end of its
/// data in `bytes`, the data back to back.
#[derive(Debug, Default)]
pub(crate) struct Batch {
    pub(crate) headers: Vec<(MessageHeader, usize)>,
    pub(crate) bytes: Vec<u8>,
}

impl Batch {
    /// Appends a message: its header and its data.
    pub(crate) fn push(&mut self, header: MessageHeader, data: &[u8]) {
        self.bytes.extend_from_slice(data);
        self.headers.push((header, self.bytes.len()));
    }
}

/// What the writer thread returns: the writer, and the first error.
pub(crate) type Written<W> = (Writer<W>, Result<(), McapError>);

/// The writer thread and the channels to it (batches to write) and from it
/// (written batches, to reuse).
pub(crate) struct WriterThread<W: Write + Seek> {
    to: Option<SyncSender<Batch>>,
    back: Receiver<Batch>,
    handle: Option<JoinHandle<Written<W>>>,
}

impl<W: Write + Seek + Send + 'static> WriterThread<W> {
    /// Starts the thread, which owns `writer` until [`WriterThread::join`].
    pub(crate) fn spawn(writer: Writer<W>) -> Result<Self, McapError> {
        let (to, from_main) = sync_channel::<Batch>(BATCHES_IN_FLIGHT);
        let (to_main, back) = sync_channel::<Batch>(BATCHES_IN_FLIGHT + 2);
        let handle = std::thread::Builder::new()
            .name("parasils-mcap".to_owned())
            .spawn(move || {
                let mut writer = writer;
                for mut batch in from_main {
                    let mut start = 0;
                    for (header, end) in &batch.headers {
                        let data = batch.bytes.get(start..*end).unwrap_or_default();
                        if let Err(e) = writer.write_to_known_channel(header, data) {
                            return (writer, Err(McapError::from(e)));
                        }
                        start = *end;
                    }
                    batch.headers.clear();
                    batch.bytes.clear();
                    // Reused if the sender wants it; dropped otherwise.
                    let _ = to_main.try_send(batch);
                }
                (writer, Ok(()))
            })
            .map_err(|e| McapError::Mcap(e.into()))?;
        Ok(Self {
            to: Some(to),
            back,
            handle: Some(handle),
        })
    }

    /// Sends `batch` to be written; on failure, the writer thread's error.
    pub(crate) fn send(&mut self, batch: Batch) -> Result<(), McapError> {
        let sent = match &self.to {
            Some(to) => to.send(batch).is_ok(),
            None => false,
        };
        if sent {
            Ok(())
        } else {
            // The thread stopped on an error: report it (once; then a
            // generic one).
            match self.join() {
                Ok((_, Err(e))) => Err(e),
                _ => Err(McapError::io("the MCAP writer stopped on an earlier error")),
            }
        }
    }

    /// An empty batch, reused when one came back.
    pub(crate) fn empty_batch(&self) -> Batch {
        self.back.try_recv().unwrap_or_else(|_| Batch {
            headers: Vec::with_capacity(256),
            bytes: Vec::with_capacity(BATCH_BYTES + (16 << 10)),
        })
    }

    /// Ends the thread once it has written everything sent; its writer and
    /// first error.
    pub(crate) fn join(&mut self) -> Result<Written<W>, McapError> {
        self.to = None;
        let handle = self
            .handle
            .take()
            .ok_or_else(|| McapError::io("the MCAP writer thread is gone"))?;
        handle
            .join()
            .map_err(|_| McapError::io("the MCAP writer thread panicked"))
    }
}
