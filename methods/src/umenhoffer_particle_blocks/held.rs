//! Blocks that hold a viewer (the eye, or a local light), drawn as their particles.
//!
//! A block's depth impostor is an orthographic view of its particles from outside; from a point
//! inside the block's bounds the particles surround the viewer and no impostor (nor billboard)
//! describes them. Such a block is replaced, in that viewer's primitive list, by its particles
//! as analytic spheres (exact chords, as `particle-splat` draws every particle): for the eye in
//! the gathering's back-to-front list (in the block's place, sorted among themselves), for a
//! light in that light's list for the light pass. The particles are the scene's own particles
//! of the block's cluster or declared instance ([`Members`], from `BlockSet::members`) — also for
//! a prototype instance, whose impostor models the prototype's particles instead: near a viewer
//! the real geometry is drawn. Primitives (a block, or a sphere) still holding the
//! viewer are drawn over the whole view (blocks.wgsl `covers_viewer`).

use glam::Vec3;
use scenes::particles::Particle;

use super::primitives::{BlockSet, Prim, sphere};

/// Each block's own particles as analytic spheres, by block index (`Prim::extra[3]`, set by
/// [`Members::index`]).
pub struct Members {
    spheres: Vec<Vec<Prim>>,
    /// Per primitive, the radius about its centre that bounds both its drawn billboard and its
    /// own particles (a robust prototype's instance can be smaller than its cluster's outliers).
    bounds: Vec<f32>,
}

impl Members {
    /// Every primitive's own particles (`BlockSet::members`: its cluster or declared instance).
    pub fn of(ps: &[Particle], set: &BlockSet) -> Members {
        let spheres = |c: &Vec<usize>| c.iter().map(|&i| sphere(&ps[i])).collect();
        let bound = |(p, c): (&Prim, &Vec<usize>)| {
            let reach = |&i: &usize| (ps[i].center - centre(p)).length() + ps[i].radius;
            c.iter().map(reach).fold(p.center[3], f32::max)
        };
        Members {
            spheres: set.members.iter().map(spheres).collect(),
            bounds: set.prims.iter().zip(&set.members).map(bound).collect(),
        }
    }

    /// Whether primitive `p` is a block whose bounds hold `x`.
    pub fn holds(&self, p: &Prim, x: Vec3) -> bool {
        self.near(p, x, COVERS)
    }

    /// Whether primitive `p` is a block whose centre is within `factor` times its bounds
    /// (the larger of its billboard's radius and its particles' reach) of `x`.
    pub fn near(&self, p: &Prim, x: Vec3, factor: f32) -> bool {
        let bound = self.bounds[p.extra[3] as usize];
        p.extra[1] >= 0.0 && (centre(p) - x).length() < factor * bound
    }

    /// Numbers the blocks (`extra[3]`), which sorting moves.
    pub fn index(set: &mut [Prim]) {
        for (i, p) in set.iter_mut().enumerate() {
            p.extra[3] = i as f32;
        }
    }
}

/// A viewer nearer a primitive's centre than this times its radius is "inside": the same factor
/// as `covers_viewer` in blocks.wgsl (passed to it as the override `COVERS`).
pub const COVERS: f32 = 1.1;

fn centre(p: &Prim) -> Vec3 {
    Vec3::new(p.center[0], p.center[1], p.center[2])
}

/// The most spheres the blocks' particles can add to one list.
pub fn capacity(prims: &[Prim], members: &Members) -> usize {
    prims
        .iter()
        .zip(&members.spheres)
        .filter(|(p, _)| p.extra[1] >= 0.0)
        .map(|(_, c)| c.len())
        .sum()
}

/// `prims` with every block for which `replace` holds replaced by its particles, in place; with
/// `back_to_front`, those particles sorted by decreasing distance from `viewer`.
pub fn expand(
    prims: &[Prim],
    members: &Members,
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
        out.extend_from_slice(&members.spheres[p.extra[3] as usize]);
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
