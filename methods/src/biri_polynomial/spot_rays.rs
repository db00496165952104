//! eval = fragment with spots: the per-pixel ray part of eq. 7 (`spot_rays.wgsl`), a compute pass
//! rebuilt before each spot's stages into layers the fragments read (t h β γ_a, the cell,
//! Σ c_i Δ_i(γ_a), then c_0 … c_n).

use harness::Gpu;

use super::passes::PolyUniform;
use crate::common::renderer::SceneRenderer;

pub(super) struct SpotRays {
    pub pipeline: wgpu::ComputePipeline,
    pub bind: wgpu::BindGroup,
    /// Which lights are spots (frame 0; the kinds are fixed per scene).
    pub is_spot: Vec<bool>,
    pub width: u32,
    pub height: u32,
}

/// What the pass reads: the per-light uniform slots and the Δ tables.
pub(super) struct Inputs<'a> {
    pub module: &'a wgpu::ShaderModule,
    pub uniform: &'a wgpu::Buffer,
    pub delta: &'a wgpu::Buffer,
    pub constants: &'a [(&'static str, f64)],
}

/// The layers' view as the fragments read them (a 1×1 dummy when no pass is needed) and the
/// pass, when `per_pixel` (fragment evaluation with at least one spot).
pub(super) fn build(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    inputs: Inputs,
    is_spot: Vec<bool>,
    (width, height): (u32, u32),
    order: u32,
) -> (wgpu::TextureView, Option<SpotRays>) {
    let per_pixel = is_spot.contains(&true);
    let (layers, width, height) = if per_pixel {
        (4 + order.min(8), width, height)
    } else {
        (1, 1, 1)
    };
    let rays = gpu.texture(&wgpu::TextureDescriptor {
        label: Some("biri-poly spot rays"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
        view_formats: &[],
    });
    let view = rays.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let pass = per_pixel.then(|| {
        let (pipeline, bind) = pipeline(gpu, renderer, &inputs, &view);
        SpotRays {
            pipeline,
            bind,
            is_spot,
            width,
            height,
        }
    });
    (view, pass)
}

/// `cs_spot_rays` with its own group 1 (the light's uniform slot, the Δ tables, the layers).
fn pipeline(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    inputs: &Inputs,
    rays: &wgpu::TextureView,
) -> (wgpu::ComputePipeline, wgpu::BindGroup) {
    let compute = wgpu::ShaderStages::COMPUTE;
    let uniform_size = wgpu::BufferSize::new(std::mem::size_of::<PolyUniform>() as u64);
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("biri-poly spot rays"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: compute,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: uniform_size,
                    },
                    count: None,
                },
                crate::common::layouts::storage_buffer(3, compute, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: compute,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba32Float,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
            ],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("biri-poly spot rays"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: inputs.uniform,
                    offset: 0,
                    size: uniform_size,
                }),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: inputs.delta.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(rays),
            },
        ],
    });
    let pl = gpu
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("biri-poly spot rays"),
            bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
            immediate_size: 0,
        });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("biri-poly spot rays"),
            layout: Some(&pl),
            module: inputs.module,
            entry_point: Some("cs_spot_rays"),
            compilation_options: crate::common::specialize::compile_options(inputs.constants),
            cache: None,
        });
    (pipeline, bind)
}
