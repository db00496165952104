//! The GPU layout of eq. 7's Δ_i tables (`spot.rs`, read by `spot.wgsl`): every spot of the
//! scene, built once at prepare from frame 0, in the spot's own frame (right, up, axis) so that a
//! moving or turning spot keeps its tables. The tables hold falloff × pattern (unitless RGB); the
//! shader multiplies by the light's intensity of the frame. A spot whose cone or pattern is
//! keyframed would need a rebuild — the library has none.

use glam::{DVec3, Vec3};
use scenes::Scene;
use scenes::light::{LightState, spot_frame};

use super::spot::HalfCircles;

/// γ samples per half circle (uniform on [−π/2, π/2]).
pub const GAMMA_SAMPLES: usize = 128;
/// Midpoint-rule points per γ interval when building (the patterns are piecewise constant).
const SUB: usize = 4;
/// Δ_0 … Δ_8 are stored for every order (the shader indexes a fixed stride).
const STORED_ORDER: usize = 8;

/// Tables of all lights, and per light its uniform words ([offset, n_u, n_phi, m], [u_max, is spot]).
pub struct SpotTables {
    pub data: Vec<[f32; 4]>,
    pub slots: Vec<([u32; 4], [f32; 4])>,
}

/// Unit-intensity copy of a spot, for falloff × pattern alone.
fn unit(light: &LightState) -> LightState {
    let mut l = light.clone();
    if let LightState::Spot { intensity, .. } = &mut l {
        *intensity = Vec3::ONE;
    }
    l
}

/// Δ tables of every spot of `scene` at frame 0, `n` half circles per grid unit.
pub fn build(scene: &Scene, n: u32) -> SpotTables {
    let frame = scene.frame(0);
    let mut data: Vec<[f32; 4]> = Vec::new();
    let mut slots = Vec::new();
    for light in &frame.lights {
        let Some(cone) = light.spot_cone() else {
            slots.push(([0; 4], [0.0; 4]));
            continue;
        };
        let axis = cone.direction.as_dvec3();
        let (r, u) = spot_frame(axis);
        let l = unit(light);
        let p = cone.apex.as_dvec3();
        let f = |w: DVec3| {
            l.intensity_toward(p + r * w.x + u * w.y + axis * w.z)
                .to_array()
        };
        let outer = (cone.cos_outer as f64).clamp(-1.0, 1.0).acos();
        let n = n as usize;
        match HalfCircles::new(STORED_ORDER, n, 2 * n, GAMMA_SAMPLES, outer, SUB, f) {
            Ok(t) => {
                let offset = data.len() as u32;
                data.extend(
                    t.raw()
                        .iter()
                        .map(|v| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0]),
                );
                slots.push((
                    [offset, t.n_u as u32, t.n_phi as u32, t.m as u32],
                    [t.u_max as f32, 1.0, 0.0, 0.0],
                ));
            }
            // `support` refuses such spots before we get here; keep the light dark otherwise.
            Err(_) => slots.push(([0; 4], [0.0; 4])),
        }
    }
    if data.is_empty() {
        data.push([0.0; 4]);
    }
    SpotTables { data, slots }
}
