//! Which light-volume faces a frame draws, and where their open directions end: per light, the
//! shadow-map faces that can hold lit space the camera sees (all six cube faces of a point
//! light, those the cone reaches for a spot, the orthographic face of a directional light), the
//! cap distance, the spot's collapse cone, or why the light needs no volume at all.

use glam::{Mat4, Vec3};
use scenes::{FrameState, LightState};

use crate::common::shadow_maps::CUBE_FACE_AXES;
use crate::common::sphere_cone::cone_reaches_sphere;
use crate::common::uniforms::ShadowSlot;

/// Half the angle a cube face spans to its corner: atan(√2) (radians).
const FACE_CORNER_ANGLE: f32 = 0.955_316_6;

/// One face to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceDraw {
    /// Index into the light's `ShadowSlot::clip_from_world` (0 for directional light).
    pub face: u32,
    pub world_from_clip: Mat4,
}

/// A light's volume this frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LightPlan {
    pub faces: Vec<FaceDraw>,
    /// Local lights: distance from the light where open directions end (m); directional: the
    /// shadow volume's cap depth along the light (m). Beyond everything the camera sees.
    pub cap: f32,
    /// Spot lights: grid vertices whose direction has a smaller cosine to the axis collapse onto
    /// the light (−2: never).
    pub collapse_cos: f32,
    pub axis: Vec3,
}

/// The eight corners of the camera's view frustum (world).
pub fn frustum_corners(frame: &FrameState, aspect: f32) -> [Vec3; 8] {
    let world_from_clip = frame.camera.clip_from_world(aspect).inverse();
    let mut out = [Vec3::ZERO; 8];
    for (k, c) in out.iter_mut().enumerate() {
        let x = if k & 1 == 0 { -1.0 } else { 1.0 };
        let y = if k & 2 == 0 { -1.0 } else { 1.0 };
        let z = if k & 4 == 0 { 0.0 } else { 1.0 };
        *c = world_from_clip.project_point3(Vec3::new(x, y, z));
    }
    out
}

/// The volume of `light` this frame, or why it has none. `casters`: the bounding sphere of the
/// shadow casters (None: no caster); `samples`: grid samples per face side.
pub fn plan(
    light: &LightState,
    slot: &ShadowSlot,
    corners: &[Vec3; 8],
    casters: Option<(Vec3, f32)>,
    samples: u32,
) -> Result<LightPlan, &'static str> {
    let Some((centre, radius)) = casters else {
        return Err("no object casts a volumetric shadow");
    };
    let face = |k: u32| FaceDraw {
        face: k,
        world_from_clip: slot.clip_from_world[k as usize].inverse(),
    };
    match light {
        LightState::Directional { direction, .. } => {
            let deepest = corners
                .iter()
                .map(|c| c.dot(*direction))
                .fold(f32::MIN, f32::max);
            let cap = deepest.max(centre.dot(*direction) + radius) + 1.0;
            Ok(LightPlan {
                faces: vec![face(0)],
                cap,
                collapse_cos: -2.0,
                axis: *direction,
            })
        }
        LightState::Point { position, .. } => Ok(LightPlan {
            faces: (0..6).map(face).collect(),
            cap: cap_distance(*position, corners),
            collapse_cos: -2.0,
            axis: Vec3::Z,
        }),
        LightState::Spot {
            position,
            direction,
            cos_outer,
            ..
        } => {
            let outer = cos_outer.clamp(-1.0, 1.0).acos();
            if !cone_reaches_sphere(*position, *direction, outer, centre, radius) {
                return Err("no shadow caster inside the spot's cone");
            }
            // Grid cells span at most 2/samples radians; vertices three cells beyond the cone
            // collapse, so every triangle reaching into the cone keeps its true vertices.
            let margin = 3.0 * 2.0 / samples as f32;
            let faces = (0..6u32)
                .filter(|k| {
                    CUBE_FACE_AXES[*k as usize]
                        .dot(*direction)
                        .clamp(-1.0, 1.0)
                        .acos()
                        < outer + FACE_CORNER_ANGLE + margin
                })
                .map(face)
                .collect();
            let collapse = outer + margin;
            Ok(LightPlan {
                faces,
                cap: cap_distance(*position, corners),
                collapse_cos: if collapse >= std::f32::consts::PI {
                    -2.0
                } else {
                    collapse.cos()
                },
                axis: *direction,
            })
        }
    }
}

/// Farther from `light` than any point of the camera's frustum (the convex hull of its
/// corners, so the farthest point is a corner), plus a margin.
fn cap_distance(light: Vec3, corners: &[Vec3; 8]) -> f32 {
    let far = corners
        .iter()
        .map(|c| (*c - light).length())
        .fold(0.0, f32::max);
    far * 1.01 + 1.0
}

/// Triangles of one face's volume at `samples` grid samples per side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangles {
    /// The displaced grid (and, directional light, as many again for the cap).
    pub grid: u64,
    pub walls: u64,
    pub directional: bool,
}

impl Triangles {
    pub fn total(&self) -> u64 {
        self.grid * if self.directional { 2 } else { 1 } + self.walls
    }
}

pub fn triangles(directional: bool, samples: u32) -> Triangles {
    let e = samples as u64 + 1;
    Triangles {
        grid: 2 * e * e,
        walls: 8 * e,
        directional,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_counts_follow_the_grid() {
        assert_eq!(triangles(false, 3).total(), 2 * 16 + 32);
        assert_eq!(triangles(true, 3).total(), 2 * 2 * 16 + 32);
    }
}
