//! Drift of the floor within a run (ARCHITECTURE §4.6): the tune times the same floor (each
//! scene's no-scatter, before every frame of every configuration) hundreds of times. Where the
//! adapter's speed trends (the H200 of `docs/results/nvidia-h200-2026-11-27-frontier-512/`,
//! where identical work slowed by up to 5.5× as a scene's records went on) or jumps, the
//! tune says so. Its ratios are paired frame by frame and stay valid; the figures say how far
//! an unpaired time from the same run would be off.
//!
//! The trend is the Theil–Sen slope of ln(floor time) over run time (the median of the pairwise
//! slopes: a few wild frames cannot tilt it; pairs straddling the largest step are left out, so
//! a step is not read as a trend), given per minute and over the samples' span. The
//! jump is the largest change of the median of the de-trended ln times between the samples
//! before and after one instant (each side at least a tenth of them, and 5).

use serde::{Deserialize, Serialize};

/// A trend over the span larger than this (±10 %) is flagged.
pub const TREND_FLAG: f64 = 0.10;
/// A jump larger than this (±25 %) is flagged.
pub const JUMP_FLAG: f64 = 0.25;
/// Fewer samples than this give no drift figure.
pub const MIN_SAMPLES: usize = 12;
/// At most this many samples, evenly spaced, enter the O(n²) slope.
const MAX_SLOPE_SAMPLES: usize = 1500;

/// A series' drift.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Drift {
    pub samples: usize,
    /// Seconds from the first sample to the last.
    pub span_s: f64,
    /// Relative change per minute (0.02: 2 % slower each minute).
    pub trend_per_min: f64,
    /// Relative change over the span (exp(slope · span) − 1).
    pub trend_total: f64,
    /// The largest step: its time (s from the first sample) and relative size.
    pub jump_at_s: f64,
    pub jump: f64,
    /// Whether the trend or the jump exceeds its flag.
    pub flagged: bool,
}

/// The drift of `samples` (seconds since the run started, time ms), in time order; None below
/// [`MIN_SAMPLES`] or for a zero span.
pub fn detect(samples: &[(f64, f64)]) -> Option<Drift> {
    let pts: Vec<(f64, f64)> = samples
        .iter()
        .filter(|(t, ms)| t.is_finite() && *ms > 0.0 && ms.is_finite())
        .map(|&(t, ms)| (t, ms.ln()))
        .collect();
    let n = pts.len();
    let span = pts.last()?.0 - pts.first()?.0;
    if n < MIN_SAMPLES || span <= 0.0 {
        return None;
    }
    // A step would read as a trend to a slope fitted across it: the slope takes only pairs on
    // the same side of the largest raw step, and the step is then measured de-trended.
    let raw: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let (split, _) = largest_step(&raw);
    let slope = theil_sen(&thin(&pts, MAX_SLOPE_SAMPLES), pts[split].0);
    let t0 = pts[0].0;
    let residual: Vec<f64> = pts.iter().map(|&(t, y)| y - slope * (t - t0)).collect();
    let (jump_at, jump) = largest_step(&residual);
    let trend_total = (slope * span).exp() - 1.0;
    let jump = jump.exp() - 1.0;
    Some(Drift {
        samples: n,
        span_s: span,
        trend_per_min: (slope * 60.0).exp() - 1.0,
        trend_total,
        jump_at_s: pts[jump_at].0 - t0,
        jump,
        flagged: trend_total.abs() > TREND_FLAG || jump.abs() > JUMP_FLAG,
    })
}

/// At most `max` of `pts`, evenly spaced.
fn thin(pts: &[(f64, f64)], max: usize) -> Vec<(f64, f64)> {
    if pts.len() <= max {
        return pts.to_vec();
    }
    (0..max).map(|i| pts[i * pts.len() / max]).collect()
}

/// The median of the slopes between all pairs of distinct times on the same side of `split`
/// (a time).
fn theil_sen(pts: &[(f64, f64)], split: f64) -> f64 {
    let mut slopes = Vec::with_capacity(pts.len() * pts.len() / 2);
    for (i, a) in pts.iter().enumerate() {
        for b in &pts[i + 1..] {
            if b.0 != a.0 && (a.0 < split) == (b.0 < split) {
                slopes.push((b.1 - a.1) / (b.0 - a.0));
            }
        }
    }
    median(&mut slopes).unwrap_or(0.0)
}

/// The split index and the change of median (after − before) of largest size.
fn largest_step(y: &[f64]) -> (usize, f64) {
    let side = (y.len() / 10).max(5);
    let mut best = (0, 0.0f64);
    for i in side..=y.len().saturating_sub(side) {
        let before = median(&mut y[..i].to_vec()).unwrap_or(0.0);
        let after = median(&mut y[i..].to_vec()).unwrap_or(0.0);
        if (after - before).abs() > best.1.abs() {
            best = (i, after - before);
        }
    }
    best
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Noise of ±3 % from a fixed sequence (no randomness).
    fn wobble(i: usize) -> f64 {
        1.0 + 0.03 * ((i * 7919 % 13) as f64 / 6.0 - 1.0)
    }

    #[test]
    fn a_steady_floor_is_not_flagged() {
        let s: Vec<(f64, f64)> = (0..200).map(|i| (i as f64, 20.0 * wobble(i))).collect();
        let d = detect(&s).unwrap();
        assert!(!d.flagged, "{d:?}");
        assert!(d.trend_total.abs() < 0.02 && d.jump.abs() < 0.05, "{d:?}");
    }

    /// The H200 pattern: identical work slowing steadily, 2× over 10 minutes.
    #[test]
    fn a_trend_is_flagged_with_its_size() {
        let s: Vec<(f64, f64)> = (0..300)
            .map(|i| {
                let t = i as f64 * 2.0;
                (t, 20.0 * 2f64.powf(t / 600.0) * wobble(i))
            })
            .collect();
        let d = detect(&s).unwrap();
        assert!(d.flagged);
        // 2^(598/600) − 1 over the span; 2^(60/600) − 1 per minute.
        assert!(
            (d.trend_total - (2f64.powf(598.0 / 600.0) - 1.0)).abs() < 0.05,
            "{d:?}"
        );
        assert!(
            (d.trend_per_min - (2f64.powf(0.1) - 1.0)).abs() < 0.01,
            "{d:?}"
        );
    }

    #[test]
    fn a_jump_is_flagged_where_it_happened() {
        let s: Vec<(f64, f64)> = (0..200)
            .map(|i| (i as f64, if i < 120 { 20.0 } else { 30.0 } * wobble(i)))
            .collect();
        let d = detect(&s).unwrap();
        assert!(d.flagged, "{d:?}");
        assert!((d.jump - 0.5).abs() < 0.08, "{d:?}");
        assert!((d.jump_at_s - 120.0).abs() <= 3.0, "{d:?}");
        assert!(detect(&s[..5]).is_none());
    }
}
