//! A full-screen pass that reads the ray-distance texture and the `surface` AOV (group 1,
//! bindings 0 and 1, plus an optional uniform at binding 2 and `extra_textures` more unfilterable
//! 2-D textures at bindings 3, 4, …) and writes `inscatter` and `total`. The last pass of every
//! method built on [`SceneRenderer`].

use harness::method::AOV_FORMAT;
use harness::{Gpu, Targets};

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
    /// Per-light mode only: `counter_slots` u32 atomics at binding 15 (`counters` in WGSL),
    /// which the pass's shader may count into (read back with `common::counters`).
    pub counters: Option<wgpu::Buffer>,
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
        Self::build(gpu, renderer, label, own, uniform_size, 0, None, 0)
    }

    /// Per-light mode: the shader declares `override LIGHT: u32;` and handles that one light;
    /// one pipeline per light slot, drawn in turn with additive blending (the pipeline for light 0
    /// also adds the surface and ambient terms). For shaders whose loop over lights would be too
    /// much for a driver's compiler, and to let the light index be a compile-time constant.
    /// `constants`: the shader's own overrides (knobs its hot code branches on), beside `LIGHT`
    /// and the scene's (`common::specialize`).
    #[allow(clippy::too_many_arguments)]
    pub fn per_light(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        uniform_size: Option<u64>,
        extra_textures: u32,
        counter_slots: u32,
        constants: &[(&'static str, f64)],
    ) -> ResolvePass {
        Self::build(
            gpu,
            renderer,
            label,
            own,
            uniform_size,
            extra_textures,
            Some(constants),
            counter_slots,
        )
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
        Self::build(
            gpu,
            renderer,
            label,
            own,
            uniform_size,
            extra_textures,
            None,
            0,
        )
    }

    fn build(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        own: &str,
        uniform_size: Option<u64>,
        extra_textures: u32,
        per_light_constants: Option<&[(&'static str, f64)]>,
        counter_slots: u32,
    ) -> ResolvePass {
        let per_light = per_light_constants.is_some();
        let tex = crate::common::layouts::fragment_texture;
        let mut entries = vec![tex(0), tex(1)];
        if uniform_size.is_some() {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            });
        }
        entries.extend((0..extra_textures).map(|k| tex(3 + k)));
        if counter_slots > 0 {
            entries.push(wgpu::BindGroupLayoutEntry {
                binding: 15,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            });
        }
        let counters = (counter_slots > 0).then(|| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("pass counters"),
                size: 4 * counter_slots as u64,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &entries,
            });
        let uniform = uniform_size.map(|size| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let module = wgsl::module(&gpu.device, label, &source(own));
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        let additive = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent::REPLACE,
        };
        let target = wgpu::ColorTargetState {
            format: AOV_FORMAT,
            blend: per_light.then_some(additive),
            write_mask: wgpu::ColorWrites::ALL,
        };
        let slots = if per_light {
            super::uniforms::MAX_LIGHTS
        } else {
            1
        };
        let pipelines = (0..slots)
            .map(|k| {
                let own = match per_light_constants {
                    Some(c) => [&[("LIGHT", k as f64)][..], c].concat(),
                    None => Vec::new(),
                };
                let constants = renderer.specialization.with(&own);
                fullscreen_pipeline(
                    &gpu.device,
                    label,
                    &pl,
                    &module,
                    "fs",
                    &constants,
                    &[Some(target.clone()), Some(target.clone())],
                )
            })
            .collect();
        ResolvePass {
            label,
            pipelines,
            per_light,
            layout,
            uniform,
            extra_textures,
            counters,
        }
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

    /// Encodes the pass with `extra` bound at bindings 3, 4, … (as many as declared).
    pub fn encode_with(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
        extra: &[&wgpu::TextureView],
    ) {
        assert_eq!(
            extra.len() as u32,
            self.extra_textures,
            "{}: texture count",
            self.label
        );
        // The harness owns the AOV textures, so the group that reads `surface` is built per frame.
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&renderer.distance_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(targets.surface),
            },
        ];
        if let Some(u) = &self.uniform {
            entries.push(wgpu::BindGroupEntry {
                binding: 2,
                resource: u.as_entire_binding(),
            });
        }
        entries.extend(extra.iter().enumerate().map(|(k, v)| wgpu::BindGroupEntry {
            binding: 3 + k as u32,
            resource: wgpu::BindingResource::TextureView(v),
        }));
        if let Some(c) = &self.counters {
            entries.push(wgpu::BindGroupEntry {
                binding: 15,
                resource: c.as_entire_binding(),
            });
        }
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout: &self.layout,
            entries: &entries,
        });
        let clear = wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        };
        let mut pass = gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some(self.label),
                color_attachments: &[
                    Some(wgpu::RenderPassColorAttachment {
                        view: targets.inscatter,
                        depth_slice: None,
                        resolve_target: None,
                        ops: clear,
                    }),
                    Some(wgpu::RenderPassColorAttachment {
                        view: targets.total,
                        depth_slice: None,
                        resolve_target: None,
                        ops: clear,
                    }),
                ],
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        pass.set_bind_group(1, &bind, &[]);
        let count = if self.per_light {
            renderer.scene.desc.lights.len().min(self.pipelines.len())
        } else {
            1
        };
        for p in &self.pipelines[..count] {
            pass.set_pipeline(p);
            pass.draw(0..3, 0..1);
        }
    }
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
    crate::common::pipeline::Stage::new(label, "vs_fullscreen")
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
