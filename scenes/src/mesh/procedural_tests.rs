//! Tests of `procedural.rs`.

use std::collections::HashMap;

use super::*;

/// Unnormalised geometric normal (twice the area vector).
fn area_vector(mesh: &TriMesh, t: [u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
    (b - a).cross(c - a)
}

/// Asserts that welding by exact (bitwise) position gives a closed, consistently oriented
/// surface: every directed edge appears exactly once and so does its reverse.
fn assert_watertight(mesh: &TriMesh, what: &str) {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let welded: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let next = ids.len() as u32;
            *ids.entry(p.to_array().map(f32::to_bits)).or_insert(next)
        })
        .collect();
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.indices {
        let w = t.map(|i| welded[i as usize]);
        for e in 0..3 {
            let (a, b) = (w[e], w[(e + 1) % 3]);
            assert_ne!(a, b, "{what}: triangle {t:?} has a collapsed edge");
            *directed.entry((a, b)).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &directed {
        assert_eq!(
            count, 1,
            "{what}: directed edge ({a},{b}) used {count} times"
        );
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "{what}: edge ({a},{b}) has no opposite half-edge (open or misoriented)"
        );
    }
}

/// Enclosed volume by the divergence theorem; positive iff outward oriented.
fn volume(mesh: &TriMesh) -> f64 {
    mesh.indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

fn assert_rel(actual: f64, expected: f64, tolerance: f64, what: &str) {
    let rel = (actual - expected).abs() / expected.abs();
    assert!(
        rel <= tolerance,
        "{what}: {actual} vs {expected} (relative error {rel:e} > {tolerance:e})"
    );
}

/// Structural sanity shared by every generator: consistent array lengths, indices in
/// range, unit normals, no zero-area (or sliver) triangles, and every vertex normal on the
/// front side of its triangle (`min_dot` tightens that for flat faces).
fn assert_well_formed(mesh: &TriMesh, min_dot: f32, what: &str) {
    assert_eq!(mesh.positions.len(), mesh.normals.len(), "{what}");
    assert!(!mesh.indices.is_empty(), "{what}: no triangles");
    for (i, n) in mesh.normals.iter().enumerate() {
        assert!(
            (n.length() - 1.0).abs() < 1e-5,
            "{what}: normal {i} = {n} not unit"
        );
    }
    for &t in &mesh.indices {
        assert!(
            t.iter().all(|&i| (i as usize) < mesh.positions.len()),
            "{what}: index out of range in {t:?}"
        );
        let area = area_vector(mesh, t);
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let longest = (b - a)
            .length_squared()
            .max((c - b).length_squared())
            .max((a - c).length_squared());
        assert!(
            area.length() > 1e-6 * longest,
            "{what}: zero-area triangle {t:?}: {a} {b} {c}"
        );
        let geometric = area.normalize();
        for i in t {
            let d = mesh.normals[i as usize].dot(geometric);
            assert!(
                d > min_dot,
                "{what}: vertex {i} normal disagrees with triangle {t:?} (dot {d})"
            );
        }
    }
}

#[test]
fn plane_is_one_upward_quad() {
    let m = plane(2.0, 3.0);
    assert_eq!(m.triangle_count(), 2);
    assert_eq!(m.positions.len(), 4);
    assert_well_formed(&m, 0.999, "plane");
    assert!(m.normals.iter().all(|&n| n == Vec3::Y));
    let (lo, hi) = m.bounds(&Mat4::IDENTITY);
    assert_eq!(
        (lo, hi),
        (Vec3::new(-1.0, 0.0, -1.5), Vec3::new(1.0, 0.0, 1.5))
    );
}

#[test]
fn cuboid_is_closed_flat_and_exact() {
    let size = Vec3::new(1.0, 2.5, 0.75);
    let m = cuboid(size);
    assert_eq!(m.positions.len(), 24);
    assert_eq!(m.triangle_count(), 12);
    assert_well_formed(&m, 0.999, "cuboid");
    assert_watertight(&m, "cuboid");
    assert_eq!(volume(&m), f64::from(size.x * size.y * size.z));
    assert_eq!(m.bounds(&Mat4::IDENTITY), (-0.5 * size, 0.5 * size));
}

#[test]
fn sphere_is_closed_smooth_and_close_to_analytic() {
    for (segments, rings) in [(3, 2), (4, 3), (48, 24), (17, 9)] {
        let m = sphere(1.5, segments, rings);
        let what = format!("sphere {segments}x{rings}");
        assert_well_formed(&m, 0.0, &what);
        assert_watertight(&m, &what);
        assert_eq!(m.positions.len() as u32, segments * (rings - 1) + 2);
        assert_eq!(m.triangle_count() as u32, 2 * segments * (rings - 1));
        // Smooth normals are the radial direction.
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!(p.normalize().dot(*n) > 0.99999, "{what}: normal {n} at {p}");
        }
        assert!(volume(&m) > 0.0, "{what}: inward");
    }
    // The inscribed polyhedron is slightly smaller than the sphere, and converges.
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 1.5f64.powi(3);
    let coarse = volume(&sphere(1.5, 48, 24));
    let fine = volume(&sphere(1.5, 192, 96));
    assert!(coarse < exact && fine < exact);
    assert_rel(coarse, exact, 0.01, "sphere 48x24 volume");
    assert_rel(fine, exact, 0.001, "sphere 192x96 volume");
    assert!(exact - fine < exact - coarse);
}

#[test]
fn sphere_clamps_counts() {
    assert_eq!(sphere(1.0, 0, 0), sphere(1.0, 3, 2));
}

#[test]
fn cylinder_is_closed_with_flat_caps() {
    for segments in [3, 5, 48] {
        let m = cylinder(0.5, 2.0, segments);
        let what = format!("cylinder {segments}");
        assert_well_formed(&m, 0.0, &what);
        assert_watertight(&m, &what);
        // Cap triangles (geometric normal ±Y) are flat-shaded; side normals are radial.
        for &t in &m.indices {
            let g = area_vector(&m, t).normalize();
            if g.y.abs() > 0.999 {
                for i in t {
                    assert!(m.normals[i as usize].dot(g) > 0.999, "{what}: cap normal");
                }
            } else {
                for i in t {
                    let (p, n) = (m.positions[i as usize], m.normals[i as usize]);
                    assert_eq!(n.y, 0.0, "{what}: side normal {n}");
                    assert!(n.dot(Vec3::new(p.x, 0.0, p.z).normalize()) > 0.99999);
                }
            }
        }
    }
    let exact = std::f64::consts::PI * 0.25 * 2.0;
    assert_rel(
        volume(&cylinder(0.5, 2.0, 48)),
        exact,
        0.01,
        "cylinder volume",
    );
    assert_eq!(cylinder(0.5, 2.0, 1), cylinder(0.5, 2.0, 3));
}

#[test]
fn torus_is_closed_and_close_to_analytic() {
    for (segments, sides) in [(3, 3), (64, 32), (7, 5)] {
        let m = torus(2.0, 0.5, segments, sides);
        let what = format!("torus {segments}x{sides}");
        assert_well_formed(&m, 0.0, &what);
        assert_watertight(&m, &what);
        // Smooth normals point away from the tube's centre circle.
        for (p, n) in m.positions.iter().zip(&m.normals) {
            let centre = 2.0 * Vec3::new(p.x, 0.0, p.z).normalize();
            assert!((*p - centre).normalize().dot(*n) > 0.9999, "{what}");
        }
    }
    let exact = 2.0 * std::f64::consts::PI.powi(2) * 2.0 * 0.25;
    assert_rel(
        volume(&torus(2.0, 0.5, 64, 32)),
        exact,
        0.015,
        "torus volume",
    );
}

#[test]
fn spring_is_closed_capped_tube() {
    for (turns, spt, sides) in [(3.0, 24, 12), (0.1, 8, 3), (2.5, 48, 32), (1.0, 1, 4)] {
        let m = spring(1.0, 0.15, turns, 2.0, spt, sides);
        let what = format!("spring turns={turns} spt={spt} sides={sides}");
        assert_well_formed(&m, 0.0, &what);
        assert_watertight(&m, &what);
        let segments = ((turns * spt as f32).ceil() as usize).max(3);
        // Side quads plus two fans.
        assert_eq!(
            m.triangle_count(),
            2 * segments * sides as usize + 2 * sides as usize
        );
    }
    // Pappus: a tube's volume is its cross-section times the centre-line length.
    let (r, w, turns, h) = (1.0f64, 0.15f64, 2.5f64, 2.0f64);
    let arc = ((std::f64::consts::TAU * turns * r).powi(2) + h * h).sqrt();
    let exact = std::f64::consts::PI * w * w * arc;
    let m = spring(r as f32, w as f32, turns as f32, h as f32, 48, 32);
    assert_rel(volume(&m), exact, 0.015, "spring volume");
    // The tube pokes out about one wire radius below y = 0 and above y = height.
    let (lo, hi) = m.bounds(&Mat4::IDENTITY);
    assert!(lo.y < -0.1 && hi.y > 2.1 && hi.y < 2.0 + 0.16);
}

#[test]
fn spring_caps_are_flat() {
    let m = spring(1.0, 0.2, 1.5, 1.0, 16, 8);
    // The last 2 * sides triangles are the two fans; all their vertex normals match the
    // triangle's geometric normal.
    let caps = &m.indices[m.indices.len() - 16..];
    for &t in caps {
        let g = area_vector(&m, t).normalize();
        for i in t {
            assert!(m.normals[i as usize].dot(g) > 0.999, "spring cap normal");
        }
    }
}

#[test]
fn pencil_is_closed_flat_and_exact() {
    let (r, length, tip) = (0.1f32, 1.5f32, 0.3f32);
    let m = pencil(r, length, tip);
    assert_well_formed(&m, 0.999, "pencil");
    assert_watertight(&m, "pencil");
    // 6 side quads, 6 tip triangles, 6-triangle bottom fan.
    assert_eq!(m.triangle_count(), 12 + 6 + 6);
    let area = 3.0 * 3f64.sqrt() / 2.0 * f64::from(r).powi(2);
    let exact = area * f64::from(length) + area * f64::from(tip) / 3.0;
    assert_rel(volume(&m), exact, 1e-4, "pencil volume");
    let (lo, hi) = m.bounds(&Mat4::IDENTITY);
    assert_eq!(lo.y, 0.0);
    assert_eq!(hi.y, length + tip);
}

#[test]
fn fence_bars_are_closed_boxes() {
    for (posts, rails) in [(1, 0), (1, 1), (2, 2), (5, 3)] {
        let (width, height, bar) = (3.0, 1.2, 0.08);
        let m = fence(width, height, posts, rails, bar);
        let what = format!("fence {posts}x{rails}");
        assert_well_formed(&m, 0.999, &what);
        let boxes = (posts + rails) as usize;
        assert_eq!(m.positions.len(), 24 * boxes, "{what}");
        assert_eq!(m.triangle_count(), 12 * boxes, "{what}");
        // Each 24-vertex / 12-triangle block is one bar, closed on its own.
        let mut total = 0.0;
        for k in 0..boxes {
            let block = TriMesh {
                positions: m.positions[24 * k..24 * (k + 1)].to_vec(),
                normals: m.normals[24 * k..24 * (k + 1)].to_vec(),
                indices: m.indices[12 * k..12 * (k + 1)]
                    .iter()
                    .map(|t| t.map(|i| i - 24 * k as u32))
                    .collect(),
            };
            assert_watertight(&block, &format!("{what} bar {k}"));
            total += volume(&block);
        }
        let bar = f64::from(bar);
        let exact =
            bar * bar * (posts as f64 * f64::from(height) + rails as f64 * f64::from(width));
        assert_rel(total, exact, 1e-5, &format!("{what} volume"));
        let (lo, hi) = m.bounds(&Mat4::IDENTITY);
        let expect_x = if posts == 1 && rails == 0 {
            0.5 * bar as f32
        } else {
            1.5
        };
        assert!(
            (hi.x - expect_x).abs() < 1e-6 && (lo.x + expect_x).abs() < 1e-6,
            "{what}"
        );
        assert!(
            (hi.y - 0.6).abs() < 1e-6 && (lo.y + 0.6).abs() < 1e-6,
            "{what}"
        );
        assert!(
            (hi.z - 0.04).abs() < 1e-6 && (lo.z + 0.04).abs() < 1e-6,
            "{what}"
        );
    }
}

#[test]
fn fence_outer_posts_are_flush() {
    let m = fence(2.0, 1.0, 3, 0, 0.1);
    let xs: Vec<f32> = (0..3)
        .map(|k| {
            m.positions[24 * k..24 * (k + 1)]
                .iter()
                .map(|p| p.x)
                .sum::<f32>()
                / 24.0
        })
        .collect();
    for (x, expected) in xs.iter().zip([-0.95, 0.0, 0.95]) {
        assert!((x - expected).abs() < 1e-6, "post centre {x} vs {expected}");
    }
}

#[test]
fn transformed_keeps_orientation_and_normals() {
    let base = cylinder(0.5, 1.0, 12);
    let v0 = volume(&base);
    let scale = Vec3::new(2.0, 0.5, 3.0);
    let m = Mat4::from_scale_rotation_translation(
        scale,
        glam::Quat::from_rotation_y(0.7),
        Vec3::new(1.0, 2.0, 3.0),
    );
    let t = transformed(&base, m);
    assert_well_formed(&t, 0.0, "transformed cylinder");
    assert_watertight(&t, "transformed cylinder");
    let expected = v0 * f64::from(scale.x * scale.y * scale.z);
    assert_rel(
        volume(&transformed(&base, Mat4::from_scale(scale))),
        expected,
        1e-5,
        "scaled",
    );
    // A mirror must flip winding so the volume stays positive and normals stay outward.
    let mirrored = transformed(
        &cuboid(Vec3::ONE),
        Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    );
    assert_well_formed(&mirrored, 0.999, "mirrored cuboid");
    assert_watertight(&mirrored, "mirrored cuboid");
    assert_rel(volume(&mirrored), 1.0, 1e-6, "mirrored volume");
}

#[test]
fn merge_offsets_indices() {
    let a = cuboid(Vec3::ONE);
    let b = pencil(0.1, 1.0, 0.2);
    let m = merge(&[a.clone(), b.clone()]);
    assert_eq!(m.positions.len(), a.positions.len() + b.positions.len());
    assert_eq!(m.triangle_count(), a.triangle_count() + b.triangle_count());
    assert_eq!(m.indices[12], b.indices[0].map(|i| i + 24));
    assert_rel(volume(&m), volume(&a) + volume(&b), 1e-6, "merged volume");
    assert_eq!(merge(&[]), TriMesh::default());
}
