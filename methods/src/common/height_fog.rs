//! Exponential height fog and the methods that cannot integrate it (ARCHITECTURE §1): a method
//! whose closed form assumes a constant σ refuses a height-fog scene by capability, naming what
//! assumes it. The methods that integrate it compose `wgsl/height_fog.wgsl` (through
//! `wgsl::MEDIUM`) and need nothing here.

use harness::Support;
use scenes::SceneFeatures;

/// `Some(Support::No("exponential height fog: <assumes>"))` on a scene with height fog, None
/// otherwise. `assumes`: what in the method takes σ to be constant.
pub fn constant_sigma_only(scene: &SceneFeatures, assumes: &str) -> Option<Support> {
    scene
        .height_fog
        .then(|| Support::No(format!("exponential height fog: {assumes}")))
}
