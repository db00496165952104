//! Midpoint subdivision: every triangle split into four, shared edges split once.
//!
//! Used where the triangle count is the experiment's variable (scaling sweeps, per-vertex
//! evaluation in `biri-polynomial`, tessellation sweeps): the surface does not move — new vertices
//! lie on the old flat triangles — so images change only through the method's own sensitivity to
//! tessellation, never through a different shape.

use std::collections::HashMap;

use super::TriMesh;

/// `mesh` with each triangle split into 4^`levels` triangles. An edge shared by two triangles
/// (same two vertex indices) gets one midpoint, so index-welded meshes stay welded and
/// 2-manifold meshes stay 2-manifold. Midpoint normals are the normalised mean of the edge's.
pub fn subdivide(mesh: &TriMesh, levels: u32) -> TriMesh {
    let mut out = mesh.clone();
    for _ in 0..levels {
        out = subdivide_once(&out);
    }
    out
}

/// The fewest subdivision levels that bring `mesh` to at least `min_triangles`, and the result.
/// An empty mesh is returned unchanged with 0 levels.
pub fn subdivide_to(mesh: &TriMesh, min_triangles: usize) -> (u32, TriMesh) {
    let mut levels = 0;
    let mut out = mesh.clone();
    while out.triangle_count() < min_triangles && out.triangle_count() > 0 {
        out = subdivide_once(&out);
        levels += 1;
    }
    (levels, out)
}

fn subdivide_once(mesh: &TriMesh) -> TriMesh {
    let mut positions = mesh.positions.clone();
    let mut normals = mesh.normals.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(mesh.indices.len() * 2);
    let mut midpoint = |a: u32, b: u32| -> u32 {
        let key = (a.min(b), a.max(b));
        *midpoints.entry(key).or_insert_with(|| {
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            positions.push((pa + pb) * 0.5);
            let n = normals[a as usize] + normals[b as usize];
            normals.push(n.try_normalize().unwrap_or(normals[a as usize]));
            (positions.len() - 1) as u32
        })
    };
    let mut indices = Vec::with_capacity(mesh.indices.len() * 4);
    for &[a, b, c] in &mesh.indices {
        let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
        indices.extend_from_slice(&[[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    TriMesh {
        positions,
        normals,
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::procedural;

    #[test]
    fn quadruples_triangles_and_keeps_area_and_welding() {
        let sphere = procedural::sphere(1.0, 12, 6);
        let fine = subdivide(&sphere, 2);
        assert_eq!(fine.triangle_count(), sphere.triangle_count() * 16);
        // The surface is unchanged: same area (flat split), same bounds.
        let (a0, a1) = (TriMesh::area(&sphere), TriMesh::area(&fine));
        assert!((a0 - a1).abs() < 1e-5 * a0, "{a0} vs {a1}");
        // Midpoint subdivision preserves V − E + F (V' = V + E, E' = 2E + 3F, F' = 4F), and only
        // does so if every shared edge got exactly one midpoint.
        let euler = |m: &TriMesh| {
            let mut edges = std::collections::HashSet::new();
            for &[a, b, c] in &m.indices {
                for (x, y) in [(a, b), (b, c), (c, a)] {
                    edges.insert((x.min(y), x.max(y)));
                }
            }
            m.positions.len() as i64 - edges.len() as i64 + m.indices.len() as i64
        };
        assert_eq!(euler(&sphere), euler(&fine));
    }

    #[test]
    fn subdivide_to_reaches_the_target() {
        let plane = procedural::plane(2.0, 2.0);
        let (levels, m) = subdivide_to(&plane, 1000);
        assert!(m.triangle_count() >= 1000 && m.triangle_count() < 4000);
        assert_eq!(
            m.triangle_count(),
            plane.triangle_count() * 4usize.pow(levels)
        );
        assert_eq!(subdivide_to(&TriMesh::default(), 10).1.triangle_count(), 0);
    }
}
