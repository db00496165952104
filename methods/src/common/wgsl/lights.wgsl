// Lights (ARCHITECTURE §1) with the spot falloff and the pattern texture. Mirrors
// common::uniforms::{LightUniform, LightsUniform}.
// common::uniforms::MAX_LIGHTS (the uniform's capacity; a header and 128 × 480 B < 64 KiB).
const MAX_LIGHTS: u32 = 128u;
const LIGHT_POINT: u32 = 0u;
const LIGHT_SPOT: u32 = 1u;
const LIGHT_DIRECTIONAL: u32 = 2u;

struct Light {
    // xyz: position (m); w: kind
    position: vec4<f32>,
    // xyz: unit axis / propagation direction; w: cos(inner)
    direction: vec4<f32>,
    // rgb: intensity (W/sr) or irradiance (W/m²); w: cos(outer)
    intensity: vec4<f32>,
    // xyz: spot slide frame right; w: tan(outer)
    right: vec4<f32>,
    // xyz: spot slide frame up; w: pattern layer (< 0: no pattern)
    up: vec4<f32>,
    // x: first shadow-atlas tile (< 0: no shadow map); y: log2 of the tiles per atlas row;
    // z: face size (texels); w: depth bias scale (shadow.wgsl)
    shadow: vec4<f32>,
    // clip_from_world of each shadow-map face (+X, −X, +Y, −Y, +Z, −Z; or one orthographic)
    faces: array<mat4x4<f32>, 6>,
};

struct Lights {
    // x: number of lights
    count: vec4<u32>,
    lights: array<Light, 128>,
};

// The functions below take the light's index and read the `lights` uniform (frame_bindings.wgsl)
// field by field: copying a whole `Light` (480 bytes) per call is what made lavapipe slow.

// Scene-baked light layout (common::specialize): a scene's light count and kinds are fixed for a
// run, so passes that set these constants compile them in and the per-light loops and kind
// branches fold away. The default, UNBAKED, means "read the lights uniform". The kinds of the
// first four lights are baked one by one; of the rest, LIGHT_KINDS_REST holds which kinds occur
// (bit 1 << kind), so `scene_has_light_kind` still folds for scenes without a kind.
const UNBAKED: u32 = 0xffffffffu;
override LIGHT_COUNT: u32 = UNBAKED;
override LIGHT_KIND_0: u32 = UNBAKED;
override LIGHT_KIND_1: u32 = UNBAKED;
override LIGHT_KIND_2: u32 = UNBAKED;
override LIGHT_KIND_3: u32 = UNBAKED;
override LIGHT_KINDS_REST: u32 = UNBAKED;

fn light_count() -> u32 {
    if (LIGHT_COUNT != UNBAKED) { return LIGHT_COUNT; }
    return lights.count.x;
}

fn light_kind(k: u32) -> u32 {
    var baked = UNBAKED;
    switch k {
        case 0u: { baked = LIGHT_KIND_0; }
        case 1u: { baked = LIGHT_KIND_1; }
        case 2u: { baked = LIGHT_KIND_2; }
        case 3u: { baked = LIGHT_KIND_3; }
        default: {}
    }
    if (baked != UNBAKED) { return baked; }
    return u32(lights.lights[k].position.w + 0.5);
}

// Whether the scene can have a light of `kind`: false only where the pass baked the light layout
// and no light has that kind, so `if (scene_has_light_kind(K) && light_kind(k) == K)` folds
// away for scenes without K even where k is a run-time index.
fn scene_has_light_kind(kind: u32) -> bool {
    if (LIGHT_COUNT == UNBAKED || LIGHT_KIND_0 == UNBAKED) { return true; }
    return LIGHT_KIND_0 == kind
        || (LIGHT_COUNT > 1u && LIGHT_KIND_1 == kind)
        || (LIGHT_COUNT > 2u && LIGHT_KIND_2 == kind)
        || (LIGHT_COUNT > 3u && LIGHT_KIND_3 == kind)
        || (LIGHT_COUNT > 4u && (LIGHT_KINDS_REST & (1u << kind)) != 0u);
}

// Bit k of a 128-bit light mask (common::uniforms::LightMask).
fn light_bit(mask: vec4<u32>, k: u32) -> bool {
    return ((mask[k / 32u] >> (k % 32u)) & 1u) != 0u;
}

// smoothstep(cos_outer, cos_inner, cos_angle), as scenes::light::spot_falloff.
fn spot_falloff(k: u32, cos_angle: f32) -> f32 {
    let ci = lights.lights[k].direction.w;
    let co = lights.lights[k].intensity.w;
    if (cos_angle >= ci) { return 1.0; }
    if (cos_angle <= co) { return 0.0; }
    let t = (cos_angle - co) / (ci - co);
    return t * t * (3.0 - 2.0 * t);
}

// Radiant intensity of light k toward world point x (W/sr), falloff and pattern included;
// irradiance for directional light. `w` is x − light position (unused for directional light).
fn light_intensity(k: u32, w: vec3<f32>) -> vec3<f32> {
    let rgb = lights.lights[k].intensity.rgb;
    if (light_kind(k) != LIGHT_SPOT) {
        return rgb;
    }
    let axis = lights.lights[k].direction.xyz;
    let len = length(w);
    let z = dot(w, axis);
    if (len <= 0.0 || z <= 0.0) { return vec3<f32>(0.0); }
    let fall = spot_falloff(k, z / len);
    if (fall <= 0.0) { return vec3<f32>(0.0); }
    var slide = vec3<f32>(1.0);
    let layer = lights.lights[k].up.w;
    if (layer >= 0.0) {
        let right = lights.lights[k].right;
        let up = lights.lights[k].up.xyz;
        let uv = vec2<f32>(0.5 + 0.5 * dot(w, right.xyz) / z / right.w, 0.5 + 0.5 * dot(w, up) / z / right.w);
        // The pattern texture's row 0 holds v = 0 (scenes::light::spot_uv's v is the texture v).
        slide = textureSampleLevel(light_patterns, linear_clamp, uv, i32(layer + 0.5), 0.0).rgb;
    }
    return rgb * fall * slide;
}
