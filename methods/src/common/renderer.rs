//! `SceneRenderer`: what every rasterising method starts from — the scene's buffers, the frame
//! uniforms (camera, medium, lights), shadow maps, pattern textures, the frame bind group
//! (group 0 in `wgsl/frame_bindings.wgsl`) and the forward surface pass that writes the
//! `surface` AOV and a per-pixel ray-distance texture (−1 where the ray hits nothing).
//!
//! Pass-level skipping (ARCHITECTURE §2.4): without shadow casters the shadow-map passes are skipped
//! (and lights carry no shadow map) unless `no_skip`.

use harness::gpu::{PassCounter, color_attachment, depth_attachment};
use harness::method::{AOV_FORMAT, PrepareContext};
use harness::{FrameReport, Gpu, Targets};
use scenes::{FrameState, Scene};

use super::gpu_scene::{GpuScene, mesh_pipeline};
use super::layouts::{
    buffer_entry, filterable_texture_array, float_texture_array, storage_buffer, uniform_buffer,
    view_entry,
};
use super::patterns::PatternTextures;
use super::pipeline;
use super::shadow_maps::{ShadowMaps, ShadowSettings};
use super::specialize::Specialization;
use super::uniforms::{
    CameraUniform, LightUniform, LightsUniform, MAX_LIGHTS, MediumUniform, lights_bytes,
};
use super::wgsl;

pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// The ray distance where the ray hits nothing.
const NO_HIT: wgpu::Color = wgpu::Color {
    r: -1.0,
    g: 0.0,
    b: 0.0,
    a: 0.0,
};

pub struct SceneRenderer {
    pub scene: Scene,
    pub gpu_scene: GpuScene,
    pub shadows: ShadowMaps,
    pub patterns: PatternTextures,
    pub camera: wgpu::Buffer,
    pub medium: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    pub frame_layout: wgpu::BindGroupLayout,
    pub frame_bind: wgpu::BindGroup,
    surface_pipeline: wgpu::RenderPipeline,
    /// The surface pass's depth (Depth32Float): later passes over the visible surfaces test against it.
    pub depth_view: wgpu::TextureView,
    pub distance: wgpu::Texture,
    pub distance_view: wgpu::TextureView,
    /// Whether shadow maps are rendered this run.
    pub shadows_on: bool,
    /// False when the method takes surface shadows from stencil volumes instead.
    shadow_maps_requested: bool,
    pub width: u32,
    pub height: u32,
    /// The scene's baked pipeline constants (light count and kinds, phase function).
    pub specialization: Specialization,
    /// Begins this renderer's passes with pipeline statistics counted.
    pub passes: PassCounter,
}

/// Why a homogeneous-medium method built on the shared renderer cannot render a scene, if it
/// cannot: too many lights for the uniforms, or a particle medium (which these methods do not
/// model). Every such method's `support` calls this, so particle scenes are refused by all.
pub fn unsupported(features: &scenes::SceneFeatures) -> Option<String> {
    if features.medium == "particles" {
        return Some(
            "particle media are not supported (this method models a homogeneous medium only)"
                .into(),
        );
    }
    renderer_limits(features)
}

/// The support answer of a homogeneous-medium method built on the shared renderer: refused where
/// [`unsupported`] says so, or (with `needs_blend = Some(why)`) on a device that cannot blend
/// Rgba32Float targets; partial on scenes with indirect single scattering, which these methods
/// ignore; full otherwise.
pub fn homogeneous_support(
    scene: &scenes::SceneFeatures,
    device: wgpu::Features,
    needs_blend: Option<&str>,
) -> harness::Support {
    use harness::Support;
    if let Some(why) = unsupported(scene) {
        return Support::No(why);
    }
    if let Some(why) = needs_blend
        && !device.contains(wgpu::Features::FLOAT32_BLENDABLE)
    {
        return Support::No(why.into());
    }
    if scene.indirect_single_scattering {
        return Support::Partial(vec!["indirect_single_scattering".into()]);
    }
    Support::Full
}

/// What the shared renderer itself cannot handle (any medium): more lights than its light
/// uniform has slots for.
pub fn renderer_limits(features: &scenes::SceneFeatures) -> Option<String> {
    (features.lights > MAX_LIGHTS).then(|| {
        format!(
            "{} lights; the shared renderer's light uniform has {MAX_LIGHTS} slots (64 KiB, \
             the uniform binding size every adapter supports)",
            features.lights
        )
    })
}

impl SceneRenderer {
    /// `shadows`: the shadow-map knobs (`ShadowSettings::from_params`).
    pub fn new(
        ctx: &PrepareContext,
        shadows: ShadowSettings,
        pattern_size: u32,
    ) -> anyhow::Result<SceneRenderer> {
        Self::with_shadow_maps(ctx, shadows, pattern_size, true)
    }

    /// `shadow_maps = false`: surfaces are shaded unshadowed (for methods whose surface shadows
    /// come from stencil shadow volumes, `common::shadow_volumes::stencil_surfaces`) and no
    /// shadow map is drawn.
    pub fn with_shadow_maps(
        ctx: &PrepareContext,
        shadow_settings: ShadowSettings,
        pattern_size: u32,
        shadow_maps: bool,
    ) -> anyhow::Result<SceneRenderer> {
        let gpu = ctx.gpu;
        let scene = ctx.scene.clone();
        if let Some(why) = renderer_limits(&scene.features()) {
            anyhow::bail!(why);
        }
        let gpu_scene = GpuScene::new(gpu, &scene);
        let shadows_on = shadow_maps && (ctx.no_skip || gpu_scene.has_casters());
        let frame0 = scene.frame(0);
        let shadows =
            ShadowMaps::new(gpu, &frame0.lights, shadow_settings, shadows_on, &gpu_scene)?;
        let patterns = PatternTextures::new(gpu, &scene.desc.lights, pattern_size);
        let uniform = |label: &str, size: usize| {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let camera = uniform("camera", std::mem::size_of::<CameraUniform>());
        let medium = uniform("medium", std::mem::size_of::<MediumUniform>());
        let lights = uniform("lights", std::mem::size_of::<LightsUniform>());
        let frame_layout = frame_layout(&gpu.device);
        let frame_bind = frame_bind_group(
            &gpu.device,
            &frame_layout,
            [&camera, &medium, &lights, &gpu_scene.objects],
            &shadows.view,
            &patterns.view,
        );
        let specialization = Specialization::of(&scene);
        let surface_pipeline = surface_pipeline(&gpu.device, &frame_layout, &specialization);
        let (depth_view, distance) = camera_targets(gpu, ctx.width, ctx.height);
        let distance_view = distance.create_view(&Default::default());
        gpu.queue.write_buffer(
            &medium,
            0,
            // Particle scenes: the background medium (the particles are the method's own business).
            bytemuck::bytes_of(&MediumUniform::new(&scene.medium().background())),
        );
        Ok(SceneRenderer {
            scene,
            gpu_scene,
            shadows,
            patterns,
            camera,
            medium,
            lights,
            frame_layout,
            frame_bind,
            surface_pipeline,
            depth_view,
            distance,
            distance_view,
            shadows_on,
            shadow_maps_requested: shadow_maps,
            width: ctx.width,
            height: ctx.height,
            specialization,
            passes: gpu.pass_counter(),
        })
    }

    /// Writes this frame's camera, lights, object transforms and shadow faces.
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState) {
        gpu.queue.write_buffer(
            &self.camera,
            0,
            bytemuck::bytes_of(&CameraUniform::new(&frame.camera, self.width, self.height)),
        );
        self.gpu_scene.update(gpu, &self.scene, frame);
        self.shadows.update(gpu, &self.scene, frame);
        let count = [frame.lights.len() as u32, 0, 0, 0];
        let lights: Vec<LightUniform> = (frame.lights.iter().enumerate().take(MAX_LIGHTS))
            .map(|(k, l)| LightUniform::new(l, self.patterns.layers[k], self.shadows.slots.get(k)))
            .collect();
        gpu.queue
            .write_buffer(&self.lights, 0, &lights_bytes(count, &lights));
    }

    /// How every rasterising method's frame starts: this frame's uniforms, then the shadow-map
    /// and surface passes. Returns the frame's report so far.
    pub fn begin_frame(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        enc: &mut wgpu::CommandEncoder,
        targets: &Targets,
    ) -> FrameReport {
        let mut report = self.start_frame(gpu, frame);
        self.encode_shadows_and_surface(enc, targets, &mut report);
        report
    }

    /// The shadow-map passes, then the surface pass that reads them.
    pub fn encode_shadows_and_surface(
        &self,
        enc: &mut wgpu::CommandEncoder,
        targets: &Targets,
        report: &mut FrameReport,
    ) {
        self.encode_shadows(enc, report);
        self.encode_surface(enc, targets, report);
    }

    /// A counted compute pass with the frame group (0) and a method's `group1` bound: how every
    /// compute stage of a method built on this renderer starts.
    pub fn compute_pass<'e>(
        &self,
        gpu: &Gpu,
        enc: &'e mut wgpu::CommandEncoder,
        label: &str,
        group1: &wgpu::BindGroup,
    ) -> harness::gpu::Counted<wgpu::ComputePass<'e>> {
        let mut pass = gpu.compute_pass(
            enc,
            &wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            },
        );
        pass.set_bind_group(0, &self.frame_bind, &[]);
        pass.set_bind_group(1, group1, &[]);
        pass
    }

    /// How a method that encodes passes between the renderer's starts its frame: this frame's
    /// uniforms written, an empty report.
    pub fn start_frame(&mut self, gpu: &Gpu, frame: &FrameState) -> FrameReport {
        self.update(gpu, frame);
        FrameReport::default()
    }

    /// The shadow-map passes, or their skip record.
    pub fn encode_shadows(&self, enc: &mut wgpu::CommandEncoder, report: &mut FrameReport) {
        if self.shadows_on {
            self.shadows.encode(enc, &self.gpu_scene, report);
            report.ran("shadow-maps");
        } else {
            let why = if self.shadow_maps_requested {
                "no object casts a volumetric shadow"
            } else {
                "surface shadows come from stencil shadow volumes"
            };
            report.skip("shadow-maps", why);
        }
    }

    /// The surface pass: writes `targets.surface` and the ray-distance texture.
    pub fn encode_surface(
        &self,
        enc: &mut wgpu::CommandEncoder,
        targets: &Targets,
        report: &mut FrameReport,
    ) {
        let mut pass = self.passes.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("surface"),
                color_attachments: &[
                    color_attachment(
                        targets.surface,
                        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    ),
                    color_attachment(&self.distance_view, wgpu::LoadOp::Clear(NO_HIT)),
                ],
                depth_stencil_attachment: Some(depth_attachment(
                    &self.depth_view,
                    wgpu::LoadOp::Clear(1.0),
                )),
                ..Default::default()
            },
        );
        pass.set_pipeline(&self.surface_pipeline);
        pass.set_bind_group(0, &self.frame_bind, &[]);
        self.gpu_scene.draw(&mut pass);
        report.ran("surface");
    }
}

pub fn surface_source() -> String {
    wgsl::compose(wgsl::PRELUDE, wgsl::SURFACE_PASS)
}

/// Group 0 (`frame_layout`): the camera, medium, lights and objects buffers, the shadow maps,
/// the spot patterns and a linear clamping sampler.
fn frame_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffers: [&wgpu::Buffer; 4],
    shadows: &wgpu::TextureView,
    patterns: &wgpu::TextureView,
) -> wgpu::BindGroup {
    let [camera, medium, lights, objects] = buffers;
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("frame"),
        layout,
        entries: &[
            buffer_entry(0, camera),
            buffer_entry(1, medium),
            buffer_entry(2, lights),
            buffer_entry(3, objects),
            view_entry(4, shadows),
            view_entry(5, patterns),
            wgpu::BindGroupEntry {
                binding: 6,
                resource: wgpu::BindingResource::Sampler(&linear_clamp(device)),
            },
        ],
    })
}

/// The surface pass's depth (as a view: later passes test against it) and the ray-distance
/// texture, `width` × `height`.
fn camera_targets(gpu: &Gpu, width: u32, height: u32) -> (wgpu::TextureView, wgpu::Texture) {
    let depth = gpu.texture_2d(
        "camera depth",
        width,
        height,
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let distance = gpu.texture_2d(
        "ray distance",
        width,
        height,
        DISTANCE_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    );
    (depth.create_view(&Default::default()), distance)
}

/// The forward surface pass writing the `surface` AOV and the ray distance, with the scene's
/// constants.
fn surface_pipeline(
    device: &wgpu::Device,
    frame_layout: &wgpu::BindGroupLayout,
    specialization: &Specialization,
) -> wgpu::RenderPipeline {
    let module = wgsl::module(device, "surface pass", &surface_source());
    let pl = pipeline::layout(device, "surface", &[frame_layout]);
    mesh_pipeline(
        device,
        "surface",
        &pl,
        &module,
        &[Some(AOV_FORMAT.into()), Some(DISTANCE_FORMAT.into())],
        specialization.constants(),
    )
}

/// Group 0 of every pass: camera, medium, lights, objects, shadow maps, spot patterns, sampler.
fn frame_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let all = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
    let textures = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("frame"),
        entries: &[
            uniform_buffer(0, all),
            uniform_buffer(1, all),
            uniform_buffer(2, all),
            storage_buffer(3, all, true),
            float_texture_array(4, textures),
            filterable_texture_array(5, textures),
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: all,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

fn linear_clamp(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("linear clamp"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}
