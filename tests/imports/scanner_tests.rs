//! The scanner on small synthetic crates: what it must find and what it must let pass.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::cycles::{cycles, describe};
use crate::folders::crossings;
use crate::resolve::{Edge, edges};
use crate::tree::{Module, modules};

/// The modules and edges of a crate made of `files` (path → text), rooted at `src/lib.rs`.
fn scan(files: &[(&str, &str)]) -> (Vec<Module>, Vec<Edge>) {
    let files: BTreeMap<PathBuf, String> = files
        .iter()
        .map(|(p, t)| (PathBuf::from(p), t.to_string()))
        .collect();
    let read = |p: &Path| files.get(p).cloned();
    let ms = modules(Path::new("src/lib.rs"), &read).unwrap_or_else(|e| panic!("{e}"));
    let es = edges(&ms);
    (ms, es)
}

/// Edges as `from -> to` with module paths joined by `::` ("" is the crate root).
fn pairs(ms: &[Module], es: &[Edge]) -> Vec<String> {
    let mut v: Vec<String> = es
        .iter()
        .map(|e| {
            format!(
                "{} -> {}",
                ms[e.from].path.join("::"),
                ms[e.to].path.join("::")
            )
        })
        .collect();
    v.dedup();
    v
}

fn cycle_modules(ms: &[Module], es: &[Edge]) -> Vec<Vec<String>> {
    cycles(ms.len(), es)
        .iter()
        .map(|c| c.modules.iter().map(|&m| ms[m].path.join("::")).collect())
        .collect()
}

#[test]
fn a_cycle_between_siblings_is_found_with_its_lines() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "mod a;\nmod b;\n"),
        ("src/a.rs", "use crate::b::B;\npub struct A;\n"),
        (
            "src/b.rs",
            "pub struct B;\nfn f() -> super::a::A { todo!() }\n",
        ),
    ]);
    assert_eq!(pairs(&ms, &es), ["a -> b", "b -> a"]);
    let found = cycles(ms.len(), &es);
    assert_eq!(found.len(), 1);
    let text = describe("demo", &ms, &found[0]);
    assert!(text.contains("src/a.rs:1: crate::b::B"), "{text}");
    assert!(text.contains("src/b.rs:2: super::a::A"), "{text}");
}

#[test]
fn a_dag_passes_and_re_exports_lead_to_the_defining_module() {
    let (ms, es) = scan(&[
        (
            "src/lib.rs",
            "pub mod a;\npub mod b;\npub mod c;\npub use c::C;\n",
        ),
        (
            "src/a.rs",
            "use crate::C;\nuse crate::b::B;\npub struct A(B, C);\n",
        ),
        ("src/b.rs", "pub struct B(crate::c::C);\n"),
        ("src/c.rs", "pub struct C;\n"),
    ]);
    // `crate::C` is c's, not the root's: the root re-exporting c is no cycle with a.
    assert_eq!(pairs(&ms, &es), [" -> c", "a -> c", "a -> b", "b -> c"]);
    assert!(cycles(ms.len(), &es).is_empty());
}

#[test]
fn super_resolves_to_the_parent_and_repeats() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "mod top;\nmod x;\n"),
        ("src/top.rs", "pub fn t() {}\n"),
        ("src/x/mod.rs", "mod y;\nmod z;\n"),
        (
            "src/x/y.rs",
            "use super::z::Z;\nfn f() { super::super::top::t(); }\n",
        ),
        ("src/x/z.rs", "pub struct Z;\n"),
    ]);
    assert_eq!(pairs(&ms, &es), ["x::y -> x::z", "x::y -> top"]);
}

#[test]
fn mod_rs_and_name_rs_folders_both_hold_children() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "mod p;\nmod q;\n"),
        ("src/p/mod.rs", "mod inner;\n"),
        (
            "src/p/inner.rs",
            "pub use crate::q::inner::Q;\npub struct P;\n",
        ),
        ("src/q.rs", "pub mod inner;\n"),
        ("src/q/inner.rs", "pub struct Q(crate::p::inner::P);\n"),
    ]);
    let files: Vec<&Path> = ms.iter().map(|m| m.file.as_path()).collect();
    assert!(files.contains(&Path::new("src/p/inner.rs")), "{files:?}");
    assert!(files.contains(&Path::new("src/q/inner.rs")), "{files:?}");
    assert_eq!(cycle_modules(&ms, &es), [["p::inner", "q::inner"]]);
}

#[test]
fn inline_modules_paths_comments_and_strings() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "mod a;\nmod b;\n"),
        (
            "src/a.rs",
            "// crate::b::g is only mentioned\nfn f() -> &'static str { crate::b::g(); \"crate::b::h\" }\n\
             #[cfg(test)]\nmod tests {\n    use super::*;\n    fn t() { f(); }\n}\n",
        ),
        ("src/b.rs", "pub fn g() {}\npub fn h() {}\n"),
    ]);
    assert_eq!(pairs(&ms, &es), ["a -> b", "a::tests -> a"]);
    assert!(cycles(ms.len(), &es).is_empty());
    assert_eq!(es[0].line, 2);
}

#[test]
fn a_parent_re_exporting_a_child_that_globs_the_parent_is_a_cycle() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "mod run;\n"),
        (
            "src/run/mod.rs",
            "mod frame;\npub use frame::render;\npub struct Config;\n",
        ),
        (
            "src/run/frame.rs",
            "use super::*;\npub fn render(_: &Config) {}\n",
        ),
    ]);
    assert_eq!(cycle_modules(&ms, &es), [["run", "run::frame"]]);
}

#[test]
fn a_module_alias_is_no_edge_but_paths_through_it_are() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "mod r;\nmod user;\n"),
        ("src/r/mod.rs", "pub mod cache;\nuse crate::user::U;\n"),
        ("src/r/cache.rs", "pub fn get() {}\n"),
        (
            "src/user.rs",
            "use crate::r::{self};\npub struct U;\nfn f() { r::cache::get(); }\n",
        ),
    ]);
    assert_eq!(pairs(&ms, &es), ["r -> user", "user -> r::cache"]);
    assert!(cycles(ms.len(), &es).is_empty());
}

#[test]
fn path_attributes_name_the_file() {
    let (ms, _) = scan(&[
        ("src/lib.rs", "mod x;\n"),
        (
            "src/x.rs",
            "#[cfg(test)]\n#[path = \"x_tests.rs\"]\nmod tests;\n",
        ),
        ("src/x_tests.rs", "use super::*;\n"),
    ]);
    assert_eq!(ms[2].file, Path::new("src/x_tests.rs"));
    assert_eq!(ms[2].path, ["x", "tests"]);
}

#[test]
fn a_missing_module_file_is_an_error_naming_both_candidates() {
    let files: BTreeMap<PathBuf, String> =
        [(PathBuf::from("src/lib.rs"), "mod gone;".to_string())].into();
    let read = |p: &Path| files.get(p).cloned();
    let err = modules(Path::new("src/lib.rs"), &read).unwrap_err();
    assert!(
        err.contains("src/gone.rs") && err.contains("src/gone/mod.rs"),
        "{err}"
    );
}

#[test]
fn one_method_folder_importing_another_is_reported_common_is_not() {
    let (ms, es) = scan(&[
        ("src/lib.rs", "pub mod common;\npub mod m1;\npub mod m2;\n"),
        ("src/common/mod.rs", "pub struct Shared;\n"),
        ("src/m1/mod.rs", "pub mod table;\n"),
        ("src/m1/table.rs", "pub struct Table;\n"),
        (
            "src/m2/mod.rs",
            "use crate::common::Shared;\nuse crate::m1::table::Table;\n",
        ),
    ]);
    let found = crossings(&ms, &es, "common");
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains("m2 -> m1::table"), "{found:?}");
    assert!(found[0].contains("src/m2/mod.rs:2"), "{found:?}");
}
