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

// Unit world direction of the ray through framebuffer position `frag` (pixel centre = +0.5):
// where the world planes that clip_from_world maps to clip x = ndc.x·w and y = ndc.y·w meet,
// the cross product of their normals (rows 0 and 1 less ndc × row 3). Unprojecting a far-plane
// point through world_from_clip instead loses 3e-6 rad (1.6e-5 with far 200 m) in f32: the
// inverse of a perspective is ill-conditioned; this way keeps 1e-7 — what an exact crossing
// distance on a plane seen at a grazing angle needs (`shadow_plane.wgsl`'s `plane_distance`).
fn camera_ray_dir(cam: Camera, frag: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(2.0 * frag.x * cam.viewport.z - 1.0, 1.0 - 2.0 * frag.y * cam.viewport.w);
    let rows = transpose(cam.clip_from_world);
    let d = normalize(cross(rows[0].xyz - ndc.x * rows[3].xyz, rows[1].xyz - ndc.y * rows[3].xyz));
    return select(-d, d, dot(d, cam.forward.xyz) > 0.0);
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

// Distance from the eye along the ray through framebuffer position `frag` to the plane through
// `point` with normal `normal` (any length): for a rasterised primitive, its interpolated world
// position and its plane's normal. Not `length(point − eye)`: a rasteriser may interpolate from
// vertex positions snapped to its sub-pixel grid (Vulkan `subPixelPrecisionBits`: 4 on
// SwiftShader), so the interpolated point lies in the plane but up to half a grid step off the
// pixel's ray, and on a plane seen at a grazing angle (a light shaft's side, a floor far away)
// that length is off by millimetres to centimetres, by how much depending on the adapter. The
// plane is exact, so the exact ray is intersected with it; seen edge-on (|cos| ≤ 1e-4, no
// intersection worth trusting) the length is kept.
fn camera_plane_distance(cam: Camera, frag: vec2<f32>, point: vec3<f32>, normal: vec3<f32>) -> f32 {
    let n = normal / max(length(normal), 1e-30);
    let to_point = point - cam.position.xyz;
    let across = dot(n, camera_ray_dir(cam, frag));
    return select(dot(n, to_point) / across, length(to_point), abs(across) <= 1e-4);
}

// `camera_plane_distance` for the primitive being rasterised at `frag`, `world` its interpolated
// world position: the normal of its plane from the screen derivatives of `world`, which lie in
// it (exact for an axis-aligned surface). Derivatives: call in uniform control flow.
fn camera_surface_distance(cam: Camera, frag: vec2<f32>, world: vec3<f32>) -> f32 {
    return camera_plane_distance(cam, frag, world, cross(dpdx(world), dpdy(world)));
}
