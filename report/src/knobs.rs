//! Knob response: how a method's verdict error (the in-scatter headline,
//! `metric::verdict_error`) moves along one numeric knob, the other knobs held fixed — e.g.
//! `biri-polynomial`'s error vs polynomial `order`, one line per `fit`. Any sweep gets these
//! plots; a knob needs at least three values on one line to be drawn.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Result;
use harness::method::ParamValue;
use harness::results::{Record, Results, Status};
use serde::Serialize;

use crate::format::{PlotLinks, anchor, url_path};
use crate::plot::{Line, loglog};

/// Fewest points on one line for a knob to be plotted.
const MIN_POINTS: usize = 3;
/// Most lines per plot (the longest are kept).
const MAX_LINES: usize = 8;

/// One knob's lines: label (the other knobs that vary, `k=v`) → (knob value, error) sorted by x.
#[derive(Debug, PartialEq)]
pub struct Response {
    pub knob: String,
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
}

/// The knob responses of one method's ok records on one scene.
pub fn responses(records: &[&Record]) -> Vec<Response> {
    let knobs: Vec<&String> = records
        .first()
        .map(|r| r.params.keys().collect())
        .unwrap_or_default();
    // Knobs that vary at all among these records, to label lines by.
    let varying: Vec<&String> = knobs
        .iter()
        .copied()
        .filter(|k| {
            let first = records[0].params.get(*k);
            records.iter().any(|r| r.params.get(*k) != first)
        })
        .collect();
    let mut out = Vec::new();
    for knob in &varying {
        let mut lines: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
        for r in records {
            let (Some(x), Some(e)) = (
                r.params.get(*knob).and_then(ParamValue::as_f64),
                crate::metric::verdict_error(r),
            ) else {
                continue;
            };
            let label: Vec<String> = varying
                .iter()
                .filter(|k| *k != knob)
                .map(|k| {
                    format!(
                        "{k}={}",
                        r.params.get(*k).map_or("-".into(), |v| v.to_string())
                    )
                })
                .collect();
            lines.entry(label.join(" ")).or_default().push((x, e));
        }
        let mut kept: Vec<(String, Vec<(f64, f64)>)> = lines
            .into_iter()
            .filter(|(_, p)| {
                let mut xs: Vec<f64> = p.iter().map(|q| q.0).collect();
                xs.sort_by(f64::total_cmp);
                xs.dedup();
                xs.len() >= MIN_POINTS
            })
            .map(|(l, mut p)| {
                p.sort_by(|a, b| a.0.total_cmp(&b.0));
                (if l.is_empty() { "all".into() } else { l }, p)
            })
            .collect();
        kept.sort_by_key(|(_, p)| std::cmp::Reverse(p.len()));
        kept.truncate(MAX_LINES);
        if !kept.is_empty() {
            out.push(Response {
                knob: (*knob).clone(),
                lines: kept,
            });
        }
    }
    out
}

#[derive(Serialize)]
pub struct KnobPlot {
    pub scene: String,
    pub method: String,
    pub knob: String,
    pub plot: Option<PlotLinks>,
    pub note: String,
}

/// Every scene × method × knob response of the run, plotted into `plots`; `y_label` names the
/// error drawn, the verdict metric's label ([`crate::metric::Metric::label`]).
pub fn view(results: &Results, plots: &Path, y_label: &str) -> Result<Vec<KnobPlot>> {
    let mut groups: BTreeMap<(String, String), Vec<&Record>> = BTreeMap::new();
    for r in results.records.iter().filter(|r| r.status == Status::Ok) {
        groups
            .entry((r.scene.clone(), r.method.clone()))
            .or_default()
            .push(r);
    }
    let mut out = Vec::new();
    for ((scene, method), recs) in groups {
        for resp in responses(&recs) {
            let stem = format!(
                "knob-{}-{}-{}",
                anchor(&scene),
                anchor(&method),
                anchor(&resp.knob)
            );
            let (png, svg) = (format!("{stem}.png"), format!("{stem}.svg"));
            let lines: Vec<Line> = resp
                .lines
                .iter()
                .map(|(name, points)| Line {
                    name: name.clone(),
                    points: points.clone(),
                    fit: None,
                })
                .collect();
            let title = format!("{scene} · {method}: error vs {}", resp.knob);
            let (plot, note) = match loglog(
                &title,
                &resp.knob,
                y_label,
                &lines,
                &plots.join(&png),
                &plots.join(&svg),
            ) {
                Ok(0) => (
                    Some(PlotLinks {
                        svg: format!("plots/{}", url_path(&svg)),
                        png: format!("plots/{}", url_path(&png)),
                    }),
                    String::new(),
                ),
                Ok(n) => (
                    Some(PlotLinks {
                        svg: format!("plots/{}", url_path(&svg)),
                        png: format!("plots/{}", url_path(&png)),
                    }),
                    format!("{n} point(s) with a zero or non-finite value are not shown."),
                ),
                Err(e) => (None, format!("plot failed: {e:#}")),
            };
            out.push(KnobPlot {
                scene: scene.clone(),
                method: method.clone(),
                knob: resp.knob,
                plot,
                note,
            });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use harness::image::metrics::ErrorMetrics;

    fn record(order: i64, fit: &str, steps: i64, err: f64) -> Record {
        let mut params = BTreeMap::new();
        params.insert("order".into(), ParamValue::Int(order));
        params.insert("fit".into(), ParamValue::Text(fit.into()));
        params.insert("steps".into(), ParamValue::Int(steps));
        let mut errors = BTreeMap::new();
        errors.insert(
            "inscatter".to_string(),
            ErrorMetrics {
                rel_rmse: err,
                ..Default::default()
            },
        );
        Record {
            scene: "s".into(),
            method: "m".into(),
            params,
            status: Status::Ok,
            reason: None,
            ignored: vec![],
            timing: None,
            memory_bytes: None,
            passes: None,
            counters: BTreeMap::new(),
            errors,
            images: BTreeMap::new(),
            errors_per_frame: None,
            validation: Vec::new(),
        }
    }

    #[test]
    fn one_line_per_combination_of_the_other_varying_knobs() {
        // order × fit swept; steps constant (not part of any label).
        let recs: Vec<Record> = [2, 4, 6, 8]
            .iter()
            .flat_map(|&n| {
                [
                    record(n, "taylor", 64, 1.0 / n as f64),
                    record(n, "chebyshev", 64, 0.1 / (n * n) as f64),
                ]
            })
            .collect();
        let refs: Vec<&Record> = recs.iter().rev().collect();
        let r = responses(&refs);
        assert_eq!(r.len(), 1, "fit is text: only order gets a plot");
        assert_eq!(r[0].knob, "order");
        let labels: Vec<&str> = r[0].lines.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(labels.len(), 2);
        assert!(labels.contains(&"fit=taylor") && labels.contains(&"fit=chebyshev"));
        let taylor = &r[0]
            .lines
            .iter()
            .find(|(l, _)| l == "fit=taylor")
            .unwrap()
            .1;
        assert_eq!(
            taylor,
            &vec![(2.0, 0.5), (4.0, 0.25), (6.0, 1.0 / 6.0), (8.0, 0.125)]
        );
    }

    #[test]
    fn too_few_values_make_no_plot() {
        let recs = [record(2, "taylor", 64, 0.1), record(4, "taylor", 64, 0.05)];
        let refs: Vec<&Record> = recs.iter().collect();
        assert!(responses(&refs).is_empty());
        assert!(responses(&[]).is_empty());
    }
}
