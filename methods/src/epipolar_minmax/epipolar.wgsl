// The buffers every epipolar-minmax pass shares (one light at a time) and its camera-ray helpers;
// the slices and rectified coordinate are common (rectification.rs, epipolar_slices.wgsl).
// Screen positions are in uv: [0, 1]², x right, y down, (0.5, 0.5)/viewport = pixel (0, 0)'s centre.
// Needs PRELUDE.

// Mirrors EpiUniform in mod.rs, field for field.
struct Epi {
    // the light this pass handles
    light: u32,
    // epipolar slices N and samples per slice M
    slices: u32,
    samples: u32,
    // the coarse sample spacing along a slice (a power of two)
    initial_step: u32,
    // leaves K of a rectified shadow-map row (a power of two) and log2 K
    leaves: u32,
    levels: u32,
    // 1: this light's unwarp writes the accumulator (first light); 0: adds to it
    first: u32,
    // 1: the light has a shadow map this frame (else every run is lit and no tree is built)
    shadowed: u32,
    // relative ray-length difference that is a depth break (refinement, unwarp weights)
    refine_threshold: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
};

// One sample along a slice.
struct Sample {
    uv: vec2<f32>,
    // length of its camera ray (to the visible surface or the far plane); < 0 on invalid slices
    dist: f32,
    // bits 0–14: left source sample, 15–29: right source sample (indices within the slice);
    // bit 31: marched
    src: u32,
    // in-scatter (rgb): marched, or interpolated from the sources
    value: vec4<f32>,
};

@group(1) @binding(0) var<uniform> epi: Epi;
@group(1) @binding(1) var<storage, read_write> slices: array<Slice>;
@group(1) @binding(2) var<storage, read_write> samples: array<Sample>;
// Marched samples, then (reused) fix-up pixels.
@group(1) @binding(3) var<storage, read_write> work: array<u32>;
// 0: marched samples, 1: fix-up pixels, 2–4: march dispatch, 5–7: fix-up dispatch.
@group(1) @binding(4) var<storage, read_write> header: array<atomic<u32>>;
// Min-max trees: per slice 2K nodes (min, max of the stored depth), level l at 2K − 2K/2^l.
@group(1) @binding(5) var<storage, read_write> tree: array<vec2<f32>>;
// Frame counters (mod.rs COUNTERS).
@group(1) @binding(6) var<storage, read_write> counters: array<atomic<u32>>;
@group(1) @binding(7) var ray_distance: texture_2d<f32>;
// In-scatter per pixel, summed over lights.
@group(1) @binding(8) var<storage, read_write> accum: array<vec4<f32>>;
@group(1) @binding(9) var published: texture_storage_2d<rgba32float, write>;

const COUNT_MARCHED: u32 = 0u;
const COUNT_INTERPOLATED: u32 = 1u;
const COUNT_FIXUP: u32 = 2u;
const COUNT_LEAVES_SKIPPED: u32 = 3u;
const COUNT_LEAVES_TESTED: u32 = 4u;

// Unit direction and length of the camera ray through uv position `uv` (the pixel's stored ray
// length, or the far plane).
fn camera_ray(uv: vec2<f32>) -> vec4<f32> {
    let frag = uv * camera.viewport.xy;
    let dir = camera_ray_dir(camera, frag);
    let size = vec2<i32>(camera.viewport.xy);
    let px = clamp(vec2<i32>(floor(frag)), vec2<i32>(0), size - vec2<i32>(1));
    let hit = textureLoad(ray_distance, px, 0).r;
    return vec4<f32>(dir, camera_ray_length(camera, dir, hit));
}

// Two ray lengths differ by a depth break.
fn depth_break(a: f32, b: f32) -> bool {
    return abs(a - b) > epi.refine_threshold * min(a, b);
}

// What samples store and pixels interpolate is the in-scatter times this: the ray's distance h
// from a local light (at least 10⁻⁶ of the eye–light distance), 1 for directional light. Near
// the epipole a local light's in-scatter grows like 1/h — unbounded at the epipole itself, where
// every slice starts — while h × in-scatter stays smooth, so it interpolates without smearing
// the light's peak along the slices.
fn interpolation_scale(k: u32, dir: vec3<f32>) -> f32 {
    if (light_kind(k) == LIGHT_DIRECTIONAL) { return 1.0; }
    let to_l = eye_to_light(k);
    return max(length(cross(dir, to_l)), 1e-6 * length(to_l));
}
