//! One scene across the runs: each configuration's time as a multiple of the run's floor, its
//! headline on every run, the rank agreement of the times per pair of runs, and each run's
//! verdict (the report's Pareto front and "fastest under a budget", without the floor).

use std::collections::BTreeSet;

use harness::results::{Record, Status};

use super::model::{Cell, Changed, PairTau, Pick, Row, SceneComparison, Verdict};
use super::runs::Run;
use super::tau::PairCounts;
use super::tolerance;
use crate::analysis::{self, BUDGETS, Clock, TimeBasis};
use crate::metric::{Metric, verdict_error};

pub use crate::analysis::FLOOR_METHOD;

/// A run's records of `scene` whose keys every run has (`common`), first of each key only.
fn records<'a>(run: &'a Run, scene: &str, common: &BTreeSet<String>) -> Vec<&'a Record> {
    let mut seen = BTreeSet::new();
    run.results
        .records
        .iter()
        .filter(|r| r.scene == scene && common.contains(&r.key()))
        .filter(|r| seen.insert(r.key()))
        .collect()
}

pub fn compare(runs: &[Run], scene: &str, common: &BTreeSet<String>) -> SceneComparison {
    let per_run: Vec<Vec<&Record>> = runs.iter().map(|r| records(r, scene, common)).collect();
    let basis = TimeBasis::for_records(per_run.iter().flatten().copied());
    let clocks: Vec<Clock> = per_run.iter().map(|rs| Clock::on(basis, rs)).collect();
    let rows = rows(&per_run, &clocks);
    let tau = pairs(runs.len())
        .map(|(a, b)| pair_tau(&rows, a, b))
        .collect();
    let verdicts: Vec<Verdict> = per_run
        .iter()
        .zip(&clocks)
        .map(|(rs, &clock)| verdict(rs, clock))
        .collect();
    SceneComparison {
        scene: scene.to_string(),
        time_basis: match basis {
            TimeBasis::Gpu => "gpu",
            TimeBasis::Wall => "wall",
        },
        floor_ms: clocks.iter().map(|c| c.floor_ms).collect(),
        changed: changed(&verdicts),
        rows,
        tau,
        verdicts,
    }
}

/// Every pair (a, b), a < b, of `n` runs.
pub fn pairs(n: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..n).flat_map(move |a| (a + 1..n).map(move |b| (a, b)))
}

/// One row per key, in the first run's order with the floor first.
fn rows(per_run: &[Vec<&Record>], clocks: &[Clock]) -> Vec<Row> {
    let mut firsts: Vec<&Record> = per_run[0].clone();
    firsts.sort_by_key(|r| r.method != FLOOR_METHOD);
    firsts
        .iter()
        .map(|first| {
            let key = first.key();
            let runs: Vec<Cell> = per_run
                .iter()
                .zip(clocks)
                .map(|(rs, &clock)| {
                    let r = rs.iter().find(|r| r.key() == key).expect("a common key");
                    cell(r, clock)
                })
                .collect();
            let headlines: Vec<f64> = runs.iter().filter_map(|c| c.headline).collect();
            Row {
                headlines_agree: (headlines.len() >= 2).then(|| tolerance::agree(&headlines)),
                method: first.method.clone(),
                params: first.params.clone(),
                floor: first.method == FLOOR_METHOD,
                key,
                runs,
            }
        })
        .collect()
}

fn cell(r: &Record, clock: Clock) -> Cell {
    let ok = r.status == Status::Ok;
    let time_ms = clock.time_ms(r).filter(|t| ok && t.is_finite() && *t > 0.0);
    Cell {
        status: r.status,
        reason: r.reason.clone(),
        time_ms,
        ratio: time_ms.and(clock.floor_ratio(r)),
        headline: verdict_error(r).filter(|_| ok),
    }
}

fn pair_tau(rows: &[Row], a: usize, b: usize) -> PairTau {
    let times: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| r.runs[a].time_ms.zip(r.runs[b].time_ms))
        .collect();
    let counts = PairCounts::of(&times);
    PairTau {
        a,
        b,
        tau: counts.tau_b(),
        counts,
    }
}

/// The run's verdict among the contenders (every configuration but the floor's), timed by
/// the run's clock on the scene.
fn verdict(records: &[&Record], clock: Clock) -> Verdict {
    let contenders = analysis::contenders(records);
    let points = analysis::points_by(&contenders, clock, Metric::Verdict);
    let pick = |p: analysis::Point| {
        let r = contenders[p.index];
        Pick {
            key: r.key(),
            method: r.method.clone(),
            params: r.params.clone(),
            time_ms: p.time,
            error: p.error,
            floor_ratio: clock.floor_ratio(r),
        }
    };
    Verdict {
        front: analysis::pareto_front(&points)
            .into_iter()
            .map(pick)
            .collect(),
        budgets: BUDGETS
            .iter()
            .map(|&b| analysis::cheapest_under_budget(&points, b).map(pick))
            .collect(),
    }
}

/// A verdict changed when the runs' fronts hold different configurations, or a budget's
/// winners differ (a budget won on one run and not reached on another counts).
fn changed(verdicts: &[Verdict]) -> Changed {
    let front_keys = |v: &Verdict| {
        v.front
            .iter()
            .map(|p| p.key.clone())
            .collect::<BTreeSet<_>>()
    };
    let differs =
        |f: &dyn Fn(&Verdict) -> Option<String>| verdicts.windows(2).any(|w| f(&w[0]) != f(&w[1]));
    Changed {
        front: verdicts
            .windows(2)
            .any(|w| front_keys(&w[0]) != front_keys(&w[1])),
        budgets: (0..BUDGETS.len())
            .map(|i| differs(&|v: &Verdict| v.budgets[i].as_ref().map(|p| p.key.clone())))
            .collect(),
    }
}
