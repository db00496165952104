//! The compute skeleton both epipolar methods hang their passes on: one bind group per light
//! over scratch buffers the lights share (lights run in turn), every entry point compiled from one
//! module under one layout, and the frame's opening and closing around the method's own passes.
//!
//! Group 1 of every compute pass has one layout (the methods' WGSL declares it so):
//! binding 0 the light's uniform; 1..=n the method's storage buffers; n + 1 the camera
//! distance texture; n + 2 the in-scatter accumulator; n + 3 the published `rgba32float`
//! texture that [`super::published`]'s resolve reads.

use harness::gpu::{PhaseTimer, phases};
use harness::method::ShaderCheck;
use harness::{FrameReport, Gpu, Targets};
use scenes::FrameState;

use super::published::{PUBLISHED_RESOLVE, published_texture, scratch_buffer};
use crate::common::layouts::{
    buffer_entry, float_texture, rgba32f_storage_write, storage_buffer, uniform_buffer, view_entry,
};
use crate::common::pipeline::{self, ComputeStage};
use crate::common::renderer::SceneRenderer;
use crate::common::resolve::{self, ResolvePass};
use crate::common::wgsl;

/// Pipeline constants: `(override name, value)`.
pub type Constants = [(&'static str, f64)];

/// Group 1's layout with `storage` method buffers at bindings 1..=storage.
fn group_layout(gpu: &Gpu, label: &str, storage: u32) -> wgpu::BindGroupLayout {
    let cs = wgpu::ShaderStages::COMPUTE;
    let mut entries = vec![uniform_buffer(0, cs)];
    entries.extend((1..=storage).map(|b| storage_buffer(b, cs, false)));
    entries.push(float_texture(storage + 1, cs));
    entries.push(storage_buffer(storage + 2, cs, false));
    entries.push(rgba32f_storage_write(storage + 3, cs));
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

/// The accumulator every light adds its in-scatter to (`vec4<f32>` per pixel) and the texture
/// the publish pass writes it to.
pub struct Published {
    pub accum: wgpu::Buffer,
    pub view: wgpu::TextureView,
}

impl Published {
    pub fn new(gpu: &Gpu, label: &str, width: u32, height: u32) -> Published {
        let pixels = width as u64 * height as u64;
        let storage = wgpu::BufferUsages::STORAGE;
        Published {
            accum: scratch_buffer(gpu, &format!("{label} accumulator"), 16 * pixels, storage),
            view: published_texture(gpu, &format!("{label} in-scatter"), width, height),
        }
    }
}

/// A light's uniform buffer of `bytes` bytes, written each frame.
pub fn light_uniform(gpu: &Gpu, label: &str, bytes: usize) -> wgpu::Buffer {
    let usage = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
    scratch_buffer(gpu, label, bytes as u64, usage)
}

/// The method's compute entry points, compiled from one module under one layout (group 0 the
/// frame's, group 1 [`group_layout`]'s) with the scene's constants, the method's and each
/// pipeline's own.
pub struct Compiler<'a> {
    pub gpu: &'a Gpu,
    pub renderer: &'a SceneRenderer,
    group: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    constants: Vec<(&'static str, f64)>,
}

impl<'a> Compiler<'a> {
    /// `storage` as in [`group_layout`]; `source` the composed compute WGSL; `constants` the
    /// method's, for every pipeline.
    pub fn new(
        gpu: &'a Gpu,
        renderer: &'a SceneRenderer,
        label: &str,
        storage: u32,
        source: &str,
        constants: Vec<(&'static str, f64)>,
    ) -> Compiler<'a> {
        let group = group_layout(gpu, label, storage);
        let layout = pipeline::layout(&gpu.device, label, &[&renderer.frame_layout, &group]);
        let module = wgsl::module(&gpu.device, label, source);
        Compiler { gpu, renderer, group, layout, module, constants }
    }

    pub fn pipeline(&self, entry: &str, own: &Constants) -> wgpu::ComputePipeline {
        let constants = self.renderer.specialization.with(&[&self.constants[..], own].concat());
        let stage = ComputeStage::new(entry, entry);
        stage.build(&self.gpu.device, &self.layout, &self.module, &constants)
    }

    /// A light's group 1: `uniform`, the method's `storage` buffers in binding order, the
    /// distance texture and `published`'s accumulator and texture.
    pub fn light_group(
        &self,
        label: &str,
        uniform: &wgpu::Buffer,
        storage: &[&wgpu::Buffer],
        published: &Published,
    ) -> wgpu::BindGroup {
        let n = storage.len() as u32;
        let mut entries = vec![buffer_entry(0, uniform)];
        entries.extend(storage.iter().zip(1..).map(|(buf, b)| buffer_entry(b, buf)));
        entries.push(view_entry(n + 1, &self.renderer.distance_view));
        entries.push(buffer_entry(n + 2, &published.accum));
        entries.push(view_entry(n + 3, &published.view));
        self.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &self.group,
            entries: &entries,
        })
    }
}

/// The publish pass (the accumulator to the published texture; any light's group 1 binds both),
/// after every light's passes.
pub fn encode_publish(
    renderer: &SceneRenderer,
    gpu: &Gpu,
    enc: &mut wgpu::CommandEncoder,
    group1: Option<&wgpu::BindGroup>,
    publish: &wgpu::ComputePipeline,
) {
    let Some(group1) = group1 else { return };
    let (w, h) = (renderer.width.div_ceil(8), renderer.height.div_ceil(8));
    let mut pass = renderer.compute_pass(gpu, enc, "epipolar publish", group1);
    pass.set_pipeline(publish);
    pass.dispatch_workgroups(w, h, 1);
}

/// The frame around a method's passes: the phase timer and the resolve of the published
/// in-scatter.
pub struct Frame {
    pub timer: Option<PhaseTimer>,
    resolve: ResolvePass,
}

impl Frame {
    /// `phases_per_light`: the phases a light's passes mark (the timer's slots).
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        label: &'static str,
        phases_per_light: u32,
    ) -> Frame {
        let lights = renderer.scene.desc.lights.len() as u32;
        Frame {
            timer: PhaseTimer::new(gpu, phases_per_light * lights.max(1) + 2),
            resolve: ResolvePass::with_textures(gpu, renderer, label, PUBLISHED_RESOLVE, None, 1),
        }
    }

    /// The frame's opening: the renderer's frame state, then (phase "surfaces") the shadow maps
    /// and the surface pass. Write the lights' uniforms before or after; the queue applies them
    /// first.
    pub fn open(
        &mut self,
        renderer: &mut SceneRenderer,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> FrameReport {
        let mut report = renderer.start_frame(gpu, frame);
        phases::mark(&mut self.timer, enc, "surfaces");
        renderer.encode_shadows_and_surface(enc, targets, &mut report);
        report
    }

    /// What the method's passes encode with.
    pub fn encoding<'a>(&'a mut self, gpu: &'a Gpu, renderer: &'a SceneRenderer) -> Encoding<'a> {
        Encoding { gpu, renderer, timer: &mut self.timer }
    }

    /// The frame's closing (phase "resolve"): the published in-scatter added to the surfaces.
    pub fn close(
        &mut self,
        renderer: &SceneRenderer,
        published: &Published,
        gpu: &Gpu,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
        report: &mut FrameReport,
    ) {
        phases::mark(&mut self.timer, enc, "resolve");
        self.resolve.encode_with(gpu, enc, renderer, targets, &[&published.view]);
        report.ran("resolve");
        phases::finish(&mut self.timer, enc);
    }
}

/// What a method's per-light passes encode with: the device, the renderer (its frame group and
/// distance texture) and the phase timer.
pub struct Encoding<'a> {
    pub gpu: &'a Gpu,
    pub renderer: &'a SceneRenderer,
    pub timer: &'a mut Option<PhaseTimer>,
}

/// The method's naga checks: its compute module over every combination of `axes`, and the
/// published resolve.
pub fn shader_checks(
    id: &str,
    compute: &str,
    axes: &[(&'static str, &[f64])],
    resolve_wgsl: &str,
) -> Vec<ShaderCheck> {
    let resolve = resolve::source(resolve_wgsl);
    let mut checks = ShaderCheck::combinations(&format!("{id}/compute"), compute, axes);
    checks.extend(ShaderCheck::combinations(&format!("{id}/resolve"), &resolve, &[]));
    checks
}
