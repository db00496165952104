//! The runner: scenes × methods × parameter sets → records, written to `results.json`
//! atomically after every record. A method that panics, raises a wgpu error or renders
//! non-finite pixels is recorded as failed and the run goes on.
//!
//! Protocol (ARCHITECTURE §4): per record, `prepare` is timed once; then W warm-up and K timed
//! frames cycle through the scene's frames (so animated scenes pay their per-frame CPU work);
//! each timed frame records the `render` call (CPU), encode+submit+wait (wall) and timestamp
//! queries (GPU). Afterwards frame 0 is rendered once more (or, when the last timed frame was
//! frame 0, its output is kept), read back and scored against the reference of frame 0. With
//! a time budget (`RunConfig::budget_ms`) slow records get fewer frames ([`another_frame`]).
//!
//! The work list (scenes × methods × parameter sets, [`work_list`]) can be cut into shards
//! ([`run_shard`], `crate::shard`) or replaced by an explicit list ([`run_items`], used by
//! `scatterbench reproduce`).

use std::collections::BTreeMap;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;

use scenes::Scene;

use crate::gpu::{Gpu, GpuTimer, WORK_COUNTERS, read_rgba32f};
use crate::image::colormap::error_map;
use crate::image::headline::masked_relative;
use crate::image::metrics::{ToneMap, compare};
use crate::image::{Image, io};
use crate::method::{
    AOV_FORMAT, FrameReport, KnobError, Method, Params, PrepareContext, Prepared, Support, Targets,
    resolve_params,
};
use crate::reference::{self, ReferenceImages, Settings};
use crate::results::{
    Machine, Passes, Record, Results, RunInfo, SCHEMA_VERSION, Stat, Status, Timing, git_commit,
    record_key,
};
use crate::sequence::{AOV_NAMES, FrameScorer, finite};
use crate::shard::Shard;
use crate::verdict::light_core_mask;

pub struct RunConfig {
    pub out_dir: PathBuf,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub warmup: u32,
    pub no_skip: bool,
    pub resume: bool,
    pub sweep: bool,
    /// Per method id: knob overrides applied to every parameter set of that method.
    pub overrides: std::collections::BTreeMap<String, Params>,
    pub reference: Settings,
    /// Where reference images are cached (None: no cache).
    pub cache_dir: Option<PathBuf>,
    pub run_id: String,
    /// Per-record time budget (ms) for warm-up plus timed frames; None: always W + K frames.
    /// See [`another_frame`] for the rule.
    pub budget_ms: Option<f64>,
    /// Records in worker processes with a watchdog, or in process (the default); with
    /// `resume`, whether failed records run again. See [`crate::isolate`].
    pub isolation: crate::isolate::Isolation,
}

mod frame;
mod score;

use frame::measure;
pub use frame::{AovTargets, FrameTiming, MIN_TIMED_FRAMES, another_frame, render_frame};
pub use score::error_scale;
use score::write_aovs;
pub(crate) use score::{panic_message, run_one};

/// Events the caller may show (progress bars, log lines).
pub enum Event<'a> {
    Reference {
        scene: &'a str,
        cached: bool,
        seconds: f64,
    },
    Record(&'a Record),
    Resumed(&'a str),
}

/// The parameter sets to run: the defaults with the overrides, and with `sweep` one set per
/// declared sweep value of each knob (the others at their base values).
pub fn param_sets(
    method: &dyn Method,
    overrides: &Params,
    sweep: bool,
) -> Result<Vec<Params>, KnobError> {
    let specs = method.knobs();
    let base = resolve_params(method, overrides)?;
    let mut out = vec![base.clone()];
    if sweep {
        for s in &specs {
            if overrides.contains_key(s.name) {
                continue;
            }
            for v in &s.sweep {
                let mut p = base.clone();
                p.insert(s.name.to_string(), v.clone());
                if !out.contains(&p) {
                    out.push(p);
                }
            }
        }
    }
    Ok(out)
}

pub fn run(
    gpu: &Gpu,
    scenes: &[Scene],
    methods: &[&dyn Method],
    cfg: &RunConfig,
    on_event: &mut dyn FnMut(Event),
) -> Result<Results, String> {
    run_shard(gpu, scenes, methods, cfg, Shard::WHOLE, on_event)
}

/// One item of a run's work list: a scene (index into the caller's list), a method and a
/// full parameter set.
pub struct WorkItem<'a> {
    pub scene: usize,
    pub entry: &'a dyn Method,
    pub params: Params,
}

/// The run's work list in the order records are written: scenes, then methods, then
/// parameter sets. Sharding slices this list (see [`crate::shard`]).
pub fn work_list<'a>(
    scenes: &[Scene],
    methods: &[&'a dyn Method],
    cfg: &RunConfig,
) -> Result<Vec<WorkItem<'a>>, String> {
    // Parameter sets depend only on the method, so they are resolved once per method.
    let mut sets = Vec::with_capacity(methods.len());
    for entry in methods {
        let overrides = cfg.overrides.get(entry.id()).cloned().unwrap_or_default();
        sets.push(param_sets(*entry, &overrides, cfg.sweep).map_err(|e| format!("--param {e}"))?);
    }
    let mut out = Vec::new();
    for scene in 0..scenes.len() {
        for (&entry, sets) in methods.iter().zip(&sets) {
            for params in sets {
                out.push(WorkItem {
                    scene,
                    entry,
                    params: params.clone(),
                });
            }
        }
    }
    Ok(out)
}

/// Like [`run`], restricted to one shard of the work list; the shard is recorded in
/// `run.shard` so `merge` can reassemble the shards in order.
pub fn run_shard(
    gpu: &Gpu,
    scenes: &[Scene],
    methods: &[&dyn Method],
    cfg: &RunConfig,
    shard: Shard,
    on_event: &mut dyn FnMut(Event),
) -> Result<Results, String> {
    let work = work_list(scenes, methods, cfg)?;
    let shard_info = (!shard.is_whole()).then_some(shard);
    run_items(
        gpu,
        scenes,
        &work[shard.range(work.len())],
        cfg,
        shard_info,
        on_event,
    )
}

/// Runs an explicit work list (e.g. a paper's table: chosen parameter sets per method),
/// recording `shard` in the run info. `cfg.sweep` and `cfg.overrides` are not consulted:
/// the items carry their full parameter sets.
pub fn run_items(
    gpu: &Gpu,
    scenes: &[Scene],
    work: &[WorkItem],
    cfg: &RunConfig,
    shard_info: Option<Shard>,
    on_event: &mut dyn FnMut(Event),
) -> Result<Results, String> {
    if let Some(item) = work.iter().find(|i| i.scene >= scenes.len()) {
        return Err(format!(
            "work item {} refers to scene {} of {}",
            item.entry.id(),
            item.scene,
            scenes.len()
        ));
    }
    std::fs::create_dir_all(&cfg.out_dir).map_err(|e| {
        format!(
            "{}: cannot create the output directory: {e}",
            cfg.out_dir.display()
        )
    })?;
    let results_path = cfg.out_dir.join("results.json");
    let mut results = if cfg.resume && results_path.exists() {
        let r = Results::load(&results_path)?;
        if r.run.shard != shard_info {
            let show =
                |s: Option<Shard>| s.map_or("the whole run".to_string(), |s| format!("shard {s}"));
            return Err(format!(
                "--resume: {} holds {}, not {}",
                results_path.display(),
                show(r.run.shard),
                show(shard_info)
            ));
        }
        r
    } else {
        Results {
            schema_version: SCHEMA_VERSION,
            run: RunInfo {
                id: cfg.run_id.clone(),
                git_commit: git_commit(),
                resolution: [cfg.width, cfg.height],
                frames: cfg.frames,
                warmup: cfg.warmup,
                machine: Machine::detect(&gpu.summary),
                scored_frame: 0,
                note: if gpu.summary.software {
                    "software adapter: timings compare only as ratios within this run".into()
                } else {
                    "timings compare as ratios within one run and machine".into()
                },
                kind: None,
                shard: shard_info,
                headline: Some(crate::verdict::HEADLINE_NAME.into()),
                methods: Default::default(),
            },
            records: Vec::new(),
        }
    };
    crate::run_methods::describe(&mut results.run.methods, work.iter().map(|i| i.entry));
    if cfg.isolation.retry_failed && !cfg.resume {
        return Err(
            "--retry-failed runs the failed records of an earlier run: it needs --resume".into(),
        );
    }
    let resume =
        crate::isolate::marker::resume(&mut results, &cfg.out_dir, cfg.isolation.retry_failed)?;
    let (done, mut retry) = (resume.done, resume.retry);
    results.save(&results_path)?;
    let mut dispatch = crate::isolate::Dispatch::new(gpu, cfg);
    // The reference of the scene being worked on (the list is grouped by scene).
    let mut reference: Option<(usize, ReferenceImages, ToneMap)> = None;
    for item in work {
        let (scene, entry, params) = (&scenes[item.scene], item.entry, &item.params);
        let key = record_key(&scene.name, entry.id(), params);
        if done.contains(&key) {
            on_event(Event::Resumed(&key));
            continue;
        }
        let support = entry.support(&scene.features(), gpu.features());
        let record = match support {
            Support::No(why) => {
                Record::unmeasured(&scene.name, entry.id(), params, Status::Skipped, why)
            }
            support => {
                if reference.as_ref().is_none_or(|r| r.0 != item.scene) {
                    let start = Instant::now();
                    let (r, cached) = reference::cache::render_cached(
                        cfg.cache_dir.as_deref(),
                        scene,
                        0,
                        cfg.width,
                        cfg.height,
                        cfg.reference,
                        &|_| {},
                    )?;
                    on_event(Event::Reference {
                        scene: &scene.name,
                        cached,
                        seconds: start.elapsed().as_secs_f64(),
                    });
                    let tone = ToneMap::auto(&r.total);
                    write_aovs(
                        &cfg.out_dir,
                        &format!("{}/reference", scene.name),
                        &r.inscatter,
                        &r.surface,
                        &r.total,
                        &tone,
                    )?;
                    reference = Some((item.scene, r, tone));
                }
                let (_, r, tone) = reference.as_ref().expect("set above");
                let ignored = if let Support::Partial(v) = support {
                    v
                } else {
                    Vec::new()
                };
                let mut rec = dispatch.run(item.scene, scene, entry, params, r, tone)?;
                rec.ignored = ignored;
                rec
            }
        };
        on_event(Event::Record(&record));
        match retry.remove(&key) {
            Some(i) => results.records[i] = record,
            None => results.records.push(record),
        }
        results.save(&results_path)?;
        crate::isolate::marker::clear(&cfg.out_dir)?;
    }
    Ok(results)
}

/// A filesystem-safe slug of a parameter set: `steps-128_jitter-false`.
pub fn params_slug(params: &Params) -> String {
    let s: Vec<String> = params.iter().map(|(k, v)| format!("{k}-{v}")).collect();
    let s = s.join("_");
    let s: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "default".into() } else { s }
}

/// A failed record with nothing measured.
pub(crate) fn failed(scene: &Scene, method: &str, params: &Params, why: String) -> Record {
    Record::unmeasured(&scene.name, method, params, Status::Failed, why)
}
