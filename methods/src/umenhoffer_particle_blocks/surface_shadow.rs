//! The cloud's shadow on surfaces, one pass per light: `common::particles::surface_shadow` with
//! this
//! method's fragment (surface_shadow.wgsl: τ from the light's slices).

pub use crate::common::particles::surface_shadow::SurfaceShadow;

/// The bindings of blocks.wgsl's group 1 the pass reads: the uniform and both slice arrays.
pub const BINDINGS: [u32; 3] = [0, 5, 6];
