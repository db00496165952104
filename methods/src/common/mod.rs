//! What several methods share: WGSL modules (composed, never pasted), uniform mirrors, the
//! scene's GPU buffers, shadow maps, light-pattern textures and the forward surface pass.

pub mod counters;
pub mod crossing_lists;
pub mod gamma;
pub mod gpu_scene;
pub mod height_fog;
pub mod knobs;
pub mod layered;
pub mod layouts;
pub mod particle_surfaces;
pub mod particle_trace;
pub mod patterns;
pub mod pipeline;
pub mod published;
pub mod quadrature;
pub mod rectification;
pub mod renderer;
pub mod resolve;
pub mod shadow_maps;
pub mod shadow_planes;
pub mod silhouette;
pub mod specialize;
pub mod sphere_cone;
pub mod stencil;
pub mod stencil_surfaces;
pub mod surface_shadow;
pub mod tables;
pub mod uniforms;
pub mod wgsl;
