//! Procedural triangle-mesh generators for the benchmark's occluders.
//!
//! Every generator builds in local space (right-handed, Y up) and follows the [`TriMesh`]
//! conventions: counter-clockwise triangles seen from outside, unit shading normals per vertex,
//! smooth surfaces sharing vertices and hard edges duplicating them so each face keeps its own
//! flat normal. No generator emits a zero-area triangle (poles and cone tips use fans).
//!
//! Closed shapes are watertight *as positions*: where two parts of a surface meet (a cap and a
//! side, consecutive tube rings, the seam of a surface of revolution) the shared position is
//! computed once and copied, or computed by the very same expression, so the copies are bitwise
//! equal and welding by exact position yields a closed, consistently oriented 2-manifold.
//! Shadow-volume methods extract silhouettes from that welded adjacency, so "almost equal" is not
//! good enough here.
//!
//! Segment counts are clamped to their documented minimums instead of panicking: the scene
//! validator rejects bad counts up front, so reaching a clamp means a caller bypassed it, and
//! producing the coarsest valid shape is more useful than aborting a benchmark run.

use std::f32::consts::TAU;

use glam::{Mat3, Mat4, Vec3};

use super::TriMesh;

/// Append-only mesh construction with the index bookkeeping in one place.
#[derive(Default)]
pub(crate) struct Builder {
    pub(crate) mesh: TriMesh,
}

impl Builder {
    /// Adds a vertex and returns its index.
    pub(crate) fn vertex(&mut self, position: Vec3, normal: Vec3) -> u32 {
        let index = u32::try_from(self.mesh.positions.len())
            .expect("procedural mesh exceeds u32::MAX vertices");
        self.mesh.positions.push(position);
        self.mesh.normals.push(normal);
        index
    }

    pub(crate) fn triangle(&mut self, a: u32, b: u32, c: u32) {
        self.mesh.indices.push([a, b, c]);
    }

    /// A flat triangle with its own three vertices; corners counter-clockwise seen from outside.
    pub(crate) fn flat_triangle(&mut self, corners: [Vec3; 3]) {
        let normal = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        let [a, b, c] = corners.map(|p| self.vertex(p, normal));
        self.triangle(a, b, c);
    }

    /// A flat planar quad with its own four vertices; corners counter-clockwise seen from
    /// outside. The normal comes from the diagonals so it is exact for any planar quad, not
    /// biased towards one of the two triangles.
    pub(crate) fn flat_quad(&mut self, corners: [Vec3; 4]) {
        let normal = (corners[2] - corners[0])
            .cross(corners[3] - corners[1])
            .normalize();
        self.flat_quad_with_normal(corners, normal);
    }

    /// [`Self::flat_quad`] with a known normal, for axis-aligned faces whose normal should be
    /// exactly an axis rather than a renormalised cross product that may be off by an ulp.
    pub(crate) fn flat_quad_with_normal(&mut self, corners: [Vec3; 4], normal: Vec3) {
        let [a, b, c, d] = corners.map(|p| self.vertex(p, normal));
        self.triangle(a, b, c);
        self.triangle(a, c, d);
    }

    /// A flat cap: a fan from `centre` over the closed loop `rim`, emitting
    /// `(centre, rim[j], rim[j + 1])`, so the caller orders `rim` counter-clockwise about
    /// `normal`. The rim positions are copied verbatim, which is what keeps caps welded to the
    /// side they close. A centre fan (rather than a fan from one rim corner) avoids slivers on
    /// finely tessellated circles.
    pub(crate) fn flat_fan(&mut self, centre: Vec3, rim: &[Vec3], normal: Vec3) {
        let c = self.vertex(centre, normal);
        let first = self.vertex(rim[0], normal);
        for &p in &rim[1..] {
            self.vertex(p, normal);
        }
        let n = rim.len() as u32;
        for j in 0..n {
            self.triangle(c, first + j, first + (j + 1) % n);
        }
    }

    /// Connects two closed rings of `n` consecutive vertices starting at `a` and `b` with `2n`
    /// triangles (quads `a_j, a_{j+1}, b_{j+1}, b_j`). The result faces outward when
    /// `(a_{j+1} - a_j) × (b_j - a_j)` points outward. Indexing modulo `n` is how smooth
    /// surfaces close their seam without duplicating (and risking non-equal) positions.
    pub(crate) fn stitch_rings(&mut self, a: u32, b: u32, n: u32) {
        for j in 0..n {
            let k = (j + 1) % n;
            self.triangle(a + j, a + k, b + k);
            self.triangle(a + j, b + k, b + j);
        }
    }

    pub(crate) fn finish(self) -> TriMesh {
        self.mesh
    }
}

/// Angle of step `i` out of `n` around a full turn.
pub(crate) fn turn_angle(i: u32, n: u32) -> f32 {
    TAU * i as f32 / n as f32
}

/// A single quad in the XZ plane centred on the origin, facing +Y. Open surface (a floor or a
/// backdrop), so it is deliberately not watertight.
pub fn plane(size_x: f32, size_z: f32) -> TriMesh {
    let (hx, hz) = (0.5 * size_x, 0.5 * size_z);
    let mut b = Builder::default();
    // Counter-clockwise seen from +Y: -X-Z, -X+Z, +X+Z, +X-Z.
    b.flat_quad_with_normal(
        [
            Vec3::new(-hx, 0.0, -hz),
            Vec3::new(-hx, 0.0, hz),
            Vec3::new(hx, 0.0, hz),
            Vec3::new(hx, 0.0, -hz),
        ],
        Vec3::Y,
    );
    b.finish()
}

/// An axis-aligned box centred on the origin with full extents `size`: 24 vertices (4 per face,
/// so every face is flat-shaded) and 12 triangles.
pub fn cuboid(size: Vec3) -> TriMesh {
    let half = 0.5 * size;
    // (outward normal, u, v) with u × v = normal, so corners walked -u-v, +u-v, +u+v, -u+v are
    // counter-clockwise seen from outside. Each corner coordinate is exactly ±half, which keeps
    // the three copies of a corner bitwise equal.
    let faces = [
        (Vec3::X, Vec3::Y, Vec3::Z),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y, Vec3::X),
    ];
    let mut b = Builder::default();
    for (n, u, v) in faces {
        let corner = |su: f32, sv: f32| (n + su * u + sv * v) * half;
        b.flat_quad_with_normal(
            [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ],
            n,
        );
    }
    b.finish()
}

/// A UV sphere centred on the origin: `segments` (≥ 3) around Y, `rings` (≥ 2) bands from pole
/// to pole. The poles are single vertices closed by triangle fans, so no band collapses into
/// zero-area triangles; the seam is closed by indexing modulo `segments`.
pub fn sphere(radius: f32, segments: u32, rings: u32) -> TriMesh {
    let segments = segments.max(3);
    let rings = rings.max(2);
    let mut b = Builder::default();

    let north = b.vertex(Vec3::new(0.0, radius, 0.0), Vec3::Y);
    // Latitude rows 1..rings, each `segments` vertices; row i starts at 1 + (i - 1) * segments.
    for i in 1..rings {
        let (sin_t, cos_t) = (std::f32::consts::PI * i as f32 / rings as f32).sin_cos();
        for j in 0..segments {
            let (sin_p, cos_p) = turn_angle(j, segments).sin_cos();
            let n = Vec3::new(sin_t * cos_p, cos_t, sin_t * sin_p).normalize();
            b.vertex(radius * n, n);
        }
    }
    let south = b.vertex(Vec3::new(0.0, -radius, 0.0), Vec3::NEG_Y);

    let row = |i: u32| 1 + (i - 1) * segments;
    // Rows advance towards -Y and longitude towards +Z, so upper row = `a` faces outward.
    for j in 0..segments {
        let k = (j + 1) % segments;
        b.triangle(north, row(1) + k, row(1) + j);
    }
    for i in 1..rings - 1 {
        b.stitch_rings(row(i), row(i + 1), segments);
    }
    let last = row(rings - 1);
    for j in 0..segments {
        let k = (j + 1) % segments;
        b.triangle(last + j, last + k, south);
    }
    b.finish()
}

/// `segments` points of a circle of `radius` in the plane `y`, starting on +X and turning
/// towards +Z.
pub(crate) fn circle(radius: f32, y: f32, segments: u32) -> Vec<Vec3> {
    (0..segments)
        .map(|j| {
            let (sin, cos) = turn_angle(j, segments).sin_cos();
            Vec3::new(radius * cos, y, radius * sin)
        })
        .collect()
}

/// A capped cylinder around the Y axis from y = 0 to y = `height`, `segments` (≥ 3) around.
/// The side is smooth-shaded; the caps are flat fans with their own vertices at the side's rim
/// positions (copied, so the rims weld exactly).
pub fn cylinder(radius: f32, height: f32, segments: u32) -> TriMesh {
    let segments = segments.max(3);
    let bottom = circle(radius, 0.0, segments);
    let top = circle(radius, height, segments);
    let mut b = Builder::default();

    let top_start = b.mesh.positions.len() as u32;
    for &p in &top {
        b.vertex(p, Vec3::new(p.x, 0.0, p.z).normalize());
    }
    let bottom_start = b.mesh.positions.len() as u32;
    for &p in &bottom {
        b.vertex(p, Vec3::new(p.x, 0.0, p.z).normalize());
    }
    b.stitch_rings(top_start, bottom_start, segments);

    // The circle turns clockwise seen from +Y, so the top cap walks it backwards.
    let top_rim: Vec<Vec3> = top.iter().rev().copied().collect();
    b.flat_fan(Vec3::new(0.0, height, 0.0), &top_rim, Vec3::Y);
    b.flat_fan(Vec3::ZERO, &bottom, Vec3::NEG_Y);
    b.finish()
}

/// A torus lying in the XZ plane (ring around the Y axis), centred on the origin: `segments`
/// (≥ 3) around the ring, `sides` (≥ 3) around the tube. Smooth normals; both seams close by
/// indexing modulo.
pub fn torus(major_radius: f32, minor_radius: f32, segments: u32, sides: u32) -> TriMesh {
    let segments = segments.max(3);
    let sides = sides.max(3);
    let mut b = Builder::default();
    for i in 0..segments {
        let (sin_u, cos_u) = turn_angle(i, segments).sin_cos();
        for j in 0..sides {
            let (sin_v, cos_v) = turn_angle(j, sides).sin_cos();
            let n = Vec3::new(cos_v * cos_u, sin_v, cos_v * sin_u).normalize();
            let centre = Vec3::new(major_radius * cos_u, 0.0, major_radius * sin_u);
            b.vertex(centre + minor_radius * n, n);
        }
    }
    // Ring i → i + 1 moves towards +Z at u = 0 and the tube angle moves towards +Y at the outer
    // equator: (+Y) × (+Z) = +X, outward.
    for i in 0..segments {
        b.stitch_rings(i * sides, ((i + 1) % segments) * sides, sides);
    }
    b.finish()
}

/// A helical spring: a tube of radius `wire_radius` swept along
/// `c(s) = (R cos(2π·turns·s), height·s, R sin(2π·turns·s))`, s ∈ [0, 1], with
/// `ceil(turns · segments_per_turn)` (≥ 3) segments and `sides` (≥ 3) vertices per ring, flat
/// caps at both ends.
///
/// The cross-section uses the helix's Frenet frame: a helix has constant non-zero curvature, so
/// the frame is defined everywhere, and it twists only at the helix's small constant torsion,
/// giving uniform, untangled quads. Consecutive segments share one ring of vertices, so the
/// joints are trivially bitwise equal.
pub fn spring(
    coil_radius: f32,
    wire_radius: f32,
    turns: f32,
    height: f32,
    segments_per_turn: u32,
    sides: u32,
) -> TriMesh {
    let segment_count = ((turns * segments_per_turn as f32).ceil() as u32).max(3);
    let sides = sides.max(3);
    let omega = TAU * turns;

    // Centre, unit tangent and ring positions at sample k; the same closure feeds the caps.
    let frame = |k: u32| {
        let s = k as f32 / segment_count as f32;
        let (sin, cos) = (omega * s).sin_cos();
        let centre = Vec3::new(coil_radius * cos, height * s, coil_radius * sin);
        let tangent = Vec3::new(
            -coil_radius * omega * sin,
            height,
            coil_radius * omega * cos,
        )
        .normalize();
        // Principal normal: towards the axis, perpendicular to the tangent analytically.
        let normal = Vec3::new(-cos, 0.0, -sin);
        let binormal = tangent.cross(normal);
        (centre, tangent, normal, binormal)
    };

    let mut b = Builder::default();
    let mut first_ring = Vec::new();
    let mut last_ring = Vec::new();
    for k in 0..=segment_count {
        let (centre, _, normal, binormal) = frame(k);
        for j in 0..sides {
            let (sin_a, cos_a) = turn_angle(j, sides).sin_cos();
            let n = (cos_a * normal + sin_a * binormal).normalize();
            let p = centre + wire_radius * n;
            b.vertex(p, n);
            if k == 0 {
                first_ring.push(p);
            } else if k == segment_count {
                last_ring.push(p);
            }
        }
    }
    // At α = 0 the ring advances along the binormal and the tube along the tangent:
    // b × t = n (principal normal direction of the offset), i.e. outward from the wire.
    for k in 0..segment_count {
        b.stitch_rings(k * sides, (k + 1) * sides, sides);
    }

    // The ring turns from n to b, counter-clockwise about t (n × b = t): the far cap (normal +t)
    // walks it forwards, the near cap (normal -t) backwards.
    let (start, start_tangent, _, _) = frame(0);
    let (end, end_tangent, _, _) = frame(segment_count);
    first_ring.reverse();
    b.flat_fan(start, &first_ring, -start_tangent);
    b.flat_fan(end, &last_ring, end_tangent);
    b.finish()
}

/// A sharpened pencil: a hexagonal prism (corners at distance `radius` from the Y axis) from
/// y = 0 to y = `length` with a flat hexagonal cap at y = 0, topped by a hexagonal pyramid whose
/// apex is at y = `length + tip_length`. All faces flat-shaded; the pyramid's base edges are
/// the prism's top ring, copied from the same stored corners so they weld exactly.
pub fn pencil(radius: f32, length: f32, tip_length: f32) -> TriMesh {
    let bottom = circle(radius, 0.0, 6);
    let top = circle(radius, length, 6);
    let apex = Vec3::new(0.0, length + tip_length, 0.0);
    let mut b = Builder::default();
    for k in 0..6 {
        let l = (k + 1) % 6;
        // Same orientation rule as `stitch_rings` with a = top, b = bottom.
        b.flat_quad([top[k], top[l], bottom[l], bottom[k]]);
        // The pyramid face is the prism's quad with its top edge collapsed into the apex.
        b.flat_triangle([apex, top[l], top[k]]);
    }
    b.flat_fan(Vec3::ZERO, &bottom, Vec3::NEG_Y);
    b.finish()
}

/// Offsets of `count` bars of thickness `bar` spread over `extent`, centred on zero: the
/// outermost bars are flush with ±extent/2, a single bar sits in the middle.
fn bar_offsets(count: u32, extent: f32, bar: f32) -> impl Iterator<Item = f32> {
    let span = (extent - bar).max(0.0);
    (0..count).map(move |i| {
        if count == 1 {
            0.0
        } else {
            -0.5 * span + span * i as f32 / (count - 1) as f32
        }
    })
}

/// `mesh` moved by `offset`.
pub(crate) fn translated(mut mesh: TriMesh, offset: Vec3) -> TriMesh {
    for p in &mut mesh.positions {
        *p += offset;
    }
    mesh
}

/// A fence in the XY plane centred on the origin, facing +Z: `posts` (≥ 1) vertical bars of
/// full height and `rails` (≥ 0) horizontal bars of full width, all with a `bar` × `bar` square
/// section. Each bar is its own closed box; bars interpenetrate at crossings, which volumetric
/// shadowing handles fine since every box is watertight on its own.
///
/// Note that the outer posts and the outer rails share coplanar end faces, and their corner
/// edges usually coincide exactly, so a consumer that welds positions across the *whole* fence
/// sees those edges used by four triangles. Adjacency must be built per box (per 24-vertex
/// block, in the order posts then rails).
pub fn fence(width: f32, height: f32, posts: u32, rails: u32, bar: f32) -> TriMesh {
    let posts = posts.max(1);
    let post = cuboid(Vec3::new(bar, height, bar));
    let rail = cuboid(Vec3::new(width, bar, bar));
    let mut boxes = Vec::new();
    for x in bar_offsets(posts, width, bar) {
        boxes.push(translated(post.clone(), Vec3::new(x, 0.0, 0.0)));
    }
    for y in bar_offsets(rails, height, bar) {
        boxes.push(translated(rail.clone(), Vec3::new(0.0, y, 0.0)));
    }
    merge(&boxes)
}

/// `mesh` transformed by `m`: positions by `m`, normals by the inverse-transpose of its linear
/// part (renormalised), and winding flipped when `m` mirrors (det < 0) so triangles stay
/// counter-clockwise seen from outside.
pub fn transformed(mesh: &TriMesh, m: Mat4) -> TriMesh {
    let linear = Mat3::from_mat4(m);
    let normal_matrix = linear.inverse().transpose();
    let mirror = linear.determinant() < 0.0;
    TriMesh {
        positions: mesh
            .positions
            .iter()
            .map(|&p| m.transform_point3(p))
            .collect(),
        // A singular `m` has no inverse; keeping the old normal beats emitting NaNs.
        normals: mesh
            .normals
            .iter()
            .map(|&n| (normal_matrix * n).try_normalize().unwrap_or(n))
            .collect(),
        indices: mesh
            .indices
            .iter()
            .map(|&[a, b, c]| if mirror { [a, c, b] } else { [a, b, c] })
            .collect(),
    }
}

/// Concatenates meshes into one, offsetting indices. Nothing is welded: each input keeps its
/// own vertices.
pub fn merge(meshes: &[TriMesh]) -> TriMesh {
    let mut out = TriMesh::default();
    for mesh in meshes {
        let base =
            u32::try_from(out.positions.len()).expect("merged mesh exceeds u32::MAX vertices");
        out.positions.extend_from_slice(&mesh.positions);
        out.normals.extend_from_slice(&mesh.normals);
        out.indices
            .extend(mesh.indices.iter().map(|t| t.map(|i| i + base)));
    }
    out
}

#[cfg(test)]
#[path = "procedural_tests.rs"]
mod tests;
