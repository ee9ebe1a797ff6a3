//! `parasils simulate -o FILE` under faults: a signal during the write, a
//! file-size limit, a folder it cannot write in, a target that is a folder or
//! a FIFO, two runs on one target, the size guard, and the temporary files
//! that killed runs leave. In every case: the message, the exit status, no
//! temporary file left, the previous file byte-identical.

mod common;

use core::time::Duration;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use common::files::names;
use common::process::{Parasils, parasils};

/// How long any one child may run.
const LIMIT: Duration = Duration::from_secs(20);
const PREVIOUS: &[u8] = b"the previous run's file\n";

/// `parasils simulate ARGS` in `dir`, killed past [`LIMIT`].
fn simulate(dir: &Path, args: &[&str]) -> Parasils {
    parasils(&["simulate"]).args(args).dir(dir).limit(LIMIT)
}

/// The temporary files in `dir`.
fn parts(dir: &Path) -> Vec<String> {
    names(dir)
        .into_iter()
        .filter(|n| n.ends_with(".part"))
        .collect()
}

/// The paper's scenario at 10 Hz written to `name` in a fresh folder.
fn reference(name: &str) -> Vec<u8> {
    let dir = tempfile::tempdir().expect("tempdir");
    simulate(dir.path(), &["--rate", "10", "-o", name])
        .run()
        .ok();
    std::fs::read(dir.path().join(name)).expect("written")
}

fn interrupted_by(signal: &str, code: i32) {
    let dir = tempfile::tempdir().expect("tempdir");
    let target = dir.path().join("run.csv");
    std::fs::write(&target, PREVIOUS).expect("previous");
    let child = simulate(dir.path(), &["--rate", "1e6", "-o", "run.csv"]).spawn();
    let start = Instant::now();
    while parts(dir.path()).is_empty() {
        assert!(start.elapsed() < LIMIT, "no temporary file appeared");
        std::thread::sleep(Duration::from_millis(5));
    }
    let part = parts(dir.path()).remove(0);
    let expected = format!(".run.csv.parasils-{}-", child.id());
    assert!(part.starts_with(&expected), "{part}");
    child.signal(signal);
    let text = child.finish().error_line_with(code);
    assert!(
        text.starts_with("parasils: interrupted: removed the partial run.csv"),
        "{text}"
    );
    assert_eq!(names(dir.path()), ["run.csv"]);
    assert_eq!(std::fs::read(&target).expect("target"), PREVIOUS);
}

#[test]
fn sigint_removes_the_partial_file_and_exits_130() {
    interrupted_by("-INT", 130);
}

#[test]
fn sigterm_removes_the_partial_file_and_exits_143() {
    interrupted_by("-TERM", 143);
}

/// The id of a process that has ended.
fn dead_pid() -> u32 {
    let mut child = Command::new("true").spawn().expect("true runs");
    let pid = child.id();
    child.wait().expect("wait");
    pid
}

#[test]
fn stale_temporary_files_of_dead_processes_only_are_removed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let dead = format!(".run.csv.parasils-{}-Ab3xYz.part", dead_pid());
    let live = format!(".run.csv.parasils-{}-Ab3xYz.part", std::process::id());
    let other_target = format!(".plot.svg.parasils-{}-q1W2e3.part", dead_pid());
    // Not of the pattern: kept whatever their process.
    let foreign = [
        ".parasils-Ab3xYz.part",
        "notes.part",
        ".run.csv.parasils-x1-Ab3xYz.part",
        ".run.csv.parasils-1-short.part",
    ];
    for name in [dead.as_str(), live.as_str(), other_target.as_str()]
        .into_iter()
        .chain(foreign)
    {
        std::fs::write(dir.path().join(name), b"x").expect("write");
    }
    // A link named as a stale file is not followed: the link itself is
    // left alone, and so is what it points to.
    let linked = dir.path().join("kept.csv");
    std::fs::write(&linked, b"kept").expect("write");
    let link = format!(".kept.csv.parasils-{}-Lk0000.part", dead_pid());
    std::os::unix::fs::symlink(&linked, dir.path().join(&link)).expect("symlink");

    simulate(dir.path(), &["--rate", "10", "-o", "run.csv"])
        .run()
        .ok();
    let mut expected: Vec<String> = foreign.iter().map(|s| s.to_string()).collect();
    expected.extend([live, link, "kept.csv".into(), "run.csv".into()]);
    expected.sort();
    assert_eq!(names(dir.path()), expected);
    assert_eq!(std::fs::read(&linked).expect("kept"), b"kept");
}

#[test]
fn a_file_size_limit_ends_with_a_clear_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let target = dir.path().join("run.csv");
    std::fs::write(&target, PREVIOUS).expect("previous");
    // 64 blocks of 512 bytes: the header fits, the paper's 4 MB do not. The
    // kernel sends SIGXFSZ, which must not kill the process.
    let text = simulate(dir.path(), &["-o", "run.csv"])
        .after_shell("ulimit -f 64")
        .run()
        .error_line_with(1);
    assert!(
        text.starts_with("parasils: error: writing run.csv: File too large"),
        "{text}"
    );
    assert_eq!(names(dir.path()), ["run.csv"]);
    assert_eq!(std::fs::read(&target).expect("target"), PREVIOUS);
}

/// A folder this process cannot create files in: one it made read-only,
/// or, when that does not stop it (root ignores permissions), `/sys`,
/// whose file system lets no one create files.
fn read_only_folder(scratch: &Path) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch.join("read-only");
    std::fs::create_dir(&dir).expect("mkdir");
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o555)).expect("chmod");
    if std::fs::write(dir.join("probe"), b"").is_ok() {
        PathBuf::from("/sys")
    } else {
        dir
    }
}

#[test]
fn a_read_only_folder_is_a_clear_error() {
    let scratch = tempfile::tempdir().expect("tempdir");
    let dir = read_only_folder(scratch.path());
    let target = dir.join("run.csv");
    let text = simulate(scratch.path(), &["--rate", "10", "-o"])
        .arg(&target)
        .run()
        .error_line_with(1);
    let expected = format!("parasils: error: cannot write in {}: ", dir.display());
    assert!(text.starts_with(&expected), "{text}");
    assert!(text.contains("(os error 13)"), "{text}");
    assert!(!target.exists());
}

#[test]
fn a_target_that_is_a_folder_is_a_clear_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("run.csv")).expect("mkdir");
    for args in [&["-o", "run.csv"][..], &["--format", "mcap", "-o", "."]] {
        let text = simulate(dir.path(), &["--rate", "10"])
            .args(args)
            .run()
            .error_line_with(1);
        assert!(text.ends_with("is a folder: give a file name\n"), "{text}");
    }
    let text = simulate(dir.path(), &["--rate", "10", "--plot", "run.csv"])
        .run()
        .error_line_with(1);
    assert!(text.contains("is a folder"), "{text}");
    assert_eq!(names(dir.path()), ["run.csv"]);
}

#[test]
fn a_fifo_is_written_directly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let fifo = dir.path().join("run.csv");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).expect("read the FIFO"))
    };
    let child = simulate(dir.path(), &["--rate", "10", "-o", "run.csv"]).spawn();
    let out = child.finish();
    if !reader.is_finished() {
        // Unblock a reader that no writer opened.
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
    }
    let read = reader.join().expect("reader");
    out.ok();
    assert_eq!(read, reference("run.csv"));
    assert_eq!(names(dir.path()), ["run.csv"]);
    let kind = std::fs::symlink_metadata(&fifo).expect("fifo").file_type();
    assert!(std::os::unix::fs::FileTypeExt::is_fifo(&kind));
}

#[test]
fn two_runs_on_one_target_leave_one_complete_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let single = {
        simulate(dir.path(), &["--rate", "2000", "-o", "one.mcap"])
            .run()
            .ok();
        std::fs::read(dir.path().join("one.mcap")).expect("written")
    };
    let children: Vec<_> = (0..2)
        .map(|_| simulate(dir.path(), &["--rate", "2000", "-o", "run.mcap"]).spawn())
        .collect();
    for child in children {
        child.finish().ok();
    }
    assert_eq!(
        std::fs::read(dir.path().join("run.mcap")).expect("written"),
        single
    );
    assert_eq!(names(dir.path()), ["one.mcap", "run.mcap"]);
}

#[test]
fn an_output_larger_than_the_free_space_is_refused_at_once() {
    let dir = tempfile::tempdir().expect("tempdir");
    let start = Instant::now();
    for args in [&["-o", "run.csv"][..], &["-o", "run.mcap", "--force"]] {
        let text = simulate(dir.path(), &["--rate", "1e12"])
            .args(args)
            .run()
            .error_line_with(1);
        assert!(text.contains("would take about "), "{text}");
        assert!(text.contains(" PB (4500000000001 samples)"), "{text}");
        assert!(text.contains(" free on its file system"), "{text}");
    }
    assert!(start.elapsed() < Duration::from_secs(5));
    assert!(names(dir.path()).is_empty());
}

#[test]
fn an_output_above_the_cap_needs_force() {
    let dir = tempfile::tempdir().expect("tempdir");
    let target = dir.path().join("run.csv");
    std::fs::write(&target, PREVIOUS).expect("previous");
    let text = simulate(dir.path(), &["--rate", "10", "-o", "run.csv"])
        .env("PARASILS_OUTPUT_CAP_BYTES", "100000")
        .run()
        .error_line_with(1);
    assert_eq!(
        text,
        "parasils: error: run.csv would take about 326.9 kB (46 samples), \
         more than the 100.0 kB cap: give --force to write it anyway\n"
    );
    assert_eq!(std::fs::read(&target).expect("target"), PREVIOUS);

    simulate(dir.path(), &["--rate", "10", "-o", "run.csv", "--force"])
        .env("PARASILS_OUTPUT_CAP_BYTES", "100000")
        .run()
        .ok();
    assert_eq!(
        std::fs::read(&target).expect("target"),
        reference("run.csv")
    );
    assert_eq!(names(dir.path()), ["run.csv"]);
}

/// A small tmpfs mounted on a fresh folder, unmounted when dropped; `None`
/// (with the reason) when this process cannot mount one (not root, no
/// `CAP_SYS_ADMIN`, a container without tmpfs).
struct SmallDisk {
    dir: tempfile::TempDir,
}

impl SmallDisk {
    fn mount(bytes: u64) -> Result<Self, String> {
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let out = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={bytes}"), "tmpfs"])
            .arg(dir.path())
            .output()
            .map_err(|e| format!("mount: {e}"))?;
        if out.status.success() {
            Ok(Self { dir })
        } else {
            Err(format!(
                "mount: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ))
        }
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

/// Writes zeros to `path` until the file system is full.
fn fill(path: &Path) {
    use std::io::Write;
    let mut f = std::fs::File::create(path).expect("filler");
    let block = vec![0u8; 1 << 16];
    // `write_all` writes what fits of the last block, then meets ENOSPC.
    loop {
        match f.write_all(&block) {
            Ok(()) => {}
            Err(e) if e.raw_os_error() == Some(28) => return,
            Err(e) => panic!("filling the disk: {e}"),
        }
    }
}

#[test]
fn a_full_disk_ends_with_a_clear_error() {
    // 64 MB: the run's estimate (58 MB for 45001 rows) fits, so the size
    // guard lets it start; once its temporary file exists the test fills
    // what is left, and the run's next write finds the disk full.
    let disk = match SmallDisk::mount(64 << 20) {
        Ok(d) => d,
        Err(reason) => {
            eprintln!("skipped: cannot mount a small file system ({reason})");
            return;
        }
    };
    let dir = disk.path();
    let target = dir.join("run.csv");
    std::fs::write(&target, PREVIOUS).expect("previous");
    // The run takes far longer than filling the disk; should it still win
    // the race, it has written a complete file, and the test tries again.
    for _attempt in 0..3 {
        let child = simulate(dir, &["--rate", "1e4", "-o", "run.csv"]).spawn();
        let start = Instant::now();
        while parts(dir).is_empty() {
            assert!(start.elapsed() < LIMIT, "no temporary file appeared");
            std::thread::sleep(Duration::from_millis(1));
        }
        let filler = dir.join("filler");
        fill(&filler);
        let out = child.finish();
        std::fs::remove_file(&filler).expect("remove the filler");
        if out.status.success() {
            eprintln!("the run finished before the disk was full: again");
            std::fs::write(&target, PREVIOUS).expect("previous");
            continue;
        }
        let text = out.error_line_with(1);
        assert!(
            text.starts_with("parasils: error: writing run.csv: No space left on device"),
            "{text}"
        );
        assert_eq!(names(dir), ["run.csv"]);
        assert_eq!(std::fs::read(&target).expect("target"), PREVIOUS);
        return;
    }
    panic!("the run finished before the disk was full, three times");
}
