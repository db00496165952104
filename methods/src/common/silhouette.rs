//! Silhouette edges as seen from a light, and the shadow-volume quads extruded from them —
//! shared by every shadow-volume method (Wyman & Ramsey's hybrid, both Biri methods).
//!
//! A mesh is welded by exact position (procedural meshes duplicate vertices at hard edges, with
//! bitwise-equal positions), then each undirected edge lists the faces that use it. An edge is
//! on the silhouette when its faces disagree about facing the light; an edge with one face (an
//! open mesh's border) is on it when that face faces the light; an edge with more than two
//! faces (non-manifold, e.g. the fence's touching bars) when not all of them agree. Each
//! silhouette edge is oriented as its light-facing face traverses it, so the extruded quad winds
//! outward (front-facing from outside the shadow), which stencil methods need.

use std::collections::HashMap;

use glam::{Mat4, Vec3};
use scenes::TriMesh;

/// Where the light is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightPos {
    Point(Vec3),
    /// Propagation direction (unit).
    Direction(Vec3),
}

/// A mesh with edge adjacency, in local space.
#[derive(Clone, Debug)]
pub struct EdgeMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// (a, b, faces using the edge) with a < b.
    edges: Vec<(u32, u32, Vec<u32>)>,
}

impl EdgeMesh {
    pub fn new(mesh: &TriMesh) -> EdgeMesh {
        let mut index: HashMap<[u32; 3], u32> = HashMap::new();
        let mut positions = Vec::new();
        let remap: Vec<u32> = mesh
            .positions
            .iter()
            .map(|p| {
                *index
                    .entry(p.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        positions.push(*p);
                        positions.len() as u32 - 1
                    })
            })
            .collect();
        let triangles: Vec<[u32; 3]> = mesh
            .indices
            .iter()
            .map(|t| t.map(|i| remap[i as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let mut map: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
        for (f, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                map.entry((a.min(b), a.max(b))).or_default().push(f as u32);
            }
        }
        let mut edges: Vec<(u32, u32, Vec<u32>)> =
            map.into_iter().map(|((a, b), f)| (a, b, f)).collect();
        edges.sort_by_key(|e| (e.0, e.1));
        EdgeMesh {
            positions,
            triangles,
            edges,
        }
    }

    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Whether every edge has exactly two faces, traversing it in opposite directions: a closed,
    /// consistently wound 2-manifold, which silhouette shadow volumes need (Biri et al. §IV.B).
    pub fn is_closed_manifold(&self) -> bool {
        let forward = |f: u32, a: u32, b: u32| {
            let t = self.triangles[f as usize];
            (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
        };
        self.edges.iter().all(|(a, b, faces)| {
            faces.len() == 2 && forward(faces[0], *a, *b) != forward(faces[1], *a, *b)
        })
    }

    /// World positions and, per triangle, its normal · direction to the light (> 0: lit side).
    fn world_facing(&self, world_from_local: &Mat4, light: LightPos) -> (Vec<Vec3>, Vec<f32>) {
        let world: Vec<Vec3> = self
            .positions
            .iter()
            .map(|p| world_from_local.transform_point3(*p))
            .collect();
        let facing = self
            .triangles
            .iter()
            .map(|t| {
                let (a, b, c) = (
                    world[t[0] as usize],
                    world[t[1] as usize],
                    world[t[2] as usize],
                );
                let n = (b - a).cross(c - a);
                let to_light = match light {
                    LightPos::Point(l) => l - (a + b + c) / 3.0,
                    LightPos::Direction(d) => -d,
                };
                n.dot(to_light)
            })
            .collect();
        (world, facing)
    }

    /// The fallback for open or non-manifold meshes: every triangle casts its own shadow volume,
    /// two-sided (an open surface shadows from either side), so its three edges are returned,
    /// oriented as its light-facing side winds them. Triangles edge-on to the light cast nothing.
    pub fn triangle_edges(&self, world_from_local: &Mat4, light: LightPos) -> Vec<[Vec3; 2]> {
        let (world, facing) = self.world_facing(world_from_local, light);
        let mut out = Vec::with_capacity(3 * self.triangles.len());
        for (t, f) in self.triangles.iter().zip(facing) {
            if f == 0.0 {
                continue;
            }
            let p = t.map(|i| world[i as usize]);
            for k in 0..3 {
                let (a, b) = (p[k], p[(k + 1) % 3]);
                out.push(if f > 0.0 { [a, b] } else { [b, a] });
            }
        }
        out
    }

    /// Silhouette edges in world space, each oriented as its light-facing face winds it.
    pub fn silhouette(&self, world_from_local: &Mat4, light: LightPos) -> Vec<[Vec3; 2]> {
        let (world, facing) = self.world_facing(world_from_local, light);
        let facing: Vec<bool> = facing.into_iter().map(|f| f > 0.0).collect();
        let mut out = Vec::new();
        for (a, b, faces) in &self.edges {
            let lit = faces.iter().filter(|f| facing[**f as usize]).count();
            let on = match faces.len() {
                1 => lit == 1,
                _ => lit > 0 && lit < faces.len(),
            };
            if !on {
                continue;
            }
            // Orient along a light-facing face's winding.
            let f = faces
                .iter()
                .find(|f| facing[**f as usize])
                .expect("some face is lit");
            let t = self.triangles[*f as usize];
            let forward = (0..3).any(|k| t[k] == *a && t[(k + 1) % 3] == *b);
            let (p, q) = (world[*a as usize], world[*b as usize]);
            out.push(if forward { [p, q] } else { [q, p] });
        }
        out
    }
}

/// The quad (two triangles) a silhouette edge sweeps away from the light, out to `reach` metres
/// from each endpoint: [p, q, q', p, q', p'] with p' = p + reach · (p − light)/|p − light|.
pub fn extrude(edge: [Vec3; 2], light: LightPos, reach: f32) -> [Vec3; 6] {
    let away = |v: Vec3| match light {
        LightPos::Point(l) => (v - l).normalize_or_zero(),
        LightPos::Direction(d) => d,
    };
    let [p, q] = edge;
    let (p2, q2) = (p + away(p) * reach, q + away(q) * reach);
    [p, q, q2, p, q2, p2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenes::mesh::procedural;

    /// A closed convex mesh seen from a point light has one closed silhouette loop: every
    /// silhouette vertex appears as a start exactly as often as as an end.
    #[test]
    fn a_sphere_has_one_closed_oriented_loop() {
        let mesh = EdgeMesh::new(&procedural::sphere(1.0, 24, 12));
        let sil = mesh.silhouette(&Mat4::IDENTITY, LightPos::Point(Vec3::new(0.3, 5.0, 0.2)));
        assert!(sil.len() >= 12, "{} edges", sil.len());
        let key = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut balance: HashMap<[u32; 3], i32> = HashMap::new();
        for [p, q] in &sil {
            *balance.entry(key(*p)).or_default() += 1;
            *balance.entry(key(*q)).or_default() -= 1;
        }
        assert!(
            balance.values().all(|b| *b == 0),
            "silhouette is not a set of closed loops"
        );
    }

    /// The silhouette of a box lit along an axis is the 4 edges around the lit face's sides.
    #[test]
    fn box_lit_from_above_has_four_side_edges() {
        let mesh = EdgeMesh::new(&procedural::cuboid(Vec3::ONE));
        let sil = mesh.silhouette(&Mat4::IDENTITY, LightPos::Direction(-Vec3::Y));
        assert_eq!(sil.len(), 4);
        for [p, q] in sil {
            assert!(p.y == q.y, "silhouette edges are horizontal");
        }
    }

    /// Procedural closed shapes are closed 2-manifolds once welded; a plane (open border) and
    /// the fence (touching bars share edges among four faces) are not.
    #[test]
    fn closed_manifold_detection() {
        use scenes::mesh::procedural as p;
        assert!(EdgeMesh::new(&p::sphere(1.0, 24, 12)).is_closed_manifold());
        assert!(EdgeMesh::new(&p::cuboid(Vec3::ONE)).is_closed_manifold());
        assert!(EdgeMesh::new(&p::cylinder(0.5, 2.0, 16)).is_closed_manifold());
        assert!(EdgeMesh::new(&p::pencil(0.05, 1.0, 0.1)).is_closed_manifold());
        assert!(!EdgeMesh::new(&p::plane(2.0, 2.0)).is_closed_manifold());
        assert!(!EdgeMesh::new(&p::fence(2.0, 1.0, 3, 2, 0.1)).is_closed_manifold());
        let quad = EdgeMesh::new(&p::plane(2.0, 2.0));
        let edges =
            quad.triangle_edges(&Mat4::IDENTITY, LightPos::Point(Vec3::new(0.0, -3.0, 0.0)));
        assert_eq!(edges.len(), 6, "two triangles, lit from below (two-sided)");
    }

    /// Extruded quads point away from the light and start at the edge.
    #[test]
    fn extrusion_goes_away_from_the_light() {
        let l = Vec3::new(0.0, 10.0, 0.0);
        let quad = extrude(
            [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0)],
            LightPos::Point(l),
            5.0,
        );
        assert_eq!(quad[0], Vec3::new(1.0, 0.0, 0.0));
        assert!(((quad[5] - l).length() - ((quad[0] - l).length() + 5.0)).abs() < 1e-4);
    }
}
