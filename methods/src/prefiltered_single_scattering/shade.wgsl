// The per-pixel in-scatter of prefiltered-single-scattering, one light per pipeline (LIGHT). The
// pixel's camera ray lies in its own epipolar plane, between two slices; along it the rectified
// coordinate u runs from 0 at the eye to u_end. SEGMENTS equal pieces in u each take the
// unshadowed in-scatter of the piece times its mean visibility, reconstructed from the two
// slices' prefix sums over the piece (two lookups per channel and slice), weighted by the
// pixel's slice coordinate. Needs PRELUDE, EPIPOLAR_SLICES, LIGHT_SEGMENTS, basis.wgsl and
// rows.wgsl.

override LIGHT: u32 = 0u;
// Pieces of the camera ray in u (1: the papers' one filtered lookup per ray)
override SEGMENTS: u32 = 1u;
// Two-node Gauss–Legendre panels per piece for a point or spot light's unshadowed in-scatter
override PANELS: u32 = 4u;
// false: the light has no shadow map this run: every ray is lit end to end
override SHADOWED: bool = true;

// A camera ray and its epipolar geometry.
struct PixelRay {
    dir: vec3<f32>,
    len: f32,
    // eye angle α to the light direction (eye_angle)
    alpha: f32,
    // the rectified coordinate at the ray's end
    u_end: f32,
};

fn pixel_ray(px: vec2<u32>) -> PixelRay {
    let dir = camera_ray_dir(camera, vec2<f32>(px) + 0.5);
    let len = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(px), 0).r);
    let alpha = eye_angle(LIGHT, dir);
    var u_end = len * sin(alpha);
    if (light_kind(LIGHT) != LIGHT_DIRECTIONAL) {
        let d = length(eye_to_light(LIGHT));
        u_end = atan2(len * sin(alpha), d - len * cos(alpha));
    }
    return PixelRay(dir, len, alpha, u_end);
}

// Distance along the ray at rectified coordinate u ≤ u_end: u / sin α across a directional
// light's rays; D sin u / sin(α + u) by the sine rule in the triangle eye, light, point.
fn ray_distance_at(r: PixelRay, u: f32) -> f32 {
    if (u >= r.u_end) { return r.len; }
    if (light_kind(LIGHT) == LIGHT_DIRECTIONAL) { return u / max(sin(r.alpha), 1e-30); }
    let d = length(eye_to_light(LIGHT));
    return clamp(d * sin(u) / max(sin(r.alpha + u), 1e-30), 0.0, r.len);
}

// σ_s ∫ of the light's unshadowed in-scatter over [a, b] of the ray (LIGHT_SEGMENTS).
fn unshadowed(dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let kind = light_kind(LIGHT);
    if (kind == LIGHT_DIRECTIONAL) { return sunlight_between(LIGHT, dir, a, b); }
    if (kind == LIGHT_SPOT) { return spot_between(LIGHT, dir, a, b, PANELS); }
    return local_quadrature(LIGHT, dir, a, b, PANELS);
}

// Channel c of slice i's prefix sum at continuous texel position x ∈ [0, K] (linear between
// entries: the exact integral of the piecewise-constant row).
fn prefix_at(i: u32, x: f32, c: u32) -> vec4<f32> {
    let j = min(u32(x), pss.texels - 1u);
    let f = x - f32(j);
    return mix(sums[row_entry(i, j) + c], sums[row_entry(i, j + 1u) + c], f);
}

// Channel c's mean coefficients over texels [x0, x1] of slice i; an interval under one texel
// takes the texel at its middle (a difference of prefix sums would lose its digits).
fn mean_channel(i: u32, x0: f32, x1: f32, c: u32) -> vec4<f32> {
    if (x1 - x0 < 1.0) {
        let j = min(u32(0.5 * (x0 + x1)), pss.texels - 1u);
        return sums[row_entry(i, j + 1u) + c] - sums[row_entry(i, j) + c];
    }
    return (prefix_at(i, x1, c) - prefix_at(i, x0, c)) / (x1 - x0);
}

// The mean visibility over rectified coordinates [u0, u1] of a ray at eye angle alpha, from
// slice i's row.
fn slice_visibility(i: u32, u0: f32, u1: f32, alpha: f32) -> f32 {
    let k = f32(pss.texels);
    let du = texel_width(slices[i], pss.texels);
    let x0 = clamp(u0 / du, 0.0, k);
    let x1 = clamp(u1 / du, 0.0, k);
    let r = angle_range[i];
    let z = clamp((alpha - r.x) / (r.y - r.x), 0.0, 1.0);
    // Moments: the double-float sums, high parts' difference plus low parts'.
    var mean0 = mean_channel(i, x0, x1, 0u);
    if (BASIS == BASIS_MOMENTS) { mean0 += mean_channel(i, x0, x1, 1u); }
    if (all_uncast(mean0)) { return 1.0; }
    if (BASIS == BASIS_MOMENTS) { return moment_lit(mean0, z); }
    var sum = fourier_channel(mean0, 0u, z);
    for (var c = 1u; c < CHANNELS; c++) {
        sum += fourier_channel(mean_channel(i, x0, x1, c), c, z);
    }
    return fourier_lit(sum);
}

@compute @workgroup_size(8, 8)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = id.y * size.x + id.x;
    let r = pixel_ray(id.xy);
    // The two slices around the pixel's epipolar plane, invalid ones left out.
    let n = pss.slices;
    let q = (vec2<f32>(id.xy) + 0.5) * camera.viewport.zw;
    let c = slice_coordinate(epipole_uv(LIGHT), q, n);
    let c0 = floor(c);
    let i0 = u32(i32(c0) + i32(n)) % n;
    let i1 = (i0 + 1u) % n;
    var w0 = select(0.0, 1.0 - (c - c0), slice_valid(slices[i0]));
    var w1 = select(0.0, c - c0, slice_valid(slices[i1]));
    let wsum = w0 + w1;
    let shadowed = SHADOWED && wsum > 0.0 && r.u_end > 1e-7;
    var l_in = vec3<f32>(0.0);
    var t0 = 0.0;
    for (var s = 0u; s < SEGMENTS; s++) {
        let u0 = r.u_end * f32(s) / f32(SEGMENTS);
        let u1 = r.u_end * f32(s + 1u) / f32(SEGMENTS);
        let t1 = select(ray_distance_at(r, u1), r.len, s + 1u == SEGMENTS);
        var vis = 1.0;
        if (shadowed) {
            vis = (w0 * slice_visibility(i0, u0, u1, r.alpha) + w1 * slice_visibility(i1, u0, u1, r.alpha)) / wsum;
        }
        l_in += unshadowed(r.dir, t0, t1) * vis;
        t0 = t1;
    }
    let prev = select(accum[p], vec4<f32>(0.0), pss.first != 0u);
    accum[p] = prev + vec4<f32>(l_in, 0.0);
}

// The summed in-scatter into the texture the resolve pass reads.
@compute @workgroup_size(8, 8)
fn publish(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(published, id.xy, accum[id.y * size.x + id.x]);
}
