//! The method's WGSL and its composition: the shadow-volume pass, and the full-screen passes
//! built on the shared airlight module (hybrid march, F' table) or alone (upsample). A leaf, so
//! the passes and the method description can both use it.

use crate::common::wgsl;

pub const VOLUMES_WGSL: &str = include_str!("volumes.wgsl");
pub const AIRLIGHT_WGSL: &str = include_str!("airlight.wgsl");
pub const HYBRID_WGSL: &str = include_str!("hybrid.wgsl");
pub const FPRIME_WGSL: &str = include_str!("fprime.wgsl");
pub const UPSAMPLE_WGSL: &str = include_str!("upsample.wgsl");

/// The hybrid resolve's own WGSL: the shared airlight module, then the pass.
pub fn hybrid_wgsl() -> String {
    format!("{AIRLIGHT_WGSL}\n{HYBRID_WGSL}")
}

/// The F' table pass's own WGSL.
pub fn fprime_wgsl() -> String {
    format!("{AIRLIGHT_WGSL}\n{FPRIME_WGSL}")
}

/// The composed WGSL of the shadow-volume pass.
pub fn volumes_source() -> String {
    wgsl::compose(wgsl::PRELUDE, VOLUMES_WGSL)
}
