//! The CPU side of Biri et al.'s angular RTE (eq. 3–6): the kernel Λ(θ), its polynomial
//! expansion (Taylor around θ = 0 as in the paper's annex, or Chebyshev interpolation over the
//! θ range a segment actually uses), and the medium contribution of a lit segment in constant
//! time. Everything in f64; plain functions, no GPU.
//!
//! Geometry (paper, Fig. 3): a ray from the eye O with unit direction u; the light L projects on
//! the ray at parameter `t` (may be negative) at distance `h` > 0. A point x along the ray is at
//! angle θ = atan((x − t)/h) from that foot. With x = t + h tanθ, dx/r² = dθ/h and
//! x + r = t + h (sinθ + 1)/cosθ, so ARCHITECTURE §1's in-scattered radiance of a lit segment is
//!
//!   L_in = σ_s I e^(−σ_t t) / h · ∫_{θa}^{θb} Λ(θ) dθ,  Λ(θ) = e^(−k (sinθ+1)/cosθ) p(θ + π/2),
//!
//! with k = σ_t h and p normalised to ∫p dω = 1 (Biri's p averages to 1 and carries 1/4π
//! outside, the same thing). The scattering angle is θ + π/2: cos = −sinθ.

// Power-series recurrences read best with explicit indices.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;

use scenes::Phase;

/// Highest polynomial order the method offers (the paper: "in practice we use superior orders").
pub const MAX_ORDER: usize = 8;

/// How the polynomial coefficients are obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fit {
    /// The paper's Taylor expansion of Λ around θ = 0 (annex), one polynomial per k.
    Taylor,
    /// Chebyshev interpolation of Λ at n+1 Chebyshev nodes of the segment's own θ range,
    /// integrated in closed form (our improvement; equivalent to Clenshaw–Curtis quadrature).
    Chebyshev,
}

impl Fit {
    pub fn parse(s: &str) -> Result<Fit, String> {
        match s {
            "taylor" => Ok(Fit::Taylor),
            "chebyshev" => Ok(Fit::Chebyshev),
            _ => Err(format!("fit must be `taylor` or `chebyshev`, not `{s}`")),
        }
    }
}

// ---- truncated power series (coefficients of θ^0 … θ^n) ----

fn mul(a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
    let mut c = vec![0.0; n + 1];
    for (i, ai) in a.iter().enumerate().take(n + 1) {
        for (j, bj) in b.iter().enumerate().take(n + 1 - i) {
            c[i + j] += ai * bj;
        }
    }
    c
}

/// a / b, b[0] ≠ 0.
fn div(a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
    let mut q = vec![0.0; n + 1];
    for i in 0..=n {
        let mut s = a.get(i).copied().unwrap_or(0.0);
        for j in 1..=i {
            s -= b.get(j).copied().unwrap_or(0.0) * q[i - j];
        }
        q[i] = s / b[0];
    }
    q
}

/// exp(a) for a with a[0] = 0: e_m = (1/m) Σ_{j=1..m} j a_j e_{m−j}.
fn exp0(a: &[f64], n: usize) -> Vec<f64> {
    let mut e = vec![0.0; n + 1];
    e[0] = 1.0;
    for m in 1..=n {
        e[m] = (1..=m)
            .map(|j| j as f64 * a.get(j).copied().unwrap_or(0.0) * e[m - j])
            .sum::<f64>()
            / m as f64;
    }
    e
}

/// a^α for a[0] > 0, from a·F' = α a'·F.
fn pow(a: &[f64], alpha: f64, n: usize) -> Vec<f64> {
    let get = |i: usize| a.get(i).copied().unwrap_or(0.0);
    let mut f = vec![0.0; n + 1];
    f[0] = get(0).powf(alpha);
    for m in 1..=n {
        let mut s = 0.0;
        for j in 1..=m {
            s += (alpha * j as f64 - (m - j) as f64) * get(j) * f[m - j];
        }
        f[m] = s / (m as f64 * get(0));
    }
    f
}

fn sin_series(n: usize) -> Vec<f64> {
    let mut s = vec![0.0; n + 1];
    let mut fact = 1.0;
    for i in 1..=n {
        fact *= i as f64;
        if i % 2 == 1 {
            s[i] = if (i / 2) % 2 == 0 { 1.0 } else { -1.0 } / fact;
        }
    }
    s
}

fn cos_series(n: usize) -> Vec<f64> {
    let mut c = vec![0.0; n + 1];
    let mut fact = 1.0;
    c[0] = 1.0;
    for i in 1..=n {
        fact *= i as f64;
        if i % 2 == 0 {
            c[i] = if (i / 2) % 2 == 0 { 1.0 } else { -1.0 } / fact;
        }
    }
    c
}

/// Series of g(θ) = (1 + sinθ)/cosθ = secθ + tanθ: 1 + θ + θ²/2 + θ³/3 + 5θ⁴/24 + …
pub fn g_series(n: usize) -> Vec<f64> {
    let mut num = sin_series(n);
    num[0] += 1.0;
    div(&num, &cos_series(n), n)
}

/// Series in θ of p(θ + π/2) (1/sr, ∫p dω = 1), using cos(θ + π/2) = −sinθ.
pub fn phase_series(phase: &Phase, n: usize) -> Vec<f64> {
    let s = sin_series(n);
    let mut out = vec![0.0; n + 1];
    match *phase {
        Phase::Isotropic => out[0] = 1.0 / (4.0 * PI),
        Phase::HenyeyGreenstein { g } => {
            let g = g as f64;
            // (1 + g² − 2g cosα)^(−3/2) with cosα = −sinθ.
            let mut base: Vec<f64> = s.iter().map(|v| 2.0 * g * v).collect();
            base[0] += 1.0 + g * g;
            out = pow(&base, -1.5, n)
                .iter()
                .map(|v| v * (1.0 - g * g) / (4.0 * PI))
                .collect();
        }
        Phase::Rayleigh => {
            let s2 = mul(&s, &s, n);
            for i in 0..=n {
                out[i] = 3.0 / (16.0 * PI) * (s2[i] + if i == 0 { 1.0 } else { 0.0 });
            }
        }
        Phase::HazyMie | Phase::MurkyMie => {
            // cos²(α/2) = (1 + cosα)/2 = (1 − sinθ)/2.
            let half: Vec<f64> = s
                .iter()
                .enumerate()
                .map(|(i, v)| if i == 0 { 0.5 } else { -0.5 * v })
                .collect();
            let (power, weight, norm) = match phase {
                Phase::HazyMie => (8.0, 9.0, 8.0 * PI),
                _ => (32.0, 50.0, 4.0 * PI + 400.0 * PI / 66.0),
            };
            let lobe = pow(&half, power, n);
            for i in 0..=n {
                out[i] = (weight * lobe[i] + if i == 0 { 1.0 } else { 0.0 }) / norm;
            }
        }
    }
    out
}

/// Taylor coefficients c_0 … c_n of Λ(θ) around θ = 0 for k = σ_t h (annex of the paper, in
/// scatterbench's phase normalisation): Λ = e^(−k) · exp(−k (g − 1)) · p(θ + π/2).
pub fn taylor(k: f64, phase: &Phase, n: usize) -> Vec<f64> {
    let mut a: Vec<f64> = g_series(n).iter().map(|v| -k * v).collect();
    a[0] = 0.0;
    let e = exp0(&a, n);
    mul(&e, &phase_series(phase, n), n)
        .iter()
        .map(|v| v * (-k).exp())
        .collect()
}

/// The exact kernel Λ(θ) for k = σ_t h, θ in (−π/2, π/2).
pub fn kernel(k: f64, phase: &Phase, theta: f64) -> f64 {
    let g = (theta.sin() + 1.0) / theta.cos();
    (-k * g).exp() * phase.eval(-theta.sin())
}

/// ∫_{a}^{b} Σ c_i θ^i dθ — eq. 6: Σ c_i [θ^(i+1)/(i+1)].
pub fn integrate_monomial(c: &[f64], a: f64, b: f64) -> f64 {
    let prim = |x: f64| {
        c.iter()
            .enumerate()
            .rev()
            .fold(0.0, |acc, (i, ci)| acc * x + ci / (i + 1) as f64)
            * x
    };
    prim(b) - prim(a)
}

/// Chebyshev coefficients (on [a, b]) of the degree-n interpolant of Λ at the n+1 Chebyshev
/// points of the first kind.
pub fn chebyshev(k: f64, phase: &Phase, n: usize, a: f64, b: f64) -> Vec<f64> {
    let m = n + 1;
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let f: Vec<f64> = (0..m)
        .map(|j| {
            kernel(
                k,
                phase,
                mid + half * (PI * (j as f64 + 0.5) / m as f64).cos(),
            )
        })
        .collect();
    (0..m)
        .map(|i| {
            let s: f64 = (0..m)
                .map(|j| f[j] * (PI * i as f64 * (j as f64 + 0.5) / m as f64).cos())
                .sum();
            s * if i == 0 { 1.0 } else { 2.0 } / m as f64
        })
        .collect()
}

/// ∫_a^b of the Chebyshev series on [a, b]: (b−a)/2 Σ_{i even} a_i · 2/(1 − i²).
pub fn integrate_chebyshev(coef: &[f64], a: f64, b: f64) -> f64 {
    0.5 * (b - a)
        * coef
            .iter()
            .enumerate()
            .filter(|(i, _)| i % 2 == 0)
            .map(|(i, c)| c * 2.0 / (1.0 - (i * i) as f64))
            .sum::<f64>()
}

/// ∫_{θa}^{θb} Λ with the chosen polynomial of order n (constant time in the segment length).
pub fn kernel_integral(fit: Fit, k: f64, phase: &Phase, n: usize, a: f64, b: f64) -> f64 {
    match fit {
        Fit::Taylor => integrate_monomial(&taylor(k, phase, n), a, b),
        Fit::Chebyshev => integrate_chebyshev(&chebyshev(k, phase, n, a, b), a, b),
    }
}

/// Where a ray meets the paper's angular frame: (t, h) for origin o, unit direction u, light l.
pub fn ray_frame(o: [f64; 3], u: [f64; 3], l: [f64; 3]) -> (f64, f64) {
    let v = [l[0] - o[0], l[1] - o[1], l[2] - o[2]];
    let t = v[0] * u[0] + v[1] * u[1] + v[2] * u[2];
    let w = [v[0] - t * u[0], v[1] - t * u[1], v[2] - t * u[2]];
    (t, (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt())
}

/// In-scattered radiance (per unit σ_s·I) of the lit segment [x0, x1] of a ray with foot `t`
/// and distance `h` (eq. 3): e^(−σ_t t)/h · ∫ Λ over [atan((x0−t)/h), atan((x1−t)/h)].
#[allow(clippy::too_many_arguments)] // the ray frame (t, h), the segment and the polynomial
pub fn segment(
    fit: Fit,
    sigma_t: f64,
    phase: &Phase,
    n: usize,
    t: f64,
    h: f64,
    x0: f64,
    x1: f64,
) -> f64 {
    let h = h.max(1e-9);
    let (a, b) = (((x0 - t) / h).atan(), ((x1 - t) / h).atan());
    (-sigma_t * t).exp() / h * kernel_integral(fit, sigma_t * h, phase, n, a, b)
}
