//! The method × scene matrix: per cell the method's best ok configuration under each metric
//! (value, colour on a perceptual scale, frame time and work per pixel), a dash for a scene
//! the method skipped or failed (its reason on hover and once in a footnote), and the
//! baselines in their own block below the published methods.

use harness::results::{Record, Results, Status};
use serde::Serialize;

use crate::analysis::{self, Clock};
use crate::format::{ms, params_text, rel};
use crate::metric::Metric;

/// Errors at or below this show as the best colour (log scale lower end).
pub const SCALE_LO: f64 = 1e-3;
/// Errors at or above this show as the worst colour (log scale upper end).
pub const SCALE_HI: f64 = 1.0;

/// Viridis (matplotlib's perceptually uniform map), dark purple → yellow, 10 stops. The
/// matrix reverses it: low error is light (yellow), high error dark (purple).
const VIRIDIS: [[u8; 3]; 10] = [
    [68, 1, 84],
    [72, 40, 120],
    [62, 73, 137],
    [49, 104, 142],
    [38, 130, 142],
    [31, 158, 137],
    [53, 183, 121],
    [110, 206, 88],
    [181, 222, 43],
    [253, 231, 37],
];

/// Position of `err` on the colour scale: 0 at ≤ [`SCALE_LO`], 1 at ≥ [`SCALE_HI`], log-linear.
pub fn scale_position(err: f64) -> f64 {
    if err.is_nan() {
        return 1.0;
    }
    let t = (err.max(1e-300).log10() - SCALE_LO.log10()) / (SCALE_HI.log10() - SCALE_LO.log10());
    t.clamp(0.0, 1.0)
}

/// Background and text colour (CSS hex) for an error: viridis reversed, text white on the
/// dark half so it stays readable.
pub fn colour(err: f64) -> (String, &'static str) {
    let t = 1.0 - scale_position(err);
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let c: Vec<u8> = (0..3)
        .map(|k| {
            let a = VIRIDIS[i][k] as f64;
            let b = VIRIDIS[i + 1][k] as f64;
            (a + (b - a) * f).round() as u8
        })
        .collect();
    let fg = if t < 0.45 { "#fff" } else { "#111" };
    (format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]), fg)
}

/// The legend: colour stops of the scale with their error values.
#[derive(Serialize)]
pub struct LegendStop {
    pub bg: String,
    pub label: String,
}

pub fn legend() -> Vec<LegendStop> {
    [1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0]
        .iter()
        .map(|&v| LegendStop {
            bg: colour(v).0,
            label: if v >= SCALE_HI {
                format!("≥ {}", rel(v))
            } else if v <= SCALE_LO {
                format!("≤ {}", rel(v))
            } else {
                rel(v)
            },
        })
        .collect()
}

#[derive(Serialize)]
pub struct Matrix {
    pub scenes: Vec<String>,
    /// Published methods first, then (`baseline` true) the baselines.
    pub rows: Vec<MatrixRow>,
    /// One entry per distinct skip/failure reason, numbered as the cells cite them.
    pub footnotes: Vec<Footnote>,
    pub legend: Vec<LegendStop>,
}

#[derive(Serialize)]
pub struct MatrixRow {
    pub method: String,
    pub baseline: bool,
    /// The first baseline row (draws the separator above it).
    pub first_baseline: bool,
    pub cells: Vec<MatrixCell>,
}

#[derive(Serialize)]
pub struct MatrixCell {
    /// "ok", "skipped", "failed", "none" (ok but unscored) or "absent" (not run).
    pub status: String,
    /// Per metric (page order): the shown value and colours, None where the metric is absent.
    pub values: Vec<Option<CellValue>>,
    /// Footnote number of the reason (skipped/failed).
    pub note: Option<usize>,
    pub title: String,
}

#[derive(Serialize)]
pub struct CellValue {
    pub metric: &'static str,
    pub text: String,
    pub time: String,
    /// Work per pixel (e.g. "3.1 frag/px"), where the record has pipeline counters.
    pub work: String,
    pub bg: String,
    pub fg: &'static str,
    pub title: String,
}

#[derive(Serialize)]
pub struct Footnote {
    pub n: usize,
    pub status: String,
    pub reason: String,
}

/// Work per pixel from the pipeline-statistics counters (issue 17), if recorded: fragment
/// and compute invocations per output pixel.
pub fn work_text(r: &Record, pixels: f64) -> String {
    let per_px = |k: &str| r.counters.get(k).map(|v| v / pixels.max(1.0));
    let mut parts = Vec::new();
    if let Some(f) = per_px("pipeline_fragment_invocations") {
        parts.push(format!("{} frag/px", rel(f)));
    }
    if let Some(c) = per_px("pipeline_compute_invocations").filter(|c| *c > 0.0) {
        parts.push(format!("{} cs/px", rel(c)));
    }
    parts.join(" · ")
}

pub fn matrix(results: &Results, metrics: &[Metric]) -> Matrix {
    let scenes = analysis::scene_names(results);
    let methods = analysis::ordered(results.records.iter().map(|r| r.method.as_str()));
    let (mut published, baselines): (Vec<String>, Vec<String>) = methods
        .into_iter()
        .partition(|m| !crate::methods::is_baseline(results, m));
    let n_published = published.len();
    published.extend(baselines);
    let pixels = (results.run.resolution[0] as f64) * (results.run.resolution[1] as f64);
    let mut footnotes: Vec<Footnote> = Vec::new();
    let clocks: Vec<Clock> = scenes
        .iter()
        .map(|s| Clock::for_records(&analysis::scene_records(results, s)))
        .collect();
    let rows = published
        .iter()
        .enumerate()
        .map(|(i, m)| MatrixRow {
            method: m.clone(),
            baseline: i >= n_published,
            first_baseline: i == n_published,
            cells: scenes
                .iter()
                .zip(&clocks)
                .map(|(s, &clock)| {
                    let recs: Vec<&Record> = results
                        .records
                        .iter()
                        .filter(|r| &r.method == m && &r.scene == s)
                        .collect();
                    cell(&recs, clock, metrics, pixels, &mut footnotes)
                })
                .collect(),
        })
        .collect();
    Matrix {
        scenes,
        rows,
        footnotes,
        legend: legend(),
    }
}

fn cell(
    recs: &[&Record],
    clock: Clock,
    metrics: &[Metric],
    pixels: f64,
    footnotes: &mut Vec<Footnote>,
) -> MatrixCell {
    let values: Vec<Option<CellValue>> = metrics
        .iter()
        .map(|&metric| {
            let points = analysis::points_by(recs, clock, metric);
            let best = points
                .iter()
                .min_by(|a, b| a.error.total_cmp(&b.error).then(a.time.total_cmp(&b.time)))?;
            let r = recs[best.index];
            let (bg, fg) = colour(best.error);
            Some(CellValue {
                metric: metric.id(),
                text: rel(best.error),
                time: format!("{} ms", ms(best.time)),
                work: work_text(r, pixels),
                bg,
                fg,
                title: format!(
                    "best of {} configuration(s): {}",
                    recs.len(),
                    params_text(r)
                ),
            })
        })
        .collect();
    if values.iter().any(Option::is_some) {
        return MatrixCell {
            status: "ok".into(),
            values,
            note: None,
            title: String::new(),
        };
    }
    let first = |s: Status| recs.iter().find(|r| r.status == s);
    let (status, r) = match (first(Status::Failed), first(Status::Skipped)) {
        (Some(r), _) => ("failed", Some(r)),
        (None, Some(r)) => ("skipped", Some(r)),
        (None, None) if recs.is_empty() => ("absent", None),
        (None, None) => ("none", recs.first()),
    };
    let reason = r.and_then(|r| r.reason.clone()).unwrap_or_default();
    let note = (status == "skipped" || status == "failed").then(|| {
        match footnotes
            .iter()
            .find(|f| f.reason == reason && f.status == status)
        {
            Some(f) => f.n,
            None => {
                let n = footnotes.len() + 1;
                footnotes.push(Footnote {
                    n,
                    status: status.into(),
                    reason: reason.clone(),
                });
                n
            }
        }
    });
    MatrixCell {
        status: status.into(),
        values,
        note,
        title: if recs.is_empty() {
            "not run".into()
        } else {
            format!("{status}: {reason}")
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_is_log_and_clamped() {
        assert_eq!(scale_position(1e-4), 0.0);
        assert_eq!(scale_position(7.62), 1.0);
        assert!((scale_position(0.01) - 1.0 / 3.0).abs() < 1e-12);
        assert!((scale_position(0.1) - 2.0 / 3.0).abs() < 1e-12);
        // The two cells: 7.62 and 0.00088 get the two ends of the scale.
        assert_eq!(colour(7.62).0, "#440154");
        assert_eq!(colour(0.00088).0, "#fde725");
    }
}
