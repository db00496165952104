//! The per-scene part of the page: results.json turned into display-ready rows and tables
//! that the template only lays out, plus the images the scene's viewer ships. Numbers are
//! formatted in [`crate::format`] so every table uses the same units and precision.

use std::path::Path;

use harness::image::Image;
use harness::image::metrics::ToneMap;
use harness::results::{Record, Results, Status};
use serde::Serialize;

use crate::analysis::{self, BUDGETS, Clock, Point, TimeBasis, ordered};
use crate::format::{PlotLinks, anchor, mib, ms, params_text, rel, status_text};
use crate::matrix::work_text;
use crate::metric::Metric;
use crate::viewer::{self, Shipped};

/// The AOVs the viewer ships (linear radiance), in display order, with their labels. Only the
/// in-scatter, the quantity the suite judges: with the total as well the default 256² run's
/// page doubles to 13 MB and takes over 2 s to open in headless Chromium on the 2-core test
/// machine (measured 1.9–2.7 s vs 1.5–1.9 s); the total and surface stay on disk as PNG/EXR.
pub const VIEWER_AOVS: [(&str, &str); 1] = [("inscatter", "in-scatter")];

#[derive(Serialize, Default)]
pub struct Counts {
    pub total: usize,
    pub ok: usize,
    pub skipped: usize,
    pub failed: usize,
}

#[derive(Serialize)]
pub struct SceneView {
    pub name: String,
    /// HTML id (and file-name stem of the plots).
    pub anchor: String,
    pub time_label: String,
    /// Tone map exposure (stops) recomputed from the reference EXR, when it is there.
    pub exposure: Option<f32>,
    pub viewer: Viewer,
    pub rows: Vec<Row>,
    /// One Pareto plot per metric (page order).
    pub plots: Vec<PlotView>,
    /// Per metric: the cheapest configuration under each budget, overall and per method.
    pub budgets: Vec<MetricBudgets>,
    /// Animated scenes: headline error and frame time over the frames ([`crate::frames`]).
    pub frames: Option<crate::frames::FramesView>,
}

#[derive(Serialize)]
pub struct PlotView {
    pub metric: &'static str,
    pub links: Option<PlotLinks>,
    pub note: String,
}

#[derive(Serialize)]
pub struct MetricBudgets {
    pub metric: &'static str,
    pub overall: Vec<BudgetRow>,
    pub per_method: Vec<MethodBudgetRow>,
}

#[derive(Serialize)]
pub struct MethodBudgetRow {
    pub method: String,
    /// Per budget: "time ms (params, error)", or None when no configuration is within it.
    pub cells: Vec<Option<String>>,
}

/// The images of one scene's viewer.
#[derive(Serialize)]
pub struct Viewer {
    /// Labels of the shipped AOVs (same order as each image's `aovs`).
    pub aovs: Vec<String>,
    /// Reference first (key R), then one per method (keys 1–9 for the first nine).
    pub images: Vec<ViewerImage>,
    /// The in-scatter error-map scale of the scene's PNG error maps, reused by the page.
    pub error_scale: f64,
}

#[derive(Serialize)]
pub struct ViewerImage {
    /// "R" for the reference, "1".."9" for the first nine methods, "" beyond.
    pub key: String,
    pub label: String,
    pub params: String,
    /// One per shipped AOV; None with `missing` naming the file that was not there.
    pub aovs: Vec<Option<Shipped>>,
    pub missing: Vec<String>,
}

#[derive(Serialize)]
pub struct Row {
    pub method: String,
    pub params: String,
    pub status: String,
    pub reason: String,
    pub ignored: String,
    pub frame_ms: String,
    pub gpu_ms: String,
    pub work: String,
    pub memory: String,
    /// Per metric (page order): the record's value.
    pub errors: Vec<String>,
    pub nonfinite: String,
    pub skipped_passes: String,
    /// Per metric: on that metric's Pareto front.
    pub on_front: Vec<bool>,
}

#[derive(Serialize)]
pub struct BudgetRow {
    pub budget: String,
    pub method: Option<String>,
    pub params: String,
    pub time: String,
    pub error: String,
}

fn row(r: &Record, on_front: Vec<bool>, metrics: &[Metric], pixels: f64) -> Row {
    let t = r.timing.as_ref();
    let nonfinite = r.errors.values().map(|m| m.nonfinite).max();
    Row {
        method: r.method.clone(),
        params: params_text(r),
        status: status_text(r.status).into(),
        reason: r.reason.clone().unwrap_or_default(),
        ignored: r.ignored.join(", "),
        frame_ms: t
            .map(|t| format!("{} / {}", ms(t.wall_ms.median), ms(t.wall_ms.p90)))
            .unwrap_or_else(|| "—".into()),
        gpu_ms: match t.map(|t| t.gpu_ms) {
            Some(Some(g)) => format!("{} / {}", ms(g.median), ms(g.p90)),
            Some(None) => "n/a".into(),
            None => "—".into(),
        },
        work: work_text(r, pixels),
        memory: r.memory_bytes.map(mib).unwrap_or_else(|| "—".into()),
        errors: metrics
            .iter()
            .map(|m| m.of(r).map(rel).unwrap_or_else(|| "—".into()))
            .collect(),
        nonfinite: nonfinite
            .map(|n| n.to_string())
            .unwrap_or_else(|| "—".into()),
        skipped_passes: r
            .passes
            .as_ref()
            .map(|p| {
                p.skipped
                    .iter()
                    .map(|s| format!("{} ({})", s.pass, s.why))
                    .collect::<Vec<_>>()
                    .join("; ")
            })
            .unwrap_or_default(),
        on_front,
    }
}

fn basis_name(basis: TimeBasis) -> &'static str {
    if basis == TimeBasis::Gpu {
        "GPU"
    } else {
        "wall"
    }
}

fn budget_rows(records: &[&Record], points: &[Point], basis: TimeBasis) -> Vec<BudgetRow> {
    BUDGETS
        .iter()
        .map(|&b| {
            let budget = format!("≤ {:.0} %", b * 100.0);
            match analysis::cheapest_under_budget(points, b) {
                Some(p) => {
                    let r = records[p.index];
                    BudgetRow {
                        budget,
                        method: Some(r.method.clone()),
                        params: params_text(r),
                        time: format!("{} ms ({})", ms(p.time), basis_name(basis)),
                        error: rel(p.error),
                    }
                }
                None => BudgetRow {
                    budget,
                    method: None,
                    params: String::new(),
                    time: String::new(),
                    error: String::new(),
                },
            }
        })
        .collect()
}

/// Per method (in order of first appearance): its cheapest ok configuration under each
/// budget, so methods compare at equal error rather than at their defaults.
fn method_budget_rows(records: &[&Record], clock: Clock, metric: Metric) -> Vec<MethodBudgetRow> {
    ordered(records.iter().map(|r| r.method.as_str()))
        .into_iter()
        .map(|m| {
            let mine: Vec<&Record> = records.iter().copied().filter(|r| r.method == m).collect();
            let points = analysis::points_by(&mine, clock, metric);
            let cells = BUDGETS
                .iter()
                .map(|&b| {
                    analysis::cheapest_under_budget(&points, b).map(|p| {
                        format!(
                            "{} ms ({}; {})",
                            ms(p.time),
                            params_text(mine[p.index]),
                            rel(p.error)
                        )
                    })
                })
                .collect();
            MethodBudgetRow { method: m, cells }
        })
        .collect()
}

/// A run-relative path inside the run directory (absolute and `..` paths are refused, since
/// the page must not depend on files outside the run).
fn inside(run_dir: &Path, rel: &str) -> Option<std::path::PathBuf> {
    let p = Path::new(rel);
    let escapes = p.is_absolute() || p.components().any(|c| c == std::path::Component::ParentDir);
    (!escapes).then(|| run_dir.join(p))
}

fn read(run_dir: &Path, rel: &str) -> Result<Image, String> {
    let path = inside(run_dir, rel).ok_or_else(|| format!("{rel} (outside the run)"))?;
    harness::image::io::read_exr(&path).map_err(|_| rel.to_string())
}

/// The viewer's images: the reference, then per method the ok record the matrix shows
/// (its lowest verdict error), each with every AOV of [`VIEWER_AOVS`].
fn viewer(run_dir: &Path, records: &[&Record], anchor: &str) -> Viewer {
    let mut images = Vec::new();
    let scene = records.first().map(|r| r.scene.as_str()).unwrap_or("");
    let mut push = |key: String, label: String, params: String, paths: Vec<Option<String>>| {
        let i = images.len();
        let mut missing = Vec::new();
        let aovs = paths
            .iter()
            .enumerate()
            .map(|(a, p)| {
                let Some(p) = p else {
                    missing.push(format!("{} (not recorded)", VIEWER_AOVS[a].0));
                    return None;
                };
                match read(run_dir, p) {
                    Ok(img) => Some(viewer::ship(format!("{anchor}-img{i}-{a}"), &img)),
                    Err(m) => {
                        missing.push(m);
                        None
                    }
                }
            })
            .collect();
        images.push(ViewerImage {
            key,
            label,
            params,
            aovs,
            missing,
        });
    };
    push(
        "R".into(),
        "reference".into(),
        "CPU ground truth".into(),
        VIEWER_AOVS
            .iter()
            .map(|(a, _)| Some(format!("{scene}/reference/{a}.exr")))
            .collect(),
    );
    let methods = ordered(records.iter().map(|r| r.method.as_str()));
    let mut n = 0;
    for m in methods {
        let best = records
            .iter()
            .filter(|r| r.method == m && r.status == Status::Ok)
            .filter_map(|r| Some((crate::metric::verdict_error(r)?, *r)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((_, r)) = best else { continue };
        n += 1;
        push(
            if n <= 9 { n.to_string() } else { String::new() },
            m.clone(),
            params_text(r),
            VIEWER_AOVS
                .iter()
                .map(|(a, _)| r.images.get(*a).cloned())
                .collect(),
        );
    }
    Viewer {
        aovs: VIEWER_AOVS.iter().map(|(_, l)| l.to_string()).collect(),
        images,
        error_scale: records
            .iter()
            .find_map(|r| r.counters.get("inscatter_error_scale").copied())
            .unwrap_or(0.0),
    }
}

/// Exposure of the scene's shared tone map, recomputed from the reference EXR the same way
/// the runner does (auto exposure on the reference total), so the page can state and use it.
fn exposure(run_dir: &Path, scene: &str) -> Option<f32> {
    let exr = run_dir.join(scene).join("reference").join("total.exr");
    let img = harness::image::io::read_exr(&exr).ok()?;
    Some(ToneMap::auto(&img).exposure)
}

/// The per-scene view plus what its plots draw.
pub struct SceneData<'a> {
    pub view: SceneView,
    pub records: Vec<&'a Record>,
    pub clock: Clock,
}

pub fn scene_data<'a>(
    run_dir: &Path,
    results: &'a Results,
    scene: &str,
    metrics: &[Metric],
) -> SceneData<'a> {
    let records = analysis::scene_records(results, scene);
    let clock = Clock::for_records(&records);
    let fronts: Vec<Vec<Point>> = metrics
        .iter()
        .map(|&m| analysis::pareto_front(&analysis::points_by(&records, clock, m)))
        .collect();
    let pixels = (results.run.resolution[0] as f64) * (results.run.resolution[1] as f64);
    let rows = records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let on = fronts
                .iter()
                .map(|f| f.iter().any(|p| p.index == i))
                .collect();
            row(r, on, metrics, pixels)
        })
        .collect();
    let budgets = metrics
        .iter()
        .map(|&m| {
            let points = analysis::points_by(&records, clock, m);
            MetricBudgets {
                metric: m.id(),
                overall: budget_rows(&records, &points, clock.basis),
                per_method: method_budget_rows(&records, clock, m),
            }
        })
        .collect();
    let anchor = anchor(scene);
    let view = SceneView {
        name: scene.to_string(),
        viewer: viewer(run_dir, &records, &anchor),
        anchor,
        time_label: clock.label(),
        exposure: exposure(run_dir, scene),
        rows,
        plots: Vec::new(),
        budgets,
        frames: None,
    };
    SceneData {
        view,
        records,
        clock,
    }
}

pub fn counts(results: &Results) -> Counts {
    let mut c = Counts {
        total: results.records.len(),
        ..Counts::default()
    };
    for r in &results.records {
        match r.status {
            Status::Ok => c.ok += 1,
            Status::Skipped => c.skipped += 1,
            Status::Failed => c.failed += 1,
        }
    }
    c
}
