//! `resolve: per-pixel` (a modern replacement of steps 4–5): per light, the shadow planes in
//! front of the visible surface are drawn into the pixels' crossing lists (distance along the
//! view ray, signed by facing; `common::shadow_volumes::crossing_lists`, sized by a counting pass
//! so they cannot
//! overflow), and a compute pass sorts every list and sums L_dss over the lit intervals only
//! (`pixel.wgsl`). Exact shadow in shadow, whatever the planes' order.
//!
//! Counters (from the shared lists): `max_crossings` (the longest list), `crossing_pool`
//! (crossings stored), `crossing_overflows` (0 by construction; a frame late).

use harness::gpu::{PhaseTimer, depth_stencil_attachment, phases};
use harness::{FrameReport, Gpu};

use crate::common::shadow_volumes::crossing_lists::{CrossingLists, GROUP};
use crate::common::layouts::{
    buffer_entry, dynamic_uniform, float_texture, rgba32f_storage_write, slot_entry,
    storage_buffer, view_entry,
};
use crate::common::pipeline::{ComputeStage, Stage};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_volumes::stencil::{DEPTH_STENCIL, PLANE_LAYOUT};

use super::types::{LightRange, SLOT_BYTES, VOLUMES, WALK, slot_offset};

pub struct PixelPass {
    layout: wgpu::BindGroupLayout,
    count: wgpu::RenderPipeline,
    gather: wgpu::RenderPipeline,
    walk: wgpu::ComputePipeline,
    lists: CrossingLists,
    sum: wgpu::Buffer,
    width: u32,
    height: u32,
}

/// What the per-pixel passes of a frame draw with: the plane vertices and each light's range of
/// them, group 0 (the renderer's) and group 1 (`bind_group`), and the scene depth the planes are
/// tested against.
pub struct Draw<'a> {
    pub gpu: &'a Gpu,
    pub renderer: &'a SceneRenderer,
    pub vertices: Option<&'a wgpu::Buffer>,
    pub ranges: &'a [LightRange],
    pub bind: &'a wgpu::BindGroup,
    pub depth: &'a wgpu::TextureView,
}

impl PixelPass {
    /// `module`: the composed plane module (`planes::source`); `lights`: the scene's lights;
    /// `spot_per_ray`: knob `spot_integral`, baked into the walk as `SPOT_INTEGRAL_PER_RAY`.
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        module: &wgpu::ShaderModule,
        (width, height): (u32, u32),
        lights: u32,
        spot_per_ray: bool,
    ) -> PixelPass {
        let vis = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("biri per-pixel"),
                entries: &[
                    float_texture(0, vis),
                    dynamic_uniform(1, vis, SLOT_BYTES),
                    float_texture(2, vis),
                    storage_buffer(5, vis, false),
                    rgba32f_storage_write(6, wgpu::ShaderStages::COMPUTE),
                ],
            });
        let lists = CrossingLists::new(gpu, width, height, lights, vis);
        let pl = crate::common::pipeline::layout(
            &gpu.device,
            "biri per-pixel",
            &[&renderer.frame_layout, &layout, &lists.layout],
        );
        // Only crossings in front of the visible surface are listed; as in the stencil passes,
        // entering a shadow rasterises clockwise (planes.rs). Count and gather share this state,
        // so they rasterise the same fragments.
        let planes = |label, entry| {
            Stage::new(label, "vs_plane")
                .vertices(PLANE_LAYOUT)
                .front_face(wgpu::FrontFace::Cw)
                .unclipped_depth(crate::common::shadow_volumes::stencil::near_plane_safe(&gpu.device))
                .fragment(entry, &[])
                .depth(wgpu::DepthStencilState {
                    format: DEPTH_STENCIL,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                })
                .build(&gpu.device, &pl, module, &[])
        };
        let walk = ComputeStage::new("biri crossing walk", "cs_walk").build(
            &gpu.device,
            &pl,
            module,
            &renderer
                .specialization
                .with(&[("SPOT_INTEGRAL_PER_RAY", f64::from(u8::from(spot_per_ray)))]),
        );
        PixelPass {
            layout,
            count: planes("biri crossing count", "fs_crossing_count"),
            gather: planes("biri crossing gather", "fs_crossing_gather"),
            walk,
            lists,
            sum: gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("biri per-pixel sum"),
                size: (16 * width as u64 * height as u64).max(16),
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            width,
            height,
        }
    }

    /// Group 1 of the per-pixel passes.
    pub fn bind_group(
        &self,
        gpu: &Gpu,
        renderer: &SceneRenderer,
        table: &wgpu::TextureView,
        uniform: &wgpu::Buffer,
        out: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("biri per-pixel"),
            layout: &self.layout,
            entries: &[
                view_entry(0, table),
                slot_entry(1, uniform, SLOT_BYTES),
                view_entry(2, &renderer.distance_view),
                buffer_entry(5, &self.sum),
                view_entry(6, out),
            ],
        })
    }

    /// The crossing lists' count encoder (the caller records the scene depth into it first).
    pub fn begin(
        &mut self,
        gpu: &Gpu,
        ranges: &[LightRange],
        report: &mut FrameReport,
    ) -> wgpu::CommandEncoder {
        let eye: Vec<u32> = ranges.iter().map(|r| r.eye_count).collect();
        self.lists.begin_count(gpu, &eye, report)
    }

    /// Per light: count its crossings into `pre` (then submitted, the pool sized), gather them
    /// and walk them into `enc`. `out` (in group 1): the Rgba32Float running sum over lights.
    pub fn encode(
        &mut self,
        mut pre: wgpu::CommandEncoder,
        enc: &mut wgpu::CommandEncoder,
        draw: Draw,
        report: &mut FrameReport,
        timer: &mut Option<PhaseTimer>,
    ) -> anyhow::Result<()> {
        let gpu = draw.gpu;
        for k in 0..draw.ranges.len() {
            self.draw_planes(&mut pre, &draw, k, &self.count);
        }
        self.lists.size_pool(gpu, pre, report)?;
        for k in 0..draw.ranges.len() {
            phases::mark(timer, enc, VOLUMES);
            self.draw_planes(enc, &draw, k, &self.gather);
            phases::mark(timer, enc, WALK);
            let mut pass = gpu.compute_pass(
                enc,
                &wgpu::ComputePassDescriptor {
                    label: Some("biri crossing walk"),
                    timestamp_writes: None,
                },
            );
            pass.set_pipeline(&self.walk);
            pass.set_bind_group(0, &draw.renderer.frame_bind, &[]);
            pass.set_bind_group(1, draw.bind, &slot_offset(k));
            pass.set_bind_group(GROUP, self.lists.bind_group(), &self.lists.slot(k));
            pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
        }
        self.lists.end_frame(enc);
        Ok(())
    }

    /// Light k's planes with `pipe` (count or gather), depth-tested, no colour.
    fn draw_planes(
        &self,
        enc: &mut wgpu::CommandEncoder,
        draw: &Draw,
        k: usize,
        pipe: &wgpu::RenderPipeline,
    ) {
        let r = &draw.ranges[k];
        let Some(v) = draw.vertices.filter(|_| r.end > r.first) else {
            return;
        };
        let mut pass = draw.gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("biri crossing lists"),
                depth_stencil_attachment: Some(depth_stencil_attachment(
                    draw.depth,
                    wgpu::LoadOp::Load,
                    wgpu::LoadOp::Load,
                )),
                ..Default::default()
            },
        );
        pass.set_pipeline(pipe);
        pass.set_bind_group(0, &draw.renderer.frame_bind, &[]);
        pass.set_bind_group(1, draw.bind, &slot_offset(k));
        pass.set_bind_group(GROUP, self.lists.bind_group(), &self.lists.slot(k));
        pass.set_vertex_buffer(0, v.slice(..));
        pass.draw(r.first..r.end, 0..1);
    }
}
