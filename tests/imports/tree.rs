//! A crate's module tree, read from its root file through `mod x;` declarations (`x.rs` or
//! `x/mod.rs` beside a `mod.rs`/crate root, `name/x.rs` or `name/x/mod.rs` beside `name.rs`,
//! or `#[path = "…"]`) and inline `mod x { … }` blocks. Per module: the names it defines at its
//! top level, its `use` declarations (anywhere in its code, `pub use` included) and the paths
//! written inline in its code (`crate::a::f()`, `super::T`, `child::g()`). A module's own
//! `mod x;` is a declaration, not an import.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::lexer::{Tok, Token, tokens};

/// One module: a file, or an inline `mod x { … }` inside one.
#[derive(Debug, Default)]
pub struct Module {
    /// Path from the crate root (empty for the root).
    pub path: Vec<String>,
    pub file: PathBuf,
    pub parent: Option<usize>,
    pub children: BTreeMap<String, usize>,
    /// Names of the items it defines (fn, struct, enum, trait, type, const, static, union,
    /// macro_rules!).
    pub items: BTreeSet<String>,
    pub uses: Vec<Use>,
    /// Paths of two or more segments written in its code outside `use`.
    pub paths: Vec<PathRef>,
    /// Where its files' `mod x;` children live.
    child_dir: PathBuf,
}

/// One leaf of a `use` tree: `use a::{b, c::*, d as e}` gives three.
#[derive(Clone, Debug, PartialEq)]
pub struct Use {
    pub path: Vec<String>,
    pub glob: bool,
    /// The name it binds (None for globs and `as _`).
    pub name: Option<String>,
    pub line: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub struct PathRef {
    pub path: Vec<String>,
    pub line: usize,
}

/// Reads a file's text; None when it does not exist.
pub type Read<'a> = &'a dyn Fn(&Path) -> Option<String>;

/// Every module of the crate whose root file is `root` (index 0 is the root).
pub fn modules(root: &Path, read: Read) -> Result<Vec<Module>, String> {
    let mut out = vec![Module {
        file: root.to_path_buf(),
        child_dir: root.parent().unwrap_or(Path::new("")).to_path_buf(),
        ..Module::default()
    }];
    let text = read(root).ok_or_else(|| format!("{}: cannot read", root.display()))?;
    scan(&mut out, 0, &tokens(&text), read)?;
    Ok(out)
}

/// Reads one module body (a whole file or the inside of an inline module's braces).
fn scan(ms: &mut Vec<Module>, m: usize, toks: &[Token], read: Read) -> Result<(), String> {
    let (mut i, mut depth) = (0, 0usize);
    let mut attr_path: Option<String> = None;
    while i < toks.len() {
        let ident = |k: usize| match toks.get(k).map(|t| &t.tok) {
            Some(Tok::Ident(s)) => Some(s.as_str()),
            _ => None,
        };
        match &toks[i].tok {
            Tok::Open => depth += 1,
            Tok::Close => depth = depth.saturating_sub(1),
            Tok::Punct('#') => {
                if let Some(p) = path_attribute(&toks[i..]) {
                    attr_path = Some(p);
                }
            }
            Tok::Ident(kw) if kw == "mod" && ident(i + 1).is_some() => {
                let name = ident(i + 1).expect("checked").to_string();
                match toks.get(i + 2).map(|t| &t.tok) {
                    Some(Tok::Open) => {
                        let end = matching_close(toks, i + 2);
                        let child = add_child(ms, m, &name, None);
                        scan(ms, child, &toks[i + 3..end], read)?;
                        i = end + 1;
                        attr_path = None;
                        continue;
                    }
                    _ => {
                        let (file, text) = module_file(&ms[m], &name, attr_path.take(), read)?;
                        let child = add_child(ms, m, &name, Some(file));
                        scan(ms, child, &tokens(&text), read)?;
                        i += 2;
                        continue;
                    }
                }
            }
            Tok::Ident(kw) if kw == "use" => {
                let end = (i..toks.len())
                    .find(|&k| toks[k].tok == Tok::Punct(';'))
                    .unwrap_or(toks.len());
                let mut leaves = Vec::new();
                use_tree(&toks[i + 1..end], &mut 0, &[], &mut leaves);
                ms[m].uses.extend(leaves);
                i = end + 1;
                continue;
            }
            Tok::Ident(kw) if depth == 0 && defines_item(kw) => {
                let name_at = if kw == "macro_rules" { i + 2 } else { i + 1 };
                if let Some(name) = ident(name_at).filter(|n| !is_keyword(n)) {
                    ms[m].items.insert(name.to_string());
                }
            }
            Tok::Ident(_) => {
                let after_dollar = i > 0 && toks[i - 1].tok == Tok::Punct('$');
                let (path, end) = inline_path(toks, i);
                if path.len() >= 2 && !after_dollar {
                    ms[m].paths.push(PathRef {
                        path,
                        line: toks[i].line,
                    });
                }
                i = end;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    Ok(())
}

fn defines_item(kw: &str) -> bool {
    matches!(
        kw,
        "fn" | "struct" | "enum" | "trait" | "type" | "const" | "static" | "union" | "macro_rules"
    )
}

fn is_keyword(s: &str) -> bool {
    matches!(s, "fn" | "mut" | "unsafe" | "async" | "extern")
}

/// `#[path = "…"]` at the start of `toks`, if that is what they hold.
fn path_attribute(toks: &[Token]) -> Option<String> {
    match toks
        .get(1..5)
        .map(|t| t.iter().map(|t| &t.tok).collect::<Vec<_>>())
    {
        Some(t) => match t.as_slice() {
            [Tok::Punct('['), Tok::Ident(p), Tok::Punct('='), Tok::Str(s)] if p == "path" => {
                Some(s.clone())
            }
            _ => None,
        },
        None => None,
    }
}

/// Index of the `}` closing the `{` at `open`.
fn matching_close(toks: &[Token], open: usize) -> usize {
    let mut depth = 0;
    for (k, t) in toks.iter().enumerate().skip(open) {
        match t.tok {
            Tok::Open => depth += 1,
            Tok::Close => {
                depth -= 1;
                if depth == 0 {
                    return k;
                }
            }
            _ => {}
        }
    }
    toks.len()
}

/// A module declared inside `parent`: inline (`file: None`, its parent's file) or from a file.
fn add_child(ms: &mut Vec<Module>, parent: usize, name: &str, file: Option<PathBuf>) -> usize {
    let p = &ms[parent];
    let mut path = p.path.clone();
    path.push(name.to_string());
    let (file, child_dir) = match file {
        None => (p.file.clone(), p.child_dir.join(name)),
        Some(f) if f.file_name().is_some_and(|n| n == "mod.rs") => {
            let dir = f.parent().unwrap_or(Path::new("")).to_path_buf();
            (f, dir)
        }
        Some(f) => {
            let dir = f.with_extension("");
            (f, dir)
        }
    };
    ms.push(Module {
        path,
        file,
        parent: Some(parent),
        child_dir,
        ..Module::default()
    });
    let child = ms.len() - 1;
    ms[parent].children.insert(name.to_string(), child);
    child
}

/// The file of `mod name;` declared in `parent` (under `#[path]` when given) and its text.
fn module_file(
    parent: &Module,
    name: &str,
    attr_path: Option<String>,
    read: Read,
) -> Result<(PathBuf, String), String> {
    let candidates = match attr_path {
        // Relative to the directory of the file holding the declaration.
        Some(rel) => vec![parent.file.parent().unwrap_or(Path::new("")).join(rel)],
        None => vec![
            parent.child_dir.join(format!("{name}.rs")),
            parent.child_dir.join(name).join("mod.rs"),
        ],
    };
    for f in &candidates {
        if let Some(text) = read(f) {
            return Ok((f.clone(), text));
        }
    }
    let tried: Vec<String> = candidates.iter().map(|f| f.display().to_string()).collect();
    Err(format!(
        "{}: `mod {name};` but neither {} exists",
        parent.file.display(),
        tried.join(" nor ")
    ))
}

/// The path starting at `i` (`a::b::c`) and the index after it.
fn inline_path(toks: &[Token], i: usize) -> (Vec<String>, usize) {
    let mut path = Vec::new();
    let mut k = i;
    while let Some(Tok::Ident(s)) = toks.get(k).map(|t| &t.tok) {
        path.push(s.clone());
        match (
            toks.get(k + 1).map(|t| &t.tok),
            toks.get(k + 2).map(|t| &t.tok),
        ) {
            (Some(Tok::PathSep), Some(Tok::Ident(_))) => k += 2,
            _ => return (path, k + 1),
        }
    }
    (path, k.max(i + 1))
}

/// The leaves of a `use` tree (`toks` without `use` and `;`), with `prefix` before each.
fn use_tree(toks: &[Token], pos: &mut usize, prefix: &[String], out: &mut Vec<Use>) {
    let mut path = prefix.to_vec();
    while *pos < toks.len() {
        let line = toks[*pos].line;
        match &toks[*pos].tok {
            Tok::PathSep => *pos += 1,
            Tok::Punct('*') => {
                *pos += 1;
                out.push(Use {
                    path,
                    glob: true,
                    name: None,
                    line,
                });
                return;
            }
            Tok::Open => {
                *pos += 1;
                while *pos < toks.len() && toks[*pos].tok != Tok::Close {
                    if toks[*pos].tok == Tok::Punct(',') {
                        *pos += 1;
                        continue;
                    }
                    use_tree(toks, pos, &path, out);
                }
                *pos += 1;
                return;
            }
            Tok::Ident(s) => {
                if s != "self" || path.is_empty() {
                    path.push(s.clone());
                }
                *pos += 1;
                if toks.get(*pos).map(|t| &t.tok) == Some(&Tok::PathSep) {
                    continue;
                }
                let mut name = path.last().cloned();
                if let Some(Tok::Ident(kw)) = toks.get(*pos).map(|t| &t.tok)
                    && kw == "as"
                {
                    name = match toks.get(*pos + 1).map(|t| &t.tok) {
                        Some(Tok::Ident(alias)) => Some(alias.clone()),
                        _ => None,
                    };
                    *pos += 2;
                }
                out.push(Use {
                    path,
                    glob: false,
                    name: name.filter(|n| n != "_"),
                    line,
                });
                return;
            }
            _ => {
                *pos += 1;
                return;
            }
        }
    }
}
