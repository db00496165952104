//! The method's WGSL and its composition: every pass composes PRELUDE, FULLSCREEN and
//! `blocks.wgsl` (the bindings and records of group 1) before its own source; the per-light
//! surface-shadow pass composes the shared surface pass instead of FULLSCREEN; the total AOV is
//! a plain full-screen sum. A leaf, so the passes and the method description can both use it.

use crate::common::wgsl;

pub const BLOCKS_WGSL: &str = include_str!("blocks.wgsl");
pub const IMPOSTOR_WGSL: &str = include_str!("impostor.wgsl");
pub const LIGHT_WGSL: &str = include_str!("light.wgsl");
pub const GATHER_WGSL: &str = include_str!("gather.wgsl");
pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");
pub const SURFACE_SHADOW_WGSL: &str = include_str!("surface_shadow.wgsl");

/// A pass's composed source: PRELUDE, FULLSCREEN, blocks.wgsl, then its own.
pub fn source(own: &str) -> String {
    let mut shared: Vec<&str> = wgsl::PRELUDE.to_vec();
    shared.push(wgsl::FULLSCREEN);
    shared.push(BLOCKS_WGSL);
    wgsl::compose(&shared, own)
}

/// The per-light surface-shadow pass: PRELUDE, blocks.wgsl, the shared surface pass, its own.
pub fn surface_shadow_source() -> String {
    let mut shared: Vec<&str> = wgsl::PRELUDE.to_vec();
    shared.extend([BLOCKS_WGSL, wgsl::SURFACE_PASS]);
    wgsl::compose(&shared, SURFACE_SHADOW_WGSL)
}

/// The total AOV's full-screen pass (in-scatter + surface), shared with the particle tracers.
pub use crate::common::particles::surfaces::total_source;
