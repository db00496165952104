//! Scaling: how each method's frame time grows with the work, from a `scatterbench scaling`
//! run. The run directory holds an ordinary results.json whose scenes are variants of one
//! base scene (more caster triangles, or more pixels), and `scaling.json` ([`Spec`]) saying
//! which variant sits at which x on which sweep. The report draws, per sweep, frame time vs
//! x on log–log axes, one line per method, and fits `time ≈ a · x^slope` by least squares in
//! log–log space: slope 1 is linear in the work, 0 is a fixed cost, 0.5 grows like a
//! silhouette's edge count with the triangle count. Each point's table cell also gives the
//! record's verdict error (the in-scatter headline), and one table puts every method's slopes
//! on every axis side by side.

use std::path::Path;

use anyhow::{Context, Result};
use harness::results::{Record, Results, Status};
use serde::{Deserialize, Serialize};

use crate::analysis::TimeBasis;
pub use crate::fit::{Fit, loglog_fit};
use crate::format::{PlotLinks, anchor, status_text, url_path};

/// The sidecar's file name in the run directory.
pub const FILE: &str = "scaling.json";

/// What `scatterbench scaling` measured.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Spec {
    /// The library scene the variants were made from.
    pub base_scene: String,
    pub sweeps: Vec<Sweep>,
}

/// One axis of work, e.g. caster triangles at a fixed resolution.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Sweep {
    /// "triangles", "pixels" or "lights".
    pub axis: String,
    /// Axis label of the plot, e.g. "caster triangles".
    pub label: String,
    /// What was held fixed, shown under the plot.
    pub note: String,
    /// The scene this sweep's variants come from, where it is not the spec's `base_scene`
    /// (the light sweep's atrium). Absent in scaling.json files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    pub points: Vec<SweepPoint>,
}

/// One scene variant of a sweep.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SweepPoint {
    /// The variant's scene name in results.json.
    pub scene: String,
    /// Position on the sweep's axis (triangles, pixels or local lights).
    pub x: f64,
    pub width: u32,
    pub height: u32,
    /// Caster triangles of the variant.
    pub triangles: usize,
}

impl Spec {
    /// The spec of `run_dir`, or None when the run is not a scaling run.
    pub fn load(run_dir: &Path) -> Result<Option<Spec>> {
        let p = run_dir.join(FILE);
        if !p.is_file() {
            return Ok(None);
        }
        let text =
            std::fs::read_to_string(&p).with_context(|| format!("reading {}", p.display()))?;
        let spec =
            serde_json::from_str(&text).with_context(|| format!("parsing {}", p.display()))?;
        Ok(Some(spec))
    }

    pub fn save(&self, run_dir: &Path) -> Result<()> {
        let p = run_dir.join(FILE);
        let text = serde_json::to_string_pretty(self)?;
        std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))
    }
}

/// One method's measured (x, ms) points on a sweep, sorted by x, and their fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pub method: String,
    /// One entry per sweep point: the time, or why there is none.
    pub cells: Vec<Result<f64, String>>,
    /// One entry per sweep point: the timed record's verdict error, where it has one.
    pub errors: Vec<Option<f64>>,
    pub fit: Option<Fit>,
}

impl Curve {
    pub fn points(&self, sweep: &Sweep) -> Vec<(f64, f64)> {
        sweep
            .points
            .iter()
            .zip(&self.cells)
            .filter_map(|(p, c)| c.as_ref().ok().map(|t| (p.x, *t)))
            .collect()
    }
}

/// The records of a sweep's scenes.
pub fn sweep_records<'a>(results: &'a Results, sweep: &Sweep) -> Vec<&'a Record> {
    results
        .records
        .iter()
        .filter(|r| sweep.points.iter().any(|p| p.scene == r.scene))
        .collect()
}

/// Per method (in order of first appearance), its time at every point of the sweep on one
/// time basis, with the fit. With several parameter sets of a method on a scene the first
/// ok one is used (a scaling run has one: the defaults).
pub fn curves(results: &Results, sweep: &Sweep) -> (TimeBasis, Vec<Curve>) {
    let recs = sweep_records(results, sweep);
    let basis = TimeBasis::for_records(recs.iter().copied());
    let mut methods: Vec<&str> = Vec::new();
    for r in &recs {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    let curves = methods
        .into_iter()
        .map(|m| {
            let (cells, errors) = sweep
                .points
                .iter()
                .map(|p| {
                    let mine: Vec<&&Record> = recs
                        .iter()
                        .filter(|r| r.method == m && r.scene == p.scene)
                        .collect();
                    if let Some((t, r)) = mine
                        .iter()
                        .filter(|r| r.status == Status::Ok)
                        .find_map(|r| basis.time_ms(r).map(|t| (t, r)))
                    {
                        return (Ok(t), crate::metric::verdict_error(r));
                    }
                    let why = match mine.first() {
                        None => "not run".to_string(),
                        Some(r) => format!(
                            "{}: {}",
                            status_text(r.status),
                            r.reason.as_deref().unwrap_or("")
                        ),
                    };
                    (Err(why), None)
                })
                .unzip();
            let mut c = Curve {
                method: m.to_string(),
                cells,
                errors,
                fit: None,
            };
            c.fit = loglog_fit(&c.points(sweep));
            c
        })
        .collect();
    (basis, curves)
}

/// A sweep as the page shows it.
#[derive(Serialize)]
pub struct SweepView {
    pub title: String,
    pub note: String,
    pub time_label: String,
    pub plot: Option<PlotLinks>,
    pub plot_note: String,
    /// Column headers: the x of each point (e.g. "61.4k").
    pub xs: Vec<String>,
    pub rows: Vec<CurveRow>,
}

#[derive(Serialize)]
pub struct CurveRow {
    pub method: String,
    /// Frame time per point ("12.3") or why there is none.
    pub cells: Vec<String>,
    /// Verdict error per point ("0.45 %"), empty where there is none.
    pub errors: Vec<String>,
    /// The fitted exponent ("0.93"), or "—" with fewer than two timed points.
    pub slope: String,
    pub r2: String,
}

/// Compact counts: 960, 3.8k, 61k, 1.0M.
pub fn count_text(x: f64) -> String {
    if x >= 1e6 {
        format!("{:.1}M", x / 1e6)
    } else if x >= 1e4 {
        format!("{:.0}k", x / 1e3)
    } else if x >= 1e3 {
        format!("{:.1}k", x / 1e3)
    } else {
        format!("{x:.0}")
    }
}

/// The scaling section of `run_dir`'s page (plots written to `plots`), or None when the run
/// has no scaling.json.
pub fn view(run_dir: &Path, results: &Results, plots: &Path) -> Result<Option<ScalingView>> {
    let Some(spec) = Spec::load(run_dir)? else {
        return Ok(None);
    };
    let mut out = Vec::new();
    let mut slopes = SlopeTable::default();
    for sweep in &spec.sweeps {
        let (basis, curves) = curves(results, sweep);
        let time_label = basis.label().to_string();
        let y_label = format!("{time_label} · {}", results.run.machine.adapter);
        let lines: Vec<crate::plot::Line> = curves
            .iter()
            .map(|c| crate::plot::Line {
                name: match &c.fit {
                    Some(f) => format!("{} (slope {:.2})", c.method, f.slope),
                    None => c.method.clone(),
                },
                points: c.points(sweep),
                fit: c.fit.as_ref(),
            })
            .collect();
        let stem = format!("scaling-{}", anchor(&sweep.axis));
        let (png, svg) = (format!("{stem}.png"), format!("{stem}.svg"));
        let scene = sweep.scene.as_deref().unwrap_or(&spec.base_scene);
        let title = format!("{scene}: frame time vs {}", sweep.label);
        let (plot, plot_note) = match crate::plot::loglog(
            &title,
            &sweep.label,
            &y_label,
            &lines,
            &plots.join(&png),
            &plots.join(&svg),
        ) {
            Ok(_) => (
                Some(PlotLinks {
                    svg: format!("plots/{}", url_path(&svg)),
                    png: format!("plots/{}", url_path(&png)),
                }),
                format!(
                    "Solid: measured; dashed: the least-squares power law time ≈ a · x^slope. Times on {}; they compare only within this run.",
                    results.run.machine.adapter
                ),
            ),
            Err(e) => (None, format!("plot failed: {e:#}")),
        };
        let rows = curves
            .iter()
            .map(|c| CurveRow {
                method: c.method.clone(),
                cells: c
                    .cells
                    .iter()
                    .map(|v| match v {
                        Ok(t) => format!("{t:.2}"),
                        Err(why) => why.clone(),
                    })
                    .collect(),
                errors: c
                    .errors
                    .iter()
                    .map(|e| e.map_or(String::new(), |e| format!("{:.3} %", 100.0 * e)))
                    .collect(),
                slope: slope_text(c),
                r2: c.fit.map_or("—".into(), |f| format!("{:.3}", f.r2)),
            })
            .collect();
        slopes.add(&sweep.label, &curves);
        out.push(SweepView {
            title: format!("Frame time vs {}", sweep.label),
            note: sweep.note.clone(),
            time_label,
            plot,
            plot_note,
            xs: sweep.points.iter().map(|p| count_text(p.x)).collect(),
            rows,
        });
    }
    Ok(Some(ScalingView {
        sweeps: out,
        slopes,
    }))
}

/// The fitted exponent ("0.93"), or "—" with fewer than two timed points.
fn slope_text(c: &Curve) -> String {
    c.fit.map_or("—".into(), |f| format!("{:.2}", f.slope))
}

/// The scaling section: every sweep, and the slopes side by side.
#[derive(Serialize)]
pub struct ScalingView {
    pub sweeps: Vec<SweepView>,
    pub slopes: SlopeTable,
}

/// Each method's fitted slope on each sweep's axis (methods in order of first appearance).
#[derive(Default, Serialize)]
pub struct SlopeTable {
    /// Axis labels, one column each.
    pub axes: Vec<String>,
    pub rows: Vec<SlopeRow>,
}

#[derive(Serialize)]
pub struct SlopeRow {
    pub method: String,
    /// One per axis: the slope, or "—".
    pub slopes: Vec<String>,
}

impl SlopeTable {
    /// Adds one axis column from its curves.
    fn add(&mut self, axis: &str, curves: &[Curve]) {
        self.axes.push(axis.to_string());
        let columns = self.axes.len();
        for c in curves {
            if !self.rows.iter().any(|r| r.method == c.method) {
                self.rows.push(SlopeRow {
                    method: c.method.clone(),
                    slopes: Vec::new(),
                });
            }
        }
        for row in &mut self.rows {
            let slope = curves
                .iter()
                .find(|c| c.method == row.method)
                .map_or("—".into(), slope_text);
            row.slopes.resize(columns - 1, "—".into());
            row.slopes.push(slope);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_recovers_a_power_law() {
        // y = 3 x^0.7 exactly: slope 0.7, intercept ln 3, r² 1.
        let pts: Vec<(f64, f64)> = [1e3, 4e3, 1.6e4, 6.4e4, 1e6]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(0.7)))
            .collect();
        let f = loglog_fit(&pts).unwrap();
        assert!((f.slope - 0.7).abs() < 1e-9, "{f:?}");
        assert!((f.intercept - 3f64.ln()).abs() < 1e-9);
        assert!((f.r2 - 1.0).abs() < 1e-9);
        assert!((f.eval(2e5) / (3.0 * 2e5f64.powf(0.7)) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn fit_of_a_fixed_cost_plus_linear_term_bends_between_zero_and_one() {
        // t = 5 + x/1000 over three decades: the fitted exponent lies strictly between the
        // fixed-cost (0) and linear (1) limits, and r² < 1 since it is not a power law.
        let pts: Vec<(f64, f64)> = [1e2, 1e3, 1e4, 1e5]
            .iter()
            .map(|&x| (x, 5.0 + x / 1000.0))
            .collect();
        let f = loglog_fit(&pts).unwrap();
        assert!(f.slope > 0.05 && f.slope < 0.95, "{f:?}");
        assert!(f.r2 < 0.999);
    }

    #[test]
    fn fit_needs_two_distinct_positive_abscissae() {
        assert!(loglog_fit(&[]).is_none());
        assert!(loglog_fit(&[(10.0, 1.0)]).is_none());
        assert!(loglog_fit(&[(10.0, 1.0), (10.0, 2.0)]).is_none());
        // Non-positive and non-finite points are dropped, not fitted.
        let f = loglog_fit(&[(0.0, 1.0), (1.0, f64::NAN), (1.0, 2.0), (100.0, 20.0)]).unwrap();
        assert!((f.slope - 0.5).abs() < 1e-12);
    }

    #[test]
    fn counts_are_compact() {
        assert_eq!(count_text(960.0), "960");
        assert_eq!(count_text(3840.0), "3.8k");
        assert_eq!(count_text(61440.0), "61k");
        assert_eq!(count_text(983040.0), "983k");
        assert_eq!(count_text(1_048_576.0), "1.0M");
    }
}
