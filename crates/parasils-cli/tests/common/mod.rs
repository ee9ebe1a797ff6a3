//! The `parasils` binary run as a process, for the command tests.

// Each test binary uses its own part of this module.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// The binary run with `args`.
pub fn parasils(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_parasils"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// The standard output of a run, after checking it succeeded.
pub fn ok(args: &[&str]) -> String {
    let out = parasils(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

/// The error line of a failing run, after checking it failed with one line.
pub fn fails(args: &[&str]) -> String {
    let out = parasils(args);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).expect("UTF-8");
    assert_eq!(err.lines().count(), 1, "{err}");
    err
}

/// The shipped demo procedure's path.
pub fn demo() -> String {
    let path: std::path::PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "procedures",
        "sils-demo.toml",
    ]
    .iter()
    .collect();
    path.to_string_lossy().into_owned()
}

/// A path as an argument.
pub fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}
