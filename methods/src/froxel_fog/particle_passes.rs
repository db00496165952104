//! GPU side of particle media: the buffers the volume passes read (per-froxel density, the
//! light grids' optical depths, the particle uniform — 16-byte stubs for homogeneous media), and
//! for particle scenes the `voxelise` and `extinction` passes, the bins they walk (rebuilt on
//! the CPU only when the camera or a light changed), the cloud's shadow on surfaces per light
//! (`common::particles::surface_shadow` with particle_shadow.wgsl) and the pass that attenuates
//! the surface
//! AOV by the cloud toward the eye (particle_surface.wgsl).

use anyhow::Result;
use bytemuck::{Pod, Zeroable};
use harness::method::AOV_FORMAT;
use harness::{FrameReport, Gpu, Targets};
use scenes::{CameraPose, FrameState, LightState};

use super::particles::{Bins, GpuParticle, LightGrid, camera_bins, light_grid};
use super::shaders::{particle_shadow_source, particle_surface_source, particles_source};
use crate::common::layouts::{
    buffer_entry, float_texture, rgba32f_storage_write, storage_buffer, uniform_buffer, view_entry,
};
use crate::common::pipeline::{self, ComputeStage};
use crate::common::renderer::SceneRenderer;
use crate::common::particles::surface_shadow::SurfaceShadow;
use crate::common::wgsl;

/// Light grids the particle uniform holds (`grids` in extinction.wgsl's `ParticleMedium`): one
/// per light, so particle media render with at most this many lights (`support`).
pub const PARTICLE_GRIDS: usize = 4;

/// Optical depths the light grids of `lights` need at most (`n` columns per side): n³ for the
/// sun's, 6 n³ for a local light's (its grid may be a cube, particles::light_grid).
pub fn grid_values(lights: &[scenes::desc::LightDesc], n: u32) -> u64 {
    let faces = |l: &scenes::desc::LightDesc| match l {
        scenes::desc::LightDesc::Directional { .. } => 1,
        _ => 6,
    };
    let per_face = (n as u64).pow(3);
    lights
        .iter()
        .take(PARTICLE_GRIDS)
        .map(|l| faces(l) * per_face)
        .sum()
}

/// `ParticleMedium` in extinction.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ParticleUniform {
    sky: [f32; 4],
    count: u32,
    _pad: [u32; 3],
    grids: [LightGrid; PARTICLE_GRIDS],
}

/// What the volume passes bind for particles (stubs for a homogeneous medium).
pub struct MediumBuffers {
    pub uniform: wgpu::Buffer,
    pub density: wgpu::Buffer,
    pub optical_depth: wgpu::Buffer,
}

impl MediumBuffers {
    /// `froxels`: cells of the grid; `grid_values`: values of every light's extinction grid.
    pub fn new(gpu: &Gpu, froxels: u64, grid_values: u64) -> MediumBuffers {
        let storage = |label, size: u64| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(32),
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        MediumBuffers {
            uniform: gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("froxel particle medium"),
                size: std::mem::size_of::<ParticleUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            density: storage("froxel density", 32 * froxels),
            optical_depth: storage("froxel light extinction", 4 * grid_values),
        }
    }
}

/// The grid the voxelisation covers: froxel columns, pixels per column, image size.
#[derive(Clone, Copy)]
pub struct Grid {
    pub columns: (u32, u32),
    pub pixel_size: f32,
    pub image: (u32, u32),
}

/// Bins and grids as last uploaded, so unchanged frames reuse them.
#[derive(Default)]
struct Cache {
    camera: Option<CameraPose>,
    camera_bins: Bins,
    lights: Vec<LightState>,
    grids: Vec<(LightGrid, Bins)>,
}

pub struct ParticlePasses {
    parts: Vec<GpuParticle>,
    particles: wgpu::Buffer,
    bins: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    bind: wgpu::BindGroup,
    voxelise: wgpu::ComputePipeline,
    extinction: wgpu::ComputePipeline,
    surface_layout: wgpu::BindGroupLayout,
    surface: wgpu::ComputePipeline,
    /// The cloud's shadow on surfaces, one pass per light.
    shadow: SurfaceShadow,
    /// The shared surface pass's output (shaded with the background medium only).
    pub surface_view: wgpu::TextureView,
    grid: Grid,
    /// Columns per side (and slabs) of each light's extinction grid.
    n: u32,
    sky: [f32; 4],
    cache: Cache,
    no_skip: bool,
}

/// Borrowed buffers the particle passes bind beside their own.
pub struct Shared<'a> {
    pub froxel: &'a wgpu::Buffer,
    pub medium: &'a MediumBuffers,
}

/// Packs bin sets one after another into one u32 array: each set's offsets (made absolute) then
/// its indices. Returns the array and where each set's offsets start.
fn pack(sets: &[&Bins]) -> (Vec<u32>, Vec<u32>) {
    let mut data = Vec::new();
    let mut starts = Vec::new();
    for b in sets {
        let start = data.len() as u32;
        let first = start + b.offsets.len() as u32;
        starts.push(start);
        data.extend(b.offsets.iter().map(|o| o + first));
        data.extend_from_slice(&b.indices);
    }
    (data, starts)
}

const CS: wgpu::ShaderStages = wgpu::ShaderStages::COMPUTE;

fn compute_pipeline(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    layout: &wgpu::BindGroupLayout,
    source: &str,
    entry: &str,
) -> wgpu::ComputePipeline {
    let module = wgsl::module(&gpu.device, entry, source);
    let pl = pipeline::layout(&gpu.device, entry, &[&renderer.frame_layout, layout]);
    ComputeStage::new(entry, entry).build(
        &gpu.device,
        &pl,
        &module,
        renderer.specialization.constants(),
    )
}

impl ParticlePasses {
    /// `n`: columns per side (and slabs) of each light's extinction grid.
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        shared: Shared,
        grid: Grid,
        n: u32,
        no_skip: bool,
    ) -> Result<ParticlePasses> {
        let medium = renderer.scene.medium();
        let p = medium.particles().expect("a particle medium");
        let parts: Vec<GpuParticle> = p.particles.iter().map(GpuParticle::of).collect();
        // wgpu refuses an empty binding: one zero particle stands in (count 0 reads none).
        let stub = [GpuParticle::zeroed()];
        let contents = if parts.is_empty() {
            &stub[..]
        } else {
            &parts[..]
        };
        let particles = gpu.buffer_init(
            "froxel particles",
            bytemuck::cast_slice(contents),
            wgpu::BufferUsages::STORAGE,
        );
        let storage = |b, ro| storage_buffer(b, wgpu::ShaderStages::COMPUTE, ro);
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("froxel particles"),
                entries: &[
                    uniform_buffer(0, CS),
                    uniform_buffer(1, CS),
                    storage(2, true),
                    storage(3, true),
                    storage(4, false),
                    storage(5, false),
                ],
            });
        let bins = bins_buffer(gpu, 16);
        let bind = particle_group(gpu, &layout, &shared, &particles, &bins);
        let surface_layout = surface_layout(gpu);
        let private = gpu.texture_2d(
            "froxel surface (background only)",
            grid.image.0,
            grid.image.1,
            AOV_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let src = particles_source();
        let lights = renderer.scene.desc.lights.len().min(PARTICLE_GRIDS);
        let (shadow_layout, shadow_bind) = shadow_group(gpu, shared.medium);
        let shadow = SurfaceShadow::new(
            &gpu.device,
            renderer,
            &[(&shadow_layout, &shadow_bind)],
            renderer.specialization.constants(),
            lights,
            &particle_shadow_source(),
        );
        Ok(ParticlePasses {
            voxelise: compute_pipeline(gpu, renderer, &layout, &src, "voxelise"),
            extinction: compute_pipeline(gpu, renderer, &layout, &src, "extinction"),
            surface: compute_pipeline(
                gpu,
                renderer,
                &surface_layout,
                &particle_surface_source(),
                "particle_surface",
            ),
            surface_view: private.create_view(&Default::default()),
            sky: p.sky.extend(0.0).to_array(),
            parts,
            particles,
            bins,
            layout,
            bind,
            surface_layout,
            shadow,
            grid,
            n,
            cache: Cache::default(),
            no_skip,
        })
    }
}

fn bins_buffer(gpu: &Gpu, bytes: u64) -> wgpu::Buffer {
    gpu.buffer(&wgpu::BufferDescriptor {
        label: Some("froxel particle bins"),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn particle_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    shared: &Shared,
    particles: &wgpu::Buffer,
    bins: &wgpu::Buffer,
) -> wgpu::BindGroup {
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("froxel particles"),
        layout,
        entries: &[
            buffer_entry(0, shared.froxel),
            buffer_entry(1, &shared.medium.uniform),
            buffer_entry(2, particles),
            buffer_entry(3, bins),
            buffer_entry(4, &shared.medium.density),
            buffer_entry(5, &shared.medium.optical_depth),
        ],
    })
}

/// Group 1 of the per-light cloud-shadow pass (particle_shadow.wgsl): the particle uniform and
/// the light grids' optical depths.
fn shadow_group(gpu: &Gpu, medium: &MediumBuffers) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let fs = wgpu::ShaderStages::FRAGMENT;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("froxel particle shadow"),
            entries: &[uniform_buffer(0, fs), storage_buffer(1, fs, true)],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("froxel particle shadow"),
        layout: &layout,
        entries: &[
            buffer_entry(0, &medium.uniform),
            buffer_entry(1, &medium.optical_depth),
        ],
    });
    (layout, bind)
}

/// Group 1 of the particle surface pass: ray distance, the background-only surface, the grid
/// uniform, the integrated volume, the particle uniform, the optical depths, the surface AOV.
fn surface_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("froxel particle surface"),
            entries: &[
                float_texture(0, CS),
                float_texture(1, CS),
                uniform_buffer(2, CS),
                float_texture(3, CS),
                uniform_buffer(4, CS),
                storage_buffer(5, wgpu::ShaderStages::COMPUTE, true),
                // AOV_FORMAT is Rgba32Float.
                rgba32f_storage_write(6, CS),
            ],
        })
}

impl ParticlePasses {
    /// This frame's bins and light grids — rebuilt on the CPU only when the camera or a light
    /// changed (or with no_skip) — and the particle uniform.
    pub fn update(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        shared: &Shared,
        report: &mut FrameReport,
    ) {
        let c = &mut self.cache;
        let camera_changed = c.camera != Some(frame.camera);
        let lights_changed = c.lights != frame.lights || c.camera.is_none();
        if !(camera_changed || lights_changed || self.no_skip) {
            report.skip(
                "particle-bins",
                "camera and lights unchanged since the previous frame",
            );
            return;
        }
        let g = self.grid;
        c.camera_bins = camera_bins(&self.parts, &frame.camera, g.image, g.pixel_size, g.columns);
        c.camera = Some(frame.camera);
        c.grids = frame
            .lights
            .iter()
            .take(PARTICLE_GRIDS)
            .map(|l| light_grid(l, &self.parts, self.n))
            .collect();
        c.lights = frame.lights.clone();
        let sets: Vec<&Bins> = std::iter::once(&c.camera_bins)
            .chain(c.grids.iter().map(|(_, b)| b))
            .collect();
        let (data, starts) = pack(&sets);
        let bytes = 4 * data.len() as u64;
        if bytes > self.bins.size() {
            self.bins = bins_buffer(gpu, (bytes + bytes / 2).next_multiple_of(16));
            self.bind = particle_group(gpu, &self.layout, shared, &self.particles, &self.bins);
        }
        gpu.queue
            .write_buffer(&self.bins, 0, bytemuck::cast_slice(&data));
        let mut u = ParticleUniform {
            sky: self.sky,
            count: self.parts.len() as u32,
            ..Zeroable::zeroed()
        };
        let per_face = self.n * self.n * self.n;
        let mut depth_at = 0;
        for (k, (grid, _)) in c.grids.iter().enumerate() {
            u.grids[k] = LightGrid {
                depth_at,
                bins_at: starts[k + 1],
                ..*grid
            };
            depth_at += grid.faces() * per_face;
        }
        gpu.queue
            .write_buffer(&shared.medium.uniform, 0, bytemuck::bytes_of(&u));
        report.ran("particle-bins");
    }

    /// Particles with a froxel column to voxelise into, and (particle, column) pairs.
    pub fn counts(&self) -> (f64, f64) {
        let b = &self.cache.camera_bins;
        let mut seen = vec![false; self.parts.len()];
        for &i in &b.indices {
            seen[i as usize] = true;
        }
        let n = seen.iter().filter(|&&s| s).count();
        (n as f64, b.indices.len() as f64)
    }

    fn pass<'e>(
        &self,
        gpu: &Gpu,
        enc: &'e mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        label: &str,
    ) -> harness::gpu::Counted<wgpu::ComputePass<'e>> {
        renderer.compute_pass(gpu, enc, label, &self.bind)
    }

    /// Every froxel's mean particle σ_s and τ.
    pub fn encode_voxelise(&self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, r: &SceneRenderer) {
        let mut pass = self.pass(gpu, enc, r, "froxel voxelise");
        pass.set_pipeline(&self.voxelise);
        let (gx, gy) = self.grid.columns;
        pass.dispatch_workgroups(gx.div_ceil(8), gy.div_ceil(8), 1);
    }

    /// Every light's extinction grid.
    pub fn encode_extinction(&self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, r: &SceneRenderer) {
        let lights = self.cache.grids.len() as u32;
        if lights == 0 {
            return;
        }
        let mut pass = self.pass(gpu, enc, r, "froxel extinction");
        pass.set_pipeline(&self.extinction);
        // Room for a cube's six faces; a grid of one face ends its threads past n².
        pass.dispatch_workgroups((6 * self.n * self.n).div_ceil(64), 1, lights);
    }

    /// Removes from the background-only surface each light's share blocked by the cloud (after
    /// `encode_extinction`).
    pub fn encode_shadow(&self, enc: &mut wgpu::CommandEncoder, r: &SceneRenderer) {
        for k in 0..self.cache.grids.len() {
            self.shadow.encode(enc, r, &self.surface_view, k);
        }
    }

    /// The surface AOV: the shadowed surface attenuated by the cloud toward the eye, or the sky.
    pub fn encode_surface(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        r: &SceneRenderer,
        shared: &Shared,
        volume: &wgpu::TextureView,
        targets: &Targets,
    ) {
        // The harness owns the AOV textures, so this group is built per frame.
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("froxel particle surface"),
            layout: &self.surface_layout,
            entries: &[
                view_entry(0, &r.distance_view),
                view_entry(1, &self.surface_view),
                buffer_entry(2, shared.froxel),
                view_entry(3, volume),
                buffer_entry(4, &shared.medium.uniform),
                buffer_entry(5, &shared.medium.optical_depth),
                view_entry(6, targets.surface),
            ],
        });
        let mut pass = gpu.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some("froxel particle surface"),
                timestamp_writes: None,
            },
        );
        pass.set_bind_group(0, &r.frame_bind, &[]);
        pass.set_bind_group(1, &bind, &[]);
        pass.set_pipeline(&self.surface);
        pass.dispatch_workgroups(targets.width.div_ceil(8), targets.height.div_ceil(8), 1);
    }
}
