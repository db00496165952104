//! `unshadowed-march`: an example method written outside `methods/`, against the public API only
//! (docs/ADDING_A_METHOD.md). It marches N midpoint steps per pixel and sums the exact
//! single-scattering integrand with visibility 1 — single scattering without volumetric shadows.
//!
//! Algorithm: the shared forward surface pass (`methods::common::renderer::SceneRenderer`, shadow
//! maps off) writes the surface AOV and each pixel's ray length; a full-screen pass
//! (`methods::common::resolve::ResolvePass`, `march.wgsl`) marches the ray.
//! Paper: none — the textbook single-scattering integral, the floor under every method here.
//! Faithful: the integrand is the reference's (same phase function, transmittance, spot falloff,
//! exponential height fog).
//! Modernised: nothing to modernise. Limits: no volumetric or surface shadows (on a scene whose
//! objects cast shadows the shafts are missing: `support` reports the scene as partial); the 1/r²
//! peak near a light in view is under-sampled at low step counts.

use anyhow::Result;
use bytemuck::{Pod, Zeroable};
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Prepared,
    Support, Targets,
};
use methods::common::knobs;
use methods::common::renderer::{SceneRenderer, unsupported};
use methods::common::resolve::{self, ResolvePass};
use methods::common::shadow_maps::ShadowSettings;
use scenes::{FrameState, SceneFeatures};

pub const MARCH_WGSL: &str = include_str!("march.wgsl");

/// This crate's registry: the library's methods and this one (how a research fork would list it).
pub fn registry() -> Vec<&'static dyn Method> {
    let mut all = methods::REGISTRY.to_vec();
    all.push(&UnshadowedMarch);
    all
}

/// `march` in march.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct MarchUniform {
    steps: u32,
    _pad: [u32; 3],
}

/// The method (a description; [`State`] is the prepared instance).
pub struct UnshadowedMarch;

/// The prepared method.
pub struct State {
    renderer: SceneRenderer,
    march: ResolvePass,
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let p = ctx.params;
        // Shadow maps off: surfaces unshadowed, no shadow pass (a 16² placeholder texture).
        let shadows = ShadowSettings {
            size: 16,
            local_budget_mib: 1,
        };
        let renderer =
            SceneRenderer::with_shadow_maps(ctx, shadows, p.knob("pattern_res")?, false)?;
        let size = std::mem::size_of::<MarchUniform>() as u64;
        let march = ResolvePass::new(
            ctx.gpu,
            &renderer,
            "unshadowed march",
            MARCH_WGSL,
            Some(size),
        );
        let uniform = MarchUniform {
            steps: p.knob("steps")?,
            _pad: [0; 3],
        };
        let buffer = march.uniform.as_ref().expect("declared above");
        ctx.gpu
            .queue
            .write_buffer(buffer, 0, bytemuck::bytes_of(&uniform));
        Ok(State { renderer, march })
    }
}

impl Prepared for State {
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        let mut report = self.renderer.begin_frame(gpu, frame, enc, targets);
        self.march.encode(gpu, enc, &self.renderer, targets);
        report.ran("march");
        Ok(report)
    }
}

impl Method for UnshadowedMarch {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "unshadowed-march",
            paper: "example (docs/ADDING_A_METHOD.md): single scattering without shadows",
            summary: "Per-pixel midpoint march of the single-scattering integral, visibility 1",
            baseline: false,
            medium: Medium::Homogeneous,
            readme: include_str!("../README.md"),
            source: include_str!("lib.rs"),
        }
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int("steps", 64, 1..=4096)
                .sweep([16, 256])
                .unit("steps")
                .meaning("midpoint steps per pixel from the eye to the surface or far plane"),
            knobs::pattern_res(256),
        ]
    }

    fn support(&self, scene: &SceneFeatures, _device: wgpu::Features) -> Support {
        if let Some(why) = unsupported(scene) {
            return Support::No(why);
        }
        let mut ignored = Vec::new();
        if scene.volumetric_occluders {
            ignored.push("volumetric shadows".to_string());
        }
        if scene.indirect_single_scattering {
            ignored.push("indirect_single_scattering".to_string());
        }
        if ignored.is_empty() {
            Support::Full
        } else {
            Support::Partial(ignored)
        }
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        ShaderCheck::combinations("unshadowed-march/march", &resolve::source(MARCH_WGSL), &[])
    }

    /// Bound ≈ 1.5× the rel RMSE measured at 48² on lavapipe with 256 steps (0.31; the light is
    /// in view of clear-fog, and its 1/r² peak dominates the error).
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![ConformanceCase::new("clear-fog", 48, Aov::Inscatter, 0.5).knob("steps", 256)]
    }
}
