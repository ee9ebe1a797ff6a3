//! `parasils` run as a process: arguments, an optional standard input, a
//! folder to run in (a fresh temporary one unless the test gives one), and
//! what came back (the exit status, standard output, standard error), with
//! one clear message when a run does not end as the test expects.
//!
//! A run is waited for while its output is read, so a child that writes
//! megabytes to a pipe never blocks; a child that runs past its time limit
//! is killed and fails the test. [`Parasils::spawn`] leaves the child
//! running, for tests that signal it or read part of its output.

// Each test binary uses its own part of this module.
#![allow(dead_code)]

use core::time::Duration;
use std::ffi::{OsStr, OsString};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, ExitStatus, Stdio};
use std::thread::JoinHandle;
use std::time::Instant;

/// How long a run may take before it is killed: a guard against a hung
/// child, far above what any run of these tests takes.
pub const LIMIT: Duration = Duration::from_secs(300);

/// The variable that lowers the output size cap (for tests); a run starts
/// without it unless the test sets it.
const CAP_VARIABLE: &str = "PARASILS_OUTPUT_CAP_BYTES";

/// A run of the `parasils` binary, to be started by [`Parasils::run`] or
/// [`Parasils::spawn`].
#[derive(Debug)]
pub struct Parasils {
    args: Vec<OsString>,
    envs: Vec<(String, String)>,
    shell: Option<String>,
    dir: Option<PathBuf>,
    stdin: Option<Vec<u8>>,
    limit: Duration,
}

/// `parasils ARGS`, run in a fresh temporary folder unless
/// [`Parasils::dir`] gives one.
pub fn parasils(args: &[&str]) -> Parasils {
    Parasils {
        args: Vec::new(),
        envs: Vec::new(),
        shell: None,
        dir: None,
        stdin: None,
        limit: LIMIT,
    }
    .args(args)
}

/// The standard output of `parasils ARGS`, after checking that it succeeded.
pub fn ok(args: &[&str]) -> String {
    parasils(args).run().ok()
}

/// The error of `parasils ARGS`, after checking that it failed with a
/// message of one line.
pub fn fails(args: &[&str]) -> String {
    parasils(args).run().error_line()
}

impl Parasils {
    /// One more argument.
    pub fn arg(mut self, arg: impl AsRef<OsStr>) -> Self {
        self.args.push(arg.as_ref().to_owned());
        self
    }

    /// More arguments.
    pub fn args<S: AsRef<OsStr>>(self, args: impl IntoIterator<Item = S>) -> Self {
        args.into_iter().fold(self, Self::arg)
    }

    /// Runs in `dir` instead of a fresh temporary folder.
    pub fn dir(mut self, dir: &Path) -> Self {
        self.dir = Some(dir.to_path_buf());
        self
    }

    /// Sets an environment variable for the run.
    pub fn env(mut self, key: &str, value: &str) -> Self {
        self.envs.push((key.to_owned(), value.to_owned()));
        self
    }

    /// Runs the binary from `sh -c "SETUP && exec BINARY ARGS"`: `setup`
    /// changes the process's limits (`ulimit -f 64`) before it starts.
    pub fn after_shell(mut self, setup: &str) -> Self {
        self.shell = Some(setup.to_owned());
        self
    }

    /// Writes `bytes` to the run's standard input, then closes it (without
    /// this, the standard input is empty).
    pub fn stdin(mut self, bytes: impl Into<Vec<u8>>) -> Self {
        self.stdin = Some(bytes.into());
        self
    }

    /// Kills the run and fails the test past `limit` (default [`LIMIT`]).
    pub fn limit(mut self, limit: Duration) -> Self {
        self.limit = limit;
        self
    }

    /// Starts the run and waits for it.
    pub fn run(self) -> Ran {
        self.spawn().finish()
    }

    /// Starts the run and leaves it running.
    pub fn spawn(self) -> Running {
        let binary = env!("CARGO_BIN_EXE_parasils");
        let words: Vec<_> = self.args.iter().map(|a| a.to_string_lossy()).collect();
        let mut shown = format!("`parasils {}`", words.join(" "));
        let mut command = match &self.shell {
            None => Command::new(binary),
            Some(setup) => {
                shown = format!("{shown} after `{setup}`");
                let mut sh = Command::new("sh");
                sh.args(["-c", &format!("{setup} && exec \"$0\" \"$@\""), binary]);
                sh
            }
        };
        command.args(&self.args).env_remove(CAP_VARIABLE);
        for (key, value) in &self.envs {
            command.env(key, value);
        }
        let scratch = match &self.dir {
            Some(dir) => {
                command.current_dir(dir);
                None
            }
            None => {
                let scratch = tempfile::tempdir().expect("a temporary folder");
                command.current_dir(scratch.path());
                Some(scratch)
            }
        };
        command
            .stdin(if self.stdin.is_some() {
                Stdio::piped()
            } else {
                Stdio::null()
            })
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let mut child = command
            .spawn()
            .unwrap_or_else(|e| panic!("{shown} did not start: {e}"));
        let stdin = self.stdin.map(|bytes| {
            let mut pipe = child.stdin.take().expect("a piped standard input");
            // A child that exits without reading all of it closes the pipe:
            // not the test's concern here, its exit status says what happened.
            std::thread::spawn(move || drop(pipe.write_all(&bytes)))
        });
        Running {
            child,
            shown,
            limit: self.limit,
            started: Instant::now(),
            stdin,
            _scratch: scratch,
        }
    }
}

/// A started run.
#[derive(Debug)]
pub struct Running {
    child: Child,
    shown: String,
    limit: Duration,
    started: Instant,
    stdin: Option<JoinHandle<()>>,
    _scratch: Option<tempfile::TempDir>,
}

impl Running {
    /// The child's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// The child's standard output, to read part of it; [`Running::finish`]
    /// then reports the rest as empty.
    pub fn take_stdout(&mut self) -> ChildStdout {
        self.child
            .stdout
            .take()
            .expect("standard output not taken yet")
    }

    /// Sends `signal` (`-INT`, `-TERM`, ...) to the child with `kill`.
    pub fn signal(&self, signal: &str) {
        let sent = Command::new("kill")
            .args([signal, &self.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(sent.success(), "kill {signal} {} failed", self.id());
    }

    /// Whether the time limit has passed since the start.
    pub fn overdue(&self) -> bool {
        self.started.elapsed() > self.limit
    }

    /// Waits for the end of the run, reading its output meanwhile.
    pub fn finish(mut self) -> Ran {
        let stdout = reader(self.child.stdout.take());
        let stderr = reader(self.child.stderr.take());
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("wait") {
                break status;
            }
            if self.overdue() {
                self.child.kill().ok();
                self.child.wait().ok();
                panic!("{} ran past {:?} and was killed", self.shown, self.limit);
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        if let Some(writer) = self.stdin.take() {
            writer.join().expect("the standard input's writer");
        }
        Ran {
            shown: self.shown.clone(),
            status,
            stdout: stdout.join().expect("the standard output's reader"),
            stderr: stderr.join().expect("the standard error's reader"),
        }
    }
}

impl Drop for Running {
    /// A child left running by a failed test is killed.
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            self.child.kill().ok();
            self.child.wait().ok();
        }
    }
}

/// A thread reading `pipe` to its end (nothing when there is no pipe).
fn reader(pipe: Option<impl Read + Send + 'static>) -> JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut pipe) = pipe {
            pipe.read_to_end(&mut bytes)
                .expect("read the child's output");
        }
        bytes
    })
}

/// A finished run.
#[derive(Debug)]
pub struct Ran {
    /// The command line, for messages.
    pub shown: String,
    /// The exit status.
    pub status: ExitStatus,
    /// The standard output, whole.
    pub stdout: Vec<u8>,
    /// The standard error, whole.
    pub stderr: Vec<u8>,
}

impl Ran {
    /// The standard output as text.
    pub fn stdout(&self) -> String {
        String::from_utf8(self.stdout.clone())
            .unwrap_or_else(|e| panic!("{}: standard output is not UTF-8: {e}", self.shown))
    }

    /// The standard error as text.
    pub fn stderr(&self) -> String {
        String::from_utf8(self.stderr.clone())
            .unwrap_or_else(|e| panic!("{}: standard error is not UTF-8: {e}", self.shown))
    }

    /// The standard output, after checking that the run succeeded.
    pub fn ok(self) -> String {
        assert!(
            self.status.success(),
            "{} failed ({}):\n{}",
            self.shown,
            self.status,
            String::from_utf8_lossy(&self.stderr)
        );
        self.stdout()
    }

    /// The standard error, after checking that the run failed.
    pub fn fails(self) -> String {
        assert!(
            !self.status.success(),
            "{} succeeded, a failure was expected; it printed:\n{}",
            self.shown,
            String::from_utf8_lossy(&self.stdout)
        );
        self.stderr()
    }

    /// The standard error, after checking that the run ended with status
    /// `code`.
    pub fn fails_with(self, code: i32) -> String {
        assert_eq!(
            self.status.code(),
            Some(code),
            "{} ended with {}, not status {code}:\n{}",
            self.shown,
            self.status,
            String::from_utf8_lossy(&self.stderr)
        );
        self.stderr()
    }

    /// The error, after checking that the run failed with a message of one
    /// line.
    pub fn error_line(self) -> String {
        let shown = self.shown.clone();
        let err = self.fails();
        assert_eq!(err.lines().count(), 1, "{shown}: not one line: {err:?}");
        err
    }

    /// The error, after checking that the run ended with status `code` and
    /// a message of one line.
    pub fn error_line_with(self, code: i32) -> String {
        let shown = self.shown.clone();
        let err = self.fails_with(code);
        assert_eq!(err.lines().count(), 1, "{shown}: not one line: {err:?}");
        err
    }
}
