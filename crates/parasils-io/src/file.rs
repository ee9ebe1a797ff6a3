//! Files written atomically: the content goes to a temporary file beside
//! the target, which is renamed to it only when everything is written, so
//! that a failed write leaves nothing behind, not even a truncated file, and
//! the previous file at the target stays as it was until the rename.
//!
//! [`AtomicFile`] is the whole mechanism (a FIFO or a device written
//! directly); [`temp_beside`] and [`persist`] are its two halves for writers
//! that want a path (a picture's renderer).
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
//! Before anything is written, [`check_bytes`] compares a writer's estimate
//! of its file's size with the free space of the target's file system and
//! with a cap ([`DEFAULT_CAP_BYTES`]) that only `force` lifts.

use std::fs::File;
use std::path::{Path, PathBuf};

/// What can go wrong with a file written atomically.
///
/// Each message is complete on its own (the file, and the operating
/// system's words): the underlying errors are in the text, not chained as
/// `source()`, so that a report of the chain does not repeat them.
/// [`WriteError::io_error`] gives the I/O error underneath, if any.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum WriteError {
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
        /// The estimated size, bytes.
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
        /// The estimated size, bytes.
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
}

impl WriteError {
    /// The I/O error underneath, if any (to tell a missing folder from a
    /// full disk).
    pub fn io_error(&self) -> Option<&std::io::Error> {
        match self {
            WriteError::Create { error, .. } | WriteError::Io { error, .. } => Some(error),
            WriteError::IsFolder { .. }
            | WriteError::NoSpace { .. }
            | WriteError::OverCap { .. } => None,
        }
    }

    /// The path the error is about: the target, or the folder it cannot be
    /// written in.
    pub fn path(&self) -> &Path {
        match self {
            WriteError::IsFolder { path }
            | WriteError::NoSpace { path, .. }
            | WriteError::OverCap { path, .. }
            | WriteError::Io { path, .. } => path,
            WriteError::Create { dir, .. } => dir,
        }
    }
}

/// The largest output file written without `force`: 10 GB.
pub const DEFAULT_CAP_BYTES: u64 = 10_000_000_000;

/// The environment variable that replaces [`DEFAULT_CAP_BYTES`] (a number
/// of bytes), for tests of the cap without writing 10 GB.
pub const CAP_ENV: &str = "PARASILS_OUTPUT_CAP_BYTES";

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

/// Checks, before anything is written, that a file of `estimate` bytes
/// (`samples` rows or samples) written beside `path` fits: within the free
/// space of its file system, and within [`cap_bytes`] unless `force`.
/// Returns the estimate. Each writer estimates its own file's size, at or
/// above the real one.
///
/// # Errors
/// [`WriteError::NoSpace`] and [`WriteError::OverCap`].
pub fn check_bytes(
    path: &Path,
    samples: usize,
    estimate: u64,
    force: bool,
) -> Result<u64, WriteError> {
    if let Some(free) = free_bytes(folder(path))
        && estimate > free
    {
        return Err(WriteError::NoSpace {
            path: path.to_owned(),
            samples,
            estimate,
            free,
        });
    }
    let cap = cap_bytes();
    if !force && estimate > cap {
        return Err(WriteError::OverCap {
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

/// Whether `path` is written directly (`true`: it exists and is a FIFO or
/// a device) or through a temporary file renamed over it (`false`: it does
/// not exist, or is a regular file, or a link to one). A writer checks the
/// size of the second kind only.
///
/// # Errors
/// [`WriteError::IsFolder`] when the target is a folder.
pub fn written_directly(path: &Path) -> Result<bool, WriteError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(WriteError::IsFolder {
            path: path.to_owned(),
        }),
        Ok(m) => Ok(!m.is_file()),
        Err(_) => Ok(false),
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
/// [`WriteError::Create`] when the folder cannot be written in.
pub fn temp_beside(path: &Path) -> Result<tempfile::NamedTempFile, WriteError> {
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
    builder.tempfile_in(dir).map_err(|e| WriteError::Create {
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
/// [`WriteError::Io`] when the rename fails.
pub fn persist(tmp: tempfile::NamedTempFile, path: &Path) -> Result<(), WriteError> {
    tmp.persist(path).map_err(|e| WriteError::Io {
        path: path.to_owned(),
        error: e.error,
    })?;
    Ok(())
}

/// A file being written atomically: the content goes to a temporary file
/// beside the target, which [`AtomicFile::persist`] renames to it. Dropped
/// without `persist`, it leaves nothing behind, and the previous file at the
/// target is untouched. A FIFO or a device is written directly.
#[derive(Debug)]
pub struct AtomicFile {
    /// `None` for a target written directly.
    tmp: Option<tempfile::NamedTempFile>,
    path: PathBuf,
}

impl AtomicFile {
    /// Starts writing `path`: returns the pending file and the handle to
    /// write the content to.
    ///
    /// # Errors
    /// [`WriteError::IsFolder`] when the target is a folder,
    /// [`WriteError::Create`] when the folder cannot be written in,
    /// [`WriteError::Io`] when the file cannot be opened.
    pub fn create(path: &Path) -> Result<(Self, File), WriteError> {
        let io = |error| WriteError::Io {
            path: path.to_owned(),
            error,
        };
        let (tmp, file) = if written_directly(path)? {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(io)?;
            (None, file)
        } else {
            let tmp = temp_beside(path)?;
            let file = tmp.reopen().map_err(io)?;
            (Some(tmp), file)
        };
        Ok((
            Self {
                tmp,
                path: path.to_owned(),
            },
            file,
        ))
    }

    /// The file's final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the content goes to a temporary file renamed at the end
    /// (`false` for a FIFO or a device, written directly).
    pub fn is_replaced(&self) -> bool {
        self.tmp.is_some()
    }

    /// Renames the temporary file to the target (the caller has written
    /// and flushed everything); returns the path.
    ///
    /// # Errors
    /// [`WriteError::Io`] when the rename fails.
    pub fn persist(self) -> Result<PathBuf, WriteError> {
        if let Some(tmp) = self.tmp {
            persist(tmp, &self.path)?;
        }
        Ok(self.path)
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn written_on_persist_and_nothing_left_when_dropped() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run.csv");
        std::fs::write(&path, "old").expect("old file");
        let (file, mut handle) = AtomicFile::create(&path).expect("create");
        assert!(file.is_replaced());
        handle.write_all(b"new").expect("write");
        // Until the rename, the old file is what the target holds.
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "old");
        assert_eq!(names(dir.path()).len(), 2);
        assert_eq!(file.persist().expect("persist"), path);
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "new");

        let (file, mut handle) = AtomicFile::create(&dir.path().join("b.csv")).expect("create");
        handle.write_all(b"unfinished").expect("write");
        drop(file);
        assert_eq!(names(dir.path()), ["run.csv"]);
    }

    #[test]
    fn folders_are_refused_and_devices_written_directly() {
        let dir = tempfile::tempdir().expect("tempdir");
        let e = AtomicFile::create(dir.path()).expect_err("a folder");
        assert!(matches!(e, WriteError::IsFolder { .. }), "{e}");
        assert!(e.to_string().ends_with("is a folder: give a file name"));
        assert!(!written_directly(&dir.path().join("new.csv")).expect("absent"));
        #[cfg(unix)]
        {
            let null = Path::new("/dev/null");
            assert!(written_directly(null).expect("a device"));
            let (file, _) = AtomicFile::create(null).expect("open");
            assert!(!file.is_replaced());
            assert_eq!(file.persist().expect("nothing to rename"), null);
        }
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
    fn stale_files_of_dead_processes_only_are_removed() {
        let dir = tempfile::tempdir().expect("tempdir");
        // Process ids above the kernel's largest (4194304 on Linux) belong
        // to no process.
        let dead = ".run.csv.parasils-999999999-aB3dE9.part";
        let own = format!(".run.csv.parasils-{}-aB3dE9.part", std::process::id());
        for name in [dead, own.as_str(), "run.csv", ".run.csv.parasils-1-x.part"] {
            std::fs::write(dir.path().join(name), "x").expect("write");
        }
        let removed = remove_stale(dir.path());
        assert_eq!(removed, [dir.path().join(dead)]);
        assert_eq!(names(dir.path()).len(), 3);
    }

    #[test]
    fn sizes_for_people_and_the_cap() {
        let shown =
            [0, 999, 1000, 309_248, 999_949, 999_950, 10_000_000_000].map(|b| Bytes(b).to_string());
        assert_eq!(
            shown,
            [
                "0 B", "999 B", "1.0 kB", "309.2 kB", "999.9 kB", "1.0 MB", "10.0 GB"
            ]
        );
        assert_eq!(Bytes(u64::MAX).to_string(), "18.4 EB");
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("big.csv");
        assert_eq!(check_bytes(&path, 10, 1000, false).ok(), Some(1000));
        // More than any disk has free: no space, whatever `force` says.
        if free_bytes(dir.path()).is_some() {
            let e = check_bytes(&path, 7, u64::MAX, true).expect_err("no space");
            assert!(matches!(e, WriteError::NoSpace { samples: 7, .. }), "{e}");
        }
    }

    #[test]
    fn a_missing_folder_is_named_once() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("missing").join("run.csv");
        let e = AtomicFile::create(&path).expect_err("no folder");
        let text = e.to_string();
        assert!(text.starts_with("cannot write in "), "{text}");
        assert!(!text.contains(".part"), "{text}");
        assert_eq!(e.path(), dir.path().join("missing"));
        assert_eq!(
            e.io_error().map(std::io::Error::kind),
            Some(std::io::ErrorKind::NotFound)
        );
    }
}
