//! `resolve: per-pixel` (modernised): per light, the shadow planes go into the pixels' crossing
//! lists (`common::crossing_lists`: counted, then gathered, so they cannot overflow), and a
//! full-screen pass sorts each list and adds eq. 12's Γ terms over the lit intervals only
//! (`pixel.wgsl`). It replaces the paper's eq. 13/14 front-to-back order of whole planes and
//! §4.4's stencil rules, which drop crossings where shadow wedges cross (the fence-spot band,
//! README); `resolve: planes` keeps the paper's.

use harness::Gpu;

use crate::common::crossing_lists::CrossingLists;
use crate::common::pipeline::{self, Stage};
use crate::common::stencil::{self, PipelineBuilder};

pub(super) struct PixelPass {
    pub lists: CrossingLists,
    pub count: wgpu::RenderPipeline,
    pub gather: wgpu::RenderPipeline,
    pub walk: wgpu::RenderPipeline,
}

impl PixelPass {
    /// `layouts`: the renderer's group 0 and the passes' group 1; `lights`: the scene's lights.
    pub fn new(
        gpu: &Gpu,
        layouts: [&wgpu::BindGroupLayout; 2],
        module: &wgpu::ShaderModule,
        constants: &[(&'static str, f64)],
        (width, height): (u32, u32),
        lights: u32,
    ) -> PixelPass {
        let lists = CrossingLists::new(gpu, width, height, lights, wgpu::ShaderStages::FRAGMENT);
        let b = PipelineBuilder::new(
            &gpu.device,
            "biri-poly per-pixel",
            [layouts[0], layouts[1], &lists.layout],
            module,
            constants,
        );
        let keep = stencil::face(
            wgpu::CompareFunction::Always,
            wgpu::StencilOperation::Keep,
            wgpu::StencilOperation::Keep,
        );
        // Count and gather share this state, so they rasterise the same fragments: the planes in
        // front of the visible surface.
        let planes = |label, fs| {
            b.build(
                Stage::new(label, "vs_plane")
                    .vertices(stencil::PLANE_LAYOUT)
                    .fragment(fs, &[])
                    .depth(stencil::depth_stencil(
                        wgpu::CompareFunction::Less,
                        false,
                        keep,
                        keep,
                    )),
            )
        };
        let targets = [pipeline::target(
            wgpu::TextureFormat::Rgba32Float,
            Some(pipeline::ADDITIVE),
        )];
        let walk = b.build(
            Stage::new("biri-poly crossing walk", "vs_fullscreen")
                .fragment("fs_walk", &targets)
                .depth(stencil::depth_stencil(
                    wgpu::CompareFunction::Always,
                    false,
                    keep,
                    keep,
                )),
        );
        PixelPass {
            count: planes("biri-poly crossing count", "fs_crossing_count"),
            gather: planes("biri-poly crossing gather", "fs_crossing_gather"),
            walk,
            lists,
        }
    }
}
