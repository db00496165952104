//! `scatterbench report`: a run directory's results.json → `RUN_DIR/report/index.html`, a
//! page that opens from disk with no server and no network (DESIGN §5).
//!
//! Per scene it shows the reference and every method's images side by side (all PNGs of a
//! scene share the tone map the runner chose from the reference), false-colour error maps
//! with their colour bar, a table of times and errors, the time-vs-error Pareto plot (PNG
//! and SVG, drawn with plotters) and the cheapest configuration under 1 %, 5 % and 10 %
//! in-scatter relative RMSE (overall and per method: the equal-error comparison); then a
//! method × scene summary and the machine and run info. A `scatterbench scaling` run
//! (a `scaling.json` beside results.json) gets log–log plots of frame time vs triangles and
//! vs pixels per method with fitted slopes ([`scaling`]).
//! A `scatterbench stress` run gets the stability table (case × method verdicts,
//! [`stability`]) first, above all of that.
//!
//! The HTML comes from a minijinja template (`templates/index.html`, compiled in) with
//! auto-escaping; the page has no external resources and a few lines of vanilla JS to switch
//! the displayed AOV and zoom images. It is written as well-formed XML (XHTML syntax) so
//! tests can parse it strictly.

pub mod analysis;
pub mod fixture;
pub mod plot;
pub mod knobs;
pub mod scaling;
pub mod stability;
pub mod view;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow};
use harness::image::{colormap, io};
use harness::results::Results;

const TEMPLATE: &str = include_str!("../templates/index.html");

/// Height × width (px) of the colour bar PNG shown beside the error maps.
const COLORBAR: (u32, u32) = (256, 16);

/// Writes `run_dir/report/index.html` (plus plots and the colour bar under `report/`) and
/// returns the page's path. Fails with a message naming the file when results.json is
/// missing or unreadable; missing images are shown as missing, not fatal.
pub fn generate(run_dir: &Path) -> Result<PathBuf> {
    let results_path = run_dir.join("results.json");
    if !results_path.is_file() {
        return Err(anyhow!(
            "{} has no results.json: pass the directory `scatterbench run` wrote (e.g. results/<run-id>)",
            run_dir.display()
        ));
    }
    let results = Results::load(&results_path).map_err(|e| anyhow!(e))?;
    let out = run_dir.join("report");
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots).with_context(|| format!("creating {}", plots.display()))?;

    let bar = out.join("colorbar.png");
    io::write_png_ldr(&bar, &colormap::colorbar(COLORBAR.0, COLORBAR.1)).map_err(|e| anyhow!(e))?;

    let mut scenes = Vec::new();
    for name in view::scene_names(&results) {
        let data = view::scene_data(run_dir, &results, &name);
        let mut v = data.view;
        let methods: Vec<&str> = {
            let mut m: Vec<&str> = Vec::new();
            for r in &data.records {
                if !m.contains(&r.method.as_str()) {
                    m.push(&r.method);
                }
            }
            m
        };
        let series: Vec<plot::Series> = methods
            .iter()
            .map(|m| plot::Series {
                name: m,
                points: data
                    .points
                    .iter()
                    .filter(|p| data.records[p.index].method == *m)
                    .copied()
                    .collect(),
            })
            .collect();
        let stem = v.anchor.clone();
        let png = plots.join(format!("{stem}.pareto.png"));
        let svg = plots.join(format!("{stem}.pareto.svg"));
        let title = format!("{name}: frame time vs in-scatter error");
        match plot::pareto(&title, data.basis.label(), &series, &png, &svg) {
            Ok(left_out) => {
                v.plot = Some(view::PlotLinks {
                    svg: format!("plots/{}", view::url_path(&format!("{stem}.pareto.svg"))),
                    png: format!("plots/{}", view::url_path(&format!("{stem}.pareto.png"))),
                });
                if left_out > 0 {
                    v.plot_note.push_str(&format!(
                        " {left_out} point(s) with zero time or error cannot be shown on log axes."
                    ));
                }
            }
            Err(e) => v.plot_note = format!("plot failed: {e:#}"),
        }
        scenes.push(v);
    }

    // A `scatterbench scaling` run: frame time vs triangles and vs pixels per method.
    let scaling = scaling::view(run_dir, &results, &plots)?;
    // Error vs each numeric knob of a sweep, the other knobs fixed per line.
    let knobs = knobs::view(&results, &plots)?;

    let page = view::Page {
        title: format!("scatterbench report — {}", results.run.id),
        counts: view::counts(&results),
        summary: view::summary(&results),
        stability: stability::is_stress(&results).then(|| stability::table(&results)),
        scaling,
        knobs,
        run: results.run.clone(),
        scenes,
        budgets: analysis::BUDGETS
            .iter()
            .map(|b| format!("{:.0} %", b * 100.0))
            .collect(),
        colorbar: "colorbar.png".into(),
        generator: format!("scatterbench report {}", env!("CARGO_PKG_VERSION")),
    };
    let html = render(&page)?;
    let index = out.join("index.html");
    std::fs::write(&index, html).with_context(|| format!("writing {}", index.display()))?;
    Ok(index)
}

/// Renders the page model through the compiled-in template.
pub fn render(page: &view::Page) -> Result<String> {
    let mut env = minijinja::Environment::new();
    // The ".html" name turns on HTML auto-escaping of every interpolated value.
    env.add_template("index.html", TEMPLATE)
        .map_err(|e| anyhow!("report template: {e:#}"))?;
    env.get_template("index.html")
        .and_then(|t| t.render(minijinja::context! { page => page }))
        .map_err(|e| anyhow!("rendering the report: {e:#}"))
}
