//! The structural rules of `ARCHITECTURE.md` as a test: file sizes, what a
//! module with child files holds, no child importing its parent, every
//! public type at its crate's root, the crate graph against the crate table,
//! and each crate's modules in its table's import order with no circle.
//!
//! The checker reads Rust as text (`source`): it sees items and the paths
//! they write, not what a macro expands to. It runs on the workspace
//! (`real_tree`) and, rule by rule, on small trees that break exactly one
//! rule (`broken`), so that each rule is seen failing.
//!
//! The workspace is read from the source tree, so this file is left out of
//! the published `parasils` package (`exclude` in the root `Cargo.toml`).

#[path = "architecture/broken.rs"]
mod broken;
#[path = "architecture/real_tree.rs"]
mod real_tree;
#[path = "architecture/rules.rs"]
mod rules;
#[path = "architecture/source.rs"]
mod source;
#[path = "architecture/workspace.rs"]
mod workspace;
