//! What the shadow-plane passes share (`planes.rs`, the per-pixel passes of `pixel.rs`, the
//! stencil pipelines of `stencil_pipes.rs`): the resolve's options, each light's range of
//! planes, and the per-light uniform slot. A leaf: it imports none of them.

use crate::common::shadow_volumes::shadow_planes::Split;

/// How the plane crossings become in-scatter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolve {
    /// Steps 4–5: planes sorted on the CPU, drawn with stencil counting.
    Stencil,
    /// Per-pixel crossing lists sorted and walked on the GPU (`pixel.rs`).
    PerPixel,
}

/// The shadow-plane options (knobs `resolve`, `stencil_rules`, `accumulate`, `silhouettes`).
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Knob `silhouettes`: closed pieces of a caster cast silhouette volumes
    /// (`Split::Components`), or a caster that is not closed as a whole falls back to
    /// per-triangle volumes (`Split::WholeMesh`).
    pub split: Split,
    pub resolve: Resolve,
    /// Step 5's stencil rules (stencil resolve only).
    pub rules: bool,
    /// The paper's 8-bit target with reverse-subtract blending (stencil resolve only).
    pub unorm8: bool,
    /// Knob `spot_panels` (the spot quadrature of `lit_between`).
    pub spot_panels: u32,
    /// Knob `spot_integral = per-ray` (per-pixel resolve, spots without a pattern): each ray's
    /// spot in-scatter fitted once (`spot_fit.wgsl`), each lit interval from its antiderivative.
    pub spot_per_ray: bool,
}

/// One light's planes in the vertex buffer and the eye's shadow count.
#[derive(Clone, Copy, Debug)]
pub struct LightRange {
    pub first: u32,
    pub end: u32,
    pub eye_count: u32,
}

/// Phase-timer names (Biri et al.'s Table 1): step 3's lit surfaces (and the scene depth they
/// need), and the shadow planes (stencil count and plane passes, or the per-pixel gather); the
/// per-pixel resolve's sort and walk of the crossing lists on their own (not in the paper).
pub const SURFACES: &str = "second_pass_surfaces";
pub const VOLUMES: &str = "second_pass_volumes";
pub const WALK: &str = "second_pass_walk";

/// Uniform slot stride (the minimum dynamic-offset alignment wgpu guarantees).
pub const SLOT: u64 = 256;
/// The bytes of a slot the passes read: [light, eye count, _, spot panels].
pub const SLOT_BYTES: u64 = 16;

/// Light k's dynamic offset into the per-light uniform slots.
pub fn slot_offset(k: usize) -> [u32; 1] {
    [(k as u64 * SLOT) as u32]
}
