//! The shadow-volume kit: silhouette shadow planes and what counts them.
//!
//! For the methods that bound shadowed space with planes extruded from the casters' silhouettes
//! (Biri, Michelin & Arquès; Biri, Arquès & Michelin; Wyman & Ramsey's hybrid). Used by
//! biri-shadow-volumes, biri-polynomial and wyman-hybrid.
//!
//! Contract:
//! - [`silhouette`] finds a caster's silhouette from a light (point or direction) and extrudes
//!   it into quads; [`shadow_planes`] keeps those quads per light on the CPU, rebuilt only when
//!   a light or a caster moved.
//! - [`stencil`] is the depth-stencil state of every pass that draws those planes (z-pass
//!   counting, near-plane-safe clipping); [`stencil_surfaces`] removes a light from the
//!   surfaces its volumes cover, so a stencil method draws no shadow map for them.
//! - [`crossing_lists`] stores each pixel's signed plane crossings for a per-pixel resolve, in a
//!   pool sized exactly for the frame (it cannot overflow).
//!
//! It builds on the framework (`common::{renderer, gpu_scene, pipeline, layouts, wgsl}`) and on
//! nothing else in `common/`.

pub mod crossing_lists;
pub mod shadow_planes;
pub mod silhouette;
pub mod stencil;
pub mod stencil_surfaces;
