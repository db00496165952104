use super::*;

/// A 97 × 300 sRGB pair with edges, gradients and noise, the test a perturbed reference.
fn pair() -> (Vec<u8>, Vec<u8>, usize, usize) {
    let (w, h) = (97, 300);
    let mut s = 7u64;
    let mut noise = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 56) as i32 - 128
    };
    let mut reference = Vec::with_capacity(w * h * 3);
    let mut test = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        for x in 0..w {
            let stripe = if (x / 7 + y / 11) % 2 == 0 { 200 } else { 40 };
            let base = [stripe, (y * 255 / h) as i32, (x * 255 / w) as i32];
            for c in base {
                reference.push(c.clamp(0, 255) as u8);
                test.push((c + noise() / 8).clamp(0, 255) as u8);
            }
        }
    }
    (test, reference, w, h)
}

/// NVIDIA's FLIP over the whole image at once: what the strips must reproduce.
fn whole(test: &[u8], reference: &[u8], w: usize, h: usize) -> Vec<f32> {
    nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w as u32, h as u32, reference),
        nv_flip::FlipImageRgb8::with_data(w as u32, h as u32, test),
        PIXELS_PER_DEGREE,
    )
    .to_vec()
}

/// How many values of `a` differ from `b`'s in any bit.
fn bitwise_differences(a: &[f32], b: &[f32]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

#[test]
fn strips_reproduce_the_whole_image_bit_for_bit() {
    let (test, reference, w, h) = pair();
    let expected = whole(&test, &reference, w, h);
    assert!(
        expected.iter().any(|&e| e > 0.05),
        "the pair must differ visibly"
    );
    for strips in [1, 2, 3, 5, 8, 13] {
        let got = flip_map(&test, &reference, w, h, strips);
        assert_eq!(got.len(), expected.len());
        let differing = bitwise_differences(&got, &expected);
        assert_eq!(
            differing, 0,
            "{strips} strips: {differing} pixels differ from the whole image"
        );
    }
}

/// The halo is what makes the strips exact: one row short of the filters' reach, rows next to
/// a strip's edge change.
#[test]
fn a_halo_short_of_the_filters_changes_rows_at_strip_edges() {
    let (test, reference, w, h) = pair();
    let expected = whole(&test, &reference, w, h);
    let reach = spatial_radius(PIXELS_PER_DEGREE).max(feature_radius(PIXELS_PER_DEGREE));
    assert_eq!(halo(PIXELS_PER_DEGREE), reach + 1);
    let short = strip_map(&test, &reference, (w, h), 4, reach - 1);
    let differing = bitwise_differences(&short, &expected);
    assert!(
        differing > 0,
        "a halo of {} rows should not be enough",
        reach - 1
    );
}

/// FLIP's radii at nv_flip's default 67 pixels per degree, from FLIP's formulas by hand:
/// 3·sqrt(0.04 / 2π²)·67 = 9.05 → 10, and 3 · 0.5 · 0.082 · 67 = 8.24 → 9.
#[test]
fn radii_follow_flips_formulas() {
    assert_eq!(PIXELS_PER_DEGREE, 67.0);
    assert_eq!(spatial_radius(PIXELS_PER_DEGREE), 10);
    assert_eq!(feature_radius(PIXELS_PER_DEGREE), 9);
}
