//! The run's methods as results.json describes them (`run.methods`, ARCHITECTURE §5.1): which
//! are baselines (the matrix sets them apart) and the "Methods" table — paper, summary, medium.
//! The report reads nothing else about a method, so results from a fork or an external method
//! report as faithfully as the built-in ones; a field a results file lacks (files written before
//! `run.methods`) reads "unknown", and a method of unknown kind is not set apart.

use harness::results::{MethodDescription, Results};
use serde::Serialize;

/// What the page shows for a field the results file does not give.
pub const UNKNOWN: &str = "unknown";

/// One method: the "Methods" table's row.
#[derive(Serialize)]
pub struct MethodRow {
    pub id: String,
    pub paper: String,
    pub summary: String,
    pub medium: String,
    /// "yes", "no" or "unknown".
    pub baseline: String,
    /// Set apart (a baseline by the results' own account).
    pub is_baseline: bool,
}

/// Whether results.json describes `method` as a baseline.
pub fn is_baseline(results: &Results, method: &str) -> bool {
    description(results, method).baseline == Some(true)
}

/// Every method of the run (those with records, then those only described), published ones
/// first and baselines last, in order of first appearance — the matrix's order.
pub fn rows(results: &Results) -> Vec<MethodRow> {
    let ids = crate::analysis::ordered(
        results
            .records
            .iter()
            .map(|r| r.method.as_str())
            .chain(results.run.methods.keys().map(String::as_str)),
    );
    let (mut rows, baselines): (Vec<MethodRow>, Vec<MethodRow>) = ids
        .into_iter()
        .map(|id| row(results, id))
        .partition(|r| !r.is_baseline);
    rows.extend(baselines);
    rows
}

fn row(results: &Results, id: String) -> MethodRow {
    let d = description(results, &id);
    let text = |v: Option<String>| v.unwrap_or_else(|| UNKNOWN.into());
    MethodRow {
        is_baseline: d.baseline == Some(true),
        baseline: match d.baseline {
            Some(true) => "yes".into(),
            Some(false) => "no".into(),
            None => UNKNOWN.into(),
        },
        paper: text(d.paper),
        summary: text(d.summary),
        medium: text(d.medium),
        id,
    }
}

fn description(results: &Results, method: &str) -> MethodDescription {
    results.run.methods.get(method).cloned().unwrap_or_default()
}
