//! A simulation's output file: its records as CSV or MCAP, written
//! atomically ([`parasils_io::AtomicFile`]: to a temporary file beside the
//! target, renamed only when everything is written, so that a failed run
//! leaves nothing behind and the previous file stays as it was until the
//! rename; a FIFO or a device written directly).
//!
//! [`OutputFile`] is what `parasils simulate -o FILE` and the Python
//! bindings' `simulate(out=...)` write. Before anything is written,
//! [`check_size`] compares the file's estimated size ([`estimate_bytes`])
//! with the free space of the target's file system and with the cap
//! ([`parasils_io::file::DEFAULT_CAP_BYTES`]) that only `force` lifts.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use parasils_io::AtomicFile;
use parasils_io::file::{WriteError, check_bytes, written_directly};

use crate::csv::CsvSink;
use crate::mcap::{McapError, McapSink};
use crate::record::Record;
use crate::scenario::Scenario;
use crate::sink::Sink;

/// The formats of a simulation's output file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// One row per record, every column named with its unit.
    Csv,
    /// MCAP for Foxglove: one channel per group of columns, `/tf` and
    /// `/scene`.
    Mcap,
}

impl Format {
    /// The format named by a path's extension (`.csv`, `.mcap`, any case).
    ///
    /// # Errors
    /// [`OutputError::UnknownFormat`] for any other extension, or none.
    pub fn from_path(path: &Path) -> Result<Self, OutputError> {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("csv") => Ok(Format::Csv),
            Some(e) if e.eq_ignore_ascii_case("mcap") => Ok(Format::Mcap),
            _ => Err(OutputError::UnknownFormat {
                path: path.to_owned(),
            }),
        }
    }
}

/// What can go wrong with an output file: the file's own errors
/// ([`WriteError`], variant for variant: [`From<WriteError>`]) and the
/// writers'.
///
/// Each message is complete on its own (the file, and the operating
/// system's or the writer's words): the underlying errors are in the text,
/// not chained as `source()`, so that a report of the chain does not repeat
/// them. [`OutputError::io_error`] gives the I/O error underneath, if any.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The path's extension names no format.
    #[error(
        "cannot tell the output format of {}: use a .csv or .mcap extension, or name the format",
        path.display()
    )]
    UnknownFormat {
        /// The path.
        path: PathBuf,
    },
    /// The file itself: a folder given as the target, no room for it, over
    /// the cap, its folder not writable, or a write that failed (the
    /// variants of `parasils_io`'s [`WriteError`]).
    #[error(transparent)]
    File(#[from] WriteError),
    /// The CSV writer failed.
    #[error("writing {}: {error}", path.display())]
    Csv {
        /// The target.
        path: PathBuf,
        /// The writer's error.
        error: csv::Error,
    },
    /// The MCAP writer failed.
    #[error("writing {}: {error}", path.display())]
    Mcap {
        /// The target.
        path: PathBuf,
        /// The writer's error.
        error: McapError,
    },
}

impl OutputError {
    /// The I/O error underneath, if any (to tell a missing folder from a
    /// full disk).
    pub fn io_error(&self) -> Option<&std::io::Error> {
        match self {
            OutputError::File(error) => error.io_error(),
            OutputError::Csv { error, .. } => match error.kind() {
                csv::ErrorKind::Io(e) => Some(e),
                _ => None,
            },
            OutputError::Mcap { error, .. } => error.io_error(),
            OutputError::UnknownFormat { .. } => None,
        }
    }

    /// The path the error is about: the target, or the folder it cannot be
    /// written in.
    pub fn path(&self) -> &Path {
        match self {
            OutputError::File(error) => error.path(),
            OutputError::UnknownFormat { path }
            | OutputError::Csv { path, .. }
            | OutputError::Mcap { path, .. } => path,
        }
    }
}

/// Bytes per CSV row in [`estimate_bytes`]. The paper's run writes 1214 bytes
/// per row on average and 1275 at most (74 columns of shortest round-trip
/// numbers, the nine port columns included); before those nine it was 1085
/// and 1147, before the eight camera columns 966 and 1025, and before the
/// four clearance columns 889 and 945 (969 at most at 20 kHz with the
/// `command` column). 1408 bounds them all with room to spare.
pub const CSV_BYTES_PER_ROW: u64 = 1408;

/// Bytes per MCAP sample in [`estimate_bytes`]. The paper's run writes 838
/// bytes per sample, compressed chunks and their index, the `/tf`,
/// `/scene` and camera messages included (761 before the shafts were drawn
/// as cylinders, 660 before the `/camera` channel and the camera's image
/// topics, 627 before the four clearance columns). 1024 bounds them with
/// room to spare.
pub const MCAP_BYTES_PER_SAMPLE: u64 = 1024;

/// Bytes of a file's fixed part in [`estimate_bytes`]: the CSV header
/// (1097 bytes), the MCAP header, schemas, scenario, summary and footer
/// (about 110 kB).
const FIXED_BYTES: u64 = 256 * 1024;

/// The estimated size, bytes, of an output file of `samples` records in
/// `format`: a fixed part and a bound per record measured on the paper's
/// run ([`CSV_BYTES_PER_ROW`], [`MCAP_BYTES_PER_SAMPLE`]). Meant to be at or
/// above the real size, not exact.
pub fn estimate_bytes(format: Format, samples: usize) -> u64 {
    let per = match format {
        Format::Csv => CSV_BYTES_PER_ROW,
        Format::Mcap => MCAP_BYTES_PER_SAMPLE,
    };
    (samples as u64)
        .saturating_mul(per)
        .saturating_add(FIXED_BYTES)
}

/// Checks, before anything is written, that an output file of `samples`
/// records in `format` fits: its estimate ([`estimate_bytes`]) within the
/// free space of the target's file system, and within [`parasils_io::file::cap_bytes`] unless
/// `force`. A target written directly (a FIFO, a device) is not checked.
/// Returns the estimate.
///
/// # Errors
/// [`OutputError::File`] when the target is a folder
/// ([`WriteError::IsFolder`]), does not fit ([`WriteError::NoSpace`]) or
/// is over the cap ([`WriteError::OverCap`]).
pub fn check_size(
    path: &Path,
    format: Format,
    samples: usize,
    force: bool,
) -> Result<u64, OutputError> {
    let estimate = estimate_bytes(format, samples);
    if written_directly(path)? {
        return Ok(estimate);
    }
    Ok(check_bytes(path, samples, estimate, force)?)
}

enum Writer {
    Csv(Box<CsvSink<BufWriter<File>>>),
    Mcap(Box<McapSink<BufWriter<File>>>),
}

/// A CSV or MCAP file that a simulation's records stream into, as
/// `parasils simulate -o FILE` writes it (the Python bindings'
/// `simulate(out=...)` too).
///
/// The records go to a temporary file beside the target, which
/// [`OutputFile::finish`] renames to it: a failed run (the file dropped
/// unfinished) leaves nothing behind, and the previous file at the target
/// is untouched. A FIFO or a device is written directly.
pub struct OutputFile {
    writer: Writer,
    file: AtomicFile,
    path: PathBuf,
}

impl core::fmt::Debug for OutputFile {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("OutputFile")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

/// An [`OutputFile`] written and flushed, still under its temporary name:
/// [`Flushed::persist`] renames it.
#[derive(Debug)]
pub struct Flushed {
    file: AtomicFile,
}

impl Flushed {
    /// Renames the file to its path; returns the path.
    ///
    /// # Errors
    /// [`OutputError::File`] ([`WriteError::Io`]) when the rename fails.
    pub fn persist(self) -> Result<PathBuf, OutputError> {
        Ok(self.file.persist()?)
    }
}

impl OutputFile {
    /// Starts writing `scenario`'s records to `path` in `format`: the CSV
    /// header (with `command` last when the scenario has commands), or the
    /// MCAP file's header, channels and scenario. The size is not checked
    /// here: see [`check_size`].
    ///
    /// # Errors
    /// [`OutputError::File`] when the target is a folder
    /// ([`WriteError::IsFolder`]) or its folder cannot be written in
    /// ([`WriteError::Create`]), and the
    /// writers' errors.
    pub fn create(path: &Path, format: Format, scenario: &Scenario) -> Result<Self, OutputError> {
        Self::create_with(
            path,
            format,
            scenario,
            crate::no_go::csv_columns_of(scenario),
        )
    }

    /// As [`OutputFile::create`], the CSV with `columns`; with a
    /// teleoperation run's ([`crate::teleop::CSV_WITH_TELEOP`]), the MCAP
    /// file has its `/teleop` channel ([`McapSink::teleop`]).
    ///
    /// # Errors
    /// As [`OutputFile::create`].
    pub fn create_with(
        path: &Path,
        format: Format,
        scenario: &Scenario,
        columns: &'static [crate::columns::Column],
    ) -> Result<Self, OutputError> {
        let (atomic, file) = AtomicFile::create(path)?;
        let file = BufWriter::new(file);
        let writer = match format {
            Format::Csv => Writer::Csv(Box::new(CsvSink::with_columns(file, columns).map_err(
                |error| OutputError::Csv {
                    path: path.to_owned(),
                    error,
                },
            )?)),
            Format::Mcap => {
                // A teleoperation run's columns put its inputs and states
                // on `/teleop`.
                let teleop = columns.len() == crate::teleop::CSV_WITH_TELEOP.len()
                    && columns
                        .iter()
                        .zip(&crate::teleop::CSV_WITH_TELEOP)
                        .all(|(a, b)| a.name == b.name);
                let sink = if teleop {
                    McapSink::teleop(file, scenario)
                } else {
                    McapSink::new(file, scenario)
                };
                Writer::Mcap(Box::new(sink.map_err(|error| OutputError::Mcap {
                    path: path.to_owned(),
                    error,
                })?))
            }
        };
        Ok(Self {
            writer,
            file: atomic,
            path: path.to_owned(),
        })
    }

    /// The file's final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the records go to a temporary file renamed at the end
    /// (`false` for a FIFO or a device, written directly).
    pub fn is_replaced(&self) -> bool {
        self.file.is_replaced()
    }

    /// Writes everything out and flushes it, under the temporary name.
    ///
    /// # Errors
    /// The writers' and the operating system's errors.
    pub fn flush(self) -> Result<Flushed, OutputError> {
        let path = self.path;
        let io = |error| {
            OutputError::File(WriteError::Io {
                path: path.clone(),
                error,
            })
        };
        match self.writer {
            Writer::Csv(w) => w.finish().map_err(io)?.flush().map_err(io)?,
            Writer::Mcap(w) => w
                .finish()
                .map_err(|error| OutputError::Mcap {
                    path: path.clone(),
                    error,
                })?
                .flush()
                .map_err(io)?,
        }
        Ok(Flushed { file: self.file })
    }

    /// Flushes the file and renames it to its path; returns the path.
    ///
    /// # Errors
    /// As [`OutputFile::flush`] and [`Flushed::persist`].
    pub fn finish(self) -> Result<PathBuf, OutputError> {
        self.flush()?.persist()
    }
}

impl Sink for OutputFile {
    type Error = OutputError;

    fn push(&mut self, record: &Record) -> Result<(), OutputError> {
        match &mut self.writer {
            Writer::Csv(w) => w.push(record).map_err(|error| OutputError::Csv {
                path: self.path.clone(),
                error,
            }),
            Writer::Mcap(w) => w.push(record).map_err(|error| OutputError::Mcap {
                path: self.path.clone(),
                error,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::Simulation;

    #[test]
    fn formats_from_extensions() {
        assert_eq!(
            Format::from_path(Path::new("a.CSV")).ok(),
            Some(Format::Csv)
        );
        assert_eq!(
            Format::from_path(Path::new("x/a.mcap")).ok(),
            Some(Format::Mcap)
        );
        let e = Format::from_path(Path::new("a.txt")).expect_err("unknown");
        assert!(
            e.to_string()
                .starts_with("cannot tell the output format of a.txt")
        );
    }

    #[test]
    fn written_on_success_and_nothing_left_on_failure() {
        let dir = tempfile::tempdir().expect("tempdir");
        let sim = Simulation::new(Scenario {
            rate_hz: 10.0,
            ..Scenario::paper()
        })
        .expect("valid");
        let path = dir.path().join("run.csv");
        let mut file = OutputFile::create(&path, Format::Csv, sim.scenario()).expect("create");
        sim.run(&mut file).expect("run");
        assert_eq!(file.finish().expect("finish"), path);
        let text = std::fs::read_to_string(&path).expect("written");
        assert_eq!(text.lines().count(), 47);

        let unfinished = dir.path().join("run.mcap");
        let file = OutputFile::create(&unfinished, Format::Mcap, sim.scenario()).expect("create");
        drop(file);
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("dir")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, ["run.csv"]);
    }

    #[test]
    fn size_estimates() {
        assert_eq!(estimate_bytes(Format::Csv, usize::MAX), u64::MAX);
        // The paper's run: at or above the real sizes (5,465,925 and
        // 3,773,644 bytes with the port columns and the shafts' cylinders),
        // within a third.
        let csv = estimate_bytes(Format::Csv, 4501);
        let mcap = estimate_bytes(Format::Mcap, 4501);
        assert!((5_465_925..7_287_900).contains(&csv), "{csv}");
        assert!((3_773_644..5_031_525).contains(&mcap), "{mcap}");
    }

    #[test]
    fn a_missing_folder_is_named_once() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("missing").join("run.csv");
        let e = OutputFile::create(&path, Format::Csv, &Scenario::paper()).expect_err("no folder");
        let text = e.to_string();
        assert!(text.starts_with("cannot write in "), "{text}");
        assert!(!text.contains(".part"), "{text}");
        assert_eq!(
            e.io_error().map(std::io::Error::kind),
            Some(std::io::ErrorKind::NotFound)
        );
    }
}
