//! Rust read as text: tokens without comments and literals, then the items
//! of a module (declarations, `use` trees, types) and the paths its code
//! names through `crate`, `super` and `self`.
//!
//! This is not a Rust parser: it knows the shape of items, not expressions.
//! What a macro writes (a path built by `macro_rules!`, an item from a
//! derive) is invisible to it, and so are `#[path]` attributes.

/// One token: an identifier, `::`, a punctuation character or a literal
/// (strings, characters and numbers, whose text is dropped).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Tok {
    /// An identifier or keyword (raw identifiers without their `r#`).
    Ident(String),
    /// `::`.
    PathSep,
    /// Any other punctuation character.
    Punct(char),
    /// A string, character or number literal.
    Lit,
}

/// A token and the line (from 1) it starts on.
#[derive(Debug, Clone)]
pub struct Token {
    /// The token.
    pub tok: Tok,
    /// Its line, from 1.
    pub line: usize,
}

impl Token {
    /// Whether this is the identifier `name`.
    pub fn is(&self, name: &str) -> bool {
        matches!(&self.tok, Tok::Ident(s) if s == name)
    }

    /// Whether this is the punctuation character `c`.
    pub fn is_punct(&self, c: char) -> bool {
        self.tok == Tok::Punct(c)
    }

    /// The identifier's text, if it is one.
    pub fn ident(&self) -> Option<&str> {
        match &self.tok {
            Tok::Ident(s) => Some(s),
            _ => None,
        }
    }
}

/// The tokens of `text`, comments (doc comments included) and the contents
/// of literals left out.
pub fn tokens(text: &str) -> Vec<Token> {
    let c: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    while i < c.len() {
        let ch = c[i];
        let start = line;
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            }
        } else if let Some(end) = raw_string_end(&c, i) {
            line += c[i..end].iter().filter(|&&x| x == '\n').count();
            i = end;
            out.push(Token {
                tok: Tok::Lit,
                line: start,
            });
        } else if ch == '"' || ((ch == 'b' || ch == 'c') && at(i + 1) == '"') {
            i += if ch == '"' { 1 } else { 2 };
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    i += 1;
                }
                line += usize::from(at(i) == '\n');
                i += 1;
            }
            i += 1;
            out.push(Token {
                tok: Tok::Lit,
                line: start,
            });
        } else if ch == '\'' || (ch == 'b' && at(i + 1) == '\'') {
            let q = if ch == '\'' { i } else { i + 1 };
            if at(q + 1) == '\\' {
                // An escaped character: up to the closing quote.
                i = q + 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
                out.push(Token {
                    tok: Tok::Lit,
                    line: start,
                });
            } else if at(q + 2) == '\'' {
                i = q + 3;
                out.push(Token {
                    tok: Tok::Lit,
                    line: start,
                });
            } else {
                // A lifetime: the quote, then its name as an identifier.
                out.push(Token {
                    tok: Tok::Punct('\''),
                    line: start,
                });
                i = q + 1;
            }
        } else if ch.is_ascii_digit() {
            while i < c.len()
                && (c[i].is_alphanumeric()
                    || c[i] == '_'
                    || (c[i] == '.' && at(i + 1).is_ascii_digit()))
            {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Lit,
                line: start,
            });
        } else if ch.is_alphabetic() || ch == '_' {
            if ch == 'r' && at(i + 1) == '#' {
                i += 2;
            }
            let s = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            let tok = Tok::Ident(c[s..i].iter().collect());
            out.push(Token { tok, line: start });
        } else if ch == ':' && at(i + 1) == ':' {
            i += 2;
            out.push(Token {
                tok: Tok::PathSep,
                line: start,
            });
        } else {
            i += 1;
            out.push(Token {
                tok: Tok::Punct(ch),
                line: start,
            });
        }
    }
    out
}

/// If a raw string (`r"..."`, `r#"..."#`, `br`, `cr`) starts at `i`, the
/// index just after it.
fn raw_string_end(c: &[char], i: usize) -> Option<usize> {
    let mut k = i;
    if matches!(c.get(k), Some('b' | 'c')) {
        k += 1;
    }
    if c.get(k) != Some(&'r') {
        return None;
    }
    k += 1;
    let mut hashes = 0;
    while c.get(k) == Some(&'#') {
        hashes += 1;
        k += 1;
    }
    if c.get(k) != Some(&'"') {
        return None;
    }
    k += 1;
    while k < c.len() {
        if c[k] == '"' && (1..=hashes).all(|h| c.get(k + h) == Some(&'#')) {
            return Some(k + 1 + hashes);
        }
        k += 1;
    }
    Some(c.len())
}

/// An item's visibility.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Vis {
    /// `pub`.
    Public,
    /// `pub(crate)`, `pub(super)`, `pub(in ...)`.
    Restricted,
    /// No `pub`.
    Private,
}

/// One path of a `use` tree, written out: `use a::{b, c::D as E}` gives
/// `a::b` and `a::c::D` (alias `E`).
#[derive(Debug, Clone)]
pub struct UsePath {
    /// The segments (`self` inside braces dropped: the path names the module).
    pub segs: Vec<String>,
    /// `as` name, if any (`_` included).
    pub alias: Option<String>,
    /// Whether the path ends in `*`.
    pub glob: bool,
}

impl UsePath {
    /// The name the path brings into scope (`None` for a glob).
    pub fn name(&self) -> Option<&str> {
        if self.glob {
            return None;
        }
        self.alias
            .as_deref()
            .or(self.segs.last().map(String::as_str))
    }
}

/// What an item is.
#[derive(Debug, Clone)]
pub enum Kind {
    /// `mod name;` (`body: None`) or `mod name { ... }`.
    Mod {
        /// The module's name.
        name: String,
        /// The items of an inline module.
        body: Option<Vec<Item>>,
    },
    /// `use ...;`
    Use(Vec<UsePath>),
    /// `struct`, `enum`, `union`, `trait` or `type`, by name.
    Type(String),
    /// `extern crate`.
    ExternCrate,
    /// Anything else (functions, impls, constants, macros), by its keyword.
    Other(String),
}

/// A path of the code that starts with `crate`, `super` or `self`.
#[derive(Debug, Clone)]
pub struct CodePath {
    /// The segments, the leading keyword included.
    pub segs: Vec<String>,
    /// Its line.
    pub line: usize,
}

/// An item of a module.
#[derive(Debug, Clone)]
pub struct Item {
    /// What it is.
    pub kind: Kind,
    /// Its visibility.
    pub vis: Vis,
    /// Whether a `#[cfg(...)]` naming `test` guards it.
    pub test: bool,
    /// The line of its first token (attributes excluded).
    pub line: usize,
    /// The `crate::`, `super::` and `self::` paths in its code (not in its
    /// `use` trees, nor in an inline module's items, which hold their own).
    pub paths: Vec<CodePath>,
}

/// The items of a file (or of an inline module's body); attributes, inner
/// and outer, are read only for `#[cfg(test)]`.
pub fn items(toks: &[Token]) -> Vec<Item> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < toks.len() {
        let mut test = false;
        // Attributes, outer and inner.
        while i < toks.len() && toks[i].is_punct('#') {
            let mut k = i + 1;
            if toks.get(k).is_some_and(|t| t.is_punct('!')) {
                k += 1;
            }
            let end = group_end(toks, k);
            let attr = &toks[k..end];
            let cfg = attr.get(1).is_some_and(|t| t.is("cfg"));
            if cfg && attr.iter().any(|t| t.is("test")) && !attr.iter().any(|t| t.is("not")) {
                test = true;
            }
            i = end;
        }
        if i >= toks.len() {
            break;
        }
        let line = toks[i].line;
        let mut vis = Vis::Private;
        if toks[i].is("pub") {
            vis = Vis::Public;
            i += 1;
            if toks.get(i).is_some_and(|t| t.is_punct('(')) {
                vis = Vis::Restricted;
                i = group_end(toks, i);
            }
        }
        let start = i;
        let Some(word) = toks.get(i).and_then(Token::ident).map(str::to_owned) else {
            // Stray punctuation (a `;` after a macro's braces): skip it.
            i += 1;
            continue;
        };
        let (kind, end) = match word.as_str() {
            "use" => {
                let end = item_end(toks, i, true);
                let mut paths = Vec::new();
                use_tree(
                    &toks[i + 1..end.saturating_sub(1)],
                    &mut Vec::new(),
                    &mut paths,
                );
                (Kind::Use(paths), end)
            }
            "mod" => {
                let name = toks
                    .get(i + 1)
                    .and_then(Token::ident)
                    .unwrap_or("")
                    .to_owned();
                if toks.get(i + 2).is_some_and(|t| t.is_punct('{')) {
                    let end = group_end(toks, i + 2);
                    let body = items(&toks[i + 3..end.saturating_sub(1)]);
                    (
                        Kind::Mod {
                            name,
                            body: Some(body),
                        },
                        end,
                    )
                } else {
                    (Kind::Mod { name, body: None }, item_end(toks, i, true))
                }
            }
            "struct" | "enum" | "union" | "trait" | "type" => {
                let name = toks
                    .get(i + 1)
                    .and_then(Token::ident)
                    .unwrap_or("")
                    .to_owned();
                (Kind::Type(name), item_end(toks, i, word == "type"))
            }
            "extern" if toks.get(i + 1).is_some_and(|t| t.is("crate")) => {
                (Kind::ExternCrate, item_end(toks, i, true))
            }
            "const" | "static"
                if !toks.get(i + 1).is_some_and(|t| {
                    ["fn", "unsafe", "async", "extern"].iter().any(|w| t.is(w))
                }) =>
            {
                (Kind::Other(word), item_end(toks, i, true))
            }
            _ => (Kind::Other(word), item_end(toks, i, false)),
        };
        let paths = match kind {
            Kind::Use(_) | Kind::Mod { .. } => Vec::new(),
            _ => code_paths(&toks[start..end]),
        };
        out.push(Item {
            kind,
            vis,
            test,
            line,
            paths,
        });
        i = end;
    }
    out
}

/// The index after the group (`(...)`, `[...]` or `{...}`) opening at `i`.
fn group_end(toks: &[Token], i: usize) -> usize {
    let mut depth = 0usize;
    let mut k = i;
    while k < toks.len() {
        match toks[k].tok {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return k + 1;
                }
            }
            _ => {}
        }
        k += 1;
    }
    toks.len()
}

/// The index after the item starting at `i`: its `;` at depth 0, or (unless
/// `semicolon_only`) the `}` that closes its body.
fn item_end(toks: &[Token], i: usize, semicolon_only: bool) -> usize {
    let mut depth = 0usize;
    let mut k = i;
    while k < toks.len() {
        match toks[k].tok {
            Tok::Punct(';') if depth == 0 => return k + 1,
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => {
                depth = depth.saturating_sub(1);
                if depth == 0 && toks[k].is_punct('}') && !semicolon_only {
                    return k + 1;
                }
            }
            _ => {}
        }
        k += 1;
    }
    toks.len()
}

/// The paths of a `use` tree (without `use` and `;`), after `prefix`.
fn use_tree(toks: &[Token], prefix: &mut Vec<String>, out: &mut Vec<UsePath>) {
    let depth_before = prefix.len();
    let mut k = 0;
    while k < toks.len() {
        match &toks[k].tok {
            Tok::PathSep => k += 1,
            Tok::Punct('*') => {
                out.push(UsePath {
                    segs: prefix.clone(),
                    alias: None,
                    glob: true,
                });
                k += 1;
            }
            Tok::Punct('{') => {
                let end = group_end(toks, k);
                for part in split_top(&toks[k + 1..end.saturating_sub(1)]) {
                    use_tree(part, prefix, out);
                }
                k = end;
            }
            Tok::Ident(s) => {
                let next_is_sep = toks.get(k + 1).is_some_and(|t| t.tok == Tok::PathSep);
                if next_is_sep {
                    prefix.push(s.clone());
                    k += 1;
                    continue;
                }
                let mut segs = prefix.clone();
                if s != "self" || segs.is_empty() {
                    segs.push(s.clone());
                }
                let mut alias = None;
                if toks.get(k + 1).is_some_and(|t| t.is("as")) {
                    alias = toks.get(k + 2).and_then(Token::ident).map(str::to_owned);
                    if toks.get(k + 2).is_some_and(|t| t.is_punct('_')) {
                        alias = Some("_".to_owned());
                    }
                }
                out.push(UsePath {
                    segs,
                    alias,
                    glob: false,
                });
                break;
            }
            _ => k += 1,
        }
    }
    prefix.truncate(depth_before);
}

/// `a, b::{c, d}, e` split at its top-level commas.
fn split_top(toks: &[Token]) -> Vec<&[Token]> {
    let mut parts = Vec::new();
    let (mut depth, mut from) = (0usize, 0);
    for (k, t) in toks.iter().enumerate() {
        match t.tok {
            Tok::Punct('{') => depth += 1,
            Tok::Punct('}') => depth = depth.saturating_sub(1),
            Tok::Punct(',') if depth == 0 => {
                parts.push(&toks[from..k]);
                from = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&toks[from..]);
    parts.into_iter().filter(|p| !p.is_empty()).collect()
}

/// Every path of `toks` that starts with `crate`, `super` or `self` and
/// continues with `::` (`$crate` in macros and `pub(crate)` excluded).
fn code_paths(toks: &[Token]) -> Vec<CodePath> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < toks.len() {
        let starts = ["crate", "super", "self"].iter().any(|w| toks[k].is(w))
            && toks.get(k + 1).is_some_and(|t| t.tok == Tok::PathSep)
            && !(k > 0 && toks[k - 1].is_punct('$'))
            && !(k > 0 && toks[k - 1].tok == Tok::PathSep);
        if !starts {
            k += 1;
            continue;
        }
        let line = toks[k].line;
        let mut segs = Vec::new();
        while let Some(s) = toks.get(k).and_then(Token::ident) {
            segs.push(s.to_owned());
            if toks.get(k + 1).is_some_and(|t| t.tok == Tok::PathSep) {
                k += 2;
            } else {
                k += 1;
                break;
            }
        }
        out.push(CodePath { segs, line });
    }
    out
}
