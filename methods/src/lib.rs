//! scatterbench methods: one folder per technique (`mod.rs`, its WGSL, a README), the shared
//! pieces in `common/`, and the registry — one ordered list of method descriptions.
//!
//! Adding a method: a folder implementing `harness::Method` and one line in [`REGISTRY`]
//! (docs/ADDING_A_METHOD.md). The conformance checks ([`conformance::check_registry`], run over
//! the registry by tests/conformance.rs) cover every entry. Out of the tree, a crate passes its
//! own registry to `scatterbench::main_with` and to the same checks (examples/external-method).

pub mod biri_polynomial;
pub mod biri_shadow_volumes;
pub mod common;
pub mod conformance;
pub mod dobashi_virtual_planes;
pub mod epipolar_minmax;
pub mod froxel_fog;
pub mod no_scatter;
pub mod particle_march;
pub mod polygonal_light_volumes;
pub mod prefiltered_single_scattering;
pub mod raymarch_brute;
pub mod umenhoffer_particle_blocks;
pub mod wyman_hybrid;

use harness::Method;

/// Every method, in the order `list` and `run --methods all` use. The id is `info().id`.
pub static REGISTRY: &[&dyn Method] = &[
    &raymarch_brute::RaymarchBrute,
    &particle_march::ParticleMarch,
    &froxel_fog::FroxelFog,
    &epipolar_minmax::EpipolarMinMax,
    &dobashi_virtual_planes::DobashiVirtualPlanes,
    &wyman_hybrid::WymanHybrid,
    &biri_shadow_volumes::BiriShadowVolumes,
    &biri_polynomial::BiriPolynomial,
    &polygonal_light_volumes::PolygonalLightVolumes,
    &prefiltered_single_scattering::PrefilteredSingleScattering,
    &umenhoffer_particle_blocks::UmenhofferParticleBlocks,
    &umenhoffer_particle_blocks::ParticleSplat,
    &no_scatter::NoScatter,
];

/// A registered method by id.
pub fn find(id: &str) -> Option<&'static dyn Method> {
    harness::method::find(REGISTRY, id)
}

/// Shader modules shared by every rasterising method (the shadow-map and surface passes),
/// validated once by the conformance test beside each method's own `shaders()`.
pub fn common_shaders() -> Vec<harness::ShaderCheck> {
    [
        harness::ShaderCheck::combinations(
            "common/shadow-pass",
            &common::shadow_maps::shader_source(),
            &[],
        ),
        harness::ShaderCheck::combinations(
            "common/surface-pass",
            &common::renderer::surface_source(),
            &[("SURFACE_LIGHT", &[0.0, 3.0])],
        ),
    ]
    .concat()
}
