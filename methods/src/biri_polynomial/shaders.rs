//! The method's WGSL and its composition: the kernel library, the passes (surfaces, planes, spot
//! rays, crossing lists) and the resolve. A leaf, so the passes and the method description can
//! both use it.

use crate::common::shadow_volumes::crossing_lists;
use crate::common::{resolve, wgsl};

/// The WGSL kernel library (Λ, Taylor and Chebyshev segment integrals); the including module
/// supplies `biri_phase(cos) -> f32`.
pub const KERNEL_WGSL: &str = include_str!("kernel.wgsl");
pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

/// The composed WGSL of the surface and shadow-plane passes; `early_depth_test`: see
/// [`crossing_lists::passes_wgsl`].
pub fn passes_source(early_depth_test: bool) -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::FULLSCREEN, wgsl::LIGHT_SEGMENTS]].concat(),
        &format!(
            "{}\n{}\n{}\n{}\n{}\n{}\n{}\n{}",
            KERNEL_WGSL,
            crate::common::shadow_volumes::stencil::PLANE_WGSL,
            include_str!("passes.wgsl"),
            include_str!("spot.wgsl"),
            include_str!("spot_rays.wgsl"),
            crossing_lists::WGSL,
            crossing_lists::passes_wgsl(early_depth_test),
            include_str!("pixel.wgsl")
        ),
    )
}

/// The composed WGSL of the last (resolve) pass.
pub fn resolve_source() -> String {
    resolve::source(RESOLVE_WGSL)
}
