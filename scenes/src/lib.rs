//! scatterbench scenes: the scene file format, its validation, procedural meshes, camera math,
//! phase functions and lights with exact CPU evaluation, and the built-in scene library.
//!
//! Data flow: JSON text → [`desc::SceneDesc`] (serde, `deny_unknown_fields`) →
//! [`validate::validate`] (every problem at once) → [`Scene`] (with meshes) →
//! [`Scene::frame`] → [`FrameState`] (camera, lights and transforms at one frame).

pub mod camera;
pub mod desc;
pub mod gltf;
pub mod library;
pub mod light;
pub mod load;
mod locate;
pub mod mesh;
pub mod particles;
pub mod phase;
pub mod scene;
pub mod validate;
pub mod variants;

pub use camera::{CameraPose, PixelRays};
pub use desc::{HeightFog, SceneDesc};
pub use light::LightState;
pub use load::{SceneError, load_scene, parse_scene};
pub use mesh::TriMesh;
pub use particles::Particle;
pub use phase::Phase;
pub use scene::{FrameState, Homogeneous, Medium, Particles, Scene, SceneFeatures};
