//! Output files written atomically: the records go to a temporary file
//! beside the target, which is renamed to it only when everything is written,
//! so that a failed run leaves nothing behind, not even a truncated file, and
//! the previous file at the target stays as it was until the rename.
//!
//! [`OutputFile`] is what `parasils simulate -o FILE` and the Python
//! bindings' `simulate(out=...)` write; [`temp_beside`] serves any other
//! file (the plot).
//!
//! The temporary file is named `.NAME.parasils-PID-XXXXXX.part` (the
//! target's name, the writer's process id, six random characters). A run
//! killed outright (SIGKILL, power loss) cannot remove its own: the next
//! temporary file created in the same folder removes every file of that
//! pattern whose process no longer exists ([`remove_stale`]), and no other
//! file.
//!
//! A target that exists and is neither a regular file nor a folder (a FIFO,
//! a device such as `/dev/null`) is written directly, as standard output
//! is: it is not replaced. A target that is a folder is refused.
//!
//! Before anything is written, [`check_size`] compares the file's estimated
//! size ([`estimate_bytes`]) with the free space of the target's file system
//! and with a cap ([`DEFAULT_CAP_BYTES`]) that only `force` lifts.

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
    /// The target is a folder.
    #[error("{} is a folder: give a file name", path.display())]
    IsFolder {
        /// The target.
        path: PathBuf,
    },
    /// The file would not fit in the free space of its file system.
    #[error(
        "{} would take about {} ({samples} samples), more than the {} free on its file system",
        path.display(), Bytes(*estimate), Bytes(*free)
    )]
    NoSpace {
        /// The target.
        path: PathBuf,
        /// The number of samples.
        samples: usize,
        /// The estimated size, bytes ([`estimate_bytes`]).
        estimate: u64,
        /// The free space, bytes.
        free: u64,
    },
    /// The file would be larger than the cap, and `force` was not given.
    #[error(
        "{} would take about {} ({samples} samples), more than the {} cap",
        path.display(), Bytes(*estimate), Bytes(*cap)
    )]
    OverCap {
        /// The target.
        path: PathBuf,
        /// The number of samples.
        samples: usize,
        /// The estimated size, bytes ([`estimate_bytes`]).
        estimate: u64,
        /// The cap, bytes ([`cap_bytes`]).
        cap: u64,
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
            OutputError::UnknownFormat { .. }
            | OutputError::IsFolder { .. }
            | OutputError::NoSpace { .. }
            | OutputError::OverCap { .. } => None,
        }
    }

    /// The path the error is about: the target, or the folder it cannot be
    /// written in.
    pub fn path(&self) -> &Path {
        match self {
            OutputError::UnknownFormat { path }
            | OutputError::IsFolder { path }
            | OutputError::NoSpace { path, .. }
            | OutputError::OverCap { path, .. }
            | OutputError::Io { path, .. }
            | OutputError::Csv { path, .. }
            | OutputError::Mcap { path, .. } => path,
            OutputError::Create { dir, .. } => dir,
        }
    }
}

/// The largest output file written without `force`: 10 GB.
pub const DEFAULT_CAP_BYTES: u64 = 10_000_000_000;

/// The environment variable that replaces [`DEFAULT_CAP_BYTES`] (a number
/// of bytes), for tests of the cap without writing 10 GB.
pub const CAP_ENV: &str = "PARASILS_OUTPUT_CAP_BYTES";

/// Bytes per CSV row in [`estimate_bytes`]. The paper's run writes 889 bytes
/// per row on average and 945 at most (53 columns of shortest round-trip
/// numbers); at 20 kHz, and with the `command` column, the longest row is
/// 969 bytes. 1024 bounds them all with room to spare.
pub const CSV_BYTES_PER_ROW: u64 = 1024;

/// Bytes per MCAP sample in [`estimate_bytes`]. The paper's run writes 627
/// bytes per sample (compressed chunks and their index, the `/tf` and
/// `/scene` messages included); 553 at 20 kHz, 648 with commands. 768
/// bounds them with room to spare.
pub const MCAP_BYTES_PER_SAMPLE: u64 = 768;

/// Bytes of a file's fixed part in [`estimate_bytes`]: the CSV header
/// (728 bytes), the MCAP header, schemas, scenario, summary and footer
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

/// The cap on an output file's size without `force`: [`CAP_ENV`] if set
/// to a number of bytes, else [`DEFAULT_CAP_BYTES`].
pub fn cap_bytes() -> u64 {
    std::env::var(CAP_ENV)
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(DEFAULT_CAP_BYTES)
}

/// The free space, bytes, available to this process on the file system of
/// `dir` (`statvfs`: the blocks available to unprivileged users); `None`
/// when it cannot be told.
pub fn free_bytes(dir: &Path) -> Option<u64> {
    #[cfg(unix)]
    {
        let st = rustix::fs::statvfs(dir).ok()?;
        // A file system without blocks (`/proc`, `/sys`) tells nothing.
        (st.f_blocks > 0).then(|| st.f_bavail.saturating_mul(st.f_frsize))
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        None
    }
}

/// Checks, before anything is written, that an output file of `samples`
/// records in `format` fits: its estimate ([`estimate_bytes`]) within the
/// free space of the target's file system, and within [`cap_bytes`] unless
/// `force`. A target written directly (a FIFO, a device) is not checked.
/// Returns the estimate.
///
/// # Errors
/// [`OutputError::IsFolder`] when the target is a folder,
/// [`OutputError::NoSpace`] and [`OutputError::OverCap`].
pub fn check_size(
    path: &Path,
    format: Format,
    samples: usize,
    force: bool,
) -> Result<u64, OutputError> {
    let estimate = estimate_bytes(format, samples);
    match Target::of(path)? {
        Target::Direct => Ok(estimate),
        Target::Replace => check_bytes(path, samples, estimate, force),
    }
}

/// Checks that a file of `estimate` bytes (`samples` rows) written beside
/// `path` fits: within the free space of its file system, and within
/// [`cap_bytes`] unless `force`. Returns the estimate. The mechanism of
/// [`check_size`], for outputs estimated by their own writers.
///
/// # Errors
/// [`OutputError::NoSpace`] and [`OutputError::OverCap`].
pub fn check_bytes(
    path: &Path,
    samples: usize,
    estimate: u64,
    force: bool,
) -> Result<u64, OutputError> {
    if let Some(free) = free_bytes(folder(path))
        && estimate > free
    {
        return Err(OutputError::NoSpace {
            path: path.to_owned(),
            samples,
            estimate,
            free,
        });
    }
    let cap = cap_bytes();
    if !force && estimate > cap {
        return Err(OutputError::OverCap {
            path: path.to_owned(),
            samples,
            estimate,
            cap,
        });
    }
    Ok(estimate)
}

/// A number of bytes for people: `4.5 TB`, `10.0 GB`, `512 B` (decimal
/// units, one decimal).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bytes(pub u64);

impl core::fmt::Display for Bytes {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        const UNITS: [&str; 6] = ["kB", "MB", "GB", "TB", "PB", "EB"];
        if self.0 < 1000 {
            return write!(f, "{} B", self.0);
        }
        #[allow(clippy::cast_precision_loss)]
        let mut value = self.0 as f64 / 1000.0;
        let mut unit = 0;
        while value >= 999.95 && unit + 1 < UNITS.len() {
            value /= 1000.0;
            unit += 1;
        }
        write!(f, "{value:.1} {}", UNITS[unit])
    }
}

/// How a target is written.
enum Target {
    /// Through a temporary file renamed over it (it does not exist, or is a
    /// regular file, or a link to one).
    Replace,
    /// Directly: a FIFO or a device.
    Direct,
}

impl Target {
    fn of(path: &Path) -> Result<Self, OutputError> {
        match std::fs::metadata(path) {
            Ok(m) if m.is_dir() => Err(OutputError::IsFolder {
                path: path.to_owned(),
            }),
            Ok(m) if !m.is_file() => Ok(Target::Direct),
            _ => Ok(Target::Replace),
        }
    }
}

/// The folder of `path` (`.` for a bare name).
fn folder(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// The part of a temporary file's name between the target's name and the
/// process id.
const TEMP_MARK: &str = ".parasils-";
/// The end of a temporary file's name.
const TEMP_SUFFIX: &str = ".part";
/// The number of random characters in a temporary file's name.
const TEMP_RANDOM: usize = 6;

/// The process id in `name` if it is the name of one of our temporary files
/// (`.NAME.parasils-PID-XXXXXX.part`), else `None`.
fn temp_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(TEMP_SUFFIX)?;
    let (_, tail) = rest.rsplit_once(TEMP_MARK)?;
    let (pid, random) = tail.split_once('-')?;
    let valid = !pid.is_empty()
        && pid.bytes().all(|b| b.is_ascii_digit())
        && random.len() == TEMP_RANDOM
        && random.bytes().all(|b| b.is_ascii_alphanumeric());
    if valid { pid.parse().ok() } else { None }
}

/// Whether process `pid` exists (`kill(pid, 0)`: a process of another user
/// counts); `true` when it cannot be told.
fn alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Some(pid) = i32::try_from(pid)
            .ok()
            .and_then(rustix::process::Pid::from_raw)
        else {
            return true;
        };
        !matches!(
            rustix::process::test_kill_process(pid),
            Err(rustix::io::Errno::SRCH)
        )
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// Removes the temporary files that runs killed outright left in `dir`:
/// regular files named `.NAME.parasils-PID-XXXXXX.part` whose process no
/// longer exists. Any other file, and those of running processes, are
/// left alone; errors are ignored (another run may remove the same file).
/// Returns the files removed.
pub fn remove_stale(dir: &Path) -> Vec<PathBuf> {
    let mut removed = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return removed;
    };
    let own = std::process::id();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(temp_pid) else {
            continue;
        };
        // Not following links: only the regular file itself is removed.
        let regular = entry.file_type().is_ok_and(|t| t.is_file());
        if regular && pid != own && !alive(pid) {
            let path = entry.path();
            if std::fs::remove_file(&path).is_ok() {
                removed.push(path);
            }
        }
    }
    removed
}

/// A temporary file in the folder of `path`, so that the final rename stays
/// on one file system; readable by others once renamed (not a temporary
/// file's 0600). Named `.NAME.parasils-PID-XXXXXX.part`; the stale ones of
/// dead processes in that folder are removed first ([`remove_stale`]).
///
/// # Errors
/// [`OutputError::Create`] when the folder cannot be written in.
pub fn temp_beside(path: &Path) -> Result<tempfile::NamedTempFile, OutputError> {
    let dir = folder(path);
    remove_stale(dir);
    // The target's name, shortened to keep the whole name within the
    // 255 bytes most file systems allow.
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut end = name.len().min(200);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    let prefix = format!(".{}{TEMP_MARK}{}-", &name[..end], std::process::id());
    let mut builder = tempfile::Builder::new();
    builder
        .prefix(&prefix)
        .suffix(TEMP_SUFFIX)
        .rand_bytes(TEMP_RANDOM);
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
/// unfinished) leaves nothing behind, and the previous file at the target
/// is untouched. A FIFO or a device is written directly.
pub struct OutputFile {
    writer: Writer,
    /// `None` for a target written directly.
    tmp: Option<tempfile::NamedTempFile>,
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
    tmp: Option<tempfile::NamedTempFile>,
    path: PathBuf,
}

impl Flushed {
    /// Renames the file to its path; returns the path.
    ///
    /// # Errors
    /// [`OutputError::Io`] when the rename fails.
    pub fn persist(self) -> Result<PathBuf, OutputError> {
        if let Some(tmp) = self.tmp {
            persist(tmp, &self.path)?;
        }
        Ok(self.path)
    }
}

impl OutputFile {
    /// Starts writing `scenario`'s records to `path` in `format`: the CSV
    /// header (with `command` last when the scenario has commands), or the
    /// MCAP file's header, channels and scenario. The size is not checked
    /// here: see [`check_size`].
    ///
    /// # Errors
    /// [`OutputError::IsFolder`] when the target is a folder,
    /// [`OutputError::Create`] when the folder cannot be written in, and the
    /// writers' errors.
    pub fn create(path: &Path, format: Format, scenario: &Scenario) -> Result<Self, OutputError> {
        let io = |error| OutputError::Io {
            path: path.to_owned(),
            error,
        };
        let (tmp, file) = match Target::of(path)? {
            Target::Replace => {
                let tmp = temp_beside(path)?;
                let file = tmp.reopen().map_err(io)?;
                (Some(tmp), file)
            }
            Target::Direct => (
                None,
                std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(io)?,
            ),
        };
        let file = BufWriter::new(file);
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

    /// Whether the records go to a temporary file renamed at the end
    /// (`false` for a FIFO or a device, written directly).
    pub fn is_replaced(&self) -> bool {
        self.tmp.is_some()
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
    fn temporary_files_are_recognised_by_name() {
        assert_eq!(temp_pid(".run.csv.parasils-4242-aB3dE9.part"), Some(4242));
        assert_eq!(temp_pid(".a.parasils-b.parasils-7-000000.part"), Some(7));
        for name in [
            ".parasils-aB3dE9.part",
            "run.csv.parasils-4242-aB3dE9.part",
            ".run.csv.parasils-4242-aB3dE9.tmp",
            ".run.csv.parasils--aB3dE9.part",
            ".run.csv.parasils-42x-aB3dE9.part",
            ".run.csv.parasils-4242-aB3dE.part",
            ".run.csv.parasils-4242-aB3dE9x.part",
            ".run.csv.parasils-4242-aB3d.9.part",
        ] {
            assert_eq!(temp_pid(name), None, "{name}");
        }
        let dir = tempfile::tempdir().expect("tempdir");
        let tmp = temp_beside(&dir.path().join("run.csv")).expect("temp");
        let name = tmp.path().file_name().and_then(|n| n.to_str());
        assert_eq!(name.and_then(temp_pid), Some(std::process::id()));
    }

    #[test]
    fn sizes_for_people() {
        let shown =
            [0, 999, 1000, 309_248, 999_949, 999_950, 10_000_000_000].map(|b| Bytes(b).to_string());
        assert_eq!(
            shown,
            [
                "0 B", "999 B", "1.0 kB", "309.2 kB", "999.9 kB", "1.0 MB", "10.0 GB"
            ]
        );
        assert_eq!(Bytes(u64::MAX).to_string(), "18.4 EB");
        assert_eq!(estimate_bytes(Format::Csv, usize::MAX), u64::MAX);
        // The paper's run: at or above the real sizes (4,003,152 and
        // 2,821,946 bytes), within a third.
        let csv = estimate_bytes(Format::Csv, 4501);
        let mcap = estimate_bytes(Format::Mcap, 4501);
        assert!((4_003_152..5_300_000).contains(&csv), "{csv}");
        assert!((2_821_946..3_750_000).contains(&mcap), "{mcap}");
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
