//! `no-scatter`: the classic OpenGL fog model — surfaces attenuated by e^(−σ_t d) (plus the
//! ambient term), no in-scattered light at all. Not a paper's method: the floor that shows what
//! ignoring single scattering costs, in error, against the methods that compute it.
//!
//! It shares the forward surface pass and shadow maps with the other rasterising methods, so
//! its `surface` AOV is directly comparable; its `inscatter` AOV is zero by construction.
//!
//! Exponential height fog: the exact optical depth of each leg attenuates the surface and
//! ambient terms (`common/wgsl/height_fog.wgsl`).
//!
//! Particle media (issue 32, [`particles`]): the floor of particle scenes — the surface or sky
//! times the exact eye-leg transmittance through the spheres and the background, each light's
//! cloud shadow on surfaces removed with the exact optical depth toward it (as the homogeneous
//! floor keeps e^(−σ_t r) on the light leg); no in-scatter.

pub mod particles;

use anyhow::Result;
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, Medium, Method, MethodInfo, Prepared, Support,
    Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::knobs;
use crate::common::particles::surfaces::particle_trace_support;
use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::{self, ResolvePass};
use crate::common::shadow_maps::ShadowSettings;

pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

/// The method (a description; [`State`] is the prepared instance).
pub struct NoScatter;

/// The prepared method: the shared renderer and the fog resolve, or in particle media the
/// particle floor.
pub struct State {
    renderer: SceneRenderer,
    resolve: ResolvePass,
    particles: Option<particles::ParticleFloor>,
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        // No spot pattern reaches the image without in-scattering: the smallest useful texture.
        let renderer = SceneRenderer::new(ctx, ShadowSettings::from_params(ctx.params)?, 256)?;
        let resolve = ResolvePass::new(ctx.gpu, &renderer, "fog resolve", RESOLVE_WGSL, None);
        let particles = (ctx.scene.medium().particles().is_some())
            .then(|| particles::ParticleFloor::new(ctx, &renderer))
            .transpose()?;
        Ok(State {
            renderer,
            resolve,
            particles,
        })
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
        if let Some(floor) = &self.particles {
            return Ok(floor.render(gpu, &mut self.renderer, frame, targets, enc));
        }
        let mut report = self.renderer.begin_frame(gpu, frame, enc, targets);
        self.resolve.encode(gpu, enc, &self.renderer, targets);
        report.ran("fog-resolve");
        Ok(report)
    }
}

impl Method for NoScatter {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            baseline "no-scatter",
            Medium::Both,
            "baseline (fixed-function fog: attenuation only)",
            "Attenuated surfaces, no in-scattering",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            knobs::shadow_map(1024).meaning("shadow-map resolution per face for surface shadows"),
            knobs::local_shadow_budget(),
        ]
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        if scene.medium == "particles" {
            return match particle_trace_support(scene, device) {
                Some(why) => Support::No(why),
                None => Support::Full,
            };
        }
        match unsupported(scene) {
            Some(why) => Support::No(why),
            None => Support::Full,
        }
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        [
            ShaderCheck::combinations("no-scatter/resolve", &resolve::source(RESOLVE_WGSL), &[]),
            ShaderCheck::combinations(
                "no-scatter/particles",
                &resolve::source(&particles::PARTICLES_COMPOSED),
                &[],
            ),
        ]
        .concat()
    }

    /// The surface AOV only (the in-scatter AOV is zero by construction); bound ≈ 1.5× the
    /// rel RMSE measured at 48² on lavapipe (0.051: shadow-map texels at the shadow's edge).
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![ConformanceCase::new("sphere-point", 48, Aov::Surface, 0.08)]
    }

    /// The floor misses all in-scatter by design, so the total's error is the scene's in-scatter
    /// and declares nothing — except where nothing scatters: zero-density particles, where it
    /// must be exact (measured 3.9e-8 at 64²).
    fn stress_bound(&self, case: &str) -> Option<f64> {
        (case == "particles-zero-density").then_some(1e-3)
    }
}
