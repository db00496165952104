//! Exponential height fog in the reference (ARCHITECTURE §1): every coefficient is the file's
//! value times the density scale e^(−(y − y₀)/H), so the optical depth of a segment is
//! σ_t · L, with L the segment's *fog length* — ∫ e^(−(y(s) − y₀)/H) ds over it, in metres.
//! Along a straight segment the height is linear, and the fog length has a closed form:
//!
//! L = e^(−(y_low − y₀)/H) · s · (1 − e^(−z))/z,  z = |d_y| s / H ≥ 0,
//!
//! taken from the segment's lower end (so the exponent never overflows for a segment that
//! rises), with (1 − e^(−z))/z computed through `exp_m1` (no cancellation as z → 0, exactly 1
//! for a level segment).

use glam::DVec3;
use scenes::HeightFog;

/// A height fog's parameters in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    /// Base height y₀, m.
    pub base: f64,
    /// Falloff height H, m (> 0).
    pub falloff: f64,
}

impl From<HeightFog> for Fog {
    fn from(f: HeightFog) -> Fog {
        Fog {
            base: f.base_height as f64,
            falloff: f.falloff_height as f64,
        }
    }
}

impl Fog {
    /// The density scale at height y: σ(y)/σ(y₀) = e^(−(y − y₀)/H).
    pub fn scale(&self, y: f64) -> f64 {
        (-(y - self.base) / self.falloff).exp()
    }

    /// The fog length (m) of the segment from `a` along the unit direction `d` for `s` metres:
    /// its optical depth divided by σ_t at the base height.
    pub fn length(&self, a: DVec3, d: DVec3, s: f64) -> f64 {
        let rise = d.y * s;
        let y_low = a.y + rise.min(0.0);
        let z = rise.abs() / self.falloff;
        self.scale(y_low) * s * rise_factor(z)
    }
}

/// (1 − e^(−z))/z for z ≥ 0, 1 at z = 0, without cancellation for small z.
fn rise_factor(z: f64) -> f64 {
    if z == 0.0 { 1.0 } else { -(-z).exp_m1() / z }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rise_factor_is_smooth_through_zero() {
        assert_eq!(rise_factor(0.0), 1.0);
        // The series 1 − z/2 + z²/6 − z³/24 + …: no cancellation at z = 1e-12 (there 1 − e^(−z)
        // computed directly keeps 4 digits); f64 rounding (1e-16) at z = 1e-4.
        let series = |z: f64| 1.0 - z / 2.0 + z * z / 6.0 - z * z * z / 24.0;
        for z in [1e-12, 1e-8, 1e-4] {
            let e = (rise_factor(z) - series(z)).abs();
            assert!(
                e < 1e-15,
                "z = {z}: {} vs {} ({e:e})",
                rise_factor(z),
                series(z)
            );
        }
    }

    #[test]
    fn length_is_the_same_from_either_end() {
        let fog = Fog {
            base: 1.0,
            falloff: 3.0,
        };
        let a = DVec3::new(0.0, -2.0, 0.0);
        let d = DVec3::new(0.6, 0.8, 0.0);
        let b = a + d * 7.0;
        let up = fog.length(a, d, 7.0);
        let down = fog.length(b, -d, 7.0);
        assert!((up - down).abs() <= 1e-14 * up, "{up} vs {down}");
    }
}
