//! CPU side of particle media (Hillaire 2015's "unified" volumes: particles voxelised into the
//! same froxel grid as the homogeneous fog): the particles as the GPU reads them, their binning
//! into froxel columns (which particles a column's rays can cross: a conservative screen
//! rectangle per sphere) and into the columns of one light-space extinction grid per light (its
//! placement: orthographic along the sun, a perspective cone from a local light around the
//! cloud, or a cube of six 90° cones when the light lies inside a particle or the cloud spans
//! more than 80° around it), as the `voxelise` and `extinction` passes consume them
//! (particles.wgsl).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use scenes::particles::Particle;
use scenes::{CameraPose, LightState};

use crate::common::shadow_maps::CUBE_FACE_AXES;
use crate::common::sphere_cone::SphereSeen;

/// `Particle` in particles.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct GpuParticle {
    pub center: [f32; 3],
    pub radius: f32,
    /// σ_s = albedo · τ, RGB.
    pub sigma_s: [f32; 3],
    pub tau: f32,
}

impl GpuParticle {
    pub fn of(p: &Particle) -> GpuParticle {
        GpuParticle {
            center: p.center.to_array(),
            radius: p.radius,
            sigma_s: (p.albedo * p.density).to_array(),
            tau: p.density,
        }
    }
}

/// The particles each column can meet: `offsets[c]..offsets[c + 1]` index `indices`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bins {
    pub offsets: Vec<u32>,
    pub indices: Vec<u32>,
}

/// A counting sort of `rects` (a particle's index and an inclusive column rectangle (x0, x1, y0,
/// y1) it covers; a particle may have several) into the columns of an `nx` × `ny` grid.
fn bin(nx: u32, ny: u32, rects: &[(u32, [u32; 4])]) -> Bins {
    let cols = (nx * ny) as usize;
    let mut offsets = vec![0u32; cols + 1];
    let each = |s: &[u32; 4], f: &mut dyn FnMut(usize)| {
        for y in s[2]..=s[3] {
            for x in s[0]..=s[1] {
                f((y * nx + x) as usize);
            }
        }
    };
    for (_, s) in rects {
        each(s, &mut |c| offsets[c + 1] += 1);
    }
    for c in 0..cols {
        offsets[c + 1] += offsets[c];
    }
    let mut fill = offsets.clone();
    let mut indices = vec![0u32; offsets[cols] as usize];
    for &(i, ref s) in rects {
        each(s, &mut |c| {
            indices[fill[c] as usize] = i;
            fill[c] += 1;
        });
    }
    Bins { offsets, indices }
}

/// One rectangle per particle (None: it covers no column) as `bin` takes them.
fn indexed(spans: &[Option<[u32; 4]>]) -> Vec<(u32, [u32; 4])> {
    let each = spans.iter().enumerate();
    each.filter_map(|(i, s)| s.map(|s| (i as u32, s))).collect()
}

/// The columns of a grid of `n` = (nx, ny) cells over [lo, hi]² covering the interval
/// [a0, a1] × [b0, b1] (inclusive), or None when it misses the grid.
fn span(n: (u32, u32), lo: f32, hi: f32, a: (f32, f32), b: (f32, f32)) -> Option<[u32; 4]> {
    let cell = |v: f32, m: u32| ((v - lo) / (hi - lo) * m as f32).floor();
    let (x0, x1, y0, y1) = (
        cell(a.0, n.0),
        cell(a.1, n.0),
        cell(b.0, n.1),
        cell(b.1, n.1),
    );
    if x1 < 0.0 || y1 < 0.0 || x0 >= n.0 as f32 || y0 >= n.1 as f32 {
        return None;
    }
    let clamp = |v: f32, m: u32| v.clamp(0.0, (m - 1) as f32) as u32;
    Some([
        clamp(x0, n.0),
        clamp(x1, n.0),
        clamp(y0, n.1),
        clamp(y1, n.1),
    ])
}

/// The range of x/d over x ∈ [x − r, x + r], d ∈ [d − r, d + r] (d − r > 0): conservative
/// perspective bounds of a sphere's projection along one axis.
fn projected(x: f32, d: f32, r: f32) -> (f32, f32) {
    let v = [
        (x - r) / (d - r),
        (x - r) / (d + r),
        (x + r) / (d - r),
        (x + r) / (d + r),
    ];
    (
        v.iter().copied().fold(f32::MAX, f32::min),
        v.iter().copied().fold(f32::MIN, f32::max),
    )
}

/// The froxel columns (`grid` = (columns x, columns y), `pixel_size` pixels each over a `width`
/// × `height` image) each particle's sphere can meet, from the camera.
pub fn camera_bins(
    parts: &[GpuParticle],
    cam: &CameraPose,
    (width, height): (u32, u32),
    pixel_size: f32,
    grid: (u32, u32),
) -> Bins {
    let view = cam.view_from_world();
    let proj = cam.clip_from_view(width as f32 / height as f32);
    let (sx, sy) = (proj.x_axis.x, proj.y_axis.y);
    // Screen extent in pixels of the whole grid (its last column may pass the image's edge).
    let (gw, gh) = (grid.0 as f32 * pixel_size, grid.1 as f32 * pixel_size);
    let spans: Vec<Option<[u32; 4]>> = parts
        .iter()
        .map(|p| {
            let v = view.transform_point3(Vec3::from_array(p.center));
            let (d, r) = (-v.z, p.radius);
            if d + r <= 0.0 {
                return None;
            }
            if d - r <= 1e-3 * cam.near {
                // The sphere reaches the eye's plane: every column, conservatively.
                return Some([0, grid.0 - 1, 0, grid.1 - 1]);
            }
            let (x0, x1) = projected(v.x, d, r);
            let (y0, y1) = projected(v.y, d, r);
            // NDC → pixels (y down).
            let px = |n: f32| (n * sx * 0.5 + 0.5) * width as f32;
            let py = |n: f32| (0.5 - n * sy * 0.5) * height as f32;
            span(
                grid,
                0.0,
                1.0,
                (px(x0) / gw, px(x1) / gw),
                (py(y1) / gh, py(y0) / gh),
            )
        })
        .collect();
    bin(grid.0, grid.1, &indexed(&spans))
}

/// One light's extinction grid: `n` × `n` columns of rays, each cut into `n` slabs between depths
/// z0 and z1; mirrors `LightGrid` in extinction.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightGrid {
    /// xyz: the sun's grid centre (on the plane through the world origin ⟂ its direction) or the
    /// local light's position.
    pub origin: [f32; 4],
    /// xyz: unit right; w: half-extent (m, sun) or tan of the cone's half-angle (local light;
    /// 1 for every face of a cube).
    pub right: [f32; 4],
    /// xyz: unit up.
    pub up: [f32; 4],
    /// xyz: unit axis (the sun's propagation direction, or the cone's axis); w: z0.
    pub axis: [f32; 4],
    pub z1: f32,
    /// 0: none, 1: orthographic (sun), 2: perspective (local light), 3: a cube of six
    /// perspective faces around a local light ([`CUBE_FACE_AXES`]; right, up and axis unused), its
    /// depths and bins face after face.
    pub kind: u32,
    pub n: u32,
    /// First value of this grid in the optical-depth buffer (n³ per face).
    pub depth_at: u32,
    /// First column offset of this grid's bins in the bins buffer.
    pub bins_at: u32,
    pub _pad: [u32; 3],
}

impl LightGrid {
    /// Faces of the grid: 6 for a cube, else 1.
    pub fn faces(&self) -> u32 {
        if self.kind == 3 { 6 } else { 1 }
    }
}

/// A unit basis (right, up) ⟂ `axis` (`grid_basis` in extinction.wgsl).
pub fn basis(axis: Vec3) -> (Vec3, Vec3) {
    let helper = if axis.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let right = axis.cross(helper).normalize();
    (right, right.cross(axis))
}

/// The widest half-angle a local light's cone may have (a perspective grid beyond it would
/// waste its columns at the edges; wider, or a light inside a particle, gets a cube).
const MAX_HALF_ANGLE_DEG: f32 = 80.0;

/// The extinction grid of `light` around `parts` (`n` columns per side, `n` slabs) and its bins.
pub fn light_grid(light: &LightState, parts: &[GpuParticle], n: u32) -> (LightGrid, Bins) {
    let centre = |p: &GpuParticle| Vec3::from_array(p.center);
    let mut g = LightGrid {
        n,
        ..Default::default()
    };
    if parts.is_empty() {
        return (g, bin(n, n, &[]));
    }
    let spans: Vec<Option<[u32; 4]>> = match light {
        LightState::Directional { direction, .. } => {
            let axis = direction.normalize();
            let (right, up) = basis(axis);
            let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for p in parts {
                let c = centre(p);
                let q = Vec3::new(c.dot(right), c.dot(up), c.dot(axis));
                lo = lo.min(q - p.radius);
                hi = hi.max(q + p.radius);
            }
            let mid = 0.5 * (lo + hi);
            let ext = (0.5 * (hi - lo)).truncate().max_element().max(1e-4) * 1.01;
            let origin = right * mid.x + up * mid.y;
            g.kind = 1;
            g.origin = origin.extend(0.0).to_array();
            g.right = right.extend(ext).to_array();
            g.up = up.extend(0.0).to_array();
            g.axis = axis.extend(lo.z).to_array();
            g.z1 = hi.z;
            parts
                .iter()
                .map(|p| {
                    let q = centre(p) - origin;
                    let (u, v, r) = (q.dot(right), q.dot(up), p.radius);
                    span((n, n), -ext, ext, (u - r, u + r), (v - r, v + r))
                })
                .collect()
        }
        _ => {
            let lp = light.position().expect("a local light has a position");
            match local_grid(lp, parts, &mut g) {
                Some(spans) => spans,
                None => return cube_grid(lp, parts, g),
            }
        }
    };
    (g, bin(n, n, &indexed(&spans)))
}

/// Per particle, the columns of an `n` × `n` perspective grid from `lp` (unit `axis`, `right`,
/// `up`; `tan` of its half-angle, depths up to `z1`) its sphere can meet: None behind the grid's
/// plane, every column when it reaches that plane.
fn cone_spans(
    lp: Vec3,
    (axis, right, up): (Vec3, Vec3, Vec3),
    tan: f32,
    (n, z1): (u32, f32),
    parts: &[GpuParticle],
) -> Vec<Option<[u32; 4]>> {
    parts
        .iter()
        .map(|p| {
            let q = Vec3::from_array(p.center) - lp;
            let (d, r) = (q.dot(axis), p.radius);
            if d + r <= 0.0 {
                return None;
            }
            if d - r <= 1e-4 * z1 {
                return Some([0, n - 1, 0, n - 1]);
            }
            let (u0, u1) = projected(q.dot(right), d, r);
            let (v0, v1) = projected(q.dot(up), d, r);
            span((n, n), -tan, tan, (u0, u1), (v0, v1))
        })
        .collect()
}

/// A local light's perspective grid: a cone around the cloud from the light, depths along each
/// column's ray from the light. None when the light lies inside a particle (or at the cloud's
/// centroid) or the cloud spans more than [`MAX_HALF_ANGLE_DEG`] around it.
fn local_grid(lp: Vec3, parts: &[GpuParticle], g: &mut LightGrid) -> Option<Vec<Option<[u32; 4]>>> {
    let sum: Vec3 = parts.iter().map(|p| Vec3::from_array(p.center)).sum();
    let axis = (sum / parts.len() as f32 - lp).try_normalize()?;
    let (right, up) = basis(axis);
    let (mut half, mut z0, mut z1) = (0.0f32, f32::MAX, 0.0f32);
    for p in parts {
        let s = SphereSeen::from(lp, axis, Vec3::from_array(p.center), p.radius)
            .filter(|s| s.distance > p.radius * 1.001)?;
        half = half.max(s.farthest());
        z0 = z0.min(s.distance - p.radius);
        z1 = z1.max(s.distance + p.radius);
    }
    if half > MAX_HALF_ANGLE_DEG.to_radians() {
        return None;
    }
    let tan = half.tan() * 1.01;
    g.kind = 2;
    g.origin = lp.extend(0.0).to_array();
    g.right = right.extend(tan).to_array();
    g.up = up.extend(0.0).to_array();
    g.axis = axis.extend(z0.max(0.0)).to_array();
    g.z1 = z1;
    Some(cone_spans(lp, (axis, right, up), tan, (g.n, z1), parts))
}

/// A local light's cube grid: six 90° perspective faces around the light (any cloud, the light
/// inside a particle included), depths from the light out to the farthest sphere; its bins are
/// one `n` × 6n grid, face f's columns in rows f·n .. (f + 1)·n.
fn cube_grid(lp: Vec3, parts: &[GpuParticle], mut g: LightGrid) -> (LightGrid, Bins) {
    let n = g.n;
    let far = |p: &GpuParticle| (Vec3::from_array(p.center) - lp).length() + p.radius;
    let z1 = parts.iter().map(far).fold(0.0f32, f32::max);
    g.kind = 3;
    g.origin = lp.extend(0.0).to_array();
    g.right = [1.0, 0.0, 0.0, 1.0];
    g.axis = [0.0; 4];
    g.z1 = z1;
    let mut rects = Vec::new();
    for (f, &axis) in CUBE_FACE_AXES.iter().enumerate() {
        let (right, up) = basis(axis);
        let spans = cone_spans(lp, (axis, right, up), 1.0, (n, z1), parts);
        let shift = f as u32 * n;
        let face = indexed(&spans).into_iter();
        rects.extend(face.map(|(i, s)| (i, [s[0], s[1], s[2] + shift, s[3] + shift])));
    }
    (g, bin(n, 6 * n, &rects))
}

#[cfg(test)]
#[path = "particles_tests.rs"]
mod tests;
