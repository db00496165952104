//! CPU geometry of biri-polynomial's second pass: the drawing order of shadow planes by the
//! distances of eq. 13 and 14 (§4.4) and their directional-light limit (modernised), the planes meshed into strips finer near the light
//! (§4.2, "a quadratic law"), which side of a plane the eye sees, and the far-plane grid that
//! carries per-vertex values where a ray hits nothing.

use glam::Vec3;

use crate::common::shadow_volumes::silhouette::LightPos;

/// Distance from `c` to the infinite planar sector {apex + s·e1 + u·e2 : s, u ≥ 0}.
pub fn sector_distance(c: Vec3, apex: Vec3, e1: Vec3, e2: Vec3) -> f32 {
    let w = c - apex;
    let ray = |e: Vec3| {
        let tau = (w.dot(e) / e.length_squared().max(1e-30)).max(0.0);
        (w - tau * e).length()
    };
    let n = e1.cross(e2);
    if n.length_squared() > 1e-20 {
        let n = n.normalize();
        let wp = w - w.dot(n) * n;
        // wp = s e1 + u e2 by the 2×2 Gram system.
        let (a, b, d) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (r1, r2) = (wp.dot(e1), wp.dot(e2));
        let det = a * d - b * b;
        let s = (r1 * d - r2 * b) / det;
        let u = (a * r2 - b * r1) / det;
        if s >= 0.0 && u >= 0.0 {
            return w.dot(n).abs();
        }
    }
    ray(e1).min(ray(e2))
}

/// The sort key of eq. 13/14 for the shadow plane of silhouette edge (a, b) of a point light at
/// `light`, seen from `eye`. Space is split by the plane through the light orthogonal to the
/// eye–light line. On the eye's side, l = d² with d the distance from the eye to the infinite
/// triangle (light, edge); on the other, l = p² + 1/d² with p = |light − eye| and d the distance
/// to the triangle's image through the light — always > p² ≥ any d² of the eye's side, so those
/// planes come after. Ascending keys draw front to back.
pub fn order_key(a: Vec3, b: Vec3, light: Vec3, eye: Vec3) -> f32 {
    let mid = 0.5 * (a + b);
    let p2 = (light - eye).length_squared();
    if (mid - light).dot(eye - light) >= 0.0 {
        let d = sector_distance(eye, light, a - light, b - light);
        d * d
    } else {
        let d = sector_distance(eye, light, light - a, light - b).max(1e-6);
        p2 + 1.0 / (d * d)
    }
}

/// Distance from `c` to the infinite strip {a + s·(b − a) + u·d : s ∈ [0, 1], u ∈ ℝ}: the
/// shadow plane of edge (a, b) under a directional light propagating along `d`, continued back
/// to the light at infinity. Minimising over u projects out d, leaving the distance to the
/// segment (a, b) in the plane orthogonal to d.
pub fn strip_distance(c: Vec3, a: Vec3, b: Vec3, d: Vec3) -> f32 {
    let d = d.normalize_or_zero();
    let perp = |v: Vec3| v - v.dot(d) * d;
    let (w, e) = (perp(c - a), perp(b - a));
    let s = (w.dot(e) / e.length_squared().max(1e-30)).clamp(0.0, 1.0);
    (w - s * e).length()
}

/// The eq. 13/14 sort key of edge (a, b)'s shadow plane for any light (modernised for
/// directional lights). Point and spot lights: [`order_key`]. Directional light along `d`: the
/// limit of [`order_key`] as the light recedes to infinity against `d` — every plane lies on the
/// eye's side of the light (eq. 14's far half-space is empty) and the infinite triangle
/// (light, a, b) becomes the strip of [`strip_distance`], so the key is its squared distance.
pub fn light_order_key(a: Vec3, b: Vec3, light: LightPos, eye: Vec3) -> f32 {
    match light {
        LightPos::Point(l) => order_key(a, b, l, eye),
        LightPos::Direction(d) => strip_distance(eye, a, b, d).powi(2),
    }
}

/// Whether the eye sees the outward-wound quad [p, q, q', …] (`silhouette::extrude`) from
/// outside its shadow volume: a ray through it enters the shadow.
pub fn faces_eye(quad: &[Vec3; 6], eye: Vec3) -> bool {
    let n = (quad[1] - quad[0]).cross(quad[2] - quad[0]);
    n.dot(eye - quad[0]) > 0.0
}

/// Quad [p, q, q', p, q', p'] cut into `segments` strips across the extrusion, at fractions
/// (i/segments)² of its length: fine near the edge (the light's side), coarse far away. Keeps the
/// winding; 6·segments vertices.
pub fn mesh_quad(quad: &[Vec3; 6], segments: u32) -> Vec<Vec3> {
    let (p, q, q2, p2) = (quad[0], quad[1], quad[2], quad[5]);
    let n = segments.max(1);
    let at = |i: u32| {
        let s = (i as f32 / n as f32).powi(2);
        (p + (p2 - p) * s, q + (q2 - q) * s)
    };
    let mut out = Vec::with_capacity(6 * n as usize);
    for i in 0..n {
        let ((a0, b0), (a1, b1)) = (at(i), at(i + 1));
        out.extend([a0, b0, b1, a0, b1, a1]);
    }
    out
}

/// A `cells` × `cells` grid of triangles covering NDC [−1, 1]² (two per cell).
pub fn far_grid(cells: u32) -> Vec<[f32; 2]> {
    let n = cells.max(1);
    let c = |i: u32| -1.0 + 2.0 * i as f32 / n as f32;
    let mut out = Vec::with_capacity(6 * (n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let (x0, x1, y0, y1) = (c(i), c(i + 1), c(j), c(j + 1));
            out.extend([[x0, y0], [x1, y0], [x1, y1], [x0, y0], [x1, y1], [x0, y1]]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sector_distance_inside_and_beside() {
        // Sector in the z = 0 plane spanning the +x/+y quadrant from the origin.
        let (o, ex, ey) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!((sector_distance(Vec3::new(2.0, 3.0, 1.5), o, ex, ey) - 1.5).abs() < 1e-6);
        // Beside the +x ray: nearest point on it.
        assert!((sector_distance(Vec3::new(2.0, -1.0, 0.0), o, ex, ey) - 1.0).abs() < 1e-6);
        // Behind the apex: the apex itself.
        let c = Vec3::new(-3.0, -4.0, 0.0);
        assert!((sector_distance(c, o, ex, ey) - 5.0).abs() < 1e-5);
        // Brute force on a grid of sector points never beats it.
        let c = Vec3::new(-0.7, 2.3, -0.4);
        let (e1, e2) = (Vec3::new(1.0, 0.3, 0.2), Vec3::new(-0.2, 1.0, 0.5));
        let d = sector_distance(c, o, e1, e2);
        let mut best = f32::MAX;
        for i in 0..200 {
            for j in 0..200 {
                let p = o + e1 * (i as f32 * 0.05) + e2 * (j as f32 * 0.05);
                best = best.min((p - c).length());
            }
        }
        assert!(d <= best + 1e-4 && best - d < 0.05, "{d} vs brute {best}");
    }

    #[test]
    fn far_half_space_sorts_after_the_eyes() {
        let (light, eye) = (Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.0, 5.0, 10.0));
        let near = order_key(
            Vec3::new(-1.0, 4.0, 1.0),
            Vec3::new(1.0, 4.0, 1.0),
            light,
            eye,
        );
        let far = order_key(
            Vec3::new(-1.0, 4.0, -1.0),
            Vec3::new(1.0, 4.0, -1.0),
            light,
            eye,
        );
        assert!(
            near < (light - eye).length_squared() && far > near,
            "{near} {far}"
        );
    }

    /// The directional key is the limit of the point-light key: with the light 2 km against the
    /// direction, eq. 13's key of random edges agrees with the strip's to 1 % (the infinite
    /// triangle's width near the eye differs from the strip's by ~|eye − edge| / 2 km), and a
    /// brute-force search over strip points never beats `strip_distance`.
    #[test]
    fn directional_key_is_the_far_light_limit() {
        let d = Vec3::new(0.4, -1.0, 0.3).normalize();
        let eye = Vec3::new(3.0, 1.5, 4.0);
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 6.0 - 3.0
        };
        for _ in 0..50 {
            let a = Vec3::new(rnd(), rnd().abs() + 1.0, rnd());
            let b = a + Vec3::new(rnd(), rnd(), rnd()) * 0.3;
            let mid = 0.5 * (a + b);
            let far = order_key(a, b, mid - 2000.0 * d, eye);
            let key = light_order_key(a, b, LightPos::Direction(d), eye);
            assert!(
                (far - key).abs() <= 0.01 * key.max(0.05),
                "far point light {far} vs directional {key}"
            );
            let mut best = f32::MAX;
            for i in 0..=40 {
                for j in -200..=200 {
                    let p = a + (b - a) * (i as f32 / 40.0) + d * (j as f32 * 0.05);
                    best = best.min((p - eye).length());
                }
            }
            let s = strip_distance(eye, a, b, d);
            assert!(s <= best + 1e-4 && best - s < 0.05, "{s} vs brute {best}");
        }
    }

    #[test]
    fn meshed_quad_covers_the_quad_quadratically() {
        let quad = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 0.0, 8.0),
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 8.0),
            Vec3::new(0.0, 0.0, 8.0),
        ];
        let m = mesh_quad(&quad, 4);
        assert_eq!(m.len(), 24);
        // Strip boundaries at 8·(i/4)²: 0, 0.5, 2, 4.5, 8.
        let zs: Vec<f32> = m.chunks(6).map(|s| s[2].z).collect();
        assert_eq!(zs, vec![0.5, 2.0, 4.5, 8.0]);
        // Same winding as the quad: every triangle's normal agrees.
        let n0 = (quad[1] - quad[0]).cross(quad[2] - quad[0]);
        for t in m.chunks(3) {
            assert!((t[1] - t[0]).cross(t[2] - t[0]).dot(n0) > 0.0);
        }
        // Total area equals the quad's (8 m²).
        let area: f32 = m
            .chunks(3)
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
            .sum();
        assert!((area - 8.0).abs() < 1e-4);
    }

    #[test]
    fn far_grid_covers_ndc_once() {
        let g = far_grid(5);
        let area: f32 = g
            .chunks(3)
            .map(|t| {
                let (a, b, c) = (t[0], t[1], t[2]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs()
            })
            .sum();
        assert!((area - 4.0).abs() < 1e-5);
    }
}
