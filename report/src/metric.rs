//! Which error the report's verdicts rank by, and the other errors the reader can switch to.
//!
//! Every verdict of the page (Pareto fronts, "fastest under a budget", the matrix colours,
//! the verdict table) goes through [`verdict_error`]: the record's in-scatter headline error
//! (`harness::verdict::headline`, issue 17) when it has one, else its in-scatter relative
//! RMSE, so the page keeps working on results.json files written before the headline existed.
//!
//! Fields newer than the harness's typed [`Record`] (headline, light-core, temporal) are read
//! from the raw JSON by [`annotate`] and kept in the record's `counters` under keys starting
//! with [`EXTRA`], so every reader of a record sees them without another lookup table.

use harness::results::{Record, Results};
use serde::Serialize;
use serde_json::Value;

/// Prefix of the counters [`annotate`] adds (never written back to results.json).
pub const EXTRA: &str = "report:";

/// One error the plots and tables can rank by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    /// [`verdict_error`]: the headline where recorded, else in-scatter relative RMSE.
    Verdict,
    /// In-scatter relative RMSE (`rmse / mean(reference)`).
    RelRmse,
    /// In-scatter relative MSE with ε (pbrt-v4 style).
    RelMse,
    /// Mean FLIP of the tone-mapped total image.
    Flip,
    /// Error over the pixels near a visible light (`errors.inscatter.light_core`).
    LightCore,
}

/// A metric as the page shows it.
#[derive(Clone, Debug, Serialize)]
pub struct MetricView {
    /// CSS-safe id ("verdict", "rel_rmse", …).
    pub id: &'static str,
    /// Label for buttons, axis titles and table captions: names the metric in full.
    pub label: String,
    /// A word or two for table heads ("fastest ≤ 1 % headline"), [`Metric::short`].
    pub short: &'static str,
}

impl Metric {
    pub fn id(self) -> &'static str {
        match self {
            Metric::Verdict => "verdict",
            Metric::RelRmse => "rel_rmse",
            Metric::RelMse => "rel_mse",
            Metric::Flip => "flip",
            Metric::LightCore => "light_core",
        }
    }

    /// Axis and button label; the verdict names the headline's definition when the run has one.
    pub fn label(self, headline: Option<&str>) -> String {
        match self {
            Metric::Verdict => match headline {
                Some(name) => format!("headline error ({name}), in-scatter"),
                None => "in-scatter relative RMSE (verdict)".into(),
            },
            Metric::RelRmse => "in-scatter relative RMSE".into(),
            Metric::RelMse => "in-scatter relative MSE".into(),
            Metric::Flip => "mean FLIP, total".into(),
            Metric::LightCore => "light-core error, in-scatter".into(),
        }
    }

    /// The metric in a word or two, for table heads: the verdict reads "headline" where the run
    /// names one (else it is rel. RMSE, and says so).
    pub fn short(self, headline: Option<&str>) -> &'static str {
        match self {
            Metric::Verdict if headline.is_some() => "headline",
            Metric::Verdict | Metric::RelRmse => "rel. RMSE",
            Metric::RelMse => "rel. MSE",
            Metric::Flip => "FLIP",
            Metric::LightCore => "light core",
        }
    }

    /// The record's value of this metric, if it was scored (and the metric recorded).
    pub fn of(self, r: &Record) -> Option<f64> {
        let ins = r.errors.get("inscatter");
        let v = match self {
            Metric::Verdict => verdict_error(r),
            Metric::RelRmse => ins.map(|m| m.rel_rmse),
            Metric::RelMse => ins.map(|m| m.rel_mse),
            Metric::Flip => r.errors.get("total").map(|m| m.flip_mean),
            Metric::LightCore => ins
                .and_then(|m| m.light_core)
                .or_else(|| extra(r, "light_core.inscatter")),
        };
        v.filter(|v| v.is_finite())
    }
}

/// THE verdict metric of a record: its in-scatter headline error when recorded, else its
/// in-scatter relative RMSE. Every ranking of the page uses this one function.
pub fn verdict_error(r: &Record) -> Option<f64> {
    harness::verdict::headline(r, "inscatter")
        .or_else(|| extra(r, "headline.inscatter"))
        .or_else(|| r.errors.get("inscatter").map(|m| m.rel_rmse))
}

/// The metrics the page offers for this run: the verdict first, then the ones some record has.
pub fn available(results: &Results) -> Vec<Metric> {
    let mut out = vec![Metric::Verdict];
    let has_headline = results.records.iter().any(|r| {
        harness::verdict::headline(r, "inscatter").is_some()
            || extra(r, "headline.inscatter").is_some()
    });
    // Without a headline the verdict IS rel_rmse; offering both would show the same twice.
    if has_headline {
        out.push(Metric::RelRmse);
    }
    out.extend([Metric::RelMse, Metric::Flip]);
    if results
        .records
        .iter()
        .any(|r| Metric::LightCore.of(r).is_some())
    {
        out.push(Metric::LightCore);
    }
    out
}

pub fn views(headline: Option<&str>, metrics: &[Metric]) -> Vec<MetricView> {
    metrics
        .iter()
        .map(|m| MetricView {
            id: m.id(),
            label: m.label(headline),
            short: m.short(headline),
        })
        .collect()
}

/// A value [`annotate`] copied from the raw JSON (`key` without the [`EXTRA`] prefix).
pub fn extra(r: &Record, key: &str) -> Option<f64> {
    r.counters.get(&format!("{EXTRA}{key}")).copied()
}

/// Copies the optional per-record fields of issue 17 from `raw` (the results.json text as
/// JSON) into the records' counters: `errors.<aov>.headline`, `errors.<aov>.light_core`,
/// `errors.<aov>.temporal` (numbers; null and absent are left out). Records pair by index.
/// Returns the run's headline definition (`run.headline`) when it names one.
pub fn annotate(results: &mut Results, raw: &Value) -> Option<String> {
    let headline = raw
        .pointer("/run/headline")
        .and_then(Value::as_str)
        .map(String::from);
    let Some(raw_records) = raw.get("records").and_then(Value::as_array) else {
        return headline;
    };
    for (r, raw_r) in results.records.iter_mut().zip(raw_records) {
        let Some(errors) = raw_r.get("errors").and_then(Value::as_object) else {
            continue;
        };
        for (aov, m) in errors {
            for field in ["headline", "light_core", "temporal"] {
                if let Some(v) = m.get(field).and_then(Value::as_f64) {
                    r.counters.insert(format!("{EXTRA}{field}.{aov}"), v);
                }
            }
        }
    }
    headline
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUN: &str = include_str!("../tests/fixtures/results.json");

    /// A results.json written before issue 17 has no headline: the verdict is rel. RMSE. With
    /// `errors.inscatter.headline` the verdict is the headline, and the run names it.
    #[test]
    fn verdict_is_the_headline_when_recorded_else_rel_rmse() {
        let mut old: Results = serde_json::from_str(RUN).unwrap();
        let raw: Value = serde_json::from_str(RUN).unwrap();
        assert_eq!(annotate(&mut old, &raw), None);
        let r = &old.records[0];
        assert_eq!(verdict_error(r), Some(r.errors["inscatter"].rel_rmse));
        assert_eq!(
            available(&old),
            [Metric::Verdict, Metric::RelMse, Metric::Flip]
        );

        let mut raw = raw;
        raw["run"]["headline"] = Value::from("rel_rmse_trimmed_0.1%");
        raw["records"][0]["errors"]["inscatter"]["headline"] = Value::from(0.0123);
        raw["records"][0]["errors"]["inscatter"]["light_core"] = Value::from(0.5);
        let mut new: Results = serde_json::from_value(raw.clone()).unwrap();
        let name = annotate(&mut new, &raw);
        assert_eq!(name.as_deref(), Some("rel_rmse_trimmed_0.1%"));
        assert_eq!(verdict_error(&new.records[0]), Some(0.0123));
        assert_eq!(
            Metric::RelRmse.of(&new.records[0]),
            Some(r.errors["inscatter"].rel_rmse)
        );
        assert_eq!(Metric::LightCore.of(&new.records[0]), Some(0.5));
        // Other records keep falling back record by record.
        let r1 = &new.records[1];
        assert_eq!(verdict_error(r1), Some(r1.errors["inscatter"].rel_rmse));
        assert_eq!(
            available(&new),
            [
                Metric::Verdict,
                Metric::RelRmse,
                Metric::RelMse,
                Metric::Flip,
                Metric::LightCore
            ]
        );
        assert!(
            Metric::Verdict
                .label(name.as_deref())
                .contains("rel_rmse_trimmed_0.1%")
        );
    }
}
