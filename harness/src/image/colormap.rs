//! False-colour error maps for the report.
//!
//! Errors are shown through *viridis*, which is perceptually uniform (equal
//! steps in error look like equal steps in colour), monotonic in lightness
//! (readable in greyscale print) and colour-blind safe — unlike jet/rainbow,
//! which invent edges that are not in the data.
//!
//! The outputs are display-space images (sRGB-encoded values in `[0, 1]`),
//! meant for [`super::io::write_png_ldr`], not for further arithmetic.

use super::{Image, luminance_of};

/// Display colour for pixels whose error is not finite (NaN/Inf in either
/// image). White lies outside viridis (whose top is yellow), so such pixels
/// cannot be mistaken for "large but finite" errors.
pub const NONFINITE_COLOR: [f32; 3] = [1.0, 1.0, 1.0];

/// Viridis colour (sRGB-encoded, `[0, 1]`) for `t` in `[0, 1]` (clamped).
///
/// A degree-6 polynomial fit per channel to matplotlib's viridis table (Matt
/// Zucker's 2020 fit, shadertoy WlfXRN, CC0); it stays within ≈0.015 of the
/// 256-entry table, far below what anyone can read off an error map, and
/// avoids carrying the table around. NaN maps to the bottom of the scale.
pub fn viridis(t: f32) -> [f32; 3] {
    // Coefficients of 1, t, t², …, t⁶ for R, G and B.
    #[rustfmt::skip]
    const C: [[f32; 7]; 3] = [
        [0.277_727_33, 0.105_093_04, -0.330_861_83, -4.634_230_5, 6.228_27, 4.776_385, -5.435_456],
        [0.005_407_344_5, 1.404_613_5, 0.214_847_56, -5.799_101, 14.179_933, -13.745_145, 4.645_852_6],
        [0.334_099_8, 1.384_590_2, 0.095_095_16, -19.332_441, 56.690_55, -65.353_035, 26.312_435],
    ];
    // `clamp` would pass NaN through; send it to the bottom of the scale.
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    C.map(|c| {
        // Horner evaluation, highest power first.
        let v = c.iter().rev().fold(0.0f32, |acc, &k| acc * t + k);
        v.clamp(0.0, 1.0)
    })
}

/// Per-pixel error map: the luminance of the per-channel absolute difference
/// `|t - r|` (so pure chroma errors still show), divided by `scale` and
/// coloured with [`viridis`]. `scale` is the error shown at the top of the
/// colour bar; larger errors saturate. Pixels where either image is
/// non-finite become white ([`NONFINITE_COLOR`]).
///
/// Panics if the sizes differ, since callers always compare a method against
/// the reference of the same scene and resolution (a mismatch is a bug that
/// [`super::metrics::compare`] reports first).
pub fn error_map(test: &Image, reference: &Image, scale: f32) -> Image {
    assert_eq!(
        (test.width, test.height),
        (reference.width, reference.height),
        "error_map: test is {}x{}, reference is {}x{}",
        test.width,
        test.height,
        reference.width,
        reference.height
    );
    let pixels = test
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(t, r)| {
            if t.iter().chain(r).any(|c| !c.is_finite()) {
                return NONFINITE_COLOR;
            }
            let diff = [
                (t[0] - r[0]).abs(),
                (t[1] - r[1]).abs(),
                (t[2] - r[2]).abs(),
            ];
            let e = luminance_of(diff);
            let v = if scale > 0.0 {
                e / scale
            } else if e > 0.0 {
                // A zero/negative scale would divide by zero; show any error
                // as saturated and a perfect match as the bottom colour.
                1.0
            } else {
                0.0
            };
            viridis(v)
        })
        .collect();
    Image {
        width: test.width,
        height: test.height,
        pixels,
    }
}

/// A vertical colour bar for the legend of [`error_map`]: the top row is the
/// maximum (`scale`), the bottom row is zero, every column identical.
pub fn colorbar(height: u32, width: u32) -> Image {
    let mut img = Image::new(width, height);
    for y in 0..height {
        let t = if height > 1 {
            1.0 - y as f32 / (height - 1) as f32
        } else {
            1.0
        };
        let c = viridis(t);
        for x in 0..width {
            img.set(x, y, c);
        }
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
    }

    /// matplotlib's viridis sampled at t = 0, 1/8, …, 1 (8-bit sRGB).
    #[test]
    fn viridis_matches_matplotlib_table() {
        const TABLE: [[u8; 3]; 9] = [
            [68, 1, 84],
            [71, 44, 122],
            [59, 81, 139],
            [44, 113, 142],
            [33, 144, 141],
            [39, 173, 129],
            [92, 200, 99],
            [170, 220, 50],
            [253, 231, 37],
        ];
        for (i, rgb) in TABLE.iter().enumerate() {
            let t = i as f32 / 8.0;
            let expected = rgb.map(|c| c as f32 / 255.0);
            let got = viridis(t);
            assert!(close(got, expected, 0.02), "t={t}: {got:?} vs {expected:?}");
        }
        // Clamping outside [0, 1] and NaN.
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(f32::NAN), viridis(0.0));
    }

    #[test]
    fn viridis_lightness_is_monotonic() {
        // Viridis is designed with monotonically increasing lightness; a
        // mistyped coefficient would almost certainly break this.
        let mut prev = -1.0;
        for i in 0..=100 {
            let l = luminance_of(viridis(i as f32 / 100.0));
            assert!(l > prev, "luma not increasing at {i}: {l} <= {prev}");
            prev = l;
        }
    }

    #[test]
    fn error_map_scales_and_flags_nonfinite() {
        let reference = Image::new(4, 1);
        let mut test = reference.clone();
        test.set(1, 0, [0.5; 3]); // half of scale
        test.set(2, 0, [10.0; 3]); // saturates
        test.set(3, 0, [f32::NAN, 0.0, 0.0]);
        let m = error_map(&test, &reference, 1.0);
        assert_eq!(m.get(0, 0), viridis(0.0));
        assert!(close(m.get(1, 0), viridis(0.5), 1e-6));
        assert_eq!(m.get(2, 0), viridis(1.0));
        assert_eq!(m.get(3, 0), NONFINITE_COLOR);
        // Zero scale: any error saturates, none stays at the bottom.
        let z = error_map(&test, &reference, 0.0);
        assert_eq!(z.get(0, 0), viridis(0.0));
        assert_eq!(z.get(1, 0), viridis(1.0));
    }

    #[test]
    fn colorbar_top_is_max() {
        let bar = colorbar(11, 3);
        assert_eq!((bar.width, bar.height), (3, 11));
        assert_eq!(bar.get(0, 0), viridis(1.0));
        assert_eq!(bar.get(2, 10), viridis(0.0));
        assert!(close(bar.get(1, 5), viridis(0.5), 1e-6));
        assert_eq!(colorbar(1, 1).get(0, 0), viridis(1.0));
    }
}
