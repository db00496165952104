//! Which lights can reach the froxel grid this frame (issue 19: "no injection for lights that
//! cannot reach the frustum"). Point and directional lights have no range (1/r² and the sun
//! reach everywhere), so only a spot light can miss: its cone lies wholly outside one plane of
//! the view frustum. The test is conservative — a cone it keeps may still miss the frustum past
//! one of its edges, a cone it drops cannot light any froxel.

use glam::{Mat4, Vec3, Vec4};
use scenes::LightState;

/// The six planes of the frustum of `clip_from_world` (wgpu clip space, depth in [0, 1]), as
/// (n, d) with n·x + d ≥ 0 inside, n not normalised (Gribb & Hartmann 2001).
pub fn frustum_planes(clip_from_world: Mat4) -> [Vec4; 6] {
    let m = clip_from_world.transpose();
    let (r0, r1, r2, r3) = (m.x_axis, m.y_axis, m.z_axis, m.w_axis);
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2]
}

/// Whether a cone (apex, unit axis, half-angle with sine `sin_half`) lies wholly on the outer
/// side of plane (n, d): its apex is outside and no direction within the cone leans inward,
/// i.e. the angle between the axis and the inward normal is at least 90° + the half-angle.
pub fn cone_outside_plane(apex: Vec3, axis: Vec3, sin_half: f32, plane: Vec4) -> bool {
    let n = plane.truncate();
    let len = n.length();
    if len <= 0.0 {
        return false;
    }
    let outside = n.dot(apex) + plane.w < 0.0;
    outside && n.dot(axis) / len <= -sin_half
}

/// Whether `light` can contribute to any point of the frustum of `clip_from_world`.
pub fn reaches(light: &LightState, clip_from_world: Mat4) -> bool {
    let Some(cone) = light.spot_cone() else {
        return true;
    };
    let cos_outer = cone.cos_outer;
    let sin_half = (1.0 - cos_outer * cos_outer).max(0.0).sqrt();
    let sin_half = if cos_outer < 0.0 { 1.0 } else { sin_half };
    let axis = cone.direction.normalize_or_zero();
    !frustum_planes(clip_from_world)
        .iter()
        .any(|&p| cone_outside_plane(cone.apex, axis, sin_half, p))
}

#[cfg(test)]
#[path = "reach_tests.rs"]
mod tests;
