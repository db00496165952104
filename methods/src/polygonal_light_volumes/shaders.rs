//! The method's WGSL and its composition: the light-volume pass and the resolve, both built on
//! the integral (`integral.wgsl`) over Biri et al.'s L_dss (`common::wgsl::LDSS`). A leaf, so the
//! passes and the method description can both use it.

use crate::common::wgsl;

pub const INTEGRAL_WGSL: &str = include_str!("integral.wgsl");
pub const VOLUME_WGSL: &str = include_str!("volume.wgsl");
pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

/// The composed WGSL of the light-volume pass.
pub fn volume_source() -> String {
    wgsl::compose(
        wgsl::PRELUDE,
        &format!("{}\n{INTEGRAL_WGSL}\n{VOLUME_WGSL}", wgsl::LDSS),
    )
}

/// The resolve's own WGSL (composed by `common::resolve::source`).
pub fn resolve_wgsl() -> String {
    format!("{}\n{INTEGRAL_WGSL}\n{RESOLVE_WGSL}", wgsl::LDSS)
}
