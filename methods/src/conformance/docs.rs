//! What a method says about itself: a unique id, a README and a `//!` module doc
//! (docs/ADDING_A_METHOD.md), a paper and a summary, and a medium that agrees with `support`.

use std::collections::BTreeSet;

use harness::method::{Method, Support};

/// A README is a Markdown document with a title and more than a stub's worth of text.
const README_MIN_BYTES: usize = 200;

/// One line per problem of any method in `registry`.
pub fn problems(registry: &[&dyn Method]) -> Vec<String> {
    let mut out = Vec::new();
    let mut ids = BTreeSet::new();
    for m in registry {
        let info = m.info();
        let id = info.id;
        if !ids.insert(id) {
            out.push(format!("{id}: registered twice (ids must be unique)"));
        }
        if !(info.readme.trim_start().starts_with('#') && info.readme.len() > README_MIN_BYTES) {
            out.push(format!(
                "{id}: README.md missing or a stub (a '#' title and more than {README_MIN_BYTES} bytes)"
            ));
        }
        if !info.source.starts_with("//!") {
            out.push(format!(
                "{id}: its source (`MethodInfo::source`) does not start with a //! module doc"
            ));
        }
        if info.paper.is_empty() || info.summary.is_empty() {
            out.push(format!("{id}: empty paper or summary"));
        }
        out.extend(medium_problems(*m));
    }
    out
}

/// The declared medium against `support` on the library scenes (every device feature on, so
/// only the scene decides): a method renders no scene outside its medium, and at least one
/// scene of each medium it declares.
fn medium_problems(m: &dyn Method) -> Vec<String> {
    let info = m.info();
    let mut out = Vec::new();
    let mut media_rendered = BTreeSet::new();
    let mut media_present = BTreeSet::new();
    for name in scenes::library::names() {
        let features = harness::testing::library(name).features();
        media_present.insert(features.medium);
        if matches!(m.support(&features, wgpu::Features::all()), Support::No(_)) {
            continue;
        }
        media_rendered.insert(features.medium);
        if !info.medium.covers(features.medium) {
            out.push(format!(
                "{}: renders {name} (a {} medium) but declares medium = {}",
                info.id,
                features.medium,
                info.medium.name()
            ));
        }
    }
    for medium in media_present {
        if info.medium.covers(medium) && !media_rendered.contains(medium) {
            out.push(format!(
                "{}: declares medium = {} but renders no library scene with a {medium} medium",
                info.id,
                info.medium.name()
            ));
        }
    }
    out
}
