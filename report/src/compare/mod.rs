//! `scatterbench compare RUN_A RUN_B [...]`: runs of the same work list measured on different
//! adapters, side by side (ARCHITECTURE §5.3). Times do not transfer between adapters, so
//! each is read as a multiple of its own run's floor (`no-scatter` on the same scene); what
//! should transfer is the order of the methods (Kendall τ-b per scene and overall,
//! [`tau`]), the verdicts (the report's Pareto front and "fastest under 1 / 5 / 10 %", the
//! floor left out; the ones that change are marked) and, since every method is deterministic,
//! each record's headline error (equal within [`tolerance`]; a larger difference is flagged
//! as a precision problem or undefined behaviour on one adapter).
//!
//! Records are matched by `harness::results::record_key` (scene | method | params); work that
//! some run lacks is listed and left out of everything else. Reads only results.json.
//! Writes `compare.json` ([`model::Comparison`]) and `compare.html` ([`page`]: self-contained,
//! opens from disk).

pub mod model;
pub mod page;
pub mod runs;
pub mod scene;
pub mod summary;
pub mod tau;
pub mod tolerance;

#[cfg(test)]
mod tests;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use harness::results::{Record, Results};

use self::model::{
    Comparison, HeadlineFlag, RunSummary, SceneComparison, StatusDiffers, TauOverall, Unmatched,
};
use self::runs::Run;
use self::scene::{FLOOR_METHOD, pairs};
use crate::analysis::{BUDGETS, ordered};
use crate::metric::Metric;

pub use self::runs::{CompareError, load};

/// Compares `runs` (already checked to hold the same kind of work by [`load`]).
pub fn compare(runs: &[Run]) -> Comparison {
    let first = &runs[0].results.run;
    let common = common_keys(runs);
    let scene_names = ordered(
        runs.iter()
            .flat_map(|r| r.results.records.iter())
            .filter(|r| common.contains(&r.key()))
            .map(|r| r.scene.as_str()),
    );
    let scenes: Vec<SceneComparison> = scene_names
        .iter()
        .map(|s| scene::compare(runs, s, &common))
        .collect();
    Comparison {
        schema: model::SCHEMA,
        runs: summaries(runs),
        resolution: first.resolution,
        frames: first.frames,
        warmup: first.warmup,
        metric: Metric::Verdict.label(first.headline.as_deref()),
        metric_short: Metric::Verdict.short(first.headline.as_deref()),
        floor_method: FLOOR_METHOD,
        budgets: BUDGETS.to_vec(),
        tolerance: tolerance::TOLERANCE,
        tau: pairs(runs.len())
            .map(|(a, b)| tau_overall(&scenes, a, b))
            .collect(),
        headline_flags: headline_flags(&scenes),
        status_differs: status_differs(&scenes),
        not_in_every_run: unmatched(runs, &common),
        notes: notes(runs),
        scenes,
    }
}

/// Each run's summary, with the raster-limited flag (`calibration`) from all of them.
fn summaries(runs: &[Run]) -> Vec<RunSummary> {
    let calibrations: Vec<_> = runs
        .iter()
        .map(|r| (r.label.as_str(), r.results.run.machine.calibration.as_ref()))
        .collect();
    let flags = crate::calibration::raster_limited(&calibrations);
    runs.iter()
        .zip(flags)
        .map(|(run, raster_limited)| RunSummary {
            label: run.label.clone(),
            dir: run.dir.display().to_string(),
            id: run.results.run.id.clone(),
            git_commit: run.results.run.git_commit.clone(),
            machine: run.results.run.machine.clone(),
            records: run.results.records.len(),
            raster_limited,
        })
        .collect()
}

fn keys(results: &Results) -> BTreeSet<String> {
    results.records.iter().map(Record::key).collect()
}

/// The record keys every run has.
fn common_keys(runs: &[Run]) -> BTreeSet<String> {
    let mut common = keys(&runs[0].results);
    for r in &runs[1..] {
        common = common.intersection(&keys(&r.results)).cloned().collect();
    }
    common
}

/// Work some run lacks, with the runs that have it, in order of first appearance.
fn unmatched(runs: &[Run], common: &BTreeSet<String>) -> Vec<Unmatched> {
    let mut out: BTreeMap<String, (usize, Unmatched)> = BTreeMap::new();
    for run in runs {
        for r in run
            .results
            .records
            .iter()
            .filter(|r| !common.contains(&r.key()))
        {
            let n = out.len();
            let entry = out.entry(r.key()).or_insert_with(|| {
                let u = Unmatched {
                    key: r.key(),
                    scene: r.scene.clone(),
                    method: r.method.clone(),
                    params: r.params.clone(),
                    in_runs: Vec::new(),
                };
                (n, u)
            });
            if !entry.1.in_runs.contains(&run.label) {
                entry.1.in_runs.push(run.label.clone());
            }
        }
    }
    let mut list: Vec<(usize, Unmatched)> = out.into_values().collect();
    list.sort_by_key(|(n, _)| *n);
    list.into_iter().map(|(_, u)| u).collect()
}

fn tau_overall(scenes: &[SceneComparison], a: usize, b: usize) -> TauOverall {
    let of_pair: Vec<&model::PairTau> = scenes
        .iter()
        .flat_map(|s| s.tau.iter().filter(|t| (t.a, t.b) == (a, b)))
        .collect();
    let defined: Vec<f64> = of_pair.iter().filter_map(|t| t.tau).collect();
    let counts: tau::PairCounts = of_pair.iter().map(|t| t.counts).sum();
    TauOverall {
        a,
        b,
        mean: (!defined.is_empty()).then(|| defined.iter().sum::<f64>() / defined.len() as f64),
        scenes: defined.len(),
        pooled: counts.tau_b(),
        counts,
    }
}

fn headline_flags(scenes: &[SceneComparison]) -> Vec<HeadlineFlag> {
    scenes
        .iter()
        .flat_map(|s| s.rows.iter().map(move |r| (s, r)))
        .filter(|(_, r)| r.headlines_agree == Some(false))
        .map(|(s, r)| {
            let headlines: Vec<Option<f64>> = r.runs.iter().map(|c| c.headline).collect();
            let values: Vec<f64> = headlines.iter().flatten().copied().collect();
            let (lo, hi) = tolerance::spread(&values).expect("two headlines");
            HeadlineFlag {
                scene: s.scene.clone(),
                method: r.method.clone(),
                params: r.params.clone(),
                key: r.key.clone(),
                headlines,
                difference: hi - lo,
                allowed: tolerance::allowed(lo),
            }
        })
        .collect()
}

fn status_differs(scenes: &[SceneComparison]) -> Vec<StatusDiffers> {
    scenes
        .iter()
        .flat_map(|s| s.rows.iter().map(move |r| (s, r)))
        .filter(|(_, r)| r.runs.windows(2).any(|w| w[0].status != w[1].status))
        .map(|(s, r)| StatusDiffers {
            scene: s.scene.clone(),
            method: r.method.clone(),
            params: r.params.clone(),
            key: r.key.clone(),
            statuses: r.runs.iter().map(|c| c.status).collect(),
            reasons: r.runs.iter().map(|c| c.reason.clone()).collect(),
        })
        .collect()
}

fn notes(runs: &[Run]) -> Vec<String> {
    let mut notes = Vec::new();
    let height = runs[0].results.run.resolution[1];
    if height < tolerance::MIN_HEIGHT {
        notes.push(format!(
            "at {height} px high, pixels along edges are a large share of the image: \
             rasterisers of different sub-pixel precision move the headline of methods scored \
             there by more than the tolerance (measured at 64²: raymarch-brute +15 %, \
             epipolar-minmax +20 % on fence-spot), so flags here may be rasterisation, not \
             precision bugs — compare at {} px or more to find those",
            tolerance::MIN_HEIGHT
        ));
    }
    for run in runs {
        let n = run.results.records.len() - keys(&run.results).len();
        if n > 0 {
            notes.push(format!(
                "{} ({}) holds {n} record(s) twice; the first of each is compared",
                run.label,
                run.dir.display()
            ));
        }
    }
    for (a, b) in pairs(runs.len()) {
        let (ma, mb) = (&runs[a].results.run.machine, &runs[b].results.run.machine);
        if ma.adapter == mb.adapter && ma.driver_info == mb.driver_info {
            notes.push(format!(
                "{} and {} ran on the same adapter ({}): differences between them are run-to-run \
                 noise",
                runs[a].label, runs[b].label, ma.adapter
            ));
        }
    }
    notes
}

/// The files [`write`] wrote.
pub struct Written {
    pub json: PathBuf,
    pub html: PathBuf,
}

/// Writes `out/compare.json` and `out/compare.html`.
pub fn write(out: &Path, comparison: &Comparison) -> Result<Written> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let json = out.join("compare.json");
    let text = serde_json::to_string_pretty(comparison).context("serialising compare.json")?;
    std::fs::write(&json, text).with_context(|| format!("writing {}", json.display()))?;
    let html = out.join("compare.html");
    let page = page::render(comparison)?;
    std::fs::write(&html, page).with_context(|| format!("writing {}", html.display()))?;
    Ok(Written { json, html })
}
