//! Knobs several methods share, declared once: the shadow-map and pattern-texture resolutions
//! and the local lights' shadow-map budget. A method adds them to its `knobs()` with its own
//! default and sweep.

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

/// `local_shadow_budget`'s default (MiB): 256 keeps every local face at 1024² up to 10 local
/// lights (60 faces at 4 MiB), so the library's one- and two-light scenes render as before; the
/// 16-torch atrium gets 512² faces, the 64-torch one 256² (96 MiB), as engines shrink their
/// shadow atlas's tiles when lights multiply.
pub const LOCAL_SHADOW_BUDGET_MIB: i64 = 256;

/// `local_shadow_budget`: MiB all local (point and spot) lights' shadow-map faces may take
/// together (1 … 65536, default [`LOCAL_SHADOW_BUDGET_MIB`]). Each local face gets `shadow_map`
/// texels per side, halved until the faces fit (`common::shadow_maps::ShadowSettings`); the
/// side used is counted per frame as `shadow_map_local`.
pub fn local_shadow_budget() -> Knob {
    Knob::int("local_shadow_budget", LOCAL_SHADOW_BUDGET_MIB, 1..=65536)
        .unit("MiB")
        .meaning("shadow-map memory for all local lights' cube faces together; each face's side is shadow_map, halved until they fit")
}

/// A method's own knobs followed by those of the shared shadow maps and spot patterns:
/// `shadow_map` (the method's default and sweep), `local_shadow_budget` and `pattern_res` (512).
pub fn with_shadow_maps(mut own: Vec<Knob>, shadow_map: Knob) -> Vec<Knob> {
    own.extend([shadow_map, local_shadow_budget(), pattern_res(512)]);
    own
}
