//! Which module each import of a crate reaches: the import edges of its module graph.
//!
//! A path is resolved as rustc would for the cases this code base writes: `crate::`, `self::`,
//! `super::` (repeated), a child module's name, or a name the module binds with `use`; a first
//! segment that is none of these (`std`, `scenes`, a local type) leaves the crate and is not
//! an edge. The path is followed through child modules; its first item is then looked up
//! through re-exports (`pub use`, and glob imports that provide the name) to the module that
//! defines it, so `use crate::Gpu` depends on `gpu`, not on the crate root that re-exports it.
//! A `use` that only names a module (`use crate::reference::{self}`) is no edge by itself; the
//! paths written through it are.

use crate::tree::{Module, Use};

/// One import: module `from` uses something of module `to`, at `line` of `from`'s file.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    pub line: usize,
    /// The path as written (`crate::isolate::phase::enter`).
    pub what: String,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    Module(usize),
    /// An item (or something reached through it, like an enum variant) defined in a module.
    Item(usize),
}

/// Nesting limit of re-export chains (a cycle of `pub use` would otherwise never end).
const MAX_DEPTH: u32 = 32;

/// Every import edge between two different modules, in module then source order.
pub fn edges(ms: &[Module]) -> Vec<Edge> {
    let mut out = Vec::new();
    for (from, m) in ms.iter().enumerate() {
        for u in &m.uses {
            let to = match resolve(ms, from, &u.path, 0) {
                Some(Target::Item(t)) => t,
                Some(Target::Module(t)) if u.glob => t,
                _ => continue,
            };
            push(&mut out, from, to, u.line, &u.path);
        }
        for p in &m.paths {
            if let Some(Target::Item(to) | Target::Module(to)) = resolve(ms, from, &p.path, 0) {
                push(&mut out, from, to, p.line, &p.path);
            }
        }
    }
    out
}

fn push(out: &mut Vec<Edge>, from: usize, to: usize, line: usize, path: &[String]) {
    if from != to {
        out.push(Edge {
            from,
            to,
            line,
            what: path.join("::"),
        });
    }
}

/// What `path`, written in module `from`, reaches in this crate.
fn resolve(ms: &[Module], from: usize, path: &[String], depth: u32) -> Option<Target> {
    let (first, rest) = path.split_first()?;
    let (start, rest) = match first.as_str() {
        "crate" => (0, rest),
        "self" => (from, rest),
        "super" => {
            let mut m = ms[from].parent?;
            let mut rest = rest;
            while rest.first().is_some_and(|s| s == "super") {
                m = ms[m].parent?;
                rest = &rest[1..];
            }
            (m, rest)
        }
        name if ms[from].children.contains_key(name) => (from, path),
        name => match binding(&ms[from], name) {
            Some(u) if depth < MAX_DEPTH => match resolve(ms, from, &u.path, depth + 1)? {
                Target::Module(m) => (m, rest),
                item => return Some(item),
            },
            _ if ms[from].items.contains(name) => return Some(Target::Item(from)),
            _ => return None,
        },
    };
    walk(ms, start, rest, depth)
}

/// From module `m` down `path`: child modules, then the first item (through re-exports).
fn walk(ms: &[Module], mut m: usize, path: &[String], depth: u32) -> Option<Target> {
    for (k, seg) in path.iter().enumerate() {
        if let Some(&c) = ms[m].children.get(seg) {
            m = c;
            continue;
        }
        return match defining(ms, m, seg, depth) {
            Target::Module(next) => walk(ms, next, &path[k + 1..], depth + 1),
            item => Some(item),
        };
    }
    Some(Target::Module(m))
}

/// Where the name `name`, as seen in module `m`, is defined: `m` itself, or through its
/// named re-export or a glob import that provides it.
fn defining(ms: &[Module], m: usize, name: &str, depth: u32) -> Target {
    if depth >= MAX_DEPTH || ms[m].items.contains(name) {
        return Target::Item(m);
    }
    if let Some(u) = binding(&ms[m], name) {
        return resolve(ms, m, &u.path, depth + 1).unwrap_or(Target::Item(m));
    }
    for u in ms[m].uses.iter().filter(|u| u.glob) {
        if let Some(Target::Module(g)) = resolve(ms, m, &u.path, depth + 1)
            && provides(&ms[g], name)
        {
            return match ms[g].children.get(name) {
                Some(&c) => Target::Module(c),
                None => defining(ms, g, name, depth + 1),
            };
        }
    }
    Target::Item(m)
}

/// The named (non-glob) `use` of `m` that binds `name`.
fn binding<'a>(m: &'a Module, name: &str) -> Option<&'a Use> {
    m.uses
        .iter()
        .find(|u| !u.glob && u.name.as_deref() == Some(name))
}

fn provides(m: &Module, name: &str) -> bool {
    m.items.contains(name) || m.children.contains_key(name) || binding(m, name).is_some()
}
