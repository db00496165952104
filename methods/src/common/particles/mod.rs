//! The particle kit: media made of spheres, traced exactly.
//!
//! For the methods that render `Medium::Particles` scenes. Used by particle-march, froxel-fog's
//! particle path, umenhoffer-particle-blocks / particle-splat and no-scatter's particle path.
//!
//! Contract:
//! - [`trace`] builds a uniform grid over the spheres at prepare and gives WGSL the exact
//!   optical depth of any segment (a 3-D DDA, each sphere's chord clipped to the cell).
//! - [`surfaces`] draws a particle scene's surfaces for methods that trace that grid: the shared
//!   surface pass, then per light the light removed × (1 − e^(−τ)) with τ traced exactly, and
//!   the eye leg's attenuation.
//! - [`surface_shadow`] is that per-light removal for methods that store τ toward the light in
//!   their own texture (froxel-fog, umenhoffer-particle-blocks).
//!
//! It builds on the framework (`common::{renderer, gpu_scene, resolve, pipeline, layouts,
//! wgsl}`) only.

pub mod surface_shadow;
pub mod surfaces;
pub mod trace;
