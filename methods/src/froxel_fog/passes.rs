//! The volume passes' GPU objects: group 1 (grid uniform, source buffer, volume texture), one
//! `inject` pipeline per (light, first-or-not) and the `integrate` pipeline, and their dispatch.

use harness::Gpu;

use super::volume_source;
use crate::common::layouts::storage_buffer;
use crate::common::renderer::SceneRenderer;
use crate::common::uniforms::MAX_LIGHTS;
use crate::common::wgsl;

/// Grid dimensions a dispatch needs.
#[derive(Clone, Copy)]
pub struct Dims {
    pub grid_x: u32,
    pub grid_y: u32,
    pub slices: u32,
}

pub struct VolumePasses {
    pub bind: wgpu::BindGroup,
    /// `inject[k][first]`: light k's injection, storing (first = 1) or adding (first = 0).
    inject: Vec<[wgpu::ComputePipeline; 2]>,
    integrate: wgpu::ComputePipeline,
    /// The source buffer (cleared when no light is injected).
    source: wgpu::Buffer,
}

impl VolumePasses {
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        uniform: &wgpu::Buffer,
        source: wgpu::Buffer,
        volume: &wgpu::TextureView,
    ) -> VolumePasses {
        let (layout, bind) = bindings(gpu, uniform, &source, volume);
        let module = wgsl::module(&gpu.device, "froxel volume", &volume_source());
        let pl = crate::common::pipeline::layout(
            &gpu.device,
            "froxel volume",
            &[&renderer.frame_layout, &layout],
        );
        let pipeline = |entry: &str, own: &[(&'static str, f64)]| {
            let constants = renderer.specialization.with(own);
            gpu.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pl),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: crate::common::specialize::compile_options(&constants),
                    cache: None,
                })
        };
        let lights = renderer.scene.desc.lights.len().min(MAX_LIGHTS);
        let inject = (0..lights)
            .map(|k| {
                [0.0, 1.0].map(|first| pipeline("inject", &[("LIGHT", k as f64), ("FIRST", first)]))
            })
            .collect();
        VolumePasses {
            bind,
            inject,
            integrate: pipeline("integrate", &[]),
            source,
        }
    }

    /// Injects the lights `active` (indices into the scene's lights) into the source buffer, or
    /// clears it when there is none.
    pub fn encode_inject(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        dims: Dims,
        active: &[usize],
    ) {
        if active.is_empty() {
            enc.clear_buffer(&self.source, 0, None);
            return;
        }
        let mut pass = gpu.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some("froxel inject"),
                timestamp_writes: None,
            },
        );
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &self.bind, &[]);
        for (i, &k) in active.iter().enumerate() {
            pass.set_pipeline(&self.inject[k][(i == 0) as usize]);
            pass.dispatch_workgroups(
                dims.grid_x.div_ceil(4),
                dims.grid_y.div_ceil(4),
                dims.slices.div_ceil(4),
            );
        }
    }

    /// Integrates every froxel column front to back into the volume texture.
    pub fn encode_integrate(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        dims: Dims,
    ) {
        let mut pass = gpu.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some("froxel integrate"),
                timestamp_writes: None,
            },
        );
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &self.bind, &[]);
        pass.set_pipeline(&self.integrate);
        pass.dispatch_workgroups(dims.grid_x.div_ceil(8), dims.grid_y.div_ceil(8), 1);
    }
}

/// Group 1 of the volume passes: the grid uniform, the source buffer, the volume texture.
fn bindings(
    gpu: &Gpu,
    uniform: &wgpu::Buffer,
    source: &wgpu::Buffer,
    volume: &wgpu::TextureView,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let cs = wgpu::ShaderStages::COMPUTE;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("froxel volume"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: cs,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage_buffer(1, cs, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: cs,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba32Float,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
            ],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("froxel volume"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: source.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(volume),
            },
        ],
    });
    (layout, bind)
}
