//! The cost of accuracy as a Markdown table (`scatterbench frontier`, ARCHITECTURE §4.5): per
//! scene, the cheapest configuration under 1 % and under 5 % of the verdict metric, with its
//! time as a multiple of the same run's floor (no-scatter), for one run or for a run before and
//! after a change. It reads the verdict table's rows ([`crate::verdict`]), so the committed
//! table and the report's page cannot disagree.
//!
//! Times compare only within one run (shared machines, other adapters); the floor ratio is
//! the number that compares across runs, and the summary counts it.

use std::fmt::Write;

use harness::results::Results;

use crate::analysis::{BUDGETS, ordered, scene_names};
use crate::format::rel;
use crate::metric::Metric;
use crate::verdict::{self, BudgetWinner, VerdictRow, pct};

/// The budgets the table shows (fractions of the verdict metric); each is one of
/// [`BUDGETS`], so the cells are the verdict table's.
pub const FRONTIER_BUDGETS: [f64; 2] = [0.01, 0.05];

/// The floor ratio at or under which a winner counts as affordable in the summary (issue 33's
/// target: the fastest configuration under 1 % within 2× the floor).
pub const AFFORDABLE_RATIO: f64 = 2.0;

/// One run's verdict per scene (None where the run did not render the scene).
struct Column<'a> {
    name: &'static str,
    results: &'a Results,
    rows: Vec<Option<VerdictRow>>,
}

/// The table for `after` (and `before`, shown to its left when given) over the union of both
/// runs' scenes, `after`'s order first.
pub fn markdown(after: &Results, before: Option<&Results>) -> String {
    let later = before.map(scene_names).unwrap_or_default();
    let scenes = ordered(scene_names(after).iter().chain(&later).map(String::as_str));
    let columns: Vec<Column> = before
        .map(|b| ("before", b))
        .into_iter()
        .chain([("after", after)])
        .map(|(name, results)| Column {
            name,
            results,
            rows: scenes
                .iter()
                .map(|s| rendered(results, s).then(|| verdict::row(results, s, Metric::Verdict)))
                .collect(),
        })
        .collect();
    let mut out = String::new();
    runs_block(&mut out, &columns);
    table(&mut out, &scenes, &columns);
    summary(&mut out, &columns);
    out
}

/// Whether `results` has a record of `scene`.
fn rendered(results: &Results, scene: &str) -> bool {
    results.records.iter().any(|r| r.scene == scene)
}

/// The verdict metric of a run in a word ("headline"; "rel. RMSE" for a run written before
/// the headline) and in full (`metric::Metric::label`).
fn metric_names(results: &Results) -> (&'static str, String) {
    let headline = results.run.headline.as_deref();
    (
        Metric::Verdict.short(headline),
        Metric::Verdict.label(headline),
    )
}

/// Which run each column is: id, adapter, resolution, commit, and the metric it ranks by.
fn runs_block(out: &mut String, columns: &[Column]) {
    out.push_str(
        "| run | id | adapter | resolution | commit | ranked by |\n|---|---|---|---|---|---|\n",
    );
    for c in columns {
        let run = &c.results.run;
        let _ = writeln!(
            out,
            "| {} | {} | {} | {}×{} | {} | {} |",
            c.name,
            run.id,
            run.machine.adapter,
            run.resolution[0],
            run.resolution[1],
            run.git_commit,
            metric_names(c.results).1
        );
    }
    out.push_str(
        "\nEach cell: the fastest configuration under the budget of the run's verdict metric \
         (ranked by, above; ARCHITECTURE §4.4), its median frame time and that time as a \
         multiple of the same run's floor (no-scatter, §4.5). Times compare only within one \
         run; the floor ratios compare across runs. In a `--paired-floor` run the floor is the \
         median of the scene's paired floors, each ratio divides by the record's own paired \
         floor, and configurations are ranked and shown at ratio × floor (drift-corrected, \
         §4.5).\n\n",
    );
}

/// One row per scene: the floor, then per budget one cell per run.
fn table(out: &mut String, scenes: &[String], columns: &[Column]) {
    out.push_str("| scene | floor |");
    let mut rule = String::from("|---|---|");
    for b in FRONTIER_BUDGETS {
        for c in columns {
            let _ = write!(
                out,
                " ≤ {} {} ({}) |",
                pct(b),
                metric_names(c.results).0,
                c.name
            );
            rule.push_str("---|");
        }
    }
    let _ = writeln!(out, "\n{rule}");
    for (i, scene) in scenes.iter().enumerate() {
        let floors: Vec<String> = columns
            .iter()
            .map(|c| match &c.rows[i] {
                Some(row) => row.floor.clone().unwrap_or_else(|| "—".into()),
                None => "not run".into(),
            })
            .collect();
        let _ = write!(out, "| {scene} | {} |", floors.join(" / "));
        for b in FRONTIER_BUDGETS {
            for c in columns {
                let _ = write!(out, " {} |", cell(c.rows[i].as_ref(), b));
            }
        }
        out.push('\n');
    }
}

/// "method `knobs` · 12.3 ms · 1.50×", or what the budget was missed by.
fn cell(row: Option<&VerdictRow>, budget: f64) -> String {
    let Some(row) = row else {
        return "not run".into();
    };
    match winner(row, budget) {
        Some(w) => {
            let knobs = if w.params.is_empty() {
                String::new()
            } else {
                format!(" `{}`", w.params)
            };
            let ratio = w.floor_ratio.as_deref().unwrap_or("no floor");
            format!("{}{knobs} · {} · {ratio}", w.method, w.time)
        }
        None => match &row.most_accurate {
            Some((method, error)) => format!("none (best: {method} {} %)", rel(error * 100.0)),
            None => "none scored".into(),
        },
    }
}

/// The verdict row's winner of `budget` (one of [`BUDGETS`]).
fn winner(row: &VerdictRow, budget: f64) -> Option<&BudgetWinner> {
    let i = BUDGETS.iter().position(|&b| b == budget)?;
    row.budgets.get(i)?.as_ref()
}

/// The floor ratio of the row's winner of `budget`, where it has a winner and a floor.
fn winner_ratio(row: &VerdictRow, budget: f64) -> Option<f64> {
    winner(row, budget)?.floor_ratio_value
}

/// Per run and budget: on how many of the scenes the winner is within [`AFFORDABLE_RATIO`]
/// of the floor, and which scenes have no winner at all.
fn summary(out: &mut String, columns: &[Column]) {
    out.push('\n');
    for b in FRONTIER_BUDGETS {
        for c in columns {
            let rows: Vec<&VerdictRow> = c.rows.iter().flatten().collect();
            let affordable = rows
                .iter()
                .filter(|r| winner_ratio(r, b).is_some_and(|x| x <= AFFORDABLE_RATIO))
                .count();
            let missed: Vec<&str> = rows
                .iter()
                .filter(|r| winner(r, b).is_none())
                .map(|r| r.scene.as_str())
                .collect();
            let _ = writeln!(
                out,
                "- {}: under {}, within {}× the floor on {affordable} of {} scenes{}",
                c.name,
                pct(b),
                AFFORDABLE_RATIO,
                rows.len(),
                if missed.is_empty() {
                    String::new()
                } else {
                    format!("; nothing under {} on {}", pct(b), missed.join(", "))
                }
            );
        }
    }
    for c in columns {
        below_floor(out, c);
    }
}

/// A warning per run where some winner is faster than the floor: the floor is then not a
/// lower bound of a frame on that scene (a drifting clock, a floor that does more work than
/// the winner), so that run's ratios there do not say what accuracy costs.
fn below_floor(out: &mut String, column: &Column) {
    let scenes: Vec<&str> = column
        .rows
        .iter()
        .flatten()
        .filter(|r| {
            FRONTIER_BUDGETS
                .iter()
                .any(|&b| winner(r, b).is_some_and(|w| w.below_floor))
        })
        .map(|r| r.scene.as_str())
        .collect();
    if !scenes.is_empty() {
        let _ = writeln!(
            out,
            "- {}: a winner runs below the floor on {} of {} scenes ({}): the floor is no lower \
             bound of a frame there, so those ratios do not measure what accuracy costs \
             (ARCHITECTURE §4.5)",
            column.name,
            scenes.len(),
            column.rows.iter().flatten().count(),
            scenes.join(", ")
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::FLOOR_METHOD;
    use crate::fixture::synthetic::{Measured, record, run};
    use harness::method::Params;

    fn with(records: &[(&str, &str, f64, f64)]) -> Results {
        let mut results = run("lavapipe", 512);
        for &(scene, method, time_ms, headline) in records {
            let measured = Some(Measured { time_ms, headline });
            results
                .records
                .push(record(scene, method, &Params::new(), measured));
        }
        results
    }

    /// Worked by hand: on "a" the 1 % winner goes from 10× to 1.5× the floor; "b" has nothing
    /// under 1 % before (best 3 %) and a 2.5× winner after; "c" is only in the later run.
    #[test]
    fn cells_and_counts_follow_the_verdict_rows() {
        let before = with(&[
            ("a", FLOOR_METHOD, 4.0, 1.0),
            ("a", "exact", 40.0, 0.001),
            ("a", "cheap", 5.0, 0.04),
            ("b", FLOOR_METHOD, 2.0, 1.0),
            ("b", "cheap", 3.0, 0.03),
        ]);
        let after = with(&[
            ("a", FLOOR_METHOD, 8.0, 1.0),
            ("a", "exact", 12.0, 0.001),
            ("a", "cheap", 10.0, 0.04),
            ("b", FLOOR_METHOD, 2.0, 1.0),
            ("b", "cheap", 3.0, 0.03),
            ("b", "new", 5.0, 0.009),
            ("c", "new", 1.0, 0.002),
        ]);
        let md = markdown(&after, Some(&before));
        let line = |scene: &str| {
            md.lines()
                .find(|l| l.starts_with(&format!("| {scene} |")))
                .unwrap_or_else(|| panic!("no row for {scene} in\n{md}"))
                .to_string()
        };
        // Columns: scene, floor, ≤1 % before, ≤1 % after, ≤5 % before, ≤5 % after.
        let cells = |scene: &str| -> Vec<String> {
            line(scene)
                .split('|')
                .map(|c| c.trim().to_string())
                .filter(|c| !c.is_empty())
                .collect()
        };
        let a = cells("a");
        assert_eq!(a[1], "4.00 ms / 8.00 ms");
        assert!(a[2].starts_with("exact · 40.0 ms · 10.0×"), "{a:?}");
        assert!(a[3].starts_with("exact · 12.0 ms · 1.50×"), "{a:?}");
        assert!(a[4].starts_with("cheap · 5.00 ms · 1.25×"), "{a:?}");
        assert!(a[5].starts_with("cheap · 10.0 ms · 1.25×"), "{a:?}");
        let b = cells("b");
        assert_eq!(b[2], "none (best: cheap 3.00 %)");
        assert!(b[3].starts_with("new · 5.00 ms · 2.50×"), "{b:?}");
        let c = cells("c");
        assert_eq!(c[1], "not run / —");
        assert_eq!(c[2], "not run");
        assert!(c[3].starts_with("new · 1.00 ms · no floor"), "{c:?}");
        // Under 1 %: before a is 10× (not affordable), b has none; after a is 1.5×, b 2.5×,
        // c has no floor: one of three.
        assert!(
            md.contains(
                "- before: under 1 %, within 2× the floor on 0 of 2 scenes; nothing under 1 % on b"
            ),
            "{md}"
        );
        assert!(
            md.contains("- after: under 1 %, within 2× the floor on 1 of 3 scenes\n"),
            "{md}"
        );
        // Under 5 %: after a is cheap at 1.25×, b cheap at 1.5×, c without a floor.
        assert!(
            md.contains("- after: under 5 %, within 2× the floor on 2 of 3 scenes\n"),
            "{md}"
        );
    }

    /// A winner is named by the knobs its sweep changed: the values most of its method's
    /// records share (a sweep's defaults) are left out, and the default configuration reads
    /// "defaults". Two configurations that differ in one knob each show that knob.
    #[test]
    fn winners_are_named_by_the_knobs_that_set_them_apart() {
        use harness::method::ParamValue::Int;
        let knobs = |slices: i64, columns: i64| -> Params {
            [
                ("columns".to_string(), Int(columns)),
                ("slices".to_string(), Int(slices)),
            ]
            .into()
        };
        let mut results = run("lavapipe", 512);
        let sweep = [
            (knobs(64, 64), 6.0, 0.005),
            (knobs(32, 64), 3.0, 0.008),
            (knobs(128, 64), 9.0, 0.004),
            (knobs(64, 32), 4.0, 0.02),
        ];
        for (params, time_ms, headline) in sweep {
            let measured = Some(Measured { time_ms, headline });
            results.records.push(record("a", "fog", &params, measured));
        }
        for (params, time_ms, headline) in [(knobs(8, 8), 2.0, 0.009), (knobs(8, 16), 1.0, 0.3)] {
            let measured = Some(Measured { time_ms, headline });
            results.records.push(record("b", "fog", &params, measured));
        }
        let md = markdown(&results, None);
        let row = |scene: &str| {
            md.lines()
                .find(|l| l.starts_with(&format!("| {scene} |")))
                .unwrap()
                .to_string()
        };
        // a: slices=32 (3 ms, 0.8 %) is the cheapest under 1 % and under 5 %.
        assert!(row("a").contains("fog `slices=32` · 3.00 ms"), "{md}");
        assert!(!row("a").contains("columns="), "{md}");
        // b: two configurations differing in columns: the winner shows columns, not slices.
        assert!(row("b").contains("fog `columns=8` · 2.00 ms"), "{md}");
        // The defaults, when they win, read as such.
        let mut defaults_win = results.clone();
        defaults_win
            .records
            .retain(|r| r.scene == "a" && r.params != knobs(32, 64));
        let md = markdown(&defaults_win, None);
        assert!(md.contains("fog `defaults` · 6.00 ms"), "{md}");
    }

    /// The table names the metric it ranks by, per run: the runs block in full, each budget's
    /// head in short: "headline" for a run that records it, "rel. RMSE" for one written before
    /// (whose verdict metric that is). What it names is what it ranks by: "fast" is under 5 %
    /// by its headline (3 %) but not by its rel. RMSE (20 %), and wins 5 % only after.
    #[test]
    fn heads_name_the_metric_each_run_ranks_by() {
        let rows = [
            ("a", FLOOR_METHOD, 1.0, 1.0),
            ("a", "fast", 2.0, 0.03),
            ("a", "exact", 8.0, 0.004),
        ];
        let after = with(&rows);
        let mut before = with(&rows);
        before.run.headline = None;
        for r in &mut before.records {
            let m = r.errors.get_mut("inscatter").unwrap();
            m.headline = None;
            m.rel_rmse = if r.method == "fast" { 0.2 } else { m.rel_rmse };
        }
        let md = markdown(&after, Some(&before));
        let head = md
            .lines()
            .find(|l| l.starts_with("| scene | floor |"))
            .unwrap_or_else(|| panic!("no table head in\n{md}"));
        assert_eq!(
            head,
            "| scene | floor | ≤ 1 % rel. RMSE (before) | ≤ 1 % headline (after) | \
             ≤ 5 % rel. RMSE (before) | ≤ 5 % headline (after) |"
        );
        let run = |name: &str| {
            md.lines()
                .find(|l| l.starts_with(&format!("| {name} |")))
                .unwrap()
                .to_string()
        };
        let headline = Metric::Verdict.label(Some(harness::verdict::HEADLINE_NAME));
        assert!(headline.contains(harness::verdict::HEADLINE_NAME));
        assert!(run("after").ends_with(&format!("| {headline} |")), "{md}");
        let old = Metric::Verdict.label(None);
        assert!(run("before").ends_with(&format!("| {old} |")), "{md}");
        let a: Vec<&str> = md
            .lines()
            .find(|l| l.starts_with("| a |"))
            .unwrap()
            .split('|')
            .map(str::trim)
            .filter(|c| !c.is_empty())
            .collect();
        assert!(a[4].starts_with("exact · 8.00 ms"), "{a:?}");
        assert!(a[5].starts_with("fast · 2.00 ms"), "{a:?}");
    }

    /// A winner faster than the floor is flagged per run and scene; a run without one is not.
    #[test]
    fn winners_below_the_floor_are_flagged() {
        let flagged = with(&[
            ("a", FLOOR_METHOD, 10.0, 1.0),
            ("a", "fast", 4.0, 0.005),
            ("b", FLOOR_METHOD, 2.0, 1.0),
            ("b", "slow", 3.0, 0.005),
        ]);
        let md = markdown(&flagged, None);
        assert!(
            md.contains("- after: a winner runs below the floor on 1 of 2 scenes (a):"),
            "{md}"
        );
        let honest = with(&[("b", FLOOR_METHOD, 2.0, 1.0), ("b", "slow", 3.0, 0.005)]);
        let md = markdown(&honest, None);
        assert!(!md.contains("below the floor"), "{md}");
    }

    /// With `--paired-floor`, a record's ratio divides by its own paired floor; a record
    /// without one falls back on the scene's floor record. By hand: the scene's floor is
    /// 10 ms, "drifted" (4 ms) was timed beside a floor of 2 ms → 2.00×, "plain" (6 ms) has
    /// none → 0.600×.
    #[test]
    fn a_paired_floor_sets_the_ratio_of_its_record() {
        let mut results = with(&[
            ("a", FLOOR_METHOD, 10.0, 1.0),
            ("a", "drifted", 4.0, 0.005),
            ("b", FLOOR_METHOD, 10.0, 1.0),
            ("b", "plain", 6.0, 0.005),
        ]);
        for r in &mut results.records {
            if r.method == "drifted" {
                r.timing.as_mut().unwrap().floor =
                    Some(crate::fixture::synthetic::paired_floor(2.0));
            }
        }
        let md = markdown(&results, None);
        assert!(md.contains("drifted · 4.00 ms · 2.00×"), "{md}");
        assert!(md.contains("plain · 6.00 ms · 0.600×"), "{md}");
    }
}
