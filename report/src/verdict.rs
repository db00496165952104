//! The verdict that opens the page: per scene, the methods on the time-vs-error Pareto front
//! and the fastest configuration under each error budget, with one sentence in words — for
//! every metric the page offers (the verdict metric shown first).

use harness::results::{Record, Results};
use serde::Serialize;

use crate::analysis::{self, BUDGETS, TimeBasis, ordered, scene_names};
use crate::format::{ms, params_text, rel};
use crate::metric::Metric;

#[derive(Serialize)]
pub struct VerdictTable {
    pub metric: &'static str,
    pub rows: Vec<VerdictRow>,
}

#[derive(Serialize)]
pub struct VerdictRow {
    pub scene: String,
    pub anchor: String,
    /// Methods on the scene's front, fastest first, each with its time.
    pub front: Vec<String>,
    /// Per budget: "method · time" of the fastest configuration within it, or None.
    pub budgets: Vec<Option<BudgetWinner>>,
    pub sentence: String,
}

#[derive(Serialize, Clone)]
pub struct BudgetWinner {
    pub method: String,
    pub time: String,
    pub error: String,
    pub params: String,
}

/// Per metric, per scene.
pub fn tables(results: &Results, metrics: &[Metric]) -> Vec<VerdictTable> {
    metrics
        .iter()
        .map(|&metric| VerdictTable {
            metric: metric.id(),
            rows: scene_names(results)
                .iter()
                .map(|s| row(results, s, metric))
                .collect(),
        })
        .collect()
}

fn row(results: &Results, scene: &str, metric: Metric) -> VerdictRow {
    let records: Vec<&Record> = results
        .records
        .iter()
        .filter(|r| r.scene == scene)
        .collect();
    let basis = TimeBasis::for_records(records.iter().copied());
    let points = analysis::points_by(&records, basis, metric);
    let front_points = analysis::pareto_front(&points);
    let front = ordered(
        front_points
            .iter()
            .map(|p| records[p.index].method.as_str()),
    );
    // A method with several configurations names the one that won.
    let several = |m: &str| records.iter().filter(|r| r.method == m).count() > 1;
    let budgets: Vec<Option<BudgetWinner>> = BUDGETS
        .iter()
        .map(|&b| {
            analysis::cheapest_under_budget(&points, b).map(|p| {
                let r = records[p.index];
                BudgetWinner {
                    method: r.method.clone(),
                    time: format!("{} ms", ms(p.time)),
                    error: rel(p.error),
                    params: if several(&r.method) {
                        params_text(r)
                    } else {
                        String::new()
                    },
                }
            })
        })
        .collect();
    VerdictRow {
        scene: scene.to_string(),
        anchor: crate::format::anchor(scene),
        front,
        sentence: sentence(scene, &budgets, points.is_empty()),
        budgets,
    }
}

/// An error budget as the page names it ("5 %").
pub fn pct(b: f64) -> String {
    format!("{:.0} %", b * 100.0)
}

/// "fence-spot: wyman-hybrid is the fastest under 5 % and 10 %; nothing reaches 1 % at the
/// measured knobs."
pub fn sentence(scene: &str, budgets: &[Option<BudgetWinner>], nothing_scored: bool) -> String {
    if nothing_scored {
        return format!("{scene}: no method has a timed, scored record.");
    }
    // Winners in budget order, merging consecutive budgets won by the same method.
    let mut parts: Vec<(String, Vec<String>)> = Vec::new();
    let mut missed: Vec<String> = Vec::new();
    for (b, w) in BUDGETS.iter().zip(budgets) {
        match w {
            Some(w) => match parts.iter_mut().find(|(m, _)| *m == w.method) {
                Some((_, bs)) => bs.push(pct(*b)),
                None => parts.push((w.method.clone(), vec![pct(*b)])),
            },
            None => missed.push(pct(*b)),
        }
    }
    let mut out = format!("{scene}: ");
    let said: Vec<String> = parts
        .iter()
        .map(|(m, bs)| format!("{m} is the fastest under {}", bs.join(" and ")))
        .collect();
    out.push_str(&said.join("; "));
    if !missed.is_empty() {
        if !said.is_empty() {
            out.push_str("; ");
        }
        out.push_str(&format!(
            "nothing reaches {} at the measured knobs",
            missed.join(" or ")
        ));
    }
    out.push('.');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(m: &str) -> Option<BudgetWinner> {
        Some(BudgetWinner {
            method: m.into(),
            time: "1 ms".into(),
            error: "0".into(),
            params: String::new(),
        })
    }

    #[test]
    fn sentences_merge_budgets_and_name_the_missed_ones() {
        assert_eq!(
            sentence(
                "fence-spot",
                &[None, w("wyman-hybrid"), w("wyman-hybrid")],
                false
            ),
            "fence-spot: wyman-hybrid is the fastest under 5 % and 10 %; nothing reaches 1 % at the measured knobs."
        );
        assert_eq!(
            sentence("a", &[w("x"), w("y"), w("y")], false),
            "a: x is the fastest under 1 %; y is the fastest under 5 % and 10 %."
        );
        assert_eq!(
            sentence("a", &[None, None, None], false),
            "a: nothing reaches 1 % or 5 % or 10 % at the measured knobs."
        );
    }
}
