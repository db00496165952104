//! A tune's verdicts (`scatterbench tune`, ARCHITECTURE §4.6) as Markdown (tune.md, printed)
//! and as the report's tune section: per scene and budget the winner with its knobs, floor
//! ratio, 95 % interval and error, the runner-up of another method and whether the two are
//! separable (a tie where not), the floor's drift, and the summary count with its range.

use std::fmt::Write;

use harness::tune::{BudgetVerdict, Interval, SceneTune, Timed, TuneResults};

use crate::verdict::pct;

/// The headline a tune ranks by: the one its run names, else this build's.
fn headline(t: &TuneResults) -> &str {
    t.run
        .headline
        .as_deref()
        .unwrap_or(harness::verdict::HEADLINE_NAME)
}

/// An error with the digits a small one needs: "0.61 %", "0.0047 %".
pub fn error_text(e: f64) -> String {
    let p = 100.0 * e;
    if p >= 0.1 || p == 0.0 {
        format!("{p:.2} %")
    } else {
        format!("{p:.2e} %")
    }
}

/// "1.42× [1.38, 1.47]", or "—".
pub fn ratio_text(i: Option<&Interval>) -> String {
    match i {
        Some(i) if i.high.is_finite() => {
            format!("{:.2}× [{:.2}, {:.2}]", i.estimate, i.low, i.high)
        }
        Some(i) => format!("{:.2}× [n = {}, no interval]", i.estimate, i.n),
        None => "—".into(),
    }
}

/// "method `knobs` · 1.42× [1.38, 1.47] · 0.61 %".
pub fn candidate_text(c: &Timed) -> String {
    format!(
        "{} `{}` · {} · {}",
        c.method,
        c.knobs,
        ratio_text(c.ratio.as_ref()),
        error_text(c.error)
    )
}

/// The winner's cell: the candidate, or what the budget was missed by.
pub fn winner_cell(s: &SceneTune, v: &BudgetVerdict) -> String {
    match v.winner {
        Some(w) => {
            let tie = if v.tie.is_empty() { "" } else { " (tie)" };
            format!("{}{tie}", candidate_text(&s.candidates[w]))
        }
        None => "none under the budget".into(),
    }
}

/// The runner-up's cell, with the separation.
pub fn runner_up_cell(s: &SceneTune, v: &BudgetVerdict) -> String {
    match v.runner_up {
        Some(r) => format!(
            "{} · {}",
            candidate_text(&s.candidates[r]),
            if v.separable {
                "separable"
            } else {
                "**inseparable: a tie**"
            }
        ),
        None => "—".into(),
    }
}

/// The floor's drift in words, or "—".
pub fn drift_text(s: &SceneTune) -> String {
    match &s.drift {
        Some(d) => format!(
            "{:+.0} % over {:.0} s ({:+.1} %/min), largest step {:+.0} %{}",
            100.0 * d.trend_total,
            d.span_s,
            100.0 * d.trend_per_min,
            100.0 * d.jump,
            if d.flagged { " **drift**" } else { "" }
        ),
        None => "—".into(),
    }
}

/// tune.md.
pub fn markdown(t: &TuneResults) -> String {
    let mut out = String::new();
    let run = &t.run;
    let _ = writeln!(
        out,
        "# Tune {} ({}, {}×{}, commit {})\n",
        run.id, run.machine.adapter, run.resolution[0], run.resolution[1], run.git_commit
    );
    let _ = writeln!(
        out,
        "Per scene and budget of the in-scatter headline (`{}`, the verdict metric, \
         ARCHITECTURE §4.4), the cheapest configuration found and timed, its floor ratio (its \
         frame time over the floor's, no-scatter, paired frame by frame) with the ratio's 95 % \
         interval, and its headline (the % in each cell); the runner-up is the best of another \
         method. Interval: {}. Times compare only as ratios within one run. Wall time {:.0} s \
         of a {:.0} s limit.\n",
        headline(t),
        t.interval,
        t.wall_s,
        t.time_limit_s
    );
    if let Some(c) = &run.machine.calibration {
        let _ = writeln!(
            out,
            "Adapter calibration (ARCHITECTURE §7.1): {}.\n",
            crate::calibration::text(c)
        );
    }
    for c in &t.summary {
        let _ = writeln!(
            out,
            "- **Under {}: within {}× the floor on {} of {} scenes** (the intervals allow {}–{}).",
            pct(c.budget),
            c.limit,
            c.k,
            c.n,
            c.low,
            c.high
        );
    }
    out.push_str("\n| scene | budget | winner | runner-up |\n|---|---|---|---|\n");
    for s in &t.scenes {
        for v in &s.verdicts {
            let _ = writeln!(
                out,
                "| {} | ≤ {} headline | {} | {} |",
                s.scene,
                pct(v.budget),
                winner_cell(s, v),
                runner_up_cell(s, v)
            );
        }
    }
    out.push_str("\n| scene | floor | screened | timed | floor drift |\n|---|---|---|---|---|\n");
    for s in &t.scenes {
        let floor = s
            .floor_ms
            .map_or("—".into(), |f| format!("{f:.2} ms ({})", s.basis));
        let _ = writeln!(
            out,
            "| {} | {floor} | {} configurations ({} from the surrogate) in {:.0} s{} | {} \
             candidates in {:.0} s | {} |",
            s.scene,
            s.screened.len(),
            s.surrogate_proposals,
            s.screen_s,
            if s.search_stopped { " (stopped)" } else { "" },
            s.candidates.len(),
            s.time_s,
            drift_text(s)
        );
    }
    out
}

/// The report's tune section (a `scatterbench tune` run: tune.json beside results.json).
#[derive(Clone, Debug, serde::Serialize)]
pub struct TuneView {
    pub summary: Vec<String>,
    pub rows: Vec<TuneRow>,
    pub scenes: Vec<TuneSceneRow>,
    pub wall: String,
    pub interval: String,
    /// The headline the budgets are of (`run.headline`).
    pub headline: String,
}

/// One scene × budget.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TuneRow {
    pub scene: String,
    /// The scene's first row carries the row span of its budgets.
    pub span: usize,
    pub budget: String,
    pub winner: String,
    pub winner_ratio: String,
    pub winner_error: String,
    pub runner_up: String,
    /// "separable", "tie" or "".
    pub verdict: String,
}

/// One scene's search and drift.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TuneSceneRow {
    pub scene: String,
    pub floor: String,
    pub screened: String,
    pub timed: String,
    pub drift: String,
    pub drift_flagged: bool,
}

/// The section's view of `run_dir/tune.json`; None where there is none. A tune.json that
/// cannot be read is an error naming it.
pub fn view(run_dir: &std::path::Path) -> anyhow::Result<Option<TuneView>> {
    let path = run_dir.join(harness::tune::TUNE_FILE);
    if !path.is_file() {
        return Ok(None);
    }
    let t = TuneResults::load(&path).map_err(|e| anyhow::anyhow!(e))?;
    let summary = t
        .summary
        .iter()
        .map(|c| {
            format!(
                "Under {}: within {}× the floor on {} of {} scenes (the 95 % intervals allow {}–{}).",
                pct(c.budget),
                c.limit,
                c.k,
                c.n,
                c.low,
                c.high
            )
        })
        .collect();
    let mut rows = Vec::new();
    for s in &t.scenes {
        for (k, v) in s.verdicts.iter().enumerate() {
            let w = v.winner.map(|w| &s.candidates[w]);
            rows.push(TuneRow {
                scene: s.scene.clone(),
                span: if k == 0 { s.verdicts.len() } else { 0 },
                budget: format!("≤ {}", pct(v.budget)),
                winner: w.map_or("none under the budget".into(), |c| {
                    format!("{} {}", c.method, c.knobs)
                }),
                winner_ratio: w.map_or("—".into(), |c| ratio_text(c.ratio.as_ref())),
                winner_error: w.map_or("—".into(), |c| error_text(c.error)),
                runner_up: v.runner_up.map_or("—".into(), |r| {
                    candidate_text(&s.candidates[r]).replace('`', "")
                }),
                verdict: match (v.winner, v.runner_up) {
                    (Some(_), Some(_)) if !v.separable => "tie".into(),
                    (Some(_), Some(_)) => "separable".into(),
                    _ => String::new(),
                },
            });
        }
    }
    let scenes = t
        .scenes
        .iter()
        .map(|s| TuneSceneRow {
            scene: s.scene.clone(),
            floor: s
                .floor_ms
                .map_or("—".into(), |f| format!("{f:.2} ms ({})", s.basis)),
            screened: format!(
                "{} in {:.0} s{}",
                s.screened.len(),
                s.screen_s,
                if s.search_stopped { " (time's up)" } else { "" }
            ),
            timed: format!("{} in {:.0} s", s.candidates.len(), s.time_s),
            drift: drift_text(s).replace("**", ""),
            drift_flagged: s.drift.as_ref().is_some_and(|d| d.flagged),
        })
        .collect();
    Ok(Some(TuneView {
        summary,
        rows,
        scenes,
        wall: format!("{:.0} s of a {:.0} s limit", t.wall_s, t.time_limit_s),
        interval: t.interval.clone(),
        headline: headline(&t).to_string(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use harness::verdict::HEADLINE_NAME;

    /// tune.md names the headline its budgets are of: the caption names the definition, each
    /// budget cell says "headline", and the % in each cell is the candidate's headline.
    #[test]
    fn tune_md_names_the_headline_it_ranks_by() {
        let run = crate::fixture::synthetic::run("lavapipe", 64);
        let md = markdown(&crate::fixture::synthetic::tune(&run));
        assert!(
            md.contains(&format!(
                "budget of the in-scatter headline (`{HEADLINE_NAME}`"
            )),
            "{md}"
        );
        let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| s |")).collect();
        assert_eq!(rows.len(), 3 + 1, "three budgets and the search row:\n{md}");
        for (row, b) in rows.iter().zip(["1 %", "5 %", "10 %"]) {
            assert!(
                row.starts_with(&format!("| s | ≤ {b} headline | ")),
                "{row}"
            );
        }
        // m-exact's headline is 0.5 %, m-fast's 3 %.
        assert!(
            rows[0].contains("| m-exact `defaults` · 4.00× ["),
            "{}",
            rows[0]
        );
        assert!(rows[0].contains("] · 0.50 % |"), "{}", rows[0]);
        assert!(
            rows[1].contains("| m-fast `defaults` · 1.50× ["),
            "{}",
            rows[1]
        );
        assert!(rows[1].contains("] · 3.00 % |"), "{}", rows[1]);
    }
}
