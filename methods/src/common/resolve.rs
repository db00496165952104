//! A full-screen pass that reads the ray-distance texture and the `surface` AOV (group 1,
//! bindings 0 and 1, plus an optional uniform at binding 2 and `extra_textures` more unfilterable
//! 2-D textures at bindings 3, 4, …) and writes `inscatter` and `total`. The last pass of every
//! method built on [`SceneRenderer`].

use harness::gpu::color_attachment;
use harness::method::AOV_FORMAT;
use harness::{Gpu, Targets};

use super::layouts::{
    buffer_entry, float_texture_array, fragment_texture, storage_buffer, uniform_buffer, view_entry,
};
use super::pipeline::{self, ADD, color_only};
use super::renderer::SceneRenderer;
use super::wgsl;

pub struct ResolvePass {
    label: &'static str,
    /// One pipeline, or (per-light mode) one per light slot with the `LIGHT` override set.
    pipelines: Vec<wgpu::RenderPipeline>,
    per_light: bool,
    layout: wgpu::BindGroupLayout,
    pub uniform: Option<wgpu::Buffer>,
    extra_textures: u32,
    /// Per-light mode only: [`Bindings::counters`] u32 atomics at binding 15.
    pub counters: Option<wgpu::Buffer>,
    /// Per-light mode only: each light's draw scissored to its rectangle of the targets (x, y,
    /// width, height in texels), for targets holding one band per light
    /// ([`ResolvePass::with_light_rects`]).
    light_rects: Option<fn(usize) -> [u32; 4]>,
    /// Whether the pipelines have a group 2 the method owns ([`ResolvePass::with_group`]).
    group2: bool,
}

/// What a resolve pass binds beyond the ray distances and the surface (bindings 0 and 1).
#[derive(Clone, Copy, Debug, Default)]
pub struct Bindings {
    /// A uniform buffer of this many bytes at binding 2 ([`ResolvePass::uniform`]).
    pub uniform: Option<u64>,
    /// This many more unfilterable 2-D textures at bindings 3, 4, …, bound with
    /// [`ResolvePass::encode_with`].
    pub textures: u32,
    /// Which of those are 2-D arrays instead (bit i: binding 3 + i).
    pub texture_arrays: u32,
    /// Per-light mode only: this many u32 atomics at binding 15 (`counters` in WGSL), which the
    /// shader may count into (read back with `common::counters`).
    pub counters: u32,
}

impl ResolvePass {
    /// `own`: the pass's WGSL (an `fs` entry point); composed after PRELUDE and FULLSCREEN.
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        uniform_size: Option<u64>,
    ) -> ResolvePass {
        Self::with_textures(gpu, renderer, label, own, uniform_size, 0)
    }

    /// Per-light mode: the shader declares `override LIGHT: u32;` and handles that one light;
    /// one pipeline per light of the scene (compiled at prepare), drawn in turn with additive blending (the pipeline for light 0
    /// also adds the surface and ambient terms). For shaders whose loop over lights would be too
    /// much for a driver's compiler, and to let the light index be a compile-time constant.
    /// `constants`: the shader's own overrides (knobs its hot code branches on), beside `LIGHT`
    /// and the scene's (`common::specialize`).
    pub fn per_light(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        bindings: Bindings,
        constants: &[(&'static str, f64)],
    ) -> ResolvePass {
        Self::build(gpu, renderer, label, own, bindings, Some(constants), None)
    }

    /// One pipeline (not per light) with the pass's own overrides (`constants`, beside the
    /// scene's) and a group 2 the method owns, laid out by `group2` and bound with
    /// [`ResolvePass::encode_with_group`] (e.g. `common::particles::trace`'s grid).
    pub fn with_group(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        constants: &[(&'static str, f64)],
        group2: &wgpu::BindGroupLayout,
    ) -> ResolvePass {
        let single = Some((constants, group2));
        Self::build(gpu, renderer, label, own, Bindings::default(), None, single)
    }

    /// Like [`ResolvePass::new`], with `extra_textures` more texture bindings (3, 4, …), bound
    /// with [`ResolvePass::encode_with`].
    pub fn with_textures(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        uniform_size: Option<u64>,
        extra_textures: u32,
    ) -> ResolvePass {
        let bindings = Bindings {
            uniform: uniform_size,
            textures: extra_textures,
            texture_arrays: 0,
            counters: 0,
        };
        Self::build(gpu, renderer, label, own, bindings, None, None)
    }

    fn build(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        bindings: Bindings,
        per_light_constants: Option<&[(&'static str, f64)]>,
        single: Option<(&[(&'static str, f64)], &wgpu::BindGroupLayout)>,
    ) -> ResolvePass {
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &layout_entries(&bindings),
            });
        let counters = (bindings.counters > 0).then(|| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("pass counters"),
                size: 4 * bindings.counters as u64,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let uniform = bindings.uniform.map(|size| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let module = wgsl::module(&gpu.device, label, &source(own));
        let mut groups = vec![&renderer.frame_layout, &layout];
        groups.extend(single.map(|(_, g)| g));
        let pl = pipeline::layout(&gpu.device, label, &groups);
        let own_constants = single.map_or(&[][..], |(c, _)| c);
        let pipelines = pipelines(
            gpu,
            renderer,
            label,
            &pl,
            &module,
            per_light_constants,
            own_constants,
        );
        ResolvePass {
            label,
            pipelines,
            per_light: per_light_constants.is_some(),
            layout,
            uniform,
            extra_textures: bindings.textures,
            counters,
            light_rects: None,
            group2: single.is_some(),
        }
    }

    /// Per-light mode: light k draws only inside `rect(k)` (x, y, width, height in texels).
    pub fn with_light_rects(mut self, rect: fn(usize) -> [u32; 4]) -> ResolvePass {
        assert!(
            self.per_light,
            "{}: light rects need per-light mode",
            self.label
        );
        self.light_rects = Some(rect);
        self
    }

    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
    ) {
        self.encode_with(gpu, enc, renderer, targets, &[]);
    }

    /// Encodes a [`ResolvePass::with_group`] pass with its group 2.
    pub fn encode_with_group(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
        group2: &wgpu::BindGroup,
    ) {
        assert!(self.group2, "{}: no group 2 declared", self.label);
        self.encode_groups(gpu, enc, renderer, targets, &[], Some(group2));
    }

    /// Encodes the pass with `extra` bound at bindings 3, 4, … (as many as declared).
    pub fn encode_with(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
        extra: &[&wgpu::TextureView],
    ) {
        self.encode_groups(gpu, enc, renderer, targets, extra, None);
    }

    fn encode_groups(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
        extra: &[&wgpu::TextureView],
        group2: Option<&wgpu::BindGroup>,
    ) {
        assert_eq!(
            extra.len() as u32,
            self.extra_textures,
            "{}: texture count",
            self.label
        );
        // The harness owns the AOV textures, so the group that reads `surface` is built per frame.
        let mut entries = vec![
            view_entry(0, &renderer.distance_view),
            view_entry(1, targets.surface),
        ];
        if let Some(u) = &self.uniform {
            entries.push(buffer_entry(2, u));
        }
        entries.extend(
            extra
                .iter()
                .enumerate()
                .map(|(k, v)| view_entry(3 + k as u32, v)),
        );
        if let Some(c) = &self.counters {
            entries.push(buffer_entry(COUNTERS_BINDING, c));
        }
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout: &self.layout,
            entries: &entries,
        });
        let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        let mut pass = gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(self.label),
                color_attachments: &[
                    color_attachment(targets.inscatter, clear),
                    color_attachment(targets.total, clear),
                ],
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &bind, &[]);
        if let Some(g) = group2 {
            pass.set_bind_group(2, g, &[]);
        }
        let count = if self.per_light {
            renderer.scene.desc.lights.len().min(self.pipelines.len())
        } else {
            1
        };
        for (k, p) in self.pipelines[..count].iter().enumerate() {
            if let Some(rect) = self.light_rects {
                // The full-screen triangle, scissored: fragment positions stay the targets'.
                let [x, y, w, h] = rect(k);
                pass.set_scissor_rect(x, y, w, h);
            }
            pass.set_pipeline(p);
            pass.draw(0..3, 0..1);
        }
    }
}

/// The binding of the per-light counters.
const COUNTERS_BINDING: u32 = 15;

/// Group 1's layout: distances (0), surface (1), then what `bindings` asks for.
fn layout_entries(bindings: &Bindings) -> Vec<wgpu::BindGroupLayoutEntry> {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    let mut entries = vec![fragment_texture(0), fragment_texture(1)];
    if bindings.uniform.is_some() {
        entries.push(uniform_buffer(2, fragment));
    }
    entries.extend((0..bindings.textures).map(|k| {
        if bindings.texture_arrays >> k & 1 == 1 {
            float_texture_array(3 + k, fragment)
        } else {
            fragment_texture(3 + k)
        }
    }));
    if bindings.counters > 0 {
        entries.push(storage_buffer(COUNTERS_BINDING, fragment, false));
    }
    entries
}

/// One pipeline writing `inscatter` and `total`, or (per-light mode, `per_light_constants`
/// given) one per light slot with `LIGHT` set, blended additively.
fn pipelines(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    per_light_constants: Option<&[(&'static str, f64)]>,
    own_constants: &[(&'static str, f64)],
) -> Vec<wgpu::RenderPipeline> {
    let per_light = per_light_constants.is_some();
    let target = pipeline::target(AOV_FORMAT, per_light.then_some(color_only(ADD)));
    // At least one: a scene without lights still draws light 0's pipeline (surface, ambient).
    let slots = if per_light {
        renderer.scene.desc.lights.len().max(1)
    } else {
        1
    };
    (0..slots)
        .map(|k| {
            let own = match per_light_constants {
                Some(c) => [&[("LIGHT", k as f64)][..], c].concat(),
                None => own_constants.to_vec(),
            };
            let constants = renderer.specialization.with(&own);
            fullscreen_pipeline(
                &gpu.device,
                label,
                layout,
                module,
                "fs",
                &constants,
                &[target.clone(), target.clone()],
            )
        })
        .collect()
}

/// A pipeline drawing `vs_fullscreen` (FULLSCREEN) with fragment entry point `fs` of `module`,
/// no depth, no vertex buffers; `constants` for both stages.
pub fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fs: &str,
    constants: &[(&str, f64)],
    targets: &[Option<wgpu::ColorTargetState>],
) -> wgpu::RenderPipeline {
    pipeline::Stage::new(label, "vs_fullscreen")
        .fragment(fs, targets)
        .build(device, layout, module, constants)
}

/// The composed WGSL of a resolve pass.
pub fn source(own: &str) -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::FULLSCREEN, RESOLVE_IO]].concat(),
        own,
    )
}

/// The bindings 0–1, `Out` and the ray-length and ambient helpers every resolve pass shares.
const RESOLVE_IO: &str = include_str!("wgsl/resolve_io.wgsl");
