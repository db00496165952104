//! The volume passes' GPU objects: group 1 (grid uniform, source buffer, volume texture, the
//! two history buffers), one `inject` pipeline per (light, first-or-not), the `temporal` and
//! `integrate` pipelines, and their dispatch.

use harness::Gpu;

use super::particle_passes::MediumBuffers;
use super::shaders::volume_source;
use crate::common::layouts::{
    buffer_entry, float_texture, rgba32f_storage_write, storage_buffer, uniform_buffer, view_entry,
};
use crate::common::pipeline::{self, ComputeStage};
use crate::common::renderer::SceneRenderer;
use crate::common::specialize::flag;
use crate::common::wgsl;

/// Grid dimensions a dispatch needs.
#[derive(Clone, Copy)]
pub struct Dims {
    pub grid_x: u32,
    pub grid_y: u32,
    pub slices: u32,
}

/// The buffers group 1 binds.
pub struct Buffers<'a> {
    pub uniform: &'a wgpu::Buffer,
    pub source: wgpu::Buffer,
    /// The accumulated source of alternate frames (temporal accumulation; else 16-byte stubs).
    pub history: [wgpu::Buffer; 2],
    /// History reject, range, revisit: 16 bytes of counts (the temporal pass's, `history_counts`
    /// in state.rs), then this frame's source at each froxel's centre (else the counts and one).
    pub centre: wgpu::Buffer,
    /// Jitter bound `surface`: each froxel column's nearest surface as a slice coordinate
    /// (surface_bound.wgsl `nearest_slice`; else a 4-byte stub).
    pub nearest_slice: wgpu::Buffer,
    /// The surface pass's ray distance per pixel (read by `nearest_surface`).
    pub surface_distance: &'a wgpu::TextureView,

    pub volume: &'a wgpu::TextureView,
    pub medium: &'a MediumBuffers,
}

/// The knob `history`'s values, in the order of their codes (HISTORY in temporal.wgsl).
pub const HISTORY_MODES: [&str; 5] = ["none", "clamp", "reject", "range", "revisit"];
/// The first code of the rejecting modes (reject, range, revisit): they inject each froxel's
/// centre too and count what they drop (temporal.wgsl `HISTORY >= 2u`).
pub const FIRST_REJECTING: u32 = 2;

/// The code of the knob `history`'s value `mode` (the knob's choices are validated against
/// [`HISTORY_MODES`] before prepare).
pub fn history_code(mode: &str) -> u32 {
    HISTORY_MODES.iter().position(|m| *m == mode).unwrap_or(0) as u32
}

/// The volume pipelines' modes (pipeline constants).
#[derive(Clone, Copy)]
pub struct Modes {
    pub temporal: bool,
    /// With `temporal`: the knob `history`'s code (an index into [`HISTORY_MODES`]).
    pub history: u32,
    /// History `reject`, `range`, `revisit`: the knob `reject_change`.
    pub reject_change: f32,
    pub slice_falloff: bool,
    /// `falloff` = quadrature: near a local light, the slice's in-scatter by Gauss nodes.
    pub slice_quadrature: bool,
    pub particles: bool,
    /// `shadow_filter` = pcf: 3 × 3 percentage-closer filtering of the shadow map.
    pub shadow_pcf: bool,
    /// With `temporal`, `jitter_bound` = surface: the jitter in depth stays in front of the
    /// column's nearest surface (surface_bound.wgsl).
    pub surface_bound: bool,
    /// With `temporal`, `jitter_pair`: each frame injects its jittered sample and its mirror
    /// image, and a dropped history restarts from that pair (volume.wgsl `JITTER_PAIR`).
    pub jitter_pair: bool,
}

pub struct VolumePasses {
    /// Group 1 for frames of parity p: history[1 − p] read, history[p] written.
    binds: [wgpu::BindGroup; 2],
    /// `inject[k][first]`: light k's injection, storing (first = 1) or adding (first = 0).
    inject: Vec<[wgpu::ComputePipeline; 2]>,
    /// Reprojects and blends the history (temporal accumulation on).
    temporal: Option<wgpu::ComputePipeline>,
    /// Each froxel column's nearest surface (jitter bound `surface`).
    nearest_surface: Option<wgpu::ComputePipeline>,
    integrate: wgpu::ComputePipeline,
    /// The source buffer, and history reject's centre sources (both cleared when no light is
    /// injected: no light, no source).
    source: wgpu::Buffer,
    centre: wgpu::Buffer,
}

impl VolumePasses {
    /// `temporal`: whether the history is accumulated (and integrated instead of the source).
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        buffers: Buffers,
        modes: Modes,
    ) -> VolumePasses {
        let (layout, binds) = bindings(gpu, &buffers);
        let module = wgsl::module(&gpu.device, "froxel volume", &volume_source());
        let pl = pipeline::layout(
            &gpu.device,
            "froxel volume",
            &[&renderer.frame_layout, &layout],
        );
        let particles = ("PARTICLES", flag(modes.particles));
        let pipeline = |entry: &str, own: &[(&'static str, f64)]| {
            let constants = renderer.specialization.with(&[own, &[particles]].concat());
            ComputeStage::new(entry, entry).build(&gpu.device, &pl, &module, &constants)
        };
        let lights = renderer.scene.desc.lights.len();
        let inject = (0..lights)
            .map(|k| {
                [0.0, 1.0].map(|first| {
                    let own = [
                        ("LIGHT", k as f64),
                        ("FIRST", first),
                        ("SLICE_FALLOFF", flag(modes.slice_falloff)),
                        ("SLICE_QUADRATURE", flag(modes.slice_quadrature)),
                        ("SHADOW_PCF", flag(modes.shadow_pcf)),
                        // History `reject`, `range` and `revisit` inject each froxel's centre
                        // too (`revisit` also the previous grid's).
                        ("TEMPORAL", flag(modes.temporal)),
                        ("HISTORY", modes.history as f64),
                        ("SURFACE_BOUND", flag(modes.surface_bound)),
                        ("JITTER_PAIR", flag(modes.jitter_pair)),
                    ];
                    pipeline("inject", &own)
                })
            })
            .collect();
        VolumePasses {
            binds,
            inject,
            temporal: modes.temporal.then(|| {
                let own = [
                    ("HISTORY", modes.history as f64),
                    ("REJECT_CHANGE", modes.reject_change as f64),
                    ("JITTER_PAIR", flag(modes.jitter_pair)),
                ];
                pipeline("temporal", &own)
            }),
            nearest_surface: modes
                .surface_bound
                .then(|| pipeline("nearest_surface", &[])),
            integrate: pipeline(
                "integrate",
                &[
                    ("TEMPORAL", flag(modes.temporal)),
                    ("HISTORY", modes.history as f64),
                ],
            ),
            source: buffers.source,
            centre: buffers.centre,
        }
    }

    fn pass<'e>(
        &self,
        gpu: &Gpu,
        enc: &'e mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        label: &str,
        parity: usize,
    ) -> harness::gpu::Counted<wgpu::ComputePass<'e>> {
        renderer.compute_pass(gpu, enc, label, &self.binds[parity])
    }

    /// Injects the lights `active` (indices into the scene's lights) into the source buffer, or
    /// clears it when there is none.
    pub fn encode_inject(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        dims: Dims,
        active: &[usize],
    ) {
        if active.is_empty() {
            enc.clear_buffer(&self.source, 0, None);
            // The centre sources after the temporal pass's counts.
            enc.clear_buffer(&self.centre, 16, None);
            return;
        }
        let mut pass = self.pass(gpu, enc, renderer, "froxel inject", 0);
        if let Some(p) = &self.nearest_surface {
            pass.set_pipeline(p);
            pass.dispatch_workgroups(dims.grid_x.div_ceil(8), dims.grid_y.div_ceil(8), 1);
        }
        for (i, &k) in active.iter().enumerate() {
            pass.set_pipeline(&self.inject[k][(i == 0) as usize]);
            pass.dispatch_workgroups(
                dims.grid_x.div_ceil(4),
                dims.grid_y.div_ceil(4),
                dims.slices.div_ceil(4),
            );
        }
    }

    /// Blends this frame's source into the reprojected history of parity 1 − `parity`, into
    /// history[`parity`]. False (nothing encoded) without temporal accumulation.
    pub fn encode_temporal(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        dims: Dims,
        parity: usize,
    ) -> bool {
        let Some(p) = &self.temporal else {
            return false;
        };
        let mut pass = self.pass(gpu, enc, renderer, "froxel temporal", parity);
        pass.set_pipeline(p);
        pass.dispatch_workgroups(
            dims.grid_x.div_ceil(4),
            dims.grid_y.div_ceil(4),
            dims.slices.div_ceil(4),
        );
        true
    }

    /// Integrates every froxel column front to back into the volume texture (the accumulated
    /// source of `parity` with temporal accumulation).
    pub fn encode_integrate(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        dims: Dims,
        parity: usize,
    ) {
        let mut pass = self.pass(gpu, enc, renderer, "froxel integrate", parity);
        pass.set_pipeline(&self.integrate);
        pass.dispatch_workgroups(dims.grid_x.div_ceil(8), dims.grid_y.div_ceil(8), 1);
    }
}

/// Group 1 of the volume passes: the grid uniform, the source buffer, the volume texture, the
/// history read and the history written (one group per frame parity), the particle media and
/// the centre sources.
fn bindings(gpu: &Gpu, b: &Buffers) -> (wgpu::BindGroupLayout, [wgpu::BindGroup; 2]) {
    let cs = wgpu::ShaderStages::COMPUTE;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("froxel volume"),
            entries: &[
                uniform_buffer(0, cs),
                storage_buffer(1, cs, false),
                rgba32f_storage_write(2, cs),
                storage_buffer(3, cs, true),
                storage_buffer(4, cs, false),
                storage_buffer(5, cs, true),
                uniform_buffer(6, cs),
                storage_buffer(7, cs, true),
                storage_buffer(8, cs, false),
                storage_buffer(9, cs, false),
                float_texture(10, cs),
            ],
        });
    let group = |parity: usize| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("froxel volume"),
            layout: &layout,
            entries: &[
                buffer_entry(0, b.uniform),
                buffer_entry(1, &b.source),
                view_entry(2, b.volume),
                buffer_entry(3, &b.history[1 - parity]),
                buffer_entry(4, &b.history[parity]),
                buffer_entry(5, &b.medium.density),
                buffer_entry(6, &b.medium.uniform),
                buffer_entry(7, &b.medium.optical_depth),
                buffer_entry(8, &b.centre),
                buffer_entry(9, &b.nearest_slice),
                view_entry(10, b.surface_distance),
            ],
        })
    };
    let binds = [group(0), group(1)];
    (layout, binds)
}
