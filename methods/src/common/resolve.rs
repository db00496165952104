//! A full-screen pass that reads the ray-distance texture and the `surface` AOV (group 1,
//! bindings 0 and 1, plus an optional uniform at binding 2) and writes `inscatter` and `total`.
//! The last pass of every method built on [`SceneRenderer`].

use harness::method::AOV_FORMAT;
use harness::{Gpu, Targets};

use super::renderer::SceneRenderer;
use super::wgsl;

pub struct ResolvePass {
    label: &'static str,
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    pub uniform: Option<wgpu::Buffer>,
}

impl ResolvePass {
    /// `own`: the pass's WGSL (an `fs` entry point); composed after PRELUDE and FULLSCREEN.
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        uniform_size: Option<u64>,
    ) -> ResolvePass {
        let tex = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let mut entries = vec![tex(0), tex(1)];
        if uniform_size.is_some() {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            });
        }
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            });
        let uniform = uniform_size.map(|size| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let module = wgsl::module(&gpu.device, label, &source(own));
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = gpu
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pl),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_fullscreen"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(AOV_FORMAT.into()), Some(AOV_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            });
        ResolvePass {
            label,
            pipeline,
            layout,
            uniform,
        }
    }

    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
    ) {
        // The harness owns the AOV textures, so the group that reads `surface` is built per frame.
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&renderer.distance_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(targets.surface),
            },
        ];
        if let Some(u) = &self.uniform {
            entries.push(wgpu::BindGroupEntry {
                binding: 2,
                resource: u.as_entire_binding(),
            });
        }
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout: &self.layout,
            entries: &entries,
        });
        let clear = wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        };
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &[
                Some(wgpu::RenderPassColorAttachment {
                    view: targets.inscatter,
                    depth_slice: None,
                    resolve_target: None,
                    ops: clear,
                }),
                Some(wgpu::RenderPassColorAttachment {
                    view: targets.total,
                    depth_slice: None,
                    resolve_target: None,
                    ops: clear,
                }),
            ],
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The composed WGSL of a resolve pass.
pub fn source(own: &str) -> String {
    wgsl::compose(&[wgsl::PRELUDE, &[wgsl::FULLSCREEN]].concat(), own)
}
