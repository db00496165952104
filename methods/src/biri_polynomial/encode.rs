//! The frame's passes in order (§4.3–4.5), for the [`Passes`] whose resources `passes.rs` holds:
//! depth, the surface-shadow counts, the unorm8 first pass, then per light the spot rays, the
//! count, the lit surfaces (stage 1) and the planes (stage 2).

use std::ops::Range;

use harness::gpu::{Counted, color_attachment, depth_stencil_attachment};
use harness::{FrameReport, Gpu};

use super::passes::{LightDraws, Passes};
use super::pixel::{PixelPass, WalkPass};
use crate::biri_polynomial::types::{Accumulate, PolyUniform, SLOT};
use crate::common::shadow_volumes::crossing_lists::GROUP;
use crate::common::gpu_scene::GpuScene;
use crate::common::layouts::{buffer_entry, slot_entry, view_entry};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_volumes::stencil_surfaces::StencilSurfaceShadows;

impl Passes {
    /// Every pass of every light into `acc_view`.
    pub fn encode(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        surface: &wgpu::TextureView,
        surface_shadows: Option<&StencilSurfaceShadows>,
        report: &mut FrameReport,
    ) -> anyhow::Result<()> {
        let bind = self.bind_group(gpu, renderer, surface);
        let f = Encoding {
            gpu,
            renderer,
            bind: &bind,
        };
        // resolve = per-pixel: the depth and the crossing counts go first, on their own, so the
        // lists' pool is sized before the gather (`common::shadow_volumes::crossing_lists`).
        let eye: Vec<u32> = self.draws.iter().map(|d| d.eye_count).collect();
        match self
            .pixel
            .as_mut()
            .map(|p| p.lists.begin_count(gpu, &eye, report))
        {
            Some(mut pre) => {
                self.encode_depth(&f, &mut pre);
                if let Some(pixel) = &self.pixel {
                    for (k, light) in self.draws.iter().enumerate() {
                        self.encode_crossings(&f, &mut pre, k, light, pixel, &pixel.count);
                    }
                }
                if let Some(pixel) = self.pixel.as_mut() {
                    pixel.lists.size_pool(gpu, pre, report)?;
                }
            }
            None => self.encode_depth(&f, enc),
        }
        // §4.3's surface shadows: per light, the count of its volumes around each visible point,
        // then its light removed from the surfaces where the count is not zero.
        // The removal redraws the renderer's own meshes and must meet their depth exactly, so
        // with a tessellated copy (eval = vertex) the count and the removal run over the
        // renderer's meshes' depth, and the copy's depth is drawn again after them.
        if let Some(shadows) = surface_shadows {
            if self.tess.is_some() {
                self.encode_depth_of(&f, enc, &renderer.gpu_scene);
            }
            for (k, light) in self.draws.iter().enumerate() {
                self.encode_count(&f, enc, k, light, "biri-poly surface-shadow count");
                shadows.encode(enc, renderer, surface, &self.depth_view, k);
            }
            if self.tess.is_some() {
                self.encode_depth(&f, enc);
            }
            report.ran("stencil-surface-shadows");
        }
        if self.cfg.accumulate == Accumulate::Unorm8 {
            self.encode_first_pass(&f, enc);
        }
        let mut first = self.cfg.accumulate == Accumulate::Float;
        for (k, light) in self.draws.iter().enumerate() {
            self.encode_spot_rays(&f, enc, k);
            if let Some(pixel) = &self.pixel {
                self.encode_crossings(&f, enc, k, light, pixel, &pixel.gather);
                self.encode_walk(&f, enc, k, first, pixel);
                first = false;
                continue;
            }
            // Stencil = shadow volumes around each visible point (z-pass from the eye's count).
            self.encode_count(&f, enc, k, light, "biri-poly count");
            self.encode_lit_surfaces(&f, enc, k, first);
            first = false;
            self.encode_planes(&f, enc, k, light);
        }
        if let Some(pixel) = self.pixel.as_mut() {
            pixel.lists.end_frame(enc);
            report.ran("crossing-lists");
        }
        report.ran("polynomial-surfaces");
        if self.spot_rays.is_some() {
            report.ran("spot-rays");
        }
        if self.casters.is_some() {
            report.ran("shadow-planes");
        } else {
            report.skip("shadow-planes", "no object casts a volumetric shadow");
        }
        Ok(())
    }

    /// Group 1 of every pass: distances, the light slots, the surface radiance, Δ, spot rays.
    fn bind_group(
        &self,
        gpu: &Gpu,
        renderer: &SceneRenderer,
        surface: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("biri-poly passes"),
            layout: &self.layout,
            entries: &[
                view_entry(0, &renderer.distance_view),
                slot_entry(1, &self.uniform, std::mem::size_of::<PolyUniform>() as u64),
                view_entry(2, surface),
                buffer_entry(3, &self.delta),
                view_entry(4, &self.spot_rays_view),
            ],
        })
    }

    fn depth_stencil(
        &self,
        depth: wgpu::LoadOp<f32>,
        stencil: wgpu::LoadOp<u32>,
    ) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        depth_stencil_attachment(&self.depth_view, depth, stencil)
    }

    fn color(
        &self,
        load: wgpu::LoadOp<wgpu::Color>,
    ) -> [Option<wgpu::RenderPassColorAttachment<'_>>; 1] {
        [color_attachment(&self.acc_view, load)]
    }

    /// The scene (tessellated for vertex evaluation) as the passes draw it.
    fn scene<'a>(&'a self, renderer: &'a SceneRenderer) -> &'a GpuScene {
        self.tess.as_ref().unwrap_or(&renderer.gpu_scene)
    }

    /// Depth of the (tessellated) scene, stencil cleared.
    fn encode_depth(&self, f: &Encoding, enc: &mut wgpu::CommandEncoder) {
        self.encode_depth_of(f, enc, self.scene(f.renderer));
    }

    /// Depth of `scene`, stencil cleared.
    fn encode_depth_of(&self, f: &Encoding, enc: &mut wgpu::CommandEncoder, scene: &GpuScene) {
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("biri-poly depth"),
                depth_stencil_attachment: Some(
                    self.depth_stencil(wgpu::LoadOp::Clear(1.0), wgpu::LoadOp::Clear(0)),
                ),
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, f.bind, &[0]);
        pass.set_pipeline(&self.pipes.depth);
        scene.draw(&mut pass);
    }

    /// z-pass count of light k's volumes, the stencil seeded with the eye's count.
    fn encode_count(
        &self,
        f: &Encoding,
        enc: &mut wgpu::CommandEncoder,
        k: usize,
        light: &LightDraws,
        label: &str,
    ) {
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(label),
                depth_stencil_attachment: Some(
                    self.depth_stencil(wgpu::LoadOp::Load, wgpu::LoadOp::Clear(light.eye_count)),
                ),
                ..Default::default()
            },
        );
        if let Some(v) = self.vertices.as_ref().filter(|_| !light.runs.is_empty()) {
            pass.set_pipeline(&self.pipes.count);
            pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
            pass.set_bind_group(1, f.bind, &slot(k));
            pass.set_vertex_buffer(0, v.slice(..));
            pass.draw(light.whole(), 0..1);
        }
    }

    /// §4.3's first pass (surfaces and ambient fog) into the 8-bit target.
    fn encode_first_pass(&self, f: &Encoding, enc: &mut wgpu::CommandEncoder) {
        let attachments = self.color(wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT));
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("biri-poly first pass"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(
                    self.depth_stencil(wgpu::LoadOp::Load, wgpu::LoadOp::Load),
                ),
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, f.bind, &[0]);
        pass.set_pipeline(&self.pipes.first);
        pass.draw(0..3, 0..1);
    }

    /// Light k's per-pixel spot rays, when it is a spot and Γ is evaluated per fragment.
    fn encode_spot_rays(&self, f: &Encoding, enc: &mut wgpu::CommandEncoder, k: usize) {
        let Some(rays) = self
            .spot_rays
            .as_ref()
            .filter(|r| r.is_spot.get(k) == Some(&true))
        else {
            return;
        };
        let mut pass = f.gpu.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some("biri-poly spot rays"),
                timestamp_writes: None,
            },
        );
        pass.set_pipeline(&rays.pipeline);
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, &rays.bind, &slot(k));
        pass.dispatch_workgroups(rays.width.div_ceil(8), rays.height.div_ceil(8), 1);
    }

    /// A pass into the accumulation target over the loaded depth-stencil, groups 0 and 1 bound
    /// for light k; `first` clears the target.
    fn accumulate_pass<'e>(
        &self,
        f: &Encoding,
        enc: &'e mut wgpu::CommandEncoder,
        label: &str,
        k: usize,
        first: bool,
    ) -> Counted<wgpu::RenderPass<'e>> {
        let load = if first {
            wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
        } else {
            wgpu::LoadOp::Load
        };
        let attachments = self.color(load);
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(
                    self.depth_stencil(wgpu::LoadOp::Load, wgpu::LoadOp::Load),
                ),
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, f.bind, &slot(k));
        pass
    }

    /// Stage 1 of §4.3.2: +Γ(P) where P is lit (stencil 0); `first` clears the target.
    fn encode_lit_surfaces(
        &self,
        f: &Encoding,
        enc: &mut wgpu::CommandEncoder,
        k: usize,
        first: bool,
    ) {
        let mut pass = self.accumulate_pass(f, enc, "biri-poly surfaces", k, first);
        pass.set_stencil_reference(0);
        pass.set_pipeline(&self.pipes.surface);
        match &self.grid {
            Some((grid, n)) => {
                self.scene(f.renderer).draw(&mut pass);
                pass.set_pipeline(&self.pipes.grid);
                pass.set_vertex_buffer(0, grid.slice(..));
                pass.draw(0..*n, 0..1);
            }
            None => pass.draw(0..3, 0..1),
        }
    }

    /// Stage 2: light k's planes front to back, stencil re-seeded with the eye's count.
    fn encode_planes(
        &self,
        f: &Encoding,
        enc: &mut wgpu::CommandEncoder,
        k: usize,
        light: &LightDraws,
    ) {
        let Some(planes) = self.vertices.as_ref().filter(|_| !light.runs.is_empty()) else {
            return;
        };
        let attachments = self.color(wgpu::LoadOp::Load);
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("biri-poly planes"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(
                    self.depth_stencil(wgpu::LoadOp::Load, wgpu::LoadOp::Clear(light.eye_count)),
                ),
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, f.bind, &slot(k));
        pass.set_stencil_reference(1);
        pass.set_vertex_buffer(0, planes.slice(..));
        if let [signed] = &self.pipes.planes[..] {
            pass.set_pipeline(signed);
            pass.draw(light.whole(), 0..1);
        } else {
            for (range, front) in &light.runs {
                pass.set_pipeline(&self.pipes.planes[if *front { 0 } else { 1 }]);
                pass.draw(range.clone(), 0..1);
            }
        }
    }

    /// resolve = per-pixel: light k's planes in front of the visible surface with `pipe` (the
    /// lists' count or gather), no colour.
    fn encode_crossings(
        &self,
        f: &Encoding,
        enc: &mut wgpu::CommandEncoder,
        k: usize,
        light: &LightDraws,
        pixel: &PixelPass,
        pipe: &wgpu::RenderPipeline,
    ) {
        let Some(v) = self.vertices.as_ref().filter(|_| !light.runs.is_empty()) else {
            return;
        };
        let mut pass = f.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("biri-poly crossing lists"),
                depth_stencil_attachment: Some(
                    self.depth_stencil(wgpu::LoadOp::Load, wgpu::LoadOp::Load),
                ),
                ..Default::default()
            },
        );
        pass.set_pipeline(pipe);
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, f.bind, &slot(k));
        pass.set_bind_group(GROUP, pixel.lists.bind_group(), &pixel.lists.slot(k));
        pass.set_vertex_buffer(0, v.slice(..));
        pass.draw(light.whole(), 0..1);
    }

    /// resolve = per-pixel: light k's lists sorted and walked, its lit intervals' Γ added to the
    /// target (`first` clears it; the compute walk's light 0 overwrites it).
    fn encode_walk(
        &self,
        f: &Encoding,
        enc: &mut wgpu::CommandEncoder,
        k: usize,
        first: bool,
        pixel: &PixelPass,
    ) {
        let (pipeline, out, tiles) = match &pixel.walk {
            WalkPass::Fragment(pipe) => {
                let mut pass = self.accumulate_pass(f, enc, "biri-poly crossing walk", k, first);
                pass.set_pipeline(pipe);
                pass.set_bind_group(GROUP, pixel.lists.bind_group(), &pixel.lists.slot(k));
                pass.draw(0..3, 0..1);
                return;
            }
            WalkPass::Compute {
                pipeline,
                out,
                tiles,
            } => (pipeline, out, tiles),
        };
        let mut pass = f.gpu.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some("biri-poly crossing walk"),
                timestamp_writes: None,
            },
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &f.renderer.frame_bind, &[]);
        pass.set_bind_group(1, f.bind, &slot(k));
        pass.set_bind_group(GROUP, pixel.lists.bind_group(), &pixel.lists.slot(k));
        pass.set_bind_group(3, out, &[]);
        pass.dispatch_workgroups(tiles.0, tiles.1, 1);
    }
}

/// What every pass of one frame's encoding binds.
struct Encoding<'a> {
    gpu: &'a Gpu,
    renderer: &'a SceneRenderer,
    bind: &'a wgpu::BindGroup,
}

/// Light k's dynamic offset into the uniform slots.
fn slot(k: usize) -> [u32; 1] {
    [(k as u64 * SLOT) as u32]
}

impl LightDraws {
    /// All of the light's planes, in one draw (they are contiguous).
    fn whole(&self) -> Range<u32> {
        self.runs.first().map_or(0, |r| r.0.start)..self.runs.last().map_or(0, |r| r.0.end)
    }
}
