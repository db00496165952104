// Group 0, shared by every scene pass (common::renderer::SceneRenderer::frame_layout).
@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> medium: Medium;
@group(0) @binding(2) var<uniform> lights: Lights;
@group(0) @binding(3) var<storage, read> objects: array<ObjectData>;
@group(0) @binding(4) var shadow_maps: texture_2d_array<f32>;
@group(0) @binding(5) var light_patterns: texture_2d_array<f32>;
@group(0) @binding(6) var linear_clamp: sampler;
