//! Surface shadows from stencil shadow volumes (Biri et al.'s step 2; Biri, Michelin & Arquès
//! §4.3), shared by the methods that already count shadow volumes in a stencil buffer.
//!
//! The surfaces are first shaded with every light unshadowed (a `SceneRenderer` built without
//! shadow maps). Then, per light, once the stencil holds the number of that light's shadow
//! volumes around each visible point (z-pass count seeded with the eye's count, which stays
//! correct with the camera inside a shadow), the scene is drawn again over the same depth and
//! removes the light's contribution wherever the count is not zero. Shadows are therefore exact
//! per pixel — no shadow-map resolution or bias — and cost one extra scene draw per light.
//!
//! The removal must touch the visible surface only, once: it draws the renderer's meshes with
//! the depth test `Equal` against the depth pass's depth (both write an `@invariant` position
//! computed the same way, under the same depth clipping, `stencil::near_plane_safe`), and zeroes
//! the stencil where it removes (a coplanar second fragment then fails). The depth bias this
//! replaced (`LessEqual`, constant −8, slope −1) also let through hidden surfaces within a
//! pixel's depth slope behind the visible one — the floor running on under a wall, a sill's lit
//! top behind its unlit face — and subtracted their light too: lines of negative radiance along
//! those seams (window-sun surface headline 0.034 at 128², now 1.5e-7).

use harness::Gpu;
use harness::gpu::PassCounter;
use harness::gpu::{color_attachment, depth_stencil_attachment};
use harness::method::AOV_FORMAT;

use crate::common::gpu_scene::Vertex;
use crate::common::renderer::{SceneRenderer, surface_source};
use crate::common::wgsl;
use crate::common::pipeline::{self, Stage};

pub struct StencilSurfaceShadows {
    /// One pipeline per light slot (`override SURFACE_LIGHT`).
    pipelines: Vec<wgpu::RenderPipeline>,
    passes: PassCounter,
}

impl StencilSurfaceShadows {
    /// Pipelines for `lights` lights drawing over a `depth_format` depth-stencil buffer that
    /// holds the scene's depth (written with the same vertex transform).
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        depth_format: wgpu::TextureFormat,
        lights: usize,
    ) -> StencilSurfaceShadows {
        let module = wgsl::module(&gpu.device, "stencil surface shadows", &surface_source());
        let layout = pipeline::layout(
            &gpu.device,
            "stencil surface shadows",
            &[&renderer.frame_layout],
        );
        // Where the count is not zero the light is removed once: the stencil is zeroed there, so
        // a second fragment at the very same depth (coplanar surfaces) cannot remove it again.
        let keep = wgpu::StencilOperation::Keep;
        let zero = wgpu::StencilOperation::Zero;
        let in_shadow = super::stencil::face(wgpu::CompareFunction::NotEqual, zero, keep);
        let depth = pipeline::visible_surface_depth(
            depth_format,
            wgpu::StencilState {
                front: in_shadow,
                back: in_shadow,
                read_mask: 0xff,
                write_mask: 0xff,
            },
        );
        let targets = [pipeline::target(AOV_FORMAT, Some(pipeline::ADDITIVE))];
        let pipelines = (0..lights)
            .map(|k| {
                Stage::new("stencil surface shadows", "vs")
                    .vertices(Vertex::LAYOUT)
                    .fragment("fs_remove_light", &targets)
                    .depth(depth.clone())
                    .unclipped_depth(super::stencil::near_plane_safe(&gpu.device))
                    .build(
                        &gpu.device,
                        &layout,
                        &module,
                        &[("SURFACE_LIGHT", k as f64)],
                    )
            })
            .collect();
        StencilSurfaceShadows {
            pipelines,
            passes: gpu.pass_counter(),
        }
    }

    /// Removes light `k`'s contribution from `surface` where the stencil of `depth_stencil` is
    /// not zero. The depth-stencil buffer must hold light k's volume count and the depth of
    /// `renderer.gpu_scene` — the very meshes drawn here, not a tessellated copy — written by an
    /// invariant position under `stencil::near_plane_safe` depth clipping (depth test Equal).
    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        surface: &wgpu::TextureView,
        depth_stencil: &wgpu::TextureView,
        k: usize,
    ) {
        let Some(pipeline) = self.pipelines.get(k) else {
            return;
        };
        let mut pass = self.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("stencil surface shadows"),
                color_attachments: &[color_attachment(surface, wgpu::LoadOp::Load)],
                depth_stencil_attachment: Some(depth_stencil_attachment(
                    depth_stencil,
                    wgpu::LoadOp::Load,
                    wgpu::LoadOp::Load,
                )),
                ..Default::default()
            },
        );
        pass.set_pipeline(pipeline);
        pass.set_stencil_reference(0);
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        renderer.gpu_scene.draw(&mut pass);
    }
}
