//! The three GPU passes of `dobashi-virtual-planes` after the shared shadow and surface passes:
//! the far-extent reduction (compute), the virtual planes (instanced lattices, additive blending
//! into the accumulation target) and the resolve (accumulation → `inscatter`, `total`).

use harness::gpu::color_attachment;
use harness::{Gpu, Targets};

use crate::common::layouts::{float_texture, storage_buffer, uniform_buffer};
use crate::common::pipeline::{self, ComputeStage, Stage};
use crate::common::renderer::SceneRenderer;
use crate::common::resolve::{self, ResolvePass};
use crate::common::specialize::flag;
use crate::common::wgsl;

pub const DOBASHI_WGSL: &str = include_str!("dobashi.wgsl");
pub const PLANES_WGSL: &str = include_str!("planes.wgsl");
pub const FAR_WGSL: &str = include_str!("far.wgsl");
pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");
pub const PROBE_WGSL: &str = include_str!("probe.wgsl");

/// Composed sources, by pass (also validated by naga via `Method::shaders`).
pub fn planes_source() -> String {
    wgsl::compose(&[wgsl::PRELUDE, &[DOBASHI_WGSL]].concat(), PLANES_WGSL)
}
pub fn far_source() -> String {
    wgsl::compose(wgsl::PRELUDE, FAR_WGSL)
}
/// The resolve pass's own part (composed by `common::resolve` after the prelude).
fn resolve_own() -> String {
    format!("{DOBASHI_WGSL}\n{RESOLVE_WGSL}")
}
pub fn resolve_source() -> String {
    resolve::source(&resolve_own())
}
pub fn probe_source() -> String {
    wgsl::compose(&[wgsl::PRELUDE, &[DOBASHI_WGSL]].concat(), PROBE_WGSL)
}

/// Mirrors `Planes` in dobashi.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlanesUniform {
    pub count: u32,
    pub nu: u32,
    pub nv: u32,
    pub flags: u32,
    pub frame: u32,
    pub _pad0: [u32; 3],
    pub scale: f32,
    pub _pad1: [f32; 3],
}

pub const FLAG_JITTER: u32 = 1;
pub const FLAG_CLIP_LAST: u32 = 4;

const ALL: wgpu::ShaderStages =
    wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE);

/// Writable storage is compute-only (vertex-stage writes need VERTEX_WRITABLE_STORAGE).
fn writable_storage(binding: u32) -> wgpu::BindGroupLayoutEntry {
    storage_buffer(binding, wgpu::ShaderStages::COMPUTE, false)
}

fn layout(gpu: &Gpu, label: &str, entries: &[wgpu::BindGroupLayoutEntry]) -> wgpu::BindGroupLayout {
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries,
        })
}

fn bind(
    gpu: &Gpu,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(k, r)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: r.clone(),
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

fn pipeline_layout(
    gpu: &Gpu,
    label: &str,
    renderer: &SceneRenderer,
    own: &wgpu::BindGroupLayout,
) -> wgpu::PipelineLayout {
    pipeline::layout(&gpu.device, label, &[&renderer.frame_layout, own])
}

fn compute_pipeline(
    gpu: &Gpu,
    label: &str,
    renderer: &SceneRenderer,
    own: &wgpu::BindGroupLayout,
    source: &str,
) -> wgpu::ComputePipeline {
    let module = wgsl::module(&gpu.device, label, source);
    ComputeStage::new(label, "main").build(
        &gpu.device,
        &pipeline_layout(gpu, label, renderer, own),
        &module,
        renderer.specialization.constants(),
    )
}

/// The virtual planes: instanced lattices blended additively into the accumulation target
/// (`accum`), ξ per fragment or per vertex. Planes end at the surfaces by a test against the
/// surface pass's distance in the fragment shader (it also needs the distance to shorten the
/// last slab): no depth.
fn planes_pipeline(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    own: &wgpu::BindGroupLayout,
    accum: wgpu::TextureFormat,
    xi_per_fragment: bool,
) -> wgpu::RenderPipeline {
    let constants = renderer
        .specialization
        .with(&[("XI_PER_FRAGMENT", flag(xi_per_fragment))]);
    let module = wgsl::module(&gpu.device, "dobashi planes", &planes_source());
    let layout = pipeline_layout(gpu, "dobashi planes", renderer, own);
    let targets = [pipeline::target(accum, Some(pipeline::ADDITIVE))];
    Stage::new("dobashi planes", "vs")
        .fragment("fs", &targets)
        .build(&gpu.device, &layout, &module, &constants)
}

/// Two triangles per cell of an `nu` × `nv` lattice of points, row by row.
fn lattice_indices((nu, nv): (u32, u32)) -> Vec<u32> {
    let mut idx = Vec::with_capacity(((nu - 1) * (nv - 1) * 6) as usize);
    for j in 0..nv - 1 {
        for i in 0..nu - 1 {
            let a = j * nu + i;
            idx.extend([a, a + 1, a + nu, a + 1, a + nu + 1, a + nu]);
        }
    }
    idx
}

/// Every pipeline and resource of the method's own passes.
pub struct Passes {
    uniform: wgpu::Buffer,
    far_bits: wgpu::Buffer,
    far_pipeline: wgpu::ComputePipeline,
    far_bind: wgpu::BindGroup,
    planes_pipeline: wgpu::RenderPipeline,
    planes_bind: wgpu::BindGroup,
    lattice: wgpu::Buffer,
    lattice_indices: u32,
    accum_view: wgpu::TextureView,
    resolve: ResolvePass,
}

impl Passes {
    /// `lattice`: (nu, nv) points; `accum`: the accumulation target's format (Rgba32Float needs
    /// FLOAT32_BLENDABLE).
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        lattice: (u32, u32),
        accum: wgpu::TextureFormat,
        xi_per_fragment: bool,
    ) -> Passes {
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("dobashi planes"),
            size: std::mem::size_of::<PlanesUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let far_bits = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("dobashi far extent"),
            size: 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let distance = wgpu::BindingResource::TextureView(&renderer.distance_view);

        // Far extent: distance texture in, one atomic u32 out.
        let far_layout = layout(
            gpu,
            "dobashi far",
            &[float_texture(0, ALL), writable_storage(1)],
        );
        let far_pipeline =
            compute_pipeline(gpu, "dobashi far", renderer, &far_layout, &far_source());
        let far_bind = bind(
            gpu,
            "dobashi far",
            &far_layout,
            &[distance.clone(), far_bits.as_entire_binding()],
        );

        // Planes: distance texture, uniform, far extent (read).
        let planes_layout = layout(
            gpu,
            "dobashi planes",
            &[
                float_texture(0, ALL),
                uniform_buffer(1, ALL),
                storage_buffer(2, ALL, true),
            ],
        );
        let planes_bind = bind(
            gpu,
            "dobashi planes",
            &planes_layout,
            &[
                distance,
                uniform.as_entire_binding(),
                far_bits.as_entire_binding(),
            ],
        );
        let planes_pipeline =
            planes_pipeline(gpu, renderer, &planes_layout, accum, xi_per_fragment);
        let idx = lattice_indices(lattice);
        let lattice_buf = gpu.buffer_init(
            "dobashi lattice",
            bytemuck::cast_slice(&idx),
            wgpu::BufferUsages::INDEX,
        );
        let accum_tex = gpu.texture_2d(
            "dobashi accumulation",
            renderer.width,
            renderer.height,
            accum,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let accum_view = accum_tex.create_view(&Default::default());

        // Resolve: the shared full-screen pass with the Planes uniform and the accumulation.
        let resolve = ResolvePass::with_textures(
            gpu,
            renderer,
            "dobashi resolve",
            &resolve_own(),
            Some(std::mem::size_of::<PlanesUniform>() as u64),
            1,
        );
        Passes {
            uniform,
            far_bits,
            far_pipeline,
            far_bind,
            planes_pipeline,
            planes_bind,
            lattice: lattice_buf,
            lattice_indices: idx.len() as u32,
            accum_view,
            resolve,
        }
    }

    /// The far-extent reduction over the surface pass's distances.
    pub fn encode_far(&self, enc: &mut wgpu::CommandEncoder, renderer: &SceneRenderer) {
        enc.clear_buffer(&self.far_bits, 0, None);
        let mut pass = renderer.passes.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some("dobashi far"),
                timestamp_writes: None,
            },
        );
        pass.set_pipeline(&self.far_pipeline);
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &self.far_bind, &[]);
        pass.dispatch_workgroups(renderer.width.div_ceil(8), renderer.height.div_ceil(8), 1);
    }

    /// Clears the accumulation target and, unless `planes` is 0, draws the planes into it.
    pub fn encode_planes(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        planes: u32,
    ) {
        let mut pass = renderer.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("dobashi planes"),
                color_attachments: &[color_attachment(
                    &self.accum_view,
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                )],
                ..Default::default()
            },
        );
        if planes == 0 {
            return;
        }
        pass.set_pipeline(&self.planes_pipeline);
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &self.planes_bind, &[]);
        pass.set_index_buffer(self.lattice.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.lattice_indices, 0, 0..planes);
    }

    /// accumulation / scale → `inscatter`; surface + inscatter + ambient → `total`.
    pub fn encode_resolve(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
    ) {
        self.resolve
            .encode_with(gpu, enc, renderer, targets, &[&self.accum_view]);
    }

    /// Writes the Planes uniform (read by the plane and resolve passes).
    pub fn write_uniform(&self, gpu: &Gpu, u: &PlanesUniform) {
        for b in [Some(&self.uniform), self.resolve.uniform.as_ref()]
            .into_iter()
            .flatten()
        {
            gpu.queue.write_buffer(b, 0, bytemuck::bytes_of(u));
        }
    }
}

/// Diagnostic for tests: the light map (`light_map` in dobashi.wgsl, what the planes multiply in)
/// of light `w` at each world point `xyz` of `points` (xyzw), read back. The renderer must have
/// been updated for the frame.
pub fn probe_light_map(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    points: &[[f32; 4]],
) -> anyhow::Result<Vec<[f32; 4]>> {
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let own = layout(
        gpu,
        "dobashi probe",
        &[storage_buffer(0, ALL, true), writable_storage(1)],
    );
    let pipeline = compute_pipeline(gpu, "dobashi probe", renderer, &own, &probe_source());
    let size = std::mem::size_of_val(points) as u64;
    let input = gpu.buffer_init(
        "probe points",
        bytemuck::cast_slice(points),
        wgpu::BufferUsages::STORAGE,
    );
    let output = gpu.buffer(&wgpu::BufferDescriptor {
        label: Some("probe values"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = gpu.buffer(&wgpu::BufferDescriptor {
        label: Some("probe staging"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let group = bind(
        gpu,
        "dobashi probe",
        &own,
        &[input.as_entire_binding(), output.as_entire_binding()],
    );
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
    }
    enc.copy_buffer_to_buffer(&output, 0, &staging, 0, size);
    gpu.queue.submit([enc.finish()]);
    let bytes = harness::gpu::map_read(gpu, &staging).map_err(anyhow::Error::msg)?;
    Ok(bytes
        .chunks_exact(16)
        .map(|c| {
            let f =
                |k: usize| f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]);
            [f(0), f(1), f(2), f(3)]
        })
        .collect())
}
