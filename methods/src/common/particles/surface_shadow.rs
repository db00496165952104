//! A particle cloud's shadow on surfaces, one pass per light: the scene redrawn over the surface
//! pass's depth (depth test Equal), additively removing that light's contribution times
//! 1 − e^(−τ), τ the particle optical depth toward the light as the method stores it. With one
//! light this equals multiplying the surface by the light's particle transmittance; with several,
//! each light's term gets its own. The method supplies the fragment `fs_cloud_shadow` (composed
//! after the shared surface pass, reading `SURFACE_LIGHT`) and its groups from 1 on; used by
//! umenhoffer-particle-blocks / particle-splat (τ from their light slices), froxel-fog (τ from
//! its light-space extinction grids) and the particle tracers (`common::particles::surfaces`: τ
//! exact through the particle grid).

use harness::method::AOV_FORMAT;

use crate::common::gpu_scene::Vertex;
use crate::common::pipeline::{self, ADDITIVE, Stage, target};
use crate::common::renderer::SceneRenderer;
use crate::common::wgsl;

pub struct SurfaceShadow {
    /// One pipeline per light (`override SURFACE_LIGHT`).
    pipelines: Vec<wgpu::RenderPipeline>,
    /// Groups 1, 2, … of the fragment.
    binds: Vec<wgpu::BindGroup>,
}

impl SurfaceShadow {
    /// `groups`: the layouts and bind groups (groups 1, 2, …) the fragment reads; `constants`:
    /// the method's pipeline constants (the pass adds `SURFACE_LIGHT`); `source`: the composed
    /// WGSL (PRELUDE, the method's groups, `wgsl::SURFACE_PASS`, then `fs_cloud_shadow`).
    pub fn new(
        device: &wgpu::Device,
        renderer: &SceneRenderer,
        groups: &[(&wgpu::BindGroupLayout, &wgpu::BindGroup)],
        constants: &[(&'static str, f64)],
        lights: usize,
        source: &str,
    ) -> SurfaceShadow {
        let label = "particle surface shadow";
        let layouts: Vec<&wgpu::BindGroupLayout> = std::iter::once(&renderer.frame_layout)
            .chain(groups.iter().map(|(l, _)| *l))
            .collect();
        let layout = pipeline::layout(device, label, &layouts);
        let module = wgsl::module(device, label, source);
        let depth =
            pipeline::visible_surface_depth(wgpu::TextureFormat::Depth32Float, Default::default());
        let targets = [target(AOV_FORMAT, Some(ADDITIVE))];
        let pipelines = (0..lights)
            .map(|k| {
                let constants = [constants, &[("SURFACE_LIGHT", k as f64)]].concat();
                Stage::new(label, "vs")
                    .vertices(Vertex::LAYOUT)
                    .fragment("fs_cloud_shadow", &targets)
                    .depth(depth.clone())
                    .build(device, &layout, &module, &constants)
            })
            .collect();
        let binds = groups.iter().map(|(_, b)| (*b).clone()).collect();
        SurfaceShadow { pipelines, binds }
    }

    /// Removes light `k`'s cloud-shadowed part from `surface` (the surface pass's output).
    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        surface: &wgpu::TextureView,
        k: usize,
    ) {
        let Some(pipeline) = self.pipelines.get(k) else {
            return;
        };
        let mut pass = renderer.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("particle surface shadow"),
                color_attachments: &[harness::gpu::color_attachment(surface, wgpu::LoadOp::Load)],
                depth_stencil_attachment: Some(harness::gpu::depth_attachment(
                    &renderer.depth_view,
                    wgpu::LoadOp::Load,
                )),
                ..Default::default()
            },
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        for (g, bind) in self.binds.iter().enumerate() {
            pass.set_bind_group(1 + g as u32, bind, &[]);
        }
        renderer.gpu_scene.draw(&mut pass);
    }
}
