//! `scatterbench scaling` (ARCHITECTURE §9.5): how each method's frame time grows with the
//! work (issue 10).
//!
//! Two sweeps over variants of one scene (default `sphere-point`), every method at its
//! default parameters, written as one ordinary results run (`results.json`, images, report)
//! plus `scaling.json` saying which variant sits where on which axis:
//!
//! - **triangles**: the casters re-tessellated to ~1k … ~1M triangles at a fixed resolution
//!   (`scenes::variants::with_caster_triangles`, named `<scene>-tris<N>`).
//! - **pixels**: the library scene itself at 128² … 1024², in increasing order
//!   (`<scene>-res<N>`); a method whose frame time extrapolated ∝ pixels would exceed
//!   [`Options::max_frame_s`] is not run at the bigger sizes, so on a software adapter 1024²
//!   is measured for the cheap methods only.
//! - **lights**: a second scene, the atrium by default, with 1, 4, 16, 64 local lights
//!   (torches on its columns, its sun kept: `scenes::variants::with_torches`, named
//!   `<scene>-lights<N>`) at a fixed resolution: the cost of per-light passes on a level.
//!
//! The report plots time vs x per method on log–log axes with the fitted slope, the error at
//! each point, and every method's slopes side by side (`report::scaling`).

use std::collections::BTreeMap;

use anyhow::{Result, anyhow};
use harness::Gpu;
use harness::method::{Method, Params, resolve_params};
use harness::record::RecordSettings;
use harness::results::{Results, Status};
use harness::runner::{Event, RunConfig, WorkItem, run_items};
use report::scaling::{Spec, Sweep, SweepPoint};
use scenes::Scene;
use scenes::mesh::atrium::layout::MAX_TORCHES;
use scenes::variants::{at_resolution, caster_triangles, with_caster_triangles, with_torches};

/// What to sweep and how to measure it.
pub struct Options {
    pub methods: Vec<&'static dyn Method>,
    /// The scene the variants are made from.
    pub base: Scene,
    /// Caster triangle targets (empty: no triangle sweep).
    pub triangles: Vec<usize>,
    /// Square sizes of the pixel sweep (empty: no pixel sweep).
    pub resolutions: Vec<u32>,
    /// Local-light counts of the light sweep (empty: no light sweep).
    pub lights: Vec<usize>,
    /// The scene of the light sweep (one with atrium stonework) and its resolution.
    pub lights_scene: Option<Scene>,
    pub lights_res: (u32, u32),
    /// Pixel sweep: a method is not run at a size where its frame time, extrapolated
    /// ∝ pixels from the previous size, would exceed this many seconds (0 = no cap).
    pub max_frame_s: f64,
    /// Frames per record, the run directory (which must not hold a results.json yet) and the
    /// reference cache; its resolution is the triangle sweep's (the pixel sweep sets its own).
    /// No time budget (ARCHITECTURE §4.2).
    pub record: RecordSettings,
    pub run_id: String,
    /// Worker processes and the watchdog for every record (ARCHITECTURE §6).
    pub isolation: harness::isolate::Isolation,
}

impl Options {
    /// Why these options cannot run (an argument problem), if they cannot.
    pub fn check(&self) -> Result<(), String> {
        if self.triangles.is_empty() && self.resolutions.is_empty() && self.lights.is_empty() {
            return Err("nothing to do: --triangles none, --res none and --lights none".into());
        }
        if !self.triangles.is_empty() && caster_triangles(&self.base) == 0 {
            return Err(format!(
                "--scene {}: no caster (non-plane object) to tessellate; pick a scene with one, or --triangles none",
                self.base.name
            ));
        }
        if let Some(bad) = self.lights.iter().find(|n| !(1..=MAX_TORCHES).contains(*n)) {
            return Err(format!(
                "--lights: {bad} is outside 1..={MAX_TORCHES} (the atrium has one torch sconce per column and storey)"
            ));
        }
        let out = &self.record.out_dir;
        if out.join("results.json").exists() {
            return Err(format!(
                "--out: {} already holds a results.json; pass a new directory",
                out.display()
            ));
        }
        Ok(())
    }
}

/// The scene variants of both sweeps.
pub struct Plan {
    /// Triangle variants, distinct counts only.
    pub triangles: Vec<Scene>,
    /// (size, variant) of the pixel sweep.
    pub pixels: Vec<(u32, Scene)>,
    /// (local lights, variant) of the light sweep.
    pub lights: Vec<(usize, Scene)>,
}

pub fn plan(opts: &Options) -> Result<Plan> {
    let mut triangles: Vec<Scene> = Vec::new();
    for t in &opts.triangles {
        let v = with_caster_triangles(&opts.base, *t).map_err(|e| anyhow!(e))?;
        if !triangles.iter().any(|s| s.name == v.name) {
            triangles.push(v);
        }
    }
    let pixels = opts
        .resolutions
        .iter()
        .map(|&n| (n, at_resolution(&opts.base, n)))
        .collect();
    let lights = match (&opts.lights_scene, opts.lights.is_empty()) {
        (_, true) => Vec::new(),
        (None, false) => return Err(anyhow!("a light sweep needs a scene")),
        (Some(scene), false) => opts
            .lights
            .iter()
            .map(|&n| Ok((n, with_torches(scene, n).map_err(|e| anyhow!(e))?)))
            .collect::<Result<_>>()?,
    };
    Ok(Plan {
        triangles,
        pixels,
        lights,
    })
}

/// What a scaling run wrote.
pub struct Outcome {
    pub spec: Spec,
    pub results: Results,
    /// "method at N² (~S s/frame)" of the pairs left out by `max_frame_s`.
    pub capped: Vec<String>,
}

/// Runs both sweeps into `opts.record.out_dir`: results.json (kind "scaling") and scaling.json.
pub fn run(
    gpu: &Gpu,
    plan: &Plan,
    opts: &Options,
    on_event: &mut dyn FnMut(Event),
) -> Result<Outcome> {
    let defaults: Vec<Params> = opts
        .methods
        .iter()
        .map(|e| resolve_params(*e, &Params::new()).map_err(anyhow::Error::from))
        .collect::<Result<_>>()?;
    let (tw, th) = (opts.record.width, opts.record.height);
    let mut cfg = crate::run_config(&opts.record, &opts.run_id, &opts.isolation);
    // Each batch appends to the same results.json (resume after the first), since the
    // resolution is per batch.
    let items = |n_scenes: usize| -> Vec<WorkItem> {
        (0..n_scenes)
            .flat_map(|s| {
                opts.methods
                    .iter()
                    .zip(&defaults)
                    .map(move |(e, p)| WorkItem {
                        scene: s,
                        entry: *e,
                        params: p.clone(),
                    })
            })
            .collect()
    };
    if !plan.triangles.is_empty() {
        let work = items(plan.triangles.len());
        run_items(gpu, &plan.triangles, &work, &cfg, None, on_event).map_err(|e| anyhow!(e))?;
        cfg.resume = true;
    }
    if !plan.lights.is_empty() {
        let scenes: Vec<Scene> = plan.lights.iter().map(|(_, s)| s.clone()).collect();
        (cfg.record.width, cfg.record.height) = opts.lights_res;
        run_items(gpu, &scenes, &items(scenes.len()), &cfg, None, on_event)
            .map_err(|e| anyhow!(e))?;
        (cfg.record.width, cfg.record.height) = (tw, th);
        cfg.resume = true;
    }
    let capped = pixel_sweep(gpu, plan, opts, &mut cfg, &items(1), on_event)?;
    let results_path = opts.record.out_dir.join("results.json");
    let mut results = Results::load(&results_path).map_err(|e| anyhow!(e))?;
    results.run.kind = Some("scaling".into());
    results.run.note = format!(
        "{}; scaling run: the triangle variants are at {tw}x{th}, the light variants at {}x{}, the resolution variants at their own size (see scaling.json)",
        results.run.note, opts.lights_res.0, opts.lights_res.1
    );
    results.save(&results_path).map_err(|e| anyhow!(e))?;
    let spec = spec(plan, opts, &capped);
    spec.save(&opts.record.out_dir)?;
    Ok(Outcome {
        spec,
        results,
        capped,
    })
}

/// The pixel sweep in increasing sizes, each method's last time predicting its next
/// (∝ pixels); returns the pairs left out by `max_frame_s`.
fn pixel_sweep(
    gpu: &Gpu,
    plan: &Plan,
    opts: &Options,
    cfg: &mut RunConfig,
    per_scene: &[WorkItem],
    on_event: &mut dyn FnMut(Event),
) -> Result<Vec<String>> {
    let mut order: Vec<usize> = (0..plan.pixels.len()).collect();
    order.sort_by_key(|&i| plan.pixels[i].0);
    let mut last: BTreeMap<&str, (u32, f64)> = BTreeMap::new();
    let mut capped: Vec<String> = Vec::new();
    for i in order {
        let (n, scene) = &plan.pixels[i];
        (cfg.record.width, cfg.record.height) = (*n, *n);
        let work: Vec<WorkItem> = per_scene
            .iter()
            .filter(|w| {
                let Some(&(m, ms)) = last.get(w.entry.id()) else {
                    return true;
                };
                let predicted_s = ms * (*n as f64 / m as f64).powi(2) / 1e3;
                let keep = opts.max_frame_s <= 0.0 || predicted_s <= opts.max_frame_s;
                if !keep {
                    capped.push(format!(
                        "{} at {n}² (~{predicted_s:.0} s/frame)",
                        w.entry.id()
                    ));
                }
                keep
            })
            .map(|w| WorkItem {
                scene: 0,
                entry: w.entry,
                params: w.params.clone(),
            })
            .collect();
        let r = run_items(gpu, std::slice::from_ref(scene), &work, cfg, None, on_event)
            .map_err(|e| anyhow!(e))?;
        cfg.resume = true;
        for rec in r.records.iter().filter(|r| r.scene == scene.name) {
            if let (Status::Ok, Some(t)) = (rec.status, &rec.timing) {
                let e = opts
                    .methods
                    .iter()
                    .find(|e| e.id() == rec.method)
                    .expect("chosen");
                last.insert(e.id(), (*n, t.wall_ms.median));
            }
        }
    }
    Ok(capped)
}

/// The sweep description written to `scaling.json`.
fn spec(plan: &Plan, opts: &Options, capped: &[String]) -> Spec {
    let (tw, th) = (opts.record.width, opts.record.height);
    let base = &opts.base;
    let base_tris = caster_triangles(base);
    let mut sweeps = Vec::new();
    if !plan.triangles.is_empty() {
        sweeps.push(Sweep {
            axis: "triangles".into(),
            label: "caster triangles".into(),
            scene: None,
            note: format!(
                "{} with its casters tessellated by midpoint subdivision (spheres from a 32×16 UV sphere), at {tw}×{th}, default parameters, {} timed frames",
                base.name, opts.record.frames
            ),
            points: plan
                .triangles
                .iter()
                .map(|s| SweepPoint {
                    scene: s.name.clone(),
                    x: caster_triangles(s) as f64,
                    width: tw,
                    height: th,
                    triangles: caster_triangles(s),
                })
                .collect(),
        });
    }
    if !plan.pixels.is_empty() {
        sweeps.push(Sweep {
            axis: "pixels".into(),
            label: "pixels".into(),
            scene: None,
            note: format!(
                "{} as in the library ({base_tris} caster triangles) at {} px², default parameters, {} timed frames{}",
                base.name,
                opts.resolutions
                    .iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                opts.record.frames,
                if capped.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; not run, predicted over {} s a frame: {}",
                        opts.max_frame_s,
                        capped.join(", ")
                    )
                }
            ),
            points: plan
                .pixels
                .iter()
                .map(|(n, s)| SweepPoint {
                    scene: s.name.clone(),
                    x: (*n as f64) * (*n as f64),
                    width: *n,
                    height: *n,
                    triangles: base_tris,
                })
                .collect(),
        });
    }
    if let (Some(scene), false) = (&opts.lights_scene, plan.lights.is_empty()) {
        sweeps.push(light_sweep(plan, opts, scene));
    }
    Spec {
        base_scene: base.name.clone(),
        sweeps,
    }
}

/// The light sweep's description: x = local lights.
fn light_sweep(plan: &Plan, opts: &Options, scene: &Scene) -> Sweep {
    let (w, h) = opts.lights_res;
    let kept = scene
        .desc
        .lights
        .iter()
        .filter(|l| matches!(l, scenes::desc::LightDesc::Directional { .. }))
        .count();
    Sweep {
        axis: "lights".into(),
        label: "local lights".into(),
        scene: Some(scene.name.clone()),
        note: format!(
            "{} ({} triangles) with N point lights on its columns (its {kept} directional light(s) kept, its spots removed), at {w}×{h}, default parameters, {} timed frames",
            scene.name,
            scene.triangle_count(),
            opts.record.frames
        ),
        points: plan
            .lights
            .iter()
            .map(|(n, s)| SweepPoint {
                scene: s.name.clone(),
                x: *n as f64,
                width: w,
                height: h,
                triangles: caster_triangles(s),
            })
            .collect(),
    }
}

/// Per sweep: method × x times (with the verdict error) and the fitted slope, as markdown.
pub fn summary_text(spec: &Spec, results: &Results) -> String {
    use std::fmt::Write as _;
    let mut t = String::new();
    for sweep in &spec.sweeps {
        let (basis, curves) = report::scaling::curves(results, sweep);
        let _ = writeln!(
            t,
            "\n## frame time vs {} ({})\n",
            sweep.label,
            basis.label()
        );
        let xs: Vec<String> = sweep
            .points
            .iter()
            .map(|p| report::scaling::count_text(p.x))
            .collect();
        let _ = writeln!(t, "| method | {} | slope | r² |", xs.join(" | "));
        let _ = writeln!(t, "|---|{}---|---|", "---|".repeat(xs.len()));
        for c in &curves {
            let cells: Vec<String> = c
                .cells
                .iter()
                .zip(&c.errors)
                .map(|(v, e)| match (v, e) {
                    (Ok(ms), Some(e)) => format!("{ms:.2} ({:.3} %)", 100.0 * e),
                    (Ok(ms), None) => format!("{ms:.2}"),
                    (Err(_), _) => "-".into(),
                })
                .collect();
            let _ = writeln!(
                t,
                "| {} | {} | {} | {} |",
                c.method,
                cells.join(" | "),
                c.fit.map_or("-".into(), |f| format!("{:.2}", f.slope)),
                c.fit.map_or("-".into(), |f| format!("{:.3}", f.r2))
            );
        }
    }
    t
}
