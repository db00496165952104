//! `resolve: per-pixel` (a modern replacement of steps 4–5): per light, a render pass appends each
//! shadow-plane fragment in front of the visible surface to its pixel's crossing list (distance
//! along the view ray, signed by facing), and a compute pass sorts every list and sums L_dss over
//! the lit intervals only (`pixel.wgsl`). Exact shadow in shadow, whatever the planes' order.
//!
//! Lists have a fixed capacity (knob `crossings`); a longer list is truncated and counted
//! (`crossing_overflows`: pixel × light pairs that overflowed, `max_crossings`: the longest list),
//! read back a frame late through `common::counters`.

use harness::gpu::depth_stencil_attachment;
use harness::{FrameReport, Gpu};

use crate::common::counters::CounterReadback;
use crate::common::pipeline::Stage;
use crate::common::renderer::SceneRenderer;

use super::planes::{DEPTH, LightRange, SLOT};

pub struct PixelPass {
    layout: wgpu::BindGroupLayout,
    gather: wgpu::RenderPipeline,
    walk: wgpu::ComputePipeline,
    counts: wgpu::Buffer,
    list: wgpu::Buffer,
    sum: wgpu::Buffer,
    stats: wgpu::Buffer,
    readback: CounterReadback,
    width: u32,
    height: u32,
}

impl PixelPass {
    /// `module`: the composed plane module (`planes::source`), `capacity`: crossings per pixel.
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        module: &wgpu::ShaderModule,
        width: u32,
        height: u32,
        capacity: u32,
    ) -> PixelPass {
        let vis = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: vis,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: vis,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("biri per-pixel"),
                entries: &[
                    texture(0),
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: vis,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: true,
                            min_binding_size: wgpu::BufferSize::new(16),
                        },
                        count: None,
                    },
                    texture(2),
                    storage(3),
                    storage(4),
                    storage(5),
                    wgpu::BindGroupLayoutEntry {
                        binding: 6,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: wgpu::BindingType::StorageTexture {
                            access: wgpu::StorageTextureAccess::WriteOnly,
                            format: wgpu::TextureFormat::Rgba32Float,
                            view_dimension: wgpu::TextureViewDimension::D2,
                        },
                        count: None,
                    },
                    storage(7),
                ],
            });
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("biri per-pixel"),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        // Only crossings in front of the visible surface are gathered; as in the stencil passes,
        // entering a shadow rasterises clockwise (planes.rs).
        let gather = Stage::new("biri crossing gather", "vs_plane")
            .vertices(super::planes::PLANE_LAYOUT)
            .front_face(wgpu::FrontFace::Cw)
            .unclipped_depth(crate::common::stencil::near_plane_safe(&gpu.device))
            .fragment("fs_gather", &[])
            .depth(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            })
            .build(&gpu.device, &pl, module, &[]);
        let walk = gpu
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("biri crossing walk"),
                layout: Some(&pl),
                module,
                entry_point: Some("cs_walk"),
                compilation_options: renderer.specialization.options(),
                cache: None,
            });
        let pixels = width as u64 * height as u64;
        let buffer = |label, size: u64, extra: wgpu::BufferUsages| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
                mapped_at_creation: false,
            })
        };
        let none = wgpu::BufferUsages::empty();
        PixelPass {
            layout,
            gather,
            walk,
            counts: buffer("biri crossing counts", 4 * pixels, none),
            list: buffer("biri crossing lists", 4 * pixels * capacity as u64, none),
            sum: buffer("biri per-pixel sum", 16 * pixels, none),
            stats: buffer("biri list stats", 8, wgpu::BufferUsages::COPY_SRC),
            readback: CounterReadback::new(gpu, 2),
            width,
            height,
        }
    }

    /// Per light: clear the counts, gather its crossings, walk them. `out`: the Rgba32Float
    /// storage view the resolve reads (the running sum over lights).
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        vertices: Option<&wgpu::Buffer>,
        ranges: &[LightRange],
        table: &wgpu::TextureView,
        uniform: &wgpu::Buffer,
        depth: &wgpu::TextureView,
        out: &wgpu::TextureView,
        report: &mut FrameReport,
    ) {
        self.readback.begin_frame(gpu, &self.stats);
        if let Some(v) = self.readback.latest() {
            report.count("crossing_overflows", v[0] as f64);
            report.count("max_crossings", v[1] as f64);
        }
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("biri per-pixel"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(table),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: uniform,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&renderer.distance_view),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: self.counts.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: self.list.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: self.sum.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(out),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: self.stats.as_entire_binding(),
                },
            ],
        });
        for (k, r) in ranges.iter().enumerate() {
            let offset = [(k as u64 * SLOT) as u32];
            enc.clear_buffer(&self.counts, 0, None);
            if let (Some(v), true) = (vertices, r.end > r.first) {
                let mut pass = gpu.render_pass(
                    enc,
                    &wgpu::RenderPassDescriptor {
                        label: Some("biri crossing gather"),
                        depth_stencil_attachment: Some(depth_stencil_attachment(
                            depth,
                            wgpu::LoadOp::Load,
                            wgpu::LoadOp::Load,
                        )),
                        ..Default::default()
                    },
                );
                pass.set_pipeline(&self.gather);
                pass.set_bind_group(0, &renderer.frame_bind, &[]);
                pass.set_bind_group(1, &bind, &offset);
                pass.set_vertex_buffer(0, v.slice(..));
                pass.draw(r.first..r.end, 0..1);
            }
            let mut pass = gpu.compute_pass(
                enc,
                &wgpu::ComputePassDescriptor {
                    label: Some("biri crossing walk"),
                    timestamp_writes: None,
                },
            );
            pass.set_pipeline(&self.walk);
            pass.set_bind_group(0, &renderer.frame_bind, &[]);
            pass.set_bind_group(1, &bind, &offset);
            pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
        }
        self.readback.end_frame(enc, &self.stats);
    }
}
