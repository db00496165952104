//! Shadow planes (steps 1, 4, 5 of Biri et al.): silhouettes per light on the CPU
//! (`common::shadow_planes`), quads sorted back to front, the scene depth, then either the
//! stencil resolve (z-pass count of the volumes at each visible point, lit surfaces' term, the
//! planes one by one under step 5's rules, in float or the paper's unorm8) or the per-pixel
//! resolve (`pixel.rs`), into `acc_view`.

use harness::gpu::{PhaseTimer, color_attachment, depth_stencil_attachment};
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu};
use scenes::FrameState;

use crate::common::crossing_lists;
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_planes::{Order, ShadowCasters};
use crate::common::stencil::PipelineBuilder;
use crate::common::stencil_surfaces::StencilSurfaceShadows;
use crate::common::wgsl;

use super::pixel::{Draw, PixelPass};
use super::stencil_pipes::{StencilPipes, depth_pipe};

/// Phase-timer names (Biri et al.'s Table 1): step 3's lit surfaces (and the scene depth they
/// need), and the shadow planes (stencil count and plane passes, or the per-pixel passes).
pub const SURFACES: &str = "second_pass_surfaces";
pub const VOLUMES: &str = "second_pass_volumes";

pub const PLANES_WGSL: &str = include_str!("planes.wgsl");
pub const PIXEL_WGSL: &str = include_str!("pixel.wgsl");
pub(super) use crate::common::stencil::{DEPTH_STENCIL as DEPTH, PLANE_LAYOUT, PlaneVertex};
/// Uniform slot stride (the minimum dynamic-offset alignment wgpu guarantees).
pub(super) const SLOT: u64 = 256;

/// The composed WGSL of the plane passes (stencil and per-pixel).
pub fn source() -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::FULLSCREEN]].concat(),
        &format!(
            "{}\n{}\n{}\n{}\n{PLANES_WGSL}\n{PIXEL_WGSL}",
            super::LDSS_WGSL,
            crate::common::stencil::PLANE_WGSL,
            crossing_lists::WGSL,
            crossing_lists::PASSES_WGSL
        ),
    )
}

/// How the plane crossings become in-scatter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolve {
    /// Steps 4–5: planes sorted on the CPU, drawn with stencil counting.
    Stencil,
    /// Per-pixel crossing lists sorted and walked on the GPU (`pixel.rs`).
    PerPixel,
}

/// The shadow-plane options (knobs `resolve`, `stencil_rules`, `accumulate`).
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub resolve: Resolve,
    /// Step 5's stencil rules (stencil resolve only).
    pub rules: bool,
    /// The paper's 8-bit target with reverse-subtract blending (stencil resolve only).
    pub unorm8: bool,
    /// Knob `spot_panels` (the spot quadrature of `lit_between`).
    pub spot_panels: u32,
}

/// One light's planes in the vertex buffer and the eye's shadow count.
#[derive(Clone, Copy, Debug)]
pub struct LightRange {
    pub first: u32,
    pub end: u32,
    pub eye_count: u32,
}

pub struct Planes {
    casters: ShadowCasters,
    opts: Options,
    depth_view: wgpu::TextureView,
    pub acc_view: wgpu::TextureView,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    depth_pipe: wgpu::RenderPipeline,
    stencil: StencilPipes,
    pixel: Option<PixelPass>,
    vertices: Option<wgpu::Buffer>,
    /// Per light, planes sorted back to front.
    ranges: Vec<LightRange>,
}

impl Planes {
    pub fn new(ctx: &PrepareContext, renderer: &SceneRenderer, opts: Options) -> Planes {
        let gpu = ctx.gpu;
        let scene = ctx.scene;
        let casters = ShadowCasters::new(scene);
        let tex =
            |label, format, usage| gpu.texture_2d(label, ctx.width, ctx.height, format, usage);
        let depth = tex(
            "biri depth-stencil",
            DEPTH,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let acc_format = if opts.unorm8 {
            wgpu::TextureFormat::Rgba8Unorm
        } else {
            wgpu::TextureFormat::Rgba32Float
        };
        let storage = if opts.resolve == Resolve::PerPixel {
            wgpu::TextureUsages::STORAGE_BINDING
        } else {
            wgpu::TextureUsages::empty()
        };
        let acc = tex(
            "biri crossings",
            acc_format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | storage,
        );
        let texture_entry = crate::common::layouts::fragment_texture;
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
        let module = wgsl::module(&gpu.device, "biri planes", &source());
        let builder = PipelineBuilder::new(
            &gpu.device,
            "biri planes",
            [&renderer.frame_layout, &layout],
            &module,
            renderer.specialization.constants(),
        );
        let pixel = (opts.resolve == Resolve::PerPixel).then(|| {
            PixelPass::new(
                gpu,
                renderer,
                &module,
                (ctx.width, ctx.height),
                ctx.scene.features().lights as u32,
            )
        });
        Planes {
            casters,
            opts,
            depth_view: depth.create_view(&Default::default()),
            acc_view: acc.create_view(&Default::default()),
            layout,
            uniform,
            depth_pipe: depth_pipe(&builder),
            stencil: StencilPipes::new(&builder, &opts, acc_format),
            pixel,
            vertices: None,
            ranges: Vec::new(),
        }
    }

    /// Whether the resolve must add the eye's term −CΓ(w(0)) for lights that see the eye (the
    /// float stencil path; the unorm8 and per-pixel paths include it).
    pub fn eye_term(&self) -> bool {
        self.opts.resolve == Resolve::Stencil && !self.opts.unorm8
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
        let mut verts: Vec<PlaneVertex> = Vec::new();
        self.ranges.clear();
        let mut eye_lit = 0u32;
        let mut slots = vec![0u8; SLOT as usize * crate::common::uniforms::MAX_LIGHTS];
        for (k, light) in planes.iter().enumerate() {
            let first = verts.len() as u32;
            verts.extend(light.quads.iter().flat_map(|q| PlaneVertex::on_quad(q, *q)));
            if light.eye_count == 0 {
                eye_lit |= 1 << k;
            }
            self.ranges.push(LightRange {
                first,
                end: verts.len() as u32,
                eye_count: light.eye_count,
            });
            if k < crate::common::uniforms::MAX_LIGHTS {
                let cfg = [k as u32, light.eye_count, 0, self.opts.spot_panels];
                slots[k * SLOT as usize..][..16].copy_from_slice(bytemuck::cast_slice(&cfg));
            }
        }
        gpu.queue.write_buffer(&self.uniform, 0, &slots);
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

    /// The scene depth pass, then per light either the stencil passes (count, lit surfaces,
    /// planes) or the per-pixel gather and walk, into `acc_view`.
    /// Group 1 of the plane passes: the Γ table, the per-light uniform slots, the ray distances.
    fn bind_group(
        &self,
        gpu: &Gpu,
        renderer: &SceneRenderer,
        table: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
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
        })
    }

    /// Step 2's surface shadows from the stencil: per light, the z-pass count of its volumes
    /// around each visible point (seeded with the eye's count), then the light's contribution
    /// removed from `surface` wherever that count is not zero. Runs after `encode`, whose depth
    /// pass left the scene depth in the depth-stencil buffer.
    pub fn encode_surface_shadows(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        table: &wgpu::TextureView,
        surface: &wgpu::TextureView,
        shadows: &StencilSurfaceShadows,
    ) {
        let bind = self.bind_group(gpu, renderer, table);
        for (k, r) in self.ranges.iter().enumerate() {
            let offset = [(k as u64 * SLOT) as u32];
            {
                let mut pass = gpu.render_pass(
                    enc,
                    &wgpu::RenderPassDescriptor {
                        label: Some("biri surface-shadow count"),
                        depth_stencil_attachment: Some(depth_stencil_attachment(
                            &self.depth_view,
                            wgpu::LoadOp::Load,
                            wgpu::LoadOp::Clear(r.eye_count),
                        )),
                        ..Default::default()
                    },
                );
                if let Some(v) = self.vertices.as_ref().filter(|_| r.end > r.first) {
                    pass.set_pipeline(&self.stencil.count);
                    pass.set_bind_group(0, &renderer.frame_bind, &[]);
                    pass.set_bind_group(1, &bind, &offset);
                    pass.set_vertex_buffer(0, v.slice(..));
                    pass.draw(r.first..r.end, 0..1);
                }
            }
            shadows.encode(enc, renderer, surface, &self.depth_view, k);
        }
    }

    pub fn encode(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        table: &wgpu::TextureView,
        report: &mut FrameReport,
        timer: &mut Option<PhaseTimer>,
    ) -> anyhow::Result<()> {
        let mut mark = |enc: &mut wgpu::CommandEncoder, phase| {
            if let Some(t) = timer.as_mut() {
                t.mark(enc, phase);
            }
        };
        mark(enc, SURFACES);
        let bind = self.bind_group(gpu, renderer, table);
        let ds = |view, depth: wgpu::LoadOp<f32>, stencil: wgpu::LoadOp<u32>| {
            wgpu::RenderPassDepthStencilAttachment {
                view,
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
        if let Some(pixel) = self.pixel.as_mut() {
            // The lists are sized before the frame goes on: depth and counts in their own
            // submission (`common::crossing_lists`).
            let mut pre = pixel.begin(gpu, &self.ranges, report);
            encode_depth(
                &self.depth_pipe,
                gpu,
                &mut pre,
                renderer,
                &self.depth_view,
                &bind,
            );
            mark(enc, VOLUMES);
            let pixel_bind = pixel.bind_group(gpu, renderer, table, &self.uniform, &self.acc_view);
            let draw = Draw {
                vertices: self.vertices.as_ref(),
                bind: &pixel_bind,
                depth: &self.depth_view,
            };
            return pixel.encode(gpu, pre, enc, renderer, draw, &self.ranges, report);
        }
        encode_depth(
            &self.depth_pipe,
            gpu,
            enc,
            renderer,
            &self.depth_view,
            &bind,
        );
        let st = &self.stencil;
        let per_plane = self.opts.rules || self.opts.unorm8;
        let mut first_color = true;
        for (k, r) in self.ranges.iter().enumerate() {
            let offset = [(k as u64 * SLOT) as u32];
            let planes = self.vertices.as_ref().filter(|_| r.end > r.first);
            mark(enc, VOLUMES);
            {
                let mut pass = gpu.render_pass(
                    enc,
                    &wgpu::RenderPassDescriptor {
                        label: Some("biri plane count"),
                        depth_stencil_attachment: Some(ds(
                            &self.depth_view,
                            wgpu::LoadOp::Load,
                            wgpu::LoadOp::Clear(r.eye_count),
                        )),
                        ..Default::default()
                    },
                );
                if let Some(v) = planes {
                    pass.set_pipeline(&st.count);
                    pass.set_bind_group(0, &renderer.frame_bind, &[]);
                    pass.set_bind_group(1, &bind, &offset);
                    pass.set_vertex_buffer(0, v.slice(..));
                    pass.draw(r.first..r.end, 0..1);
                }
            }
            let load = if first_color {
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
            } else {
                wgpu::LoadOp::Load
            };
            first_color = false;
            let acc_view = &self.acc_view;
            let depth_view = &self.depth_view;
            let begin = |enc: &mut wgpu::CommandEncoder, label, load| {
                let color = [color_attachment(acc_view, load)];
                renderer
                    .passes
                    .render_pass(
                        enc,
                        &wgpu::RenderPassDescriptor {
                            label: Some(label),
                            color_attachments: &color,
                            depth_stencil_attachment: Some(ds(
                                depth_view,
                                wgpu::LoadOp::Load,
                                wgpu::LoadOp::Load,
                            )),
                            ..Default::default()
                        },
                    )
                    .forget_lifetime()
            };
            // Step 3 (lit surfaces) in its own pass so the phase timer can tell it apart.
            mark(enc, SURFACES);
            {
                let mut pass = begin(enc, "biri lit surfaces", load);
                pass.set_bind_group(0, &renderer.frame_bind, &[]);
                pass.set_bind_group(1, &bind, &offset);
                pass.set_pipeline(&st.surface);
                pass.set_stencil_reference(0);
                pass.draw(0..3, 0..1);
            }
            let Some(v) = planes else { continue };
            mark(enc, VOLUMES);
            let mut pass = begin(enc, "biri ldss planes", wgpu::LoadOp::Load);
            pass.set_bind_group(0, &renderer.frame_bind, &[]);
            pass.set_bind_group(1, &bind, &offset);
            pass.set_stencil_reference(1);
            pass.set_vertex_buffer(0, v.slice(..));
            if !per_plane {
                pass.set_pipeline(&st.all);
                pass.draw(r.first..r.end, 0..1);
                continue;
            }
            // Back to front, one plane at a time: its colour under the stencil test, then its
            // stencil step, so each plane sees the stencil the planes behind it left.
            for q in (r.first..r.end).step_by(6) {
                for c in &st.color {
                    pass.set_pipeline(c);
                    pass.draw(q..q + 6, 0..1);
                }
                if let Some(step) = &st.step {
                    pass.set_pipeline(step);
                    pass.draw(q..q + 6, 0..1);
                }
            }
        }
        Ok(())
    }
}

/// The scene depth the planes are tested against (stencil cleared).
fn encode_depth(
    pipe: &wgpu::RenderPipeline,
    gpu: &Gpu,
    enc: &mut wgpu::CommandEncoder,
    renderer: &SceneRenderer,
    depth: &wgpu::TextureView,
    bind: &wgpu::BindGroup,
) {
    let mut pass = gpu.render_pass(
        enc,
        &wgpu::RenderPassDescriptor {
            label: Some("biri scene depth"),
            depth_stencil_attachment: Some(depth_stencil_attachment(
                depth,
                wgpu::LoadOp::Clear(1.0),
                wgpu::LoadOp::Clear(0),
            )),
            ..Default::default()
        },
    );
    pass.set_pipeline(pipe);
    pass.set_bind_group(0, &renderer.frame_bind, &[]);
    pass.set_bind_group(1, bind, &[0]);
    renderer.gpu_scene.draw(&mut pass);
}
