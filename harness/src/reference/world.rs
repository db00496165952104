//! The scene at one frame as the reference sees it: world-space f64 triangles with their
//! shading data, one BVH over all of them.

use glam::{DVec3, Mat3};
use scenes::desc::Material;
use scenes::{FrameState, Scene};

use super::bvh::{Bvh, Tri};

/// Shading data of one triangle, indexed like the BVH's leaf-ordered triangles.
#[derive(Clone, Debug)]
pub struct Shading {
    pub n: [DVec3; 3],
    pub material: u32,
}

pub struct World {
    pub bvh: Bvh,
    pub shading: Vec<Shading>,
    pub materials: Vec<Material>,
}

impl World {
    pub fn new(scene: &Scene, frame: &FrameState) -> World {
        let mut tris = Vec::with_capacity(scene.triangle_count());
        let mut shading = Vec::with_capacity(scene.triangle_count());
        let mut materials = Vec::with_capacity(scene.meshes.len());
        for (k, (mesh, obj)) in scene.meshes.iter().zip(&scene.desc.objects).enumerate() {
            let m = frame.world_from_local[k];
            let md = m.as_dmat4();
            let normal_m = Mat3::from_mat4(m).inverse().transpose().as_dmat3();
            let flip = md.determinant() < 0.0;
            materials.push(obj.material.clone());
            for idx in &mesh.indices {
                let mut ids = [idx[0] as usize, idx[1] as usize, idx[2] as usize];
                if flip {
                    ids.swap(1, 2);
                }
                let p = ids.map(|i| md.transform_point3(mesh.positions[i].as_dvec3()));
                let n = ids.map(|i| (normal_m * mesh.normals[i].as_dvec3()).normalize_or_zero());
                tris.push(Tri {
                    p,
                    casts_shadow: obj.casts_volumetric_shadow,
                });
                shading.push(Shading {
                    n,
                    material: k as u32,
                });
            }
        }
        let bvh = Bvh::build(tris);
        let shading = bvh
            .order
            .iter()
            .map(|&i| shading[i as usize].clone())
            .collect();
        World {
            bvh,
            shading,
            materials,
        }
    }

    /// A length scale of the scene (for offsets): the largest coordinate magnitude, ≥ 1.
    pub fn scale(&self) -> f64 {
        self.bvh
            .tris
            .iter()
            .flat_map(|t| t.p)
            .map(|p| p.abs().max_element())
            .fold(1.0, f64::max)
    }
}
