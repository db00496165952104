//! The knob-derived configuration and the per-light uniform every pass of the method shares
//! (`passes.rs`, `encode.rs`, `pipelines.rs`, `spot_rays.rs`, `pixel.rs`). A leaf: it imports
//! none of them.

/// Where Γ is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Eval {
    /// Per vertex, Gouraud-interpolated (the paper).
    Vertex,
    /// Per fragment (the modern variant).
    Fragment,
}

/// How the plane crossings become in-scatter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolve {
    /// Per-pixel crossing lists sorted and walked (`pixel.rs`; modern, exact shadow in shadow).
    PerPixel,
    /// The paper's: planes front to back in eq. 13/14's order under §4.4's stencil rules.
    Planes,
}

/// Where the per-pixel resolve walks its crossing lists (knob `walk`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// A full-screen fragment pass blended into the accumulation target.
    Fragment,
    /// A compute pass over 8×8 tiles writing the running sum over lights (`cs_walk`).
    Compute,
}

/// The accumulation target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accumulate {
    /// Rgba32Float, signed sums: exact up to f32 rounding.
    Float,
    /// Rgba8Unorm as on the paper's GeForce 2: total radiance clamped to [0, 1] after every
    /// blend and quantised to 1/255 (§5.2's quantization problem).
    Unorm8,
}

/// The knobs the passes depend on.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    pub resolve: Resolve,
    /// Knob `walk` (resolve = per-pixel).
    pub walk: Walk,
    pub eval: Eval,
    pub accumulate: Accumulate,
    /// Subdivision levels of the surfaces (vertex evaluation only).
    pub tessellation: u32,
    /// Strips per shadow plane (vertex evaluation only).
    pub plane_segments: u32,
    /// §4.4's stencil rules; false counts every crossing (exact for disjoint shadow volumes).
    pub stencil_rules: bool,
    /// The per-light uniform: [order, fit, _, _] and the phase series.
    pub order: u32,
    pub fit: u32,
    pub series: [f32; 12],
    /// Spots (eq. 7): half circles per unit of the plane-normal grid (n_u = N, n_φ = 2N).
    pub half_circles: u32,
}

/// `poly` in passes.wgsl, field for field (order and fit are the overrides ORDER and FIT).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PolyUniform {
    pub light: u32,
    pub signed_output: u32,
    pub _pad: [u32; 2],
    pub series: [f32; 12],
    pub spot: [u32; 4],
    pub spot_f: [f32; 4],
}

/// Uniform slot stride (wgpu's guaranteed minimum dynamic-offset alignment).
pub const SLOT: u64 = 256;
