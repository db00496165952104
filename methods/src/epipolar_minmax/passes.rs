//! epipolar-minmax's GPU resources, pipelines and per-light pass sequence.

use bytemuck::{Pod, Zeroable};
use harness::Gpu;
use harness::gpu::phases;

use crate::common::epipolar::published::scratch_buffer as buffer;
use crate::common::epipolar::rectification::{EPIPOLAR_SLICES, SLICE_BYTES};
use crate::common::epipolar::skeleton::{self, Compiler, Constants, Encoding, Published};
use crate::common::renderer::SceneRenderer;
use crate::common::specialize::flag;
use crate::common::wgsl;

pub const EPIPOLAR_WGSL: &str = include_str!("epipolar.wgsl");
pub const SAMPLING_WGSL: &str = include_str!("sampling.wgsl");
pub const TREES_WGSL: &str = include_str!("trees.wgsl");
pub const MARCH_WGSL: &str = include_str!("march.wgsl");
pub const UNWARP_WGSL: &str = include_str!("unwarp.wgsl");

/// The compute passes' composed WGSL (every entry point of the method but the resolve).
pub fn compute_source() -> String {
    let own = [SAMPLING_WGSL, TREES_WGSL, MARCH_WGSL, UNWARP_WGSL].join("\n");
    wgsl::compose(
        &[wgsl::PRELUDE, &[EPIPOLAR_SLICES, EPIPOLAR_WGSL]].concat(),
        &own,
    )
}

/// `Epi` in epipolar.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct EpiUniform {
    pub light: u32,
    pub slices: u32,
    pub samples: u32,
    pub initial_step: u32,
    pub leaves: u32,
    pub levels: u32,
    pub first: u32,
    pub shadowed: u32,
    pub refine_threshold: f32,
    pub _pad: [f32; 3],
}

/// Frame counters the passes add to (the `COUNT_*` slots of epipolar.wgsl), in slot order.
pub const COUNTERS: [&str; 5] = [
    "samples_marched",
    "samples_interpolated",
    "fixup_pixels",
    "tree_leaves_skipped",
    "leaves_tested",
];

/// Header words per light: counts of marched samples and fix-up pixels, two dispatch triples.
const HEADER_WORDS: u64 = 8;

/// The method's sizes, fixed at prepare.
#[derive(Clone, Copy)]
pub struct Sizes {
    pub slices: u32,
    pub samples: u32,
    pub leaves: u32,
    pub width: u32,
    pub height: u32,
}

/// One light's uniform, header and bind group (the scratch buffers are shared: lights run in turn).
struct LightSlot {
    uniform: wgpu::Buffer,
    header: wgpu::Buffer,
    /// The header's two dispatch triples, copied out: a buffer bound as storage in a dispatch
    /// cannot also hold that dispatch's indirect arguments.
    args: wgpu::Buffer,
    bind: wgpu::BindGroup,
    march: wgpu::ComputePipeline,
    fixup: wgpu::ComputePipeline,
}

/// Every compute pipeline but the per-light ones.
struct Shared {
    slice_ends: wgpu::ComputePipeline,
    place_samples: wgpu::ComputePipeline,
    refine: wgpu::ComputePipeline,
    march_args: wgpu::ComputePipeline,
    rectify: wgpu::ComputePipeline,
    build_tree: wgpu::ComputePipeline,
    interpolate: wgpu::ComputePipeline,
    unwarp: wgpu::ComputePipeline,
    fixup_args: wgpu::ComputePipeline,
    publish: wgpu::ComputePipeline,
}

pub struct Passes {
    pub sizes: Sizes,
    pub counters: wgpu::Buffer,
    pub published: Published,
    lights: Vec<LightSlot>,
    shared: Shared,
    shadowed: bool,
}

/// Method buffers at bindings 1..=6 of group 1 (epipolar.wgsl; the rest is
/// [`skeleton::group_layout`]'s).
const STORAGE: u32 = 6;

/// The buffers and textures every light's passes share (lights run in turn).
struct Scratch {
    slices: wgpu::Buffer,
    samples: wgpu::Buffer,
    work: wgpu::Buffer,
    tree: wgpu::Buffer,
    counters: wgpu::Buffer,
    published: Published,
}

impl Scratch {
    fn new(gpu: &Gpu, sizes: &Sizes) -> Scratch {
        let storage = wgpu::BufferUsages::STORAGE;
        let per_sample = sizes.slices as u64 * sizes.samples as u64;
        let pixels = sizes.width as u64 * sizes.height as u64;
        let tree_size = 16 * sizes.slices as u64 * sizes.leaves as u64;
        let copies = wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        Scratch {
            slices: buffer(
                gpu,
                "epipolar slices",
                SLICE_BYTES * sizes.slices as u64,
                storage,
            ),
            samples: buffer(gpu, "epipolar samples", 32 * per_sample, storage),
            work: buffer(
                gpu,
                "epipolar work list",
                4 * per_sample.max(pixels),
                storage,
            ),
            tree: buffer(gpu, "epipolar min-max trees", tree_size, storage),
            counters: buffer(
                gpu,
                "epipolar counters",
                4 * COUNTERS.len() as u64,
                storage | copies,
            ),
            published: Published::new(gpu, "epipolar", sizes.width, sizes.height),
        }
    }
}

impl Shared {
    fn new(c: &Compiler) -> Shared {
        Shared {
            slice_ends: c.pipeline("slice_ends", &[]),
            place_samples: c.pipeline("place_samples", &[]),
            refine: c.pipeline("refine", &[]),
            march_args: c.pipeline("march_args", &[]),
            rectify: c.pipeline("rectify", &[]),
            build_tree: c.pipeline("build_tree", &[]),
            interpolate: c.pipeline("interpolate", &[]),
            unwarp: c.pipeline("unwarp", &[]),
            fixup_args: c.pipeline("fixup_args", &[]),
            publish: c.pipeline("publish", &[]),
        }
    }
}

impl LightSlot {
    /// Light k's uniform, header, dispatch arguments and group 1 over the shared `scratch`;
    /// `own`: its march and fix-up pipelines' constants.
    fn new(c: &Compiler, scratch: &Scratch, own: &Constants) -> LightSlot {
        let gpu = c.gpu;
        let uniform = skeleton::light_uniform(gpu, "epipolar light", size_of::<EpiUniform>());
        let header = buffer(
            gpu,
            "epipolar header",
            4 * HEADER_WORDS,
            wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
        );
        let args = buffer(
            gpu,
            "epipolar dispatch",
            24,
            wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
        );
        let s = scratch;
        let storage = [&s.slices, &s.samples, &s.work, &header, &s.tree, &s.counters];
        let bind = c.light_group("epipolar", &uniform, &storage, &s.published);
        LightSlot {
            uniform,
            header,
            args,
            bind,
            march: c.pipeline("march", own),
            fixup: c.pipeline("fixup", own),
        }
    }
}

impl Passes {
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, sizes: Sizes, min_max: bool) -> Passes {
        let scratch = Scratch::new(gpu, &sizes);
        let c = Compiler::new(gpu, renderer, "epipolar", STORAGE, &compute_source(), vec![]);
        let shared = Shared::new(&c);
        let shadowed = renderer.shadows_on;
        let lights = (0..renderer.scene.desc.lights.len())
            .map(|k| {
                let own = [
                    ("LIGHT", k as f64),
                    ("MIN_MAX", flag(min_max)),
                    ("SHADOWED", flag(shadowed)),
                ];
                LightSlot::new(&c, &scratch, &own)
            })
            .collect();
        Passes {
            sizes,
            counters: scratch.counters,
            published: scratch.published,
            lights,
            shared,
            shadowed,
        }
    }

    /// Writes each light's uniform and clears its header (before the frame is encoded).
    pub fn write_uniforms(&self, gpu: &Gpu, base: EpiUniform) {
        for (k, slot) in self.lights.iter().enumerate() {
            let u = EpiUniform {
                light: k as u32,
                first: (k == 0) as u32,
                shadowed: self.shadowed as u32,
                ..base
            };
            gpu.queue
                .write_buffer(&slot.uniform, 0, bytemuck::bytes_of(&u));
            gpu.queue
                .write_buffer(&slot.header, 0, &[0u8; 4 * HEADER_WORDS as usize]);
        }
    }

    /// Every light's passes in turn, then the publish pass. `timer` marks the phases.
    pub fn encode(&self, enc: &mut wgpu::CommandEncoder, e: Encoding) {
        let Encoding { gpu, renderer, timer } = e;
        let s = self.sizes;
        let sh = &self.shared;
        let per_sample = (s.samples.div_ceil(64), s.slices, 1);
        let per_pixel = (s.width.div_ceil(8), s.height.div_ceil(8), 1);
        for slot in &self.lights {
            let mut mark = |enc: &mut wgpu::CommandEncoder, name| phases::mark(timer, enc, name);
            let run = |enc: &mut wgpu::CommandEncoder,
                       steps: &[(&wgpu::ComputePipeline, Dispatch)]| {
                let mut pass = renderer.compute_pass(gpu, enc, "epipolar", &slot.bind);
                for (p, d) in steps {
                    pass.set_pipeline(p);
                    match *d {
                        Dispatch::Direct(x, y, z) => pass.dispatch_workgroups(x, y, z),
                        Dispatch::Indirect(offset) => {
                            pass.dispatch_workgroups_indirect(&slot.args, offset)
                        }
                    }
                }
            };
            let d = |(x, y, z): (u32, u32, u32)| Dispatch::Direct(x, y, z);
            mark(enc, "sampling");
            run(
                enc,
                &[
                    (&sh.slice_ends, d((s.slices.div_ceil(64), 1, 1))),
                    (&sh.place_samples, d(per_sample)),
                    (&sh.refine, d(per_sample)),
                    (&sh.march_args, d((1, 1, 1))),
                ],
            );
            enc.copy_buffer_to_buffer(&slot.header, 8, &slot.args, 0, 12);
            if self.shadowed {
                mark(enc, "trees");
                run(
                    enc,
                    &[
                        (&sh.rectify, d((s.leaves.div_ceil(64), s.slices, 1))),
                        (&sh.build_tree, d((s.slices.div_ceil(64), 1, 1))),
                    ],
                );
            }
            mark(enc, "march");
            run(enc, &[(&slot.march, Dispatch::Indirect(0))]);
            mark(enc, "interpolate");
            run(
                enc,
                &[
                    (&sh.interpolate, d(per_sample)),
                    (&sh.unwarp, d(per_pixel)),
                    (&sh.fixup_args, d((1, 1, 1))),
                ],
            );
            enc.copy_buffer_to_buffer(&slot.header, 20, &slot.args, 12, 12);
            mark(enc, "fixup");
            run(enc, &[(&slot.fixup, Dispatch::Indirect(12))]);
        }
        let group1 = self.lights.first().map(|slot| &slot.bind);
        skeleton::encode_publish(renderer, gpu, enc, group1, &sh.publish);
    }
}

/// How a pipeline is dispatched: workgroup counts, or from the light's `args` at a byte offset.
#[derive(Clone, Copy)]
enum Dispatch {
    Direct(u32, u32, u32),
    Indirect(u64),
}
