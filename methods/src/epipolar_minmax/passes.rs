//! epipolar-minmax's GPU resources, pipelines and per-light pass sequence.

use bytemuck::{Pod, Zeroable};
use harness::Gpu;
use harness::gpu::{PhaseTimer, phases};

use crate::common::layouts::{
    buffer_entry, float_texture, rgba32f_storage_write, storage_buffer, uniform_buffer, view_entry,
};
use crate::common::renderer::SceneRenderer;
use crate::common::specialize::{compile_options, flag};
use crate::common::wgsl;

pub const EPIPOLAR_WGSL: &str = include_str!("epipolar.wgsl");
pub const SAMPLING_WGSL: &str = include_str!("sampling.wgsl");
pub const TREES_WGSL: &str = include_str!("trees.wgsl");
pub const MARCH_WGSL: &str = include_str!("march.wgsl");
pub const UNWARP_WGSL: &str = include_str!("unwarp.wgsl");

/// The compute passes' composed WGSL (every entry point of the method but the resolve).
pub fn compute_source() -> String {
    let own = [SAMPLING_WGSL, TREES_WGSL, MARCH_WGSL, UNWARP_WGSL].join("\n");
    wgsl::compose(&[wgsl::PRELUDE, &[EPIPOLAR_WGSL]].concat(), &own)
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
    pub published_view: wgpu::TextureView,
    lights: Vec<LightSlot>,
    shared: Shared,
    shadowed: bool,
}

fn buffer(gpu: &Gpu, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage,
        mapped_at_creation: false,
    })
}

/// Group 1 of every compute pass (epipolar.wgsl's bindings).
fn layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    let cs = wgpu::ShaderStages::COMPUTE;
    let mut entries = vec![uniform_buffer(0, cs)];
    entries.extend((1..=6).map(|b| storage_buffer(b, cs, false)));
    entries.push(float_texture(7, cs));
    entries.push(storage_buffer(8, cs, false));
    entries.push(rgba32f_storage_write(9, cs));
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("epipolar"),
            entries: &entries,
        })
}

impl Passes {
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, sizes: Sizes, min_max: bool) -> Passes {
        let storage = wgpu::BufferUsages::STORAGE;
        let per_sample = sizes.slices as u64 * sizes.samples as u64;
        let pixels = sizes.width as u64 * sizes.height as u64;
        let slices = buffer(gpu, "epipolar slices", 48 * sizes.slices as u64, storage);
        let samples = buffer(gpu, "epipolar samples", 32 * per_sample, storage);
        let work = buffer(
            gpu,
            "epipolar work list",
            4 * per_sample.max(pixels),
            storage,
        );
        let tree_size = 16 * sizes.slices as u64 * sizes.leaves as u64;
        let tree = buffer(gpu, "epipolar min-max trees", tree_size, storage);
        let counters = buffer(
            gpu,
            "epipolar counters",
            4 * COUNTERS.len() as u64,
            storage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        );
        let accum = buffer(gpu, "epipolar accumulator", 16 * pixels, storage);
        let published = gpu.texture_2d(
            "epipolar in-scatter",
            sizes.width,
            sizes.height,
            wgpu::TextureFormat::Rgba32Float,
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let published_view = published.create_view(&Default::default());
        let layout = layout(gpu);
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("epipolar"),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        let module = wgsl::module(&gpu.device, "epipolar", &compute_source());
        let pipeline = |entry: &str, own: &[(&'static str, f64)]| {
            let constants = renderer.specialization.with(own);
            gpu.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pl),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: compile_options(&constants),
                    cache: None,
                })
        };
        let shared = Shared {
            slice_ends: pipeline("slice_ends", &[]),
            place_samples: pipeline("place_samples", &[]),
            refine: pipeline("refine", &[]),
            march_args: pipeline("march_args", &[]),
            rectify: pipeline("rectify", &[]),
            build_tree: pipeline("build_tree", &[]),
            interpolate: pipeline("interpolate", &[]),
            unwarp: pipeline("unwarp", &[]),
            fixup_args: pipeline("fixup_args", &[]),
            publish: pipeline("publish", &[]),
        };
        let shadowed = renderer.shadows_on;
        let lights = (0..renderer.scene.desc.lights.len() as u32)
            .map(|k| {
                let uniform = buffer(
                    gpu,
                    "epipolar light",
                    std::mem::size_of::<EpiUniform>() as u64,
                    wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                );
                let header = buffer(
                    gpu,
                    "epipolar header",
                    4 * HEADER_WORDS,
                    storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                );
                let args = buffer(
                    gpu,
                    "epipolar dispatch",
                    24,
                    wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                );
                let resources: [&wgpu::Buffer; 7] = [
                    &uniform, &slices, &samples, &work, &header, &tree, &counters,
                ];
                let mut entries: Vec<wgpu::BindGroupEntry> = resources
                    .iter()
                    .enumerate()
                    .map(|(b, buf)| buffer_entry(b as u32, buf))
                    .collect();
                entries.push(view_entry(7, &renderer.distance_view));
                entries.push(buffer_entry(8, &accum));
                entries.push(view_entry(9, &published_view));
                let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("epipolar"),
                    layout: &layout,
                    entries: &entries,
                });
                let own = [
                    ("LIGHT", k as f64),
                    ("MIN_MAX", flag(min_max)),
                    ("SHADOWED", flag(shadowed)),
                ];
                LightSlot {
                    uniform,
                    header,
                    args,
                    bind,
                    march: pipeline("march", &own),
                    fixup: pipeline("fixup", &own),
                }
            })
            .collect();
        Passes {
            sizes,
            counters,
            published_view,
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
    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        timer: &mut Option<PhaseTimer>,
    ) {
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
        if let Some(slot) = self.lights.first() {
            let mut pass = renderer.compute_pass(gpu, enc, "epipolar publish", &slot.bind);
            pass.set_pipeline(&sh.publish);
            pass.dispatch_workgroups(per_pixel.0, per_pixel.1, 1);
        }
    }
}

/// How a pipeline is dispatched: workgroup counts, or from the light's `args` at a byte offset.
#[derive(Clone, Copy)]
enum Dispatch {
    Direct(u32, u32, u32),
    Indirect(u64),
}
