//! prefiltered-single-scattering's GPU resources, pipelines and per-light pass sequence: per
//! light, the slices, the rectified rows in the basis, their prefix sums and the per-pixel
//! shading into an accumulator; then one publish pass for the resolve.

use bytemuck::{Pod, Zeroable};
use harness::Gpu;
use harness::gpu::phases;

use crate::common::epipolar::published::scratch_buffer as buffer;
use crate::common::epipolar::rectification::{EPIPOLAR_SLICES, SLICE_BYTES};
use crate::common::epipolar::skeleton::{self, Compiler, Constants, Encoding, Published};
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
    pub published: Published,
    lights: Vec<LightSlot>,
    shared: Shared,
    shadowed: bool,
}

/// Method buffers at bindings 1..=3 of group 1 (rows.wgsl; the rest is
/// [`skeleton::group_layout`]'s).
const STORAGE: u32 = 3;

/// Bytes of the prefix-sum rows: per slice K + 1 entries of `channels` vec4s.
pub fn rows_bytes(sizes: &Sizes) -> u64 {
    16 * sizes.slices as u64 * (sizes.texels as u64 + 1) * sizes.basis.channels() as u64
}

/// The buffers every light's passes share (lights run in turn).
struct Scratch {
    slices: wgpu::Buffer,
    angle_range: wgpu::Buffer,
    sums: wgpu::Buffer,
    published: Published,
}

impl Scratch {
    fn new(gpu: &Gpu, sizes: &Sizes) -> Scratch {
        let storage = wgpu::BufferUsages::STORAGE;
        let n = sizes.slices as u64;
        Scratch {
            slices: buffer(gpu, "prefiltered slices", SLICE_BYTES * n, storage),
            angle_range: buffer(gpu, "prefiltered angle ranges", 8 * n, storage),
            sums: buffer(gpu, "prefiltered rows", rows_bytes(sizes), storage),
            published: Published::new(gpu, "prefiltered", sizes.width, sizes.height),
        }
    }
}

impl Passes {
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, sizes: Sizes) -> Passes {
        let scratch = Scratch::new(gpu, &sizes);
        let basis = sizes.basis.constants(sizes.moment_bias);
        let c = Compiler::new(gpu, renderer, "prefiltered", STORAGE, &compute_source(), basis);
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
                light_slot(&c, &scratch, &own)
            })
            .collect();
        Passes {
            sizes,
            published: scratch.published,
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
    pub fn encode(&self, enc: &mut wgpu::CommandEncoder, e: Encoding) {
        let Encoding { gpu, renderer, timer } = e;
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
        let group1 = self.lights.first().map(|slot| &slot.bind);
        skeleton::encode_publish(renderer, gpu, enc, group1, &sh.publish);
    }
}

/// Light k's uniform and group 1 over the shared `scratch`; `own`: its shade pipeline's constants.
fn light_slot(c: &Compiler, scratch: &Scratch, own: &Constants) -> LightSlot {
    let uniform = skeleton::light_uniform(c.gpu, "prefiltered light", size_of::<PssUniform>());
    let s = scratch;
    let storage = [&s.slices, &s.angle_range, &s.sums];
    LightSlot {
        bind: c.light_group("prefiltered", &uniform, &storage, &s.published),
        uniform,
        shade: c.pipeline("shade", own),
    }
}
