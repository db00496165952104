//! `compare.html`: the comparison as display-ready text for `templates/compare.html`, which
//! only lays it out. One page, no files beside it, no network; it fits a 1280 px window
//! (tests/browser.rs checks that with `#layout`, the script shared with the report).

use anyhow::Result;
use harness::method::Params;
use serde::Serialize;

use super::model::{Cell, Comparison, Row, SceneComparison};
use super::scene::pairs;
use crate::format::{anchor, knobs_text, ms, rel, status_text};

#[derive(Serialize)]
struct View {
    title: String,
    runs: Vec<RunView>,
    resolution: [u32; 2],
    frames: u32,
    warmup: u32,
    metric: String,
    metric_short: &'static str,
    floor_method: &'static str,
    tolerance: &'static str,
    budgets: Vec<String>,
    pairs: Vec<PairView>,
    scenes: Vec<SceneView>,
    flags: Vec<FlagView>,
    status: Vec<StatusView>,
    unmatched: Vec<UnmatchedView>,
    notes: Vec<String>,
    changed: usize,
    generator: String,
}

#[derive(Serialize)]
struct RunView {
    label: String,
    adapter: String,
    software: bool,
    driver: String,
    backend: String,
    device_type: String,
    id: String,
    commit: String,
    records: usize,
    dir: String,
    /// The calibration as one line, or "—".
    calibration: String,
    /// The raster-limited flag's message, if flagged.
    raster_limited: Option<String>,
}

#[derive(Serialize)]
struct PairView {
    label: String,
    mean: String,
    scenes: usize,
    pooled: String,
    concordant: u64,
    discordant: u64,
    pairs: u64,
}

#[derive(Serialize)]
struct SceneView {
    name: String,
    anchor: String,
    basis: &'static str,
    taus: Vec<String>,
    floors: Vec<String>,
    /// The front, then one per budget.
    verdicts: Vec<VerdictCell>,
    rows: Vec<RowView>,
}

#[derive(Serialize)]
struct VerdictCell {
    changed: bool,
    lines: Vec<VerdictLine>,
}

#[derive(Serialize)]
struct VerdictLine {
    run: String,
    text: String,
    detail: String,
}

#[derive(Serialize)]
struct RowView {
    name: String,
    params: String,
    floor: bool,
    cells: Vec<CellView>,
    headlines: Vec<String>,
    /// "agree", "differ" or "" (fewer than two headlines).
    agreement: &'static str,
}

#[derive(Serialize)]
struct CellView {
    status: &'static str,
    reason: String,
    ratio: String,
    time: String,
}

#[derive(Serialize)]
struct FlagView {
    scene: String,
    anchor: String,
    name: String,
    params: String,
    headlines: Vec<String>,
    difference: String,
    allowed: String,
}

#[derive(Serialize)]
struct StatusView {
    scene: String,
    name: String,
    params: String,
    statuses: Vec<String>,
}

/// The configurations of one scene that the same runs lack.
#[derive(Serialize)]
struct UnmatchedView {
    scene: String,
    in_runs: String,
    configs: Vec<Config>,
}

#[derive(Serialize)]
struct Config {
    method: String,
    params: String,
}

/// A fraction as a percentage with three significant digits ("0.00400 %", "12.3 %").
pub fn percent(v: f64) -> String {
    format!("{} %", rel(v * 100.0))
}

fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map(f).unwrap_or_else(|| "—".into())
}

fn tau_text(t: Option<f64>) -> String {
    opt(t, |t| format!("{t:.2}"))
}

/// A configuration's name on the page: its method, with its knobs when the scene has
/// several configurations of that method.
fn name(method: &str, params: &Params, rows: &[Row]) -> String {
    if rows.iter().filter(|r| r.method == method).count() > 1 {
        format!("{method} ({})", knobs_text(params))
    } else {
        method.to_string()
    }
}

pub fn render(c: &Comparison) -> Result<String> {
    crate::template::render("compare.html", &view(c))
}

fn view(c: &Comparison) -> View {
    let labels: Vec<String> = c.runs.iter().map(|r| r.label.clone()).collect();
    let scenes: Vec<SceneView> = c.scenes.iter().map(|s| scene(s, &labels)).collect();
    View {
        title: format!(
            "scatterbench compare — {}",
            c.runs
                .iter()
                .map(|r| r.machine.adapter.as_str())
                .collect::<Vec<_>>()
                .join(" vs ")
        ),
        runs: c.runs.iter().map(run).collect(),
        resolution: c.resolution,
        frames: c.frames,
        warmup: c.warmup,
        metric: c.metric.clone(),
        metric_short: c.metric_short,
        floor_method: c.floor_method,
        tolerance: c.tolerance.rule,
        budgets: c.budgets.iter().map(|b| crate::verdict::pct(*b)).collect(),
        pairs: c
            .tau
            .iter()
            .map(|t| PairView {
                label: format!("{}–{}", labels[t.a], labels[t.b]),
                mean: tau_text(t.mean),
                scenes: t.scenes,
                pooled: tau_text(t.pooled),
                concordant: t.counts.concordant,
                discordant: t.counts.discordant,
                pairs: t.counts.pairs,
            })
            .collect(),
        changed: c.scenes.iter().filter(|s| s.changed.any()).count(),
        flags: flags(c),
        status: status(c),
        unmatched: unmatched(c),
        notes: c.notes.clone(),
        scenes,
        generator: format!("scatterbench compare {}", env!("CARGO_PKG_VERSION")),
    }
}

fn run(r: &super::model::RunSummary) -> RunView {
    let m = &r.machine;
    RunView {
        label: r.label.clone(),
        adapter: m.adapter.clone(),
        software: m.software,
        driver: format!("{} {}", m.driver, m.driver_info).trim().to_string(),
        backend: m.backend.clone(),
        device_type: m.device_type.clone(),
        id: r.id.clone(),
        commit: r.git_commit.clone(),
        records: r.records,
        dir: r.dir.clone(),
        calibration: m
            .calibration
            .as_ref()
            .map_or("—".into(), crate::calibration::text),
        raster_limited: r.raster_limited.as_ref().map(|f| f.message.clone()),
    }
}

fn scene(s: &SceneComparison, labels: &[String]) -> SceneView {
    SceneView {
        name: s.scene.clone(),
        anchor: anchor(&s.scene),
        basis: if s.time_basis == "gpu" { "GPU" } else { "wall" },
        taus: pairs(labels.len())
            .zip(&s.tau)
            .map(|((a, b), t)| match labels.len() > 2 {
                true => format!("{}–{} {}", labels[a], labels[b], tau_text(t.tau)),
                false => tau_text(t.tau),
            })
            .collect(),
        floors: s
            .floor_ms
            .iter()
            .zip(labels)
            .map(|(f, l)| format!("{l} {}", opt(*f, |f| format!("{} ms", ms(f)))))
            .collect(),
        verdicts: verdict_cells(s, labels),
        rows: s.rows.iter().map(|r| row(r, &s.rows)).collect(),
    }
}

/// The front, then the winner of each budget: one line per run.
fn verdict_cells(s: &SceneComparison, labels: &[String]) -> Vec<VerdictCell> {
    let line = |run: usize, text: String, detail: String| VerdictLine {
        run: labels[run].clone(),
        text,
        detail,
    };
    let front = |run: usize| {
        let names: Vec<String> = s.verdicts[run]
            .front
            .iter()
            .map(|p| name(&p.method, &p.params, &s.rows))
            .collect();
        let text = if names.is_empty() {
            "—".into()
        } else {
            names.join(", ")
        };
        line(run, text, String::new())
    };
    let winner = |run: usize, b: usize| match &s.verdicts[run].budgets[b] {
        None => line(run, "none".into(), String::new()),
        Some(p) => line(
            run,
            name(&p.method, &p.params, &s.rows),
            match p.floor_ratio {
                Some(x) => format!("{}× · {}", rel(x), percent(p.error)),
                None => format!("{} ms · {}", ms(p.time_ms), percent(p.error)),
            },
        ),
    };
    let runs = 0..labels.len();
    let mut cells = vec![VerdictCell {
        changed: s.changed.front,
        lines: runs.clone().map(front).collect(),
    }];
    cells.extend(
        s.changed
            .budgets
            .iter()
            .enumerate()
            .map(|(b, &changed)| VerdictCell {
                changed,
                lines: runs.clone().map(|run| winner(run, b)).collect(),
            }),
    );
    cells
}

fn row(r: &Row, rows: &[Row]) -> RowView {
    RowView {
        name: name(&r.method, &r.params, rows),
        params: knobs_text(&r.params),
        floor: r.floor,
        cells: r.runs.iter().map(cell).collect(),
        headlines: r.runs.iter().map(|c| opt(c.headline, percent)).collect(),
        agreement: match r.headlines_agree {
            Some(true) => "agree",
            Some(false) => "differ",
            None => "",
        },
    }
}

fn cell(c: &Cell) -> CellView {
    CellView {
        status: status_text(c.status),
        reason: c.reason.clone().unwrap_or_default(),
        ratio: opt(c.ratio, |r| format!("{}×", rel(r))),
        time: opt(c.time_ms, |t| format!("{} ms", ms(t))),
    }
}

/// A configuration's name in a list of `scene`'s configurations (see [`name`]).
fn name_in(c: &Comparison, scene: &str, method: &str, params: &Params) -> String {
    let rows = c
        .scenes
        .iter()
        .find(|s| s.scene == scene)
        .map(|s| &s.rows[..]);
    name(method, params, rows.unwrap_or_default())
}

fn flags(c: &Comparison) -> Vec<FlagView> {
    c.headline_flags
        .iter()
        .map(|f| FlagView {
            anchor: anchor(&f.scene),
            scene: f.scene.clone(),
            name: name_in(c, &f.scene, &f.method, &f.params),
            params: knobs_text(&f.params),
            headlines: f.headlines.iter().map(|h| opt(*h, percent)).collect(),
            difference: percent(f.difference),
            allowed: percent(f.allowed),
        })
        .collect()
}

fn status(c: &Comparison) -> Vec<StatusView> {
    c.status_differs
        .iter()
        .map(|s| StatusView {
            scene: s.scene.clone(),
            name: name_in(c, &s.scene, &s.method, &s.params),
            params: knobs_text(&s.params),
            statuses: s
                .statuses
                .iter()
                .zip(&s.reasons)
                .map(|(st, why)| match why {
                    Some(w) if !w.is_empty() => format!("{}: {w}", status_text(*st)),
                    _ => status_text(*st).to_string(),
                })
                .collect(),
        })
        .collect()
}

/// The work some run lacks, one line per scene and set of runs that have it.
fn unmatched(c: &Comparison) -> Vec<UnmatchedView> {
    let mut out: Vec<UnmatchedView> = Vec::new();
    for u in &c.not_in_every_run {
        let in_runs = u.in_runs.join(", ");
        let config = Config {
            method: u.method.clone(),
            params: knobs_text(&u.params),
        };
        match out
            .iter_mut()
            .find(|v| v.scene == u.scene && v.in_runs == in_runs)
        {
            Some(v) => v.configs.push(config),
            None => out.push(UnmatchedView {
                scene: u.scene.clone(),
                in_runs,
                configs: vec![config],
            }),
        }
    }
    out
}
