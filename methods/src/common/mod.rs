//! What methods share. The framework every method uses sits at this level: the scene on the GPU
//! (`gpu_scene`, `uniforms`, `layouts`), the frame (`renderer`: shadow maps, patterns, the forward
//! surface pass), the resolve into the final image (`resolve`), knobs and specialisation (`knobs`,
//! `specialize`, `pipeline`), and WGSL composition (`wgsl`, `wgsl/`). The rest is math tables
//! (`gamma`, `quadrature`, `tables`, `sphere_cone`, `height_fog`) and work counters (`counters`).
//! Three kits, each used by a few methods, are folders with their contract in their `mod.rs`:
//! - [`shadow_volumes`]: silhouette shadow planes, stencil counting, crossing lists;
//! - [`epipolar`]: epipolar slices, their compute skeleton and resolve;
//! - [`particles`]: the particle grid traced exactly, and particle shadows on surfaces.
//!
//! Kits build on the framework, never on each other; the framework never uses a kit.

pub mod counters;
pub mod epipolar;
pub mod gamma;
pub mod gpu_scene;
pub mod height_fog;
pub mod knobs;
pub mod layered;
pub mod layouts;
pub mod particles;
pub mod patterns;
pub mod pipeline;
pub mod quadrature;
pub mod renderer;
pub mod resolve;
pub mod shadow_maps;
pub mod shadow_volumes;
pub mod specialize;
pub mod sphere_cone;
pub mod tables;
pub mod uniforms;
pub mod wgsl;
