//! prefiltered-single-scattering's GPU resources, pipelines and per-light pass sequence: per
//! light, the slices, the rectified rows in the basis, their prefix sums and the per-pixel
//! shading into an accumulator; then one publish pass for the resolve.

use bytemuck::{Pod, Zeroable};
use harness::Gpu;
use harness::gpu::{PhaseTimer, phases};

use crate::common::layouts::{
    buffer_entry, float_texture, rgba32f_storage_write, storage_buffer, uniform_buffer, view_entry,
};
use crate::common::pipeline::{self, ComputeStage};
use crate::common::epipolar::published::{published_texture, scratch_buffer as buffer};
use crate::common::epipolar::rectification::{EPIPOLAR_SLICES, SLICE_BYTES};
use crate::common::renderer::SceneRenderer;
use crate::common::specialize::flag;
use crate::common::wgsl;

pub const BASIS_WGSL: &str = include_str!("basis.wgsl");
pub const ROWS_WGSL: &str = include_str!("rows.wgsl");
pub const SHADE_WGSL: &str = include_str!("shade.wgsl");

/// The compute passes' composed WGSL (every entry point of the method but the resolve).
pub fn compute_source() -> String {
    let own = [BASIS_WGSL, ROWS_WGSL, SHADE_WGSL].join("\n");
    wgsl::compose(
        &[wgsl::PRELUDE, &[EPIPOLAR_SLICES, wgsl::LIGHT_SEGMENTS]].concat(),
        &own,
    )
}

/// `Pss` in rows.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct PssUniform {
    pub light: u32,
    pub slices: u32,
    pub texels: u32,
    pub first: u32,
}

/// The visibility basis (the `basis` knob) and what it needs per row entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Basis {
    /// Peters et al.'s four moments, summed as double floats (high and low vec4).
    Moments,
    /// Annen et al.'s / Klehm et al.'s Fourier series with this many terms (even, ≤ 32).
    Fourier { terms: u32, lanczos: bool },
}

impl Basis {
    /// vec4 channels per row entry (basis.wgsl's CHANNELS).
    pub fn channels(self) -> u32 {
        match self {
            Basis::Moments => 2,
            Basis::Fourier { terms, .. } => terms / 2,
        }
    }

    /// The basis' overrides (basis.wgsl).
    pub fn constants(self, moment_bias: f64) -> Vec<(&'static str, f64)> {
        let (basis, terms, lanczos) = match self {
            Basis::Moments => (0.0, 2.0, false),
            Basis::Fourier { terms, lanczos } => (1.0, terms as f64, lanczos),
        };
        vec![
            ("BASIS", basis),
            ("TERMS", terms),
            ("CHANNELS", self.channels() as f64),
            ("MOMENT_BIAS", moment_bias),
            ("LANCZOS", flag(lanczos)),
        ]
    }
}

/// The method's sizes and compile-time choices, fixed at prepare.
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    pub slices: u32,
    pub texels: u32,
    pub segments: u32,
    pub panels: u32,
    pub basis: Basis,
    pub moment_bias: f64,
    pub width: u32,
    pub height: u32,
}

/// One light's uniform, bind group and shade pipeline (the scratch buffers are shared: lights
/// run in turn).
struct LightSlot {
    uniform: wgpu::Buffer,
    bind: wgpu::BindGroup,
    shade: wgpu::ComputePipeline,
}

/// The pipelines every light shares.
struct Shared {
    slice_rows: wgpu::ComputePipeline,
    rectify: wgpu::ComputePipeline,
    prefix: wgpu::ComputePipeline,
    publish: wgpu::ComputePipeline,
}

pub struct Passes {
    pub sizes: Sizes,
    pub published_view: wgpu::TextureView,
    lights: Vec<LightSlot>,
    shared: Shared,
    shadowed: bool,
}

/// Group 1 of every compute pass (rows.wgsl's bindings).
fn layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    let cs = wgpu::ShaderStages::COMPUTE;
    let mut entries = vec![uniform_buffer(0, cs)];
    entries.extend((1..=3).map(|b| storage_buffer(b, cs, false)));
    entries.push(float_texture(4, cs));
    entries.push(storage_buffer(5, cs, false));
    entries.push(rgba32f_storage_write(6, cs));
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("prefiltered"),
            entries: &entries,
        })
}

/// Bytes of the prefix-sum rows: per slice K + 1 entries of `channels` vec4s.
pub fn rows_bytes(sizes: &Sizes) -> u64 {
    16 * sizes.slices as u64 * (sizes.texels as u64 + 1) * sizes.basis.channels() as u64
}

/// The buffers every light's passes share (lights run in turn).
struct Scratch {
    slices: wgpu::Buffer,
    angle_range: wgpu::Buffer,
    sums: wgpu::Buffer,
    accum: wgpu::Buffer,
    published_view: wgpu::TextureView,
}

impl Scratch {
    fn new(gpu: &Gpu, sizes: &Sizes) -> Scratch {
        let storage = wgpu::BufferUsages::STORAGE;
        let n = sizes.slices as u64;
        let pixels = sizes.width as u64 * sizes.height as u64;
        Scratch {
            slices: buffer(gpu, "prefiltered slices", SLICE_BYTES * n, storage),
            angle_range: buffer(gpu, "prefiltered angle ranges", 8 * n, storage),
            sums: buffer(gpu, "prefiltered rows", rows_bytes(sizes), storage),
            accum: buffer(gpu, "prefiltered accumulator", 16 * pixels, storage),
            published_view: published_texture(
                gpu,
                "prefiltered in-scatter",
                sizes.width,
                sizes.height,
            ),
        }
    }
}

/// The method's compute entry points, compiled from one module under one layout with the
/// scene's constants, the basis' and each pipeline's own.
struct Compiler<'a> {
    gpu: &'a Gpu,
    renderer: &'a SceneRenderer,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    basis: Vec<(&'static str, f64)>,
}

impl Compiler<'_> {
    fn pipeline(&self, entry: &str, own: &[(&'static str, f64)]) -> wgpu::ComputePipeline {
        let constants = self
            .renderer
            .specialization
            .with(&[&self.basis[..], own].concat());
        ComputeStage::new(entry, entry).build(
            &self.gpu.device,
            &self.layout,
            &self.module,
            &constants,
        )
    }
}

impl Passes {
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, sizes: Sizes) -> Passes {
        let scratch = Scratch::new(gpu, &sizes);
        let layout = layout(gpu);
        let c = Compiler {
            gpu,
            renderer,
            layout: pipeline::layout(
                &gpu.device,
                "prefiltered",
                &[&renderer.frame_layout, &layout],
            ),
            module: wgsl::module(&gpu.device, "prefiltered", &compute_source()),
            basis: sizes.basis.constants(sizes.moment_bias),
        };
        let shared = Shared {
            slice_rows: c.pipeline("slice_rows", &[]),
            rectify: c.pipeline("rectify", &[]),
            prefix: c.pipeline("prefix", &[]),
            publish: c.pipeline("publish", &[]),
        };
        let shadowed = renderer.shadows_on;
        let lights = (0..renderer.scene.desc.lights.len())
            .map(|k| {
                let own = [
                    ("LIGHT", k as f64),
                    ("SEGMENTS", sizes.segments as f64),
                    ("PANELS", sizes.panels as f64),
                    ("SHADOWED", flag(shadowed)),
                ];
                light_slot(&c, &layout, &scratch, &own)
            })
            .collect();
        Passes {
            sizes,
            published_view: scratch.published_view,
            lights,
            shared,
            shadowed,
        }
    }

    /// Writes each light's uniform (before the frame is encoded).
    pub fn write_uniforms(&self, gpu: &Gpu) {
        for (k, slot) in self.lights.iter().enumerate() {
            let u = PssUniform {
                light: k as u32,
                slices: self.sizes.slices,
                texels: self.sizes.texels,
                first: (k == 0) as u32,
            };
            gpu.queue
                .write_buffer(&slot.uniform, 0, bytemuck::bytes_of(&u));
        }
    }

    /// Every light's passes in turn, then the publish pass. `timer` marks the phases.
    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        timer: &mut Option<PhaseTimer>,
    ) {
        let s = self.sizes;
        let sh = &self.shared;
        let per_pixel = (s.width.div_ceil(8), s.height.div_ceil(8));
        for slot in &self.lights {
            phases::mark(timer, enc, "rows");
            {
                let mut pass = renderer.compute_pass(gpu, enc, "prefiltered rows", &slot.bind);
                pass.set_pipeline(&sh.slice_rows);
                pass.dispatch_workgroups(s.slices.div_ceil(64), 1, 1);
                if self.shadowed {
                    pass.set_pipeline(&sh.rectify);
                    pass.dispatch_workgroups(s.texels.div_ceil(64), s.slices, 1);
                    pass.set_pipeline(&sh.prefix);
                    pass.dispatch_workgroups(s.slices.div_ceil(64), 1, 1);
                }
            }
            phases::mark(timer, enc, "shade");
            let mut pass = renderer.compute_pass(gpu, enc, "prefiltered shade", &slot.bind);
            pass.set_pipeline(&slot.shade);
            pass.dispatch_workgroups(per_pixel.0, per_pixel.1, 1);
        }
        if let Some(slot) = self.lights.first() {
            let mut pass = renderer.compute_pass(gpu, enc, "prefiltered publish", &slot.bind);
            pass.set_pipeline(&sh.publish);
            pass.dispatch_workgroups(per_pixel.0, per_pixel.1, 1);
        }
    }
}

/// Light k's uniform and group 1 over the shared `scratch`; `own`: its shade pipeline's constants.
fn light_slot(
    c: &Compiler,
    layout: &wgpu::BindGroupLayout,
    scratch: &Scratch,
    own: &[(&'static str, f64)],
) -> LightSlot {
    let gpu = c.gpu;
    let uniform = buffer(
        gpu,
        "prefiltered light",
        std::mem::size_of::<PssUniform>() as u64,
        wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    );
    let s = scratch;
    let entries = [
        buffer_entry(0, &uniform),
        buffer_entry(1, &s.slices),
        buffer_entry(2, &s.angle_range),
        buffer_entry(3, &s.sums),
        view_entry(4, &c.renderer.distance_view),
        buffer_entry(5, &s.accum),
        view_entry(6, &s.published_view),
    ];
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("prefiltered"),
        layout,
        entries: &entries,
    });
    LightSlot {
        uniform,
        bind,
        shade: c.pipeline("shade", own),
    }
}
