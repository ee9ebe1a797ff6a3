//! The workspace as the rules see it: its crates (from the manifests), each
//! crate's module tree (from its source files), and the tables of
//! `ARCHITECTURE.md`.

use std::fs;
use std::path::{Path, PathBuf};

use crate::source::{Item, Kind, Vis, items, tokens};

/// What a crate builds, which decides the rules that apply to its root.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrateKind {
    /// A Rust library (`src/lib.rs`).
    Library,
    /// A binary (`src/main.rs` and no library).
    Binary,
    /// A library built as a `cdylib`: the Python extension.
    Extension,
}

/// A dependency of a crate on another crate of the workspace.
#[derive(Debug, Clone)]
pub struct Dependency {
    /// The crate depended on (its package name).
    pub name: String,
    /// The manifest's line that names it.
    pub line: usize,
}

/// One module: a file, or an inline `mod name { ... }` inside one.
#[derive(Debug, Clone)]
pub struct Module {
    /// Its path from the crate root (empty for the root).
    pub path: Vec<String>,
    /// Its file, relative to the workspace root.
    pub file: PathBuf,
    /// Whether every module from the root to it is declared `pub`.
    pub public: bool,
    /// Whether it (or a module around it) is under `#[cfg(test)]`.
    pub test: bool,
    /// Whether it is written inline in its parent's file.
    pub inline: bool,
    /// Whether some of its child modules are files of their own.
    pub has_file_children: bool,
    /// Its items.
    pub items: Vec<Item>,
}

impl Module {
    /// The names of its child modules (inline or files), test ones included.
    pub fn children(&self) -> impl Iterator<Item = &str> {
        self.items.iter().filter_map(|it| match &it.kind {
            Kind::Mod { name, .. } => Some(name.as_str()),
            _ => None,
        })
    }

    /// The module's name for messages: `crate` for the root.
    pub fn display(&self) -> String {
        if self.path.is_empty() {
            "the crate root".to_owned()
        } else {
            format!("`{}`", self.path.join("::"))
        }
    }
}

/// A crate of the workspace.
#[derive(Debug, Clone)]
pub struct Crate {
    /// Its package name.
    pub name: String,
    /// Its folder, relative to the workspace root (empty for the root).
    pub dir: PathBuf,
    /// Its manifest, relative to the workspace root.
    pub manifest: PathBuf,
    /// What it builds.
    pub kind: CrateKind,
    /// Its `[dependencies]` on workspace crates.
    pub deps: Vec<Dependency>,
    /// Its modules, the root first.
    pub modules: Vec<Module>,
}

impl Crate {
    /// The module at `path`, if there is one.
    pub fn module(&self, path: &[String]) -> Option<&Module> {
        self.modules.iter().find(|m| m.path == path)
    }

    /// The root module.
    pub fn root(&self) -> Option<&Module> {
        self.modules.first()
    }

    /// Its top-level modules that are not tests.
    pub fn top_modules(&self) -> Vec<&str> {
        self.modules
            .iter()
            .filter(|m| m.path.len() == 1 && !m.test)
            .map(|m| m.path[0].as_str())
            .collect()
    }
}

/// The workspace: its root, its crates and its `ARCHITECTURE.md`.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// The folder holding the root manifest.
    pub root: PathBuf,
    /// The member crates (the root package included, if it has one).
    pub crates: Vec<Crate>,
    /// The text of `ARCHITECTURE.md` (empty if there is none).
    pub doc: String,
}

/// A file's text, or an error naming it.
pub fn read(path: &Path) -> Result<String, String> {
    fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The workspace at `root`: the root manifest's `members` and, if it has a
/// `[package]`, the root package.
pub fn load(root: &Path) -> Result<Workspace, String> {
    let manifest = read(&root.join("Cargo.toml"))?;
    let mut dirs = Vec::new();
    if sections(&manifest).any(|(s, _, _)| s == "package") {
        dirs.push(PathBuf::new());
    }
    for member in members(&manifest) {
        match member.strip_suffix("/*") {
            // `crates/*`: every folder with a manifest.
            Some(parent) => {
                let mut found: Vec<PathBuf> = fs::read_dir(root.join(parent))
                    .map_err(|e| format!("{parent}: {e}"))?
                    .filter_map(Result::ok)
                    .map(|e| Path::new(parent).join(e.file_name()))
                    .filter(|d| root.join(d).join("Cargo.toml").is_file())
                    .collect();
                found.sort();
                dirs.extend(found);
            }
            None => dirs.push(PathBuf::from(member)),
        }
    }
    let mut crates = Vec::new();
    for dir in dirs {
        crates.push(load_crate(root, &dir)?);
    }
    let names: Vec<String> = crates.iter().map(|c| c.name.clone()).collect();
    for c in &mut crates {
        c.deps.retain(|d| names.contains(&d.name));
    }
    let doc = read(&root.join("ARCHITECTURE.md")).unwrap_or_default();
    Ok(Workspace {
        root: root.to_owned(),
        crates,
        doc,
    })
}

/// The strings of the root manifest's `members = [...]`.
fn members(manifest: &str) -> Vec<String> {
    let Some(at) = manifest.find("\nmembers") else {
        return Vec::new();
    };
    let rest = &manifest[at..];
    let list = rest.split_once('[').map_or("", |(_, r)| r);
    let list = list.split_once(']').map_or("", |(l, _)| l);
    list.lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(|l| l.split(','))
        .map(|s| s.trim().trim_matches('"').to_owned())
        .filter(|s| !s.is_empty())
        .collect()
}

/// The lines of a manifest, each with its section's header (`[a.b]` as
/// `a.b`) and its line number.
fn sections(manifest: &str) -> impl Iterator<Item = (String, usize, &str)> {
    let mut section = String::new();
    manifest.lines().enumerate().filter_map(move |(k, line)| {
        let t = line.trim();
        if t.starts_with('[') && !t.starts_with("[[") {
            section = t.trim_matches(|c| c == '[' || c == ']').trim().to_owned();
            return None;
        }
        if t.starts_with("[[") {
            section = t.to_owned();
            return None;
        }
        Some((section.clone(), k + 1, t))
    })
}

/// A crate from its manifest and its source files.
fn load_crate(root: &Path, dir: &Path) -> Result<Crate, String> {
    let manifest_path = dir.join("Cargo.toml");
    let text = read(&root.join(&manifest_path))?;
    let mut name = String::new();
    let mut deps = Vec::new();
    let mut cdylib = false;
    for (section, line, t) in sections(&text) {
        let key = t.split(['=', '.']).next().unwrap_or("").trim();
        if section == "package" && key == "name" {
            name = value(t);
        }
        if section == "lib" && key == "crate-type" && t.contains("\"cdylib\"") {
            cdylib = true;
        }
        let is_deps = section == "dependencies"
            || (section.starts_with("target.") && section.ends_with(".dependencies"));
        if is_deps && !key.is_empty() && !t.starts_with('#') {
            let renamed = t.split_once("package").map(|(_, r)| value(r));
            let name = renamed.unwrap_or_else(|| key.to_owned());
            deps.push(Dependency { name, line });
        }
        let table = section.strip_prefix("dependencies.");
        if let Some(dep) = table.filter(|d| !deps.iter().any(|x: &Dependency| x.name == *d)) {
            deps.push(Dependency {
                name: dep.to_owned(),
                line,
            });
        }
    }
    if name.is_empty() {
        return Err(format!("{}: no [package] name", manifest_path.display()));
    }
    let src = dir.join("src");
    let (root_file, kind) = if root.join(src.join("lib.rs")).is_file() {
        let kind = if cdylib {
            CrateKind::Extension
        } else {
            CrateKind::Library
        };
        (src.join("lib.rs"), kind)
    } else {
        (src.join("main.rs"), CrateKind::Binary)
    };
    let mut modules = Vec::new();
    load_module(
        root,
        &root_file,
        &src,
        Vec::new(),
        (true, false),
        &mut modules,
    )?;
    Ok(Crate {
        name,
        dir: dir.to_owned(),
        manifest: manifest_path,
        kind,
        deps,
        modules,
    })
}

/// The string after the first `=` of a `key = "value"` line, unquoted.
fn value(t: &str) -> String {
    let v = t.split_once('=').map_or("", |(_, v)| v).trim();
    let v = v.strip_prefix('"').unwrap_or(v);
    v.split('"').next().unwrap_or("").to_owned()
}

/// A file module at `path` and, after it, its descendants; `children_dir`
/// is where its child files live. `(public, test)` are inherited.
fn load_module(
    root: &Path,
    file: &Path,
    children_dir: &Path,
    path: Vec<String>,
    (public, test): (bool, bool),
    out: &mut Vec<Module>,
) -> Result<(), String> {
    let text = read(&root.join(file))?;
    let its = items(&tokens(&text));
    add_module(
        root,
        file,
        children_dir,
        path,
        (public, test, false),
        its,
        out,
    )
}

/// Adds one module (file or inline) and its descendants to `out`.
fn add_module(
    root: &Path,
    file: &Path,
    children_dir: &Path,
    path: Vec<String>,
    (public, test, inline): (bool, bool, bool),
    its: Vec<Item>,
    out: &mut Vec<Module>,
) -> Result<(), String> {
    let mut children = Vec::new();
    for it in &its {
        if let Kind::Mod { name, body } = &it.kind {
            let mut p = path.clone();
            p.push(name.clone());
            let flags = (public && it.vis == Vis::Public, test || it.test);
            children.push((p, body.clone(), flags, name.clone()));
        }
    }
    let has_file_children = children.iter().any(|c| c.1.is_none());
    out.push(Module {
        path,
        file: file.to_owned(),
        public,
        test,
        inline,
        has_file_children,
        items: its,
    });
    for (p, body, (pb, ts), name) in children {
        let dir = children_dir.join(&name);
        match body {
            Some(body) => {
                add_module(root, file, &dir, p, (pb, ts, true), body, out)?;
            }
            None => {
                let flat = children_dir.join(format!("{name}.rs"));
                let nested = dir.join("mod.rs");
                if root.join(&flat).is_file() {
                    load_module(root, &flat, &dir, p, (pb, ts), out)?;
                } else if root.join(&nested).is_file() {
                    load_module(root, &nested, &dir, p, (pb, ts), out)?;
                }
            }
        }
    }
    Ok(())
}

/// A row of a Markdown table, split into trimmed cells; `None` for a line
/// that is not a row or is the header's rule (`|---|`).
fn row(line: &str) -> Option<Vec<String>> {
    let t = line.trim();
    if !t.starts_with('|') || t.chars().all(|c| matches!(c, '|' | '-' | ':' | ' ')) {
        return None;
    }
    let inner = t.trim_start_matches('|').trim_end_matches('|');
    Some(inner.split('|').map(|c| c.trim().to_owned()).collect())
}

/// The `` `quoted` `` words of a cell, in order.
pub fn quoted(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_owned)
        .collect()
}

/// A row of the crate table: the crate and the workspace crates it depends on.
#[derive(Debug, Clone)]
pub struct CrateRow {
    /// The crate (first quoted word of the first cell).
    pub name: String,
    /// The quoted words of the "depends on" cell.
    pub depends_on: Vec<String>,
    /// The row's line in `ARCHITECTURE.md`.
    pub line: usize,
}

/// The rows of the table whose header has a `crate` and a `depends on` column.
pub fn crate_table(doc: &str) -> Vec<CrateRow> {
    let mut out = Vec::new();
    let mut column = None;
    for (k, line) in doc.lines().enumerate() {
        let Some(cells) = row(line) else {
            if !line.trim().starts_with('|') {
                column = None;
            }
            continue;
        };
        match column {
            None if cells.first().is_some_and(|c| c == "crate") => {
                column = cells.iter().position(|c| c == "depends on");
            }
            Some(col) => {
                let name = quoted(&cells[0]).into_iter().next().unwrap_or_default();
                let depends_on = cells.get(col).map(|c| quoted(c)).unwrap_or_default();
                out.push(CrateRow {
                    name,
                    depends_on,
                    line: k + 1,
                });
            }
            None => {}
        }
    }
    out
}

/// A crate's module table: the modules in import order, each with its line.
#[derive(Debug, Clone)]
pub struct ModuleTable {
    /// The crate, from the section's heading (`## parasils-kin`).
    pub crate_name: String,
    /// The modules in the order written (left to right, top to bottom).
    pub modules: Vec<(String, usize)>,
}

/// The first `| module | ... |` table of each `## <crate>` section.
pub fn module_tables(doc: &str) -> Vec<ModuleTable> {
    let mut out: Vec<ModuleTable> = Vec::new();
    let mut section: Option<String> = None;
    let mut state = 0; // 0: before the table, 1: in it, 2: after it
    for (k, line) in doc.lines().enumerate() {
        if let Some(h) = line.strip_prefix("## ") {
            let word = h.split_whitespace().next().unwrap_or("").trim_matches('`');
            section = Some(word.to_owned());
            state = 0;
            continue;
        }
        let Some(name) = &section else { continue };
        match (state, row(line)) {
            (0, Some(cells)) if cells.first().is_some_and(|c| c == "module") => {
                out.push(ModuleTable {
                    crate_name: name.clone(),
                    modules: Vec::new(),
                });
                state = 1;
            }
            (1, Some(cells)) => {
                if let Some(t) = out.last_mut() {
                    let names = cells.first().map(|c| quoted(c)).unwrap_or_default();
                    t.modules.extend(names.into_iter().map(|n| (n, k + 1)));
                }
            }
            (1, None) if !line.trim().starts_with('|') => state = 2,
            _ => {}
        }
    }
    out
}
