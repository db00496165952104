//! Sun et al. (2005)'s airlight special function, tabulated:
//! F(u, v) = ∫_0^v exp(−u tan ξ) dξ, u ≥ 0, v ∈ [0, π/2).
//!
//! In the project's convention (ARCHITECTURE §1) the unshadowed in-scatter of an isotropic point light
//! of intensity I over the ray interval [a, b] is, with t₀ the ray parameter closest to the light,
//! h that distance and ξ(x) = π/4 + ½ atan((x − t₀)/h):
//!
//!   L = σ_s · I · (1/4π) · (2/h) · e^(−σ_t t₀) · [F(σ_t h, ξ(b)) − F(σ_t h, ξ(a))]
//!
//! (substitute x = t₀ + h tan φ, then ξ = π/4 + φ/2, using x + r = t₀ + h tan ξ). This is Sun's
//! A₀ = σ_s e^(−σ_t d_l cos γ)/(2π d_l sin γ) with his phase folded out: his 1/2π is our
//! (1/4π)·2. The table is computed by Gauss–Legendre quadrature per cell, accumulated along v.

use std::f64::consts::FRAC_PI_2;

use crate::common::quadrature::gauss;

/// F on a regular grid: `data[j * nu + i] = F(u_i, v_j)`, u_i = i·u_max/(nu−1), v_j = j·(π/2)/(nv−1).
#[derive(Clone, Debug)]
pub struct FTable {
    pub nu: u32,
    pub nv: u32,
    pub u_max: f32,
    pub data: Vec<f32>,
}

/// ∫_a^b exp(−u tan ξ) dξ by 8-point Gauss–Legendre on `panels` sub-intervals.
fn integral(u: f64, a: f64, b: f64, panels: usize) -> f64 {
    gauss(|xi| (-u * xi.tan()).exp(), a, b, panels)
}

impl FTable {
    pub fn new(nu: u32, nv: u32, u_max: f32) -> FTable {
        let (nu, nv) = (nu.max(2), nv.max(2));
        let mut data = vec![0f32; (nu * nv) as usize];
        for i in 0..nu {
            let u = u_max as f64 * i as f64 / (nu - 1) as f64;
            let mut acc = 0.0;
            for j in 1..nv {
                let (a, b) = (
                    FRAC_PI_2 * (j - 1) as f64 / (nv - 1) as f64,
                    FRAC_PI_2 * j as f64 / (nv - 1) as f64,
                );
                // Near π/2 the integrand falls off a cliff for u > 0: more panels there.
                acc += integral(u, a, b.min(FRAC_PI_2 - 1e-12), 4);
                data[(j * nu + i) as usize] = acc as f32;
            }
        }
        FTable {
            nu,
            nv,
            u_max,
            data,
        }
    }

    /// Bilinear lookup, as the shader does it (clamped to the table).
    pub fn lookup(&self, u: f32, v: f32) -> f32 {
        let fu = (u / self.u_max).clamp(0.0, 1.0) * (self.nu - 1) as f32;
        let fv = (v / std::f32::consts::FRAC_PI_2).clamp(0.0, 1.0) * (self.nv - 1) as f32;
        let (i0, j0) = (fu.floor() as u32, fv.floor() as u32);
        let (i1, j1) = ((i0 + 1).min(self.nu - 1), (j0 + 1).min(self.nv - 1));
        let (tu, tv) = (fu - i0 as f32, fv - j0 as f32);
        let at = |i: u32, j: u32| self.data[(j * self.nu + i) as usize];
        let a = at(i0, j0) + (at(i1, j0) - at(i0, j0)) * tu;
        let b = at(i0, j1) + (at(i1, j1) - at(i0, j1)) * tu;
        a + (b - a) * tv
    }
}

/// F(u, v) by dense quadrature (for tests and as the table's definition).
pub fn f_exact(u: f64, v: f64) -> f64 {
    integral(u, 0.0, v.min(FRAC_PI_2 - 1e-12), 256)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f_at_u_zero_is_v() {
        assert!((f_exact(0.0, 1.0) - 1.0).abs() < 1e-12);
        let t = FTable::new(64, 64, 4.0);
        assert!((t.lookup(0.0, 1.2) - 1.2).abs() < 1e-5);
    }

    /// The airlight formula with the table equals a direct quadrature of the in-scatter integral
    /// for an isotropic point light (independent: integrates in x, not in ξ).
    #[test]
    fn airlight_formula_matches_direct_quadrature() {
        let (sigma_s, sigma_t, intensity) = (0.1f64, 0.15f64, 40.0f64);
        let (t0, h, a, b) = (3.0f64, 0.7f64, 0.5f64, 9.0f64);
        let n = 200_000;
        let dx = (b - a) / n as f64;
        let direct: f64 = (0..n)
            .map(|k| {
                let x = a + (k as f64 + 0.5) * dx;
                let r2 = (x - t0).powi(2) + h * h;
                sigma_s * intensity / (4.0 * std::f64::consts::PI)
                    * (-sigma_t * (x + r2.sqrt())).exp()
                    / r2
                    * dx
            })
            .sum();
        let xi = |x: f64| std::f64::consts::FRAC_PI_4 + 0.5 * ((x - t0) / h).atan();
        let u = sigma_t * h;
        let exact = sigma_s * intensity / (4.0 * std::f64::consts::PI) * 2.0 / h
            * (-sigma_t * t0).exp()
            * (f_exact(u, xi(b)) - f_exact(u, xi(a)));
        assert!((exact / direct - 1.0).abs() < 1e-6, "{exact} vs {direct}");
        let t = FTable::new(256, 256, 2.0);
        let tab = sigma_s * intensity / (4.0 * std::f64::consts::PI) * 2.0 / h
            * (-sigma_t * t0).exp()
            * (t.lookup(u as f32, xi(b) as f32) as f64 - t.lookup(u as f32, xi(a) as f32) as f64);
        assert!((tab / direct - 1.0).abs() < 2e-3, "table {tab} vs {direct}");
    }
}
