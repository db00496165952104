//! Error metrics between a method's image and the CPU reference, and the
//! tone map that turns linear radiance into display values.
//!
//! Two families of metrics are computed by [`compare`]:
//!
//! * **HDR metrics** (`headline`, `rmse`, `rel_rmse`, `rel_mse`, `mae`, `p99_abs`,
//!   `max_abs`, `smape`) on the linear radiance, over every pixel and all three
//!   channels. These are what a renderer engineer means by "error".
//! * **Perceptual metrics** (`psnr`, `ssim`, `flip_mean`) on the *tone-mapped*
//!   images in `[0, 1]`. Both images go through the **same** [`ToneMap`], which
//!   is normally chosen once per scene from the reference with
//!   [`ToneMap::auto`], so that every method is judged under identical display
//!   conditions.
//!
//! Non-finite values: a test pixel with any NaN/±Inf channel is counted once
//! in [`ErrorMetrics::nonfinite`], and its non-finite channels are replaced by
//! 0 before *all* other metrics are computed, so a broken image still gets
//! finite (and usually terrible) numbers instead of poisoning averages with
//! NaN. Non-finite reference values (which would be a reference-renderer bug)
//! are likewise treated as 0 but are not counted.

use super::{Image, luminance_of};
use rayon::prelude::*;
use std::borrow::Cow;

/// Regulariser, relative to `mean(reference)²`, in the denominator of
/// [`ErrorMetrics::rel_mse`]. It keeps near-black reference pixels from
/// dominating the average (the same role as the `1e-2` in pbrt's/Mitsuba's
/// relMSE), while staying scale-invariant: multiplying both images by a
/// constant leaves `rel_mse` unchanged.
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// PSNR reported for identical (or nearly identical) LDR images, in dB.
pub const PSNR_CAP_DB: f64 = 100.0;

/// SSIM stabilisation constants for a dynamic range L = 1 (Wang et al. 2004).
const SSIM_C1: f64 = 0.01 * 0.01;
const SSIM_C2: f64 = 0.03 * 0.03;
/// Standard SSIM window: 11×11 Gaussian, σ = 1.5.
const SSIM_RADIUS: usize = 5;
const SSIM_SIGMA: f64 = 1.5;

/// Error of a test image against a reference; see [`compare`] for the exact
/// definitions.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ErrorMetrics {
    /// `sqrt(mean((t - r)²))` on linear radiance.
    pub rmse: f64,
    /// `rmse / mean(r)`; equals `rmse` when `mean(r) ≤ 1e-30`.
    pub rel_rmse: f64,
    /// `mean((t - r)² / (r² + REL_MSE_EPSILON·mean(r)² + 1e-30))`.
    pub rel_mse: f64,
    /// `mean(|t - r|)`.
    pub mae: f64,
    /// 99th percentile (nearest rank) of `|t - r|`.
    pub p99_abs: f64,
    /// `max(|t - r|)`.
    pub max_abs: f64,
    /// `10·log10(1 / mse)` of the tone-mapped images, capped at 100 dB.
    pub psnr: f64,
    /// Mean SSIM of the luma of the tone-mapped images (11×11 Gaussian window).
    pub ssim: f64,
    /// Mean NVIDIA FLIP (LDR) error of the tone-mapped 8-bit images.
    pub flip_mean: f64,
    /// Number of test pixels with at least one non-finite channel.
    pub nonfinite: u64,
    /// The headline error, a fraction: relative MAE with the 0.1 % worst pixels left out
    /// ([`super::headline`], named by `run.headline`). Absent in results written before it.
    #[serde(default)]
    pub headline: Option<f64>,
    /// Symmetric mean absolute percentage error, a fraction in [0, 2] (a headline candidate
    /// that lost: [`super::headline::smape`]).
    #[serde(default)]
    pub smape: Option<f64>,
    /// Relative MAE over the light-core pixels (`crate::verdict::light_core_mask`), set by the
    /// runner; null when no light is in view.
    #[serde(default)]
    pub light_core: Option<f64>,
    /// The temporal-stability figure over the record's scored frames
    /// ([`super::headline::Temporal`]); absent with fewer than two frames and in per-frame entries.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temporal: Option<f64>,
    /// `mean(t) / mean(r)` over every pixel and channel: 1 when the method's image carries the
    /// reference's energy (a constant-factor error reads as that factor); null when the
    /// reference's mean is ≤ 1e-30. Absent in results written before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_ratio: Option<f64>,
    /// Frames of lag over the record's shown frames ([`super::lag`]): how many frames late the
    /// images match the references best (0 … 3); absent with fewer than two frames.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lag_frames: Option<f64>,
    /// The frame-to-frame change of the error not explained by the lag ([`super::lag`]), a
    /// fraction of the mean radiance; absent with fewer than two frames (or no pair of frames
    /// reaching back the lag).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flicker: Option<f64>,
}

/// Linear radiance → display sRGB in `[0, 1]`: exposure, per-channel
/// Reinhard `x / (1 + x)`, then the sRGB OETF.
///
/// Reinhard never clips, so HDR highlights (bright media near lights) keep
/// some contrast in the LDR metrics instead of all methods saturating to the
/// same white.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ToneMap {
    /// Exposure in stops: radiance is multiplied by `2^exposure`.
    pub exposure: f32,
}

impl Default for ToneMap {
    fn default() -> Self {
        Self { exposure: 0.0 }
    }
}

/// Luminance that [`ToneMap::auto`] maps the reference's 95th percentile to,
/// before Reinhard (0.8 → 0.44 after Reinhard → ≈0.70 after sRGB encoding,
/// leaving headroom above for the brightest 5 %).
pub const AUTO_EXPOSURE_TARGET: f32 = 0.8;

impl ToneMap {
    /// Display colour of a pixel with a NaN/Inf channel: magenta, which no
    /// physically plausible scattering result produces, so bugs stand out.
    pub const NONFINITE_COLOR: [f32; 3] = [1.0, 0.0, 1.0];

    /// Tone-maps one linear RGB triple to display sRGB in `[0, 1]`.
    ///
    /// Negative radiance (possible from noisy or buggy estimators) is clamped
    /// to 0 before Reinhard, whose pole at −1 would otherwise explode.
    pub fn apply(&self, linear: [f32; 3]) -> [f32; 3] {
        if linear.iter().any(|c| !c.is_finite()) {
            return Self::NONFINITE_COLOR;
        }
        let scale = self.exposure.exp2();
        linear.map(|c| {
            let x = (c * scale).max(0.0);
            // Finite radiance times a large exposure can overflow to +Inf,
            // whose Reinhard limit is 1 (Inf/Inf would be NaN).
            let reinhard = if x.is_finite() { x / (1.0 + x) } else { 1.0 };
            srgb_oetf(reinhard).clamp(0.0, 1.0)
        })
    }

    /// Tone-maps a whole image into display space (values in `[0, 1]`).
    pub fn apply_image(&self, img: &Image) -> Image {
        Image {
            width: img.width,
            height: img.height,
            pixels: img.pixels.par_iter().map(|&p| self.apply(p)).collect(),
        }
    }

    /// Tone-maps and quantises to tightly packed 8-bit sRGB (RGBRGB…), the
    /// layout of PNG rows and of `nv_flip::FlipImageRgb8`.
    pub fn to_srgb8(&self, img: &Image) -> Vec<u8> {
        img.pixels
            .par_iter()
            .flat_map_iter(|&p| self.apply(p).map(quantize_u8))
            .collect()
    }

    /// Chooses an exposure from the reference image so that its
    /// 95th-percentile luminance (nearest rank, over finite pixels) maps to
    /// [`AUTO_EXPOSURE_TARGET`] = 0.8 before Reinhard.
    ///
    /// The 95th percentile rather than the maximum keeps a few fireflies or a
    /// directly visible light from darkening the whole image. If that
    /// percentile is 0 (a mostly black frame, e.g. a thin beam in a dark
    /// room) the percentile is taken over the non-zero pixels instead; an
    /// all-black reference gets exposure 0. The exposure is clamped to
    /// ±64 stops so `2^exposure` stays a normal f32.
    ///
    /// Build this **once per scene** and pass the same object to every
    /// [`compare`] and PNG export for that scene.
    pub fn auto(reference: &Image) -> ToneMap {
        let mut lum: Vec<f32> = reference
            .pixels
            .iter()
            .map(|&p| luminance_of(p))
            .filter(|l| l.is_finite())
            .collect();
        let mut p95 = nearest_rank_f32(&mut lum, 0.95).unwrap_or(0.0);
        if p95 <= 0.0 {
            lum.retain(|&l| l > 0.0);
            p95 = nearest_rank_f32(&mut lum, 0.95).unwrap_or(0.0);
        }
        if p95 <= 0.0 {
            return ToneMap::default();
        }
        let exposure = (AUTO_EXPOSURE_TARGET / p95).log2().clamp(-64.0, 64.0);
        ToneMap { exposure }
    }
}

/// The sRGB opto-electronic transfer function (linear → encoded), IEC 61966-2-1.
///
/// Evaluated in f64 so that 1.0 encodes to exactly 1.0 (in f32,
/// `1.055 - 0.055` rounds to 0.99999994).
#[inline]
pub fn srgb_oetf(x: f32) -> f32 {
    let x = x as f64;
    let y = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    y as f32
}

/// Display value in `[0, 1]` → 8-bit code, rounding to nearest (NaN → 0).
#[inline]
pub fn quantize_u8(v: f32) -> u8 {
    // `as u8` saturates and maps NaN to 0, so no extra checks are needed.
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// Nearest-rank percentile (`q` in `(0, 1]`) of `values`, reordering them.
fn nearest_rank_f32(values: &mut [f32], q: f64) -> Option<f32> {
    let i = nearest_rank_index(values.len(), q)?;
    Some(*values.select_nth_unstable_by(i, f32::total_cmp).1)
}

/// Zero-based index of the nearest-rank percentile: rank = ceil(q·n), 1-based.
fn nearest_rank_index(n: usize, q: f64) -> Option<usize> {
    if n == 0 {
        return None;
    }
    let rank = (q * n as f64).ceil() as usize;
    Some(rank.clamp(1, n) - 1)
}

/// Replaces non-finite channels by 0; returns the number of pixels affected.
/// Borrows when the image is clean (the common case) to avoid a copy.
fn sanitize(img: &Image) -> (Cow<'_, Image>, u64) {
    let bad = img
        .pixels
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite()))
        .count() as u64;
    if bad == 0 {
        return (Cow::Borrowed(img), 0);
    }
    let mut clean = img.clone();
    for p in &mut clean.pixels {
        for c in p.iter_mut() {
            if !c.is_finite() {
                *c = 0.0;
            }
        }
    }
    (Cow::Owned(clean), bad)
}

/// Compares `test` against `reference`; see [`ErrorMetrics`] and the module
/// docs for the definitions and the treatment of non-finite values.
///
/// `tone` is used for the perceptual metrics (PSNR, SSIM, FLIP) on both
/// images. Returns `Err` if the sizes differ or the images are empty.
pub fn compare(test: &Image, reference: &Image, tone: &ToneMap) -> Result<ErrorMetrics, String> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(format!(
            "image size mismatch: test is {}x{}, reference is {}x{}",
            test.width, test.height, reference.width, reference.height
        ));
    }
    if test.is_empty() {
        return Err(format!(
            "cannot compare empty images ({}x{})",
            test.width, test.height
        ));
    }
    for (name, img) in [("test", test), ("reference", reference)] {
        if img.pixels.len() != img.width as usize * img.height as usize {
            return Err(format!(
                "{name} image claims {}x{} but holds {} pixels",
                img.width,
                img.height,
                img.pixels.len()
            ));
        }
    }

    let (test, nonfinite) = sanitize(test);
    let (reference, _) = sanitize(reference);
    let (test, reference) = (test.as_ref(), reference.as_ref());

    let mut m = hdr_metrics(test, reference);
    m.nonfinite = nonfinite;

    let (w, h) = (test.width as usize, test.height as usize);
    let test_ldr = tone.apply_image(test);
    let ref_ldr = tone.apply_image(reference);

    // PSNR on the unquantised display values, so it is not limited by 8-bit
    // rounding for good methods.
    let sq: f64 = test_ldr
        .pixels
        .iter()
        .zip(&ref_ldr.pixels)
        .flat_map(|(t, r)| (0..3).map(move |c| (t[c] as f64 - r[c] as f64).powi(2)))
        .sum();
    let mse_ldr = sq / (3 * w * h) as f64;
    m.psnr = if mse_ldr > 0.0 {
        (10.0 * (1.0 / mse_ldr).log10()).min(PSNR_CAP_DB)
    } else {
        PSNR_CAP_DB
    };

    let luma =
        |img: &Image| -> Vec<f64> { img.pixels.iter().map(|&p| luminance_of(p) as f64).collect() };
    m.ssim = ssim_luma(&luma(&test_ldr), &luma(&ref_ldr), w, h);

    // Quantise the already tone-mapped images (identical to
    // `tone.to_srgb8`, without paying for the sRGB `powf` twice).
    let srgb8 =
        |img: &Image| -> Vec<u8> { img.pixels.iter().flat_map(|p| p.map(quantize_u8)).collect() };
    m.flip_mean = super::flip::flip_mean(&srgb8(&test_ldr), &srgb8(&ref_ldr), w, h);
    Ok(m)
}

/// The linear-radiance metrics (everything but psnr/ssim/flip/nonfinite).
/// Inputs must be finite and the same size.
fn hdr_metrics(test: &Image, reference: &Image) -> ErrorMetrics {
    let n = 3 * test.pixels.len();
    let mean_r = reference.mean();
    let rel_eps = REL_MSE_EPSILON * mean_r * mean_r + 1e-30;

    let mut abs_diff = Vec::with_capacity(n);
    let (mut sum_sq, mut sum_abs, mut sum_rel, mut max_abs) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (t, r) in test.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            // Differences in f64: f32 subtraction would round away small
            // errors on bright pixels.
            let (tc, rc) = (t[c] as f64, r[c] as f64);
            let d = tc - rc;
            let a = d.abs();
            sum_sq += d * d;
            sum_abs += a;
            sum_rel += d * d / (rc * rc + rel_eps);
            max_abs = max_abs.max(a);
            abs_diff.push(a);
        }
    }
    let nf = n as f64;
    let rmse = (sum_sq / nf).sqrt();
    let p99_abs = nearest_rank_index(n, 0.99)
        .map(|i| *abs_diff.select_nth_unstable_by(i, f64::total_cmp).1)
        .unwrap_or(0.0);
    ErrorMetrics {
        rmse,
        rel_rmse: if mean_r > 1e-30 { rmse / mean_r } else { rmse },
        rel_mse: sum_rel / nf,
        mae: sum_abs / nf,
        p99_abs,
        max_abs,
        headline: Some(super::headline::headline(test, reference)),
        smape: Some(super::headline::smape(test, reference)),
        mean_ratio: (mean_r > 1e-30).then(|| test.mean() / mean_r),
        ..ErrorMetrics::default()
    }
}

/// Normalised 1-D Gaussian taps for the SSIM window.
fn ssim_kernel() -> [f64; 2 * SSIM_RADIUS + 1] {
    let mut k = [0.0; 2 * SSIM_RADIUS + 1];
    for (i, w) in k.iter_mut().enumerate() {
        let d = i as f64 - SSIM_RADIUS as f64;
        *w = (-d * d / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp();
    }
    let s: f64 = k.iter().sum();
    k.map(|w| w / s)
}

/// Separable Gaussian blur, same size as the input. Near the border the
/// window is truncated to the image and renormalised (rather than the
/// reference MATLAB code's "valid" cropping), so every pixel contributes and
/// images smaller than the window still get a meaningful SSIM.
fn gaussian_blur(src: &[f64], w: usize, h: usize) -> Vec<f64> {
    let k = ssim_kernel();
    let r = SSIM_RADIUS as isize;
    // Because the truncated window is a rectangle and the kernel separable,
    // normalising each 1-D pass separately equals normalising the 2-D sum.
    let tap = |len: usize, i: usize, get: &dyn Fn(usize) -> f64| -> f64 {
        let (mut acc, mut wsum) = (0.0, 0.0);
        for (j, &kw) in k.iter().enumerate() {
            let p = i as isize + j as isize - r;
            if p >= 0 && (p as usize) < len {
                acc += kw * get(p as usize);
                wsum += kw;
            }
        }
        acc / wsum
    };

    let mut horiz = vec![0.0; w * h];
    horiz
        .par_chunks_mut(w)
        .zip(src.par_chunks(w))
        .for_each(|(out, row)| {
            for (x, o) in out.iter_mut().enumerate() {
                *o = tap(w, x, &|p| row[p]);
            }
        });
    let mut out = vec![0.0; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, o) in row.iter_mut().enumerate() {
            *o = tap(h, y, &|p| horiz[p * w + x]);
        }
    });
    out
}

/// Mean SSIM (Wang et al. 2004) of two single-channel images in `[0, 1]`,
/// with an 11×11 Gaussian window (σ = 1.5), C1 = 0.01², C2 = 0.03².
///
/// The formula is evaluated so that swapping `a` and `b` gives a bit-identical
/// result (all operations involved are commutative in IEEE arithmetic).
fn ssim_luma(a: &[f64], b: &[f64], w: usize, h: usize) -> f64 {
    let prod = |x: &[f64], y: &[f64]| -> Vec<f64> { x.iter().zip(y).map(|(p, q)| p * q).collect() };
    let mu_a = gaussian_blur(a, w, h);
    let mu_b = gaussian_blur(b, w, h);
    let e_aa = gaussian_blur(&prod(a, a), w, h);
    let e_bb = gaussian_blur(&prod(b, b), w, h);
    let e_ab = gaussian_blur(&prod(a, b), w, h);
    let sum: f64 = (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (ma, mb) = (mu_a[i], mu_b[i]);
            let var_a = e_aa[i] - ma * ma;
            let var_b = e_bb[i] - mb * mb;
            let cov = e_ab[i] - ma * mb;
            ((2.0 * ma * mb + SSIM_C1) * (2.0 * cov + SSIM_C2))
                / ((ma * ma + mb * mb + SSIM_C1) * (var_a + var_b + SSIM_C2))
        })
        .collect::<Vec<f64>>()
        // Summed in order: a parallel f64 sum depends on how work was split, and the same
        // images must always score the same (resumed and merged runs are compared exactly).
        .iter()
        .sum();
    sum / (w * h) as f64
}

#[cfg(test)]
#[path = "metrics_tests.rs"]
mod tests;
