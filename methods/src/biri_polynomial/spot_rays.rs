//! eval = fragment with spots: the per-pixel ray part of eq. 7 (`spot_rays.wgsl`), a compute pass
//! rebuilt before each spot's stages into layers the fragments read (t h β γ_a, the cell,
//! Σ c_i Δ_i(γ_a), then c_0 … c_n).

use harness::Gpu;

use super::types::PolyUniform;
use crate::common::layouts::{
    buffer_entry, dynamic_uniform, rgba32f_storage_array_write, slot_entry, storage_buffer,
    view_entry,
};
use crate::common::pipeline::{self, ComputeStage};
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
    let slot = std::mem::size_of::<PolyUniform>() as u64;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("biri-poly spot rays"),
            entries: &[
                dynamic_uniform(1, compute, slot),
                storage_buffer(3, compute, true),
                rgba32f_storage_array_write(5, compute),
            ],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("biri-poly spot rays"),
        layout: &layout,
        entries: &[
            slot_entry(1, inputs.uniform, slot),
            buffer_entry(3, inputs.delta),
            view_entry(5, rays),
        ],
    });
    let pl = pipeline::layout(
        &gpu.device,
        "biri-poly spot rays",
        &[&renderer.frame_layout, &layout],
    );
    let pipeline = ComputeStage::new("biri-poly spot rays", "cs_spot_rays").build(
        &gpu.device,
        &pl,
        inputs.module,
        inputs.constants,
    );
    (pipeline, bind)
}
