//! The reference's numerical building blocks: adaptive Gauss–Kronrod (G7K15) quadrature of
//! RGB integrands, the closed-form ∫ e^(−s x) dx of a directional light's lit interval, and a
//! per-channel exp. Shared by the camera-ray integrals (`integrate.rs`,
//! `particle_ray.rs`) and indirect single scattering (`indirect.rs`).

use glam::DVec3;

/// e^v per channel.
pub fn exp(v: DVec3) -> DVec3 {
    DVec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}

/// ∫_a^b e^(−s x) dx.
pub fn exp_integral(s: f64, a: f64, b: f64) -> f64 {
    if s * (b - a) < 1e-12 {
        return (b - a) * (-s * a).exp();
    }
    (-s * a).exp() * -(-s * (b - a)).exp_m1() / s
}

// Gauss–Kronrod 7–15 nodes and weights (QUADPACK qk15).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728_0,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One G7K15 panel: (Kronrod estimate, |Kronrod − Gauss| per channel).
pub fn gk15(f: &impl Fn(f64) -> DVec3, a: f64, b: f64) -> (DVec3, DVec3) {
    let c = 0.5 * (a + b);
    let hl = 0.5 * (b - a);
    let fc = f(c);
    let mut k = fc * WGK[7];
    let mut g = fc * WG[3];
    for j in 0..7 {
        let x = hl * XGK[j];
        let s = f(c - x) + f(c + x);
        k += s * WGK[j];
        if j % 2 == 1 {
            g += s * WG[j / 2];
        }
    }
    (k * hl, (k - g).abs() * hl)
}

/// Adaptive G7K15 on [a, b] until each panel's error is below `rel_tol` times the running
/// estimate of the whole integral (per channel maximum), or panels are 2⁻³⁰ of the interval.
pub fn adaptive(f: &impl Fn(f64) -> DVec3, a: f64, b: f64, rel_tol: f64) -> DVec3 {
    if b <= a {
        return DVec3::ZERO;
    }
    let (whole, err) = gk15(f, a, b);
    let scale = whole.abs().max_element();
    refine(f, a, b, whole, err, rel_tol * scale.max(1e-300))
}

/// Adaptive G7K15 on [a, b] from its first panel (whole, err) until the summed panel errors
/// are below the absolute `target` (per channel maximum), or panels are 2⁻³⁰ of the interval.
pub fn refine(
    f: &impl Fn(f64) -> DVec3,
    a: f64,
    b: f64,
    whole: DVec3,
    err: DVec3,
    target: f64,
) -> DVec3 {
    if b <= a {
        return DVec3::ZERO;
    }
    let min_width = (b - a) * 2f64.powi(-30);
    let mut stack = vec![(a, b, whole, err)];
    let mut sum = DVec3::ZERO;
    while let Some((lo, hi, est, e)) = stack.pop() {
        // Each panel gets a share of the error budget proportional to its width.
        let allowed = target * (hi - lo) / (b - a);
        if e.max_element() <= allowed.max(1e-300) || hi - lo < min_width {
            sum += est;
            continue;
        }
        let m = 0.5 * (lo + hi);
        let (l, le) = gk15(f, lo, m);
        let (r, re) = gk15(f, m, hi);
        stack.push((lo, m, l, le));
        stack.push((m, hi, r, re));
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adaptive_quadrature_integrates_a_peak() {
        // ∫_{-1}^{1} 1/(1e-4 + x²) dx = 2/√1e-4 · atan(1/√1e-4).
        let f = |x: f64| DVec3::splat(1.0 / (1e-4 + x * x));
        let exact = 2.0 / 1e-2 * (1.0f64 / 1e-2).atan();
        let got = adaptive(&f, -1.0, 1.0, 1e-10).x;
        assert!((got / exact - 1.0).abs() < 1e-9, "{got} vs {exact}");
    }

    #[test]
    fn exp_integral_matches_its_limit() {
        assert!((exp_integral(0.0, 1.0, 3.0) - 2.0).abs() < 1e-15);
        let s = 0.7;
        let exact = ((-s * 1.0f64).exp() - (-s * 3.0f64).exp()) / s;
        assert!((exp_integral(s, 1.0, 3.0) - exact).abs() < 1e-15);
    }
}
