//! FLIP (Andersson et al. 2020, LDR) of two 8-bit sRGB images, computed in horizontal strips
//! on the cores.
//!
//! `nv_flip` runs NVIDIA's C++ FLIP on one thread, and at 512² it is most of a record's scoring
//! time (≈ 85 ms of ≈ 200 ms per image pair). Every stage of FLIP is local: a separable spatial
//! filter of radius [`spatial_radius`], a pointwise colour difference, a separable feature
//! filter of radius [`feature_radius`] and a pointwise combination, with edge-clamped borders.
//! So a strip of rows, extended by [`halo`] rows of the image on each side where the image has
//! them, gives exactly the whole image's error values on its own rows: the filters of those
//! rows never reach the strip's clamped edge. The stitched error map equals the whole image's
//! bit for bit (`flip_tests.rs`), and its mean is summed in row-major order whatever the number
//! of strips, so no figure depends on the machine's core count.

use rayon::prelude::*;

/// FLIP's pixels per degree: 67, about 0.7 m from a 0.7 m wide 4K monitor (FLIP's default).
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// Rows of a strip's own, before the halo; fewer rows per strip would spend more on halos.
const MIN_STRIP_ROWS: usize = 128;

/// FLIP's spatial (CSF) filter radius in pixels: `ceil(3·sqrt(b_max / (2π²))·ppd)` with the
/// largest Gaussian scale parameter b_max = 0.04 (FLIP's `calculateSpatialFilterRadius`).
pub fn spatial_radius(ppd: f32) -> usize {
    let pi_sq = std::f32::consts::PI * std::f32::consts::PI;
    (3.0 * (0.04f32 / (2.0 * pi_sq)).sqrt() * ppd).ceil() as usize
}

/// FLIP's edge and point filter radius in pixels: `ceil(3σ)`, σ = ½·w·ppd with w = 0.082.
pub fn feature_radius(ppd: f32) -> usize {
    (3.0 * 0.5 * 0.082f32 * ppd).ceil() as usize
}

/// Rows a strip needs beyond its own on each side: the wider filter's radius, plus one for
/// rounding in the constants above.
pub fn halo(ppd: f32) -> usize {
    spatial_radius(ppd).max(feature_radius(ppd)) + 1
}

/// The per-pixel FLIP error map (row-major, `w·h` values) of `test` against `reference`, both
/// tightly packed 8-bit sRGB RGB, computed in `strips` horizontal strips (1: the whole image
/// at once; more than the rows allow are reduced).
pub fn flip_map(test: &[u8], reference: &[u8], w: usize, h: usize, strips: usize) -> Vec<f32> {
    strip_map(test, reference, (w, h), strips, halo(PIXELS_PER_DEGREE))
}

/// [`flip_map`] with strips extended by `halo` rows (the tests show a smaller halo is wrong).
fn strip_map(
    test: &[u8],
    reference: &[u8],
    (w, h): (usize, usize),
    strips: usize,
    halo: usize,
) -> Vec<f32> {
    let strips = strips.clamp(1, h.max(1));
    let rows_per = h.div_ceil(strips);
    let parts: Vec<Vec<f32>> = (0..strips)
        .into_par_iter()
        .map(|s| {
            let (y0, y1) = (s * rows_per, ((s + 1) * rows_per).min(h));
            if y0 >= y1 {
                return Vec::new();
            }
            let (top, bottom) = (y0.saturating_sub(halo), (y1 + halo).min(h));
            let band = top * w * 3..bottom * w * 3;
            let (sw, sh) = (w as u32, (bottom - top) as u32);
            let err = nv_flip::flip(
                nv_flip::FlipImageRgb8::with_data(sw, sh, &reference[band.clone()]),
                nv_flip::FlipImageRgb8::with_data(sw, sh, &test[band]),
                PIXELS_PER_DEGREE,
            )
            .to_vec();
            err[(y0 - top) * w..(y1 - top) * w].to_vec()
        })
        .collect();
    parts.concat()
}

/// Strips for an image of `h` rows on this machine: one per two rayon threads (the three
/// AOVs of a record are compared at once), each at least [`MIN_STRIP_ROWS`] rows.
pub fn strips_for(h: usize) -> usize {
    (rayon::current_num_threads() / 2).clamp(1, (h / MIN_STRIP_ROWS).max(1))
}

/// Mean of the FLIP error map, summed in f64 in row-major order.
pub fn flip_mean(test: &[u8], reference: &[u8], w: usize, h: usize) -> f64 {
    let map = flip_map(test, reference, w, h, strips_for(h));
    map.iter().map(|&e| e as f64).sum::<f64>() / map.len() as f64
}

#[cfg(test)]
#[path = "flip_tests.rs"]
mod tests;
