//! The rules on this workspace.

use std::path::Path;

use crate::rules::check;

/// Every rule holds on the workspace; a failure lists every violation, one
/// a line, with its file, line and rule.
#[test]
fn the_workspace_keeps_its_structural_rules() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let violations = check(root).expect("the workspace reads");
    let list: Vec<String> = violations.iter().map(ToString::to_string).collect();
    assert!(
        violations.is_empty(),
        "{} violation(s) of ARCHITECTURE.md's structural rules:\n{}",
        list.len(),
        list.join("\n")
    );
}
