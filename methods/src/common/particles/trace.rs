//! Exact particle optical depth on the GPU: a uniform grid over the scene's spheres, built on the
//! CPU at prepare, and its WGSL (`wgsl/particle_trace.wgsl`: a 3-D DDA over the cells along a
//! segment, each sphere's chord clipped to the current cell's t-range).
//!
//! Why clipping makes the sums exact without deduplication: the cells' t-ranges partition the
//! segment, and a sphere whose chord meets a cell's range overlaps that cell, so it is listed
//! there. Summing `τ_j · |chord_j ∩ [t_enter, t_exit]|` over each visited cell's list counts
//! every sphere's chord once, piece by piece, front to back. Listing is conservative (each
//! sphere goes to every cell its bounds overlap, padded by a small fraction of a cell against
//! rounding in the DDA): a listed sphere whose chord misses the cell adds zero.
//!
//! Cells are cubes sized so the grid has about [`CELLS_PER_PARTICLE`] cells per particle over
//! the cloud's bounds (capped at [`MAX_CELLS_PER_AXIS`] per axis); empty cells cost the DDA one
//! step and one read of their (equal) offsets. Limits: every storage binding must fit the
//! device's `max_storage_buffer_binding_size` (128 MiB on lavapipe); a scene whose spheres or
//! cell lists exceed it is refused at prepare with the sizes in the message. 1 000 000 spheres
//! take 32 MB of spheres plus their cell lists (about 4 B per sphere-cell overlap).

use anyhow::{Result, bail};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use harness::Gpu;
use scenes::Particles;

use crate::common::layouts::{buffer_entry, storage_buffer, uniform_buffer};

/// Target cells per particle (grid resolution from the particle count).
pub const CELLS_PER_PARTICLE: f32 = 1.0;
/// Largest cells per axis (the cell-offset array stays ≤ 64 MiB).
pub const MAX_CELLS_PER_AXIS: u32 = 256;

/// `GridInfo` in particle_trace.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GridInfo {
    /// xyz: the grid's low corner (m); w: unused.
    pub lo: [f32; 4],
    /// xyz: one cell's size (m); w: unused.
    pub cell: [f32; 4],
    /// xyz: cells per axis; w: the number of spheres.
    pub dims: [u32; 4],
    /// rgb: the sky radiance behind the cloud (W/(m² sr)); w: unused.
    pub sky: [f32; 4],
}

/// `Sphere` in particle_trace.wgsl: centre and radius, albedo and extinction τ.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuSphere {
    /// xyz: centre (m); w: radius (m).
    pub center_radius: [f32; 4],
    /// rgb: single-scattering albedo; w: extinction τ inside (1/m).
    pub albedo_tau: [f32; 4],
}

/// The grid on the CPU: its header, spheres and per-cell lists (CSR: `cell_start[c] ..
/// cell_start[c + 1]` index `cell_items`).
#[derive(Clone, Debug)]
pub struct ParticleGrid {
    pub info: GridInfo,
    pub spheres: Vec<GpuSphere>,
    pub cell_start: Vec<u32>,
    pub cell_items: Vec<u32>,
}

impl ParticleGrid {
    /// The grid over `p`'s spheres (zero-radius and zero-density spheres are left out: they add
    /// nothing to any optical depth).
    pub fn build(p: &Particles) -> ParticleGrid {
        let spheres: Vec<GpuSphere> = (p.particles.iter())
            .filter(|q| q.radius > 0.0 && q.density > 0.0)
            .map(|q| GpuSphere {
                center_radius: [q.center.x, q.center.y, q.center.z, q.radius],
                albedo_tau: [q.albedo.x, q.albedo.y, q.albedo.z, q.density],
            })
            .collect();
        let (lo, cell, dims) = layout(&spheres);
        let cells = (dims[0] * dims[1] * dims[2]) as usize;
        let mut counts = vec![0u32; cells + 1];
        for_each_overlap(&spheres, lo, cell, dims, |c, _| counts[c] += 1);
        // Exclusive prefix sum: counts[c] becomes the first index of cell c.
        let mut sum = 0u32;
        for n in counts.iter_mut() {
            let here = *n;
            *n = sum;
            sum += here;
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; sum as usize];
        for_each_overlap(&spheres, lo, cell, dims, |c, j| {
            items[fill[c] as usize] = j;
            fill[c] += 1;
        });
        let sky = p.sky;
        ParticleGrid {
            info: GridInfo {
                lo: [lo.x, lo.y, lo.z, 0.0],
                cell: [cell.x, cell.y, cell.z, 0.0],
                dims: [dims[0], dims[1], dims[2], spheres.len() as u32],
                sky: [sky.x, sky.y, sky.z, 0.0],
            },
            spheres,
            cell_start: counts,
            cell_items: items,
        }
    }

    /// The largest storage binding this grid needs, bytes.
    pub fn largest_binding(&self) -> u64 {
        let sphere_bytes = std::mem::size_of::<GpuSphere>() as u64 * self.spheres.len() as u64;
        sphere_bytes
            .max(4 * self.cell_start.len() as u64)
            .max(4 * self.cell_items.len() as u64)
    }
}

/// The grid's low corner, cell size and cells per axis: cubic cells, about
/// [`CELLS_PER_PARTICLE`] per sphere over the spheres' bounds, at least one.
fn layout(spheres: &[GpuSphere]) -> (Vec3, Vec3, [u32; 3]) {
    if spheres.is_empty() {
        return (Vec3::ZERO, Vec3::ONE, [1, 1, 1]);
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for s in spheres {
        let [x, y, z, r] = s.center_radius;
        lo = lo.min(Vec3::new(x, y, z) - r);
        hi = hi.max(Vec3::new(x, y, z) + r);
    }
    // A little margin so no sphere touches the grid's faces.
    let pad = (hi - lo).max_element() * 1e-4 + 1e-6;
    let (lo, hi) = (lo - pad, hi + pad);
    let extent = hi - lo;
    let target = (spheres.len() as f32 * CELLS_PER_PARTICLE).max(1.0);
    let side = (extent.x * extent.y * extent.z / target)
        .cbrt()
        .max(extent.max_element() / MAX_CELLS_PER_AXIS as f32);
    let dims = (extent / side)
        .ceil()
        .clamp(Vec3::ONE, Vec3::splat(MAX_CELLS_PER_AXIS as f32));
    let dims = [dims.x as u32, dims.y as u32, dims.z as u32];
    let cell = extent / Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
    (lo, cell, dims)
}

/// Calls `f(cell, sphere)` for every cell a sphere overlaps (sphere–box distance ≤ radius plus
/// 1e-3 of a cell, against rounding in the GPU's DDA).
fn for_each_overlap(
    spheres: &[GpuSphere],
    lo: Vec3,
    cell: Vec3,
    dims: [u32; 3],
    mut f: impl FnMut(usize, u32),
) {
    let pad = 1e-3 * cell.max_element();
    let max = [dims[0] - 1, dims[1] - 1, dims[2] - 1];
    let index = |v: f32, k: usize| ((v / cell[k]).floor().max(0.0) as u32).min(max[k]);
    for (j, s) in spheres.iter().enumerate() {
        let [x, y, z, r] = s.center_radius;
        let c = Vec3::new(x, y, z);
        let (a, b) = (c - r - pad - lo, c + r + pad - lo);
        for iz in index(a.z, 2)..=index(b.z, 2) {
            for iy in index(a.y, 1)..=index(b.y, 1) {
                for ix in index(a.x, 0)..=index(b.x, 0) {
                    let box_lo = lo + Vec3::new(ix as f32, iy as f32, iz as f32) * cell;
                    let nearest = c.clamp(box_lo, box_lo + cell);
                    if (nearest - c).length() <= r + pad {
                        let id = ix + dims[0] * (iy + dims[1] * iz);
                        f(id as usize, j as u32);
                    }
                }
            }
        }
    }
}

/// The grid on the GPU: group 2 of the passes that compose `particle_trace.wgsl` (the header
/// uniform at binding 0, spheres, cell offsets and cell lists at 1–3).
pub struct GpuParticleGrid {
    pub layout: wgpu::BindGroupLayout,
    pub bind: wgpu::BindGroup,
}

impl GpuParticleGrid {
    /// Uploads `grid`; fails, naming the limit, where a binding exceeds the device's largest
    /// storage binding.
    pub fn new(gpu: &Gpu, grid: &ParticleGrid) -> Result<GpuParticleGrid> {
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        if grid.largest_binding() > limit {
            bail!(
                "{} particles: the particle grid needs a {} MiB storage binding (spheres {} MiB, \
                 cell lists {} MiB); the device's max_storage_buffer_binding_size is {} MiB",
                grid.spheres.len(),
                grid.largest_binding() >> 20,
                (32 * grid.spheres.len()) >> 20,
                (4 * grid.cell_items.len()) >> 20,
                limit >> 20
            );
        }
        let storage = wgpu::BufferUsages::STORAGE;
        // Storage bindings may not be empty: one zero element stands in.
        let nonempty = |bytes: &[u8]| -> Vec<u8> {
            if bytes.is_empty() {
                vec![0u8; 32]
            } else {
                bytes.to_vec()
            }
        };
        let info = gpu.buffer_init(
            "particle grid info",
            bytemuck::bytes_of(&grid.info),
            wgpu::BufferUsages::UNIFORM,
        );
        let spheres = gpu.buffer_init(
            "particle spheres",
            &nonempty(bytemuck::cast_slice(&grid.spheres)),
            storage,
        );
        let starts = gpu.buffer_init(
            "particle cell starts",
            bytemuck::cast_slice(&grid.cell_start),
            storage,
        );
        let items = gpu.buffer_init(
            "particle cell items",
            &nonempty(bytemuck::cast_slice(&grid.cell_items)),
            storage,
        );
        let layout = grid_layout(&gpu.device);
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particle grid"),
            layout: &layout,
            entries: &[
                buffer_entry(0, &info),
                buffer_entry(1, &spheres),
                buffer_entry(2, &starts),
                buffer_entry(3, &items),
            ],
        });
        Ok(GpuParticleGrid { layout, bind })
    }
}

/// Group 2's layout: the header uniform and three read-only storage buffers, fragment stage.
fn grid_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("particle grid"),
        entries: &[
            uniform_buffer(0, fragment),
            storage_buffer(1, fragment, true),
            storage_buffer(2, fragment, true),
            storage_buffer(3, fragment, true),
        ],
    })
}

/// The particle trace's WGSL (group 2 bindings, the DDA, `optical_depth`); needs PRELUDE.
pub const PARTICLE_TRACE_WGSL: &str = include_str!("particle_trace.wgsl");

/// What the particle resolves share (`pixel_ray`, `surface_or_sky`); composed after
/// [`PARTICLE_TRACE_WGSL`] in a `common::resolve` pass.
pub const PARTICLE_RESOLVE_WGSL: &str = include_str!("particle_resolve.wgsl");

/// A particle resolve's own WGSL after the trace and [`PARTICLE_RESOLVE_WGSL`] (the resolve
/// pass adds PRELUDE, FULLSCREEN and its I/O first).
pub fn resolve_source(own: &str) -> String {
    format!("{PARTICLE_TRACE_WGSL}\n{PARTICLE_RESOLVE_WGSL}\n{own}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// particle_trace.wgsl's walk and clipped sums, on the CPU (f32, the same steps).
    fn walk_depth(g: &ParticleGrid, o: Vec3, d: Vec3, t0: f32, t1: f32) -> f32 {
        let dims = [
            g.info.dims[0] as i32,
            g.info.dims[1] as i32,
            g.info.dims[2] as i32,
        ];
        let lo = Vec3::from_slice(&g.info.lo[..3]);
        let size = Vec3::from_slice(&g.info.cell[..3]);
        let hi = lo + size * Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
        let safe = Vec3::select(d.abs().cmplt(Vec3::splat(1e-20)), Vec3::splat(1e-20), d);
        let inv = 1.0 / safe;
        let (a, b) = ((lo - o) * inv, (hi - o) * inv);
        let mut t = a.min(b).max_element().max(t0);
        let t_end = a.max(b).min_element().min(t1);
        let p = o + d * (0.5 * (t + t_end.min(t + 1e-3 * size.min_element())));
        let mut cell = ((p - lo) / size).floor().as_ivec3();
        cell = cell.clamp(glam::IVec3::ZERO, glam::IVec3::from(dims) - 1);
        let step = glam::IVec3::select(safe.cmpgt(Vec3::ZERO), glam::IVec3::ONE, -glam::IVec3::ONE);
        let up = glam::IVec3::select(
            step.cmpgt(glam::IVec3::ZERO),
            glam::IVec3::ONE,
            glam::IVec3::ZERO,
        );
        let mut t_next = (lo + size * (cell + up).as_vec3() - o) * inv;
        let t_delta = (size * inv).abs();
        let mut tau = 0.0;
        while t < t_end {
            let index = (cell.x + dims[0] * (cell.y + dims[1] * cell.z)) as usize;
            let enter = t;
            let axis = if t_next.x <= t_next.y && t_next.x <= t_next.z {
                0
            } else if t_next.y <= t_next.z {
                1
            } else {
                2
            };
            let mut exit = t_next.min_element().min(t_end);
            cell[axis] += step[axis];
            t_next[axis] += t_delta[axis];
            if cell[axis] < 0 || cell[axis] >= dims[axis] {
                exit = t_end;
            }
            let exit = exit.max(enter);
            t = exit;
            for &j in &g.cell_items[g.cell_start[index] as usize..g.cell_start[index + 1] as usize]
            {
                tau += chord(&g.spheres[j as usize], o, d, enter, exit);
            }
        }
        tau
    }

    /// τ_j · |chord_j ∩ [a, b]|.
    fn chord(s: &GpuSphere, o: Vec3, d: Vec3, a: f32, b: f32) -> f32 {
        let [x, y, z, r] = s.center_radius;
        let oc = Vec3::new(x, y, z) - o;
        let tc = oc.dot(d);
        let q = oc - d * tc;
        let h2 = r * r - q.length_squared();
        if h2 <= 0.0 {
            return 0.0;
        }
        let h = h2.sqrt();
        s.albedo_tau[3] * ((tc + h).min(b) - (tc - h).max(a)).max(0.0)
    }

    #[test]
    fn the_walk_sums_every_chord_once() {
        let scene = scenes::library::load("cloud-8000").unwrap().unwrap();
        let medium = scene.medium();
        let g = ParticleGrid::build(medium.particles().unwrap());
        let o = Vec3::new(0.3, 2.0, 9.0);
        let mut worst = 0.0f32;
        for k in 0..400 {
            let u = (k as f32 * 0.618034).fract() - 0.5;
            let v = (k as f32 * 0.414214).fract() - 0.5;
            let d = (Vec3::new(u, v - 0.2, -1.0)).normalize();
            let brute: f32 = g.spheres.iter().map(|s| chord(s, o, d, 0.0, 100.0)).sum();
            let walked = walk_depth(&g, o, d, 0.0, 100.0);
            worst = worst.max((walked - brute).abs() / brute.max(1e-3));
        }
        assert!(worst < 1e-4, "worst relative difference {worst}");
    }
}
