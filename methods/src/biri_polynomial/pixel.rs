//! `resolve: per-pixel` (modernised): per light, the shadow planes go into the pixels' crossing
//! lists (`common::shadow_volumes::crossing_lists`: counted, then gathered, so they cannot
//! overflow), and a
//! per-pixel pass sorts each list and adds eq. 12's Γ terms over the lit intervals only
//! (`pixel.wgsl`). It replaces the paper's eq. 13/14 front-to-back order of whole planes and
//! §4.4's stencil rules, which drop crossings where shadow wedges cross (the fence-spot band,
//! README); `resolve: planes` keeps the paper's.
//!
//! The walk (knob `walk`): `fragment` (default) draws `fs_walk` full-screen, blended additively
//! into the accumulation target; `compute` dispatches `cs_walk` over 8×8 tiles, which adds each
//! light's sum to the running sum over lights (a storage buffer) and stores it into the target.
//! The same per-pixel function and the same sums in the same order: the same image.

use harness::Gpu;

use crate::common::shadow_volumes::crossing_lists::CrossingLists;
use crate::common::layouts::{buffer_entry, rgba32f_storage_write, storage_buffer, view_entry};
use crate::common::pipeline::{self, ComputeStage, Stage};
use crate::common::shadow_volumes::stencil::{self, PipelineBuilder};

use super::types::Walk;

pub(super) struct PixelPass {
    pub lists: CrossingLists,
    pub count: wgpu::RenderPipeline,
    pub gather: wgpu::RenderPipeline,
    pub walk: WalkPass,
}

/// The walk's pass, by knob `walk`.
pub(super) enum WalkPass {
    Fragment(wgpu::RenderPipeline),
    /// `cs_walk` with its group 3: the running sum over lights and the accumulation target.
    Compute {
        pipeline: wgpu::ComputePipeline,
        out: wgpu::BindGroup,
        tiles: (u32, u32),
    },
}

/// What the passes are built from: the renderer's group 0 and the passes' group 1 layouts, the
/// composed module and its constants, the accumulation target and its size.
pub(super) struct Inputs<'a> {
    pub layouts: [&'a wgpu::BindGroupLayout; 2],
    pub module: &'a wgpu::ShaderModule,
    pub constants: &'a [(&'static str, f64)],
    pub acc: &'a wgpu::TextureView,
    pub size: (u32, u32),
}

impl PixelPass {
    /// `lights`: the scene's lights; `walk`: knob `walk`.
    pub fn new(gpu: &Gpu, inputs: Inputs, lights: u32, walk: Walk) -> PixelPass {
        let (width, height) = inputs.size;
        let lists = CrossingLists::new(gpu, width, height, lights, wgpu::ShaderStages::FRAGMENT);
        let b = PipelineBuilder::new(
            &gpu.device,
            "biri-poly per-pixel",
            [inputs.layouts[0], inputs.layouts[1], &lists.layout],
            inputs.module,
            inputs.constants,
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
        let walk = match walk {
            Walk::Fragment => {
                let targets = [pipeline::target(
                    wgpu::TextureFormat::Rgba32Float,
                    Some(pipeline::ADDITIVE),
                )];
                WalkPass::Fragment(
                    b.build(
                        Stage::new("biri-poly crossing walk", "vs_fullscreen")
                            .fragment("fs_walk", &targets)
                            .depth(stencil::depth_stencil(
                                wgpu::CompareFunction::Always,
                                false,
                                keep,
                                keep,
                            )),
                    ),
                )
            }
            Walk::Compute => compute_walk(gpu, &inputs, &lists),
        };
        PixelPass {
            count: planes("biri-poly crossing count", "fs_crossing_count"),
            gather: planes("biri-poly crossing gather", "fs_crossing_gather"),
            walk,
            lists,
        }
    }
}

/// `cs_walk` and its group 3 (binding 0: the running sum over lights, 16 bytes per pixel;
/// 1: the accumulation target as a storage texture).
fn compute_walk(gpu: &Gpu, inputs: &Inputs, lists: &CrossingLists) -> WalkPass {
    let (width, height) = inputs.size;
    let compute = wgpu::ShaderStages::COMPUTE;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("biri-poly walk out"),
            entries: &[
                storage_buffer(0, compute, false),
                rgba32f_storage_write(1, compute),
            ],
        });
    let sum = gpu.buffer(&wgpu::BufferDescriptor {
        label: Some("biri-poly walk sum"),
        size: (16 * width as u64 * height as u64).max(16),
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let out = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("biri-poly walk out"),
        layout: &layout,
        entries: &[buffer_entry(0, &sum), view_entry(1, inputs.acc)],
    });
    let pl = pipeline::layout(
        &gpu.device,
        "biri-poly compute walk",
        &[inputs.layouts[0], inputs.layouts[1], &lists.layout, &layout],
    );
    let pipeline = ComputeStage::new("biri-poly crossing walk", "cs_walk").build(
        &gpu.device,
        &pl,
        inputs.module,
        inputs.constants,
    );
    WalkPass::Compute {
        pipeline,
        out,
        tiles: (width.div_ceil(8), height.div_ceil(8)),
    }
}
