//! `froxel-fog`: frustum-aligned volumetric fog — a 3-D grid of "froxels" filled by a compute
//! pass, integrated front to back by a second, read once per pixel (what Unreal, Godot and
//! Frostbite ship).
//!
//! Algorithm: the shared shadow-map and surface passes; `inject` evaluates the in-scatter source
//! S = σ_s Σ_lights p(θ) V I(ω) e^(−σ_t r) / r² at one point of every froxel (its centre, or a
//! per-frame hashed point with `jitter`) with V from the common shadow maps and I(ω) from the
//! spot falloff and pattern; `integrate` walks each froxel column from the eye and accumulates
//! L += T (S − S e^(−σ_t d)) / σ_t, T *= e^(−σ_t d) per slice of length d, storing L at every
//! slice's far boundary; `apply` reads L at each pixel's ray length (bilinear across columns,
//! linear between slice boundaries) and writes the three AOVs. Froxels cover `pixel_size` ×
//! `pixel_size` screen pixels; slice boundary k sits at view depth far · (k / slices)^
//! `depth_exponent` (1 = linear, larger packs slices near the eye, like Wronski's and Unreal's
//! exponential distribution, without their arbitrary near-slice clip).
//!
//! Papers: Wronski, "Volumetric fog: unified compute shader based solution to atmospheric
//! scattering", SIGGRAPH 2014 Advances in Real-Time Rendering (inject / integrate / apply over a
//! 160×90×64 frustum grid, cost that follows the grid); Hillaire, "Physically based and unified
//! volumetric rendering in Frostbite", SIGGRAPH 2015 (the energy-conserving per-slice integral).
//! Knob defaults after Godot 4 (`volumetric_fog.glsl`, `volumetric_fog_process.glsl`: 64 slices,
//! depth curve) and Unreal's `r.VolumetricFog.GridPixelSize` = 8 / `GridSizeZ` = 64 / jitter.
//! No code was taken from them.
//!
//! Faithful: the three passes, one injected sample per froxel with shadow-map visibility, the
//! front-to-back column integration, one volume lookup per pixel: cost follows the grid.
//! Modernised: Hillaire's analytic slice integral instead of Wronski's point sample times slice
//! length; float32 volume; the scene's phase function; spot patterns.
//! Limits: shafts thinner than a froxel are blurred across it, and light leaks across depth
//! discontinuities within a froxel column (a surface reads the volume interpolated from its
//! neighbours); a light inside the view is point-sampled once per froxel (the 1/r² peak is
//! under- or over-estimated); homogeneous media only (particle media are refused); no temporal
//! reprojection yet.

use anyhow::{Result, bail};
use bytemuck::{Pod, Zeroable};
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Method, MethodInfo, Prepared, Support,
    Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::knobs;
use crate::common::renderer::{SceneRenderer, homogeneous_support};
use crate::common::resolve::{self, ResolvePass};
use crate::common::wgsl;

pub const GRID_WGSL: &str = include_str!("grid.wgsl");
pub const VOLUME_WGSL: &str = include_str!("volume.wgsl");
pub const APPLY_WGSL: &str = include_str!("apply.wgsl");

/// The volume passes' composed WGSL (inject and integrate entry points).
pub fn volume_source() -> String {
    wgsl::compose(&[wgsl::PRELUDE, &[GRID_WGSL]].concat(), VOLUME_WGSL)
}

/// The apply pass's composed WGSL.
pub fn apply_source() -> String {
    resolve::source(&wgsl::compose(&[GRID_WGSL], APPLY_WGSL))
}

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
}

/// The method (a description; [`State`] is the prepared instance).
pub struct FroxelFog;

/// The prepared method: the shared renderer, the volume passes and the apply pass.
pub struct State {
    pub renderer: SceneRenderer,
    grid: FroxelUniform,
    uniform: wgpu::Buffer,
    volume_bind: wgpu::BindGroup,
    inject: wgpu::ComputePipeline,
    integrate: wgpu::ComputePipeline,
    volume_view: wgpu::TextureView,
    apply: ResolvePass,
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
        let grid = FroxelUniform {
            grid_x,
            grid_y,
            slices,
            pixel_size,
            frame: 0,
            jitter: p.knob::<bool>("jitter")? as u32,
            depth_exponent: p.knob("depth_exponent")?,
            tiles_x,
        };
        let volume = gpu.texture_2d(
            "froxel volume",
            grid_x * tiles_x,
            grid_y * tiles_y,
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let volume_view = volume.create_view(&Default::default());
        let source = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("froxel source"),
            size: 16 * grid_x as u64 * grid_y as u64 * slices as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("froxel grid"),
            size: std::mem::size_of::<FroxelUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (layout, volume_bind) = volume_bindings(gpu, &uniform, &source, &volume_view);
        let module = wgsl::module(&gpu.device, "froxel volume", &volume_source());
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("froxel volume"),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = |entry: &str| {
            gpu.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pl),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: renderer.specialization.options(),
                    cache: None,
                })
        };
        let inject = pipeline("inject");
        let integrate = pipeline("integrate");
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
            volume_bind,
            inject,
            integrate,
            volume_view,
            apply,
        })
    }
}

/// Group 1 of the volume passes: the grid uniform, the source buffer, the volume texture.
fn volume_bindings(
    gpu: &Gpu,
    uniform: &wgpu::Buffer,
    source: &wgpu::Buffer,
    volume: &wgpu::TextureView,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let cs = wgpu::ShaderStages::COMPUTE;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("froxel volume"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: cs,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                crate::common::layouts::storage_buffer(1, cs, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: cs,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba32Float,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                    count: None,
                },
            ],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("froxel volume"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: source.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(volume),
            },
        ],
    });
    (layout, bind)
}

impl Prepared for State {
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        let mut report = self.renderer.begin_frame(gpu, frame, enc, targets);
        self.grid.frame = frame.index;
        let bytes = bytemuck::bytes_of(&self.grid);
        gpu.queue.write_buffer(&self.uniform, 0, bytes);
        if let Some(u) = &self.apply.uniform {
            gpu.queue.write_buffer(u, 0, bytes);
        }
        let g = self.grid;
        {
            let mut pass = gpu.compute_pass(
                enc,
                &wgpu::ComputePassDescriptor {
                    label: Some("froxel inject + integrate"),
                    timestamp_writes: None,
                },
            );
            pass.set_bind_group(0, &self.renderer.frame_bind, &[]);
            pass.set_bind_group(1, &self.volume_bind, &[]);
            pass.set_pipeline(&self.inject);
            pass.dispatch_workgroups(
                g.grid_x.div_ceil(4),
                g.grid_y.div_ceil(4),
                g.slices.div_ceil(4),
            );
            pass.set_pipeline(&self.integrate);
            pass.dispatch_workgroups(g.grid_x.div_ceil(8), g.grid_y.div_ceil(8), 1);
        }
        report.ran("inject");
        report.ran("integrate");
        self.apply
            .encode_with(gpu, enc, &self.renderer, targets, &[&self.volume_view]);
        report.ran("apply");
        let froxels = g.grid_x as f64 * g.grid_y as f64 * g.slices as f64;
        report.count("froxels", froxels);
        report.count(
            "lights_injected",
            self.renderer.scene.desc.lights.len() as f64,
        );
        Ok(report)
    }
}

impl Method for FroxelFog {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "froxel-fog",
            paper: "Wronski, Volumetric fog: unified compute shader based solution to atmospheric scattering, SIGGRAPH 2014 Advances; Hillaire, Physically based and unified volumetric rendering in Frostbite, SIGGRAPH 2015",
            summary: "Frustum-aligned froxel grid: inject, integrate front to back (Hillaire's slice integral), one lookup per pixel",
            readme: include_str!("README.md"),
            source: include_str!("mod.rs"),
        }
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int("pixel_size", 8, 2..=64)
                .sweep([4, 16])
                .unit("pixels")
                .meaning("screen pixels per froxel in x and y (Unreal's GridPixelSize)"),
            // 1024 slices already make a 1024² volume texture tile at pixel_size 8 and 512².
            Knob::int("slices", 64, 4..=1024)
                .sweep([32, 128, 256])
                .unit("slices")
                .meaning("froxel slices along view depth, eye to far plane"),
            Knob::float("depth_exponent", 2.0, 1.0..=4.0)
                .sweep([1.0, 3.0])
                .meaning("slice boundary k at depth far·(k/slices)^exponent: 1 linear, larger packs slices near the eye"),
            Knob::boolean("jitter", false)
                .meaning("per-frame hashed sample point within each froxel instead of its centre"),
            knobs::shadow_map(1024),
            knobs::pattern_res(512),
        ]
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        homogeneous_support(scene, device, None)
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        [
            ShaderCheck::combinations("froxel-fog/volume", &volume_source(), &[]),
            ShaderCheck::combinations("froxel-fog/apply", &apply_source(), &[]),
        ]
        .concat()
    }

    fn conformance(&self) -> Vec<ConformanceCase> {
        // A fine grid (2 px froxels, 256 slices): at the defaults a 48² image is 6×6 froxels.
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.3)
                .knob("pixel_size", 2i64)
                .knob("slices", 256i64),
        ]
    }
}
