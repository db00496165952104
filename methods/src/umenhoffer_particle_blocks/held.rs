//! Blocks that hold a viewer (the eye, or a local light), drawn as their particles.
//!
//! A block's depth impostor is an orthographic view of its particles from outside; from a point
//! inside the block's bounds the particles surround the viewer and no impostor (nor billboard)
//! describes them. Such a block is replaced, in that viewer's primitive list, by its particles
//! as analytic spheres (exact chords, as `particle-splat` draws every particle): for the eye in
//! the gathering's back-to-front list (in the block's place, sorted among themselves), for a
//! light in that light's list for the light pass. A prototype instance's particles are the
//! prototype's, moved and scaled to the instance (its optical depth multiplier kept), i.e.
//! exactly what the instance's impostor models. Primitives (a block, or a sphere) still holding
//! the viewer are drawn over the whole view (common.wgsl `covers_viewer`).

use glam::Vec3;

use super::blocks::{ImpParticle, Prim};

/// A viewer nearer a primitive's centre than this times its radius is "inside": the same factor
/// as `covers_viewer` in common.wgsl (passed to it as the override `COVERS`).
pub const COVERS: f32 = 1.1;

fn centre(p: &Prim) -> Vec3 {
    Vec3::new(p.center[0], p.center[1], p.center[2])
}

/// Whether primitive `p` is a block (not an analytic sphere) whose bounds hold `x`.
pub fn holds(p: &Prim, x: Vec3) -> bool {
    near(p, x, COVERS)
}

/// Whether primitive `p` is a block whose centre is within `factor` times its radius of `x`.
pub fn near(p: &Prim, x: Vec3, factor: f32) -> bool {
    p.extra[1] >= 0.0 && (centre(p) - x).length() < factor * p.center[3]
}

/// Block `p`'s particles as analytic spheres: the impostor particles of its light tile (every
/// particle of the prototype, or of its own cluster), scaled to the instance.
pub fn particles_of<'a>(p: &'a Prim, imp: &'a [ImpParticle]) -> impl Iterator<Item = Prim> + 'a {
    let (c, scale) = (centre(p), p.extra[0]);
    imp.iter().filter(move |e| e.data[1] == p.extra[1]).map(move |e| {
        let x = c + Vec3::new(e.pos[0], e.pos[1], e.pos[2]) * scale;
        Prim {
            center: [x.x, x.y, x.z, e.pos[3] * scale],
            albedo: [p.albedo[0], p.albedo[1], p.albedo[2], e.data[0] * p.albedo[3]],
            extra: [1.0, -1.0, -1.0, 0.0],
        }
    })
}

/// The most spheres the blocks' particles can add to one list.
pub fn capacity(prims: &[Prim], imp: &[ImpParticle]) -> usize {
    prims
        .iter()
        .filter(|p| p.extra[1] >= 0.0)
        .map(|p| imp.iter().filter(|e| e.data[1] == p.extra[1]).count())
        .sum()
}

/// `prims` with every block for which `replace` holds replaced by its particles, in place; with
/// `back_to_front`, those particles sorted by decreasing distance from `viewer`.
pub fn expand(
    prims: &[Prim],
    imp: &[ImpParticle],
    viewer: Vec3,
    back_to_front: bool,
    replace: impl Fn(&Prim) -> bool,
) -> Vec<Prim> {
    let mut out = Vec::with_capacity(prims.len());
    for p in prims {
        if !replace(p) {
            out.push(*p);
            continue;
        }
        let start = out.len();
        out.extend(particles_of(p, imp));
        if back_to_front {
            out[start..].sort_by(|a, b| {
                (centre(b) - viewer)
                    .length_squared()
                    .total_cmp(&(centre(a) - viewer).length_squared())
            });
        }
    }
    out
}
