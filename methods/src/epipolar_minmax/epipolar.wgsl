// Epipolar geometry and the buffers every epipolar-minmax pass shares (one light at a time).
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

// One epipolar slice: a screen segment from the epipole outward, and its epipolar plane.
struct Slice {
    // entry uv (xy), exit uv (zw)
    ends: vec4<f32>,
    // xyz: the plane's first axis (from the light toward the eye; the light direction for
    // directional light); w: 1 valid, 0 the segment misses the screen
    e1: vec4<f32>,
    // xyz: the in-plane axis toward the slice's rays; w: the rectified coordinate's extent u_max
    e2: vec4<f32>,
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

// The light's projection (the epipole) in uv: a finite point of its projective line, also for a
// light behind the camera (then rays through the screen run away from it) or at infinity.
fn epipole_uv(k: u32) -> vec2<f32> {
    var c: vec4<f32>;
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        c = camera.clip_from_world * vec4<f32>(-lights.lights[k].direction.xyz, 0.0);
    } else {
        c = camera.clip_from_world * vec4<f32>(lights.lights[k].position.xyz, 1.0);
    }
    let floor_w = 1e-6 * max(length(c.xy), 1e-20);
    let w = select(-1.0, 1.0, c.w >= 0.0) * max(abs(c.w), floor_w);
    let ndc = clamp(c.xy / w, vec2<f32>(-1e5), vec2<f32>(1e5));
    return vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
}

// The point at perimeter parameter u ∈ [0, 1) of the screen's border, clockwise from the
// top-left corner: top, right, bottom, left edge, a quarter each.
fn border_point(u: f32) -> vec2<f32> {
    let e = fract(u) * 4.0;
    let f = fract(e);
    switch u32(e) {
        case 0u: { return vec2<f32>(f, 0.0); }
        case 1u: { return vec2<f32>(1.0, f); }
        case 2u: { return vec2<f32>(1.0 - f, 1.0); }
        default: { return vec2<f32>(0.0, 1.0 - f); }
    }
}

// Inverse of border_point for a point on the border.
fn border_param(p: vec2<f32>) -> f32 {
    let d = vec4<f32>(p.y, 1.0 - p.x, 1.0 - p.y, p.x);
    let m = min(min(d.x, d.y), min(d.z, d.w));
    if (m == d.x) { return 0.25 * clamp(p.x, 0.0, 1.0); }
    if (m == d.y) { return 0.25 + 0.25 * clamp(p.y, 0.0, 1.0); }
    if (m == d.z) { return 0.5 + 0.25 * clamp(1.0 - p.x, 0.0, 1.0); }
    return 0.75 + 0.25 * clamp(1.0 - p.y, 0.0, 1.0);
}

// Where the line o + s v is inside the screen: (s_in, s_out); s_in > s_out when it misses.
fn screen_span(o: vec2<f32>, v: vec2<f32>) -> vec2<f32> {
    var s = vec2<f32>(-3.0e38, 3.0e38);
    for (var a = 0u; a < 2u; a++) {
        if (abs(v[a]) < 1e-12) {
            if (o[a] < 0.0 || o[a] > 1.0) { s = vec2<f32>(1.0, 0.0); }
        } else {
            let s0 = (0.0 - o[a]) / v[a];
            let s1 = (1.0 - o[a]) / v[a];
            s = vec2<f32>(max(s.x, min(s0, s1)), min(s.y, max(s0, s1)));
        }
    }
    return s;
}

// Continuous slice coordinate of screen point q: its ray from the epipole leaves the screen at
// perimeter parameter u, and slice i exits at (i + 0.5) / N.
fn slice_coordinate(ep: vec2<f32>, q: vec2<f32>) -> f32 {
    let v = q - ep;
    if (dot(v, v) < 1e-14) { return 0.0; }
    let s = screen_span(ep, v);
    return border_param(ep + s.y * v) * f32(epi.slices) - 0.5;
}

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

// From the eye to local light k; a light at the eye (closer than 0.1 mm) is taken 0.1 mm ahead
// of it, where the epipolar frame is defined (the in-scatter there is unbounded anyway).
fn eye_to_light(k: u32) -> vec3<f32> {
    let v = lights.lights[k].position.xyz - camera.position.xyz;
    return select(v, camera.forward.xyz * 1e-4, dot(v, v) < 1e-8);
}
