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
//!
//! Closed pieces (`EdgeMesh::components`): a caster that is a union of closed solids touching or
//! overlapping one another (the fence's posts and rails share edges among four faces) is not a
//! 2-manifold as a whole, but each solid is. Split at its non-manifold edges (faces joined only
//! across edges with exactly two faces), every closed piece casts its own silhouette volume
//! (Crow 1977; Heidmann 1991's counting: a point is in shadow where the count of volumes around
//! it is above zero, so overlapping volumes of touching solids need no union), and only the open
//! pieces fall back to per-triangle volumes — the per-piece decomposition that Kim et al. 2008
//! (*Robust shadow volumes for non-manifold geometry*) generalise with edge multiplicities.

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
    /// `mesh` welded by exact position, with its edge adjacency.
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
        EdgeMesh::welded(positions, triangles)
    }

    /// Edge adjacency of an already welded mesh (no degenerate triangles).
    fn welded(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> EdgeMesh {
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

    /// The mesh split into pieces whose faces are joined only across manifold edges (exactly two
    /// faces): a union of closed solids that touch along shared edges comes apart into its
    /// solids, each a closed 2-manifold again. A connected closed mesh is one piece (itself).
    /// Pieces are ordered by their first triangle.
    pub fn components(&self) -> Vec<EdgeMesh> {
        let mut root: Vec<u32> = (0..self.triangles.len() as u32).collect();
        fn find(root: &mut [u32], mut f: u32) -> u32 {
            while root[f as usize] != f {
                root[f as usize] = root[root[f as usize] as usize];
                f = root[f as usize];
            }
            f
        }
        for (_, _, faces) in self.edges.iter().filter(|e| e.2.len() == 2) {
            let (a, b) = (find(&mut root, faces[0]), find(&mut root, faces[1]));
            root[a.max(b) as usize] = a.min(b);
        }
        let mut piece_of_root: HashMap<u32, usize> = HashMap::new();
        let mut pieces: Vec<Vec<[u32; 3]>> = Vec::new();
        for (f, t) in self.triangles.iter().enumerate() {
            let r = find(&mut root, f as u32);
            let k = *piece_of_root.entry(r).or_insert_with(|| {
                pieces.push(Vec::new());
                pieces.len() - 1
            });
            pieces[k].push(*t);
        }
        if pieces.len() <= 1 {
            return vec![self.clone()];
        }
        pieces
            .into_iter()
            .map(|tris| {
                let mut local: HashMap<u32, u32> = HashMap::new();
                let mut positions = Vec::new();
                let triangles = tris
                    .iter()
                    .map(|t| {
                        t.map(|v| {
                            *local.entry(v).or_insert_with(|| {
                                positions.push(self.positions[v as usize]);
                                positions.len() as u32 - 1
                            })
                        })
                    })
                    .collect();
                EdgeMesh::welded(positions, triangles)
            })
            .collect()
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

    /// The fence is a union of touching closed boxes: not a 2-manifold as a whole, but it splits
    /// into one closed piece per bar (posts + rails), every triangle in exactly one piece. A
    /// connected closed mesh stays one piece; a plane stays one open piece.
    #[test]
    fn a_fence_splits_into_its_closed_bars() {
        use scenes::mesh::procedural as p;
        let fence = EdgeMesh::new(&p::fence(4.0, 2.4, 9, 4, 0.08));
        let pieces = fence.components();
        assert_eq!(pieces.len(), 9 + 4);
        assert!(pieces.iter().all(EdgeMesh::is_closed_manifold));
        let triangles: usize = pieces.iter().map(|m| m.triangles.len()).sum();
        assert_eq!(triangles, fence.triangles.len());
        assert!(pieces.iter().all(|m| m.triangles.len() == 12), "a box each");
        assert_eq!(EdgeMesh::new(&p::sphere(1.0, 24, 12)).components().len(), 1);
        let plane = EdgeMesh::new(&p::plane(2.0, 2.0)).components();
        assert_eq!(plane.len(), 1);
        assert!(!plane[0].is_closed_manifold());
    }

    /// A closed piece's silhouette bounds the same shadow as its triangles' own volumes: along
    /// a segment through a bar's shadow, the signed crossings of the silhouette quads (+1 into
    /// a volume, −1 out) give count > 0 exactly where the per-triangle quads' count is > 0. The
    /// shadow of the first post lit from above is a slanted column under it; the points run
    /// across it.
    #[test]
    fn piece_silhouette_and_triangle_volumes_shadow_the_same_points() {
        use scenes::mesh::procedural as p;
        let light = LightPos::Point(Vec3::new(0.3, 6.0, 0.2));
        let bar = &EdgeMesh::new(&p::fence(2.0, 1.0, 3, 2, 0.1)).components()[0];
        let inside = |edges: &[[Vec3; 2]], x: Vec3| {
            // Signed crossings of the quads on the segment from far off to the side (outside
            // every volume: they run down from the light) to x: entering a volume adds 1.
            let from = Vec3::new(-50.0, x.y, x.z);
            let mut n = 0i32;
            for e in edges {
                let q = extrude(*e, light, 100.0);
                for tri in [[q[0], q[1], q[2]], [q[3], q[4], q[5]]] {
                    if let Some(s) = crossing_sign(from, x, tri) {
                        n += s;
                    }
                }
            }
            n
        };
        let sil = bar.silhouette(&Mat4::IDENTITY, light);
        let tri = bar.triangle_edges(&Mat4::IDENTITY, light);
        assert!(sil.len() < tri.len() / 4, "{} vs {}", sil.len(), tri.len());
        let mut shadowed = 0;
        for i in 0..200 {
            let x = Vec3::new(-1.2 + 0.012 * i as f32, -0.9, -0.03);
            let (a, b) = (inside(&sil, x), inside(&tri, x));
            assert!(a >= 0 && b >= 0, "{x}: {a} {b}");
            assert_eq!(a > 0, b > 0, "{x}: silhouette {a}, triangles {b}");
            shadowed += (a > 0) as u32;
        }
        assert!(
            shadowed > 3 && shadowed < 197,
            "{shadowed} of 200 in shadow"
        );
    }

    /// +1 when the segment p → q crosses the triangle along (b − a) × (c − a), which points
    /// into the volume of an extruded quad (wound counter-clockwise seen from inside, clockwise
    /// on screen from outside: `common::shadow_volumes::stencil`'s front face), −1 against it,
    /// None when it
    /// misses.
    fn crossing_sign(p: Vec3, q: Vec3, [a, b, c]: [Vec3; 3]) -> Option<i32> {
        let n = (b - a).cross(c - a);
        let (dp, dq) = (n.dot(p - a), n.dot(q - a));
        if dp * dq >= 0.0 {
            return None;
        }
        let x = p + (q - p) * (dp / (dp - dq));
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|(u, v)| (*v - *u).cross(x - *u).dot(n) >= 0.0);
        inside.then_some(if dp < 0.0 { 1 } else { -1 })
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
