// The rectified rows of prefiltered-single-scattering: per epipolar slice, the caster's eye angle
// at each texel of the row, expanded in the basis (BASIS), and the row's prefix sums of the basis
// coefficients. One light at a time (pss.light). Needs PRELUDE, EPIPOLAR_SLICES and basis.wgsl.

// Mirrors PssUniform in passes.rs, field for field.
struct Pss {
    // the light this pass handles
    light: u32,
    // epipolar slices N and texels K of a rectified row
    slices: u32,
    texels: u32,
    // 1: this light's shade pass writes the accumulator (first light); 0: adds to it
    first: u32,
};

@group(1) @binding(0) var<uniform> pss: Pss;
@group(1) @binding(1) var<storage, read_write> slices: array<Slice>;
// Per slice: the eye angles (lo, hi) mapped to the basis' [0, 1] (rays of the slice lie inside).
@group(1) @binding(2) var<storage, read_write> angle_range: array<vec2<f32>>;
// Per slice, K + 1 entries of CHANNELS vec4s: entry j holds the sum of the basis coefficients of
// texels 0 … j − 1 (entry 0 is zero). The rectify pass writes texel j's own coefficients at
// entry j + 1; the prefix pass sums them in place.
@group(1) @binding(3) var<storage, read_write> sums: array<vec4<f32>>;
@group(1) @binding(4) var ray_distance: texture_2d<f32>;
// In-scatter per pixel, summed over lights.
@group(1) @binding(5) var<storage, read_write> accum: array<vec4<f32>>;
@group(1) @binding(6) var published: texture_storage_2d<rgba32float, write>;


// First vec4 of entry j of slice i's row.
fn row_entry(i: u32, j: u32) -> u32 {
    return (i * (pss.texels + 1u) + j) * CHANNELS;
}

// Unit vector from the eye toward light k (along its rays' reverse for directional light).
fn toward_light(k: u32) -> vec3<f32> {
    if (light_kind(k) == LIGHT_DIRECTIONAL) { return -lights.lights[k].direction.xyz; }
    return normalize(eye_to_light(k));
}

// The angle at the eye between direction `dir` and the direction toward light k.
fn eye_angle(k: u32, dir: vec3<f32>) -> f32 {
    let w = toward_light(k);
    return atan2(length(cross(dir, w)), dot(dir, w));
}

// The eye angles of a slice's rays, from its entry to its exit (monotone along a slice: the
// slice is an arc of a great circle through the light's direction), widened by 2 % and 1 mrad on
// both sides for pixels between two slices.
fn slice_angle_range(k: u32, sl: Slice) -> vec2<f32> {
    let a = eye_angle(k, camera_ray_dir(camera, sl.ends.xy * camera.viewport.xy));
    let b = eye_angle(k, camera_ray_dir(camera, sl.ends.zw * camera.viewport.xy));
    let margin = 0.02 * abs(b - a) + 1e-3;
    return vec2<f32>(min(a, b) - margin, max(a, b) + margin);
}

// Slice i of light pss.light and its eye-angle range.
@compute @workgroup_size(64)
fn slice_rows(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= pss.slices) { return; }
    let sl = epipolar_slice(pss.light, i, pss.slices);
    slices[i] = sl;
    angle_range[i] = slice_angle_range(pss.light, sl);
}

// The eye angle of the caster on the light ray at rectified coordinate u of slice sl: the point
// where the stored depth (with the shadow test's bias) puts it; π without a caster. Along one
// light ray, away from the light, the eye angle grows, so a camera ray of the slice at eye angle
// α is lit where it crosses that light ray iff α < this angle.
fn caster_angle(k: u32, sl: Slice, u: f32) -> f32 {
    let stored = shadow_stored(k, rectified_point(k, sl, u));
    if (stored >= 0.5 * SHADOW_NONE) { return PI; }
    let b = shadow_bound(k);
    let dist = (stored + b.y) / b.x;
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        // Depth of the caster along the light from the eye's, and u across it.
        let x = dist - dot(camera.position.xyz, sl.e1.xyz);
        return atan2(u, -x);
    }
    let d = length(eye_to_light(k));
    return atan2(dist * sin(u), d - dist * cos(u));
}

// Texel j of slice i: its caster angle mapped to [0, 1] by the slice's range, in the basis.
@compute @workgroup_size(64)
fn rectify(@builtin(global_invocation_id) id: vec3<u32>) {
    let j = id.x;
    let i = id.y;
    if (j >= pss.texels || i >= pss.slices) { return; }
    let sl = slices[i];
    var z = 1.0;
    if (slice_valid(sl)) {
        let u = texel_centre(sl, j, pss.texels);
        let r = angle_range[i];
        z = clamp((caster_angle(pss.light, sl, u) - r.x) / (r.y - r.x), 0.0, 1.0);
    }
    let e = row_entry(i, j + 1u);
    for (var c = 0u; c < CHANNELS; c++) {
        sums[e + c] = basis_coefficients(z, c);
    }
}

// Knuth's two-sum: s + e = a + b exactly (s = fl(a + b)).
fn two_sum(a: vec4<f32>, b: vec4<f32>) -> array<vec4<f32>, 2> {
    let s = a + b;
    let bb = s - a;
    return array<vec4<f32>, 2>(s, (a - (s - bb)) + (b - bb));
}

// Slice i's row summed in place. Moments: a double-float sum (channel 0 the high part, channel 1
// the low part), since a row of K texels reaches K and a short interval's mean moments are
// differences of such sums; Fourier coefficients: plain float sums per channel.
@compute @workgroup_size(64)
fn prefix(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= pss.slices) { return; }
    let e0 = row_entry(i, 0u);
    var run: array<vec4<f32>, MAX_CHANNELS>;
    for (var c = 0u; c < CHANNELS; c++) {
        sums[e0 + c] = vec4<f32>(0.0);
    }
    for (var j = 1u; j <= pss.texels; j++) {
        let e = row_entry(i, j);
        if (BASIS == BASIS_MOMENTS) {
            let s = two_sum(run[0], sums[e]);
            run[0] = s[0];
            run[1] += s[1];
            sums[e] = run[0];
            sums[e + 1u] = run[1];
        } else {
            for (var c = 0u; c < CHANNELS; c++) {
                run[c] += sums[e + c];
                sums[e + c] = run[c];
            }
        }
    }
}
