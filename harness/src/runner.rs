//! The runner: scenes × methods × parameter sets → records, written to `results.json`
//! atomically after every record. A method that panics, raises a wgpu error or renders
//! non-finite pixels is recorded as failed and the run goes on.
//!
//! Protocol (DESIGN §4): per record, `prepare` is timed once; then W warm-up and K timed
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

/// Fewest timed frames a record gets under a time budget (a median needs a few samples).
pub const MIN_TIMED_FRAMES: u32 = 3;

/// Under a time budget B: warm-up stops after its first frame once warm-up has used B/4,
/// and timing stops once [`MIN_TIMED_FRAMES`] frames are timed and the timed frames have used
/// B. Fast methods still get the full W + K frames; a 9 s/frame method gets 1 + 3 instead of
/// 3 + 10. Returns whether to render another frame of the phase.
pub fn another_frame(budget_ms: Option<f64>, warmup: bool, done: u32, used_ms: f64) -> bool {
    match budget_ms {
        None => true,
        Some(b) if warmup => done < 1 || used_ms < 0.25 * b,
        Some(b) => done < MIN_TIMED_FRAMES || used_ms < b,
    }
}

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
            },
            records: Vec::new(),
        }
    };
    if cfg.isolation.retry_failed && !cfg.resume {
        return Err("--retry-failed runs the failed records of an earlier run: it needs --resume".into());
    }
    let resume = crate::isolate::marker::resume(&mut results, &cfg.out_dir, cfg.isolation.retry_failed)?;
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
            Support::No(why) => skipped(scene, entry.id(), params, why),
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

fn skipped(scene: &Scene, method: &str, params: &Params, why: String) -> Record {
    Record {
        scene: scene.name.clone(),
        method: method.to_string(),
        params: params.clone(),
        status: Status::Skipped,
        reason: Some(why),
        ignored: Vec::new(),
        timing: None,
        memory_bytes: None,
        passes: None,
        counters: Default::default(),
        errors: Default::default(),
        images: Default::default(),
        errors_per_frame: None,
    }
}

fn failed(scene: &Scene, method: &str, params: &Params, why: String) -> Record {
    Record {
        status: Status::Failed,
        ..skipped(scene, method, params, why)
    }
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

pub(crate) fn run_one(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    cfg: &RunConfig,
    reference: &ReferenceImages,
    tone: &ToneMap,
) -> Record {
    let _ = gpu.take_errors();
    let mut scorer = match FrameScorer::new(
        scene,
        tone,
        reference,
        cfg.reference,
        cfg.cache_dir.as_deref(),
    ) {
        Ok(s) => s,
        Err(e) => return failed(scene, entry.id(), params, format!("per-frame references: {e}")),
    };
    let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
        measure(gpu, scene, entry, params, cfg, &mut scorer)
    }));
    let errors = gpu.take_errors();
    crate::isolate::phase::enter(crate::isolate::Phase::Score);
    let (mut rec, images) = match outcome {
        Err(panic) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            return failed(scene, entry.id(), params, format!("panicked: {msg}"));
        }
        Ok(Err(e)) => {
            return failed(
                scene,
                entry.id(),
                params,
                if errors.is_empty() {
                    e
                } else {
                    format!("{e}; wgpu: {}", errors.join("; "))
                },
            );
        }
        Ok(Ok(_)) if !errors.is_empty() => {
            return failed(
                scene,
                entry.id(),
                params,
                format!("wgpu error: {}", errors.join("; ")),
            );
        }
        Ok(Ok(v)) => v,
    };
    let [inscatter, surface, total] = &images;
    let dir = format!("{}/{}/{}", scene.name, entry.id(), params_slug(params));
    // Scoring and writing images are independent CPU work while the GPU idles: spread them over
    // the cores (FLIP at 512² is most of a record's overhead on a 2-core machine).
    let score_start = Instant::now();
    // The light core of the scored frame (frame 0), judged beside the headline.
    let core = light_core_mask(&scene.frame(0), cfg.width, cfg.height, &reference.distance);
    let scored = [
        ("inscatter", inscatter, &reference.inscatter),
        ("total", total, &reference.total),
        ("surface", surface, &reference.surface),
    ];
    let mapped = [
        ("inscatter", inscatter, &reference.inscatter),
        ("total", total, &reference.total),
    ];
    let (scores, (written, maps)) = rayon::join(
        || {
            scored
                .par_iter()
                .map(|(name, img, refimg)| {
                    let m = compare(img, refimg, tone).map(|mut m| {
                        m.light_core = core
                            .as_ref()
                            .and_then(|c| masked_relative(&finite(img), refimg, c));
                        m
                    });
                    (*name, m)
                })
                .collect::<Vec<_>>()
        },
        || {
            let written = write_aovs(&cfg.out_dir, &dir, inscatter, surface, total, tone);
            // Error maps: |method − reference| on a shared scale per AOV (the reference's
            // 99th percentile / 10); after write_aovs, which creates the directory.
            let maps = mapped
                .par_iter()
                .map(|(name, img, refimg)| {
                    let scale = error_scale(refimg);
                    let path = format!("{dir}/{name}.error.png");
                    io::write_png_ldr(&cfg.out_dir.join(&path), &error_map(img, refimg, scale))
                        .map(|()| (*name, path, scale))
                })
                .collect::<Vec<_>>();
            (written, maps)
        },
    );
    let mut nonfinite = 0;
    let score_seconds = scorer.seconds;
    let (per_frame, temporal) = scorer.finish();
    rec.counters.insert(
        "light_core_pixels".into(),
        core.as_ref().map_or(0, |m| m.iter().filter(|&&c| c).count()) as f64,
    );
    for (name, m) in scores {
        match m {
            Ok(mut m) => {
                nonfinite = nonfinite.max(m.nonfinite);
                let k = AOV_NAMES.iter().position(|a| *a == name).expect("an AOV");
                m.temporal = temporal[k];
                rec.errors.insert(name.to_string(), m);
            }
            Err(e) => {
                return failed(
                    scene,
                    entry.id(),
                    params,
                    format!("cannot score {name}: {e}"),
                );
            }
        }
    }
    rec.errors_per_frame = per_frame;
    match written {
        Ok(paths) => rec.images = paths,
        Err(e) => return failed(scene, entry.id(), params, e),
    }
    for map in maps {
        match map {
            Ok((name, path, scale)) => {
                rec.images.insert(format!("{name}_error"), path);
                rec.counters
                    .insert(format!("{name}_error_scale"), scale as f64);
            }
            Err(e) => return failed(scene, entry.id(), params, e),
        }
    }
    if let Some(t) = rec.timing.as_mut() {
        t.score_ms = (score_start.elapsed().as_secs_f64() + score_seconds) * 1e3;
    }
    if nonfinite > 0 {
        rec.status = Status::Failed;
        rec.reason = Some(format!("{nonfinite} non-finite pixels in the output"));
    }
    rec
}

/// The error that maps to the top of an error map's colour bar: a tenth of the reference's
/// 99th-percentile luminance, so 10% errors saturate.
pub fn error_scale(reference: &Image) -> f32 {
    let mut l = reference.luminance();
    l.retain(|v| v.is_finite());
    if l.is_empty() {
        return 1.0;
    }
    l.sort_by(f32::total_cmp);
    let p99 = l[((l.len() as f64 * 0.99) as usize).min(l.len() - 1)];
    (0.1 * p99).max(1e-12)
}

fn write_aovs(
    out: &Path,
    rel_dir: &str,
    inscatter: &Image,
    surface: &Image,
    total: &Image,
    tone: &ToneMap,
) -> Result<std::collections::BTreeMap<String, String>, String> {
    let mut paths = std::collections::BTreeMap::new();
    for (name, img) in [
        ("inscatter", inscatter),
        ("surface", surface),
        ("total", total),
    ] {
        let exr = format!("{rel_dir}/{name}.exr");
        let png = format!("{rel_dir}/{name}.png");
        std::fs::create_dir_all(out.join(rel_dir))
            .map_err(|e| format!("{}: {e}", out.join(rel_dir).display()))?;
        io::write_exr(&out.join(&exr), img)?;
        io::write_png(&out.join(&png), img, tone)?;
        paths.insert(name.to_string(), exr);
        paths.insert(format!("{name}_png"), png);
    }
    Ok(paths)
}

/// The AOV textures the harness renders into.
pub struct AovTargets {
    pub textures: [wgpu::Texture; 3],
    pub views: [wgpu::TextureView; 3],
    pub width: u32,
    pub height: u32,
}

impl AovTargets {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> AovTargets {
        let make = |label: &str| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: AOV_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let textures = [
            make("aov inscatter"),
            make("aov surface"),
            make("aov total"),
        ];
        let views = [0, 1, 2].map(|i| textures[i].create_view(&Default::default()));
        AovTargets {
            textures,
            views,
            width,
            height,
        }
    }

    pub fn targets(&self) -> Targets<'_> {
        Targets {
            inscatter: &self.views[0],
            surface: &self.views[1],
            total: &self.views[2],
            width: self.width,
            height: self.height,
        }
    }

    /// Clears all three to zero (outside any timed region).
    pub fn clear(&self, gpu: &Gpu) {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for v in &self.views {
            let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("clear aov"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
        }
        gpu.queue.submit([enc.finish()]);
    }

    pub fn read(&self, gpu: &Gpu) -> Result<[Image; 3], String> {
        Ok([
            read_rgba32f(gpu, &self.textures[0])?,
            read_rgba32f(gpu, &self.textures[1])?,
            read_rgba32f(gpu, &self.textures[2])?,
        ])
    }
}

/// One frame: clear, encode (timed as CPU), submit and wait (timed as wall), GPU timestamps.
pub struct FrameTiming {
    pub cpu_ms: f64,
    pub wall_ms: f64,
    pub gpu_ms: Option<f64>,
    pub report: FrameReport,
}

pub fn render_frame(
    gpu: &Gpu,
    method: &mut dyn Prepared,
    scene: &Scene,
    index: u32,
    aovs: &AovTargets,
    timer: Option<&GpuTimer>,
) -> Result<FrameTiming, String> {
    aovs.clear(gpu);
    gpu.wait()?;
    let frame = scene.frame(index % scene.frame_count());
    let start = Instant::now();
    let mut enc = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        });
    if let Some(t) = timer {
        t.begin(&mut enc);
    }
    gpu.stats_begin_frame();
    let cpu_start = Instant::now();
    let report = method
        .render(gpu, &frame, &aovs.targets(), &mut enc)
        .map_err(|e| format!("render failed: {e:#}"))?;
    let cpu_ms = cpu_start.elapsed().as_secs_f64() * 1e3;
    if let Some(t) = timer {
        t.end(&mut enc);
    }
    gpu.stats_resolve(&mut enc);
    gpu.queue.submit([enc.finish()]);
    gpu.wait()?;
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    let gpu_ms = match timer {
        Some(t) => Some(t.read_ms(gpu)?),
        None => None,
    };
    let mut report = report;
    if let Some(phases) = method.phase_timer() {
        for (name, ms) in phases.read_ms(gpu)? {
            report.count(&format!("gpu_ms_{name}"), ms);
        }
    }
    if let Some(work) = gpu.stats_read()? {
        for (name, n) in work.counters() {
            report.count(name, n);
        }
    }
    if gpu.is_lost() {
        return Err(gpu.take_errors().join("; "));
    }
    Ok(FrameTiming {
        cpu_ms,
        wall_ms,
        gpu_ms,
        report,
    })
}

/// Prepares, times and reads back one method × params. Returns the record (without errors
/// and images) and the three AOVs of the scored frame.
fn measure(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    cfg: &RunConfig,
    scorer: &mut FrameScorer,
) -> Result<(Record, [Image; 3]), String> {
    crate::isolate::phase::enter(crate::isolate::Phase::Prepare);
    gpu.reset_allocated();
    let start = Instant::now();
    let mut method = entry
        .prepare(&PrepareContext {
            gpu,
            scene,
            params,
            width: cfg.width,
            height: cfg.height,
            no_skip: cfg.no_skip,
        })
        .map_err(|e| format!("prepare failed: {e:#}"))?;
    gpu.wait()?;
    let prepare_ms = start.elapsed().as_secs_f64() * 1e3;
    let memory = gpu.allocated_bytes();
    let errors = gpu.take_errors();
    if !errors.is_empty() {
        return Err(format!("wgpu error during prepare: {}", errors.join("; ")));
    }
    let aovs = AovTargets::new(gpu, cfg.width, cfg.height);
    let timer = GpuTimer::new(gpu);
    let (mut cpu, mut wall, mut gpu_ms) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = FrameReport::default();
    let mut work: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    crate::isolate::phase::enter(crate::isolate::Phase::Render);
    // Frames cycle through the scene's frames: warm-up first, then the timed ones.
    let (mut f, mut warm_ms, mut timed_ms) = (0u32, 0.0, 0.0);
    while f < cfg.warmup && another_frame(cfg.budget_ms, true, f, warm_ms) {
        warm_ms += render_frame(gpu, method.as_mut(), scene, f, &aovs, timer.as_ref())?.wall_ms;
        f += 1;
    }
    let warmed = f;
    while f - warmed < cfg.frames && another_frame(cfg.budget_ms, false, f - warmed, timed_ms) {
        let t = render_frame(gpu, method.as_mut(), scene, f, &aovs, timer.as_ref())?;
        timed_ms += t.wall_ms;
        cpu.push(t.cpu_ms);
        wall.push(t.wall_ms);
        if let Some(g) = t.gpu_ms {
            gpu_ms.push(g);
        }
        for name in WORK_COUNTERS {
            if let Some(n) = t.report.counters.get(name) {
                work.entry(name).or_default().push(*n);
            }
        }
        last = t.report;
        // Read back and score outside the timed region (the next frame's clock starts after
        // its own clear and wait).
        scorer.timed_frame(f, &aovs.read(gpu)?)?;
        f += 1;
    }
    // Work counts are per frame, median over the timed frames (an animated scene's frames differ).
    for (name, values) in &work {
        last.counters.insert(name.to_string(), Stat::of(values).median);
    }
    if cfg.budget_ms.is_some() {
        last.count("warmup_frames", warmed as f64);
        last.count("timed_frames", (f - warmed) as f64);
    }
    // An accumulating method converges over `converge` frames: on a static scene the scored
    // frame is the converge-th rendered since prepare, or later.
    let converge = entry.converge_frames(params);
    if converge > 0 {
        last.count("converge_frames", converge as f64);
        if scene.frame_count() == 1 {
            while f < converge {
                render_frame(gpu, method.as_mut(), scene, f, &aovs, None)?;
                f += 1;
            }
        }
    }
    // The scored frame: frame 0 once more — unless the last timed frame was frame 0 (always,
    // in a static scene): its output is still in the AOVs, the same inputs rendered by the same
    // method, so rendering it again would only cost a frame.
    let reuse = f > warmed && (f - 1) % scene.frame_count().max(1) == 0;
    let scored = if reuse {
        None
    } else {
        Some(render_frame(gpu, method.as_mut(), scene, 0, &aovs, None)?.report)
    };
    let images = aovs.read(gpu)?;
    let report = if cfg.frames > 0 {
        last
    } else {
        scored.unwrap_or_default()
    };
    let record = Record {
        scene: scene.name.clone(),
        method: entry.id().to_string(),
        params: params.clone(),
        status: Status::Ok,
        reason: None,
        ignored: Vec::new(),
        timing: Some(Timing {
            prepare_ms,
            wall_ms: Stat::of(&wall),
            gpu_ms: (!gpu_ms.is_empty()).then(|| Stat::of(&gpu_ms)),
            cpu_ms: Stat::of(&cpu),
            score_ms: 0.0,
        }),
        memory_bytes: Some(memory),
        passes: Some(Passes {
            run: report.run,
            skipped: report.skipped,
        }),
        counters: report.counters,
        errors: Default::default(),
        images: Default::default(),
        errors_per_frame: None,
    };
    Ok((record, images))
}

#[cfg(test)]
mod budget_tests {
    use super::*;

    /// Simulates the frame loop of `measure` for a method taking `frame_ms` a frame.
    fn frames(budget: Option<f64>, warmup: u32, timed: u32, frame_ms: f64) -> (u32, u32) {
        let (mut w, mut used) = (0, 0.0);
        while w < warmup && another_frame(budget, true, w, used) {
            w += 1;
            used += frame_ms;
        }
        let (mut k, mut used) = (0, 0.0);
        while k < timed && another_frame(budget, false, k, used) {
            k += 1;
            used += frame_ms;
        }
        (w, k)
    }

    #[test]
    fn budget_cuts_only_slow_records_and_keeps_the_minimums() {
        // No budget: always W + K.
        assert_eq!(frames(None, 3, 10, 9000.0), (3, 10));
        // Fast methods are untouched by an 8 s budget (10 × 0.5 s = 5 s < 8 s).
        assert_eq!(frames(Some(8000.0), 3, 10, 500.0), (3, 10));
        // 1 s/frame: warm-up stops at 2 s (B/4), timing at 8 s.
        assert_eq!(frames(Some(8000.0), 3, 10, 1000.0), (2, 8));
        // 9 s/frame: one warm-up frame, the minimum of timed frames.
        assert_eq!(frames(Some(8000.0), 3, 10, 9000.0), (1, MIN_TIMED_FRAMES));
        // A budget never asks for more than requested.
        assert_eq!(frames(Some(8000.0), 0, 2, 9000.0), (0, 2));
    }
}
