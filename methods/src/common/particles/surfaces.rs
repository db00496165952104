//! The surfaces of a particle scene for methods that trace the particle grid
//! (`common::particles::trace`): the shared surface pass drawn into a target of its own, then one
//! additive pass per light removing that light's contribution × (1 − e^(−τ)), τ the exact
//! particle optical depth toward the light (`wgsl/particle_surfaces.wgsl`). A method's resolve
//! then reads that target, writes the in-scatter and the eye-attenuated surface into the
//! harness's `inscatter` and `surface` ([`ParticleSurfaces::resolve_targets`]), and
//! [`ParticleSurfaces::encode_total`] sums them into `total` (three Rgba32Float targets exceed
//! the 32 bytes per sample one render pass may write).

use harness::gpu::color_attachment;
use harness::method::AOV_FORMAT;
use harness::{FrameReport, Gpu, Targets};

use crate::common::layouts::{fragment_texture, view_entry};
use super::trace::{GpuParticleGrid, PARTICLE_TRACE_WGSL};
use crate::common::pipeline::{self, target};
use crate::common::renderer::{SceneRenderer, renderer_limits};
use crate::common::resolve::fullscreen_pipeline;
use super::surface_shadow::SurfaceShadow;
use crate::common::wgsl;

const SURFACES_WGSL: &str = include_str!("particle_surfaces.wgsl");
const TOTAL_WGSL: &str = include_str!("aov_total.wgsl");

pub struct ParticleSurfaces {
    /// The surface pass's output with every light's cloud shadow removed (not yet attenuated by
    /// the particles on the eye leg).
    surface_view: wgpu::TextureView,
    /// Each light's cloud shadow removed (groups: 1 empty, 2 the grid, as in every trace pass).
    shadow: SurfaceShadow,
    total: wgpu::RenderPipeline,
    total_layout: wgpu::BindGroupLayout,
}

/// Why a particle method tracing the grid cannot render a scene, if it cannot: a homogeneous
/// medium, height fog, too many lights for the shared renderer, or no additive Rgba32Float
/// blending (the surface-shadow passes).
pub fn particle_trace_support(
    scene: &scenes::SceneFeatures,
    device: wgpu::Features,
) -> Option<String> {
    if scene.medium != "particles" {
        return Some(
            "homogeneous media are not supported (this method renders particle media only)".into(),
        );
    }
    if scene.height_fog {
        return Some("exponential height fog in the background medium is not supported".into());
    }
    if let Some(why) = renderer_limits(scene) {
        return Some(why);
    }
    (!device.contains(wgpu::Features::FLOAT32_BLENDABLE))
        .then(|| "needs FLOAT32_BLENDABLE (additive surface-shadow passes)".into())
}

/// The composed WGSL of the cloud-shadow pass.
pub fn shadow_source() -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::SURFACE_PASS, PARTICLE_TRACE_WGSL]].concat(),
        SURFACES_WGSL,
    )
}

/// The composed WGSL of the total pass.
pub fn total_source() -> String {
    wgsl::compose(&[wgsl::FULLSCREEN], TOTAL_WGSL)
}

impl ParticleSurfaces {
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, grid: &GpuParticleGrid) -> ParticleSurfaces {
        let device = &gpu.device;
        // The view keeps its texture alive.
        let surface_view = gpu
            .texture_2d(
                "particle surfaces",
                renderer.width,
                renderer.height,
                AOV_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default());
        let empty_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("empty"),
            entries: &[],
        });
        let empty = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("empty"),
            layout: &empty_layout,
            entries: &[],
        });
        let shadow = SurfaceShadow::new(
            device,
            renderer,
            &[(&empty_layout, &empty), (&grid.layout, &grid.bind)],
            renderer.specialization.constants(),
            renderer.scene.desc.lights.len(),
            &shadow_source(),
        );
        let total_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("particle total"),
            entries: &[fragment_texture(0), fragment_texture(1)],
        });
        let total = fullscreen_pipeline(
            device,
            "particle total",
            &pipeline::layout(device, "particle total", &[&total_layout]),
            &wgsl::module(device, "particle total", &total_source()),
            "fs_total",
            &[],
            &[target(AOV_FORMAT, None)],
        );
        ParticleSurfaces {
            surface_view,
            shadow,
            total,
            total_layout,
        }
    }

    /// The surface pass into this target, then each light's cloud shadow removed from it.
    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        targets: &Targets,
        report: &mut FrameReport,
    ) {
        renderer.encode_surface(enc, &self.resolve_targets(targets), report);
        for k in 0..renderer.scene.desc.lights.len() {
            self.shadow.encode(enc, renderer, &self.surface_view, k);
        }
        report.ran("particle-surface-shadows");
    }

    /// The targets a resolve pass (`common::resolve`) gets: it reads this surface target (its
    /// `surface`), writes the in-scatter to the harness's `inscatter` and the eye-attenuated
    /// surface to the harness's `surface` (its `total` location).
    pub fn resolve_targets<'a>(&'a self, targets: &Targets<'a>) -> Targets<'a> {
        Targets {
            inscatter: targets.inscatter,
            surface: &self.surface_view,
            total: targets.surface,
            width: targets.width,
            height: targets.height,
        }
    }

    /// `total` = `inscatter` + `surface` of the harness's targets.
    pub fn encode_total(&self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, targets: &Targets) {
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particle total"),
            layout: &self.total_layout,
            entries: &[
                view_entry(0, targets.inscatter),
                view_entry(1, targets.surface),
            ],
        });
        let mut pass = gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("particle total"),
                color_attachments: &[color_attachment(
                    targets.total,
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                )],
                ..Default::default()
            },
        );
        pass.set_pipeline(&self.total);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
