//! Triangle meshes: the type every consumer uses, procedural generators and OBJ loading.

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
