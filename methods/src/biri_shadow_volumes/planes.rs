//! Shadow planes (steps 1, 4, 5 of Biri et al.): silhouettes per light on the CPU
//! (`common::shadow_volumes::shadow_planes`), quads sorted back to front, the scene depth, then
//! either the
//! stencil resolve (z-pass count of the volumes at each visible point, lit surfaces' term, the
//! planes one by one under step 5's rules, in float or the paper's unorm8) or the per-pixel
//! resolve (`pixel.rs`), into `acc_view`.

use harness::gpu::{PhaseTimer, color_attachment, depth_stencil_attachment, phases};
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu};
use scenes::FrameState;

use crate::common::shadow_volumes::crossing_lists;
use crate::common::gpu_scene::write_vertices;
use crate::common::layouts::{dynamic_uniform, fragment_texture, slot_entry, view_entry};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_volumes::shadow_planes::{Order, ShadowCasters};
use crate::common::shadow_volumes::stencil::{DEPTH_STENCIL, PipelineBuilder, PlaneVertex};
use crate::common::shadow_volumes::stencil_surfaces::StencilSurfaceShadows;
use crate::common::uniforms::LightMask;
use crate::common::wgsl;

use super::pixel::{Draw, PixelPass};
use super::stencil_pipes::{StencilPipes, depth_pipe};
use super::types::{
    LightRange, Options, Resolve, SLOT, SLOT_BYTES, SURFACES, VOLUMES, slot_offset,
};

pub const PLANES_WGSL: &str = include_str!("planes.wgsl");
pub const PIXEL_WGSL: &str = include_str!("pixel.wgsl");
pub const SPOT_FIT_WGSL: &str = include_str!("spot_fit.wgsl");

/// The composed WGSL of the plane passes (stencil and per-pixel); `early_depth_test`: see
/// [`crossing_lists::passes_wgsl`].
pub fn source(early_depth_test: bool) -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::FULLSCREEN]].concat(),
        &format!(
            "{}\n{}\n{}\n{}\n{PLANES_WGSL}\n{SPOT_FIT_WGSL}\n{PIXEL_WGSL}",
            wgsl::LDSS,
            crate::common::shadow_volumes::stencil::PLANE_WGSL,
            crossing_lists::WGSL,
            crossing_lists::passes_wgsl(early_depth_test)
        ),
    )
}

/// What every plane pass of a frame binds: group 0 (the renderer's) and group 1.
struct Frame<'a> {
    gpu: &'a Gpu,
    renderer: &'a SceneRenderer,
    bind: wgpu::BindGroup,
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
        let casters = ShadowCasters::with_split(scene, opts.split);
        let tex =
            |label, format, usage| gpu.texture_2d(label, ctx.width, ctx.height, format, usage);
        let depth = tex(
            "biri depth-stencil",
            DEPTH_STENCIL,
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
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("biri planes"),
                entries: &[
                    fragment_texture(0),
                    dynamic_uniform(1, wgpu::ShaderStages::FRAGMENT, SLOT_BYTES),
                    fragment_texture(2),
                ],
            });
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("biri planes"),
            size: SLOT * ctx.scene.desc.lights.len().max(1) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let module = wgsl::module(
            &gpu.device,
            "biri planes",
            &source(crossing_lists::early_depth_test(&gpu.device)),
        );
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
                opts.spot_per_ray,
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
    /// Returns the mask of lights whose eye is lit.
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState, report: &mut FrameReport) -> LightMask {
        let eye = frame.camera.position;
        let far = frame.camera.far;
        // The stencil rules need back to front (step 4); the per-pixel lists come out nearly
        // sorted when the planes are drawn near to far (`crossing_sorted`).
        let order = match self.opts.resolve {
            Resolve::Stencil => Order::BackToFront,
            Resolve::PerPixel => Order::FrontToBack,
        };
        let planes = self.casters.planes(
            frame,
            order,
            |l| 2.0 * (far + (l.position().unwrap_or(eye) - eye).length()) + 1.0,
            report,
        );
        let mut verts: Vec<PlaneVertex> = Vec::new();
        self.ranges.clear();
        let mut eye_lit = LightMask::default();
        let mut slots = vec![0u8; self.uniform.size() as usize];
        for (k, light) in planes.iter().enumerate() {
            let first = verts.len() as u32;
            verts.extend(light.quads.iter().flat_map(|q| PlaneVertex::on_quad(q, *q)));
            if light.eye_count == 0 {
                eye_lit.set(k);
            }
            self.ranges.push(LightRange {
                first,
                end: verts.len() as u32,
                eye_count: light.eye_count,
            });
            let cfg = [k as u32, light.eye_count, 0, self.opts.spot_panels];
            slots[k * SLOT as usize..][..SLOT_BYTES as usize]
                .copy_from_slice(bytemuck::cast_slice(&cfg));
        }
        gpu.queue.write_buffer(&self.uniform, 0, &slots);
        report.count("shadow_planes", (verts.len() / 6) as f64);
        if !verts.is_empty() {
            let bytes: &[u8] = bytemuck::cast_slice(&verts);
            write_vertices(gpu, &mut self.vertices, "biri planes", bytes);
        }
        eye_lit
    }

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
                view_entry(0, table),
                slot_entry(1, &self.uniform, SLOT_BYTES),
                view_entry(2, &renderer.distance_view),
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
        let f = Frame {
            gpu,
            renderer,
            bind,
        };
        for (k, r) in self.ranges.iter().enumerate() {
            self.encode_count(&f, enc, "biri surface-shadow count", k, r);
            shadows.encode(enc, renderer, surface, &self.depth_view, k);
        }
    }

    /// Light k's z-pass count of its volumes at each visible point, seeded with the eye's count
    /// (`r.eye_count`), into the stencil over the scene depth.
    fn encode_count(
        &self,
        f: &Frame,
        enc: &mut wgpu::CommandEncoder,
        label: &str,
        k: usize,
        r: &LightRange,
    ) {
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(label),
                depth_stencil_attachment: Some(depth_stencil_attachment(
                    &self.depth_view,
                    wgpu::LoadOp::Load,
                    wgpu::LoadOp::Clear(r.eye_count),
                )),
                ..Default::default()
            },
        );
        if let Some(v) = self.planes_of(r) {
            pass.set_pipeline(&self.stencil.count);
            pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
            pass.set_bind_group(1, &f.bind, &slot_offset(k));
            pass.set_vertex_buffer(0, v.slice(..));
            pass.draw(r.first..r.end, 0..1);
        }
    }

    /// The vertex buffer, if light range `r` has planes to draw.
    fn planes_of(&self, r: &LightRange) -> Option<&wgpu::Buffer> {
        self.vertices.as_ref().filter(|_| r.end > r.first)
    }

    /// The scene depth pass, then per light either the stencil passes (count, lit surfaces,
    /// planes) or the per-pixel gather and walk, into `acc_view`.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        table: &wgpu::TextureView,
        report: &mut FrameReport,
        timer: &mut Option<PhaseTimer>,
    ) -> anyhow::Result<()> {
        phases::mark(timer, enc, SURFACES);
        let f = Frame {
            gpu,
            renderer,
            bind: self.bind_group(gpu, renderer, table),
        };
        if self.pixel.is_some() {
            return self.encode_per_pixel(&f, enc, table, report, timer);
        }
        encode_depth(&self.depth_pipe, &f, enc, &self.depth_view);
        for (k, r) in self.ranges.iter().enumerate() {
            // The first light's lit surfaces clear the accumulation target.
            let load = if k == 0 {
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
            } else {
                wgpu::LoadOp::Load
            };
            phases::mark(timer, enc, VOLUMES);
            self.encode_count(&f, enc, "biri plane count", k, r);
            // Step 3 (lit surfaces) in its own pass so the phase timer can tell it apart.
            phases::mark(timer, enc, SURFACES);
            self.encode_lit_surfaces(&f, enc, k, load);
            if let Some(v) = self.planes_of(r) {
                phases::mark(timer, enc, VOLUMES);
                self.encode_planes(&f, enc, v, k, r);
            }
        }
        Ok(())
    }

    /// `resolve = per-pixel`: the lists are sized before the frame goes on — the scene depth and
    /// the counts in their own submission (`common::shadow_volumes::crossing_lists`) — then
    /// gathered and walked.
    fn encode_per_pixel(
        &mut self,
        f: &Frame,
        enc: &mut wgpu::CommandEncoder,
        table: &wgpu::TextureView,
        report: &mut FrameReport,
        timer: &mut Option<PhaseTimer>,
    ) -> anyhow::Result<()> {
        let pixel = self.pixel.as_mut().expect("resolve = per-pixel");
        let mut pre = pixel.begin(f.gpu, &self.ranges, report);
        encode_depth(&self.depth_pipe, f, &mut pre, &self.depth_view);
        let pixel_bind = pixel.bind_group(f.gpu, f.renderer, table, &self.uniform, &self.acc_view);
        let draw = Draw {
            gpu: f.gpu,
            renderer: f.renderer,
            vertices: self.vertices.as_ref(),
            ranges: &self.ranges,
            bind: &pixel_bind,
            depth: &self.depth_view,
        };
        pixel.encode(pre, enc, draw, report, timer)
    }

    /// A pass over the accumulation target (`load`: cleared or kept) and the depth-stencil
    /// buffer (both kept), with both groups bound at light k's slot.
    fn begin_accumulation<'e>(
        &self,
        f: &Frame,
        enc: &'e mut wgpu::CommandEncoder,
        label: &str,
        k: usize,
        load: wgpu::LoadOp<wgpu::Color>,
    ) -> harness::gpu::Counted<wgpu::RenderPass<'e>> {
        let color = [color_attachment(&self.acc_view, load)];
        let mut pass = f.renderer.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &color,
                depth_stencil_attachment: Some(depth_stencil_attachment(
                    &self.depth_view,
                    wgpu::LoadOp::Load,
                    wgpu::LoadOp::Load,
                )),
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, &f.bind, &slot_offset(k));
        pass
    }

    /// Step 3: light k's term at the visible points its count left lit (stencil 0).
    fn encode_lit_surfaces(
        &self,
        f: &Frame,
        enc: &mut wgpu::CommandEncoder,
        k: usize,
        load: wgpu::LoadOp<wgpu::Color>,
    ) {
        let mut pass = self.begin_accumulation(f, enc, "biri lit surfaces", k, load);
        pass.set_pipeline(&self.stencil.surface);
        pass.set_stencil_reference(0);
        pass.draw(0..3, 0..1);
    }

    /// Steps 4–5: light k's planes (range `r` of `vertices`), all at once without the rules,
    /// otherwise back to front, one plane at a time: its colour under the stencil test, then its
    /// stencil step, so each plane sees the stencil the planes behind it left.
    fn encode_planes(
        &self,
        f: &Frame,
        enc: &mut wgpu::CommandEncoder,
        vertices: &wgpu::Buffer,
        k: usize,
        r: &LightRange,
    ) {
        let st = &self.stencil;
        let mut pass = self.begin_accumulation(f, enc, "biri ldss planes", k, wgpu::LoadOp::Load);
        pass.set_stencil_reference(1);
        pass.set_vertex_buffer(0, vertices.slice(..));
        if !(self.opts.rules || self.opts.unorm8) {
            pass.set_pipeline(&st.all);
            pass.draw(r.first..r.end, 0..1);
            return;
        }
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
}

/// The scene depth the planes are tested against (stencil cleared).
fn encode_depth(
    pipe: &wgpu::RenderPipeline,
    f: &Frame,
    enc: &mut wgpu::CommandEncoder,
    depth: &wgpu::TextureView,
) {
    let mut pass = f.gpu.render_pass(
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
    pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
    pass.set_bind_group(1, &f.bind, &[0]);
    f.renderer.gpu_scene.draw(&mut pass);
}
