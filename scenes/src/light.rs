//! Lights at one frame, with exact CPU evaluation of their intensity toward a point.
//!
//! The GPU methods sample a texture of a spot's pattern; the reference calls
//! [`LightState::intensity_toward`], which evaluates the analytic pattern exactly.

use glam::{DVec3, Vec3};

use crate::desc::Pattern;

/// A light at one frame (keyframes already applied). Directions are unit length.
#[derive(Clone, Debug, PartialEq)]
pub enum LightState {
    Point {
        position: Vec3,
        intensity: Vec3,
    },
    Spot {
        position: Vec3,
        direction: Vec3,
        cos_inner: f32,
        cos_outer: f32,
        tan_outer: f32,
        intensity: Vec3,
        pattern: Option<Pattern>,
    },
    Directional {
        direction: Vec3,
        irradiance: Vec3,
    },
}

/// A spot light's cone, for the tests of what it can reach: its apex, its direction as given and
/// the cosine of its outer half-angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotCone {
    pub apex: Vec3,
    pub direction: Vec3,
    pub cos_outer: f32,
}

impl LightState {
    /// The cone of a spot light; None for the other kinds, which reach every direction.
    pub fn spot_cone(&self) -> Option<SpotCone> {
        match *self {
            LightState::Spot { position, direction, cos_outer, .. } => Some(SpotCone {
                apex: position,
                direction,
                cos_outer,
            }),
            _ => None,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            LightState::Point { .. } => "point",
            LightState::Spot { .. } => "spot",
            LightState::Directional { .. } => "directional",
        }
    }

    /// The light's position, or None for a directional light.
    pub fn position(&self) -> Option<Vec3> {
        match self {
            LightState::Point { position, .. } | LightState::Spot { position, .. } => {
                Some(*position)
            }
            LightState::Directional { .. } => None,
        }
    }

    /// Radiant intensity I(ω) in W/sr toward world point `x` (falloff and pattern included).
    /// For a directional light this is its irradiance E (W/m²), whatever `x`.
    pub fn intensity_toward(&self, x: DVec3) -> DVec3 {
        match self {
            LightState::Point { intensity, .. } => intensity.as_dvec3(),
            LightState::Directional { irradiance, .. } => irradiance.as_dvec3(),
            LightState::Spot {
                position,
                direction,
                cos_inner,
                cos_outer,
                tan_outer,
                intensity,
                pattern,
            } => {
                let w = x - position.as_dvec3();
                let len = w.length();
                if len <= 0.0 {
                    return DVec3::ZERO;
                }
                let axis = direction.as_dvec3();
                let cos_a = w.dot(axis) / len;
                let fall = spot_falloff(cos_a, *cos_inner as f64, *cos_outer as f64);
                if fall <= 0.0 {
                    return DVec3::ZERO;
                }
                let slide = match pattern {
                    None => DVec3::ONE,
                    Some(p) => {
                        let (u, v) = spot_uv(axis, *tan_outer as f64, w);
                        pattern_value(p, u, v)
                    }
                };
                intensity.as_dvec3() * fall * slide
            }
        }
    }
}

/// smoothstep(cos_outer, cos_inner, cos_angle): 1 inside the inner cone, 0 outside the outer.
pub fn spot_falloff(cos_angle: f64, cos_inner: f64, cos_outer: f64) -> f64 {
    if cos_angle >= cos_inner {
        return 1.0;
    }
    if cos_angle <= cos_outer {
        return 0.0;
    }
    let t = (cos_angle - cos_outer) / (cos_inner - cos_outer);
    t * t * (3.0 - 2.0 * t)
}

/// The spot's slide frame: (right, up) perpendicular to `axis`, right-handed with it.
/// `up` is the world Y projected out of the axis (world Z if the axis is vertical).
pub fn spot_frame(axis: DVec3) -> (DVec3, DVec3) {
    let hint = if axis.y.abs() > 0.999 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let right = axis.cross(hint).normalize();
    let up = right.cross(axis);
    (right, up)
}

/// Slide coordinates of direction `w` (from the light, any length) for a spot with unit
/// `axis` and outer half-angle tan `tan_outer`: u = ½ + ½ (w·right)/(w·axis)/tan_outer, v likewise
/// with `up`. The outer cone is the disc inscribed in [0,1]². Behind the light: (-1, -1).
pub fn spot_uv(axis: DVec3, tan_outer: f64, w: DVec3) -> (f64, f64) {
    let (right, up) = spot_frame(axis);
    let z = w.dot(axis);
    if z <= 0.0 {
        return (-1.0, -1.0);
    }
    let u = 0.5 + 0.5 * w.dot(right) / z / tan_outer;
    let v = 0.5 + 0.5 * w.dot(up) / z / tan_outer;
    (u, v)
}

/// Transmission (RGB in [0,1]) of a pattern at slide coordinates (u, v); 0 outside [0,1]².
pub fn pattern_value(p: &Pattern, u: f64, v: f64) -> DVec3 {
    if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
        return DVec3::ZERO;
    }
    match *p {
        Pattern::Checker { cells, dark } => {
            let n = cells.max(1) as f64;
            let (i, j) = (
                ((u * n).floor() as i64).min(cells as i64 - 1),
                ((v * n).floor() as i64).min(cells as i64 - 1),
            );
            if (i + j).rem_euclid(2) == 0 {
                DVec3::ONE
            } else {
                DVec3::splat(dark as f64)
            }
        }
        Pattern::StainedGlass { panes, seed, lead } => {
            let n = panes.max(1) as f64;
            let (fu, fv) = (u * n, v * n);
            let (i, j) = ((fu.floor()).min(n - 1.0), (fv.floor()).min(n - 1.0));
            let (lu, lv) = (fu - i, fv - j);
            let half = 0.5 * lead as f64;
            if lu < half || lu > 1.0 - half || lv < half || lv > 1.0 - half {
                return DVec3::ZERO;
            }
            pane_colour(seed, i as u32, j as u32)
        }
    }
}

/// Saturated colour of pane (i, j): a hash picks one of a small palette of glass colours.
fn pane_colour(seed: u32, i: u32, j: u32) -> DVec3 {
    const PALETTE: [[f64; 3]; 6] = [
        [0.9, 0.15, 0.1],
        [0.1, 0.35, 0.9],
        [0.95, 0.8, 0.1],
        [0.1, 0.75, 0.25],
        [0.6, 0.2, 0.8],
        [0.95, 0.95, 0.9],
    ];
    let mut h =
        seed.wrapping_mul(0x9E37_79B9) ^ i.wrapping_mul(0x85EB_CA6B) ^ j.wrapping_mul(0xC2B2_AE35);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7FEB_352D);
    h ^= h >> 15;
    DVec3::from_array(PALETTE[(h % PALETTE.len() as u32) as usize])
}

/// The slide coordinates at which `p` is discontinuous (the same set for u and v), so that
/// an integrator can split a ray exactly where the light changes.
pub fn pattern_breaks(p: &Pattern) -> Vec<f64> {
    match *p {
        Pattern::Checker { cells, .. } => (0..=cells).map(|k| k as f64 / cells as f64).collect(),
        Pattern::StainedGlass { panes, lead, .. } => {
            let n = panes as f64;
            let half = 0.5 * lead as f64;
            let mut out = Vec::with_capacity(2 * panes as usize + 2);
            for k in 0..panes {
                out.push((k as f64 + half) / n);
                out.push((k as f64 + 1.0 - half) / n);
            }
            out.push(0.0);
            out.push(1.0);
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spot_uv_maps_outer_cone_to_inscribed_circle() {
        let axis = DVec3::new(0.3, -1.0, 0.2).normalize();
        let tan_outer = 30f64.to_radians().tan();
        let (right, up) = spot_frame(axis);
        for k in 0..16 {
            let phi = k as f64 * std::f64::consts::TAU / 16.0;
            let w = axis + (right * phi.cos() + up * phi.sin()) * tan_outer;
            let (u, v) = spot_uv(axis, tan_outer, w * 3.7);
            let r = ((u - 0.5).powi(2) + (v - 0.5).powi(2)).sqrt();
            assert!((r - 0.5).abs() < 1e-12, "radius {r}");
        }
        assert_eq!(spot_uv(axis, tan_outer, axis), (0.5, 0.5));
    }

    #[test]
    fn falloff_is_a_smoothstep_between_the_cones() {
        let (ci, co) = (20f64.to_radians().cos(), 30f64.to_radians().cos());
        assert_eq!(spot_falloff(1.0, ci, co), 1.0);
        assert_eq!(spot_falloff(co - 1e-9, ci, co), 0.0);
        assert!((spot_falloff(0.5 * (ci + co), ci, co) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn patterns_change_only_at_their_breaks() {
        for p in [
            Pattern::Checker {
                cells: 5,
                dark: 0.1,
            },
            Pattern::StainedGlass {
                panes: 4,
                seed: 3,
                lead: 0.1,
            },
        ] {
            let mut breaks = pattern_breaks(&p);
            breaks.sort_by(f64::total_cmp);
            let v = 0.37;
            for w in breaks.windows(2) {
                let a = pattern_value(&p, w[0] + 1e-9, v);
                for s in 1..10 {
                    let u = w[0] + (w[1] - w[0]) * s as f64 / 10.0;
                    assert_eq!(
                        pattern_value(&p, u, v),
                        a,
                        "{p:?} changes inside ({}, {})",
                        w[0],
                        w[1]
                    );
                }
            }
        }
    }
}
