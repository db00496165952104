//! Surfaces of revolution: a (radius, height) profile turned about the Y axis and closed by
//! flat caps, for columns and balusters. Watertight as positions, like every procedural mesh
//! (`procedural`'s module doc): each ring is computed once and the caps copy its rim.

use glam::{Vec2, Vec3};

use super::TriMesh;
use super::procedural::{Builder, circle};

/// A closed solid of revolution. `profile` lists (radius, y) from the bottom to the top, every
/// radius > 0 and consecutive points distinct; `segments` (≥ 3) around. The side is
/// smooth-shaded (each profile point's normal bisects its two profile edges), the bottom and top
/// are flat fans.
pub fn lathe(profile: &[(f32, f32)], segments: u32) -> TriMesh {
    let segments = segments.max(3);
    let points: Vec<Vec2> = profile.iter().map(|&(r, y)| Vec2::new(r, y)).collect();
    let normals = profile_normals(&points);
    let mut b = Builder::default();
    let mut ring_starts = Vec::with_capacity(points.len());
    let mut rings = Vec::with_capacity(points.len());
    for (p, n) in points.iter().zip(&normals) {
        let ring = circle(p.x, p.y, segments);
        ring_starts.push(b.mesh.positions.len() as u32);
        for q in &ring {
            let radial = Vec3::new(q.x, 0.0, q.z) / p.x;
            b.vertex(*q, (radial * n.x + Vec3::Y * n.y).normalize());
        }
        rings.push(ring);
    }
    for k in 1..ring_starts.len() {
        // Upper ring first: `stitch_rings` then faces outward (see `procedural::cylinder`).
        b.stitch_rings(ring_starts[k], ring_starts[k - 1], segments);
    }
    let (first, last) = (&rings[0], &rings[rings.len() - 1]);
    let top_rim: Vec<Vec3> = last.iter().rev().copied().collect();
    b.flat_fan(Vec3::new(0.0, last[0].y, 0.0), &top_rim, Vec3::Y);
    b.flat_fan(Vec3::new(0.0, first[0].y, 0.0), first, Vec3::NEG_Y);
    b.finish()
}

/// Outward (radius, y) normal at each profile point: the normalised sum of its edges' normals
/// (an edge going up has normal +r).
fn profile_normals(points: &[Vec2]) -> Vec<Vec2> {
    let edge_normal = |a: Vec2, b: Vec2| {
        let d = b - a;
        Vec2::new(d.y, -d.x).normalize_or_zero()
    };
    (0..points.len())
        .map(|i| {
            let before = (i > 0).then(|| edge_normal(points[i - 1], points[i]));
            let after = (i + 1 < points.len()).then(|| edge_normal(points[i], points[i + 1]));
            let sum = before.unwrap_or(Vec2::ZERO) + after.unwrap_or(Vec2::ZERO);
            sum.try_normalize().unwrap_or(Vec2::X)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lathe of a two-point profile is a cylinder: its area is the closed form 2πr(h + r) up
    /// to the polygon's inscribed-circle factor, and it has the cylinder's triangle count.
    #[test]
    fn a_two_point_profile_is_a_capped_cylinder() {
        let (r, h, n) = (0.5f32, 2.0f32, 64u32);
        let m = lathe(&[(r, 0.0), (r, h)], n);
        assert_eq!(m.triangle_count(), 4 * n as usize);
        let polygon = 0.5 * n as f64 * (std::f64::consts::TAU / n as f64).sin();
        let side = n as f64 * 2.0 * (std::f64::consts::PI / n as f64).sin() * r as f64 * h as f64;
        let expected = side + 2.0 * polygon * (r as f64).powi(2);
        assert!(
            (m.area() - expected).abs() < 1e-5 * expected,
            "{} vs {expected}",
            m.area()
        );
    }

    /// Every edge of the welded mesh is used by exactly two triangles in opposite directions:
    /// closed and consistently oriented, as the shadow-volume methods need.
    #[test]
    fn a_lathe_is_a_closed_oriented_manifold() {
        let m = lathe(&[(0.3, 0.0), (0.5, 0.2), (0.2, 0.9), (0.4, 1.0)], 12);
        let key = |p: Vec3| p.to_array().map(f32::to_bits);
        let mut edges = std::collections::HashMap::new();
        for t in &m.indices {
            for e in 0..3 {
                let (a, b) = (
                    m.positions[t[e] as usize],
                    m.positions[t[(e + 1) % 3] as usize],
                );
                *edges.entry((key(a), key(b))).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "directed edge used {count} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its opposite");
        }
    }
}
