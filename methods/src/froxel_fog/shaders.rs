//! The method's WGSL and its composition: the volume passes (inject, temporal, integrate), the
//! apply pass, and for particle media the voxelise / extinction passes, the per-light cloud
//! shadow on surfaces and the particle surface pass. A leaf, so the passes and the method description can both use it.

use crate::common::{resolve, wgsl};

pub const GRID_WGSL: &str = include_str!("grid.wgsl");
pub const VOLUME_WGSL: &str = include_str!("volume.wgsl");
pub const SLICE_QUADRATURE_WGSL: &str = include_str!("slice_quadrature.wgsl");
pub const TEMPORAL_WGSL: &str = include_str!("temporal.wgsl");
pub const SURFACE_BOUND_WGSL: &str = include_str!("surface_bound.wgsl");
pub const APPLY_WGSL: &str = include_str!("apply.wgsl");
pub const LOOKUP_WGSL: &str = include_str!("lookup.wgsl");
pub const EXTINCTION_WGSL: &str = include_str!("extinction.wgsl");
pub const PARTICLES_WGSL: &str = include_str!("particles.wgsl");
pub const PARTICLE_SURFACE_WGSL: &str = include_str!("particle_surface.wgsl");
pub const PARTICLE_SHADOW_WGSL: &str = include_str!("particle_shadow.wgsl");

/// The volume passes' composed WGSL (inject, temporal and integrate entry points).
pub fn volume_source() -> String {
    let shared = [
        GRID_WGSL,
        EXTINCTION_WGSL,
        TEMPORAL_WGSL,
        SURFACE_BOUND_WGSL,
        SLICE_QUADRATURE_WGSL,
    ];
    wgsl::compose(&[wgsl::PRELUDE, &shared].concat(), VOLUME_WGSL)
}

/// The apply pass's own WGSL (composed by `common::resolve`).
pub fn apply_wgsl() -> String {
    wgsl::compose(&[GRID_WGSL, LOOKUP_WGSL], APPLY_WGSL)
}

/// The apply pass's composed WGSL.
pub fn apply_source() -> String {
    resolve::source(&apply_wgsl())
}

/// The particle passes' composed WGSL (voxelise and extinction entry points).
pub fn particles_source() -> String {
    let shared = [GRID_WGSL, EXTINCTION_WGSL];
    wgsl::compose(&[wgsl::PRELUDE, &shared].concat(), PARTICLES_WGSL)
}

/// The particle surface pass's composed WGSL.
pub fn particle_surface_source() -> String {
    let shared = [GRID_WGSL, LOOKUP_WGSL, EXTINCTION_WGSL];
    resolve::source(&wgsl::compose(&shared, PARTICLE_SURFACE_WGSL))
}

/// The per-light cloud-shadow pass over the surfaces (`common::particles::surface_shadow`).
pub fn particle_shadow_source() -> String {
    let mut shared: Vec<&str> = wgsl::PRELUDE.to_vec();
    shared.extend([EXTINCTION_WGSL, wgsl::SURFACE_PASS]);
    wgsl::compose(&shared, PARTICLE_SHADOW_WGSL)
}
