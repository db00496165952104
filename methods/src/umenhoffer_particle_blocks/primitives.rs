//! What the GPU draws from the blocks (Umenhoffer et al.'s hierarchy): one *primitive* per
//! block (or per particle, unblocked), the impostor *tiles* and the particles rendered into
//! them — the records blocks.wgsl mirrors — and each tile's frame for a frame. `blocks.rs`
//! builds a [`BlockSet`] of them once; the passes draw it every frame.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use scenes::particles::Particle;

/// One billboard the light pass and the final gathering draw. Mirrors `Prim` in blocks.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Prim {
    /// xyz: centre (m); w: half-size of the billboard (m) — the block's (or sphere's) bounding radius.
    pub center: [f32; 4],
    /// rgb: albedo; w: τ (1/m) of an analytic sphere, or the extinction multiplier of an instance.
    pub albedo: [f32; 4],
    /// x: instance scale (world m per prototype m); y: light tile (−1: analytic sphere);
    /// z: camera tile; w: unused.
    pub extra: [f32; 4],
}

/// One particle splatted into an impostor tile. Mirrors `ImpParticle` in blocks.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct ImpParticle {
    /// xyz: centre relative to its block's centroid (prototype metres); w: radius.
    pub pos: [f32; 4],
    /// x: τ (1/m); y: light tile; z: camera tile; w: unused.
    pub data: [f32; 4],
}

/// An impostor tile's orthographic frame for this frame. Mirrors `Tile` in blocks.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Tile {
    /// xyz: right; w: half-extent h of the tile (prototype metres).
    pub right: [f32; 4],
    /// xyz: up.
    pub up: [f32; 4],
    /// xyz: forward (the direction the impostor is rendered along).
    pub fwd: [f32; 4],
}

/// Which way a tile looks, decided per frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TileView {
    /// Along the light, toward this anchor (a cluster centroid or the cloud's centroid).
    Light(Vec3),
    /// Along the camera ray toward this anchor.
    Camera(Vec3),
}

/// Everything the passes draw, built once in `prepare`.
pub struct BlockSet {
    /// Unsorted; the gather sorts them back to front each frame.
    pub prims: Vec<Prim>,
    pub imp: Vec<ImpParticle>,
    /// One per tile: its direction rule and half-extent.
    pub tiles: Vec<(TileView, f32)>,
    /// Particles per block (mean), for the report.
    pub per_block: f64,
    /// Centroid of all particles.
    pub centroid: Vec3,
    /// Built from the scene's declared block instances (not from clusters).
    pub declared: bool,
    /// Each primitive's own particles (indices into the scene's), in `prims` order: a block's
    /// cluster or declared instance, a sphere's one particle (`held.rs` draws a block that holds
    /// a viewer as these).
    pub members: Vec<Vec<usize>>,
}

/// A stable orthonormal (right, up) pair perpendicular to `dir`; the same rule as `basis_of`
/// in blocks.wgsl, so a cluster's tile and its billboard share their orientation.
pub fn basis_of(dir: Vec3) -> (Vec3, Vec3) {
    let up_ref = if dir.y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
    let right = dir.cross(up_ref).normalize();
    (right, right.cross(dir))
}

/// A scene particle as an analytic sphere primitive (exact chord per fragment, no impostor).
pub fn sphere(p: &Particle) -> Prim {
    Prim {
        center: [p.center.x, p.center.y, p.center.z, p.radius],
        albedo: [p.albedo.x, p.albedo.y, p.albedo.z, p.density],
        extra: [1.0, -1.0, -1.0, 0.0],
    }
}

/// This frame's tile frames: light tiles look along the light (directional: its propagation
/// direction; local: from the light to the anchor), camera tiles from the eye to the anchor.
pub fn tile_frames(
    tiles: &[(TileView, f32)],
    eye: Vec3,
    light_dir: Option<Vec3>,
    light_pos: Option<Vec3>,
) -> Vec<Tile> {
    tiles
        .iter()
        .map(|&(view, h)| {
            let fwd = match view {
                TileView::Camera(a) => (a - eye).try_normalize().unwrap_or(Vec3::Z),
                TileView::Light(a) => match (light_dir, light_pos) {
                    (Some(d), _) => d,
                    (None, Some(p)) => (a - p).try_normalize().unwrap_or(Vec3::NEG_Y),
                    (None, None) => Vec3::NEG_Y,
                },
            };
            let (r, u) = basis_of(fwd);
            Tile {
                right: [r.x, r.y, r.z, h],
                up: [u.x, u.y, u.z, 0.0],
                fwd: [fwd.x, fwd.y, fwd.z, 0.0],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_and_perpendicular() {
        for d in [
            Vec3::X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::new(0.3, -1.0, 0.2).normalize(),
        ] {
            let (r, u) = basis_of(d);
            assert!((r.length() - 1.0).abs() < 1e-5 && (u.length() - 1.0).abs() < 1e-5);
            assert!(r.dot(d).abs() < 1e-5 && u.dot(d).abs() < 1e-5 && r.dot(u).abs() < 1e-5);
        }
    }
}
