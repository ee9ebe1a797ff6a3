//! What the command tests share: one way to run `parasils` as a process
//! ([`process`]), one reader of the CSV files it writes ([`table`]), and
//! the paths and folder listings the tests look at ([`files`]).
//!
//! Each test file declares `mod common;` and uses the parts it needs
//! (`use common::process::parasils;`).

pub mod files;
pub mod process;
pub mod table;
