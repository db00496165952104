// The visibility bases of prefiltered-single-scattering: a camera ray at normalised eye angle z
// is lit where it crosses a light ray whose caster's normalised eye angle z_c exceeds z,
// V = H(z_c − z), and over an interval of light rays its mean is reconstructed from the mean
// basis coefficients of the z_c there. Self-contained (the tests compose it alone).
//
// Fourier (Annen et al. 2007's convolution shadow maps, Klehm et al. 2014): for z_c − z in
// (−1, 1), H(z_c − z) = ½ + 2 Σ_{k≥1} sin(c_k (z_c − z)) / c_k with c_k = π (2k − 1) (the square
// wave's series), truncated after TERMS terms; sin(c_k (z_c − z)) = sin(c_k z_c) cos(c_k z) −
// cos(c_k z_c) sin(c_k z), so the row stores cos(c_k z_c) and sin(c_k z_c).
// Moments (Peters & Klein 2015, Peters et al. 2016/2017): b = (z_c, z_c², z_c³, z_c⁴); the lit
// fraction is one minus the 4-moment Hamburger lower bound on the fraction of z_c below z.

const BASIS_MOMENTS: u32 = 0u;
const BASIS_FOURIER: u32 = 1u;
// Largest CHANNELS (passes.rs: 32 Fourier terms in 16 vec4s).
const MAX_CHANNELS: u32 = 16u;

// 0: moments, 1: Fourier
override BASIS: u32 = 0u;
// Moments: the caster and ray values are moved into [MOMENT_MARGIN, 1 − MOMENT_MARGIN] first.
// Peters & Klein's bias mixes in the moments of half a unit mass at 0 and half at 1; a row
// interval whose casters all sit at 0 or 1 (clamped below the slice's angles, or no caster at
// all) would then have moments of only two points, a singular Hankel matrix (NaN).
const MOMENT_MARGIN: f32 = 0.0625;

// Fourier terms M (even); vec4 channels per row entry (moments: 2, the double-float sum; Fourier: M / 2)
override TERMS: u32 = 16u;
override CHANNELS: u32 = 2u;
// Moments: the mixing weight toward the moments of a uniform distribution (Peters & Klein 2015)
override MOMENT_BIAS: f32 = 3e-5;
// Fourier: 1 multiplies term k by Lanczos' σ factor sinc(k / (M + 1)) against ringing
override LANCZOS: bool = false;

const BASIS_PI: f32 = 3.14159265358979;

// Frequency c_k of Fourier term k (0-based: π (2k + 1)).
fn fourier_frequency(k: u32) -> f32 {
    return BASIS_PI * f32(2u * k + 1u);
}

// A value of [0, 1] moved into the moments' interior range.
fn moment_value(z: f32) -> f32 {
    return mix(MOMENT_MARGIN, 1.0 - MOMENT_MARGIN, z);
}

// Channel c of the basis coefficients of caster value z_c ∈ [0, 1].
fn basis_coefficients(zc: f32, c: u32) -> vec4<f32> {
    if (BASIS == BASIS_MOMENTS) {
        let zm = moment_value(zc);
        let z2 = zm * zm;
        return select(vec4<f32>(0.0), vec4<f32>(zm, z2, z2 * zm, z2 * z2), c == 0u);
    }
    let a = fourier_frequency(2u * c) * zc;
    let b = fourier_frequency(2u * c + 1u) * zc;
    return vec4<f32>(cos(a), sin(a), cos(b), sin(b));
}

// Whether every caster value behind mean channel 0 is 1 (no caster: the row's default), where
// the interval is lit whatever the basis would reconstruct (the moments' bias and the series'
// ringing would darken it slightly). Channel 0's first component is the mean of z_c
// (moments, moved) or of cos(π z_c) (Fourier), at its extreme only if every z_c is 1.
fn all_uncast(mean0: vec4<f32>) -> bool {
    if (BASIS == BASIS_MOMENTS) { return mean0.x >= moment_value(1.0) - 1e-5; }
    return mean0.x <= -1.0 + 1e-5;
}

// Weight of term k's Lanczos σ factor (1 without LANCZOS).
fn fourier_window(k: u32) -> f32 {
    if (!LANCZOS) { return 1.0; }
    let x = BASIS_PI * f32(k + 1u) / f32(TERMS + 1u);
    return sin(x) / x;
}

// 2 Σ over channel c's two terms of (S̄_k cos(c_k z) − C̄_k sin(c_k z)) / c_k, from the channel's
// mean coefficients (C̄, S̄ of term 2c; C̄, S̄ of term 2c + 1).
fn fourier_channel(mean: vec4<f32>, c: u32, z: f32) -> f32 {
    let ka = 2u * c;
    let fa = fourier_frequency(ka);
    let fb = fourier_frequency(ka + 1u);
    let ta = (mean.y * cos(fa * z) - mean.x * sin(fa * z)) / fa * fourier_window(ka);
    let tb = (mean.w * cos(fb * z) - mean.z * sin(fb * z)) / fb * fourier_window(ka + 1u);
    return 2.0 * (ta + tb);
}

// The Fourier reconstruction of the lit fraction from the channels' sum (fourier_channel),
// clamped to [0, 1].
fn fourier_lit(channel_sum: f32) -> f32 {
    return clamp(0.5 + channel_sum, 0.0, 1.0);
}

// Weight of support point x of the three-point distribution through points x, y, w with the
// moments (1, b₁, b₂): the Lagrange form (y w − b₁ (y + w) + b₂) / ((x − y)(x − w)).
fn support_weight(b: vec4<f32>, x: f32, y: f32, w: f32) -> f32 {
    return (y * w - b.x * (y + w) + b.y) / ((x - y) * (x - w));
}

// The lit fraction at z from the mean moments b of the z_c: 1 minus Peters & Klein's 4-moment
// "Hamburger" shadow intensity (2015, Algorithm 2 for [0, 1] depths). The moments, biased toward
// a uniform distribution's, give a Hankel matrix B; B c = (1, z, z²) by its LDLᵀ factorisation;
// the roots z₁ ≤ z₂ of c₀ + c₁ x + c₂ x² with z complete the distribution of least mass below z
// that has these moments, and the shadow is its mass strictly below z — a lower bound, so the
// lit fraction is an upper bound (light leaks; exact for one caster value per interval).
fn moment_lit(b_in: vec4<f32>, z_in: f32) -> f32 {
    let z = moment_value(z_in);
    let b = mix(b_in, vec4<f32>(0.5), MOMENT_BIAS);
    let d1 = b.y - b.x * b.x;
    let l21d1 = b.z - b.x * b.y;
    let l21 = l21d1 / d1;
    let d2 = (b.w - b.y * b.y) - l21d1 * l21;
    var c1 = (z - b.x) / d1;
    var c2 = (z * z - b.y - l21 * (z - b.x)) / d2;
    c1 -= l21 * c2;
    let c0 = 1.0 - b.x * c1 - b.y * c2;
    let p = c1 / c2;
    let q = c0 / c2;
    let r = sqrt(max(0.25 * p * p - q, 0.0));
    let z1 = -0.5 * p - r;
    let z2 = -0.5 * p + r;
    var shadow = 0.0;
    if (z2 < z) {
        shadow = 1.0 - support_weight(b, z, z1, z2);
    } else if (z1 < z) {
        shadow = support_weight(b, z1, z, z2);
    }
    return 1.0 - clamp(shadow, 0.0, 1.0);
}
