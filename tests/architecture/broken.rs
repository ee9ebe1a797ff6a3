//! Each rule seen failing: a small workspace that keeps every rule, then,
//! one test per rule, the same workspace with exactly that rule broken, and
//! the checker's report naming the file and the rule.

use std::fs;
use std::path::{Path, PathBuf};

use crate::rules::{Rule, Violation, check};

/// A workspace in a temporary folder, removed when dropped.
struct Tree {
    root: PathBuf,
}

/// The small workspace that keeps every rule: `alpha` (an error, a `shape`
/// folder of two siblings, the one using the other through `super::`) and
/// `beta`, which depends on it. Comments and strings hold what would break
/// the rules, to show that they are not read.
const GOOD: &[(&str, &str)] = &[
    (
        "Cargo.toml",
        "[workspace]\nmembers = [\n    \"crates/alpha\", # the shapes\n    \"crates/beta\",\n]\n",
    ),
    (
        "crates/alpha/Cargo.toml",
        "[package]\nname = \"alpha\"\n\n[dependencies]\nlibm = \"0.2\"\n",
    ),
    (
        "crates/alpha/src/lib.rs",
        "//! Shapes.\n#![no_std]\n\nmod error;\npub mod shape;\n\n\
         pub use error::Error;\npub use shape::{Circle, Square};\n",
    ),
    (
        "crates/alpha/src/error.rs",
        "//! The error. `use crate::shape::Circle;` in a doc is not code.\n\n\
         /// What went wrong.\npub struct Error;\n\n\
         /// Unreachable: its module is private and nothing re-exports it.\npub struct Detail;\n",
    ),
    (
        "crates/alpha/src/shape/mod.rs",
        "//! Shapes: docs, declarations and re-exports only.\n\
         // fn hidden() {} and /* struct Hidden; */ are comments.\n\n\
         mod circle;\nmod square;\n\npub use circle::Circle;\npub use square::Square;\n",
    ),
    (
        "crates/alpha/src/shape/circle.rs",
        "//! A circle.\nuse crate::error::Error;\n\n/// A circle.\npub struct Circle(pub f64);\n\n\
         impl Circle {\n    /// Checked.\n    pub fn new(r: f64) -> Result<Self, Error> {\n        \
         let _s = \"super::Circle crate::Error\";\n        if r > 0.0 { Ok(Self(r)) } else { Err(Error) }\n    }\n}\n",
    ),
    (
        "crates/alpha/src/shape/square.rs",
        "//! A square, the circle's sibling.\nuse super::circle::Circle;\n\n\
         /// A square around a circle.\npub struct Square(pub Circle);\n\n\
         #[cfg(test)]\nmod tests {\n    use super::*;\n    use crate::shape::Circle as C;\n}\n",
    ),
    (
        "crates/beta/Cargo.toml",
        "[package]\nname = \"beta\"\n\n[dependencies]\nalpha = { path = \"../alpha\" }\n",
    ),
    (
        "crates/beta/src/lib.rs",
        "//! Areas.\n\nmod area;\n\npub use area::Area;\n",
    ),
    (
        "crates/beta/src/area.rs",
        "//! An area.\nuse alpha::Circle;\n\n/// An area.\npub struct Area(pub Circle);\n",
    ),
    ("ARCHITECTURE.md", DOC),
];

/// The small workspace's `ARCHITECTURE.md`: the crate table, then a module
/// table per crate.
const DOC: &str = "# Architecture

| crate | kind | depends on |
|---|---|---|
| `alpha` | library | nothing (libm) |
| `beta` | library | `alpha` |

## alpha

| module | concept |
|---|---|
| `error` | the error |
| `shape` | shapes |

## beta

| module | concept |
|---|---|
| `area` | areas |
";

impl Tree {
    /// [`GOOD`] with `changes` applied (a file's new text; `None` removes it).
    fn new(name: &str, changes: &[(&str, Option<&str>)]) -> Tree {
        let dir = format!("parasils-architecture-{}-{name}", std::process::id());
        let root = std::env::temp_dir().join(dir);
        let _ = fs::remove_dir_all(&root);
        let mut files: Vec<(&str, Option<&str>)> =
            GOOD.iter().map(|(p, t)| (*p, Some(*t))).collect();
        for (path, text) in changes {
            match files.iter_mut().find(|(p, _)| p == path) {
                Some(f) => f.1 = *text,
                None => files.push((path, *text)),
            }
        }
        for (path, text) in files {
            let Some(text) = text else { continue };
            let file = root.join(path);
            let dir = file.parent().expect("a file has a folder");
            fs::create_dir_all(dir).expect("the temporary folder is writable");
            fs::write(&file, text).expect("the temporary folder is writable");
        }
        Tree { root }
    }

    /// The checker's violations on this tree.
    fn check(&self) -> Vec<Violation> {
        check(&self.root).expect("the small tree reads")
    }
}

impl Drop for Tree {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.root);
    }
}

/// Asserts that `found` holds violations of `rule` in `file` only (at least
/// one), each printed with the file and the rule's name, and returns them.
fn only(found: &[Violation], rule: Rule, file: &str) -> Vec<String> {
    let shown: Vec<String> = found.iter().map(ToString::to_string).collect();
    assert!(
        !found.is_empty(),
        "expected a violation of [{}] in {file}",
        rule.name()
    );
    for (v, s) in found.iter().zip(&shown) {
        assert_eq!(
            (v.rule, v.file.as_path()),
            (rule, Path::new(file)),
            "{}",
            shown.join("\n")
        );
        assert!(
            s.starts_with(file) && s.contains(&format!("[{}]", rule.name())),
            "{s}"
        );
    }
    shown
}

#[test]
fn the_small_tree_keeps_every_rule() {
    let tree = Tree::new("good", &[]);
    let found: Vec<String> = tree.check().iter().map(ToString::to_string).collect();
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn a_file_over_800_lines_is_reported_and_one_of_800_is_not() {
    let long = "// a line\n".repeat(801);
    let exact = "// a line\n".repeat(800);
    let tree = Tree::new(
        "size",
        &[
            ("crates/alpha/tests/long.rs", Some(&long)),
            ("crates/beta/tests/exact.rs", Some(&exact)),
        ],
    );
    let shown = only(&tree.check(), Rule::FileSize, "crates/alpha/tests/long.rs");
    assert_eq!(shown.len(), 1);
    assert!(shown[0].contains("801 lines"), "{}", shown[0]);
}

#[test]
fn code_in_a_mod_rs_is_reported() {
    let text = "//! Shapes.\nmod circle;\nmod square;\n\npub use circle::Circle;\npub use square::Square;\n\n\
                /// Code that belongs in a child.\npub fn unit() -> Circle {\n    Circle(1.0)\n}\n";
    let tree = Tree::new("modrs", &[("crates/alpha/src/shape/mod.rs", Some(text))]);
    let shown = only(
        &tree.check(),
        Rule::ModFile,
        "crates/alpha/src/shape/mod.rs",
    );
    assert_eq!(shown.len(), 1);
    assert!(shown[0].contains("`fn` (line 9)"), "{}", shown[0]);
}

#[test]
fn code_beside_a_folder_of_children_is_reported() {
    // `shape.rs` beside `shape/` instead of `shape/mod.rs`.
    let text = "//! Shapes.\nmod circle;\nmod square;\n\npub use circle::Circle;\npub use square::Square;\n\
                use core::f64::consts::PI;\n";
    let tree = Tree::new(
        "modfile",
        &[
            ("crates/alpha/src/shape/mod.rs", None),
            ("crates/alpha/src/shape.rs", Some(text)),
        ],
    );
    let shown = only(&tree.check(), Rule::ModFile, "crates/alpha/src/shape.rs");
    assert!(
        shown[0].contains("a private `use` (line 7)"),
        "{}",
        shown[0]
    );
}

#[test]
fn a_child_importing_its_parent_is_reported() {
    let text =
        "//! A square.\nuse super::Circle;\n\n/// A square.\npub struct Square(pub Circle);\n";
    let tree = Tree::new(
        "parent",
        &[("crates/alpha/src/shape/square.rs", Some(text))],
    );
    let shown = only(
        &tree.check(),
        Rule::ParentImport,
        "crates/alpha/src/shape/square.rs",
    );
    assert_eq!(shown.len(), 1);
    assert!(
        shown[0].contains(":2: ") && shown[0].contains("`Circle`, an item of its parent `shape`")
    );
}

#[test]
fn a_child_naming_its_parent_by_a_crate_path_in_code_is_reported() {
    let text = "//! A square.\n\n/// A square.\npub struct Square(pub f64);\n\n\
                impl Square {\n    /// Its circle.\n    pub fn circle(&self) -> crate::shape::Circle {\n        \
                crate::shape::Circle(self.0)\n    }\n}\n";
    let tree = Tree::new(
        "parentpath",
        &[("crates/alpha/src/shape/square.rs", Some(text))],
    );
    let shown = only(
        &tree.check(),
        Rule::ParentImport,
        "crates/alpha/src/shape/square.rs",
    );
    assert_eq!(shown.len(), 2, "{shown:?}");
    assert!(
        shown[0].contains(":8: ") && shown[1].contains(":9: "),
        "{shown:?}"
    );
}

#[test]
fn a_public_type_missing_at_the_root_is_reported() {
    let circle = "//! A circle.\n\n/// A circle.\npub struct Circle(pub f64);\n\n/// Its radius.\npub struct Radius(pub f64);\n";
    let shape = "//! Shapes.\nmod circle;\nmod square;\n\npub use circle::{Circle, Radius};\npub use square::Square;\n";
    let tree = Tree::new(
        "reexport",
        &[
            ("crates/alpha/src/shape/circle.rs", Some(circle)),
            ("crates/alpha/src/shape/mod.rs", Some(shape)),
        ],
    );
    let shown = only(
        &tree.check(),
        Rule::RootReexport,
        "crates/alpha/src/shape/circle.rs",
    );
    assert_eq!(shown.len(), 1);
    assert!(
        shown[0].contains(":7: ") && shown[0].contains("`Radius`"),
        "{}",
        shown[0]
    );
}

#[test]
fn a_dependency_missing_from_the_crate_table_is_reported() {
    let doc = DOC.replace(
        "| `beta` | library | `alpha` |",
        "| `beta` | library | nothing |",
    );
    let tree = Tree::new("graphmissing", &[("ARCHITECTURE.md", Some(&doc))]);
    let shown = only(&tree.check(), Rule::CrateGraph, "crates/beta/Cargo.toml");
    assert_eq!(shown.len(), 1);
    assert!(
        shown[0].contains(":5: ") && shown[0].contains("depends on `alpha`"),
        "{}",
        shown[0]
    );
}

#[test]
fn a_dependency_the_manifests_lack_is_reported() {
    let doc = DOC.replace(
        "| `alpha` | library | nothing (libm) |",
        "| `alpha` | library | `beta` |",
    );
    let tree = Tree::new("graphextra", &[("ARCHITECTURE.md", Some(&doc))]);
    let shown = only(&tree.check(), Rule::CrateGraph, "ARCHITECTURE.md");
    assert_eq!(shown.len(), 1);
    assert!(
        shown[0].contains(":5: ") && shown[0].contains("`alpha` depends on `beta`"),
        "{}",
        shown[0]
    );
}

#[test]
fn a_module_using_one_listed_after_it_is_reported() {
    let text = "//! The error.\n\n/// What went wrong, with the shape.\npub struct Error(pub crate::shape::Circle);\n";
    let tree = Tree::new("order", &[("crates/alpha/src/error.rs", Some(text))]);
    let found = tree.check();
    let order: Vec<Violation> = found
        .iter()
        .filter(|v| v.rule == Rule::ModuleOrder)
        .cloned()
        .collect();
    let shown = only(&order, Rule::ModuleOrder, "crates/alpha/src/error.rs");
    assert!(
        shown[0].contains(":4: ") && shown[0].contains("`error` uses `shape`"),
        "{}",
        shown[0]
    );
    // `error` uses `shape` and `shape` uses `error`: a circle too.
    let circle: Vec<Violation> = found
        .iter()
        .filter(|v| v.rule == Rule::ImportCircle)
        .cloned()
        .collect();
    assert_eq!(found.len(), order.len() + circle.len(), "{found:?}");
}

#[test]
fn a_module_missing_from_its_table_is_reported() {
    let lib = "//! Areas.\n\nmod area;\nmod volume;\n\npub use area::Area;\n";
    let tree = Tree::new(
        "unlisted",
        &[
            ("crates/beta/src/lib.rs", Some(lib)),
            ("crates/beta/src/volume.rs", Some("//! Volumes.\n")),
        ],
    );
    let shown = only(
        &tree.check(),
        Rule::ModuleOrder,
        "crates/beta/src/volume.rs",
    );
    assert!(shown[0].contains("`volume` is not listed"), "{}", shown[0]);
}

#[test]
fn an_import_circle_is_reported_and_the_trait_iterator_pair_is_not() {
    // Three modules in a ring: `a` uses `b`, `b` uses `c`, `c` uses `a`. The
    // table's order can hold only two of the three uses, so the order rule
    // reports the third; the circle rule names the whole ring.
    let lib = "//! Ring.\n\nmod a;\nmod b;\nmod c;\n";
    let doc = "| crate | kind | depends on |\n|---|---|---|\n| `alpha` | library | nothing |\n\
               | `beta` | library | `alpha` |\n| `parasils-traj` | library | nothing |\n\n\
               ## alpha\n\n| module | concept |\n|---|---|\n| `error` | |\n| `shape` | |\n\n\
               ## beta\n\n| module | concept |\n|---|---|\n| `c` | |\n| `b` | |\n| `a` | |\n\n\
               ## parasils-traj\n\n| module | concept |\n|---|---|\n| `profile` | |\n| `sampler` | |\n";
    let tree = Tree::new(
        "circle",
        &[
            (
                "Cargo.toml",
                Some("[workspace]\nmembers = [\"crates/*\"]\n"),
            ),
            ("crates/beta/src/lib.rs", Some(lib)),
            ("crates/beta/src/area.rs", None),
            (
                "crates/beta/src/a.rs",
                Some("//! A.\nuse crate::b::B;\n/// A.\npub(crate) struct A(B);\n"),
            ),
            (
                "crates/beta/src/b.rs",
                Some("//! B.\n/// B.\npub(crate) struct B(crate::c::C);\n"),
            ),
            (
                "crates/beta/src/c.rs",
                Some("//! C.\n/// C.\npub(crate) struct C(Box<crate::a::A>);\n"),
            ),
            (
                "crates/traj/Cargo.toml",
                Some("[package]\nname = \"parasils-traj\"\n"),
            ),
            (
                "crates/traj/src/lib.rs",
                Some("//! Profiles.\npub mod profile;\npub mod sampler;\n"),
            ),
            (
                "crates/traj/src/profile.rs",
                Some("//! P.\nuse crate::sampler::Sampler;\n"),
            ),
            (
                "crates/traj/src/sampler.rs",
                Some("//! S.\nuse crate::profile;\n"),
            ),
            ("ARCHITECTURE.md", Some(doc)),
        ],
    );
    let found = tree.check();
    let circles: Vec<Violation> = found
        .iter()
        .filter(|v| v.rule == Rule::ImportCircle)
        .cloned()
        .collect();
    let shown = only(&circles, Rule::ImportCircle, "crates/beta/src/a.rs");
    assert_eq!(shown.len(), 1, "{found:?}");
    assert!(shown[0].contains("between `a`, `b`, `c`"), "{}", shown[0]);
    let rest: Vec<String> = found
        .iter()
        .filter(|v| v.rule != Rule::ImportCircle)
        .map(ToString::to_string)
        .collect();
    assert_eq!(rest.len(), 1, "{rest:?}");
    assert!(
        rest[0].starts_with("crates/beta/src/c.rs:3: [module order] `c` uses `a`"),
        "{}",
        rest[0]
    );
}

#[test]
fn the_reader_skips_comments_and_literals_but_not_code() {
    use crate::source::{Kind, items, tokens};
    let text = r####"
//! `use crate::doc::Hidden;`
/* a block /* nested crate::block::Hidden */ still a comment */
use crate::real::{self, Used as Alias, nested::*};
fn f<'a>(x: &'a str) -> char {
    let _ = r#"crate::raw::Hidden "quoted""#;
    let _ = "crate::string::Hidden \" super::Hidden";
    let _ = (b'\'', '"', 'x', br"crate::bytes::Hidden");
    crate::code::seen(x); '}'
}
#[cfg(not(test))]
mod kept {}
#[cfg(test)]
mod tests {}
"####;
    let found = items(&tokens(text));
    let Kind::Use(uses) = &found[0].kind else {
        panic!("{found:?}")
    };
    let written: Vec<String> = uses.iter().map(|u| u.segs.join("::")).collect();
    assert_eq!(
        written,
        ["crate::real", "crate::real::Used", "crate::real::nested"]
    );
    assert_eq!(uses[1].name(), Some("Alias"));
    assert!(uses[2].glob && uses[2].name().is_none());
    let paths: Vec<(String, usize)> = found[1]
        .paths
        .iter()
        .map(|p| (p.segs.join("::"), p.line))
        .collect();
    assert_eq!(paths, [("crate::code::seen".to_owned(), 9)]);
    assert_eq!(found.len(), 4, "{found:?}");
    assert!(!found[2].test && found[3].test);
}
