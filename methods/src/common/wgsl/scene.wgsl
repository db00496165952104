// Scene geometry: local-space vertices with an object index, and per-object data.
// Mirrors common::gpu_scene::{Vertex, ObjectData}.
struct ObjectData {
    world_from_local: mat4x4<f32>,
    // upper 3×3: inverse-transpose of world_from_local's 3×3
    normal_from_local: mat4x4<f32>,
    // rgb: Lambert albedo; w: 1 if two-sided
    albedo: vec4<f32>,
    // rgb: Phong ks; w: shininess (0: no Phong lobe)
    phong: vec4<f32>,
};

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) object: u32,
    @location(2) normal: vec3<f32>,
};
