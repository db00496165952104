//! No module imports one that imports it back (ARCHITECTURE §2.1), in any crate of the
//! workspace, no method imports another method, and `methods::common`'s kits build on its
//! framework only.
//!
//! The scan reads every crate's module tree from its root file (`src/lib.rs`, `src/main.rs`)
//! and the imports of every module (`use` declarations, `pub use` re-exports and paths written
//! inline such as `crate::isolate::phase::enter(…)`), resolves each to the module that defines
//! what it names, and reports every cycle of the resulting graph with the modules on it and
//! the imports that close it. How paths resolve: `resolve.rs`; the scanner's own tests:
//! `scanner_tests.rs`.

mod cycles;
mod folders;
mod lexer;
mod resolve;
mod tree;

#[cfg(test)]
mod scanner_tests;

use std::path::{Path, PathBuf};

/// A crate of the workspace: its name and root file.
struct Crate {
    name: String,
    root: PathBuf,
}

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The `members = [...]` of the workspace manifest, and the root package itself.
fn package_dirs(ws: &Path) -> Vec<PathBuf> {
    let manifest = std::fs::read_to_string(ws.join("Cargo.toml")).expect("workspace Cargo.toml");
    let members = manifest
        .lines()
        .find(|l| l.trim_start().starts_with("members"))
        .expect("a members list on one line");
    let mut dirs = vec![ws.to_path_buf()];
    for m in members.split('"').skip(1).step_by(2) {
        match m.strip_suffix("/*") {
            Some(parent) => {
                let mut found: Vec<PathBuf> = std::fs::read_dir(ws.join(parent))
                    .expect("member glob")
                    .flatten()
                    .map(|e| e.path())
                    .filter(|p| p.join("Cargo.toml").exists())
                    .collect();
                found.sort();
                dirs.extend(found);
            }
            None => dirs.push(ws.join(m)),
        }
    }
    dirs
}

/// The package's name (the first `name = "…"` of its manifest).
fn package_name(dir: &Path) -> String {
    let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).expect("package Cargo.toml");
    manifest
        .lines()
        .find_map(|l| l.trim().strip_prefix("name = \"")?.strip_suffix('"'))
        .expect("a package name")
        .to_string()
}

/// Every library and binary crate of the workspace (`src/lib.rs`, `src/main.rs`, `src/bin/*.rs`).
fn crates() -> Vec<Crate> {
    let mut out = Vec::new();
    for dir in package_dirs(&workspace()) {
        let name = package_name(&dir);
        let src = dir.join("src");
        let mut roots: Vec<PathBuf> = vec![src.join("lib.rs"), src.join("main.rs")];
        if let Ok(bins) = std::fs::read_dir(src.join("bin")) {
            roots.extend(bins.flatten().map(|e| e.path()));
        }
        for root in roots.into_iter().filter(|r| r.is_file()) {
            let kind = root.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            let label = match kind {
                "lib" => name.clone(),
                "main" => format!("{name} (bin)"),
                bin => format!("{name} (bin {bin})"),
            };
            out.push(Crate { name: label, root });
        }
    }
    out
}

fn read(path: &Path) -> Option<String> {
    std::fs::read_to_string(path).ok()
}

/// Paths relative to the workspace, for messages.
fn relative(ms: &mut [tree::Module]) {
    let ws = workspace();
    for m in ms {
        if let Ok(r) = m.file.strip_prefix(&ws) {
            m.file = r.to_path_buf();
        }
    }
}

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let crates = crates();
    let names: Vec<&str> = crates.iter().map(|c| c.name.as_str()).collect();
    for expected in [
        "scenes",
        "harness",
        "methods",
        "report",
        "experiments",
        "scatterbench (bin)",
        "external-method",
    ] {
        assert!(
            names.contains(&expected),
            "crate {expected} not scanned: {names:?}"
        );
    }
    let mut report = String::new();
    for c in &crates {
        let mut ms = tree::modules(&c.root, &read).unwrap_or_else(|e| panic!("{}: {e}", c.name));
        relative(&mut ms);
        let edges = resolve::edges(&ms);
        if c.name == "harness" {
            // The scan must see the crate it guards: a broken reader would pass vacuously.
            assert!(
                ms.len() > 30 && edges.len() > 100,
                "{} modules, {} edges",
                ms.len(),
                edges.len()
            );
        }
        for cycle in cycles::cycles(ms.len(), &edges) {
            report += &cycles::describe(&c.name, &ms, &cycle);
        }
    }
    assert!(report.is_empty(), "import cycles:\n{report}");
}

/// The `methods` crate's module tree, paths relative to the workspace.
fn methods_modules() -> Vec<tree::Module> {
    let krate = crates()
        .into_iter()
        .find(|c| c.name == "methods")
        .expect("methods");
    let mut ms = tree::modules(&krate.root, &read).expect("methods crate");
    relative(&mut ms);
    ms
}

#[test]
fn no_method_imports_another_method() {
    let ms = methods_modules();
    let crossings = folders::crossings(&ms, &resolve::edges(&ms), "common");
    assert!(
        ms[0].children.len() > 5,
        "methods has {} top-level modules",
        ms[0].children.len()
    );
    assert!(
        crossings.is_empty(),
        "a method imports another method (shared code belongs in common/):\n{}",
        crossings.join("\n")
    );
}

#[test]
fn common_kits_build_on_the_framework_only() {
    let ms = methods_modules();
    let edges = resolve::edges(&ms);
    let kits = ["shadow_volumes", "epipolar", "particles"];
    // Not vacuous: every kit is a folder of modules, and each imports the framework.
    for kit in kits {
        let in_kit = |m: usize| ms[m].path.len() > 2 && ms[m].path[..2] == ["common", kit];
        let framework = |m: usize| {
            let p = &ms[m].path;
            p.len() == 2 && p[0] == "common" && !kits.contains(&p[1].as_str())
        };
        let uses = edges.iter().filter(|e| in_kit(e.from) && framework(e.to)).count();
        assert!(uses > 0, "common::{kit}: no module of it imports the framework");
    }
    let crossings = folders::kit_crossings(&ms, &edges, "common", &kits);
    assert!(
        crossings.is_empty(),
        "the framework imports a kit, or a kit another kit:\n{}",
        crossings.join("\n")
    );
}
