//! `scatterbench tune`: per scene and error budget, the cheapest configuration of each method
//! under the budget and the overall winner, with 95 % intervals on its floor ratio
//! (ARCHITECTURE §4.6). The search and the statistics are `harness::tune`; this module spends
//! the time limit on the GPU:
//! - each scene gets an equal share of what is left; within it, [`SCREEN_SHARE`] screens
//!   (`screen.rs`: one timed pair and the headline per configuration), the rest
//!   times the candidates (`timing.rs`) and writes the winners' full records;
//! - tune.json, tune.md and results.json (the winners' records and the floor's, with images)
//!   are written after every scene, atomically; the report gets a tune section.
//!
//! The floor (no-scatter) is always the denominator, at its defaults: knobs it shares with a
//! method (the scene's rasterisation: `shadow_map`, `local_shadow_budget`) are not searched,
//! so every ratio of a scene divides by the same work (`--param` may still fix them).

mod ctx;
mod screen;
mod timing;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Result, anyhow};
use clap::Args;
use harness::method::find;
use harness::record::RecordSettings;
use harness::results::Results;
use harness::tune::{TUNE_FILE, TuneResults, verdict};
use report::analysis::FLOOR_METHOD;

use self::ctx::Ctx;
use crate::registry::Registry;
use crate::args::{self, MethodList, Output, Size};

/// The share of a scene's time spent screening; the rest times the candidates and writes the
/// winners' records.
pub const SCREEN_SHARE: f64 = 0.6;
/// Of a scene's share, the part kept for the winners' full records.
pub const RECORDS_SHARE: f64 = 0.12;
/// The summary counts scenes whose winner is within this many times the floor.
pub const AFFORDABLE: f64 = report::frontier::AFFORDABLE_RATIO;

#[derive(Args)]
pub struct TuneArgs {
    /// Comma-separated scenes (library names, variants, .json paths), or "all".
    #[arg(long, default_value = "all")]
    pub scenes: String,
    #[command(flatten)]
    pub methods: MethodList,
    /// Comma-separated error budgets on the verdict metric (fractions, each in (0, 10]).
    #[arg(long, default_value = "0.01,0.05,0.10", value_parser = parse_budgets)]
    pub budgets: Budgets,
    #[command(flatten)]
    pub size: Size,
    /// Wall-clock limit for the whole tune in seconds, 10..=86400: each scene gets an equal
    /// share of what is left.
    #[arg(long, default_value = "1800", value_parser = args::int_in(10..=86400u64))]
    pub time_limit: u64,
    /// METHOD.KNOB=VALUE (repeatable): fixes a knob (it is not searched).
    #[arg(long = "param")]
    pub params: Vec<String>,
    #[command(flatten)]
    pub output: Output,
    #[command(flatten)]
    pub device: crate::args::device::DeviceArgs,
}

/// Error budgets, ascending.
#[derive(Clone, Debug)]
pub struct Budgets(pub Vec<f64>);

fn parse_budgets(s: &str) -> Result<Budgets, String> {
    let mut v = Vec::new();
    for item in s.split(',') {
        let b: f64 = item.trim().parse().map_err(|_| {
            format!("'{item}' is not a number (budgets are fractions: 0.01 is 1 %)")
        })?;
        if !(b > 0.0 && b <= 10.0) {
            return Err(format!("budget {b} is out of range: allowed is (0, 10]"));
        }
        v.push(b);
    }
    v.sort_by(f64::total_cmp);
    v.dedup();
    Ok(Budgets(v))
}


pub fn run(a: TuneArgs, registry: Registry) -> Result<()> {
    let start = Instant::now();
    let chosen = args::pick_methods(&a.methods.methods, registry)?;
    let scenes = args::pick_scenes(&a.scenes)?;
    let overrides = args::parse_overrides(&a.params, &chosen, registry)?;
    let Some(floor) = find(registry, FLOOR_METHOD) else {
        return args::refuse(format!(
            "the floor method {FLOOR_METHOD} is not in the registry"
        ));
    };
    let methods: Vec<_> = chosen
        .into_iter()
        .filter(|m| m.id() != FLOOR_METHOD)
        .collect();
    if methods.is_empty() {
        return args::refuse("--methods: no method to tune besides the floor".to_string());
    }
    let run_id = format!("tune-{}", harness::results::run_id_now());
    let out: PathBuf = a.output.dir(&run_id);
    args::check_fresh(&out)?;
    std::fs::create_dir_all(&out).map_err(|e| anyhow!("{}: {e}", out.display()))?;
    let gpu = a.device.open()?;
    let (w, h) = (a.size.res.width, a.size.res.height);
    let settings = RecordSettings {
        cache_dir: Some(a.output.cache.clone()),
        paired_floor: Some(FLOOR_METHOD.to_string()),
        budget_ms: Some(4000.0),
        ..RecordSettings::new(&out, (w, h), (5, 1))
    };
    let mut results = harness::runner::fresh_results(&gpu, &settings, &run_id, None);
    results.run.kind = Some("tune".into());
    let ctx = Ctx {
        gpu: &gpu,
        floor,
        methods,
        overrides,
        budgets: a.budgets.0.clone(),
        settings,
        start,
    };
    let limit = Duration::from_secs(a.time_limit);
    eprintln!(
        "tuning {} methods on {} scenes at {w}x{h}, budgets {:?}, time limit {} s",
        ctx.methods.len(),
        scenes.len(),
        ctx.budgets,
        a.time_limit
    );
    let mut tune = TuneResults {
        schema_version: harness::tune::results::TUNE_SCHEMA_VERSION,
        run: results.run.clone(),
        budgets: ctx.budgets.clone(),
        time_limit_s: limit.as_secs_f64(),
        wall_s: 0.0,
        interval: harness::tune::interval::DESCRIPTION.into(),
        scenes: Vec::new(),
        summary: Vec::new(),
    };
    for (i, scene) in scenes.iter().enumerate() {
        let left = limit.saturating_sub(start.elapsed());
        let share = left / (scenes.len() - i) as u32;
        let (scene_tune, records) = tune_scene(&ctx, scene, share)?;
        results.records.extend(records);
        tune.scenes.push(scene_tune);
        finish(&mut tune, &results, &out, start)?;
    }
    let md = report::tune::markdown(&tune);
    print!("{md}");
    println!("written: {}", out.join(TUNE_FILE).display());
    super::write_report(&out);
    Ok(())
}

/// One scene: screen, time, decide, and the winners' full records.
fn tune_scene(
    ctx: &Ctx,
    scene: &scenes::Scene,
    share: Duration,
) -> Result<(harness::tune::SceneTune, Vec<harness::results::Record>)> {
    let scene_start = Instant::now();
    let refs = screen::References::load(ctx, scene, &ctx.settings.out_dir)?;
    let screen_end = scene_start + share.mul_f64(SCREEN_SHARE);
    let timing_end = scene_start + share.mul_f64(1.0 - RECORDS_SHARE);
    let mut screening = screen::screen(ctx, scene, &refs, screen_end);
    let screen_s = scene_start.elapsed().as_secs_f64();
    let ph = screening.phases;
    eprintln!(
        "{}: screened {} configurations ({} proposed by the surrogate, {} left out as too \
         costly) of {} methods in {screen_s:.0} s (prepare {:.0} s, time {:.0} s, score {:.0} s){}",
        scene.name,
        screening.log.evaluations,
        screening.log.proposals,
        screening.log.pruned,
        screening
            .methods
            .iter()
            .filter(|m| m.skipped.is_none())
            .count(),
        ph.prepare_s,
        ph.time_s,
        ph.score_s,
        if screening.log.stopped {
            " (time's up)"
        } else {
            ""
        }
    );
    let timed = timing::time_candidates(ctx, scene, &refs, &mut screening, timing_end);
    let time_s = scene_start.elapsed().as_secs_f64() - screen_s;
    let verdicts: Vec<_> = ctx
        .budgets
        .iter()
        .map(|&b| verdict::decide(&timed.candidates, b))
        .collect();
    let records = timing::winner_records(ctx, scene, &refs, &timed.candidates, &verdicts);
    eprintln!(
        "{}: timed {} candidates in {time_s:.0} s; {} records",
        scene.name,
        timed.candidates.len(),
        records.len()
    );
    let drift = harness::tune::drift::detect(&screening.floor_samples_then(timed.floor_samples));
    let tune = harness::tune::SceneTune {
        scene: scene.name.clone(),
        floor_ms: timed.floor_ms,
        basis: timed.basis.into(),
        methods: screening.methods,
        screened: screening.screened,
        candidates: timed.candidates,
        verdicts,
        drift,
        screen_s,
        time_s,
        search_stopped: screening.log.stopped,
        surrogate_proposals: screening.log.proposals,
        pruned: screening.log.pruned,
        screen_phases_s: [ph.prepare_s, ph.time_s, ph.score_s],
    };
    Ok((tune, records))
}

/// The summary, tune.json, tune.md and results.json as they stand.
fn finish(
    tune: &mut TuneResults,
    results: &Results,
    out: &std::path::Path,
    start: Instant,
) -> Result<()> {
    tune.wall_s = start.elapsed().as_secs_f64();
    let per_scene: Vec<&[harness::tune::Timed]> = tune
        .scenes
        .iter()
        .map(|s| s.candidates.as_slice())
        .collect();
    tune.summary = tune
        .budgets
        .iter()
        .map(|&b| verdict::count(&per_scene, b, AFFORDABLE))
        .collect();
    tune.save(&out.join(TUNE_FILE)).map_err(|e| anyhow!(e))?;
    results
        .save(&out.join("results.json"))
        .map_err(|e| anyhow!(e))?;
    harness::fsutil::write_atomic(
        &out.join("tune.md"),
        report::tune::markdown(tune).as_bytes(),
    )
    .map_err(|e| anyhow!(e))
}
