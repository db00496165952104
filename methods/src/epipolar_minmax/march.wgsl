// The march at the marched samples (Chen et al. 2011's min-max traversal over the rectified row)
// and the direct march of fix-up pixels. One light per pipeline (LIGHT), so its kind is a
// compile-time constant. Needs PRELUDE, epipolar.wgsl and trees.wgsl.
//
// A local light's integral is taken over the angle φ about the light in the ray's epipolar plane
// instead of the distance t: with D the eye–light distance, α the angle at the eye between the
// ray and the light and h = D sin α the ray's distance from the light, t = D sin φ / sin(α + φ),
// r = h / sin(α + φ) and dt / r² = dφ / h, so ∫ I p e^(−σt (t + r)) / r² dt = ∫ I p e^(−σt (t + r)) / h dφ:
// the 1/r² peak is flattened, and shadow boundaries (light rays) are lines of constant φ.
// A directional light's coordinate is u = t sin β (β: the ray's angle to the light direction).

override LIGHT: u32 = 0u;
// false: test every leaf the ray crosses (a plain march over the rectified row)
override MIN_MAX: bool = true;
// false: the light has no shadow map this run: every ray is lit end to end
override SHADOWED: bool = true;

// Lit runs are integrated by two-point Gauss–Legendre on pieces of at most this many leaves.
const GL_LEAVES: f32 = 4.0;
const HALF_PI: f32 = 1.5707963267949;

// A camera ray in the light's epipolar plane.
struct Ray {
    dir: vec3<f32>,
    len: f32,
    // local light: D, α, h = D sin α; directional: sin β, cos β, depth along the light at the eye
    // (scalars, not a vec3: a vec3 member of a struct passed by value read wrong on lavapipe)
    a: f32,
    b: f32,
    c: f32,
    // the rectified coordinate at the ray's end
    u_end: f32,
};

fn directional() -> bool {
    return light_kind(LIGHT) == LIGHT_DIRECTIONAL;
}

fn make_ray(dir: vec3<f32>, len: f32) -> Ray {
    let eye = camera.position.xyz;
    if (directional()) {
        let e1 = lights.lights[LIGHT].direction.xyz;
        let cb = dot(dir, e1);
        let sb = length(dir - e1 * cb);
        return Ray(dir, len, sb, cb, dot(eye, e1), len * sb);
    }
    let to_l = eye_to_light(LIGHT);
    let d = max(length(to_l), 1e-6);
    let sa = interpolation_scale(LIGHT, dir) / d;
    let alpha = atan2(sa, dot(dir, to_l) / d);
    return Ray(dir, len, d, alpha, d * sa, atan2(len * sa, d - len * cos(alpha)));
}

// Distance along the ray at rectified coordinate u (the ray's end from u_end on).
fn ray_t(r: Ray, u: f32) -> f32 {
    if (u <= 0.0) { return 0.0; }
    if (u >= r.u_end) { return r.len; }
    if (directional()) { return u / max(r.a, 1e-30); }
    return r.a * sin(u) / sin(r.b + u);
}

// Local light: the integrand in φ, I p e^(−σt (t + r)) / h (σ_s applied by the caller).
fn local_integrand(r: Ray, phi: f32) -> vec3<f32> {
    let s = sin(r.b + phi);
    let t = r.a * sin(phi) / s;
    let dist = r.c / s;
    let w = camera.position.xyz + r.dir * t - lights.lights[LIGHT].position.xyz;
    let i = light_intensity(LIGHT, w);
    let path = scattering_path(medium, camera.position.xyz, r.dir, t, -w / dist, dist);
    return i * phase(medium, dot(w, -r.dir) / dist) * path / r.c;
}

// The unshadowed in-scatter (without σ_s) of the ray between rectified coordinates ua < ub.
fn lit(r: Ray, ua: f32, ub: f32, du: f32) -> vec3<f32> {
    if (directional()) {
        // Constant scattering angle: ∫ I p e^(−σt t) dt in closed form (with height fog too).
        let ta = ray_t(r, ua);
        let tb = ray_t(r, ub);
        let ex = attenuated_fog_length(medium, camera.position.xyz, r.dir, ta, tb);
        let l = lights.lights[LIGHT];
        return l.intensity.rgb * phase(medium, dot(l.direction.xyz, -r.dir)) * ex;
    }
    // At most one piece per leaf of the finest row (bounded whatever du is).
    let pieces = u32(clamp(ceil((ub - ua) / (GL_LEAVES * du)), 1.0, f32(epi.leaves)));
    let w = (ub - ua) / f32(pieces);
    let off = 0.5 * w * (1.0 - 0.57735026918963);
    var sum = vec3<f32>(0.0);
    for (var q = 0u; q < pieces; q++) {
        let a = ua + f32(q) * w;
        sum += local_integrand(r, a + off) + local_integrand(r, a + w - off);
    }
    return sum * (0.5 * w);
}

// The light-space distance range (min, max) of the ray over [ua, ub]: to a local light, or
// along the directional light.
fn distance_range(r: Ray, ua: f32, ub: f32) -> vec2<f32> {
    if (directional()) {
        let xa = r.c + ray_t(r, ua) * r.b;
        let xb = r.c + ray_t(r, ub) * r.b;
        return vec2<f32>(min(xa, xb), max(xa, xb));
    }
    let da = r.c / sin(r.b + ua);
    let db = r.c / sin(r.b + ub);
    let closest = ua <= HALF_PI - r.b && HALF_PI - r.b <= ub;
    return vec2<f32>(select(min(da, db), r.c, closest), max(da, db));
}

// One leaf [ua, ub] with stored depth `stored`: the part where the ray is nearer the light
// than the caster (solved exactly), integrated.
fn leaf(r: Ray, ua: f32, ub: f32, stored: f32, du: f32) -> vec3<f32> {
    let b = shadow_bound(LIGHT);
    let limit = stored + b.y;
    if (directional()) {
        // x(t) = x0 + t cos β ≤ limit
        var ta = ray_t(r, ua);
        var tb = ray_t(r, ub);
        if (abs(r.b) < 1e-9) {
            if (r.c > limit) { return vec3<f32>(0.0); }
        } else {
            let t_cross = (limit - r.c) / r.b;
            if (r.b > 0.0) { tb = min(tb, t_cross); } else { ta = max(ta, t_cross); }
        }
        if (tb <= ta) { return vec3<f32>(0.0); }
        // Back to u for `lit` (u = t sin β is linear in t).
        return lit(r, ta * r.a, select(tb * r.a, r.u_end, tb >= r.len), du);
    }
    // h / sin(α + φ) · b.x ≤ limit ⇔ sin(α + φ) ≥ h b.x / limit
    let s = r.c * b.x / max(limit, 1e-30);
    if (limit <= 0.0 || s >= 1.0) { return vec3<f32>(0.0); }
    let psi = asin(s);
    let lo = max(ua, psi - r.b);
    let hi = min(ub, 3.14159265358979 - psi - r.b);
    if (hi <= lo) { return vec3<f32>(0.0); }
    return lit(r, lo, hi, du);
}

// In-scatter (without σ_s) along ray r of slice i: Chen et al.'s traversal — at leaf j, the
// highest aligned node of the tree that lies inside the ray's span and is wholly lit or wholly
// shadowed settles 2^l leaves at once; a mixed leaf is split exactly.
fn march_slice(r: Ray, i: u32) -> vec3<f32> {
    let du = texel_width(slices[i], epi.leaves);
    if (!SHADOWED) { return lit(r, 0.0, r.u_end, du); }
    let b = shadow_bound(LIGHT);
    let j_end = u32(clamp(r.u_end / du, 0.0, f32(epi.leaves - 1u)));
    var sum = vec3<f32>(0.0);
    var skipped = 0u;
    var tested = 0u;
    var j = 0u;
    loop {
        if (j > j_end) { break; }
        var l = 0u;
        if (MIN_MAX) { l = min(min(countTrailingZeros(j), epi.levels), firstLeadingBit(j_end + 1u - j)); }
        loop {
            let n = 1u << l;
            let ua = f32(j) * du;
            let ub = select(min(f32(j + n) * du, r.u_end), r.u_end, j + n > j_end);
            let node = tree[tree_node(i, l, j >> l)];
            let range = distance_range(r, ua, ub) * b.x;
            if (range.y <= node.x + b.y) {
                sum += lit(r, ua, ub, du);
                if (l > 0u) { skipped += n; }
                break;
            }
            if (range.x > node.y + b.y) {
                if (l > 0u) { skipped += n; }
                break;
            }
            if (l == 0u) {
                sum += leaf(r, ua, ub, node.x, du);
                tested += 1u;
                break;
            }
            l -= 1u;
        }
        j += 1u << l;
    }
    atomicAdd(&counters[COUNT_LEAVES_SKIPPED], skipped);
    atomicAdd(&counters[COUNT_LEAVES_TESTED], tested);
    return sum;
}

// One marched sample.
@compute @workgroup_size(64)
fn march(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= atomicLoad(&header[0])) { return; }
    let s = work[id.x];
    let smp = samples[s];
    let ray = camera_ray(smp.uv);
    let l_in = medium.sigma_s.rgb * march_slice(make_ray(ray.xyz, smp.dist), s / epi.samples);
    samples[s].value = vec4<f32>(l_in * interpolation_scale(LIGHT, ray.xyz), 1.0);
}

// A fix-up pixel's ray marched directly against the shadow map: `leaves / 4` midpoint steps in
// the rectified coordinate. The count is uniform on purpose: a loop whose trip count differs
// between the lanes of this pass crashes lavapipe (Mesa 22.3) inside the driver.
fn march_direct(r: Ray) -> vec3<f32> {
    let n = max(epi.leaves / 4u, 8u);
    let du = r.u_end / f32(n);
    var sum = vec3<f32>(0.0);
    for (var q = 0u; q < n; q++) {
        let u = (f32(q) + 0.5) * du;
        let x = camera.position.xyz + r.dir * ray_t(r, u);
        sum += lit(r, u - 0.5 * du, u + 0.5 * du, du) * shadow_visibility(LIGHT, x);
    }
    return sum;
}

@compute @workgroup_size(64)
fn fixup(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= atomicLoad(&header[1])) { return; }
    let p = work[id.x];
    let w = u32(camera.viewport.x);
    let uv = (vec2<f32>(f32(p % w), f32(p / w)) + 0.5) * camera.viewport.zw;
    let ray = camera_ray(uv);
    accum[p] += vec4<f32>(medium.sigma_s.rgb * march_direct(make_ray(ray.xyz, ray.w)), 0.0);
}
