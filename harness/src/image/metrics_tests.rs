//! Tests of `metrics.rs`.

use super::*;

use crate::testing::Lcg;

/// A smooth, structured scene-like image with values around 0.1–1.
fn pattern(w: u32, h: u32) -> Image {
    let mut img = Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let u = x as f32 / w as f32;
            let v = y as f32 / h as f32;
            let s = (u * 12.0).sin() * (v * 9.0).cos();
            img.set(x, y, [0.5 + 0.4 * s, 0.3 + 0.5 * u, 0.2 + 0.6 * v * v]);
        }
    }
    img
}

fn with_noise(base: &Image, amplitude: f64, seed: u64) -> Image {
    let mut rng = Lcg(seed);
    let mut out = base.clone();
    for p in &mut out.pixels {
        for c in p.iter_mut() {
            *c += (amplitude * rng.gaussian()) as f32;
        }
    }
    out
}

#[test]
fn identical_images_are_perfect() {
    let img = pattern(40, 30);
    let tone = ToneMap::auto(&img);
    let m = compare(&img, &img, &tone).unwrap();
    assert_eq!(m.rmse, 0.0);
    assert_eq!(m.rel_rmse, 0.0);
    assert_eq!(m.rel_mse, 0.0);
    assert_eq!(m.mae, 0.0);
    assert_eq!(m.p99_abs, 0.0);
    assert_eq!(m.max_abs, 0.0);
    assert_eq!(m.psnr, 100.0);
    assert!((m.ssim - 1.0).abs() <= 1e-9, "ssim = {}", m.ssim);
    assert!(m.flip_mean < 1e-6, "flip = {}", m.flip_mean);
    assert_eq!(m.nonfinite, 0);
}

#[test]
fn constant_offset() {
    // Values that are exact binary fractions, so t - r is exactly the
    // offset and the expected numbers are exact.
    let mut reference = Image::new(8, 4);
    for (i, p) in reference.pixels.iter_mut().enumerate() {
        let v = (i % 7) as f32 * 0.125 + 0.5;
        *p = [v, 2.0 * v, 0.25 * v];
    }
    let offset = 0.25f32;
    let mut test = reference.clone();
    for p in &mut test.pixels {
        for c in p.iter_mut() {
            *c += offset;
        }
    }
    let m = compare(&test, &reference, &ToneMap::default()).unwrap();
    assert_eq!(m.rmse, 0.25);
    assert_eq!(m.mae, 0.25);
    assert_eq!(m.max_abs, 0.25);
    assert_eq!(m.p99_abs, 0.25);
    let mean_r: f64 = reference
        .pixels
        .iter()
        .flat_map(|p| p.iter().map(|&c| c as f64))
        .sum::<f64>()
        / (3.0 * 32.0);
    assert!((m.rel_rmse - 0.25 / mean_r).abs() < 1e-12);
}

#[test]
fn rel_mse_on_constant_reference() {
    // r = 2 everywhere, t = 2.5: each term is 0.25 / (4 + 0.01·4).
    let mut reference = Image::new(3, 3);
    reference.pixels.fill([2.0; 3]);
    let mut test = reference.clone();
    test.pixels.fill([2.5; 3]);
    let m = compare(&test, &reference, &ToneMap::default()).unwrap();
    assert!((m.rel_mse - 0.25 / 4.04).abs() < 1e-12, "{}", m.rel_mse);
    assert!((m.rel_rmse - 0.25).abs() < 1e-12);
}

#[test]
fn hand_computed_2x2() {
    let reference = Image {
        width: 2,
        height: 2,
        pixels: vec![[1.0; 3], [2.0; 3], [0.0; 3], [4.0; 3]],
    };
    // Per-channel differences:
    //   (+0.5, -0.5, 0), (+1, 0, 0), (0, 0, +2), (-1, 0, 0)
    let test = Image {
        width: 2,
        height: 2,
        pixels: vec![
            [1.5, 0.5, 1.0],
            [3.0, 2.0, 2.0],
            [0.0, 0.0, 2.0],
            [3.0, 4.0, 4.0],
        ],
    };
    let m = compare(&test, &reference, &ToneMap::default()).unwrap();
    // Σ|d| = 0.5+0.5+1+2+1 = 5 over 12 values; Σd² = 0.25+0.25+1+4+1 = 6.5.
    assert!((m.mae - 5.0 / 12.0).abs() < 1e-15);
    assert!((m.rmse - (6.5f64 / 12.0).sqrt()).abs() < 1e-15);
    assert_eq!(m.max_abs, 2.0);
    // Nearest rank ceil(0.99·12) = 12 → the largest value.
    assert_eq!(m.p99_abs, 2.0);
    // mean(r) = (3 + 6 + 0 + 12) / 12 = 1.75.
    assert!((m.rel_rmse - (6.5f64 / 12.0).sqrt() / 1.75).abs() < 1e-15);
    // Σt = 3 + 7 + 2 + 11 = 23 over Σr = 21.
    assert!((m.mean_ratio.unwrap() - 23.0 / 21.0).abs() < 1e-15);
}

#[test]
fn mean_ratio_reads_a_constant_factor_and_is_null_on_a_black_reference() {
    let reference = pattern(16, 12);
    let mut test = reference.clone();
    for p in &mut test.pixels {
        *p = p.map(|c| 2.5 * c);
    }
    let m = compare(&test, &reference, &ToneMap::default()).unwrap();
    assert!(
        (m.mean_ratio.unwrap() - 2.5).abs() < 1e-6,
        "{:?}",
        m.mean_ratio
    );
    let black = Image::new(16, 12);
    assert_eq!(
        compare(&test, &black, &ToneMap::default())
            .unwrap()
            .mean_ratio,
        None
    );
}

#[test]
fn p99_nearest_rank() {
    // 10×10 image, red differences 0, 1, …, 99; green/blue exact.
    // 300 values sorted: 201 zeros, then 1..=99. Rank ceil(0.99·300) =
    // 297 → zero-based index 296 → value 296 − 200 = 96.
    let reference = Image::new(10, 10);
    let mut test = reference.clone();
    for (i, p) in test.pixels.iter_mut().enumerate() {
        p[0] = i as f32;
    }
    let m = compare(&test, &reference, &ToneMap::default()).unwrap();
    assert_eq!(m.p99_abs, 96.0);
    assert_eq!(m.max_abs, 99.0);
    // All-black reference → rel_rmse falls back to rmse.
    assert_eq!(m.rel_rmse, m.rmse);
}

#[test]
fn nonfinite_pixels_are_counted_and_metrics_stay_finite() {
    let reference = pattern(16, 16);
    let mut test = reference.clone();
    test.set(0, 0, [f32::NAN, 0.5, 0.5]);
    test.set(3, 4, [f32::INFINITY, f32::NEG_INFINITY, 0.0]);
    test.set(15, 15, [f32::NAN; 3]);
    let m = compare(&test, &reference, &ToneMap::auto(&reference)).unwrap();
    assert_eq!(m.nonfinite, 3);
    for (name, v) in [
        ("rmse", m.rmse),
        ("rel_rmse", m.rel_rmse),
        ("rel_mse", m.rel_mse),
        ("mae", m.mae),
        ("p99_abs", m.p99_abs),
        ("max_abs", m.max_abs),
        ("psnr", m.psnr),
        ("ssim", m.ssim),
        ("flip_mean", m.flip_mean),
    ] {
        assert!(v.is_finite(), "{name} = {v}");
    }
    // The bad pixels were treated as 0, so the error is non-zero.
    assert!(m.rmse > 0.0 && m.psnr < 100.0 && m.ssim < 1.0);
    // Every other value matches, so the worst absolute error is the
    // largest reference value among the zeroed channels.
    let zeroed = [
        reference.get(0, 0)[0],
        reference.get(3, 4)[0],
        reference.get(3, 4)[1],
        reference.get(15, 15)[0],
        reference.get(15, 15)[1],
        reference.get(15, 15)[2],
    ];
    let expected = zeroed.iter().fold(0.0f32, |a, &b| a.max(b.abs()));
    assert_eq!(m.max_abs, expected as f64);
}

#[test]
fn ssim_of_constant_images_matches_closed_form() {
    // Zero variance everywhere: SSIM = (2ab + C1) / (a² + b² + C1).
    let (w, h) = (13, 9);
    let a = vec![0.3; w * h];
    let b = vec![0.6; w * h];
    let expected = (2.0 * 0.3 * 0.6 + SSIM_C1) / (0.09 + 0.36 + SSIM_C1);
    let got = ssim_luma(&a, &b, w, h);
    assert!((got - expected).abs() < 1e-12, "{got} vs {expected}");
}

#[test]
fn ssim_of_checkerboard_vs_flat_matches_closed_form() {
    // Unit-amplitude checkerboard a ∈ {0, 1} against its mean b = 0.5.
    // With b flat, cov = 0 and SSIM = (2·μa·0.5 + C1)·C2 /
    // ((μa² + 0.25 + C1)(σa² + C2)), with μa = 0.5, σa² = 0.25 for an
    // ideal window. A σ = 1.5 Gaussian almost perfectly averages the
    // period-2 pattern (its response at Nyquist is ~1e-5), and only the
    // truncated windows in the corners deviate, hence the small slack.
    let (w, h) = (64, 64);
    let a: Vec<f64> = (0..w * h).map(|i| ((i % w + i / w) % 2) as f64).collect();
    let b = vec![0.5; w * h];
    let expected = (0.5 + SSIM_C1) * SSIM_C2 / ((0.5 + SSIM_C1) * (0.25 + SSIM_C2));
    let got = ssim_luma(&a, &b, w, h);
    assert!((got - expected).abs() < 1e-6, "{got} vs {expected}");
}

#[test]
fn ssim_decreases_with_noise_and_is_symmetric() {
    let reference = pattern(64, 48);
    let tone = ToneMap::auto(&reference);
    let mut previous = 1.0 + 1e-12;
    for amplitude in [0.003, 0.01, 0.03, 0.1, 0.3] {
        let noisy = with_noise(&reference, amplitude, 12345);
        let m = compare(&noisy, &reference, &tone).unwrap();
        assert!(
            m.ssim < previous,
            "ssim {} at amplitude {amplitude} not below {previous}",
            m.ssim
        );
        previous = m.ssim;

        let swapped = compare(&reference, &noisy, &tone).unwrap();
        assert!((m.ssim - swapped.ssim).abs() <= 1e-9);
        // The symmetric HDR metrics must not care about the order either.
        assert!((m.rmse - swapped.rmse).abs() <= 1e-12);
        assert!((m.psnr - swapped.psnr).abs() <= 1e-9);
    }
    assert!(
        previous < 0.9,
        "heavy noise should hurt SSIM a lot: {previous}"
    );
}

#[test]
fn flip_grows_with_perturbation() {
    let reference = pattern(48, 48);
    let tone = ToneMap::auto(&reference);
    let small = compare(&with_noise(&reference, 0.02, 7), &reference, &tone).unwrap();
    let big = compare(&with_noise(&reference, 0.2, 7), &reference, &tone).unwrap();
    assert!(small.flip_mean > 0.0);
    assert!(
        big.flip_mean > small.flip_mean,
        "big {} vs small {}",
        big.flip_mean,
        small.flip_mean
    );
    assert!(big.flip_mean <= 1.0);
}

#[test]
fn size_mismatch_is_an_error() {
    let err = compare(&Image::new(4, 3), &Image::new(3, 4), &ToneMap::default()).unwrap_err();
    assert!(err.contains("4x3") && err.contains("3x4"), "{err}");
    assert!(compare(&Image::new(0, 0), &Image::new(0, 0), &ToneMap::default()).is_err());
}

#[test]
fn tone_map_values() {
    let t = ToneMap::default();
    assert_eq!(t.apply([0.0; 3]), [0.0; 3]);
    assert_eq!(t.apply([-1.0, -5.0, 0.0]), [0.0; 3]);
    assert_eq!(t.apply([f32::NAN, 0.0, 0.0]), [1.0, 0.0, 1.0]);
    assert_eq!(t.apply([0.0, f32::INFINITY, 0.0]), [1.0, 0.0, 1.0]);
    // 1 → Reinhard 0.5 → sRGB 1.055·0.5^(1/2.4) − 0.055 ≈ 0.735357.
    let v = t.apply([1.0; 3]);
    assert!((v[0] - 0.735_357).abs() < 1e-5, "{v:?}");
    // +1 stop doubles the input: 0.5 → 1 → same as above.
    let v2 = ToneMap { exposure: 1.0 }.apply([0.5; 3]);
    assert!((v2[0] - v[0]).abs() < 1e-6);
    // Huge radiance × huge exposure saturates instead of going NaN.
    assert_eq!(ToneMap { exposure: 64.0 }.apply([f32::MAX; 3]), [1.0; 3]);
}

#[test]
fn auto_exposure_maps_p95_to_target() {
    // Constant luminance-5 image: p95 = 5 → 5·2^e = 0.8.
    let mut img = Image::new(10, 10);
    img.pixels.fill([5.0; 3]);
    let t = ToneMap::auto(&img);
    assert!((5.0 * t.exposure.exp2() - 0.8).abs() < 1e-5, "{t:?}");

    // Mostly black with a dim beam: falls back to the non-zero pixels.
    let mut sparse = Image::new(100, 1);
    for x in 0..3 {
        sparse.set(x, 0, [0.01; 3]);
    }
    let t = ToneMap::auto(&sparse);
    assert!((0.01 * t.exposure.exp2() - 0.8).abs() < 1e-4, "{t:?}");

    assert_eq!(ToneMap::auto(&Image::new(4, 4)), ToneMap::default());
}
