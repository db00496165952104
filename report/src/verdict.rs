//! The verdict that opens the page: per scene, the methods on the time-vs-error Pareto front
//! and the fastest configuration under each error budget, with one sentence in words — for
//! every metric the page offers (the verdict metric shown first). The floor (`no-scatter`,
//! ARCHITECTURE §4.5) is not a contender: it is left out of the front and the budgets, shown
//! in its own column, and each winner's time is given as a multiple of it.

use harness::results::Results;
use serde::Serialize;

use crate::analysis::{self, BUDGETS, Clock, ordered, scene_names};
use crate::format::{knobs_apart, ms, rel};
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
    /// Methods on the scene's front, fastest first (the floor left out).
    pub front: Vec<String>,
    /// The floor's time ("4.1 ms"), or None where the run has no floor on this scene.
    pub floor: Option<String>,
    /// Per budget: "method · time" of the fastest configuration within it, or None.
    pub budgets: Vec<Option<BudgetWinner>>,
    pub sentence: String,
    /// The most accurate configuration's method and error, whatever its time (what a missed
    /// budget was missed by; `scatterbench frontier`).
    #[serde(skip)]
    pub most_accurate: Option<(String, f64)>,
}

#[derive(Serialize, Clone)]
pub struct BudgetWinner {
    pub method: String,
    pub time: String,
    pub error: String,
    pub params: String,
    /// Its time as a multiple of the floor's ("1.20×"), None where the run has no floor.
    pub floor_ratio: Option<String>,
    /// The same multiple as a number.
    #[serde(skip)]
    pub floor_ratio_value: Option<f64>,
    /// Timed faster than the floor (ratio < 1): no method does less than the floor's work, so
    /// the two were timed in different states of the machine (ARCHITECTURE §4.5).
    pub below_floor: bool,
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

/// The verdict on `scene` of `results` by `metric` (one row of [`tables`]).
pub(crate) fn row(results: &Results, scene: &str, metric: Metric) -> VerdictRow {
    let records = analysis::scene_records(results, scene);
    let clock = Clock::for_records(&records);
    let records = analysis::contenders(&records);
    let points = analysis::points_by(&records, clock, metric);
    let front_points = analysis::pareto_front(&points);
    let front = ordered(
        front_points
            .iter()
            .map(|p| records[p.index].method.as_str()),
    );
    // A method with several configurations in the run names the one that won: by the knobs
    // off its defaults where the run recorded them (a `confirm` run holds one configuration
    // of a method on one scene and another on the next), else by those that set it apart
    // from the scene's others.
    let several = |m: &str| {
        let mut mine = results.records.iter().filter(|r| r.method == m);
        let first = mine.next().map(|r| &r.params);
        mine.any(|r| Some(&r.params) != first)
    };
    let defaults = |m: &str| results.run.methods.get(m).and_then(|d| d.defaults.as_ref());
    let budgets: Vec<Option<BudgetWinner>> = BUDGETS
        .iter()
        .map(|&b| {
            analysis::cheapest_under_budget(&points, b).map(|p| {
                let r = records[p.index];
                let ratio = clock.floor_ratio(r);
                BudgetWinner {
                    method: r.method.clone(),
                    time: format!("{} ms", ms(p.time)),
                    error: rel(p.error),
                    params: if several(&r.method) {
                        knobs_apart(r, &records, defaults(&r.method))
                    } else {
                        String::new()
                    },
                    floor_ratio: ratio.map(times_floor),
                    floor_ratio_value: ratio,
                    below_floor: ratio.is_some_and(|x| x < 1.0),
                }
            })
        })
        .collect();
    let most_accurate = points
        .iter()
        .filter(|p| p.error.is_finite())
        .min_by(|a, b| a.error.total_cmp(&b.error))
        .map(|p| (records[p.index].method.clone(), p.error));
    VerdictRow {
        most_accurate,
        scene: scene.to_string(),
        anchor: crate::format::anchor(scene),
        front,
        floor: clock.floor_ms.map(|f| format!("{} ms", ms(f))),
        sentence: sentence(scene, &budgets, points.is_empty()),
        budgets,
    }
}

/// A floor ratio as the page prints it: "1.20×" (three significant digits).
pub fn times_floor(ratio: f64) -> String {
    format!("{}×", rel(ratio))
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
    // Winners in budget order, merging the budgets won by the same configuration.
    // (who: the method, and in a run with several of its configurations the knobs that set
    // the winner apart; its floor ratio where the first budget it won has one; budgets).
    let mut parts: Vec<(String, Option<String>, Vec<String>)> = Vec::new();
    let mut missed: Vec<String> = Vec::new();
    for (b, w) in BUDGETS.iter().zip(budgets) {
        let Some(w) = w else {
            missed.push(pct(*b));
            continue;
        };
        let who = match w.params.as_str() {
            "" => w.method.clone(),
            knobs => format!("{} at {knobs}", w.method),
        };
        match parts.iter_mut().find(|(m, _, _)| *m == who) {
            Some((_, _, bs)) => bs.push(pct(*b)),
            None => {
                let below = if w.below_floor {
                    ", below it: timed apart"
                } else {
                    ""
                };
                let ratio = w
                    .floor_ratio
                    .as_ref()
                    .map(|r| format!("{r} the floor{below}"));
                parts.push((who, ratio, vec![pct(*b)]))
            }
        }
    }
    let mut out = format!("{scene}: ");
    let said: Vec<String> = parts
        .iter()
        .map(|(m, ratio, bs)| {
            let at = ratio
                .as_ref()
                .map(|r| format!(" ({r})"))
                .unwrap_or_default();
            format!("{m} is the fastest under {}{at}", bs.join(" and "))
        })
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
            floor_ratio: None,
            floor_ratio_value: None,
            below_floor: false,
        })
    }

    /// The floor is the fastest configuration at 100 % error: it must not head the front or win
    /// a budget, and each winner's time reads as its multiple (worked out by hand).
    #[test]
    fn the_floor_is_no_contender_and_winners_read_as_multiples_of_it() {
        let mut results = scene_s(&[
            (FLOOR, 4.0, 1.0),
            ("m-fast", 5.0, 0.2),
            ("m-good", 6.0, 0.04),
            ("m-exact", 10.0, 0.001),
        ]);
        let row = row(&results, "s", Metric::Verdict);
        assert_eq!(row.front, ["m-fast", "m-good", "m-exact"]);
        assert_eq!(row.floor.as_deref(), Some("4.00 ms"));
        let winners: Vec<(&str, Option<&str>)> = row
            .budgets
            .iter()
            .map(|w| {
                let w = w.as_ref().expect("every budget is won");
                (w.method.as_str(), w.floor_ratio.as_deref())
            })
            .collect();
        // 10 / 4 = 2.5, 6 / 4 = 1.5; the floor (error 100 %) wins nothing.
        assert_eq!(
            winners,
            [
                ("m-exact", Some("2.50×")),
                ("m-good", Some("1.50×")),
                ("m-good", Some("1.50×"))
            ]
        );
        assert!(
            row.sentence
                .contains("m-exact is the fastest under 1 % (2.50× the floor)")
        );
        // Without a floor record the ratios are undefined, not guessed.
        results.records.retain(|r| r.method != FLOOR);
        let row = super::row(&results, "s", Metric::Verdict);
        assert!(row.floor.is_none());
        assert!(
            row.budgets
                .iter()
                .flatten()
                .all(|w| w.floor_ratio.is_none())
        );
    }

    const FLOOR: &str = crate::analysis::FLOOR_METHOD;

    /// A synthetic run of one scene "s": per (method, GPU ms, headline), one record at defaults.
    fn scene_s(measured: &[(&str, f64, f64)]) -> harness::results::Results {
        use crate::fixture::synthetic::{Measured, record, run};
        let none = harness::method::Params::new();
        let mut results = run("lavapipe", 128);
        for &(method, time_ms, headline) in measured {
            let m = Some(Measured { time_ms, headline });
            results.records.push(record("s", method, &none, m));
        }
        results
    }

    /// In a `--paired-floor` run the budgets go to the cheapest record relative to the floor
    /// timed beside it, not to the lowest raw time: "m-lucky" (20 ms) ran while the machine
    /// was fast (its floor 5 ms: 4.00×), "m-cheap" (30 ms) while it was slow (20 ms: 1.50×).
    /// Raw times would crown m-lucky. The scene's floor is the median paired floor, 12.5 ms,
    /// and the times shown are drift-corrected to it: 30 × 12.5 / 20 = 18.75 ms.
    #[test]
    fn a_paired_run_ranks_on_the_floor_timed_beside_each_record() {
        let mut results = scene_s(&[
            (FLOOR, 10.0, 1.0),
            ("m-lucky", 20.0, 0.005),
            ("m-cheap", 30.0, 0.005),
        ]);
        for r in &mut results.records {
            let floor = match r.method.as_str() {
                "m-lucky" => 5.0,
                "m-cheap" => 20.0,
                _ => continue,
            };
            r.timing.as_mut().expect("timed").floor =
                Some(crate::fixture::synthetic::paired_floor(floor));
        }
        let row = row(&results, "s", Metric::Verdict);
        let w = row.budgets[0].as_ref().expect("1 % is won");
        assert_eq!(
            (w.method.as_str(), w.time.as_str(), w.floor_ratio.as_deref()),
            ("m-cheap", "18.8 ms", Some("1.50×"))
        );
        assert_eq!(row.floor.as_deref(), Some("12.5 ms"));
        assert_eq!(row.front, ["m-cheap"]);
    }

    /// Where the run recorded a method's defaults, a winner is named by the knobs off them,
    /// whatever else the scene holds: a `confirm` run holds one configuration of a method on
    /// "s" and another on "t" and still names each. A method with one configuration in the
    /// whole run is not named.
    #[test]
    fn a_configuration_is_named_by_its_knobs_off_the_defaults() {
        use crate::fixture::synthetic::{Measured, record};
        let mut results = scene_s(&[(FLOOR, 4.0, 1.0)]);
        let knobs = |slices: i64| {
            let mut p = harness::method::Params::new();
            p.insert("slices".into(), harness::method::ParamValue::Int(slices));
            p.insert("columns".into(), harness::method::ParamValue::Int(64));
            p
        };
        let m = |time_ms| {
            Some(Measured {
                time_ms,
                headline: 0.001,
            })
        };
        for (scene, slices) in [("s", 32), ("t", 64)] {
            results
                .records
                .push(record(scene, "m", &knobs(slices), m(6.0)));
        }
        results.run.methods.insert(
            "m".into(),
            harness::run_methods::MethodDescription {
                defaults: Some(knobs(64)),
                ..Default::default()
            },
        );
        let name = |results: &harness::results::Results, scene| {
            let row = row(results, scene, Metric::Verdict);
            row.budgets[0].as_ref().expect("1 % is won").params.clone()
        };
        assert_eq!(name(&results, "s"), "slices=32");
        assert_eq!(name(&results, "t"), "defaults");
        results.records.retain(|r| r.scene != "t");
        assert_eq!(name(&results, "s"), "");
    }

    /// A winner timed faster than the floor (which does less work than any method) is marked as
    /// such, in its cell's flag and its sentence; one above it is not.
    #[test]
    fn a_winner_below_the_floor_is_marked() {
        let results = scene_s(&[
            (FLOOR, 4.0, 1.0),
            ("m-slow", 8.0, 0.001),
            ("m-fast", 3.0, 0.03),
        ]);
        let row = row(&results, "s", Metric::Verdict);
        let flags: Vec<(&str, bool)> = row
            .budgets
            .iter()
            .map(|w| {
                let w = w.as_ref().expect("every budget is won");
                (w.method.as_str(), w.below_floor)
            })
            .collect();
        // 8 / 4 = 2 (1 %); 3 / 4 = 0.75 (5 % and 10 %).
        assert_eq!(
            flags,
            [("m-slow", false), ("m-fast", true), ("m-fast", true)]
        );
        assert!(
            row.sentence
                .contains("m-slow is the fastest under 1 % (2.00× the floor)"),
            "{}",
            row.sentence
        );
        assert!(
            row.sentence.contains(
                "m-fast is the fastest under 5 % and 10 % (0.750× the floor, below it: timed apart)"
            ),
            "{}",
            row.sentence
        );
    }

    /// Budgets won by two configurations of one method are two clauses, each naming its knobs
    /// and its own ratio, not one clause with the first configuration's ratio.
    #[test]
    fn sentences_name_the_configuration_that_won() {
        let won = |params: &str, ratio: f64| {
            Some(BudgetWinner {
                params: params.into(),
                floor_ratio: Some(times_floor(ratio)),
                floor_ratio_value: Some(ratio),
                below_floor: ratio < 1.0,
                ..w("froxel-fog").expect("a winner")
            })
        };
        assert_eq!(
            sentence(
                "spring-point",
                &[
                    won("slices=32", 1.14),
                    won("columns=32", 0.804),
                    won("columns=32", 0.804)
                ],
                false
            ),
            "spring-point: froxel-fog at slices=32 is the fastest under 1 % (1.14× the floor); \
             froxel-fog at columns=32 is the fastest under 5 % and 10 % (0.804× the floor, below \
             it: timed apart)."
        );
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
