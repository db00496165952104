//! Phase functions, normalised so that ∫ p dω = 1 over the sphere (ARCHITECTURE §1).
//!
//! θ is the scattering angle between the light's propagation direction at x and the direction
//! from x toward the eye: θ = 0 is forward scattering.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Phase {
    /// 1/4π.
    #[default]
    Isotropic,
    /// (1 - g²) / (4π (1 + g² - 2g cosθ)^(3/2)), g in (-1, 1).
    HenyeyGreenstein { g: f32 },
    /// 3/(16π) (1 + cos²θ).
    Rayleigh,
    /// (1 + 9 cos¹⁶(θ/2)) / 8π — Nishita's hazy Mie, used by Dobashi.
    HazyMie,
    /// (1 + 50 cos⁶⁴(θ/2)) / (4π + 400π/66).
    MurkyMie,
}

impl Phase {
    /// p(θ) in 1/sr, from cos θ.
    pub fn eval(&self, cos_theta: f64) -> f64 {
        let c = cos_theta.clamp(-1.0, 1.0);
        match *self {
            Phase::Isotropic => 1.0 / (4.0 * PI),
            Phase::HenyeyGreenstein { g } => {
                let g = g as f64;
                let denom = (1.0 + g * g - 2.0 * g * c).max(1e-300);
                (1.0 - g * g) / (4.0 * PI * denom * denom.sqrt())
            }
            Phase::Rayleigh => 3.0 / (16.0 * PI) * (1.0 + c * c),
            Phase::HazyMie => {
                // cos²(θ/2) = (1 + cosθ)/2, so cos¹⁶(θ/2) = ((1+c)/2)^8.
                let h = (0.5 * (1.0 + c)).powi(8);
                (1.0 + 9.0 * h) / (8.0 * PI)
            }
            Phase::MurkyMie => {
                let h = (0.5 * (1.0 + c)).powi(32);
                (1.0 + 50.0 * h) / (4.0 * PI + 400.0 * PI / 66.0)
            }
        }
    }

    /// Whether p depends on θ at all.
    pub fn is_anisotropic(&self) -> bool {
        !matches!(self, Phase::Isotropic)
    }

    /// Stable short name, as in the scene file.
    pub fn name(&self) -> &'static str {
        match self {
            Phase::Isotropic => "isotropic",
            Phase::HenyeyGreenstein { .. } => "henyey-greenstein",
            Phase::Rayleigh => "rayleigh",
            Phase::HazyMie => "hazy-mie",
            Phase::MurkyMie => "murky-mie",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ p dω = 2π ∫_{-1}^{1} p(c) dc, by composite Gauss–Legendre (independent of the closed forms).
    fn integrate_sphere(p: &Phase) -> f64 {
        // 5-point Gauss–Legendre on 4000 panels: murky Mie's cos⁶⁴ peak is resolved many times over.
        let nodes = [
            0.0,
            -0.538_469_310_105_683_1,
            0.538_469_310_105_683_1,
            -0.906_179_845_938_664,
            0.906_179_845_938_664,
        ];
        let weights = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_5,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
            0.236_926_885_056_189_1,
        ];
        let panels = 4000;
        let h = 2.0 / panels as f64;
        let mut sum = 0.0;
        for i in 0..panels {
            let mid = -1.0 + (i as f64 + 0.5) * h;
            for (x, w) in nodes.iter().zip(weights) {
                sum += w * 0.5 * h * p.eval(mid + 0.5 * h * x);
            }
        }
        2.0 * PI * sum
    }

    #[test]
    fn every_phase_function_integrates_to_one() {
        let all = [
            Phase::Isotropic,
            Phase::HenyeyGreenstein { g: 0.0 },
            Phase::HenyeyGreenstein { g: 0.6 },
            Phase::HenyeyGreenstein { g: -0.3 },
            Phase::HenyeyGreenstein { g: 0.9 },
            Phase::Rayleigh,
            Phase::HazyMie,
            Phase::MurkyMie,
        ];
        for p in all {
            let total = integrate_sphere(&p);
            assert!((total - 1.0).abs() < 1e-6, "{p:?} integrates to {total}");
        }
    }

    #[test]
    fn forward_peaked_phases_prefer_theta_zero() {
        for p in [
            Phase::HazyMie,
            Phase::MurkyMie,
            Phase::HenyeyGreenstein { g: 0.5 },
        ] {
            // Hazy Mie's forward/backward ratio is exactly 10, murky Mie's 51.
            assert!(
                p.eval(1.0) >= 10.0 * p.eval(-1.0) * (1.0 - 1e-12)
                    || matches!(p, Phase::HenyeyGreenstein { .. })
            );
            assert!(p.eval(1.0) > p.eval(0.0));
        }
    }
}
