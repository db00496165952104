//! The headline error and the figures beside it: the trimmed relative mean absolute error that
//! every verdict ranks by, the same error over a chosen set of pixels (the light's core), SMAPE
//! (a compared candidate kept in results.json), and the temporal-stability figure of a frame
//! sequence.
//!
//! **Headline** ([`HEADLINE_NAME`], "trimmed relative MAE"): with `d = t − r` per channel,
//! per pixel `e_p = Σ_c |d_c|` and `s_p = Σ_c |r_c|`, drop the `⌊TRIM_FRACTION · n⌋` pixels of
//! largest `e_p` (ties broken by pixel index, so it is deterministic), and over the kept set K
//!
//! ```text
//! headline = Σ_K e_p / Σ_K s_p
//! ```
//!
//! i.e. the mean absolute error as a fraction of the mean radiance, over the kept pixels. It is
//! a fraction (0.05 = 5 %), exactly 5 % for an image uniformly 5 % too bright whatever its
//! content, unchanged when both images are scaled by a constant, and no set of ⌊0.1 %⌋ pixels
//! can decide it: they are the ones it drops. Why L1 and not the trimmed relative RMSE,
//! relMSE, SMAPE or FLIP: docs/ARCHITECTURE.md §4.4, with the runs (a squared error concentrates in the
//! halo around a visible light, just outside any small trimmed set).
//!
//! A black reference over the kept pixels (`Σ_K s_p ≤ 1e-30`) has no relative error: the
//! headline is then the trimmed mean absolute error `Σ_K e_p / 3|K|` (0 when the test is black
//! too), like `rel_rmse`'s fallback.

use super::Image;

/// The headline's definition, recorded as `run.headline` in results.json.
pub const HEADLINE_NAME: &str = "trimmed-rel-mae-0.1%";

/// Fraction of pixels, those of largest absolute error, that the headline leaves out.
pub const TRIM_FRACTION: f64 = 1e-3;

/// Sums of absolute error and absolute reference over a set of pixels, channels summed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AbsSums {
    /// Σ |t − r| over the pixels (all three channels).
    pub error: f64,
    /// Σ |r| over the same pixels.
    pub reference: f64,
    /// Pixels summed.
    pub pixels: usize,
}

impl AbsSums {
    /// `error / reference`; the mean absolute error over the pixels when the reference is
    /// black there.
    pub fn relative(&self) -> f64 {
        if self.reference > 1e-30 {
            self.error / self.reference
        } else if self.pixels > 0 {
            self.error / (3 * self.pixels) as f64
        } else {
            0.0
        }
    }

    pub fn add(&mut self, other: AbsSums) {
        self.error += other.error;
        self.reference += other.reference;
        self.pixels += other.pixels;
    }
}

/// Per pixel `(Σ_c |d_c|, Σ_c |r_c|)` in f64. `diff` and `reference` must be the same size.
fn pixel_sums(diff: &Image, reference: &Image) -> Vec<(f64, f64)> {
    diff.pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(d, r)| {
            let abs = |v: &[f32; 3]| v.iter().map(|&c| (c as f64).abs()).sum::<f64>();
            (abs(d), abs(r))
        })
        .collect()
}

/// `t − r` per channel, in f32 from f64 differences (non-finite inputs must be sanitised first).
pub fn difference(test: &Image, reference: &Image) -> Image {
    Image {
        width: reference.width,
        height: reference.height,
        pixels: test
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(t, r)| [0, 1, 2].map(|c| (t[c] as f64 - r[c] as f64) as f32))
            .collect(),
    }
}

/// The sums over every pixel except the `⌊TRIM_FRACTION · n⌋` of largest `Σ_c |diff_c|`, where
/// `diff` is an error image (`t − r`, or a frame-to-frame change of it) and `reference` the
/// image its size is judged against.
pub fn trimmed_sums(diff: &Image, reference: &Image) -> AbsSums {
    let mut px: Vec<(usize, (f64, f64))> = pixel_sums(diff, reference)
        .into_iter()
        .enumerate()
        .collect();
    let n = px.len();
    let drop = (TRIM_FRACTION * n as f64).floor() as usize;
    if drop > 0 {
        // Largest error first; equal errors by pixel index, so the kept set is deterministic.
        let order = |a: &(usize, (f64, f64)), b: &(usize, (f64, f64))| {
            b.1.0.total_cmp(&a.1.0).then(a.0.cmp(&b.0))
        };
        px.select_nth_unstable_by(drop - 1, order);
    }
    let kept = &px[drop..];
    AbsSums {
        error: kept.iter().map(|p| p.1.0).sum(),
        reference: kept.iter().map(|p| p.1.1).sum(),
        pixels: kept.len(),
    }
}

/// The headline error of `test` against `reference` (module docs). Same size, finite inputs.
pub fn headline(test: &Image, reference: &Image) -> f64 {
    trimmed_sums(&difference(test, reference), reference).relative()
}

/// Relative MAE `Σ|t − r| / Σ|r|` over the pixels whose `mask` entry is true (no trimming);
/// None when the mask selects nothing.
pub fn masked_relative(test: &Image, reference: &Image, mask: &[bool]) -> Option<f64> {
    let mut s = AbsSums::default();
    for ((d, r), &m) in pixel_sums(&difference(test, reference), reference)
        .into_iter()
        .zip(mask)
    {
        if m {
            s.add(AbsSums {
                error: d,
                reference: r,
                pixels: 1,
            });
        }
    }
    (s.pixels > 0).then(|| s.relative())
}

/// SMAPE: mean over pixels and channels of `2|t − r| / (|t| + |r|)` (0 where both are 0).
/// Bounded by 2; dominated by dark pixels, where a tiny absolute error is a large ratio.
pub fn smape(test: &Image, reference: &Image) -> f64 {
    let n = 3 * reference.pixels.len();
    if n == 0 {
        return 0.0;
    }
    let sum: f64 = test
        .pixels
        .iter()
        .zip(&reference.pixels)
        .flat_map(|(t, r)| {
            (0..3).map(move |c| {
                let (a, b) = (t[c] as f64, r[c] as f64);
                let den = a.abs() + b.abs();
                if den > 0.0 {
                    2.0 * (a - b).abs() / den
                } else {
                    0.0
                }
            })
        })
        .sum();
    sum / n as f64
}

/// The temporal-stability figure of a sequence of scored frames, fed one frame at a time:
/// with `e_k = t_k − r_k` (the method's error at frame k against that frame's own reference),
///
/// ```text
/// temporal = Σ_k Σ_{K_k} |e_k − e_{k−1}| / Σ_k Σ_{K_k} |r_k|
/// ```
///
/// over consecutive pairs of scored frames, each pair trimmed like the headline (K_k drops the
/// ⌊0.1 %⌋ pixels of largest change). A method whose error does not change from frame to frame
/// (exact, or wrong the same way every frame: no flicker) scores 0, whatever its headline; noise
/// that changes every frame scores its mean frame-to-frame change relative to the mean radiance.
/// None until two frames have been pushed.
#[derive(Default)]
pub struct Temporal {
    previous_error: Option<Image>,
    sums: AbsSums,
    pairs: u32,
}

impl Temporal {
    /// Adds the next frame (test and its own reference; same size, finite).
    pub fn push(&mut self, test: &Image, reference: &Image) {
        let error = difference(test, reference);
        if let Some(prev) = &self.previous_error {
            let change = difference(&error, prev);
            self.sums.add(trimmed_sums(&change, reference));
            self.pairs += 1;
        }
        self.previous_error = Some(error);
    }

    /// The figure (a fraction), or None with fewer than two frames.
    pub fn value(&self) -> Option<f64> {
        (self.pairs > 0).then(|| self.sums.relative())
    }

    /// Consecutive pairs compared so far.
    pub fn pairs(&self) -> u32 {
        self.pairs
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Lcg;

    /// A smooth image with values spread over 0.05–1.1 (not constant: a uniform 5 % error must
    /// read 5 % whatever the content).
    fn pattern(w: u32, h: u32) -> Image {
        let mut img = Image::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
                let s = (u * 11.0).sin() * (v * 7.0).cos();
                img.set(x, y, [0.55 + 0.5 * s, 0.05 + u, 0.1 + 0.8 * v * v]);
            }
        }
        img
    }

    #[test]
    fn three_wild_pixels_cannot_decide_it() {
        // 64×64 = 4096 pixels: ⌊0.1 %⌋ = 4 dropped ≥ the 3 wrong ones.
        let reference = pattern(64, 64);
        let mut test = reference.clone();
        for (x, y) in [(3, 5), (40, 40), (63, 0)] {
            test.set(x, y, reference.get(x, y).map(|c| 1000.0 * c));
        }
        let h = headline(&test, &reference);
        assert!(h <= 0.01, "headline {h}");
        // The untrimmed relative MAE of the same images is large: the trim is what saves it.
        let all = masked_relative(&test, &reference, &vec![true; 4096]).unwrap();
        assert!(all > 0.3, "untrimmed {all}");
    }

    #[test]
    fn uniformly_five_percent_too_bright_is_five_percent() {
        let reference = pattern(64, 48);
        let mut test = reference.clone();
        for p in &mut test.pixels {
            *p = p.map(|c| 1.05 * c);
        }
        let h = headline(&test, &reference);
        assert!((h - 0.05).abs() <= 0.001, "headline {h}");
        // Scale invariance: both images ×1000 give the same figure.
        let scale = |img: &Image| Image {
            pixels: img.pixels.iter().map(|p| p.map(|c| 1000.0 * c)).collect(),
            ..img.clone()
        };
        let h2 = headline(&scale(&test), &scale(&reference));
        assert!((h - h2).abs() < 1e-6, "{h} vs {h2}");
        // SMAPE of the same pair is 2·0.05/2.05 = 4.88 %, not 5 % (why it is not the headline).
        let s = smape(&test, &reference);
        assert!((s - 0.1 / 2.05).abs() < 1e-5, "smape {s}");
    }

    #[test]
    fn black_reference_falls_back_to_mae() {
        let reference = Image::new(50, 50);
        assert_eq!(headline(&reference, &reference), 0.0);
        let mut test = reference.clone();
        test.pixels.fill([0.5; 3]);
        assert!((headline(&test, &reference) - 0.5).abs() < 1e-9);
    }

    #[test]
    fn temporal_is_zero_without_flicker_and_grows_with_noise() {
        let reference = pattern(48, 48);
        // A static method, 10 % too dark every frame: wrong, but steady.
        let steady: Image = Image {
            pixels: reference
                .pixels
                .iter()
                .map(|p| p.map(|c| 0.9 * c))
                .collect(),
            ..reference.clone()
        };
        let mut quiet = Temporal::default();
        assert_eq!(quiet.value(), None);
        for _ in 0..5 {
            quiet.push(&steady, &reference);
        }
        assert_eq!(quiet.value(), Some(0.0));
        assert_eq!(quiet.pairs(), 4);

        // The same method plus independent noise each frame (uniform, amplitude a).
        let noisy_run = |a: f32| {
            let mut rng = Lcg(7);
            let mut t = Temporal::default();
            for _ in 0..5 {
                let mut frame = steady.clone();
                for p in &mut frame.pixels {
                    *p = p.map(|c| c + a * (2.0 * rng.uniform() as f32 - 1.0));
                }
                t.push(&frame, &reference);
            }
            t.value().unwrap()
        };
        let (small, large) = (noisy_run(0.01), noisy_run(0.05));
        assert!(small > 0.0 && large > 2.0 * small, "{small} {large}");
    }
}
