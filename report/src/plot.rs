//! Time-vs-error Pareto plots (log-log), drawn with plotters to PNG and SVG.
//!
//! One colour per method: every configuration of its sweep is a marker and the method's
//! own Pareto front is a line through its best trade-offs; the scene's overall front is a
//! dashed black line. Text uses the bundled DejaVu Sans (fonts/), registered once with
//! plotters' ab_glyph backend, so the PNG looks the same on every machine and needs no
//! system fonts.

use std::path::Path;
use std::sync::Once;

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::analysis::{Point, pareto_front};

static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");
pub(crate) const FAMILY: &str = "sans-serif";

pub(crate) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bundled file is a valid TTF; failing here would be a packaging bug, and the
        // plot then reports a font error rather than panicking.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// A method's points, in any order.
pub struct Series<'a> {
    pub name: &'a str,
    pub points: Vec<Point>,
}

/// Tableau-10: distinguishable, colour-blind tolerant for the first few series.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

pub const SIZE: (u32, u32) = (720, 480);

/// A log axis range covering `values` (all > 0), padded by a factor on each side so markers
/// are not clipped; a single value gets a decade around it.
pub(crate) fn log_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return None;
    }
    Some((lo / 1.5, hi * 1.5))
}

/// What a Pareto plot shows besides its points.
pub struct ParetoLabels<'a> {
    pub title: &'a str,
    /// Time axis title with its unit.
    pub x: &'a str,
    /// Error axis title.
    pub y: &'a str,
    /// The adapter the times come from (printed under the time axis).
    pub device: &'a str,
}

/// Draws the plot to `png` and `svg`. Points with non-positive time or error cannot sit on a
/// log axis and are left out; returns how many were left out.
pub fn pareto(labels: &ParetoLabels, series: &[Series], png: &Path, svg: &Path) -> Result<usize> {
    register_font();
    let positive = |p: &&Point| p.time > 0.0 && p.error > 0.0;
    let shown: Vec<Series> = series
        .iter()
        .map(|s| Series {
            name: s.name,
            points: s.points.iter().filter(positive).copied().collect(),
        })
        .collect();
    let total: usize = series.iter().map(|s| s.points.len()).sum();
    let kept: usize = shown.iter().map(|s| s.points.len()).sum();
    to_png_and_svg!(png, svg, |root| draw(root, labels, &shown));
    Ok(total - kept)
}

/// Width (px) of the legend column right of the data area.
pub(crate) const LEGEND_W: u32 = 190;

/// Draws one plot twice, to the PNG `$png` and the SVG `$svg`: `$draw` is called with each
/// backend's root area (a closure, expanded once per backend so each gets its own type).
macro_rules! to_png_and_svg {
    ($png:expr, $svg:expr, $draw:expr) => {{
        {
            let root = BitMapBackend::new($png, SIZE).into_drawing_area();
            ($draw)(root).map_err(|e| anyhow!("drawing {}: {e}", $png.display()))?;
        }
        let root = SVGBackend::new($svg, SIZE).into_drawing_area();
        ($draw)(root).map_err(|e| anyhow!("drawing {}: {e}", $svg.display()))?;
    }};
}
pub(crate) use to_png_and_svg;

/// Writes `message` where a plot has nothing to draw.
pub(crate) fn draw_empty<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    message: &str,
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.draw(&Text::new(message, (20, 40), (FAMILY, 16).into_font()))?;
    root.present()?;
    Ok(())
}

/// The chart of a plot of lines: its caption and the room for the axes' labels.
pub(crate) fn line_chart<'a, 'b, DB: DrawingBackend>(
    plot_area: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(plot_area);
    builder
        .caption(title, (FAMILY, 16))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64);
    builder
}

/// A plot of lines after its chart is built: the mesh (axis titles, tick labels, a light grid;
/// `x_tick` formats the x labels, the y labels are log ticks), the lines with their legend,
/// and the root presented.
pub(crate) fn finish_lines<DB, X, Y>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    legend_area: &DrawingArea<DB, plotters::coord::Shift>,
    (x_desc, y_desc): (&str, &str),
    x_tick: &dyn Fn(&f64) -> String,
    lines: &[Line],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style((FAMILY, 13))
        .axis_desc_style((FAMILY, 14))
        .x_label_formatter(x_tick)
        .y_label_formatter(&|v| fmt_tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    draw_lines(chart, legend_area, lines)?;
    root.present()?;
    Ok(())
}

/// Binds `$e` to a hollow marker of shape `$i` (circle, square, triangle, diamond, plus, x,
/// repeating) at `$c` and evaluates `$body`: hollow so coincident points of different methods
/// stay visible through each other. A macro because each shape is its own element type.
macro_rules! with_marker {
    ($i:expr, $c:expr, $style:expr, $e:ident => $body:expr) => {{
        let (c, st) = ($c, $style);
        match $i % 6 {
            0 => {
                let $e = EmptyElement::at(c) + Circle::new((0, 0), 5, st);
                $body
            }
            1 => {
                let $e = EmptyElement::at(c) + Rectangle::new([(-4, -4), (4, 4)], st);
                $body
            }
            2 => {
                let $e = EmptyElement::at(c)
                    + PathElement::new(vec![(0, -6), (5, 4), (-5, 4), (0, -6)], st);
                $body
            }
            3 => {
                let $e = EmptyElement::at(c)
                    + PathElement::new(vec![(0, -6), (6, 0), (0, 6), (-6, 0), (0, -6)], st);
                $body
            }
            4 => {
                let $e = EmptyElement::at(c)
                    + PathElement::new(vec![(-6, 0), (6, 0)], st)
                    + PathElement::new(vec![(0, -6), (0, 6)], st);
                $body
            }
            _ => {
                let $e = EmptyElement::at(c)
                    + PathElement::new(vec![(-5, -5), (5, 5)], st)
                    + PathElement::new(vec![(-5, 5), (5, -5)], st);
                $body
            }
        }
    }};
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    labels: &ParetoLabels,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (plot_area, legend_area) = root.split_horizontally(SIZE.0 - LEGEND_W);
    let all = || series.iter().flat_map(|s| s.points.iter());
    let (Some(x), Some(y)) = (
        log_range(all().map(|p| p.time)),
        log_range(all().map(|p| p.error)),
    ) else {
        root.draw(&Text::new(
            "no timed, scored record to plot",
            (20, 40),
            (FAMILY, 16).into_font(),
        ))?;
        root.present()?;
        return Ok(());
    };
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(labels.title, (FAMILY, 16))
        .margin(10)
        .x_label_area_size(58)
        .y_label_area_size(64)
        // plotters' own log key points start at the first power of ten inside the range, so
        // a range within one decade would get no labels; give it 1-2-5 ticks instead.
        .build_cartesian_2d(log_axis(x), log_axis(y))?;
    chart
        .configure_mesh()
        .x_desc(format!("{} on {}", labels.x, labels.device))
        .y_desc(labels.y)
        .label_style((FAMILY, 13))
        .axis_desc_style((FAMILY, 12))
        .x_label_formatter(&|v| fmt_tick(*v))
        .y_label_formatter(&|v| fmt_tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    // The device on the time axis; the caveat under the legend (the axis has no room left).
    for (k, line) in ["times compare only", "within this run"].iter().enumerate() {
        legend_area.draw(&Text::new(
            line.to_string(),
            (4, (SIZE.1 - 60) as i32 + 16 * k as i32),
            (FAMILY, 12).into_font().color(&RGBColor(90, 90, 90)),
        ))?;
    }

    // The scene's overall front under the points, so the markers stay on top.
    let everything: Vec<Point> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .collect();
    let front: Vec<(f64, f64)> = pareto_front(&everything)
        .iter()
        .map(|p| (p.time, p.error))
        .collect();
    chart.draw_series(DashedLineSeries::new(
        front.clone(),
        6,
        4,
        BLACK.stroke_width(1),
    ))?;
    chart.draw_series(
        front
            .iter()
            .map(|&(t, e)| Circle::new((t, e), 9, RGBColor(0, 0, 0).mix(0.5).stroke_width(1))),
    )?;
    // Colours and shapes follow the method's position in the list so they stay stable
    // across scenes; methods without a plottable point get no legend entry.
    let mut legend_y = 28;
    for (i, s) in series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.points.is_empty())
    {
        let color = PALETTE[i % PALETTE.len()];
        let own_front: Vec<(f64, f64)> = pareto_front(&s.points)
            .iter()
            .map(|p| (p.time, p.error))
            .collect();
        chart.draw_series(LineSeries::new(own_front, color.mix(0.6).stroke_width(1)))?;
        for p in &s.points {
            with_marker!(i, (p.time, p.error), color.stroke_width(2), e => {
                chart.draw_series(std::iter::once(e))?;
            });
        }
        with_marker!(i, (12, legend_y), color.stroke_width(2), e => legend_area.draw(&e)?);
        legend_area.draw(&Text::new(
            s.name.to_string(),
            (26, legend_y - 7),
            (FAMILY, 13).into_font(),
        ))?;
        legend_y += 22;
    }
    legend_area.draw(&PathElement::new(
        vec![(4, legend_y), (22, legend_y)],
        BLACK.stroke_width(1),
    ))?;
    legend_area.draw(&Text::new(
        "Pareto front (all)",
        (26, legend_y - 7),
        (FAMILY, 13).into_font(),
    ))?;
    root.present()?;
    Ok(())
}

/// One line of a log–log scaling plot: measured (x, y) points and an optional power-law fit,
/// drawn dashed over the points' x range.
pub struct Line<'a> {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub fit: Option<&'a crate::fit::Fit>,
}

/// Draws y vs x on log–log axes (one colour per line, markers at the measurements, the fit
/// dashed) to `png` and `svg`. Non-positive points are left out; returns how many.
pub fn loglog(
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line],
    png: &Path,
    svg: &Path,
) -> Result<usize> {
    register_font();
    let total: usize = lines.iter().map(|l| l.points.len()).sum();
    let shown: Vec<Line> = lines
        .iter()
        .map(|l| Line {
            name: l.name.clone(),
            points: l
                .points
                .iter()
                .copied()
                .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
                .collect(),
            fit: l.fit,
        })
        .collect();
    let kept: usize = shown.iter().map(|l| l.points.len()).sum();
    to_png_and_svg!(png, svg, |root| draw_loglog(
        root, title, x_label, y_label, &shown
    ));
    Ok(total - kept)
}

fn draw_loglog<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let (plot_area, legend_area) = root.split_horizontally(SIZE.0 - LEGEND_W);
    let all = || lines.iter().flat_map(|l| l.points.iter());
    let (Some(x), Some(y)) = (log_range(all().map(|p| p.0)), log_range(all().map(|p| p.1))) else {
        return draw_empty(&root, "no timed record to plot");
    };
    let mut chart = line_chart(&plot_area, title).build_cartesian_2d(log_axis(x), log_axis(y))?;
    let x_tick = |v: &f64| fmt_tick(*v);
    finish_lines(
        &root,
        &mut chart,
        &legend_area,
        (x_label, y_label),
        &x_tick,
        lines,
    )
}

/// Draws each line (markers joined in x order, the fit dashed) in its palette colour, with its
/// legend entry; shared by every plot of lines whatever its axes' scales.
pub(crate) fn draw_lines<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    legend_area: &DrawingArea<DB, plotters::coord::Shift>,
    lines: &[Line],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    for (i, l) in lines
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.points.is_empty())
    {
        let color = PALETTE[i % PALETTE.len()];
        let mut pts = l.points.clone();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?;
        for &p in &pts {
            with_marker!(i, p, color.stroke_width(2), e => {
                chart.draw_series(std::iter::once(e))?;
            });
        }
        let y = 28 + 22 * i as i32;
        with_marker!(i, (12, y), color.stroke_width(2), e => legend_area.draw(&e)?);
        legend_area.draw(&Text::new(
            l.name.clone(),
            (26, y - 7),
            (FAMILY, 12).into_font(),
        ))?;
        if let (Some(f), Some(a), Some(b)) = (l.fit, pts.first(), pts.last()) {
            let fit: Vec<(f64, f64)> = [a.0, b.0].iter().map(|&x| (x, f.eval(x))).collect();
            chart.draw_series(DashedLineSeries::new(fit, 5, 4, color.stroke_width(1)))?;
        }
    }
    Ok(())
}

/// A log axis over `range` (as [`log_range`] gives it) with the house ticks: 1-2-5 or decades
/// labelled ([`log_ticks`]), the rest of each decade as light grid lines.
pub(crate) fn log_axis(
    (lo, hi): (f64, f64),
) -> plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>> {
    (lo..hi)
        .log_scale()
        .with_key_points(log_ticks(lo, hi))
        .with_light_points(log_minor(lo, hi))
}

/// Tick values for a log axis over `[lo, hi]` (0 < lo < hi): 1-2-5 per decade when the range
/// spans at most three decades, else powers of ten (every k-th one to stay under ~10 labels).
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let (d0, d1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let decades = d1 - d0;
    let mantissas: &[f64] = if decades <= 3 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let step = (decades / 10 + 1).max(1);
    let mut out = Vec::new();
    for d in (d0..=d1).filter(|d| (d - d0) % step == 0) {
        for m in mantissas {
            let v = m * 10f64.powi(d);
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
    }
    out
}

/// Minor grid lines: 1..9 × every power of ten inside `[lo, hi]`.
pub(crate) fn log_minor(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let (d0, d1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (d0..=d1)
        .flat_map(|d| (1..10).map(move |m| m as f64 * 10f64.powi(d)))
        .filter(|v| *v >= lo && *v <= hi)
        .collect()
}

/// Tick labels: plain decimals in the usual range, scientific notation outside it.
pub(crate) fn fmt_tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e4).contains(&a) {
        format!("{v:.0e}")
    } else if a >= 10.0 {
        format!("{v:.0}")
    } else if a >= 1.0 {
        format!("{v:.1}")
    } else {
        // Enough digits to keep one significant figure.
        let digits = (-a.log10()).ceil() as usize;
        format!("{v:.digits$}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_range_pads_and_ignores_non_positive() {
        let (lo, hi) = log_range([0.0, -1.0, 2.0, 8.0, f64::NAN].into_iter()).unwrap();
        assert!((lo - 2.0 / 1.5).abs() < 1e-12 && (hi - 12.0).abs() < 1e-12);
        assert!(log_range([0.0, -2.0].into_iter()).is_none());
    }

    #[test]
    fn log_ticks_label_every_range() {
        // Within one decade: 1-2-5 values inside, never empty.
        assert_eq!(log_ticks(12.0, 90.0), vec![20.0, 50.0]);
        let t = log_ticks(9.0, 870.0);
        assert_eq!(t, vec![10.0, 20.0, 50.0, 100.0, 200.0, 500.0]);
        // Many decades: powers of ten only.
        let t = log_ticks(3e-4, 4.0);
        assert_eq!(t.len(), 4);
        assert!(
            t.iter()
                .zip([1e-3, 1e-2, 1e-1, 1.0])
                .all(|(a, b)| (a / b - 1.0).abs() < 1e-12)
        );
        // Twenty decades: thinned to at most ~11 labels.
        assert!(log_ticks(1e-10, 1e10).len() <= 11);
        assert!(log_ticks(0.0, 1.0).is_empty() && log_ticks(2.0, 1.0).is_empty());
        assert_eq!(log_minor(15.0, 45.0), vec![20.0, 30.0, 40.0]);
    }

    #[test]
    fn tick_labels_keep_a_significant_digit() {
        assert_eq!(fmt_tick(0.05), "0.05");
        assert_eq!(fmt_tick(0.2), "0.2");
        assert_eq!(fmt_tick(3.0), "3.0");
        assert_eq!(fmt_tick(20.0), "20");
        assert_eq!(fmt_tick(1e-5), "1e-5");
    }
}
