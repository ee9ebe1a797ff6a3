//! Output files written atomically: the records go to a temporary file
//! beside the target, which is renamed to it only when everything is written,
//! so that a failed run leaves nothing behind, not even a truncated file.
//!
//! [`OutputFile`] is what `parasils simulate -o FILE` and the Python
//! bindings' `simulate(out=...)` write; [`temp_beside`] serves any other
//! file (the plot).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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

/// What can go wrong with an output file.
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
    /// The temporary file cannot be created in the target's folder.
    #[error("cannot write in {}: {error}", dir.display())]
    Create {
        /// The folder.
        dir: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// Writing failed.
    #[error("writing {}: {error}", path.display())]
    Io {
        /// The target.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
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
            OutputError::Create { error, .. } | OutputError::Io { error, .. } => Some(error),
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
            OutputError::UnknownFormat { path }
            | OutputError::Io { path, .. }
            | OutputError::Csv { path, .. }
            | OutputError::Mcap { path, .. } => path,
            OutputError::Create { dir, .. } => dir,
        }
    }
}

/// A temporary file in the folder of `path`, so that the final rename stays
/// on one file system; readable by others once renamed (not a temporary
/// file's 0600).
///
/// # Errors
/// [`OutputError::Create`] when the folder cannot be written in.
pub fn temp_beside(path: &Path) -> Result<tempfile::NamedTempFile, OutputError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".parasils-").suffix(".part");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    builder.tempfile_in(dir).map_err(|e| OutputError::Create {
        dir: dir.to_owned(),
        error: innermost(e),
    })
}

/// The operating system's error inside `e`, without what tempfile appends
/// to its message (` at path "..."`, the temporary file's name), its number
/// kept when the message shows it.
fn innermost(e: std::io::Error) -> std::io::Error {
    if e.raw_os_error().is_some() {
        return e;
    }
    let text = e.to_string();
    let text = text
        .rfind(" at path \"")
        .map_or(text.as_str(), |i| &text[..i]);
    let code = text
        .strip_suffix(')')
        .and_then(|t| t.rsplit_once("(os error "))
        .and_then(|(_, n)| n.parse::<i32>().ok());
    match code {
        Some(code) => std::io::Error::from_raw_os_error(code),
        None => std::io::Error::new(e.kind(), text.to_owned()),
    }
}

/// Renames the temporary file `tmp` to `path`.
///
/// # Errors
/// [`OutputError::Io`] when the rename fails.
pub fn persist(tmp: tempfile::NamedTempFile, path: &Path) -> Result<(), OutputError> {
    tmp.persist(path).map_err(|e| OutputError::Io {
        path: path.to_owned(),
        error: e.error,
    })?;
    Ok(())
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
/// unfinished) leaves nothing behind.
pub struct OutputFile {
    writer: Writer,
    tmp: tempfile::NamedTempFile,
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
    tmp: tempfile::NamedTempFile,
    path: PathBuf,
}

impl Flushed {
    /// Renames the file to its path; returns the path.
    ///
    /// # Errors
    /// [`OutputError::Io`] when the rename fails.
    pub fn persist(self) -> Result<PathBuf, OutputError> {
        persist(self.tmp, &self.path)?;
        Ok(self.path)
    }
}

impl OutputFile {
    /// Starts writing `scenario`'s records to `path` in `format`: the CSV
    /// header (with `command` last when the scenario has commands), or the
    /// MCAP file's header, channels and scenario.
    ///
    /// # Errors
    /// [`OutputError::Create`] when the folder cannot be written in, and the
    /// writers' errors.
    pub fn create(path: &Path, format: Format, scenario: &Scenario) -> Result<Self, OutputError> {
        let tmp = temp_beside(path)?;
        let io = |error| OutputError::Io {
            path: path.to_owned(),
            error,
        };
        let file = BufWriter::new(tmp.reopen().map_err(io)?);
        let writer = match format {
            Format::Csv => Writer::Csv(Box::new(CsvSink::for_scenario(file, scenario).map_err(
                |error| OutputError::Csv {
                    path: path.to_owned(),
                    error,
                },
            )?)),
            Format::Mcap => Writer::Mcap(Box::new(McapSink::new(file, scenario).map_err(
                |error| OutputError::Mcap {
                    path: path.to_owned(),
                    error,
                },
            )?)),
        };
        Ok(Self {
            writer,
            tmp,
            path: path.to_owned(),
        })
    }

    /// The file's final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes everything out and flushes it, under the temporary name.
    ///
    /// # Errors
    /// The writers' and the operating system's errors.
    pub fn flush(self) -> Result<Flushed, OutputError> {
        let path = self.path;
        let io = |error| OutputError::Io {
            path: path.clone(),
            error,
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
        Ok(Flushed {
            tmp: self.tmp,
            path,
        })
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
