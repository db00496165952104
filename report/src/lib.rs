//! `scatterbench report`: a run directory's results.json → `RUN_DIR/report/index.html`, a
//! page that opens from disk with no server and no network (ARCHITECTURE §5.2).
//!
//! It opens with the verdict ([`verdict`]): per scene the methods on the time-vs-error
//! Pareto front and the fastest configuration under 1 %, 5 % and 10 % error, in a table and
//! a sentence. Then the method × scene matrix ([`matrix`]): each method's best
//! configuration, coloured on a perceptual (viridis, log) scale, with frame time and work
//! per pixel, skipped cells as a dash with a numbered reason, baselines set apart (as
//! results.json's `run.methods` describes them: the report reads nothing but the run directory,
//! [`methods`], which also gives the page its table of papers). A switch
//! re-ranks every table and plot by another metric ([`metric`]; the verdict metric is the
//! headline error where records have it, else in-scatter relative RMSE). Per scene: an
//! in-place image viewer ([`viewer`]: reference and one record per method as linear
//! half-float data, flipped with keys as in tev, synchronised nearest-pixel zoom, a read-out
//! of both images' radiance), the Pareto plot per metric (PNG and SVG, plotters; legend
//! outside the data, hollow markers, the device under the time axis), the budget and
//! equal-error tables and every record. A `scatterbench scaling` run (a `scaling.json`
//! beside results.json) gets log–log plots of frame time vs triangles and vs pixels per
//! method with fitted slopes ([`scaling`]); a `scatterbench stress` run the stability
//! table ([`stability`]).
//!
//! The HTML comes from a minijinja template (`templates/index.html`, compiled in) with
//! auto-escaping and the inlined script `templates/viewer.js`; the page is well-formed XML
//! (XHTML syntax, the script in CDATA) so tests parse it strictly. Opened with
//! `#selftest=X,Y` the script drives the first viewer and writes a JSON verdict into the
//! DOM (tests/browser.rs reads it through headless Chromium).

pub mod analysis;
pub mod calibration;
pub mod candidates;
pub mod compare;
pub mod fit;
pub mod fixture;
pub mod format;
pub mod frames;
pub mod frontier;
pub mod knobs;
pub mod matrix;
pub mod methods;
pub mod metric;
pub mod page;
pub mod plot;
pub mod scaling;
pub mod stability;
pub mod template;
pub mod tune;
pub mod verdict;
pub mod view;
pub mod viewer;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow};
use harness::results::Results;

use crate::metric::Metric;

/// The page's script: viewer, metric switch, self-test (inlined into the page).
const SCRIPT: &str = include_str!("../templates/viewer.js");

/// Reads results.json and the optional fields newer than [`Results`] (see [`metric`]).
pub(crate) fn load(results_path: &Path) -> Result<(Results, Option<String>)> {
    let mut results = Results::load(results_path).map_err(|e| anyhow!(e))?;
    let text = std::fs::read_to_string(results_path)
        .with_context(|| format!("reading {}", results_path.display()))?;
    let raw: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("parsing {}", results_path.display()))?;
    let headline = metric::annotate(&mut results, &raw).or_else(|| results.run.headline.clone());
    Ok((results, headline))
}

/// Writes `run_dir/report/index.html` (plus plots under `report/plots`) and returns the
/// page's path. Fails with a message naming the file when results.json is missing or
/// unreadable; missing images are shown as missing, not fatal.
pub fn generate(run_dir: &Path) -> Result<PathBuf> {
    let results_path = run_dir.join("results.json");
    if !results_path.is_file() {
        return Err(anyhow!(
            "{} has no results.json: pass the directory `scatterbench run` wrote (e.g. results/<run-id>)",
            run_dir.display()
        ));
    }
    let (results, headline) = load(&results_path)?;
    let out = run_dir.join("report");
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots).with_context(|| format!("creating {}", plots.display()))?;

    let metrics = metric::available(&results);
    let metric_views = metric::views(headline.as_deref(), &metrics);
    let device = &results.run.machine.adapter;
    let mut scenes = Vec::new();
    for name in analysis::scene_names(&results) {
        let data = view::scene_data(run_dir, &results, &name, &metrics);
        let mut v = data.view;
        v.plots = metrics
            .iter()
            .zip(&metric_views)
            .map(|(&m, mv)| {
                scene_plot(
                    &data.records,
                    data.clock,
                    m,
                    &mv.label,
                    device,
                    &v.anchor,
                    &name,
                    &plots,
                )
            })
            .collect();
        v.frames = frames::view(&data.records, &name, &v.anchor, device, &plots);
        scenes.push(v);
    }

    // A `scatterbench scaling` run: frame time vs triangles and vs pixels per method.
    let scaling = scaling::view(run_dir, &results, &plots)?;
    // Error vs each numeric knob of a sweep, the other knobs fixed per line.
    let knobs = knobs::view(&results, &plots, &metric_views[0].label)?;

    let page = page::Page {
        title: format!("scatterbench report — {}", results.run.id),
        counts: view::counts(&results),
        verdicts: verdict::tables(&results, &metrics),
        matrix: matrix::matrix(&results, &metrics),
        methods: methods::rows(&results),
        metrics: metric_views,
        tune: tune::view(run_dir)?,
        stability: stability::is_stress(&results).then(|| stability::table(&results)),
        scaling,
        knobs,
        calibration: results
            .run
            .machine
            .calibration
            .as_ref()
            .map(calibration::text),
        run: results.run.clone(),
        scenes,
        budgets: analysis::BUDGETS
            .iter()
            .map(|b| format!("{:.0} %", b * 100.0))
            .collect(),
        generator: format!("scatterbench report {}", env!("CARGO_PKG_VERSION")),
        script: SCRIPT,
    };
    let html = render(&page)?;
    let index = out.join("index.html");
    std::fs::write(&index, html).with_context(|| format!("writing {}", index.display()))?;
    Ok(index)
}

/// One scene's Pareto plot under one metric (PNG and SVG under `plots/`).
#[allow(clippy::too_many_arguments)]
fn scene_plot(
    records: &[&harness::results::Record],
    clock: analysis::Clock,
    metric: Metric,
    label: &str,
    device: &str,
    anchor: &str,
    scene: &str,
    plots: &Path,
) -> view::PlotView {
    let points = analysis::points_by(records, clock, metric);
    let series: Vec<plot::Series> = analysis::ordered(records.iter().map(|r| r.method.as_str()))
        .iter()
        .map(|m| plot::Series {
            name: records
                .iter()
                .find(|r| &r.method == m)
                .map(|r| r.method.as_str())
                .unwrap_or(""),
            points: points
                .iter()
                .filter(|p| &records[p.index].method == m)
                .copied()
                .collect(),
        })
        .collect();
    let stem = format!("{anchor}.pareto.{}", metric.id());
    let (png, svg) = (format!("{stem}.png"), format!("{stem}.svg"));
    let front = analysis::pareto_front(&points).len();
    let mut note = format!(
        "{} of {} records plotted (ok, timed and scored); {front} on the Pareto front.",
        points.len(),
        records.len()
    );
    let labels = plot::ParetoLabels {
        title: &format!("{scene}: frame time vs {label}"),
        x: &clock.label(),
        y: label,
        device,
    };
    let links = match plot::pareto(&labels, &series, &plots.join(&png), &plots.join(&svg)) {
        Ok(left_out) => {
            if left_out > 0 {
                note.push_str(&format!(
                    " {left_out} point(s) with zero time or error cannot be shown on log axes."
                ));
            }
            Some(format::PlotLinks {
                svg: format!("plots/{}", format::url_path(&svg)),
                png: format!("plots/{}", format::url_path(&png)),
            })
        }
        Err(e) => {
            note = format!("plot failed: {e:#}");
            None
        }
    };
    view::PlotView {
        metric: metric.id(),
        links,
        note,
    }
}

/// Renders the page model through the compiled-in template.
pub fn render(page: &page::Page) -> Result<String> {
    template::render("index.html", page)
}
