//! The page's data: results.json turned into display-ready rows, cards and tables that the
//! template only lays out. Numbers are formatted here so every table uses the same units
//! and precision. Image links are made only to files that exist, so a page never shows a
//! broken image; a missing file is shown as "missing" with its path.

use std::collections::BTreeMap;
use std::path::Path;

use harness::image::metrics::ToneMap;
use harness::results::{Record, Results, Status};
use serde::Serialize;

use crate::analysis::{self, BUDGETS, Point, TimeBasis};

/// The AOVs shown side by side, in display order, with their labels.
pub const AOVS: [(&str, &str); 3] = [
    ("inscatter", "in-scatter"),
    ("total", "total"),
    ("surface", "surface"),
];

#[derive(Serialize)]
pub struct Page {
    pub title: String,
    pub run: harness::results::RunInfo,
    pub counts: Counts,
    pub scenes: Vec<SceneView>,
    pub summary: Summary,
    /// The stability table, for a stress run only.
    pub stability: Option<crate::stability::Stability>,
    /// The scaling sweeps, for a `scatterbench scaling` run only.
    pub scaling: Option<Vec<crate::scaling::SweepView>>,
    /// Error vs each swept numeric knob (empty without a sweep).
    pub knobs: Vec<crate::knobs::KnobPlot>,
    pub budgets: Vec<String>,
    pub colorbar: String,
    pub generator: String,
}

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
    pub exposure: Option<String>,
    pub reference: Vec<ImageLink>,
    /// Error at the top of the colour bar, per error map ("inscatter", "total").
    pub error_scales: Vec<ScaleView>,
    pub cards: Vec<Card>,
    pub rows: Vec<Row>,
    pub plot: Option<PlotLinks>,
    pub plot_note: String,
    pub budget: Vec<BudgetRow>,
    /// Equal error: each method's cheapest configuration under each budget.
    pub method_budget: Vec<MethodBudgetRow>,
}

#[derive(Serialize)]
pub struct MethodBudgetRow {
    pub method: String,
    /// Per budget: "time ms (params, error)", or None when no configuration is within it.
    pub cells: Vec<Option<String>>,
}

#[derive(Serialize)]
pub struct ScaleView {
    pub aov: String,
    pub top: String,
}

#[derive(Serialize)]
pub struct PlotLinks {
    pub svg: String,
    pub png: String,
}

/// An image of one AOV (or error map): a link when the file exists, else the missing path.
#[derive(Serialize, Clone)]
pub struct ImageLink {
    /// "inscatter", "total", "surface", "inscatter_error", "total_error".
    pub kind: String,
    pub label: String,
    pub src: Option<String>,
    pub missing: Option<String>,
}

#[derive(Serialize)]
pub struct Card {
    pub method: String,
    pub params: String,
    pub status: String,
    pub reason: String,
    pub images: Vec<ImageLink>,
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
    pub memory: String,
    pub rel_rmse: String,
    pub flip: String,
    pub nonfinite: String,
    pub skipped_passes: String,
    pub on_front: bool,
}

#[derive(Serialize)]
pub struct BudgetRow {
    pub budget: String,
    pub method: Option<String>,
    pub params: String,
    pub time: String,
    pub error: String,
}

#[derive(Serialize)]
pub struct Summary {
    pub scenes: Vec<String>,
    pub rows: Vec<SummaryRow>,
}

#[derive(Serialize)]
pub struct SummaryRow {
    pub method: String,
    pub cells: Vec<SummaryCell>,
}

#[derive(Serialize)]
pub struct SummaryCell {
    /// "ok", "skipped", "failed", "none" (ok but unscored) or "absent" (not run).
    pub status: String,
    pub text: String,
    pub title: String,
}

/// The record's parameters as `k=v k=v`, sorted by knob name.
pub fn params_text(r: &Record) -> String {
    let p: Vec<String> = r.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    if p.is_empty() {
        "(none)".into()
    } else {
        p.join(" ")
    }
}

pub fn status_text(s: Status) -> &'static str {
    match s {
        Status::Ok => "ok",
        Status::Skipped => "skipped",
        Status::Failed => "failed",
    }
}

fn ms(v: f64) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

/// Relative errors with three significant digits (0.0123, 1.89, 4.20e-5).
pub fn rel(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    if v.abs() < 1e-3 || v.abs() >= 1e4 {
        return format!("{v:.2e}");
    }
    let decimals = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

fn mib(bytes: u64) -> String {
    format!("{:.1} MiB", bytes as f64 / (1024.0 * 1024.0))
}

/// A file-name and HTML-id friendly form of a scene name.
pub fn anchor(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("scene-{s}")
}

/// Percent-encodes a relative path for an `src`/`href` (keeps `/` and unreserved chars).
pub fn url_path(rel: &str) -> String {
    let mut out = String::new();
    for b in rel.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// A link from `report/index.html` to `rel` (relative to the run directory), if that file
/// exists. Absolute paths and paths leaving the run directory are treated as missing, since
/// the page must work wherever the run directory is copied to.
fn link(run_dir: &Path, kind: &str, label: &str, rel: Option<&str>) -> ImageLink {
    let (src, missing) = match rel {
        None => (None, Some("(not recorded)".to_string())),
        Some(p) => {
            let escapes = Path::new(p).is_absolute()
                || Path::new(p)
                    .components()
                    .any(|c| c == std::path::Component::ParentDir);
            if !escapes && run_dir.join(p).is_file() {
                (Some(format!("../{}", url_path(p))), None)
            } else {
                (None, Some(p.to_string()))
            }
        }
    };
    ImageLink {
        kind: kind.into(),
        label: label.into(),
        src,
        missing,
    }
}

fn card(run_dir: &Path, r: &Record) -> Card {
    // A record that failed before writing anything has no images to show as missing.
    if r.images.is_empty() {
        return Card {
            method: r.method.clone(),
            params: params_text(r),
            status: status_text(r.status).into(),
            reason: r.reason.clone().unwrap_or_default(),
            images: Vec::new(),
        };
    }
    let mut images: Vec<ImageLink> = AOVS
        .iter()
        .map(|(aov, label)| {
            let key = format!("{aov}_png");
            link(run_dir, aov, label, r.images.get(&key).map(String::as_str))
        })
        .collect();
    for (aov, label) in [("inscatter", "in-scatter error"), ("total", "total error")] {
        let key = format!("{aov}_error");
        images.push(link(
            run_dir,
            &key,
            label,
            r.images.get(&key).map(String::as_str),
        ));
    }
    Card {
        method: r.method.clone(),
        params: params_text(r),
        status: status_text(r.status).into(),
        reason: r.reason.clone().unwrap_or_default(),
        images,
    }
}

fn row(r: &Record, on_front: bool) -> Row {
    let t = r.timing.as_ref();
    let errs = |aov: &str| r.errors.get(aov);
    let flip: Vec<String> = ["inscatter", "total"]
        .iter()
        .filter_map(|a| errs(a).map(|m| format!("{:.4}", m.flip_mean)))
        .collect();
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
        memory: r.memory_bytes.map(mib).unwrap_or_else(|| "—".into()),
        rel_rmse: errs("inscatter")
            .map(|m| rel(m.rel_rmse))
            .unwrap_or_else(|| "—".into()),
        flip: if flip.is_empty() {
            "—".into()
        } else {
            flip.join(" / ")
        },
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
                        time: format!(
                            "{} ms ({})",
                            ms(p.time),
                            if basis == TimeBasis::Gpu {
                                "GPU"
                            } else {
                                "wall"
                            }
                        ),
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
fn method_budget_rows(records: &[&Record], basis: TimeBasis) -> Vec<MethodBudgetRow> {
    ordered(records.iter().map(|r| r.method.as_str()))
        .into_iter()
        .map(|m| {
            let mine: Vec<&Record> = records.iter().copied().filter(|r| r.method == m).collect();
            let points = analysis::points(&mine, basis);
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

/// Exposure of the scene's shared tone map, recomputed from the reference EXR the same way
/// the runner does (auto exposure on the reference total), so the page can state it.
fn exposure(run_dir: &Path, scene: &str) -> Option<String> {
    let exr = run_dir.join(scene).join("reference").join("total.exr");
    let img = harness::image::io::read_exr(&exr).ok()?;
    Some(format!("{:+.2} stops", ToneMap::auto(&img).exposure))
}

/// Items in order of first appearance.
fn ordered<'a>(items: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in items {
        if !out.iter().any(|o| o == s) {
            out.push(s.to_string());
        }
    }
    out
}

/// The per-scene view plus the records and Pareto points the plot draws.
pub struct SceneData<'a> {
    pub view: SceneView,
    pub records: Vec<&'a Record>,
    pub points: Vec<Point>,
    pub basis: TimeBasis,
}

pub fn scene_data<'a>(run_dir: &Path, results: &'a Results, scene: &str) -> SceneData<'a> {
    let records: Vec<&Record> = results
        .records
        .iter()
        .filter(|r| r.scene == scene)
        .collect();
    let basis = TimeBasis::for_records(records.iter().copied());
    let points = analysis::points(&records, basis);
    let front = analysis::pareto_front(&points);
    let reference = AOVS
        .iter()
        .map(|(aov, label)| {
            let rel = format!("{scene}/reference/{aov}.png");
            link(run_dir, aov, label, Some(&rel))
        })
        .collect();
    // All records of a scene share the reference and so the scale; take the first one.
    let error_scales = ["inscatter", "total"]
        .iter()
        .filter_map(|aov| {
            let key = format!("{aov}_error_scale");
            records
                .iter()
                .find_map(|r| r.counters.get(&key))
                .map(|v| ScaleView {
                    aov: format!("{aov}_error"),
                    top: format!("{v:.3e}"),
                })
        })
        .collect();
    let rows = records
        .iter()
        .enumerate()
        .map(|(i, r)| row(r, front.iter().any(|p| p.index == i)))
        .collect();
    let cards = records
        .iter()
        .filter(|r| r.status != Status::Skipped)
        .map(|r| card(run_dir, r))
        .collect();
    let plot_note = format!(
        "{} of {} records plotted (ok, timed and scored); {} on the Pareto front.",
        points.len(),
        records.len(),
        front.len()
    );
    let view = SceneView {
        name: scene.to_string(),
        anchor: anchor(scene),
        time_label: basis.label().to_string(),
        exposure: exposure(run_dir, scene),
        reference,
        error_scales,
        cards,
        rows,
        plot: None,
        plot_note,
        budget: budget_rows(&records, &points, basis),
        method_budget: method_budget_rows(&records, basis),
    };
    SceneData {
        view,
        records,
        points,
        basis,
    }
}

pub fn scene_names(results: &Results) -> Vec<String> {
    ordered(results.records.iter().map(|r| r.scene.as_str()))
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

/// Method × scene: the most accurate ok configuration (error and its time), else why none.
pub fn summary(results: &Results) -> Summary {
    let scenes = scene_names(results);
    let methods = ordered(results.records.iter().map(|r| r.method.as_str()));
    let mut by_scene: BTreeMap<&str, TimeBasis> = BTreeMap::new();
    for s in &scenes {
        by_scene.insert(
            s,
            TimeBasis::for_records(results.records.iter().filter(|r| &r.scene == s)),
        );
    }
    let rows = methods
        .iter()
        .map(|m| SummaryRow {
            method: m.clone(),
            cells: scenes
                .iter()
                .map(|s| {
                    let recs: Vec<&Record> = results
                        .records
                        .iter()
                        .filter(|r| &r.method == m && &r.scene == s)
                        .collect();
                    summary_cell(&recs, by_scene[s.as_str()])
                })
                .collect(),
        })
        .collect();
    Summary { scenes, rows }
}

fn summary_cell(recs: &[&Record], basis: TimeBasis) -> SummaryCell {
    let points = analysis::points(recs, basis);
    let best = points
        .iter()
        .min_by(|a, b| a.error.total_cmp(&b.error).then(a.time.total_cmp(&b.time)));
    if let Some(p) = best {
        return SummaryCell {
            status: "ok".into(),
            text: format!("{} @ {} ms", rel(p.error), ms(p.time)),
            title: format!(
                "best in-scatter rel. RMSE of {} configuration(s): {}",
                recs.len(),
                params_text(recs[p.index])
            ),
        };
    }
    let first = |s: Status| recs.iter().find(|r| r.status == s);
    let (status, r) = match (first(Status::Failed), first(Status::Skipped)) {
        (Some(r), _) => ("failed", Some(r)),
        (None, Some(r)) => ("skipped", Some(r)),
        (None, None) if recs.is_empty() => ("absent", None),
        // Ok records without a time or an error (should not happen) show as unscored.
        (None, None) => ("none", recs.first()),
    };
    SummaryCell {
        status: status.into(),
        text: if recs.is_empty() {
            "not run".into()
        } else if status == "none" {
            "unscored".into()
        } else {
            status.into()
        },
        title: r.and_then(|r| r.reason.clone()).unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rel_keeps_three_significant_digits() {
        assert_eq!(rel(0.0013916), "0.00139");
        assert_eq!(rel(0.04389), "0.0439");
        assert_eq!(rel(1.8857), "1.89");
        assert_eq!(rel(12.34), "12.3");
        assert_eq!(rel(5.575e-4), "5.58e-4");
        assert_eq!(rel(0.0), "0");
        assert_eq!(rel(f64::NAN), "NaN");
    }

    #[test]
    fn url_path_encodes_reserved_characters_only() {
        assert_eq!(url_path("a b/c&d/x-1_y.png"), "a%20b/c%26d/x-1_y.png");
        assert_eq!(url_path("é"), "%C3%A9");
    }
}
