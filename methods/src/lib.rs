//! scatterbench methods: one folder per technique (`mod.rs`, its WGSL, a README), the shared
//! pieces in `common/`, and the registry — an explicit list in a stable order.

pub mod biri_polynomial;
pub mod biri_shadow_volumes;
pub mod common;
pub mod dobashi_virtual_planes;
pub mod no_scatter;
pub mod polygonal_light_volumes;
pub mod raymarch_brute;
pub mod umenhoffer_particle_blocks;
pub mod wyman_hybrid;

use harness::method::Entry;

/// Every method, in the order `list` and `run --methods all` use.
pub const REGISTRY: &[Entry] = &[
    Entry {
        id: "raymarch-brute",
        make: || Box::new(raymarch_brute::RaymarchBrute::default()),
    },
    Entry {
        id: "dobashi-virtual-planes",
        make: || Box::new(dobashi_virtual_planes::DobashiVirtualPlanes::default()),
    },
    Entry {
        id: "wyman-hybrid",
        make: || Box::new(wyman_hybrid::WymanHybrid::default()),
    },
    Entry {
        id: "biri-shadow-volumes",
        make: || Box::new(biri_shadow_volumes::BiriShadowVolumes::default()),
    },
    Entry {
        id: "biri-polynomial",
        make: || Box::new(biri_polynomial::BiriPolynomial::default()),
    },
    Entry {
        id: "polygonal-light-volumes",
        make: || Box::new(polygonal_light_volumes::PolygonalLightVolumes::default()),
    },
    Entry {
        id: "umenhoffer-particle-blocks",
        make: || Box::new(umenhoffer_particle_blocks::UmenhofferParticleBlocks::default()),
    },
    Entry {
        id: "particle-splat",
        make: || Box::new(umenhoffer_particle_blocks::ParticleSplat::default()),
    },
    Entry {
        id: "no-scatter",
        make: || Box::new(no_scatter::NoScatter::default()),
    },
];

/// A registry entry by id.
pub fn find(id: &str) -> Option<&'static Entry> {
    REGISTRY.iter().find(|e| e.id == id)
}

/// Every composed WGSL module, by name, for validation without a GPU.
pub fn shader_sources() -> Vec<(&'static str, String)> {
    vec![
        ("shadow-pass", common::shadow_maps::shader_source()),
        ("surface-pass", common::renderer::surface_source()),
        (
            "raymarch-brute/march",
            common::resolve::source(raymarch_brute::MARCH_WGSL),
        ),
        ("wyman-hybrid/volumes", wyman_hybrid::volumes_source()),
        (
            "wyman-hybrid/hybrid",
            common::resolve::source(&wyman_hybrid::hybrid_wgsl()),
        ),
        (
            "wyman-hybrid/fprime",
            common::resolve::source(&wyman_hybrid::fprime_wgsl()),
        ),
        (
            "wyman-hybrid/upsample",
            common::resolve::source(wyman_hybrid::UPSAMPLE_WGSL),
        ),
        (
            "dobashi-virtual-planes/planes",
            dobashi_virtual_planes::planes_source(),
        ),
        (
            "dobashi-virtual-planes/far",
            dobashi_virtual_planes::far_source(),
        ),
        (
            "dobashi-virtual-planes/resolve",
            dobashi_virtual_planes::resolve_source(),
        ),
        (
            "dobashi-virtual-planes/probe",
            dobashi_virtual_planes::probe_source(),
        ),
        (
            "no-scatter/resolve",
            common::resolve::source(no_scatter::RESOLVE_WGSL),
        ),
        (
            "biri-shadow-volumes/ldss",
            biri_shadow_volumes::resolve_source(),
        ),
        (
            "biri-shadow-volumes/planes",
            biri_shadow_volumes::planes_source(),
        ),
        (
            "biri-shadow-volumes/indirect",
            biri_shadow_volumes::indirect::source(),
        ),
        (
            "polygonal-light-volumes/volume",
            polygonal_light_volumes::volume_source(),
        ),
        (
            "polygonal-light-volumes/resolve",
            common::resolve::source(&polygonal_light_volumes::resolve_wgsl()),
        ),
        ("biri-polynomial/passes", biri_polynomial::passes_source()),
        ("biri-polynomial/resolve", biri_polynomial::resolve_source()),
    ]
    .into_iter()
    .chain(umenhoffer_particle_blocks::shader_sources())
    .collect()
}
