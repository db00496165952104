// What every resolve pass (common::resolve::ResolvePass) reads and writes: group 1 holds the
// ray-distance and surface AOVs at bindings 0 and 1; the pass writes in-scatter and total.
// Needs PRELUDE.

@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var surface: texture_2d<f32>;

struct Out {
    @location(0) inscatter: vec4<f32>,
    @location(1) total: vec4<f32>,
};

// Length of pixel px's ray along dir: to the visible surface, or to the far plane.
fn pixel_ray_length(px: vec2<i32>, dir: vec3<f32>) -> f32 {
    return camera_ray_length(camera, dir, textureLoad(ray_distance, px, 0).r);
}

// ARCHITECTURE §1's ambient term over the camera ray along dir of length d: L_a (1 − e^(−τ)),
// τ = σt d without height fog.
fn ambient_fog(dir: vec3<f32>, d: f32) -> vec3<f32> {
    return medium.ambient.rgb * (vec3<f32>(1.0) - transmittance_along(medium, camera.position.xyz, dir, d));
}
