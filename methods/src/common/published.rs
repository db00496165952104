//! The resolve of methods whose compute passes sum each light's in-scatter into a buffer and
//! publish it to an rgba32float texture (epipolar-minmax, prefiltered-single-scattering): a
//! [`super::resolve::ResolvePass`] with that texture at binding 3.

/// The resolve's fragment shader (an `fs` entry; composed by `common::resolve::source`).
pub const PUBLISHED_RESOLVE: &str = include_str!("wgsl/published_resolve.wgsl");
