//! The light maps of one light for this frame (Umenhoffer et al. §2.2's light pass needs one
//! map looking at the whole cloud): the projection, the depth range the primitives span along
//! the light and the slice depths, written into the uniform's views of light k.
//!
//! - A directional light: one orthographic map along the light (the paper).
//! - A local light outside every primitive's bounds that sees the whole cloud within an 80°
//!   half-angle cone: one perspective map around the axis toward the cloud (the paper).
//! - Otherwise (the light inside a block's bounds or among the particles, or the cloud spread
//!   around it): a cube of six perspective maps with 90° fields, one per axis direction, as
//!   omnidirectional shadow maps do — the light pass runs once per face (counter
//!   `light_faces`); a block whose bounds hold the light is drawn as its particles (held.rs),
//!   a sphere holding it covers its faces whole (light.wgsl). Each face's slices span the depth
//!   range of the primitives that face can see.
//! - A spot light whose cone reaches no primitive's bounds: no map at all (its light pass and
//!   surface-shadow pass are skipped; nothing it lights is behind the cloud).

use glam::{Vec2, Vec3};
use scenes::LightState;

use super::passes::{FACES, PbUniform, ViewUniform};
use super::primitives::{Prim, basis_of};
use crate::common::shadow_maps::CUBE_FACE_AXES;
use crate::common::sphere_cone::{SphereSeen, cone_reaches_sphere};

/// The widest half-angle (degrees) one perspective light map is used for.
pub const MAX_HALF_ANGLE_DEG: f32 = 80.0;
/// A primitive's bounds for the light map: its billboard half-size times this.
const BOUNDS: f32 = 1.2;
/// tan of a cube face's half-angle: a little over 1 so that face edges are never sampled
/// outside the rendered area.
const CUBE_TAN: f32 = 1.02;

fn centre(p: &Prim) -> Vec3 {
    Vec3::new(p.center[0], p.center[1], p.center[2])
}

/// Writes light `k`'s maps into `u.views[FACES·k ..]` and `u.maps[k]`; returns how many (0 when
/// there are no primitives, 1, or FACES for a cube).
pub fn light_views(
    light: &LightState,
    prims: &[Prim],
    centroid: Vec3,
    slices: u32,
    k: usize,
    u: &mut PbUniform,
) -> u32 {
    if prims.is_empty() || !reaches(light, prims) {
        u.maps[k] = [0.0; 4];
        return 0;
    }
    let base = FACES * k;
    let count = match light {
        LightState::Directional { direction, .. } => {
            u.views[base] = directional(direction.normalize(), prims, slices);
            1
        }
        _ => {
            let lp = light.position().unwrap_or(Vec3::ZERO);
            if let Some(v) = single_perspective(lp, prims, centroid, slices) {
                u.views[base] = v;
                1
            } else {
                for (f, v) in cube(lp, prims, slices).into_iter().enumerate() {
                    u.views[base + f] = v;
                }
                FACES as u32
            }
        }
    };
    u.maps[k] = [count as f32, 0.0, 0.0, 0.0];
    count
}

/// Whether the light can light any primitive: false only for a spot whose cone (its outer
/// angle) misses every primitive's bounding sphere.
fn reaches(light: &LightState, prims: &[Prim]) -> bool {
    let Some(cone) = light.spot_cone() else {
        return true;
    };
    let (axis, outer) = (cone.direction.normalize(), cone.cos_outer.clamp(-1.0, 1.0).acos());
    prims
        .iter()
        .any(|p| cone_reaches_sphere(cone.apex, axis, outer, centre(p), p.center[3] * BOUNDS))
}

/// S slices spread evenly over [dmin, dmax]: slice s at dmin + (dmax − dmin)(s + 1)/S
/// (blocks.wgsl `slice_depth`).
fn with_slices(mut v: ViewUniform, dmin: f32, dmax: f32, slices: u32) -> ViewUniform {
    v.range = [dmin, dmax, slices.max(1) as f32, 0.0];
    v
}

fn directional(l: Vec3, prims: &[Prim], slices: u32) -> ViewUniform {
    let (r, up) = basis_of(l);
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    let (mut dmin, mut dmax) = (f32::INFINITY, f32::NEG_INFINITY);
    for p in prims {
        let c = centre(p);
        let h = p.center[3] * BOUNDS;
        let a = Vec2::new(c.dot(r), c.dot(up));
        lo = lo.min(a - h);
        hi = hi.max(a + h);
        dmin = dmin.min(c.dot(l) - h);
        dmax = dmax.max(c.dot(l) + h);
    }
    let mid = (lo + hi) * 0.5;
    let ext = ((hi - lo) * 0.5).max_element().max(1e-4);
    let c = r * mid.x + up * mid.y;
    let v = ViewUniform {
        u: [r.x, r.y, r.z, 0.0],
        v: [up.x, up.y, up.z, 0.0],
        w: [l.x, l.y, l.z, 0.0],
        p: [c.x, c.y, c.z, ext],
        ..Default::default()
    };
    with_slices(v, dmin, dmax, slices)
}

/// A perspective map with axis `axis` and half-angle tangent `tan` at `lp`.
fn perspective(lp: Vec3, axis: Vec3, tan: f32) -> ViewUniform {
    let (r, up) = basis_of(axis);
    ViewUniform {
        u: [r.x, r.y, r.z, 1.0],
        v: [up.x, up.y, up.z, 0.0],
        w: [axis.x, axis.y, axis.z, 0.0],
        p: [lp.x, lp.y, lp.z, tan],
        ..Default::default()
    }
}

/// The paper's single map, if the light is outside every primitive's bounds and sees the cloud
/// within MAX_HALF_ANGLE_DEG of the axis toward its centroid.
fn single_perspective(
    lp: Vec3,
    prims: &[Prim],
    centroid: Vec3,
    slices: u32,
) -> Option<ViewUniform> {
    let axis = (centroid - lp).try_normalize()?;
    let (mut half, mut dmin, mut dmax) = (0.0f32, f32::INFINITY, f32::NEG_INFINITY);
    for p in prims {
        let h = p.center[3] * BOUNDS;
        let s = SphereSeen::from(lp, axis, centre(p), h).filter(|s| s.distance > h * 1.01)?;
        half = half.max(s.farthest());
        dmin = dmin.min(s.distance - h);
        dmax = dmax.max(s.distance + h);
    }
    if half > MAX_HALF_ANGLE_DEG.to_radians() {
        return None;
    }
    let v = perspective(lp, axis, half.tan() * 1.01);
    Some(with_slices(v, dmin.max(0.0), dmax, slices))
}

/// The eye's slice view (knob `eye_slices`): a perspective map at `eye` along `axis` whose
/// square field (half-angle tangent `tan`) covers the screen, its slices spanning the depth
/// range of the primitives in front of the eye.
pub fn eye_view(eye: Vec3, axis: Vec3, tan: f32, prims: &[Prim], slices: u32) -> ViewUniform {
    let v = perspective(eye, axis, tan);
    let (mut dmin, mut dmax) = (f32::INFINITY, f32::NEG_INFINITY);
    for p in prims {
        let q = centre(p) - eye;
        let h = p.center[3] * BOUNDS;
        if q.dot(axis) + h > 0.0 {
            dmin = dmin.min(q.length() - h);
            dmax = dmax.max(q.length() + h);
        }
    }
    if dmin > dmax {
        (dmin, dmax) = (0.0, 1e-3);
    }
    with_slices(v, dmin.max(0.0), dmax, slices)
}

/// Six 90° perspective maps around `lp`; each face's depth range covers the primitives whose
/// bounding spheres reach into its frustum (a plane test against its four sides).
// Faces in `CUBE_FACE_AXES` order, the order blocks.wgsl's `view_of` indexes them.
fn cube(lp: Vec3, prims: &[Prim], slices: u32) -> Vec<ViewUniform> {
    let side = (1.0 + CUBE_TAN * CUBE_TAN).sqrt();
    CUBE_FACE_AXES
        .iter()
        .map(|&axis| {
            let v = perspective(lp, axis, CUBE_TAN);
            let (r, up) = basis_of(axis);
            let (mut dmin, mut dmax) = (f32::INFINITY, f32::NEG_INFINITY);
            for p in prims {
                let q = centre(p) - lp;
                let h = p.center[3] * BOUNDS;
                let z = q.dot(axis);
                let (x, y) = (q.dot(r).abs(), q.dot(up).abs());
                if z + h > 0.0 && x - CUBE_TAN * z <= h * side && y - CUBE_TAN * z <= h * side {
                    let d = q.length();
                    dmin = dmin.min(d - h);
                    dmax = dmax.max(d + h);
                }
            }
            if dmin > dmax {
                (dmin, dmax) = (0.0, 1e-3);
            }
            with_slices(v, dmin.max(0.0), dmax, slices)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prim(c: Vec3, r: f32) -> Prim {
        Prim {
            center: [c.x, c.y, c.z, r],
            albedo: [1.0; 4],
            extra: [1.0, -1.0, -1.0, 0.0],
        }
    }

    fn spot(direction: Vec3, outer_deg: f32) -> LightState {
        let outer = outer_deg.to_radians();
        LightState::Spot {
            position: Vec3::ZERO,
            direction,
            cos_inner: outer.cos(),
            cos_outer: outer.cos(),
            tan_outer: outer.tan(),
            intensity: Vec3::ONE,
            pattern: None,
        }
    }

    /// Maps per light: a sun 1; a point light outside the cloud 1, inside a block 6; a spot 1
    /// when its cone reaches a block's bounds (even by its edge), 0 when it points away.
    #[test]
    fn maps_per_light() {
        let prims = [
            prim(Vec3::new(0.0, 0.0, 5.0), 1.0),
            prim(Vec3::new(1.0, 0.0, 6.0), 1.0),
        ];
        let c = Vec3::new(0.5, 0.0, 5.5);
        let mut u: PbUniform = bytemuck::Zeroable::zeroed();
        let mut views = |l: &LightState| light_views(l, &prims, c, 4, 1, &mut u);
        let sun = LightState::Directional {
            direction: Vec3::NEG_Y,
            irradiance: Vec3::ONE,
        };
        let point = |p: Vec3| LightState::Point {
            position: p,
            intensity: Vec3::ONE,
        };
        assert_eq!(views(&sun), 1);
        assert_eq!(views(&point(Vec3::ZERO)), 1);
        assert_eq!(views(&point(Vec3::new(0.2, 0.0, 5.0))), FACES as u32);
        assert_eq!(views(&spot(Vec3::Z, 20.0)), 1);
        // 30° to the side of the first block, away from the second: the first block's 1.2 m
        // bounds subtend 13.9° at 5 m, so a 20° cone reaches them and a 10° cone does not.
        let (s, c30) = (30f32.to_radians().sin(), 30f32.to_radians().cos());
        let off = Vec3::new(-s, 0.0, c30);
        assert_eq!(views(&spot(off, 20.0)), 1);
        assert_eq!(views(&spot(off, 10.0)), 0);
        assert_eq!(views(&spot(Vec3::NEG_Z, 60.0)), 0);
        assert_eq!(
            u.maps[1][0], 0.0,
            "a light without maps is marked so for the shaders"
        );
    }
}
