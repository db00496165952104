//! Biri's Γ(λ, γ) (eq. 6) in the project convention (∫ p dω = 1, so no 1/4π outside):
//!
//! Γ(λ, γ) = ∫₀^γ p(cos θ = −sin α) e^(−λ (1 + sin α)/cos α) dα,
//!
//! and the direct single scattering of a point light of intensity I over [0, d] of a view ray
//! (eq. 7) is σ_s I e^(−σ_t t) / h · [Γ(σ_t h, γ_d) − Γ(σ_t h, γ_0)], with t the distance along
//! the ray to the foot of the light's perpendicular, h the light's distance to the ray,
//! γ_0 = atan(−t/h), γ_d = atan((d − t)/h).
//!
//! The table is indexed by u = λ/(1 + λ) (λ ∈ [0, ∞) onto [0, 1)) and by
//! w = s/(1 + s), s = tan(γ/2 + π/4) = (1 + sin γ)/cos γ (γ ∈ [−π/2, π/2] onto [0, 1]). In w the
//! integrand p · e^(−λ s) · 2/((1 − w)² + w²) is smooth up to γ = π/2, where the paper's linear γ
//! axis bends sharply (rays pointing away from the light); and the shader gets w without an atan:
//! with y the signed distance along the ray from the foot, s = (r + y)/h.
//!
//! Shared by biri-shadow-volumes (eq. 7 itself) and polygonal-light-volumes (the unshadowed
//! in-scatter of its light volumes); the shader side is `wgsl::LDSS` (`wgsl/ldss.wgsl`).

use harness::Gpu;
use scenes::Phase;

use super::quadrature::gauss;

/// Γ sampled on a `lambda_res` × `w_res` grid: row i holds λ_i = u_i/(1 − u_i), u_i = i/lambda_res
/// (the last row is λ = lambda_res − 1; larger λ clamp to it); column j holds w_j = j/(w_res − 1).
#[derive(Clone, Debug)]
pub struct GammaTable {
    pub lambda_res: u32,
    pub w_res: u32,
    /// Row-major, `lambda_res` rows of `w_res` values.
    pub data: Vec<f32>,
}

/// λ of table row coordinate u ∈ [0, 1).
pub fn lambda_of_u(u: f64) -> f64 {
    u / (1.0 - u)
}

/// γ (radians) of the w coordinate ∈ [0, 1].
pub fn gamma_of_w(w: f64) -> f64 {
    if w >= 1.0 {
        return std::f64::consts::FRAC_PI_2;
    }
    let s = w / (1.0 - w);
    2.0 * s.atan() - std::f64::consts::FRAC_PI_2
}

/// w coordinate of γ.
pub fn w_of_gamma(g: f64) -> f64 {
    let s = (g / 2.0 + std::f64::consts::FRAC_PI_4).tan();
    if s.is_finite() { s / (1.0 + s) } else { 1.0 }
}

/// The integrand of Γ in w: dα = 2 dw / ((1 − w)² + w²), sin α = (s² − 1)/(s² + 1).
fn integrand_w(phase: &Phase, lambda: f64, w: f64) -> f64 {
    let jac = 2.0 / ((1.0 - w).powi(2) + w * w);
    if w >= 1.0 {
        return if lambda == 0.0 {
            phase.eval(-1.0) * jac
        } else {
            0.0
        };
    }
    let s = w / (1.0 - w);
    let sin_a = (s * s - 1.0) / (s * s + 1.0);
    phase.eval(-sin_a) * (-lambda * s).exp() * jac
}

impl GammaTable {
    /// Integrates Γ for `phase`: per row, a cumulative Gauss–Legendre sum over the w cells (4
    /// pieces of 8 nodes per cell), shifted so that Γ(λ, 0) = 0 (w = 1/2).
    pub fn build(phase: &Phase, lambda_res: u32, w_res: u32) -> GammaTable {
        let (m, n) = (lambda_res.max(2), w_res.max(3));
        let mut data = Vec::with_capacity((m * n) as usize);
        for i in 0..m {
            let lambda = lambda_of_u(i as f64 / m as f64);
            let f = |w: f64| integrand_w(phase, lambda, w);
            let zero = gauss(f, 0.0, 0.5, 4 * n as usize);
            let mut acc = 0.0;
            data.push(-zero as f32);
            for j in 1..n {
                let (a, b) = ((j - 1) as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                acc += gauss(f, a, b, 4);
                data.push((acc - zero) as f32);
            }
        }
        GammaTable {
            lambda_res: m,
            w_res: n,
            data,
        }
    }

    /// The table as an R32Float texture (w along x, λ along y), as `wgsl::LDSS` reads it.
    pub fn upload(&self, gpu: &Gpu, label: &str) -> wgpu::Texture {
        super::tables::r32_table(gpu, label, self.w_res, self.lambda_res, &self.data)
    }

    /// Bilinear lookup (what the shader does), λ ≥ 0, w ∈ [0, 1].
    pub fn lookup(&self, lambda: f64, w: f64) -> f64 {
        let (m, n) = (self.lambda_res as usize, self.w_res as usize);
        let fi = ((lambda / (1.0 + lambda)) * m as f64).clamp(0.0, (m - 1) as f64);
        let fj = (w * (n - 1) as f64).clamp(0.0, (n - 1) as f64);
        let (i0, j0) = (fi.floor() as usize, fj.floor() as usize);
        let (i1, j1) = ((i0 + 1).min(m - 1), (j0 + 1).min(n - 1));
        let (a, b) = (fi - i0 as f64, fj - j0 as f64);
        let v = |i: usize, j: usize| self.data[i * n + j] as f64;
        (1.0 - a) * ((1.0 - b) * v(i0, j0) + b * v(i0, j1))
            + a * ((1.0 - b) * v(i1, j0) + b * v(i1, j1))
    }
}

/// Γ(λ, γ) straight from eq. 6: Gauss–Legendre in α on 400 pieces (independent of the table's
/// w variable and its cumulative sum).
pub fn gamma_direct(phase: &Phase, lambda: f64, gamma: f64) -> f64 {
    let f = |a: f64| {
        let c = a.cos();
        let e = if c <= 0.0 {
            if a < 0.0 { 1.0 } else { 0.0 }
        } else {
            (-lambda * (1.0 + a.sin()) / c).exp()
        };
        let e = if lambda == 0.0 { 1.0 } else { e };
        phase.eval(-a.sin()) * e
    };
    gauss(f, 0.0, gamma, 400)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bilinear table lookup against eq. 6 integrated directly in α, over the whole domain
    /// (λ from 0 to 50, γ from −π/2 to π/2), for an isotropic, a hazy-Mie and a strongly forward
    /// Henyey–Greenstein (g = 0.8) phase. The error is measured relative to the scale of the row
    /// (|Γ(λ, −π/2)| + |Γ(λ, π/2)|, what a Γ difference is made of). At 256² the worst is where
    /// λ is largest (50) and γ within 0.013 rad of −π/2: there e^(−λ s) is a boundary layer 1/λ
    /// wide in w, a few table columns (measured 3.2e-3 isotropic; see the eprintln for the others;
    /// such rays see the light almost head-on through ≥ 50 optical depths, so their in-scatter is
    /// negligible). Bound 5e-3 over the whole domain and 5e-4 for λ ≤ 7. A Γ with the paper's
    /// 1/4π left in, or the exponent's sign or an axis map wrong, is ≥ 100% off.
    /// Just inside ±π/2, where eq. 6's integrand is still finite.
    const EDGE: f64 = std::f64::consts::FRAC_PI_2 - 1e-4;

    #[test]
    fn table_matches_direct_quadrature() {
        for phase in [
            Phase::Isotropic,
            Phase::HazyMie,
            Phase::HenyeyGreenstein { g: 0.8 },
        ] {
            let t = GammaTable::build(&phase, 256, 256);
            let mut worst: f64 = 0.0;
            let mut worst_small: f64 = 0.0;
            for &lambda in &[0.0, 0.01, 0.1, 0.37, 1.0, 2.5, 7.0, 20.0, 50.0] {
                let scale = gamma_direct(&phase, lambda, -EDGE).abs()
                    + gamma_direct(&phase, lambda, EDGE).abs();
                for k in 0..=40 {
                    let g = -EDGE + 2.0 * EDGE * k as f64 / 40.0 + 0.013;
                    let g = g.min(EDGE);
                    let exact = gamma_direct(&phase, lambda, g);
                    let err = (t.lookup(lambda, w_of_gamma(g)) - exact).abs() / scale;
                    worst = worst.max(err);
                    if lambda <= 7.0 {
                        worst_small = worst_small.max(err);
                    }
                }
            }
            eprintln!(
                "{phase:?}: worst Γ table error relative to the row scale: {worst:.2e} (λ ≤ 7: {worst_small:.2e})"
            );
            assert!(worst < 5e-3, "{phase:?}: {worst}");
            assert!(worst_small < 5e-4, "{phase:?}, λ ≤ 7: {worst_small}");
        }
    }

    /// Γ for isotropic scattering and λ = 0 is (γ − 0)/4π exactly.
    #[test]
    fn isotropic_lambda_zero_is_linear() {
        let t = GammaTable::build(&Phase::Isotropic, 64, 64);
        for g in [-1.5, -0.3, 0.0, 0.8, 1.5] {
            let exact = g / (4.0 * std::f64::consts::PI);
            assert!((t.lookup(0.0, w_of_gamma(g)) - exact).abs() < 2e-4, "{g}");
        }
    }
}
