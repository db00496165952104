//! The compiled-in templates and the one minijinja environment every page renders through:
//! the report (`index.html`) and the comparison (`compare.html`) both extend `page.html`,
//! which inlines what they share — the style (`base.css`) and the self-check script
//! (`selfcheck.js`: error capture, the `#layout` check, the JSON verdict the browser tests
//! read).

use anyhow::{Result, anyhow};
use serde::Serialize;

const TEMPLATES: [(&str, &str); 5] = [
    ("page.html", include_str!("../templates/page.html")),
    ("index.html", include_str!("../templates/index.html")),
    ("compare.html", include_str!("../templates/compare.html")),
    ("base.css", include_str!("../templates/base.css")),
    ("selfcheck.js", include_str!("../templates/selfcheck.js")),
];

/// Renders template `name` with `page` as `page`. The ".html" names turn on HTML
/// auto-escaping of every interpolated value.
pub fn render(name: &str, page: &impl Serialize) -> Result<String> {
    let mut env = minijinja::Environment::new();
    for (n, source) in TEMPLATES {
        env.add_template(n, source)
            .map_err(|e| anyhow!("template {n}: {e:#}"))?;
    }
    env.get_template(name)
        .and_then(|t| t.render(minijinja::context! { page => page }))
        .map_err(|e| anyhow!("rendering {name}: {e:#}"))
}
