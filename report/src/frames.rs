//! Per-frame plots of an animated scene (issue 34): each method's in-scatter headline error and
//! frame time over the scene's frames, so lag after a cut, a spike on one frame or a cost that
//! grows with the view read at a glance instead of hiding in the sequence's mean.
//!
//! One line per method: its configuration of lowest mean headline over the frames (the
//! matrix's "best configuration", on the sequence's mean). Timed frames cycle through the
//! scene's frames, so a frame shown twice is the mean of its two measurements. x is the scene's
//! frame index (linear); y is log, since errors and times of the methods span decades.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Result, anyhow};
use harness::results::{FrameErrors, Record, Status};
use plotters::prelude::*;
use serde::Serialize;

use crate::format::{self, PlotLinks};
use crate::plot::{
    LEGEND_W, Line, SIZE, draw_empty, finish_lines, line_chart, log_axis, log_range, register_font,
    to_png_and_svg,
};

/// The per-frame plots of one scene (absent for static scenes).
#[derive(Serialize)]
pub struct FramesView {
    pub plots: Vec<FramePlot>,
    /// Which record each line is, and what the plots leave out.
    pub note: String,
}

#[derive(Serialize)]
pub struct FramePlot {
    pub alt: String,
    pub links: Option<PlotLinks>,
    pub note: String,
}

/// Each method's record of lowest mean in-scatter headline among those scored frame by frame.
fn lines_of<'a>(records: &[&'a Record]) -> Vec<&'a Record> {
    let mean = |r: &Record| {
        r.errors_per_frame
            .as_ref()
            .and_then(|e| e.mean.get("inscatter"))
            .map(|s| s.headline)
            .filter(|h| h.is_finite())
    };
    let mut best: BTreeMap<&str, &Record> = BTreeMap::new();
    for r in records.iter().filter(|r| r.status == Status::Ok) {
        let Some(h) = mean(r) else { continue };
        let better = best
            .get(r.method.as_str())
            .is_none_or(|b| mean(b).is_none_or(|bh| h < bh));
        if better {
            best.insert(r.method.as_str(), r);
        }
    }
    // In the run's order, as every other table and plot of the scene.
    let order = crate::analysis::ordered(records.iter().map(|r| r.method.as_str()));
    order
        .iter()
        .filter_map(|m| best.get(m.as_str()).copied())
        .collect()
}

/// The record's scored frames (none for a static scene).
fn frames(r: &Record) -> &[FrameErrors] {
    r.errors_per_frame
        .as_ref()
        .map(|e| e.frames.as_slice())
        .unwrap_or(&[])
}

/// (scene frame, value) per frame, a frame shown several times averaged.
fn per_frame(
    frames: &[FrameErrors],
    value: impl Fn(&FrameErrors) -> Option<f64>,
) -> Vec<(f64, f64)> {
    let mut sums: BTreeMap<u32, (f64, u32)> = BTreeMap::new();
    for f in frames {
        if let Some(v) = value(f).filter(|v| v.is_finite()) {
            let e = sums.entry(f.frame).or_default();
            (e.0, e.1) = (e.0 + v, e.1 + 1);
        }
    }
    sums.into_iter()
        .map(|(k, (s, n))| (k as f64, s / n as f64))
        .collect()
}

/// The scene's per-frame plots, written under `plots/` as `<anchor>.frames.{error,time}.*`;
/// `None` when no record of the scene was scored frame by frame.
pub fn view(
    records: &[&Record],
    scene: &str,
    anchor: &str,
    device: &str,
    plots: &Path,
) -> Option<FramesView> {
    let chosen = lines_of(records);
    if chosen.is_empty() {
        return None;
    }
    let gpu = chosen
        .iter()
        .all(|r| frames(r).iter().all(|f| f.gpu_ms.is_some()));
    let line = |r: &Record, value: &dyn Fn(&FrameErrors) -> Option<f64>| Line {
        name: r.method.clone(),
        points: per_frame(frames(r), value),
        fit: None,
    };
    let headline = |f: &FrameErrors| f.errors.get("inscatter").and_then(|m| m.headline);
    let time = |f: &FrameErrors| if gpu { f.gpu_ms } else { f.wall_ms };
    let error_lines: Vec<Line> = chosen.iter().map(|r| line(r, &headline)).collect();
    let time_lines: Vec<Line> = chosen.iter().map(|r| line(r, &time)).collect();
    let time_label = if gpu {
        "GPU time (ms)"
    } else {
        "wall time (ms)"
    };
    let plots = vec![
        plot(
            scene,
            "headline error, in-scatter",
            &error_lines,
            &format!("{anchor}.frames.error"),
            device,
            plots,
        ),
        plot(
            scene,
            time_label,
            &time_lines,
            &format!("{anchor}.frames.time"),
            device,
            plots,
        ),
    ];
    let note = format!(
        "One line per method: its configuration of lowest mean headline ({}). A frame shown more than once is the mean of its measurements.",
        chosen
            .iter()
            .map(|r| format!("{} {}", r.method, format::params_text(r)))
            .collect::<Vec<_>>()
            .join("; ")
    );
    Some(FramesView { plots, note })
}

fn plot(
    scene: &str,
    y_label: &str,
    lines: &[Line],
    stem: &str,
    device: &str,
    dir: &Path,
) -> FramePlot {
    let (png, svg) = (format!("{stem}.png"), format!("{stem}.svg"));
    let title = format!("{scene}: {y_label} per frame");
    let kept: Vec<Line> = lines
        .iter()
        .map(|l| Line {
            name: l.name.clone(),
            points: l.points.iter().copied().filter(|p| p.1 > 0.0).collect(),
            fit: None,
        })
        .collect();
    let left_out: usize = lines
        .iter()
        .zip(&kept)
        .map(|(a, b)| a.points.len() - b.points.len())
        .sum();
    let drawn = draw_both(
        &title,
        y_label,
        device,
        &kept,
        &dir.join(&png),
        &dir.join(&svg),
    );
    let mut note = String::new();
    if left_out > 0 {
        note = format!("{left_out} frame(s) with zero value cannot be shown on a log axis.");
    }
    let links = match drawn {
        Ok(()) => Some(PlotLinks {
            svg: format!("plots/{}", format::url_path(&svg)),
            png: format!("plots/{}", format::url_path(&png)),
        }),
        Err(e) => {
            note = format!("plot failed: {e:#}");
            None
        }
    };
    FramePlot {
        alt: title,
        links,
        note,
    }
}

fn draw_both(
    title: &str,
    y_label: &str,
    device: &str,
    lines: &[Line],
    png: &Path,
    svg: &Path,
) -> Result<()> {
    register_font();
    to_png_and_svg!(png, svg, |root| draw(root, title, y_label, device, lines));
    Ok(())
}

/// Linear frame axis, log value axis.
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    y_label: &str,
    device: &str,
    lines: &[Line],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (plot_area, legend_area) = root.split_horizontally(SIZE.0 - LEGEND_W);
    let all = || lines.iter().flat_map(|l| l.points.iter());
    let last = all().map(|p| p.0).fold(0.0f64, f64::max).max(1.0);
    let Some(y) = log_range(all().map(|p| p.1)) else {
        return draw_empty(&root, "no scored frame to plot");
    };
    let mut chart =
        line_chart(&plot_area, title).build_cartesian_2d(-0.5..last + 0.5, log_axis(y))?;
    let x_desc = format!("frame (times: {device})");
    let x_tick = |v: &f64| format!("{v:.0}");
    finish_lines(
        &root,
        &mut chart,
        &legend_area,
        (&x_desc, y_label),
        &x_tick,
        lines,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(frame: u32, v: f64) -> FrameErrors {
        FrameErrors {
            frame,
            errors: Default::default(),
            wall_ms: Some(v),
            gpu_ms: None,
        }
    }

    #[test]
    fn a_frame_shown_twice_is_the_mean_of_its_measurements_in_frame_order() {
        let frames = [
            frame(2, 4.0),
            frame(0, 1.0),
            frame(2, 6.0),
            frame(1, f64::NAN),
        ];
        let pts = per_frame(&frames, |f| f.wall_ms);
        assert_eq!(pts, vec![(0.0, 1.0), (2.0, 5.0)]);
    }
}
