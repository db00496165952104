//! The prepared method: the shared renderer, the grid, the volume passes and the apply pass, and
//! one frame's encoding (timed per phase: surfaces, inject, integrate, apply).

use anyhow::{Result, bail};
use bytemuck::{Pod, Zeroable};
use harness::gpu::PhaseTimer;
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, KnobRead, Prepared, Targets};
use scenes::FrameState;

use super::passes::{Buffers, Dims, VolumePasses};
use super::{APPLY_WGSL, GRID_WGSL, reach};
use crate::common::renderer::SceneRenderer;
use crate::common::resolve::ResolvePass;
use crate::common::wgsl;

/// `Froxel` in grid.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FroxelUniform {
    grid_x: u32,
    grid_y: u32,
    slices: u32,
    pixel_size: u32,
    frame: u32,
    jitter: u32,
    depth_exponent: f32,
    tiles_x: u32,
    blend: f32,
    history: u32,
    moved: u32,
    _pad: u32,
    offset: [f32; 4],
    prev_clip_from_world: [[f32; 4]; 4],
    prev_position: [f32; 4],
    prev_forward: [f32; 4],
}

/// Temporal accumulation's bookkeeping across frames.
struct Temporal {
    /// Frames blended (0: off).
    frames: u32,
    /// Frames rendered since prepare (the jitter sequence's index).
    rendered: u32,
    /// The camera of the frame the history holds.
    previous: Option<scenes::CameraPose>,
}

/// The radical inverse of i in base b: the Halton sequence's i-th element in that base.
fn halton(mut i: u32, b: u32) -> f32 {
    let (mut f, mut r) = (1.0f32, 0.0f32);
    while i > 0 {
        f /= b as f32;
        r += f * (i % b) as f32;
        i /= b;
    }
    r
}

/// The prepared method: the shared renderer, the volume passes and the apply pass.
pub struct State {
    pub renderer: SceneRenderer,
    grid: FroxelUniform,
    uniform: wgpu::Buffer,
    volume: VolumePasses,
    volume_view: wgpu::TextureView,
    apply: ResolvePass,
    no_skip: bool,
    temporal: Temporal,
    /// GPU time per phase (counters `gpu_ms_<phase>`), where timestamps inside encoders exist.
    timer: Option<PhaseTimer>,
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let p = ctx.params;
        let gpu = ctx.gpu;
        let renderer = SceneRenderer::new(ctx, p.knob("shadow_map")?, p.knob("pattern_res")?)?;
        let pixel_size: u32 = p.knob("pixel_size")?;
        let slices: u32 = p.knob("slices")?;
        let grid_x = renderer.width.div_ceil(pixel_size);
        let grid_y = renderer.height.div_ceil(pixel_size);
        let tiles_x = (slices as f64).sqrt().ceil() as u32;
        let tiles_y = slices.div_ceil(tiles_x);
        let max = gpu.device.limits().max_texture_dimension_2d;
        if grid_x * tiles_x > max || grid_y * tiles_y > max {
            bail!(
                "froxel-fog: a {grid_x}×{grid_y}×{slices} grid needs a {}×{} volume texture; this adapter allows {max}² (raise pixel_size or lower slices)",
                grid_x * tiles_x,
                grid_y * tiles_y
            );
        }
        let temporal: u32 = p.knob("temporal")?;
        let grid = FroxelUniform {
            grid_x,
            grid_y,
            slices,
            pixel_size,
            jitter: match (temporal, p.knob::<String>("jitter")?.as_str()) {
                (0, _) => 0,
                (_, "depth") => 1,
                _ => 2,
            },
            depth_exponent: p.knob("depth_exponent")?,
            tiles_x,
            blend: 1.0,
            ..Zeroable::zeroed()
        };
        let volume = gpu.texture_2d(
            "froxel volume",
            grid_x * tiles_x,
            grid_y * tiles_y,
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let volume_view = volume.create_view(&Default::default());
        let froxel_bytes = 16 * grid_x as u64 * grid_y as u64 * slices as u64;
        let source = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("froxel source"),
            size: froxel_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let history = |label| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: if temporal > 0 { froxel_bytes } else { 16 },
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let history = [history("froxel history 0"), history("froxel history 1")];
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("froxel grid"),
            size: std::mem::size_of::<FroxelUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let buffers = Buffers {
            uniform: &uniform,
            source,
            history,
            volume: &volume_view,
        };
        let slice_falloff = p.knob::<String>("falloff")? == "slice";
        let volume_passes = VolumePasses::new(gpu, &renderer, buffers, temporal > 0, slice_falloff);
        let apply = ResolvePass::with_textures(
            gpu,
            &renderer,
            "froxel apply",
            &wgsl::compose(&[GRID_WGSL], APPLY_WGSL),
            Some(std::mem::size_of::<FroxelUniform>() as u64),
            1,
        );
        Ok(State {
            renderer,
            grid,
            uniform,
            volume: volume_passes,
            volume_view,
            apply,
            no_skip: ctx.no_skip,
            temporal: Temporal {
                frames: temporal,
                rendered: 0,
                previous: None,
            },
            timer: PhaseTimer::new(gpu, 5),
        })
    }

    /// This frame's jitter offset and temporal blend, and the previous frame's camera.
    fn update_grid(&mut self, frame: &FrameState) {
        let t = &self.temporal;
        let g = &mut self.grid;
        g.frame = t.rendered;
        let i = t.rendered + 1;
        g.offset = [halton(i, 2), halton(i, 3), halton(i, 5), 0.0];
        // A progressive average over the first N frames, then an exponential one (weight 1/N).
        let held = t.previous.is_some() as u32 * t.rendered.min(t.frames);
        g.blend = match t.frames {
            0 => 1.0,
            n => (1.0 / (held + 1) as f32).max(1.0 / n as f32),
        };
        g.history = (t.frames > 0 && t.previous.is_some()) as u32;
        g.moved = 0;
        if let Some(prev) = &t.previous {
            g.moved = (*prev != frame.camera) as u32;
            let aspect = self.renderer.width as f32 / self.renderer.height as f32;
            g.prev_clip_from_world = prev.clip_from_world(aspect).to_cols_array_2d();
            g.prev_position = prev.position.extend(prev.far).to_array();
            g.prev_forward = prev.forward().as_vec3().extend(0.0).to_array();
        }
    }

    fn mark(&mut self, enc: &mut wgpu::CommandEncoder, phase: &'static str) {
        if let Some(t) = self.timer.as_mut() {
            t.mark(enc, phase);
        }
    }

    /// The lights injected this frame: those that can reach the view frustum (all with no_skip).
    fn active_lights(&self, frame: &FrameState) -> Vec<usize> {
        let aspect = self.renderer.width as f32 / self.renderer.height as f32;
        let clip_from_world = frame.camera.clip_from_world(aspect);
        frame
            .lights
            .iter()
            .enumerate()
            .filter(|(_, l)| self.no_skip || reach::reaches(l, clip_from_world))
            .map(|(k, _)| k)
            .collect()
    }
}

impl Prepared for State {
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        self.mark(enc, "surfaces");
        let mut report = self.renderer.begin_frame(gpu, frame, enc, targets);
        self.update_grid(frame);
        let bytes = bytemuck::bytes_of(&self.grid);
        gpu.queue.write_buffer(&self.uniform, 0, bytes);
        if let Some(u) = &self.apply.uniform {
            gpu.queue.write_buffer(u, 0, bytes);
        }
        let g = self.grid;
        let dims = Dims {
            grid_x: g.grid_x,
            grid_y: g.grid_y,
            slices: g.slices,
        };
        let active = self.active_lights(frame);
        self.mark(enc, "inject");
        self.volume
            .encode_inject(gpu, enc, &self.renderer, dims, &active);
        if active.is_empty() {
            report.skip("inject", "no light can reach the view frustum");
        } else {
            report.ran("inject");
        }
        let parity = (self.temporal.rendered % 2) as usize;
        if self.temporal.frames > 0 {
            self.mark(enc, "temporal");
        }
        if self
            .volume
            .encode_temporal(gpu, enc, &self.renderer, dims, parity)
        {
            report.ran("temporal");
        }
        self.mark(enc, "integrate");
        self.volume
            .encode_integrate(gpu, enc, &self.renderer, dims, parity);
        report.ran("integrate");
        self.temporal.rendered += 1;
        self.temporal.previous = Some(frame.camera);
        self.mark(enc, "apply");
        self.apply
            .encode_with(gpu, enc, &self.renderer, targets, &[&self.volume_view]);
        report.ran("apply");
        if let Some(t) = self.timer.as_mut() {
            t.finish(enc);
        }
        let froxels = g.grid_x as f64 * g.grid_y as f64 * g.slices as f64;
        report.count("froxels", froxels);
        report.count("lights_injected", active.len() as f64);
        Ok(report)
    }

    fn phase_timer(&self) -> Option<&PhaseTimer> {
        self.timer.as_ref()
    }
}
