//! `scatterbench scaling`: how each method's frame time grows with the work (issue 10).
//!
//! Two sweeps over variants of one scene (default `sphere-point`), every method at its
//! default parameters, written as one ordinary results run (`results.json`, images, report)
//! plus `scaling.json` saying which variant sits where on which axis:
//!
//! - **triangles**: the casters (every non-plane object) re-tessellated to ~1k … ~1M
//!   triangles at a fixed resolution. Sphere casters start from a 32×16 UV sphere (960
//!   triangles) so that midpoint subdivision (`scenes::mesh::subdivide`, which keeps the
//!   surface where it is) lands on 960 · 4^k ≈ 1k, 4k, …, 1M; other casters are subdivided
//!   from their own mesh to at least the target.
//! - **pixels**: the library scene itself at 128² … 1024², in increasing order; a method whose
//!   frame time extrapolated ∝ pixels would exceed `--max-frame-s` (5 s) is not run at the
//!   bigger sizes, so on a software adapter 1024² is measured for the cheap methods only.
//!
//! The report plots time vs x per method on log–log axes with the fitted slope
//! (`report::scaling`). Scene variants are named `<scene>-tris<N>` and `<scene>-res<N>`.
//! [`resolve_scene`] also understands `<scene>-sub<L>` (every caster subdivided L times from
//! the library mesh), used by `reproduce` for Biri et al.'s triangle-count table.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Result, anyhow, bail};
use clap::Args;
use harness::method::{Params, resolve_params};
use harness::reference::Settings;
use harness::results::{Results, Status};
use harness::runner::{Event, RunConfig, WorkItem, run_items};
use report::scaling::{Spec, Sweep, SweepPoint};
use scenes::Scene;
use scenes::desc::Shape;
use scenes::mesh::subdivide::{subdivide, subdivide_to};

#[derive(Args)]
pub struct ScalingArgs {
    /// Comma-separated method ids, or "all".
    #[arg(long, default_value = "all")]
    pub methods: String,
    /// The library scene the variants are made from.
    #[arg(long, default_value = "sphere-point")]
    pub scene: String,
    /// Caster triangle targets (k = 1000, M = 1000000), comma-separated; "none" skips the sweep.
    #[arg(long, default_value = "1k,4k,16k,64k,256k,1M")]
    pub triangles: String,
    /// Resolution of the triangle sweep (N or WxH).
    #[arg(long, default_value = "128")]
    pub triangles_res: String,
    /// Square resolutions of the pixel sweep, comma-separated; "none" skips the sweep.
    #[arg(long, default_value = "128,256,512,1024")]
    pub res: String,
    /// Pixel sweep: a method is not run at a resolution where its frame time, extrapolated
    /// ∝ pixels from the previous resolution, would exceed this many seconds (0 = no cap),
    /// so the big resolutions are measured for the methods that are cheap enough.
    #[arg(long, default_value_t = 5.0)]
    pub max_frame_s: f64,
    /// Timed frames per record (fewer frames keep the big variants affordable on a software
    /// adapter; the median of 3 is already stable there).
    #[arg(long, default_value_t = 3)]
    pub frames: u32,
    /// Warm-up frames per record.
    #[arg(long, default_value_t = 1)]
    pub warmup: u32,
    /// Output directory (default results/scaling-<run-id>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Reference cache directory.
    #[arg(long, default_value = "results/cache")]
    pub cache: PathBuf,
    #[command(flatten)]
    pub isolate: super::worker::IsolateArgs,
}

/// Parses "1k,4k,1M,2500" into counts.
pub fn parse_counts(s: &str) -> Result<Vec<usize>> {
    if s.trim() == "none" {
        return Ok(Vec::new());
    }
    s.split(',')
        .map(|t| {
            let t = t.trim();
            let (num, mult) = match t.chars().last() {
                Some('k' | 'K') => (&t[..t.len() - 1], 1_000.0),
                Some('m' | 'M') => (&t[..t.len() - 1], 1_000_000.0),
                _ => (t, 1.0),
            };
            let v: f64 = num
                .parse()
                .map_err(|_| anyhow!("'{t}' is not a count (e.g. 4k, 1M, 2500)"))?;
            let n = v * mult;
            if !(1.0..=1e8).contains(&n) {
                bail!("'{t}': counts must be within 1 … 100M");
            }
            Ok(n.round() as usize)
        })
        .collect()
}

/// Whether an object counts as a caster for the sweeps (every shape but the ground plane).
fn is_caster(shape: &Shape) -> bool {
    !matches!(shape, Shape::Plane { .. })
}

/// Triangles of the scene's casters.
pub fn caster_triangles(scene: &Scene) -> usize {
    scene
        .desc
        .objects
        .iter()
        .zip(&scene.meshes)
        .filter(|(o, _)| is_caster(&o.shape))
        .map(|(_, m)| m.triangle_count())
        .sum()
}

/// `scene` with every caster subdivided `levels` times (same surface, 4^levels the triangles).
pub fn subdivided(scene: &Scene, levels: u32) -> Scene {
    let mut s = scene.clone();
    for (o, m) in s.desc.objects.iter().zip(s.meshes.iter_mut()) {
        if is_caster(&o.shape) {
            *m = Arc::new(subdivide(m, levels));
        }
    }
    s.name = format!("{}-sub{levels}", scene.name);
    s
}

/// `scene` with its casters re-tessellated to about `target` triangles in total, each caster
/// getting its share by its current triangle count. Sphere casters are first rebuilt as 32×16
/// UV spheres (960 triangles; the description is changed to match) so that the steps of
/// midpoint subdivision land near round targets; every variant of a sweep then has that
/// same faceted surface.
pub fn with_caster_triangles(scene: &Scene, target: usize) -> Result<Scene> {
    let mut s = scene.clone();
    let base = std::path::Path::new(".");
    for (o, m) in s.desc.objects.iter_mut().zip(s.meshes.iter_mut()) {
        if let Shape::Sphere {
            segments, rings, ..
        } = &mut o.shape
        {
            (*segments, *rings) = (32, 16);
            *m = Arc::new(scenes::load::build_mesh(&o.shape, base).map_err(|e| anyhow!(e))?);
        }
    }
    let total = caster_triangles(&s).max(1);
    for (o, m) in s.desc.objects.iter().zip(s.meshes.iter_mut()) {
        if is_caster(&o.shape) {
            let share = (target as f64 * m.triangle_count() as f64 / total as f64).round();
            // Within 10 % below the target is close enough (960 for "1k"); otherwise refine.
            let (_, fine) = subdivide_to(m, (share * 0.9) as usize);
            *m = Arc::new(fine);
        }
    }
    s.name = format!("{}-tris{}", scene.name, caster_triangles(&s));
    Ok(s)
}

/// A library scene or file, or a variant `<library-scene>-sub<L>` (casters subdivided L times).
pub fn resolve_scene(spec: &str) -> Result<Scene> {
    if let Some((name, levels)) = spec.rsplit_once("-sub")
        && let Ok(levels) = levels.parse::<u32>()
        && scenes::library::names().contains(&name)
    {
        if levels > 8 {
            bail!("{spec}: at most 8 subdivision levels (each quadruples the triangles)");
        }
        let base = scenes::library::resolve(name).map_err(|e| anyhow!(e))?;
        return Ok(subdivided(&base, levels));
    }
    scenes::library::resolve(spec).map_err(|e| anyhow!(e))
}

/// `scene` renamed for the pixel sweep at `n`².
fn at_resolution(scene: &Scene, n: u32) -> Scene {
    let mut s = scene.clone();
    s.name = format!("{}-res{n}", scene.name);
    s
}

pub fn run(a: ScalingArgs) -> Result<()> {
    let chosen = super::run::pick_methods(&a.methods)?;
    let base = scenes::library::resolve(&a.scene).map_err(|e| anyhow!(e))?;
    let targets = parse_counts(&a.triangles)?;
    let (tw, th) = super::parse_res(&a.triangles_res)?;
    let resolutions: Vec<u32> = if a.res.trim() == "none" {
        Vec::new()
    } else {
        a.res
            .split(',')
            .map(|r| {
                let (w, h) = super::parse_res(r)?;
                if w != h {
                    bail!("--res: the pixel sweep takes square sizes (N), not {r}");
                }
                Ok(w)
            })
            .collect::<Result<_>>()?
    };
    if !a.max_frame_s.is_finite() || a.max_frame_s < 0.0 {
        bail!(
            "--max-frame-s: {} is not a number of seconds ≥ 0",
            a.max_frame_s
        );
    }
    if targets.is_empty() && resolutions.is_empty() {
        bail!("nothing to do: --triangles none and --res none");
    }
    if !targets.is_empty() && caster_triangles(&base) == 0 {
        bail!(
            "{}: no caster (non-plane object) to tessellate; pick a scene with one, or --triangles none",
            base.name
        );
    }

    // Triangle variants (distinct counts only) and resolution variants.
    let mut tri_scenes: Vec<Scene> = Vec::new();
    for t in &targets {
        let v = with_caster_triangles(&base, *t)?;
        if !tri_scenes.iter().any(|s| s.name == v.name) {
            tri_scenes.push(v);
        }
    }
    let res_scenes: Vec<(u32, Scene)> = resolutions
        .iter()
        .map(|&n| (n, at_resolution(&base, n)))
        .collect();

    let run_id = harness::results::run_id_now();
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("scaling-{run_id}")));
    if out.join("results.json").exists() {
        bail!(
            "{} already holds a results.json; pass a new --out",
            out.display()
        );
    }
    let gpu = harness::Gpu::new().map_err(|e| anyhow!(e))?;
    eprintln!(
        "adapter: {} ({}); {} methods × ({} triangle variants at {tw}x{th} + {} resolutions), {} frames",
        gpu.summary.adapter,
        gpu.summary.backend,
        chosen.len(),
        tri_scenes.len(),
        res_scenes.len(),
        a.frames
    );
    let defaults: Vec<Params> = chosen
        .iter()
        .map(|e| resolve_params(*e, &Params::new()).map_err(anyhow::Error::from))
        .collect::<Result<_>>()?;
    let mut cfg = RunConfig {
        out_dir: out.clone(),
        width: tw,
        height: th,
        frames: a.frames,
        warmup: a.warmup,
        no_skip: false,
        resume: false,
        sweep: false,
        overrides: BTreeMap::new(),
        reference: Settings::default(),
        cache_dir: Some(a.cache.clone()),
        run_id: format!("scaling-{run_id}"),
        budget_ms: None,
        isolation: a.isolate.isolation()?,
    };
    let mut log = |ev: Event| match ev {
        Event::Reference {
            scene,
            cached,
            seconds,
        } => eprintln!(
            "reference {scene}: {}",
            if cached {
                "cached".to_string()
            } else {
                format!("{seconds:.1} s")
            }
        ),
        Event::Record(r) => {
            let t = r.timing.as_ref().map(|t| t.wall_ms.median);
            eprintln!(
                "  {:<8} {:<24} {:<24} {}",
                format!("{:?}", r.status).to_lowercase(),
                r.scene,
                r.method,
                match (r.status, t) {
                    (Status::Ok, Some(t)) => format!("wall {t:.2} ms"),
                    _ => r.reason.clone().unwrap_or_default(),
                }
            );
        }
        Event::Resumed(_) => {}
    };
    // Each batch appends to the same results.json (resume after the first), since the
    // resolution is per batch.
    let items = |n_scenes: usize| -> Vec<WorkItem> {
        (0..n_scenes)
            .flat_map(|s| {
                chosen.iter().zip(&defaults).map(move |(e, p)| WorkItem {
                    scene: s,
                    entry: *e,
                    params: p.clone(),
                })
            })
            .collect()
    };
    if !tri_scenes.is_empty() {
        run_items(
            &gpu,
            &tri_scenes,
            &items(tri_scenes.len()),
            &cfg,
            None,
            &mut log,
        )
        .map_err(|e| anyhow!(e))?;
        cfg.resume = true;
    }
    // Increasing resolutions, each method's last time predicting its next (∝ pixels).
    let mut order: Vec<usize> = (0..res_scenes.len()).collect();
    order.sort_by_key(|&i| res_scenes[i].0);
    let mut last: BTreeMap<&str, (u32, f64)> = BTreeMap::new();
    let mut capped: Vec<String> = Vec::new();
    for i in order {
        let (n, scene) = &res_scenes[i];
        (cfg.width, cfg.height) = (*n, *n);
        let work: Vec<WorkItem> = items(1)
            .into_iter()
            .filter(|w| {
                let Some(&(m, ms)) = last.get(w.entry.id()) else {
                    return true;
                };
                let predicted_s = ms * (*n as f64 / m as f64).powi(2) / 1e3;
                let keep = a.max_frame_s <= 0.0 || predicted_s <= a.max_frame_s;
                if !keep {
                    capped.push(format!(
                        "{} at {n}² (~{predicted_s:.0} s/frame)",
                        w.entry.id()
                    ));
                }
                keep
            })
            .collect();
        let r = run_items(
            &gpu,
            std::slice::from_ref(scene),
            &work,
            &cfg,
            None,
            &mut log,
        )
        .map_err(|e| anyhow!(e))?;
        cfg.resume = true;
        for rec in r.records.iter().filter(|r| r.scene == scene.name) {
            if let (Status::Ok, Some(t)) = (rec.status, &rec.timing) {
                let e = chosen
                    .iter()
                    .find(|e| e.id() == rec.method)
                    .expect("chosen");
                last.insert(e.id(), (*n, t.wall_ms.median));
            }
        }
    }
    if !capped.is_empty() {
        eprintln!(
            "not run (over --max-frame-s {}): {}",
            a.max_frame_s,
            capped.join(", ")
        );
    }

    // Mark the run (its resolution varies per variant) and write the sweep description.
    let results_path = out.join("results.json");
    let mut results = Results::load(&results_path).map_err(|e| anyhow!(e))?;
    results.run.kind = Some("scaling".into());
    results.run.note = format!(
        "{}; scaling run: the triangle variants are at {tw}x{th}, the resolution variants at their own size (see scaling.json)",
        results.run.note
    );
    results.save(&results_path).map_err(|e| anyhow!(e))?;
    let base_tris = caster_triangles(&base);
    let mut sweeps = Vec::new();
    if !tri_scenes.is_empty() {
        sweeps.push(Sweep {
            axis: "triangles".into(),
            label: "caster triangles".into(),
            note: format!(
                "{} with its casters tessellated by midpoint subdivision (spheres from a 32×16 UV sphere), at {tw}×{th}, default parameters, {} timed frames",
                base.name, a.frames
            ),
            points: tri_scenes
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
    if !res_scenes.is_empty() {
        sweeps.push(Sweep {
            axis: "pixels".into(),
            label: "pixels".into(),
            note: format!(
                "{} as in the library ({base_tris} caster triangles) at {} px², default parameters, {} timed frames{}",
                base.name,
                resolutions
                    .iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                a.frames,
                if capped.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; not run, predicted over {} s a frame: {}",
                        a.max_frame_s,
                        capped.join(", ")
                    )
                }
            ),
            points: res_scenes
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
    let spec = Spec {
        base_scene: base.name.clone(),
        sweeps,
    };
    spec.save(&out)?;
    print!("{}", summary_text(&spec, &results));
    println!("written: {}", results_path.display());
    match report::generate(&out) {
        Ok(index) => println!("report: {}", index.display()),
        Err(e) => eprintln!("warning: the report was not written: {e:#}"),
    }
    Ok(())
}

/// Per sweep: method × x times and the fitted slope, as markdown.
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
                .map(|v| match v {
                    Ok(ms) => format!("{ms:.2}"),
                    Err(_) => "-".into(),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_parse_with_suffixes_and_refuse_junk() {
        assert_eq!(
            parse_counts("1k, 4K,2500,1M").unwrap(),
            vec![1000, 4000, 2500, 1_000_000]
        );
        assert_eq!(parse_counts("1.5k").unwrap(), vec![1500]);
        assert!(parse_counts("none").unwrap().is_empty());
        assert!(parse_counts("abc").is_err());
        assert!(parse_counts("0").is_err());
        assert!(parse_counts("").is_err());
    }

    /// The variants hit the targets the default sweep promises (960 · 4^k), keep every
    /// non-caster mesh untouched, and keep the casters' surface: subdivision adds vertices on
    /// the 32×16 sphere's facets, so the bounding box and the area are those of level 0.
    #[test]
    fn triangle_variants_land_on_the_targets_and_keep_the_surface() {
        let base = scenes::library::resolve("sphere-point").unwrap();
        let area = |m: &scenes::TriMesh| -> f64 {
            m.indices
                .iter()
                .map(|&[a, b, c]| {
                    let (pa, pb, pc) = (
                        m.positions[a as usize].as_dvec3(),
                        m.positions[b as usize].as_dvec3(),
                        m.positions[c as usize].as_dvec3(),
                    );
                    (pb - pa).cross(pc - pa).length() * 0.5
                })
                .sum()
        };
        let sphere = |s: &Scene| {
            s.desc
                .objects
                .iter()
                .position(|o| matches!(o.shape, Shape::Sphere { .. }))
                .unwrap()
        };
        let mut level0_area = None;
        for (target, expect) in [
            (1000, 960),
            (4000, 3840),
            (64_000, 61_440),
            (1_000_000, 983_040),
        ] {
            let v = with_caster_triangles(&base, target).unwrap();
            assert_eq!(caster_triangles(&v), expect, "target {target}");
            assert_eq!(v.name, format!("sphere-point-tris{expect}"));
            // The floor is the library's.
            for (i, o) in v.desc.objects.iter().enumerate() {
                if !is_caster(&o.shape) {
                    assert_eq!(v.meshes[i], base.meshes[i]);
                }
            }
            let a = area(&v.meshes[sphere(&v)]);
            let a0 = *level0_area.get_or_insert(a);
            assert!((a / a0 - 1.0).abs() < 1e-5, "area {a} vs {a0}");
        }
        // The faceted 32×16 sphere's area is below the true sphere's 4πr² (r = 0.9), close.
        let exact = 4.0 * std::f64::consts::PI * 0.81;
        let a0 = level0_area.unwrap();
        assert!(a0 < exact && a0 > 0.97 * exact, "{a0} vs {exact}");
    }

    #[test]
    fn sub_variants_resolve_and_bad_specs_are_refused() {
        let base = scenes::library::resolve("spring-point").unwrap();
        let v = resolve_scene("spring-point-sub2").unwrap();
        assert_eq!(v.name, "spring-point-sub2");
        assert_eq!(caster_triangles(&v), 16 * caster_triangles(&base));
        assert_eq!(
            v.triangle_count() - caster_triangles(&v),
            2,
            "the floor stays 2 triangles"
        );
        assert_eq!(resolve_scene("spring-point").unwrap().name, "spring-point");
        assert!(resolve_scene("spring-point-sub9").is_err());
        assert!(resolve_scene("nowhere-sub2").is_err());
    }
}
