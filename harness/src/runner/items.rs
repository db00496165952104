//! Running a work list: the results file opened (or resumed), each scene's reference rendered
//! (through the cache) and written once, each item dispatched (in process or to a worker),
//! and results.json saved after every record.

use std::time::Instant;

use scenes::Scene;

use super::config::{Event, RunConfig};
use crate::gpu::Gpu;
use crate::image::metrics::ToneMap;
use crate::isolate::{Dispatch, marker};
use crate::method::{Method, Params, Support};
use crate::record::{RecordSettings, write_aovs};
use crate::reference::{self, ReferenceImages};
use crate::results::{
    Machine, Record, Results, RunInfo, SCHEMA_VERSION, Status, git_commit, record_key,
};
use crate::shard::Shard;
use crate::verdict::HEADLINE_NAME;

/// One item of a run's work list: a scene (index into the caller's list), a method and a
/// full parameter set.
pub struct WorkItem<'a> {
    pub scene: usize,
    pub entry: &'a dyn Method,
    pub params: Params,
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
    let out = &cfg.record.out_dir;
    let results_path = out.join("results.json");
    let mut results = open_results(gpu, cfg, shard_info)?;
    crate::run_methods::describe(&mut results.run.methods, work.iter().map(|i| i.entry));
    if cfg.isolation.retry_failed && !cfg.resume {
        return Err(
            "--retry-failed runs the failed records of an earlier run: it needs --resume".into(),
        );
    }
    let resume = marker::resume(&mut results, out, cfg.isolation.retry_failed)?;
    let (done, mut retry) = (resume.done, resume.retry);
    results.save(&results_path)?;
    let floor = paired_floor(work, &cfg.record)?;
    let mut dispatch = Dispatch::new(gpu, &cfg.record, &cfg.isolation, floor);
    // The reference of the scene being worked on (the list is grouped by scene).
    let mut reference: Option<(usize, ReferenceImages, ToneMap)> = None;
    on_event(Event::Planned(work.len()));
    for item in work {
        let (scene, entry, params) = (&scenes[item.scene], item.entry, &item.params);
        let key = record_key(&scene.name, entry.id(), params);
        if done.contains(&key) {
            on_event(Event::Resumed(&key));
            continue;
        }
        on_event(Event::Starting {
            scene: &scene.name,
            method: entry.id(),
            params,
        });
        let support = entry.support(&scene.features(), gpu.features());
        let record = match support {
            Support::No(why) => {
                Record::unmeasured(&scene.name, entry.id(), params, Status::Skipped, why)
            }
            support => {
                if reference.as_ref().is_none_or(|r| r.0 != item.scene) {
                    let (r, tone) = scene_reference(cfg, scene, on_event)?;
                    reference = Some((item.scene, r, tone));
                }
                let (_, r, tone) = reference.as_ref().expect("set above");
                let mut ignored = if let Support::Partial(v) = support {
                    v
                } else {
                    Vec::new()
                };
                // Imported content the suite does not model applies to every method.
                ignored.extend(scene.ignored.iter().cloned());
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
        marker::clear(out)?;
    }
    Ok(results)
}

/// The method `record.paired_floor` names, found among the work list's methods (the floor
/// must run in the run: its records are the scenes' floor too). Err where it is not there.
fn paired_floor<'a>(
    work: &[WorkItem<'a>],
    record: &RecordSettings,
) -> Result<Option<&'a dyn Method>, String> {
    let Some(id) = record.paired_floor.as_deref() else {
        return Ok(None);
    };
    work.iter()
        .map(|i| i.entry)
        .find(|m| m.id() == id)
        .map(Some)
        .ok_or_else(|| {
            format!(
                "--paired-floor: the floor method '{id}' is not in this run's work list \
                 (add it to --methods, in every shard)"
            )
        })
}

/// The run's results: those in the output directory when resuming (of the same shard), else a
/// fresh run with no records.
fn open_results(gpu: &Gpu, cfg: &RunConfig, shard_info: Option<Shard>) -> Result<Results, String> {
    let out = &cfg.record.out_dir;
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create the output directory: {e}", out.display()))?;
    let results_path = out.join("results.json");
    if !(cfg.resume && results_path.exists()) {
        return Ok(fresh_results(gpu, &cfg.record, &cfg.run_id, shard_info));
    }
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
    Ok(r)
}

/// A run with no records yet: `run_id`, measured as `s` says on `gpu`'s adapter, `shard` (None:
/// the whole run).
pub fn fresh_results(gpu: &Gpu, s: &RecordSettings, run_id: &str, shard: Option<Shard>) -> Results {
    Results {
        schema_version: SCHEMA_VERSION,
        run: RunInfo {
            id: run_id.to_string(),
            git_commit: git_commit(),
            resolution: [s.width, s.height],
            frames: s.frames,
            warmup: s.warmup,
            time_budget_s: s.budget_ms.map(|ms| ms / 1e3),
            machine: Machine {
                calibration: calibration(gpu),
                ..Machine::detect(&gpu.summary)
            },
            scored_frame: 0,
            note: if gpu.summary.software {
                "software adapter: timings compare only as ratios within this run".into()
            } else {
                "timings compare as ratios within one run and machine".into()
            },
            kind: None,
            shard,
            headline: Some(HEADLINE_NAME.into()),
            methods: Default::default(),
        },
        records: Vec::new(),
    }
}

/// The adapter's calibration (ARCHITECTURE §7.1); None, with a warning, where it failed: a
/// run is not refused for want of it.
fn calibration(gpu: &Gpu) -> Option<crate::gpu::Calibration> {
    crate::gpu::calibrate(gpu)
        .map_err(|e| eprintln!("warning: {e}"))
        .ok()
}

/// Frame 0's reference of `scene` (rendered through the cache) and its tone map, its images
/// written under `<scene>/reference/`.
fn scene_reference(
    cfg: &RunConfig,
    scene: &Scene,
    on_event: &mut dyn FnMut(Event),
) -> Result<(ReferenceImages, ToneMap), String> {
    let s = &cfg.record;
    let start = Instant::now();
    let (r, cached) = reference::cache::render_cached(
        s.cache_dir.as_deref(),
        scene,
        0,
        s.width,
        s.height,
        s.reference,
        &|_| {},
    )?;
    on_event(Event::Reference {
        scene: &scene.name,
        cached,
        seconds: start.elapsed().as_secs_f64(),
    });
    let tone = ToneMap::auto(&r.total);
    write_aovs(
        &s.out_dir,
        &format!("{}/reference", scene.name),
        &r.inscatter,
        &r.surface,
        &r.total,
        &tone,
    )?;
    Ok((r, tone))
}
