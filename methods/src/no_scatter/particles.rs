//! no-scatter in particle media (issue 32): the floor of particle scenes. Attenuation only —
//! the surface (or the sky) times the eye leg's exact transmittance through the particles
//! (`common::particles::trace`) and the background medium; the cloud's in-scatter is zero. As in
//! homogeneous media, where the surface pass attenuates each light's leg by e^(−σ_t r), the
//! medium's attenuation of the light reaching surfaces is kept: each light's cloud shadow on
//! the surfaces is removed with the exact optical depth toward it (`common::particles::surfaces`).

use anyhow::Result;
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, Targets};
use scenes::FrameState;

use crate::common::particles::surfaces::ParticleSurfaces;
use crate::common::particles::trace::{self, GpuParticleGrid, ParticleGrid};
use crate::common::renderer::SceneRenderer;
use crate::common::resolve::ResolvePass;

pub const PARTICLES_WGSL: &str = include_str!("particles.wgsl");

/// particles.wgsl after the particle trace and particle_resolve.wgsl (the resolve pass adds PRELUDE and FULLSCREEN).
pub static PARTICLES_COMPOSED: std::sync::LazyLock<String> =
    std::sync::LazyLock::new(|| trace::resolve_source(PARTICLES_WGSL));

/// The grid, the surfaces with their cloud shadows and the attenuating resolve.
pub struct ParticleFloor {
    grid: GpuParticleGrid,
    surfaces: ParticleSurfaces,
    resolve: ResolvePass,
}

impl ParticleFloor {
    pub fn new(ctx: &PrepareContext, renderer: &SceneRenderer) -> Result<ParticleFloor> {
        let medium = ctx.scene.medium();
        let particles = (medium.particles())
            .ok_or_else(|| anyhow::anyhow!("no-scatter's particle floor needs particle media"))?;
        let grid = GpuParticleGrid::new(ctx.gpu, &ParticleGrid::build(particles))?;
        let surfaces = ParticleSurfaces::new(ctx.gpu, renderer, &grid);
        let resolve = ResolvePass::with_group(
            ctx.gpu,
            renderer,
            "particle floor",
            PARTICLES_COMPOSED.as_str(),
            &[],
            &grid.layout,
        );
        Ok(ParticleFloor {
            grid,
            surfaces,
            resolve,
        })
    }

    /// Shadow maps, surfaces and their cloud shadows, the attenuating resolve, the total.
    pub fn render(
        &self,
        gpu: &Gpu,
        renderer: &mut SceneRenderer,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> FrameReport {
        let mut report = renderer.start_frame(gpu, frame);
        renderer.encode_shadows(enc, &mut report);
        self.surfaces.encode(enc, renderer, targets, &mut report);
        let resolve_targets = self.surfaces.resolve_targets(targets);
        (self.resolve).encode_with_group(gpu, enc, renderer, &resolve_targets, &self.grid.bind);
        report.ran("fog-resolve");
        self.surfaces.encode_total(gpu, enc, targets);
        report.ran("total");
        report
    }
}
