//! Lag and flicker: the temporal figure split into what a method shows late and what it changes
//! from frame to frame for no reason (ARCHITECTURE §4.4; issue 34).
//!
//! Fed the timed frames in the order they were shown (test image, that frame's reference), it
//! compares each frame's image with the references of the current and earlier frames,
//! r(k − λ) for a lag λ in [0, [`MAX_LAG_FRAMES`]] on a grid of [`LAG_STEPS_PER_FRAME`] steps a
//! frame, with r between two shown frames interpolated linearly:
//!
//! ```text
//! M(λ)    = Σ_k Σ_{K} |t_k − r(k − λ)|  /  Σ_k Σ_{K} |r_k|         over frames k ≥ Λ
//! lag     = argmin_λ M(λ)   (the smallest λ within 1e-6 of the minimum; refined by a parabola
//!                            through the grid minimum and its neighbours)
//! flicker = Σ_k Σ_{K} |e_k − e_{k−1}| / Σ_k Σ_{K} |r_k|,  e_k = t_k − r(k − λ*)
//! ```
//!
//! Λ = min([`MAX_LAG_FRAMES`], frames − 1) so every λ is judged on the same frames; K trims each
//! sum like the headline; λ* is the grid lag nearest `lag`. A method exact every frame reads 0
//! and 0; one that shows frame k − 1 exactly reads lag 1 and flicker 0; fresh noise every frame
//! reads lag ≈ 0 and flicker > 0 (its error matches no earlier frame better). On a static scene
//! every λ matches alike, so lag is 0 and flicker is the plain temporal figure.

use std::borrow::Cow;
use std::collections::VecDeque;

use super::Image;
use super::headline::{AbsSums, difference, trimmed_sums};

/// The longest lag looked for, in frames.
pub const MAX_LAG_FRAMES: usize = 3;
/// Grid steps per frame of lag (λ = j / this).
pub const LAG_STEPS_PER_FRAME: usize = 4;
const GRID: usize = MAX_LAG_FRAMES * LAG_STEPS_PER_FRAME + 1;

/// What one shown frame adds, per grid lag j (None where fewer than λ_j earlier frames exist).
struct FrameSums {
    /// Σ_K |t_k − r(k − λ_j)| with Σ_K |r_k|.
    matched: [Option<AbsSums>; GRID],
    /// Σ_K |e_k(λ_j) − e_{k−1}(λ_j)| with Σ_K |r_k| (None on the first frame λ_j allows).
    change: [Option<AbsSums>; GRID],
}

/// Lag and flicker of one AOV over a record's shown frames.
#[derive(Default)]
pub struct LagFlicker {
    /// The last MAX_LAG_FRAMES + 1 references, newest last.
    references: VecDeque<Image>,
    /// e_{k−1}(λ_j) per grid lag.
    previous_errors: Vec<Option<Image>>,
    frames: Vec<FrameSums>,
}

/// A shown frame's lag figures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LagFigures {
    /// Frames of lag (0 … MAX_LAG_FRAMES).
    pub lag_frames: f64,
    /// The frame-to-frame change of the error left once the lag is accounted for (a fraction of
    /// the mean radiance); None where no pair of frames reaches back that far.
    pub flicker: Option<f64>,
}

fn lag_of(j: usize) -> f64 {
    j as f64 / LAG_STEPS_PER_FRAME as f64
}

impl LagFlicker {
    /// Adds the next shown frame (test and its own reference; same size, finite).
    pub fn push(&mut self, test: &Image, reference: &Image) {
        self.references.push_back(reference.clone());
        if self.references.len() > MAX_LAG_FRAMES + 1 {
            self.references.pop_front();
        }
        if self.previous_errors.is_empty() {
            self.previous_errors = vec![None; GRID];
        }
        let shown = self.frames.len();
        let mut sums = FrameSums {
            matched: [None; GRID],
            change: [None; GRID],
        };
        for j in 0..GRID {
            if lag_of(j) > shown as f64 {
                self.previous_errors[j] = None;
                continue;
            }
            let error = difference(test, &self.reference_at(lag_of(j)));
            sums.matched[j] = Some(trimmed_sums(&error, reference));
            if let Some(previous) = &self.previous_errors[j] {
                sums.change[j] = Some(trimmed_sums(&difference(&error, previous), reference));
            }
            self.previous_errors[j] = Some(error);
        }
        self.frames.push(sums);
    }

    /// r(k − λ) for the newest frame k, linear between the two shown frames around it (a shown
    /// frame's reference itself, not a copy, at whole lags).
    fn reference_at(&self, lag: f64) -> Cow<'_, Image> {
        let newest = self.references.len() - 1;
        let (whole, frac) = (lag.floor() as usize, (lag - lag.floor()) as f32);
        let later = &self.references[newest - whole];
        if frac == 0.0 {
            return Cow::Borrowed(later);
        }
        let earlier = &self.references[newest - whole - 1];
        Cow::Owned(Image {
            width: later.width,
            height: later.height,
            pixels: later
                .pixels
                .iter()
                .zip(&earlier.pixels)
                .map(|(a, b)| [0, 1, 2].map(|c| (1.0 - frac) * a[c] + frac * b[c]))
                .collect(),
        })
    }

    /// The figures, or None with fewer than two shown frames.
    pub fn value(&self) -> Option<LagFigures> {
        let n = self.frames.len();
        if n < 2 {
            return None;
        }
        let reach = MAX_LAG_FRAMES.min(n - 1);
        let grid = reach * LAG_STEPS_PER_FRAME + 1;
        let total = |field: fn(&FrameSums) -> &[Option<AbsSums>; GRID], j: usize, from: usize| {
            let mut s = AbsSums::default();
            let mut any = false;
            for f in &self.frames[from..] {
                if let Some(x) = field(f)[j] {
                    s.add(x);
                    any = true;
                }
            }
            any.then(|| s.relative())
        };
        let matched: Vec<f64> = (0..grid)
            .map(|j| total(|f| &f.matched, j, reach).expect("every lag up to the reach"))
            .collect();
        let best = matched.iter().copied().fold(f64::INFINITY, f64::min);
        let j = matched
            .iter()
            .position(|&m| m <= best + 1e-6 * best.abs().max(1e-30))
            .expect("a minimum");
        let lag_frames = lag_of(j) + refine(&matched, j) / LAG_STEPS_PER_FRAME as f64;
        Some(LagFigures {
            lag_frames,
            flicker: total(|f| &f.change, j, 0),
        })
    }
}

/// The vertex offset (in grid steps, within ±½) of the parabola through the grid minimum j and
/// its neighbours; 0 at either end of the grid or where the three are not convex.
fn refine(m: &[f64], j: usize) -> f64 {
    if j == 0 || j + 1 >= m.len() {
        return 0.0;
    }
    let (a, b, c) = (m[j - 1], m[j], m[j + 1]);
    let curvature = a - 2.0 * b + c;
    if curvature <= 0.0 {
        return 0.0;
    }
    (0.5 * (a - c) / curvature).clamp(-0.5, 0.5)
}

#[cfg(test)]
#[path = "lag_tests.rs"]
mod tests;
