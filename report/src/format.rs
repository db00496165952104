//! Number, name and path formatting shared by every table and plot of the page, so all of
//! them use the same units and precision.

use harness::method::Params;
use harness::results::{Record, Status};
use serde::Serialize;

/// Links to a plot drawn in both formats.
#[derive(Serialize, Clone)]
pub struct PlotLinks {
    pub svg: String,
    pub png: String,
}

/// The record's parameters as `k=v k=v`, sorted by knob name.
pub fn params_text(r: &Record) -> String {
    knobs_text(&r.params)
}

/// The knobs that tell `r` apart from the other records of its method in `peers` (any
/// records; those of other methods are ignored): each knob whose value is not the one a
/// strict majority of the method's records share, as `k=v k=v`, or "defaults" where every
/// knob has the majority's value. In a sweep (one knob at a time) the majority's values are
/// the method's defaults, so a configuration reads as what was changed (`slices=32`), as the
/// run's log prints it; in a run of a few hand-picked configurations the knobs they differ in
/// are shown on each.
pub fn distinguishing_knobs(r: &Record, peers: &[&Record]) -> String {
    let mine: Vec<&Record> = peers
        .iter()
        .copied()
        .filter(|p| p.method == r.method)
        .collect();
    let differs = |(k, v): &(&String, &harness::method::ParamValue)| {
        let same = mine.iter().filter(|p| p.params.get(*k) == Some(*v)).count();
        2 * same <= mine.len()
    };
    knobs_or_defaults(r.params.iter().filter(differs))
}

/// How `r` is named among configurations of its method: the knobs whose value is not the
/// method's default where the run recorded its defaults (`run.methods`), as `k=v k=v` or
/// "defaults"; else [`distinguishing_knobs`] among `peers`.
pub fn knobs_apart(r: &Record, peers: &[&Record], defaults: Option<&Params>) -> String {
    match defaults {
        Some(d) => knobs_or_defaults(r.params.iter().filter(|(k, v)| d.get(*k) != Some(*v))),
        None => distinguishing_knobs(r, peers),
    }
}

/// Knobs as `k=v k=v` in the order given, or "defaults" for none: how a configuration that
/// differs from its method's defaults in those knobs is named.
pub fn knobs_or_defaults<'a>(
    knobs: impl Iterator<Item = (&'a String, &'a harness::method::ParamValue)>,
) -> String {
    let p: Vec<String> = knobs.map(|(k, v)| format!("{k}={v}")).collect();
    if p.is_empty() {
        "defaults".into()
    } else {
        p.join(" ")
    }
}

/// Parameters as `k=v k=v`, sorted by knob name; "(none)" for none.
pub fn knobs_text(params: &harness::method::Params) -> String {
    let p: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    if p.is_empty() {
        "(none)".into()
    } else {
        p.join(" ")
    }
}

pub fn status_text(s: Status) -> &'static str {
    match s {
        Status::Ok => "ok",
        Status::Skipped => "skipped",
        Status::Failed => "failed",
    }
}

pub fn ms(v: f64) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

/// Relative errors with three significant digits (0.0123, 1.89, 4.20e-5).
pub fn rel(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    if v.abs() < 1e-3 || v.abs() >= 1e4 {
        return format!("{v:.2e}");
    }
    let decimals = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

pub fn mib(bytes: u64) -> String {
    format!("{:.1} MiB", bytes as f64 / (1024.0 * 1024.0))
}

/// A file-name and HTML-id friendly form of a scene name.
pub fn anchor(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("scene-{s}")
}

/// Percent-encodes a relative path for an `src`/`href` (keeps `/` and unreserved chars).
pub fn url_path(rel: &str) -> String {
    let mut out = String::new();
    for b in rel.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rel_keeps_three_significant_digits() {
        assert_eq!(rel(0.0013916), "0.00139");
        assert_eq!(rel(0.04389), "0.0439");
        assert_eq!(rel(1.8857), "1.89");
        assert_eq!(rel(12.34), "12.3");
        assert_eq!(rel(5.575e-4), "5.58e-4");
        assert_eq!(rel(0.0), "0");
        assert_eq!(rel(f64::NAN), "NaN");
    }

    #[test]
    fn url_path_encodes_reserved_characters_only() {
        assert_eq!(url_path("a b/c&d/x-1_y.png"), "a%20b/c%26d/x-1_y.png");
        assert_eq!(url_path("é"), "%C3%A9");
    }
}
