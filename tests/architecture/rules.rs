//! The structural rules of `ARCHITECTURE.md`, each a function from the
//! workspace to the places that break it. The same functions check the real
//! tree and the small broken trees of the tests.

use std::collections::BTreeSet;
use std::fmt;
use std::fs;
use std::path::{Path, PathBuf};

use crate::source::{Item, Kind, UsePath, Vis};
use crate::workspace::{Crate, CrateKind, Module, Workspace, crate_table, load, module_tables};

/// The longest a source or test file may be, in lines.
pub const MAX_LINES: usize = 800;

/// The one import circle allowed: a trait and its iterator
/// (`traj::profile::Motion::sampler` returns a `traj::sampler::Sampler`).
/// The first module uses the second although the table lists it later.
pub const ALLOWED_CIRCLE: (&str, &str, &str) = ("parasils-traj", "profile", "sampler");

/// A structural rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Rule {
    /// No source or test file over [`MAX_LINES`] lines.
    FileSize,
    /// A module with child files holds only docs, `mod`, `pub use`, attributes.
    ModFile,
    /// A child module never imports its parent's items.
    ParentImport,
    /// Every public type of a library is re-exported at its crate root.
    RootReexport,
    /// The crate table's "depends on" column is the manifests' graph.
    CrateGraph,
    /// A module uses only modules listed before it; every module is listed.
    ModuleOrder,
    /// No import circle between a crate's top-level modules (one allowed).
    ImportCircle,
}

impl Rule {
    /// The rule's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Rule::FileSize => "file size",
            Rule::ModFile => "mod.rs holds declarations only",
            Rule::ParentImport => "child imports parent",
            Rule::RootReexport => "root re-export",
            Rule::CrateGraph => "crate graph",
            Rule::ModuleOrder => "module order",
            Rule::ImportCircle => "import circle",
        }
    }
}

/// One place that breaks a rule.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Violation {
    /// The file, relative to the workspace root.
    pub file: PathBuf,
    /// Its line (0 when the whole file is meant).
    pub line: usize,
    /// The rule broken.
    pub rule: Rule,
    /// What is wrong and where.
    pub message: String,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (file, line, rule) = (self.file.display(), self.line, self.rule.name());
        write!(f, "{file}:{line}: [{rule}] {}", self.message)
    }
}

/// Every violation of every rule in the workspace at `root`, sorted by
/// file and line.
pub fn check(root: &Path) -> Result<Vec<Violation>, String> {
    let ws = load(root)?;
    let mut out = file_sizes(&ws)?;
    out.extend(mod_files(&ws));
    out.extend(parent_imports(&ws));
    out.extend(root_reexports(&ws));
    out.extend(crate_graph(&ws));
    out.extend(module_order(&ws));
    out.sort();
    Ok(out)
}

/// The `.rs` files under `dir` (relative to `root`), sub-packages (folders
/// with a `Cargo.toml`) left out.
fn rust_files(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let Ok(entries) = fs::read_dir(root.join(dir)) else {
        return Ok(());
    };
    let mut entries: Vec<_> = entries
        .filter_map(Result::ok)
        .map(|e| e.file_name())
        .collect();
    entries.sort();
    for name in entries {
        let rel = dir.join(&name);
        let abs = root.join(&rel);
        if abs.is_dir() && !abs.join("Cargo.toml").exists() {
            rust_files(root, &rel, out)?;
        } else if rel.extension().is_some_and(|e| e == "rs") {
            out.push(rel);
        }
    }
    Ok(())
}

/// No `.rs` file of a crate's `src/`, `tests/`, `benches/` or `examples/`
/// over [`MAX_LINES`] lines.
pub fn file_sizes(ws: &Workspace) -> Result<Vec<Violation>, String> {
    let mut out = Vec::new();
    for c in &ws.crates {
        let mut files = Vec::new();
        for part in ["src", "tests", "benches", "examples"] {
            rust_files(&ws.root, &c.dir.join(part), &mut files)?;
        }
        for file in files {
            let lines = crate::workspace::read(&ws.root.join(&file))?
                .lines()
                .count();
            if lines > MAX_LINES {
                let message = format!("{lines} lines, more than {MAX_LINES}: split it by concept");
                out.push(Violation {
                    file,
                    line: 0,
                    rule: Rule::FileSize,
                    message,
                });
            }
        }
    }
    Ok(out)
}

/// What an item is, for messages.
fn describe(it: &Item) -> String {
    match &it.kind {
        Kind::Type(name) => format!("type `{name}`"),
        Kind::Other(word) => format!("`{word}`"),
        Kind::Use(_) => "a private `use`".to_owned(),
        Kind::Mod { name, .. } => format!("inline module `{name}`"),
        Kind::ExternCrate => "`extern crate`".to_owned(),
    }
}

/// A module whose children are files (`mod.rs`, `name.rs` beside `name/`, a
/// library's `lib.rs`) holds only docs, `mod` declarations of files,
/// `pub use`/`pub(crate) use` re-exports, `extern crate` and attributes. A
/// binary's `main.rs` and the Python extension's `lib.rs` are entry points
/// (`fn main`, `#[pymodule]`) and exempt.
pub fn mod_files(ws: &Workspace) -> Vec<Violation> {
    let mut out = Vec::new();
    for c in &ws.crates {
        for m in &c.modules {
            let entry = m.path.is_empty() && c.kind != CrateKind::Library;
            if m.inline || !m.has_file_children || entry {
                continue;
            }
            let code: Vec<&Item> = m
                .items
                .iter()
                .filter(|it| match &it.kind {
                    Kind::Mod { body, .. } => body.is_some(),
                    Kind::Use(_) => it.vis == Vis::Private,
                    Kind::ExternCrate => false,
                    _ => true,
                })
                .collect();
            let Some(first) = code.first() else { continue };
            // The items that are code first, the private `use`s they need after.
            let mut shown = code.clone();
            shown.sort_by_key(|it| matches!(it.kind, Kind::Use(_)));
            let listed: Vec<String> = shown
                .iter()
                .take(6)
                .map(|it| format!("{} (line {})", describe(it), it.line))
                .collect();
            let more = if code.len() > 6 { ", ..." } else { "" };
            let message = format!(
                "{} has child files, so it holds only docs, `mod` declarations and re-exports; \
                 it holds {} item(s) of code: {}{more}; move them into a named child module",
                m.display(),
                code.len(),
                listed.join(", ")
            );
            out.push(Violation {
                file: m.file.clone(),
                line: first.line,
                rule: Rule::ModFile,
                message,
            });
        }
    }
    out
}

/// `segs` (a path written in module `at`) as a path from the crate root,
/// or `None` if it leaves the crate (another crate, a prelude name).
pub fn resolve(c: &Crate, at: &[String], segs: &[String]) -> Option<Vec<String>> {
    let first = segs.first()?;
    let mut base: Vec<String> = at.to_vec();
    let mut rest = segs;
    if first == "crate" {
        base.clear();
        rest = &segs[1..];
    } else if first == "super" || first == "self" {
        while let Some(s) = rest.first() {
            match s.as_str() {
                "super" => {
                    base.pop()?;
                }
                "self" => {}
                _ => break,
            }
            rest = &rest[1..];
        }
    } else {
        // A `use` path from a child module of `at` (`use geometry::X`).
        let m = c.module(at)?;
        if !m.children().any(|ch| ch == first) {
            return None;
        }
    }
    base.extend(rest.iter().cloned());
    Some(base)
}

/// A reference of a module's code to a path of its crate.
struct Ref {
    /// The path from the crate root.
    abs: Vec<String>,
    /// Whether the path ends in `*`.
    glob: bool,
    /// Its line.
    line: usize,
}

/// The paths of the crate that module `m`'s code outside tests names, in
/// its `use` trees and through `crate::`, `super::`, `self::`.
fn refs(c: &Crate, m: &Module) -> Vec<Ref> {
    let mut out = Vec::new();
    for it in m.items.iter().filter(|it| !it.test) {
        if let Kind::Use(paths) = &it.kind {
            for p in paths {
                if let Some(abs) = resolve(c, &m.path, &p.segs) {
                    out.push(Ref {
                        abs,
                        glob: p.glob,
                        line: it.line,
                    });
                }
            }
        }
        for p in &it.paths {
            if let Some(abs) = resolve(c, &m.path, &p.segs) {
                out.push(Ref {
                    abs,
                    glob: false,
                    line: p.line,
                });
            }
        }
    }
    out
}

/// Whether `name` in module `m` is a `use` of another crate
/// (`pub use parasils_kin as kin`): naming it through `m` makes no circle.
fn is_external_alias(c: &Crate, m: &Module, name: &str) -> bool {
    m.items.iter().any(|it| match &it.kind {
        Kind::Use(paths) => paths
            .iter()
            .any(|p| p.name() == Some(name) && resolve(c, &m.path, &p.segs).is_none()),
        _ => false,
    })
}

/// A module never names an item of its parent (or of any module above it,
/// the crate root included): `use super::Item`, `use super::*`,
/// `crate::parent::Item`. Paths through the parent to a sibling
/// (`super::sibling::Item`) and to another crate's alias are fine. Modules
/// under `#[cfg(test)]` are exempt.
pub fn parent_imports(ws: &Workspace) -> Vec<Violation> {
    let mut out = Vec::new();
    for c in &ws.crates {
        for m in c.modules.iter().filter(|m| !m.test && !m.path.is_empty()) {
            for r in refs(c, m) {
                for depth in 0..m.path.len() {
                    let anc = &m.path[..depth];
                    if !r.abs.starts_with(anc) {
                        break;
                    }
                    let Some(anc_mod) = c.module(anc) else { break };
                    let whose = if depth + 1 == m.path.len() {
                        "its parent"
                    } else {
                        "an ancestor"
                    };
                    let what = match r.abs.get(depth) {
                        None if r.glob => format!("everything of {whose} {}", anc_mod.display()),
                        None => format!("{whose} {} itself", anc_mod.display()),
                        Some(next) if anc_mod.children().any(|ch| ch == next) => continue,
                        Some(next) if is_external_alias(c, anc_mod, next) => break,
                        Some(next) => format!("`{next}`, an item of {whose} {}", anc_mod.display()),
                    };
                    let message = format!(
                        "{} imports {what} (`crate::{}`); import the sibling that defines it",
                        m.display(),
                        r.abs.join("::")
                    );
                    let file = m.file.clone();
                    out.push(Violation {
                        file,
                        line: r.line,
                        rule: Rule::ParentImport,
                        message,
                    });
                    break;
                }
            }
        }
    }
    out
}

/// Whether module `at` declares the public type `name`.
fn declares(c: &Crate, at: &[String], name: &str) -> bool {
    c.module(at).is_some_and(|m| {
        m.items.iter().any(|it| {
            it.vis == Vis::Public && !it.test && matches!(&it.kind, Kind::Type(n) if n == name)
        })
    })
}

/// Whether module `at` gives the type `name` of module `target` to its
/// users: declares it, or names it in a `pub use` (followed through other
/// modules' re-exports and globs).
fn provides(c: &Crate, at: &[String], target: &[String], name: &str, depth: usize) -> bool {
    if at == target && declares(c, at, name) {
        return true;
    }
    let Some(m) = c.module(at) else { return false };
    if depth > 8 {
        return false;
    }
    m.items
        .iter()
        .filter(|it| it.vis == Vis::Public && !it.test)
        .any(|it| {
            let Kind::Use(paths) = &it.kind else {
                return false;
            };
            paths.iter().any(|p: &UsePath| {
                let Some(abs) = resolve(c, at, &p.segs) else {
                    return false;
                };
                if p.glob {
                    return abs != at && provides(c, &abs, target, name, depth + 1);
                }
                let Some((last, prefix)) = abs.split_last() else {
                    return false;
                };
                if prefix == target && last == name {
                    return true;
                }
                last == name && prefix != at && provides(c, prefix, target, name, depth + 1)
            })
        })
}

/// Every `pub struct/enum/union/trait/type` of a library that its users can
/// reach (through `pub mod`s, or a `pub use` in a public module) is
/// re-exported by the crate root. Binaries and the Python extension are
/// exempt.
pub fn root_reexports(ws: &Workspace) -> Vec<Violation> {
    let mut out = Vec::new();
    for c in ws.crates.iter().filter(|c| c.kind == CrateKind::Library) {
        for m in c.modules.iter().filter(|m| !m.test && !m.path.is_empty()) {
            for it in m
                .items
                .iter()
                .filter(|it| it.vis == Vis::Public && !it.test)
            {
                let Kind::Type(name) = &it.kind else { continue };
                let reachable = m.public
                    || c.modules.iter().any(|n| {
                        n.public
                            && !n.test
                            && n.path != m.path
                            && provides(c, &n.path, &m.path, name, 0)
                    });
                if !reachable || provides(c, &[], &m.path, name, 0) {
                    continue;
                }
                let message = format!(
                    "public type `{name}` of {} is not re-exported at the crate root: \
                     add `pub use {}::{name};` to the root",
                    m.display(),
                    m.path.join("::")
                );
                let file = m.file.clone();
                out.push(Violation {
                    file,
                    line: it.line,
                    rule: Rule::RootReexport,
                    message,
                });
            }
        }
    }
    out
}

/// The crate table's "depends on" column names exactly the workspace crates
/// each crate's manifest depends on (`[dependencies]`, target-specific
/// ones included), and every workspace crate has a row.
pub fn crate_graph(ws: &Workspace) -> Vec<Violation> {
    let doc = PathBuf::from("ARCHITECTURE.md");
    let names: BTreeSet<&str> = ws.crates.iter().map(|c| c.name.as_str()).collect();
    let rows = crate_table(&ws.doc);
    let mut out = Vec::new();
    let mut push = |file: &Path, line, message: String| {
        out.push(Violation {
            file: file.to_owned(),
            line,
            rule: Rule::CrateGraph,
            message,
        });
    };
    for row in &rows {
        if !names.contains(row.name.as_str()) && !row.name.contains('/') {
            let message = format!(
                "the crate table has a row for `{}`, not a workspace crate",
                row.name
            );
            push(&doc, row.line, message);
        }
    }
    for c in &ws.crates {
        let Some(row) = rows.iter().find(|r| r.name == c.name) else {
            push(
                &doc,
                0,
                format!("the crate table has no row for `{}`", c.name),
            );
            continue;
        };
        let listed: BTreeSet<&str> = row
            .depends_on
            .iter()
            .map(String::as_str)
            .filter(|n| n.starts_with("parasils") || names.contains(n))
            .collect();
        let actual: BTreeSet<&str> = c.deps.iter().map(|d| d.name.as_str()).collect();
        for d in &c.deps {
            if !listed.contains(d.name.as_str()) {
                let message = format!(
                    "`{}` depends on `{}`, which its row of ARCHITECTURE.md's crate table \
                     (line {}) does not name in `depends on`",
                    c.name, d.name, row.line
                );
                push(&c.manifest, d.line, message);
            }
        }
        for n in listed.difference(&actual) {
            let message = format!(
                "the crate table says `{}` depends on `{n}`, which {} does not depend on",
                c.name,
                c.manifest.display()
            );
            push(&doc, row.line, message);
        }
    }
    out
}

/// The top-level module a reference of top-level module `from` leads to:
/// the first segment, or, for a root re-export, the module it re-exports from.
fn target_top(c: &Crate, from: &str, abs: &[String]) -> Option<String> {
    let first = abs.first()?;
    let tops = c.top_modules();
    let top = if tops.contains(&first.as_str()) {
        first.clone()
    } else {
        let root = c.root()?;
        root.items.iter().find_map(|it| match &it.kind {
            Kind::Use(paths) => paths
                .iter()
                .filter(|p| p.name() == Some(first.as_str()))
                .find_map(|p| resolve(c, &[], &p.segs)?.first().cloned()),
            _ => None,
        })?
    };
    (top != from && tops.contains(&top.as_str())).then_some(top)
}

/// A use of one top-level module by another: user, used, and the first
/// place (file, line) the user names it.
pub type Use = (String, String, PathBuf, usize);

/// The uses between crate `c`'s top-level modules, outside tests.
pub fn module_uses(c: &Crate) -> Vec<Use> {
    let mut edges: Vec<Use> = Vec::new();
    for m in c.modules.iter().filter(|m| !m.test && !m.path.is_empty()) {
        for r in refs(c, m) {
            let Some(to) = target_top(c, &m.path[0], &r.abs) else {
                continue;
            };
            if !edges.iter().any(|e| e.0 == m.path[0] && e.1 == to) {
                edges.push((m.path[0].clone(), to, m.file.clone(), r.line));
            }
        }
    }
    edges
}

/// Each crate's top-level modules are listed in its `## <crate>` section's
/// module table, a module uses only modules listed before it (the
/// [`ALLOWED_CIRCLE`] aside), and the modules form no import circle.
pub fn module_order(ws: &Workspace) -> Vec<Violation> {
    let doc = PathBuf::from("ARCHITECTURE.md");
    let tables = module_tables(&ws.doc);
    let mut out = Vec::new();
    for c in &ws.crates {
        let tops = c.top_modules();
        if tops.is_empty() {
            continue;
        }
        let edges = module_uses(c);
        let allowed = |a: &str, b: &str| (c.name.as_str(), a, b) == ALLOWED_CIRCLE;
        out.extend(circles(c, &edges, &allowed));
        let Some(table) = tables.iter().find(|t| t.crate_name == c.name) else {
            let message = format!(
                "no module table for `{}`: a `## {}` section with a `| module | concept |` table",
                c.name, c.name
            );
            out.push(Violation {
                file: doc.clone(),
                line: 0,
                rule: Rule::ModuleOrder,
                message,
            });
            continue;
        };
        let pos = |n: &str| table.modules.iter().position(|(m, _)| m == n);
        for (name, line) in &table.modules {
            if !tops.contains(&name.as_str()) {
                let message = format!(
                    "the table of `{}` lists `{name}`, not a module of it",
                    c.name
                );
                out.push(Violation {
                    file: doc.clone(),
                    line: *line,
                    rule: Rule::ModuleOrder,
                    message,
                });
            }
        }
        for m in c.modules.iter().filter(|m| m.path.len() == 1 && !m.test) {
            if pos(&m.path[0]).is_none() {
                let message = format!(
                    "module {} is not listed in ARCHITECTURE.md's table of `{}`",
                    m.display(),
                    c.name
                );
                out.push(Violation {
                    file: m.file.clone(),
                    line: 0,
                    rule: Rule::ModuleOrder,
                    message,
                });
            }
        }
        for (a, b, file, line) in &edges {
            let (Some(pa), Some(pb)) = (pos(a), pos(b)) else {
                continue;
            };
            if pb > pa && !allowed(a, b) {
                let message = format!(
                    "`{a}` uses `{b}`, which ARCHITECTURE.md's table of `{}` lists after it \
                     (a module uses only those listed before it)",
                    c.name
                );
                let file = file.clone();
                out.push(Violation {
                    file,
                    line: *line,
                    rule: Rule::ModuleOrder,
                    message,
                });
            }
        }
    }
    out
}

/// The import circles (strongly connected sets of two or more top-level
/// modules), the allowed pair aside.
fn circles(c: &Crate, edges: &[Use], allowed: &dyn Fn(&str, &str) -> bool) -> Vec<Violation> {
    let nodes = c.top_modules();
    let n = nodes.len();
    let idx = |s: &str| nodes.iter().position(|x| *x == s);
    let mut reach = vec![vec![false; n]; n];
    for (a, b, _, _) in edges {
        if let (Some(i), Some(j)) = (idx(a), idx(b)) {
            reach[i][j] = true;
        }
    }
    for k in 0..n {
        for i in 0..n {
            for j in 0..n {
                reach[i][j] = reach[i][j] || (reach[i][k] && reach[k][j]);
            }
        }
    }
    let mut out = Vec::new();
    let mut seen = vec![false; n];
    for i in 0..n {
        if seen[i] || !reach[i][i] {
            continue;
        }
        let members: Vec<usize> = (0..n).filter(|&j| reach[i][j] && reach[j][i]).collect();
        for &j in &members {
            seen[j] = true;
        }
        let names: Vec<&str> = members.iter().map(|&j| nodes[j]).collect();
        if names.len() == 2 && (allowed(names[0], names[1]) || allowed(names[1], names[0])) {
            continue;
        }
        let inside: Vec<&Use> = edges
            .iter()
            .filter(|e| names.contains(&e.0.as_str()) && names.contains(&e.1.as_str()))
            .collect();
        let uses: Vec<String> = inside
            .iter()
            .map(|(a, b, f, l)| format!("`{a}` uses `{b}` at {}:{l}", f.display()))
            .collect();
        let quoted: Vec<String> = names.iter().map(|s| format!("`{s}`")).collect();
        let message = format!(
            "import circle in `{}` between {}: {}",
            c.name,
            quoted.join(", "),
            uses.join("; ")
        );
        let (file, line) = inside
            .first()
            .map_or((PathBuf::new(), 0), |e| (e.2.clone(), e.3));
        out.push(Violation {
            file,
            line,
            rule: Rule::ImportCircle,
            message,
        });
    }
    out
}
