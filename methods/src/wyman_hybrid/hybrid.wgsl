// Wyman & Ramsey's hybrid resolve: per pixel and light, the airlight model where the ray meets
// no shadow polygon, otherwise airlight before the first and after the last polygon and a march
// between them that tests the shadow map per step and integrates each lit run analytically.
// Spot lights (§3.2): restricted to the ray's interval inside the cone and integrated by
// angle-uniform steps (their intensity varies across the beam). Needs PRELUDE and FULLSCREEN.

// Light k's nearest and farthest polygon distances: channel k % 4 of layer k / 4.
@group(1) @binding(3) var volume_front: texture_2d_array<f32>;
@group(1) @binding(4) var volume_back: texture_2d_array<f32>;
@group(1) @binding(6) var f_prime: texture_2d<f32>;
// [0]: pixels (and lights) marched; [1]: march steps taken (common::counters).
@group(1) @binding(15) var<storage, read_write> counters: array<atomic<u32>, 2>;

// §3.4: F'(γ, x) from this frame's table (light k's band of columns), at table position fi in γ.
fn fprime_lookup(k: u32, fi: f32, x: f32) -> vec3<f32> {
    let ng = hybrid.fprime_ng;
    let nx = hybrid.fprime_nx;
    let fj = clamp(x / hybrid.fprime_x_max, 0.0, 1.0) * (nx - 1.0);
    let i0 = u32(fi);
    let j0 = u32(fj);
    let i1 = min(i0 + 1u, u32(ng) - 1u);
    let j1 = min(j0 + 1u, u32(nx) - 1u);
    let o = fprime_band(k);
    let ti = fi - f32(i0);
    let tj = fj - f32(j0);
    let a = mix(textureLoad(f_prime, o + vec2<u32>(i0, j0), 0).rgb, textureLoad(f_prime, o + vec2<u32>(i1, j0), 0).rgb, ti);
    let b = mix(textureLoad(f_prime, o + vec2<u32>(i0, j1), 0).rgb, textureLoad(f_prime, o + vec2<u32>(i1, j1), 0).rgb, ti);
    return mix(a, b, tj);
}

// The table is indexed by γ itself (not cos γ as in the paper: near γ = 0, where F' ∝ 1/sin γ,
// cos γ samples are degrees apart). Within FPRIME_EXACT samples of the light's direction F' is
// too curved to interpolate, and the F(u,v) formula is used instead.
const FPRIME_EXACT: f32 = 8.0;

fn airlight_fprime(k: u32, dir: vec3<f32>, ap: Approach, a: f32, b: f32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let cg = dot(dir, normalize(lights.lights[k].position.xyz - camera.position.xyz));
    let fi = acos(clamp(cg, -1.0, 1.0)) / PI * (hybrid.fprime_ng - 1.0);
    if (fi < FPRIME_EXACT) { return airlight(k, ap, a, b); }
    return max(fprime_lookup(k, fi, b) - fprime_lookup(k, fi, a), vec3<f32>(0.0));
}

// Unshadowed in-scatter over [a, b] by n midpoint steps uniform in the angle φ (x = t0 + h tan φ,
// dx/r² = dφ/h): any phase function, spot falloff and pattern.
fn angular(k: u32, dir: vec3<f32>, ap: Approach, a: f32, b: f32, n: u32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let pa = atan((a - ap.t0) / ap.h);
    let pb = atan((b - ap.t0) / ap.h);
    let dphi = (pb - pa) / f32(n);
    var sum = vec3<f32>(0.0);
    for (var s = 0u; s < n; s++) {
        let phi = pa + (f32(s) + 0.5) * dphi;
        // sin/cos, not tan(): lavapipe (Mesa 22.3) crashes compiling tan() in this loop.
        let t = ap.t0 + ap.h * sin(phi) / cos(phi);
        let w = camera.position.xyz + dir * t - lights.lights[k].position.xyz;
        let r = ap.h / cos(phi);
        sum += light_intensity(k, w) * phase(medium, dot(w, -dir) / r) * transmittance(medium, t + r);
    }
    return medium.sigma_s.rgb * sum * (dphi / ap.h);
}

// Unshadowed in-scatter of directional light k over [a, b], in closed form.
fn sunlight(k: u32, dir: vec3<f32>, a: f32, b: f32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    let st = max(medium.sigma_t.rgb, vec3<f32>(1e-12));
    let seg = (exp(-st * a) - exp(-st * b)) / st;
    return medium.sigma_s.rgb * lights.lights[k].intensity.rgb * phase(medium, dot(lights.lights[k].direction.xyz, -dir)) * seg;
}

// Knobs baked per run (mod.rs): lavapipe evaluates both sides of a branch on a uniform flag,
// so testing them at run time paid for the angular quadrature and both airlight forms in every
// lit interval.
override AIRLIGHT: bool = true;
override FPRIME: bool = false;

// Lit in-scatter of light k over [a, b] (no shadow inside).
fn lit(k: u32, dir: vec3<f32>, ap: Approach, a: f32, b: f32, n: u32) -> vec3<f32> {
    let kind = light_kind(k);
    if (kind == LIGHT_DIRECTIONAL) { return sunlight(k, dir, a, b); }
    let analytic = AIRLIGHT && kind == LIGHT_POINT && phase_kind(medium) == 0u;
    if (analytic && FPRIME) { return airlight_fprime(k, dir, ap, a, b); }
    if (analytic) { return airlight(k, ap, a, b); }
    return angular(k, dir, ap, a, b, n);
}

// The interval of the ray inside spot k's outer cone, intersected with [0, len] (empty: x ≥ y).
// The cone is f(t) = (w·a)² − cos²·|w|² ≥ 0 with w·a > 0, w(t) = w0 + t·dir; a ray meets the
// (convex) cone in one interval. Analytic, where the paper rasterised the light frustum.
fn cone_interval(k: u32, dir: vec3<f32>, len: f32) -> vec2<f32> {
    let axis = lights.lights[k].direction.xyz;
    let c = lights.lights[k].intensity.w;
    let w0 = camera.position.xyz - lights.lights[k].position.xyz;
    let da = dot(dir, axis);
    let wa = dot(w0, axis);
    let qa = da * da - c * c;
    let qb = 2.0 * (wa * da - c * c * dot(w0, dir));
    let qc = wa * wa - c * c * dot(w0, w0);
    let none = vec2<f32>(1.0, 0.0);
    let disc = qb * qb - 4.0 * qa * qc;
    if (abs(qa) < 1e-9 || disc < 0.0) {
        // Grazing the cone's angle, or no crossing: inside everywhere or nowhere.
        return select(none, vec2<f32>(0.0, len), wa > 0.0 && qc >= 0.0);
    }
    let sq = sqrt(disc);
    let t_lo = min((-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa));
    let t_hi = max((-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa));
    var iv = none;
    if (qa < 0.0) {
        // Inside between the roots, if that stretch is on the front nappe.
        if (dot(w0 + dir * (0.5 * (t_lo + t_hi)), axis) > 0.0) { iv = vec2<f32>(t_lo, t_hi); }
    } else if (da > 0.0) {
        // Heading along the axis: inside from the far root on.
        iv = vec2<f32>(t_hi, 3.4e38);
    } else {
        iv = vec2<f32>(-3.4e38, t_lo);
    }
    return vec2<f32>(max(iv.x, 0.0), min(iv.y, len));
}

// Component k of v (lavapipe mishandles dynamically indexed vector components).
fn channel(v: vec4<f32>, k: u32) -> f32 {
    return dot(v, vec4<f32>(vec4<u32>(0u, 1u, 2u, 3u) == vec4<u32>(k)));
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    // At 1/scale resolution (§3.3) each fragment stands for the full-resolution pixel at the
    // middle of its block; `upsample.wgsl` spreads it back with a depth-aware filter.
    let scale = hybrid.scale;
    let full = floor(frag.xy - 0.5) * scale + floor(0.5 * scale) + 0.5;
    let px = vec2<i32>(full);
    let dir = camera_ray_dir(camera, full);
    let len = pixel_ray_length(px, dir);
    // The shadow volumes were rasterised at this pass's resolution, each pixel at the ray of `full`.
    let here = vec2<i32>(frag.xy);
    let fronts = textureLoad(volume_front, here, i32(LIGHT / 4u), 0);
    let backs = textureLoad(volume_back, here, i32(LIGHT / 4u), 0);
    let n = hybrid.samples;
    var l_in = vec3<f32>(0.0);
    // This pipeline handles light LIGHT (common::resolve per-light mode): with the light index a
    // compile-time constant, lavapipe (Mesa 22.3) compiles the nested march; with a loop over
    // lights around it, it crashes. Iteration 0 integrates [span.x, a], 1 integrates [b, span.y],
    // then come the march steps between the shadow polygons and a last one closes a lit run.
    let k = LIGHT;
    var span = vec2<f32>(0.0, len);
    if (light_kind(k) == LIGHT_SPOT) { span = cone_interval(k, dir, len); }
    var ap = Approach(0.0, 1.0);
    if (light_kind(k) != LIGHT_DIRECTIONAL) { ap = approach(k, dir); }
    var a = span.y;
    var b = span.y;
    var steps = 0u;
    let back = channel(backs, k % 4u);
    if (back >= 0.0) {
        // Shadow polygons on this ray: march between the first and the last.
        a = clamp(channel(fronts, k % 4u), span.x, span.y);
        b = clamp(back, span.x, span.y);
        // No march when every polygon lies behind the surface or outside the spot's cone.
        steps = select(0u, n, b > a);
    }
    // No polygon is crossed before a or after b, so visibility is constant on each of those
    // segments: one shadow-map test at its middle says whether it is lit. (The paper assumes both
    // lit unless the eye is in shadow; a ray that ends inside a shadow volume — a room lit through
    // a window — breaks that assumption.)
    let lit_before = shadow_visibility(k, camera.position.xyz + dir * (0.5 * (span.x + a))) > 0.5;
    let lit_after = shadow_visibility(k, camera.position.xyz + dir * (0.5 * (b + span.y))) > 0.5;
    var lit_here = span.x < span.y;
    let dt = (b - a) / f32(max(steps, 1u));
    if (steps > 0u) {
        atomicAdd(&counters[0], 1u);
        atomicAdd(&counters[1], steps);
    }
    var run_start = -1.0;
    for (var i = 0u; lit_here && i < steps + 3u; i++) {
        var seg = vec2<f32>(0.0, 0.0);
        var m = n;
        if (i == 0u) {
            seg = select(vec2<f32>(0.0), vec2<f32>(span.x, a), lit_before);
        } else if (i == 1u) {
            seg = select(vec2<f32>(0.0), vec2<f32>(b, span.y), lit_after);
        } else {
            let s = i - 2u;
            let t0 = a + f32(s) * dt;
            var vis = false;
            if (s < steps) { vis = shadow_visibility(k, camera.position.xyz + dir * (t0 + 0.5 * dt)) > 0.5; }
            if (vis && run_start < 0.0) { run_start = t0; }
            if (!vis && run_start >= 0.0) {
                seg = vec2<f32>(run_start, t0);
                m = max(n / 8u, 2u);
                run_start = -1.0;
            }
        }
        if (seg.y > seg.x) { l_in += lit(k, dir, ap, seg.x, seg.y, m); }
    }
    var base = vec3<f32>(0.0);
    if (LIGHT == 0u) {
        base = textureLoad(surface, px, 0).rgb + ambient_fog(dir, len);
    }
    // Alpha carries the ray length for the bilateral upsample (the AOV's alpha is unused).
    return Out(vec4<f32>(l_in, len), vec4<f32>(base + l_in, 1.0));
}
