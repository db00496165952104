//! Triangle meshes: the type every consumer uses, procedural generators and OBJ loading.

pub mod atrium;
pub mod lathe;
pub mod memo;
pub mod obj;
pub mod procedural;
pub mod subdivide;

use glam::{Mat4, Vec3};

/// An indexed triangle mesh in local space. Counter-clockwise triangles seen from outside
/// (the side the normal faces). `normals[i]` is the shading normal of vertex `i`; hard edges
/// duplicate vertices, so welding by position is the consumer's job where it needs adjacency.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
}

impl TriMesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Surface area in local units², summed in f64 over the triangles.
    pub fn area(&self) -> f64 {
        self.indices
            .iter()
            .map(|&[a, b, c]| {
                let (pa, pb, pc) = (
                    self.positions[a as usize].as_dvec3(),
                    self.positions[b as usize].as_dvec3(),
                    self.positions[c as usize].as_dvec3(),
                );
                (pb - pa).cross(pc - pa).length() * 0.5
            })
            .sum()
    }

    /// Axis-aligned bounds (min, max) of the mesh after `world_from_local`.
    pub fn bounds(&self, world_from_local: &Mat4) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in &self.positions {
            let w = world_from_local.transform_point3(*p);
            lo = lo.min(w);
            hi = hi.max(w);
        }
        (lo, hi)
    }
}
