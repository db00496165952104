//! Imports between sibling folders: in `methods`, each method is a top-level folder module
//! (`methods/src/<id>/mod.rs`) and what two methods share belongs in `common/`, so an import
//! from one method's folder into another's is refused.

use crate::resolve::Edge;
use crate::tree::Module;

/// The top-level folder module (`<name>/mod.rs` under the crate root) holding module `m`.
fn folder(ms: &[Module], mut m: usize) -> Option<usize> {
    while let Some(p) = ms[m].parent {
        if p == 0 {
            return ms[m].file.ends_with("mod.rs").then_some(m);
        }
        m = p;
    }
    None
}

/// Every import from one top-level folder into another, neither being `shared`, in words.
pub fn crossings(ms: &[Module], edges: &[Edge], shared: &str) -> Vec<String> {
    let is_shared = |f: usize| ms[f].path == [shared];
    edges
        .iter()
        .filter_map(|e| {
            let (a, b) = (folder(ms, e.from)?, folder(ms, e.to)?);
            (a != b && !is_shared(a) && !is_shared(b)).then(|| {
                format!(
                    "  {} -> {}  ({}:{}: {})",
                    ms[e.from].path.join("::"),
                    ms[e.to].path.join("::"),
                    ms[e.from].file.display(),
                    e.line,
                    e.what
                )
            })
        })
        .collect()
}

/// Under `root` (`common`), the imports that break the kits' rule: the framework (every module
/// of `root` outside `kits`) never imports a kit, and no kit imports another.
pub fn kit_crossings(ms: &[Module], edges: &[Edge], root: &str, kits: &[&str]) -> Vec<String> {
    // Some(kit) for a kit's module, Some("") for the framework's, None outside `root`.
    let side = |m: usize| match ms[m].path.as_slice() {
        [r, k, ..] if r == root && kits.contains(&k.as_str()) => Some(k.as_str()),
        [r, ..] if r == root => Some(""),
        _ => None,
    };
    edges
        .iter()
        .filter_map(|e| {
            let (a, b) = (side(e.from)?, side(e.to)?);
            (a != b && !b.is_empty()).then(|| {
                let from = ms[e.from].path.join("::");
                let file = ms[e.from].file.display();
                format!("  {from} -> {}  ({file}:{}: {})", ms[e.to].path.join("::"), e.line, e.what)
            })
        })
        .collect()
}
