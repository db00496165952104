//! The atrium's building blocks in their own local frames: column and baluster profiles, the
//! arched spandrel wall of one bay, a hanging banner. Every solid is closed and consistently
//! oriented (welded by exact position), as the shadow-volume methods need.

use std::f32::consts::{FRAC_PI_2, PI, TAU};

use glam::{Vec2, Vec3};

use super::layout::{ABACUS_HALF, ARCADE_DEPTH, BAY};
use crate::mesh::TriMesh;
use crate::mesh::procedural::Builder;

/// `base` scaled by the detail level, at least `min`.
pub fn samples(base: u32, detail: f32, min: u32) -> u32 {
    ((base as f32 * detail).round() as u32).max(min)
}

/// Adds a flat quad turned so that its normal has a positive component along `outward`.
fn quad_facing(b: &mut Builder, corners: [Vec3; 4], outward: Vec3) {
    let normal = (corners[2] - corners[0]).cross(corners[3] - corners[1]);
    if normal.dot(outward) >= 0.0 {
        b.flat_quad(corners);
    } else {
        let [p, q, r, s] = corners;
        b.flat_quad([p, s, r, q]);
    }
}

/// (radius, y) profile of a column of `height` m: plinth, torus moulding, scotia, a shaft with
/// entasis, echinus and abacus (all turned, so the abacus is round).
pub fn column_profile(height: f32, detail: f32) -> Vec<(f32, f32)> {
    let s = height / 5.0;
    let arc = samples(6, detail, 2);
    let rings = samples(16, detail, 2);
    let mut p = vec![(0.52, 0.0), (0.52, 0.12 * s)];
    // Torus: a half ellipse bulging outward, from its bottom to its top.
    p.extend((0..=arc).map(|k| {
        let a = -FRAC_PI_2 + PI * k as f32 / arc as f32;
        (0.44 + 0.08 * a.cos(), (0.2 + 0.08 * a.sin()) * s)
    }));
    p.extend([(0.38, 0.31 * s), (0.36, 0.38 * s)]);
    // Shaft with entasis: the radius narrows quadratically toward the top.
    p.extend((0..=rings).map(|k| {
        let t = k as f32 / rings as f32;
        (0.36 - 0.05 * t * t, (0.4 + 3.9 * t) * s)
    }));
    // Echinus: a quarter ellipse flaring out to the abacus.
    p.extend((1..=arc).map(|k| {
        let a = FRAC_PI_2 * k as f32 / arc as f32;
        (0.31 + 0.17 * a.sin(), (4.3 + 0.32 * (1.0 - a.cos())) * s)
    }));
    p.extend([(ABACUS_HALF, 4.62 * s), (ABACUS_HALF, 5.0 * s)]);
    p
}

/// Height of a baluster, m.
pub const BALUSTER_HEIGHT: f32 = 0.9;

/// (radius, y) profile of a baluster: square-edged foot and head, a bulb low and a ring high.
pub fn baluster_profile(detail: f32) -> Vec<(f32, f32)> {
    let n = samples(14, detail, 3);
    let h = BALUSTER_HEIGHT;
    let mut p = vec![(0.07, 0.0), (0.07, 0.06)];
    p.extend((0..=n).map(|k| {
        let t = k as f32 / n as f32;
        let bump = |c: f32, w: f32| (-((t - c) / w).powi(2)).exp();
        let r = 0.04 + 0.035 * bump(0.35, 0.18) + 0.02 * bump(0.85, 0.06);
        (r, 0.08 + (h - 0.16) * t)
    }));
    p.extend([(0.065, h - 0.06), (0.065, h)]);
    p
}

/// One side's arcade wall above the springing line: `bays` bays side by side along local u
/// (centred on the origin, BAY each), y from 0 to `height`, w across ±ARCADE_DEPTH/2, each bay
/// pierced by a semicircular arch springing from the abacus edges (radius BAY/2 −
/// ABACUS_HALF), `segments` (even, ≥ 4) along each half circle pair. One closed solid: the
/// bays share their boundary points exactly (each bay's left half is its right half mirrored,
/// and bay centres are exact in f32), so the wall welds into a 2-manifold without internal
/// faces, as the shadow-volume methods' silhouettes need.
pub fn arcade(bays: u32, height: f32, segments: u32) -> TriMesh {
    let (inner, outer) = bay_outline(height, segments / 2);
    let (half, hw) = (0.5 * BAY, 0.5 * ARCADE_DEPTH);
    let mut b = Builder::default();
    let last = inner.len() - 1;
    for j in 0..bays {
        let u0 = (j as f32 + 0.5) * BAY - 0.5 * bays as f32 * BAY;
        let at = |p: Vec2, w: f32| Vec3::new(u0 + p.x, p.y, w);
        for k in 0..last {
            let (i0, i1, o0, o1) = (inner[k], inner[k + 1], outer[k], outer[k + 1]);
            for w in [hw, -hw] {
                quad_facing(
                    &mut b,
                    [at(i0, w), at(i1, w), at(o1, w), at(o0, w)],
                    Vec3::Z * w,
                );
            }
            let mid = 0.5 * (i0 + i1);
            quad_facing(
                &mut b,
                [at(i0, hw), at(i1, hw), at(i1, -hw), at(i0, -hw)],
                -mid.extend(0.0),
            );
            // The outline's top is the wall's top; its sides are wall ends only at the run's ends.
            let side = (o1 - o0).x.abs() <= (o1 - o0).y.abs();
            let end = (o0.x > 0.0 && j == bays - 1) || (o0.x < 0.0 && j == 0);
            if !side || end {
                let outward = if side {
                    Vec3::X * o0.x.signum()
                } else {
                    Vec3::Y
                };
                quad_facing(
                    &mut b,
                    [at(o0, hw), at(o1, hw), at(o1, -hw), at(o0, -hw)],
                    outward,
                );
            }
        }
        // The two strips on the abaci, at the springing line.
        for (i, o) in [(inner[0], outer[0]), (inner[last], outer[last])] {
            quad_facing(
                &mut b,
                [at(i, hw), at(o, hw), at(o, -hw), at(i, -hw)],
                Vec3::NEG_Y,
            );
        }
        debug_assert!(outer[0].x == half && outer[last].x == -half);
    }
    b.finish()
}

/// One bay's outline in (u, y) from the right springing point over the arch to the left one:
/// the arch (inner) and, at the same angles seen from the arch's centre, the bay's rectangle
/// (outer; its top corners are among the angles, so each outer segment lies on one side). The
/// right half is computed with `quarter` samples, the left half is its exact mirror.
fn bay_outline(height: f32, quarter: u32) -> (Vec<Vec2>, Vec<Vec2>) {
    let quarter = quarter.max(2);
    let (half, r) = (0.5 * BAY, 0.5 * BAY - ABACUS_HALF);
    let corner = height.atan2(half);
    // Samples within a milliradian of the corner would make slivers: the corner replaces them.
    let mut angles: Vec<f32> = (0..quarter)
        .map(|k| FRAC_PI_2 * k as f32 / quarter as f32)
        .filter(|a| (a - corner).abs() > 1e-3)
        .chain([corner])
        .collect();
    angles.sort_by(f32::total_cmp);
    let mut inner: Vec<Vec2> = angles
        .iter()
        .map(|a| r * Vec2::new(a.cos(), a.sin()))
        .collect();
    let mut outer: Vec<Vec2> = angles
        .iter()
        .map(|&a| {
            if a <= corner {
                Vec2::new(half, half * a.tan())
            } else {
                Vec2::new(height / a.tan(), height)
            }
        })
        .collect();
    // The crown, exactly on the axis (cos(π/2) is not 0 in f32).
    inner.push(Vec2::new(0.0, r));
    outer.push(Vec2::new(0.0, height));
    let mirror = |v: &[Vec2]| -> Vec<Vec2> {
        v.iter()
            .rev()
            .skip(1)
            .map(|p| Vec2::new(-p.x, p.y))
            .collect()
    };
    let (inner_left, outer_left) = (mirror(&inner), mirror(&outer));
    inner.extend(inner_left);
    outer.extend(outer_left);
    (inner, outer)
}

/// Banner size, m: width, length, cloth thickness.
pub const BANNER: [f32; 3] = [1.6, 4.4, 0.015];

/// A hanging banner: a cloth slab of BANNER's thickness in local x (width, centred) and y (0 at
/// the top edge, down to −length), facing +z, rippled along z more toward its free bottom edge.
/// `columns` × `rows` cells.
pub fn banner(columns: u32, rows: u32) -> TriMesh {
    let [width, length, thickness] = BANNER;
    let ripple = |s: f32, t: f32| {
        // t = depth below the top in [0, 1]: the top edge hangs straight from its rod.
        0.06 * t * (TAU * (t * length / 1.8) + 1.3 * s).sin()
    };
    let grid: Vec<Vec<(f32, f32, f32)>> = (0..=rows)
        .map(|j| {
            let t = j as f32 / rows as f32;
            (0..=columns)
                .map(|i| {
                    let s = i as f32 / columns as f32 - 0.5;
                    (s * width, -t * length, ripple(s, t))
                })
                .collect()
        })
        .collect();
    let face = |w: f32| -> Vec<Vec<Vec3>> {
        grid.iter()
            .map(|row| {
                row.iter()
                    .map(|&(x, y, z)| Vec3::new(x, y, z + w))
                    .collect()
            })
            .collect()
    };
    let (front, back) = (face(0.5 * thickness), face(-0.5 * thickness));
    let mut b = Builder::default();
    for j in 0..rows as usize {
        for i in 0..columns as usize {
            let cell = |f: &Vec<Vec<Vec3>>| [f[j][i], f[j][i + 1], f[j + 1][i + 1], f[j + 1][i]];
            quad_facing(&mut b, cell(&front), Vec3::Z);
            quad_facing(&mut b, cell(&back), Vec3::NEG_Z);
        }
    }
    // The four edges, each a strip of quads joining front and back.
    let (last_row, last_col) = (rows as usize, columns as usize);
    let edges: [(Vec<(usize, usize)>, Vec3); 4] = [
        ((0..=last_col).map(|i| (0, i)).collect(), Vec3::Y),
        ((0..=last_col).map(|i| (last_row, i)).collect(), Vec3::NEG_Y),
        ((0..=last_row).map(|j| (j, 0)).collect(), Vec3::NEG_X),
        ((0..=last_row).map(|j| (j, last_col)).collect(), Vec3::X),
    ];
    for (path, outward) in edges {
        for w in path.windows(2) {
            let ((j0, i0), (j1, i1)) = (w[0], w[1]);
            let corners = [front[j0][i0], front[j1][i1], back[j1][i1], back[j0][i0]];
            quad_facing(&mut b, corners, outward);
        }
    }
    b.finish()
}
