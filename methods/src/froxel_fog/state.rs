//! The prepared method: the shared renderer, the grid, the volume passes, the particle passes
//! (particle media) and the apply pass, and one frame's encoding, timed per phase (surfaces,
//! voxelise, extinction, inject, temporal, integrate, particle-surface, apply).

use anyhow::Result;
use harness::gpu::{PhaseTimer, phases};
use harness::knobs::{KnobError, KnobProblem};
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, KnobRead, Prepared, Targets};
use scenes::FrameState;

use super::grid::{FroxelUniform, Temporal};
use super::particle_passes::{Grid, MediumBuffers, ParticlePasses, Shared, grid_values};
use super::passes::{self, Buffers, Dims, Modes, VolumePasses};
use super::reach;
use super::shaders::apply_wgsl;
use crate::common::counters::CounterReadback;
use crate::common::renderer::SceneRenderer;
use crate::common::resolve::ResolvePass;
use crate::common::shadow_maps::ShadowSettings;

/// The prepared method.
pub struct State {
    pub renderer: SceneRenderer,
    grid: FroxelUniform,
    uniform: wgpu::Buffer,
    volume: VolumePasses,
    volume_view: wgpu::TextureView,
    medium: MediumBuffers,
    /// Particle media only.
    particles: Option<ParticlePasses>,
    apply: ResolvePass,
    no_skip: bool,
    temporal: Temporal,
    /// The temporal pass's counts (temporal.wgsl `centre.counts`) and their readback (history
    /// reject, range, revisit).
    history_counts: Option<HistoryCounts>,
    /// GPU time per phase (counters `gpu_ms_<phase>`), where timestamps inside encoders exist.
    timer: Timer,
}

/// The phase timer and what keeps its marks in order with compute work.
struct Timer {
    timer: Option<PhaseTimer>,
    /// 16 bytes cleared after every mark: on lavapipe a timestamp between compute passes is
    /// otherwise not ordered with their work (measured: the voxelise pass's 70 ms showed up in
    /// the phase before it, and its own read 0.02 ms); the clear orders them.
    fence: wgpu::Buffer,
}

impl Timer {
    /// Room for the frame's eight phases, where the device has timestamps inside encoders.
    fn new(gpu: &Gpu) -> Timer {
        Timer {
            timer: PhaseTimer::new(gpu, 8),
            fence: gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("froxel phase fence"),
                size: 16,
                usage: wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    /// Starts phase `phase` of the frame, if there is a timer.
    fn mark(&mut self, enc: &mut wgpu::CommandEncoder, phase: &'static str) {
        phases::mark(&mut self.timer, enc, phase);
        if self.timer.is_some() {
            enc.clear_buffer(&self.fence, 0, None);
        }
    }
}

/// The temporal pass's counts (history reject, range, revisit) of froxels whose reprojected
/// history was dropped and that had one, reported (counters `history_rejected`,
/// `history_reprojected`) two frames late, as [`CounterReadback`] delivers them.
struct HistoryCounts {
    /// The centre-source buffer, whose first 8 bytes are the counts (temporal.wgsl).
    buffer: wgpu::Buffer,
    readback: CounterReadback,
}

impl HistoryCounts {
    fn new(gpu: &Gpu, buffer: wgpu::Buffer) -> HistoryCounts {
        HistoryCounts {
            buffer,
            readback: CounterReadback::new(gpu, 2),
        }
    }

    /// Zeroes this frame's counts and reports the latest that arrived.
    fn begin(&mut self, gpu: &Gpu, report: &mut FrameReport) {
        self.readback.begin_frame(gpu, &self.buffer);
        if let Some(c) = self.readback.latest() {
            report.count("history_rejected", c[0] as f64);
            report.count("history_reprojected", c[1] as f64);
        }
    }
}

/// A storage buffer of `size` bytes.
fn storage(gpu: &Gpu, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | usage,
        mapped_at_creation: false,
    })
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let p = ctx.params;
        let gpu = ctx.gpu;
        let renderer =
            SceneRenderer::new(ctx, ShadowSettings::from_params(p)?, p.knob("pattern_res")?)?;
        let max = gpu.device.limits().max_texture_dimension_2d;
        let grid = FroxelUniform::new(p, (ctx.width, ctx.height), max)?;
        let temporal: u32 = p.knob("temporal")?;
        let (tw, th) = grid.texture_size();
        let volume = gpu.texture_2d(
            "froxel volume",
            tw,
            th,
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let volume_view = volume.create_view(&Default::default());
        let bytes = 16 * grid.froxels();
        let history_bytes = if temporal > 0 { bytes } else { 16 };
        let history = passes::history_code(&p.knob::<String>("history")?);
        // History reject, range and revisit also inject every froxel's centre (temporal.wgsl),
        // after 16 bytes of the temporal pass's counts.
        let rejecting = temporal > 0 && history >= passes::FIRST_REJECTING;
        let centre_bytes = if rejecting { 16 + bytes } else { 32 };
        let none = wgpu::BufferUsages::empty();
        // Cleared when no light is injected (passes.rs).
        let cleared = wgpu::BufferUsages::COPY_DST;
        let counted = cleared | wgpu::BufferUsages::COPY_SRC;
        let centre = storage(gpu, "froxel centre source", centre_bytes, counted);
        let history_counts = rejecting.then(|| HistoryCounts::new(gpu, centre.clone()));
        // Jitter bound `surface`: one nearest-surface slice coordinate per froxel column.
        let surface_bound = temporal > 0 && p.knob::<String>("jitter_bound")? == "surface";
        let columns = grid.grid_x as u64 * grid.grid_y as u64;
        let nearest_bytes = if surface_bound { 4 * columns } else { 4 };
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("froxel grid"),
            size: std::mem::size_of::<FroxelUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let is_particles = renderer.scene.medium().particles().is_some();
        let n: u32 = p.knob("extinction_grid")?;
        let grid_values = if is_particles {
            grid_values(&renderer.scene.desc.lights, n)
        } else {
            0
        };
        let max = gpu.device.limits().max_storage_buffer_binding_size;
        if 4 * grid_values > max {
            return Err(KnobError {
                method: "froxel-fog".into(),
                knob: "extinction_grid".into(),
                value: n.to_string(),
                problem: KnobProblem::Conflict,
                allowed: format!(
                    "the lights' extinction grids (n³ optical depths per sun, 6 n³ per local light) within the adapter's {} MiB storage binding, not {} MiB",
                    max >> 20,
                    (4 * grid_values) >> 20
                ),
            }
            .into());
        }
        let medium = MediumBuffers::new(
            gpu,
            if is_particles { grid.froxels() } else { 0 },
            grid_values,
        );
        let buffers = Buffers {
            uniform: &uniform,
            source: storage(gpu, "froxel source", bytes, cleared),
            history: [
                storage(gpu, "froxel history 0", history_bytes, none),
                storage(gpu, "froxel history 1", history_bytes, none),
            ],
            centre,
            nearest_slice: storage(gpu, "froxel nearest surface", nearest_bytes, none),
            surface_distance: &renderer.distance_view,
            volume: &volume_view,
            medium: &medium,
        };
        let falloff: String = p.knob("falloff")?;
        let modes = Modes {
            temporal: temporal > 0,
            history,
            reject_change: p.knob("reject_change")?,
            slice_falloff: falloff != "point",
            slice_quadrature: falloff == "quadrature",
            particles: is_particles,
            shadow_pcf: p.knob::<String>("shadow_filter")? == "pcf",
            surface_bound,
            jitter_pair: temporal > 0 && p.knob("jitter_pair")?,
        };
        let volume_passes = VolumePasses::new(gpu, &renderer, buffers, modes);
        let particles = is_particles
            .then(|| {
                let shared = Shared {
                    froxel: &uniform,
                    medium: &medium,
                };
                let g = Grid {
                    columns: (grid.grid_x, grid.grid_y),
                    pixel_size: grid.pixel_size,
                    image: (ctx.width, ctx.height),
                };
                ParticlePasses::new(gpu, &renderer, shared, g, n, ctx.no_skip)
            })
            .transpose()?;
        let apply = ResolvePass::with_textures(
            gpu,
            &renderer,
            "froxel apply",
            &apply_wgsl(),
            Some(std::mem::size_of::<FroxelUniform>() as u64),
            1,
        );
        Ok(State {
            renderer,
            grid,
            uniform,
            volume: volume_passes,
            volume_view,
            medium,
            particles,
            apply,
            no_skip: ctx.no_skip,
            temporal: Temporal {
                frames: temporal,
                rendered: 0,
                previous: None,
            },
            history_counts,
            timer: Timer::new(gpu),
        })
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

    /// Shadow maps and surfaces (into the private background-only target for particle media),
    /// this frame's grid uniform; for particle media the bins, the voxelisation and the light
    /// grids.
    fn begin(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        self.timer.mark(enc, "surfaces");
        let mut report = self.renderer.start_frame(gpu, frame);
        self.renderer.encode_shadows(enc, &mut report);
        let aspect = self.renderer.width as f32 / self.renderer.height as f32;
        self.temporal.fill(&mut self.grid, &frame.camera, aspect);
        let bytes = bytemuck::bytes_of(&self.grid);
        gpu.queue.write_buffer(&self.uniform, 0, bytes);
        if let Some(u) = &self.apply.uniform {
            gpu.queue.write_buffer(u, 0, bytes);
        }
        let Some(parts) = self.particles.as_mut() else {
            self.renderer.encode_surface(enc, targets, &mut report);
            return Ok(report);
        };
        let private = Targets {
            surface: &parts.surface_view,
            ..*targets
        };
        self.renderer.encode_surface(enc, &private, &mut report);
        let shared = Shared {
            froxel: &self.uniform,
            medium: &self.medium,
        };
        parts.update(gpu, frame, &shared, &mut report);
        let (voxelised, pairs) = parts.counts();
        report.count("voxelised_particles", voxelised);
        report.count("particle_column_pairs", pairs);
        self.timer.mark(enc, "voxelise");
        parts.encode_voxelise(gpu, enc, &self.renderer);
        report.ran("voxelise");
        self.timer.mark(enc, "extinction");
        parts.encode_extinction(gpu, enc, &self.renderer);
        report.ran("extinction");
        parts.encode_shadow(enc, &self.renderer);
        report.ran("particle-shadow");
        Ok(report)
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
        let mut report = self.begin(gpu, frame, targets, enc)?;
        let g = self.grid;
        let dims = Dims {
            grid_x: g.grid_x,
            grid_y: g.grid_y,
            slices: g.slices,
        };
        let active = self.active_lights(frame);
        self.timer.mark(enc, "inject");
        self.volume
            .encode_inject(gpu, enc, &self.renderer, dims, &active);
        if active.is_empty() {
            report.skip("inject", "no light can reach the view frustum");
        } else {
            report.ran("inject");
        }
        let parity = (self.temporal.rendered % 2) as usize;
        if self.temporal.frames > 0 {
            self.timer.mark(enc, "temporal");
            if let Some(c) = &mut self.history_counts {
                c.begin(gpu, &mut report);
            }
            self.volume
                .encode_temporal(gpu, enc, &self.renderer, dims, parity);
            if let Some(c) = &mut self.history_counts {
                c.readback.end_frame(enc, &c.buffer);
            }
            report.ran("temporal");
        }
        self.timer.mark(enc, "integrate");
        self.volume
            .encode_integrate(gpu, enc, &self.renderer, dims, parity);
        report.ran("integrate");
        self.temporal.advance(&frame.camera);
        if let Some(parts) = &self.particles {
            self.timer.mark(enc, "particle-surface");
            let shared = Shared {
                froxel: &self.uniform,
                medium: &self.medium,
            };
            parts.encode_surface(
                gpu,
                enc,
                &self.renderer,
                &shared,
                &self.volume_view,
                targets,
            );
            report.ran("particle-surface");
        }
        self.timer.mark(enc, "apply");
        self.apply
            .encode_with(gpu, enc, &self.renderer, targets, &[&self.volume_view]);
        report.ran("apply");
        phases::finish(&mut self.timer.timer, enc);
        report.count("froxels", g.froxels() as f64);
        report.count("lights_injected", active.len() as f64);
        Ok(report)
    }

    fn phase_timer(&self) -> Option<&PhaseTimer> {
        self.timer.timer.as_ref()
    }
}
