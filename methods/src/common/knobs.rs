//! Knobs several methods share, declared once: the shadow-map and pattern-texture resolutions.
//! A method adds them to its `knobs()` with its own default and sweep.

use harness::Knob;

/// Largest 2D texture side every wgpu adapter supports (`Limits::default().max_texture_dimension_2d`).
pub const MAX_TEXTURE_SIDE: i64 = 8192;

/// `shadow_map`: texels per side of each shadow-map face (16 … 8192).
pub fn shadow_map(default: i64) -> Knob {
    Knob::int("shadow_map", default, 16..=MAX_TEXTURE_SIDE)
        .unit("texels")
        .meaning("shadow-map resolution per face")
}

/// `pattern_res`: texels per side of each spot-light pattern layer (1 … 8192).
pub fn pattern_res(default: i64) -> Knob {
    Knob::int("pattern_res", default, 1..=MAX_TEXTURE_SIDE)
        .unit("texels")
        .meaning("spot pattern texture resolution per side")
}
