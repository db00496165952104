//! Shadow planes (steps 1, 4, 5 of Biri et al.): silhouettes per light on the CPU
//! (`common::silhouette`), quads sorted back to front, the stencil count of shadow volumes at
//! each visible point, and the signed L_dss crossing terms accumulated into a float target.

use harness::method::PrepareContext;
use harness::{FrameReport, Gpu};
use scenes::FrameState;

use crate::common::gpu_scene::Vertex;
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_planes::{Order, ShadowCasters};
use crate::common::wgsl;

pub const PLANES_WGSL: &str = include_str!("planes.wgsl");
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;
/// Uniform slot stride (the minimum dynamic-offset alignment wgpu guarantees).
const SLOT: u64 = 256;

/// The composed WGSL of the plane passes.
pub fn source() -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::FULLSCREEN]].concat(),
        &format!("{}\n{PLANES_WGSL}", super::LDSS_WGSL),
    )
}

pub struct Planes {
    casters: ShadowCasters,
    depth_view: wgpu::TextureView,
    pub acc_view: wgpu::TextureView,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    depth_pipe: wgpu::RenderPipeline,
    count_pipe: wgpu::RenderPipeline,
    surface_pipe: wgpu::RenderPipeline,
    plane_pipe: wgpu::RenderPipeline,
    vertices: Option<wgpu::Buffer>,
    /// Per light: vertex range (sorted back to front) and the eye's shadow count.
    ranges: Vec<(u32, u32, u32)>,
}

fn stencil_face(
    compare: wgpu::CompareFunction,
    op: wgpu::StencilOperation,
    fail: wgpu::StencilOperation,
) -> wgpu::StencilFaceState {
    wgpu::StencilFaceState {
        compare,
        fail_op: fail,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op: op,
    }
}

impl Planes {
    /// `rules`: the paper's step-5 stencil rules (drop crossings inside another shadow); false:
    /// every crossing counts (exact only where shadow volumes do not overlap).
    pub fn new(ctx: &PrepareContext, renderer: &SceneRenderer, rules: bool) -> Planes {
        let gpu = ctx.gpu;
        let scene = ctx.scene;
        let casters = ShadowCasters::new(scene);
        let size = wgpu::Extent3d {
            width: ctx.width,
            height: ctx.height,
            depth_or_array_layers: 1,
        };
        let tex = |label, format, usage| {
            gpu.texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let depth = tex(
            "biri depth-stencil",
            DEPTH,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let acc = tex(
            "biri crossings",
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let texture_entry = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("biri planes"),
                entries: &[
                    texture_entry(0),
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: true,
                            min_binding_size: wgpu::BufferSize::new(16),
                        },
                        count: None,
                    },
                    texture_entry(2),
                ],
            });
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("biri planes"),
            size: SLOT * crate::common::uniforms::MAX_LIGHTS as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let slots: Vec<u8> = (0..crate::common::uniforms::MAX_LIGHTS as u32)
            .flat_map(|k| {
                let mut v = vec![0u8; SLOT as usize];
                v[..4].copy_from_slice(&k.to_le_bytes());
                v
            })
            .collect();
        gpu.queue.write_buffer(&uniform, 0, &slots);
        let module = wgsl::module(&gpu.device, "biri planes", &source());
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("biri planes"),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        use wgpu::{CompareFunction as C, StencilOperation as S};
        let depth_state = |compare, write, front, back| wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState {
                front,
                back,
                read_mask: 0xff,
                write_mask: 0xff,
            },
            bias: Default::default(),
        };
        let keep = stencil_face(C::Always, S::Keep, S::Keep);
        let plane_layout = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        };
        let additive = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent::REPLACE,
        };
        let color = [Some(wgpu::ColorTargetState {
            format: wgpu::TextureFormat::Rgba32Float,
            blend: Some(additive),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let pipe = |label,
                    vs,
                    vbuf: Option<wgpu::VertexBufferLayout>,
                    fs: Option<&str>,
                    depth: wgpu::DepthStencilState| {
            gpu.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&pl),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers: &vbuf.into_iter().map(Some).collect::<Vec<_>>(),
                    },
                    // silhouette::extrude winds quads outward in a right-handed sense, which wgpu's
                    // y-up clip space rasterises clockwise: "front" (entering a shadow) is Cw here.
                    primitive: wgpu::PrimitiveState {
                        cull_mode: None,
                        front_face: wgpu::FrontFace::Cw,
                        ..Default::default()
                    },
                    depth_stencil: Some(depth),
                    multisample: Default::default(),
                    fragment: fs.map(|fs| wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &color,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
        };
        let depth_pipe = pipe(
            "biri scene depth",
            "vs_scene",
            Some(Vertex::LAYOUT),
            None,
            depth_state(C::Less, true, keep, keep),
        );
        // z-pass count: entering a volume (front face) +1, leaving (back face) −1.
        let count_pipe = pipe(
            "biri plane count",
            "vs_plane",
            Some(plane_layout.clone()),
            None,
            depth_state(
                C::Less,
                false,
                stencil_face(C::Always, S::IncrementWrap, S::Keep),
                stencil_face(C::Always, S::DecrementWrap, S::Keep),
            ),
        );
        // Lit ray ends: stencil == reference 0.
        let surface_pipe = pipe(
            "biri lit surfaces",
            "vs_fullscreen",
            None,
            Some("fs_surface"),
            depth_state(
                C::Always,
                false,
                stencil_face(C::Equal, S::Keep, S::Keep),
                stencil_face(C::Equal, S::Keep, S::Keep),
            ),
        );
        // Step 5 with reference 1: front faces pass on stencil == 1, back faces on stencil == 0
        // (1 > stencil); front faces always decrement, back faces always increment.
        let plane_pipe = pipe(
            "biri planes",
            "vs_plane",
            Some(plane_layout),
            Some("fs_plane"),
            depth_state(
                C::Less,
                false,
                stencil_face(
                    if rules { C::Equal } else { C::Always },
                    S::DecrementWrap,
                    S::DecrementWrap,
                ),
                stencil_face(
                    if rules { C::Greater } else { C::Always },
                    S::IncrementWrap,
                    S::IncrementWrap,
                ),
            ),
        );
        Planes {
            casters,
            depth_view: depth.create_view(&Default::default()),
            acc_view: acc.create_view(&Default::default()),
            layout,
            uniform,
            depth_pipe,
            count_pipe,
            surface_pipe,
            plane_pipe,
            vertices: None,
            ranges: Vec::new(),
        }
    }

    /// Steps 1 and 4 on the CPU: silhouettes (only when a light or caster moved), the quads
    /// sorted back to front by the eye distance of their edge's midpoint, and the eye's count.
    /// Returns the bit mask of lights whose eye is lit.
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState, report: &mut FrameReport) -> u32 {
        let eye = frame.camera.position;
        let far = frame.camera.far;
        let planes = self.casters.planes(
            frame,
            Order::BackToFront,
            |l| 2.0 * (far + (l.position().unwrap_or(eye) - eye).length()) + 1.0,
            report,
        );
        let mut verts: Vec<[f32; 3]> = Vec::new();
        self.ranges.clear();
        let mut eye_lit = 0u32;
        for (k, light) in planes.iter().enumerate() {
            let first = verts.len() as u32;
            verts.extend(light.quads.iter().flat_map(|q| q.map(|p| p.to_array())));
            if light.eye_count == 0 {
                eye_lit |= 1 << k;
            }
            self.ranges.push((first, verts.len() as u32, light.eye_count));
        }
        report.count("shadow_planes", (verts.len() / 6) as f64);
        if !verts.is_empty() {
            let bytes: &[u8] = bytemuck::cast_slice(&verts);
            if !self
                .vertices
                .as_ref()
                .is_some_and(|b| b.size() >= bytes.len() as u64)
            {
                self.vertices = Some(gpu.buffer(&wgpu::BufferDescriptor {
                    label: Some("biri planes"),
                    size: bytes.len().next_power_of_two() as u64,
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
            }
            gpu.queue
                .write_buffer(self.vertices.as_ref().expect("allocated"), 0, bytes);
        }
        eye_lit
    }

    /// The depth, count, lit-surface and plane passes of every light into `acc_view`.
    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        table: &wgpu::TextureView,
    ) {
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("biri planes"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(table),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.uniform,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&renderer.distance_view),
                },
            ],
        });
        let ds = |depth: wgpu::LoadOp<f32>, stencil: wgpu::LoadOp<u32>| {
            wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: depth,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: stencil,
                    store: wgpu::StoreOp::Store,
                }),
            }
        };
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("biri scene depth"),
                depth_stencil_attachment: Some(ds(
                    wgpu::LoadOp::Clear(1.0),
                    wgpu::LoadOp::Clear(0),
                )),
                ..Default::default()
            });
            pass.set_pipeline(&self.depth_pipe);
            pass.set_bind_group(0, &renderer.frame_bind, &[]);
            pass.set_bind_group(1, &bind, &[0]);
            pass.set_vertex_buffer(0, renderer.gpu_scene.vertices.slice(..));
            pass.set_index_buffer(
                renderer.gpu_scene.indices.slice(..),
                wgpu::IndexFormat::Uint32,
            );
            for d in &renderer.gpu_scene.draws {
                pass.draw_indexed(d.first_index..d.first_index + d.index_count, 0, 0..1);
            }
        }
        let mut first_color = true;
        for (k, &(a, b, count)) in self.ranges.iter().enumerate() {
            let offset = [(k as u64 * SLOT) as u32];
            {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("biri plane count"),
                    depth_stencil_attachment: Some(ds(
                        wgpu::LoadOp::Load,
                        wgpu::LoadOp::Clear(count),
                    )),
                    ..Default::default()
                });
                if b > a {
                    pass.set_pipeline(&self.count_pipe);
                    pass.set_bind_group(0, &renderer.frame_bind, &[]);
                    pass.set_bind_group(1, &bind, &offset);
                    pass.set_vertex_buffer(0, self.vertices.as_ref().expect("planes").slice(..));
                    pass.draw(a..b, 0..1);
                }
            }
            let load = if first_color {
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
            } else {
                wgpu::LoadOp::Load
            };
            first_color = false;
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("biri ldss planes"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.acc_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(ds(wgpu::LoadOp::Load, wgpu::LoadOp::Load)),
                ..Default::default()
            });
            pass.set_bind_group(0, &renderer.frame_bind, &[]);
            pass.set_bind_group(1, &bind, &offset);
            pass.set_pipeline(&self.surface_pipe);
            pass.set_stencil_reference(0);
            pass.draw(0..3, 0..1);
            if b > a {
                pass.set_pipeline(&self.plane_pipe);
                pass.set_stencil_reference(1);
                pass.set_vertex_buffer(0, self.vertices.as_ref().expect("planes").slice(..));
                pass.draw(a..b, 0..1);
            }
        }
    }
}
