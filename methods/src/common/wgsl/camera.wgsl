// Camera: the same matrices and pixel-ray convention as scenes::camera (pixel centres, top row
// first, wgpu clip space). Mirrors common::uniforms::CameraUniform.
struct Camera {
    clip_from_world: mat4x4<f32>,
    world_from_clip: mat4x4<f32>,
    // xyz: eye position (m); w: near plane (view depth, m)
    position: vec4<f32>,
    // xyz: unit forward; w: far plane (view depth, m)
    forward: vec4<f32>,
    // width, height, 1/width, 1/height (pixels)
    viewport: vec4<f32>,
};

// Unit world direction of the ray through framebuffer position `frag` (pixel centre = +0.5).
fn camera_ray_dir(cam: Camera, frag: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(2.0 * frag.x * cam.viewport.z - 1.0, 1.0 - 2.0 * frag.y * cam.viewport.w);
    let p = cam.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    return normalize(p.xyz / p.w - cam.position.xyz);
}

// Distance along `dir` to the far plane: where a ray that hits nothing ends.
fn camera_far_distance(cam: Camera, dir: vec3<f32>) -> f32 {
    return cam.forward.w / dot(dir, cam.forward.xyz);
}

// Length of the camera ray along `dir` given the surface pass's distance (−1 where the ray hit
// nothing: then the ray ends at the far plane).
fn camera_ray_length(cam: Camera, dir: vec3<f32>, hit: f32) -> f32 {
    return select(camera_far_distance(cam, dir), hit, hit >= 0.0);
}
