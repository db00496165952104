//! The timing phase of a scene: the candidates near each budget's front, picked from the
//! screening, kept prepared beside the floor and timed round-robin in rounds of interleaved
//! pairs while their verdict is open (`harness::tune::verdict::open`), each round one batch of
//! the candidate's interval (`Interval::of_rounds`); then the winners' full records
//! (`record::run_one`, with images) for results.json and the report.

use std::time::Instant;

use harness::method::{Method, Params, Support, resolve_params};
use harness::record::{Contender, run_one};
use harness::results::Record;
use harness::tune::search::Point;
use harness::tune::{BudgetVerdict, Interval, Timed, verdict};

use super::ctx::Ctx;
use super::screen::{References, Screening};

/// Per budget and method, configurations within this fraction of the method's cheapest
/// screened cost under the budget are candidates (the one-pair estimate's noise).
pub const CANDIDATE_MARGIN: f64 = 0.3;
/// At most this many candidates per method and budget, …
pub const PER_METHOD: usize = 2;
/// … of the methods whose cheapest is within this many times the budget's best, …
pub const METHOD_SPREAD: f64 = 2.5;
/// … at most this many methods per budget.
pub const METHODS_PER_BUDGET: usize = 4;
/// Pairs per round; the first round has [`FIRST_WARMUP`] untimed pairs before.
pub const ROUND: u32 = 4;
pub const FIRST_WARMUP: u32 = 2;

/// What timing a scene's candidates measured.
pub struct TimedOut {
    pub candidates: Vec<Timed>,
    /// The median floor frame over all pairs, ms.
    pub floor_ms: Option<f64>,
    pub basis: &'static str,
    pub floor_samples: Vec<(f64, f64)>,
}

/// Picks, prepares and times the candidates until `deadline` or every verdict is settled.
pub fn time_candidates(
    ctx: &Ctx,
    scene: &scenes::Scene,
    refs: &References,
    screening: &mut Screening,
    deadline: Instant,
) -> TimedOut {
    let picks = pick(&screening.log.points, &ctx.budgets, screening.entries.len());
    let mut candidates = Vec::new();
    let mut live: Vec<(usize, Contender)> = Vec::new();
    // Per candidate, per round: the round's pair log ratios (the interval's batches).
    let mut rounds: Vec<Vec<Vec<f64>>> = Vec::new();
    for p in &picks {
        let entry = screening.entries[p.method];
        let mut t = Timed {
            method: entry.id().into(),
            params: p.params.clone(),
            error: p.error,
            total_error: f64::NAN,
            mean_ratio: None,
            ratio: None,
            knobs: knobs_off_defaults(entry, &p.params),
            failed: None,
        };
        match Contender::prepare(ctx.gpu, scene, (entry, &p.params), ctx.floor, &ctx.settings)
            .and_then(|mut c| c.score(ctx.gpu, scene, &refs.scored()).map(|s| (c, s)))
        {
            Ok((c, s)) => {
                (t.error, t.total_error, t.mean_ratio) = (s.inscatter, s.total, s.mean_ratio);
                live.push((candidates.len(), c));
            }
            Err(why) => t.failed = Some(why),
        }
        candidates.push(t);
        rounds.push(Vec::new());
    }
    let basis = live.first().map_or("wall", |(_, c)| c.basis());
    let mut floors = Vec::new();
    let mut samples = Vec::new();
    let mut first = true;
    loop {
        let open = verdict::open(&candidates, &ctx.budgets);
        let todo: Vec<usize> = (0..live.len())
            .filter(|&k| first || open[live[k].0])
            .collect();
        // The first round always runs: every candidate gets a ratio.
        if todo.is_empty() || (!first && Instant::now() >= deadline) {
            break;
        }
        for k in todo {
            let (i, c) = &mut live[k];
            let warmup = if first { FIRST_WARMUP } else { 0 };
            match c.time(ctx.gpu, scene, warmup, ROUND) {
                Ok(pairs) => {
                    for p in &pairs {
                        floors.push(p.floor_ms);
                        samples.push((ctx.start.elapsed().as_secs_f64(), p.floor_ms));
                    }
                    rounds[*i].push(pairs.iter().map(|p| p.log_ratio()).collect());
                    candidates[*i].ratio = Interval::of_rounds(&rounds[*i]);
                }
                Err(why) => candidates[*i].failed = Some(why),
            }
            if !first && Instant::now() >= deadline {
                break;
            }
        }
        first = false;
        live.retain(|(i, _)| candidates[*i].failed.is_none());
    }
    TimedOut {
        candidates,
        floor_ms: median(&mut floors),
        basis,
        floor_samples: samples,
    }
}

/// The candidates: per budget, the two best methods and any others within [`METHOD_SPREAD`]
/// of the best, [`METHODS_PER_BUDGET`] at most, each with up to [`PER_METHOD`] configurations within
/// [`CANDIDATE_MARGIN`] of its cheapest; each configuration once.
pub fn pick(points: &[Point], budgets: &[f64], methods: usize) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::new();
    for &b in budgets {
        let mut per_method: Vec<Vec<&Point>> = (0..methods)
            .map(|m| {
                let mut v: Vec<&Point> = points
                    .iter()
                    .filter(|p| p.method == m && p.error <= b)
                    .collect();
                v.sort_by(|x, y| x.cost.total_cmp(&y.cost));
                v
            })
            .filter(|v| !v.is_empty())
            .collect();
        per_method.sort_by(|x, y| x[0].cost.total_cmp(&y[0].cost));
        let Some(best) = per_method.first().map(|v| v[0].cost) else {
            continue;
        };
        // The two best methods always (a runner-up to separate from), then any within the spread.
        for v in per_method
            .iter()
            .enumerate()
            .filter(|(k, v)| *k < 2 || v[0].cost <= best * METHOD_SPREAD)
            .map(|(_, v)| v)
            .take(METHODS_PER_BUDGET)
        {
            let cap = v[0].cost * (1.0 + CANDIDATE_MARGIN);
            for p in v.iter().filter(|p| p.cost <= cap).take(PER_METHOD) {
                if !out
                    .iter()
                    .any(|q| q.method == p.method && q.params == p.params)
                {
                    out.push((*p).clone());
                }
            }
        }
    }
    out
}

/// The full record (images, every metric, paired floor) of each budget's winner and of the
/// floor, for results.json and the report.
pub fn winner_records(
    ctx: &Ctx,
    scene: &scenes::Scene,
    refs: &References,
    candidates: &[Timed],
    verdicts: &[BudgetVerdict],
) -> Vec<Record> {
    let mut chosen: Vec<(&'static dyn Method, Params)> = vec![(
        ctx.floor,
        resolve_params(ctx.floor, &Params::new()).expect("the floor's defaults resolve"),
    )];
    for w in verdicts.iter().filter_map(|v| v.winner) {
        let c = &candidates[w];
        let entry = ctx
            .methods
            .iter()
            .find(|m| m.id() == c.method)
            .expect("a tuned method");
        if !chosen
            .iter()
            .any(|(m, p)| m.id() == c.method && *p == c.params)
        {
            chosen.push((*entry, c.params.clone()));
        }
    }
    chosen
        .into_iter()
        .map(|(entry, params)| {
            let mut rec = run_one(
                ctx.gpu,
                scene,
                entry,
                &params,
                &ctx.settings,
                (&refs.frame0, &refs.tone),
                Some(ctx.floor),
            );
            if let Support::Partial(v) = entry.support(&scene.features(), ctx.gpu.features()) {
                rec.ignored = v;
            }
            rec.ignored.extend(scene.ignored.iter().cloned());
            rec
        })
        .collect()
}

/// `knob=value …` off `entry`'s defaults, or "defaults".
pub fn knobs_off_defaults(entry: &dyn Method, params: &Params) -> String {
    let defaults = resolve_params(entry, &Params::new()).unwrap_or_default();
    report::format::knobs_or_defaults(params.iter().filter(|(k, v)| defaults.get(*k) != Some(*v)))
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}
