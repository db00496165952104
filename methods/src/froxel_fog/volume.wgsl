// Froxel volume passes (Wronski 2014; Hillaire 2015): `inject` adds σ_s p V I e^(−σ_t r)/r² of one
// light at one (optionally jittered) point per froxel; `integrate` accumulates each froxel column
// front to back with Hillaire's per-slice integral (S − S e^(−σ_t d)) / σ_t. Needs PRELUDE and grid.wgsl.

@group(1) @binding(0) var<uniform> froxel: Froxel;
// In-scatter source S (rgb, W m⁻³ sr⁻¹ per unit radiance) per froxel, x fastest then y then slice.
@group(1) @binding(1) var<storage, read_write> source: array<vec4<f32>>;
// Integrated in-scatter at each slice's far boundary, slice k in tile (k % tiles_x, k / tiles_x).
@group(1) @binding(2) var volume: texture_storage_2d<rgba32float, write>;

fn hash01(p: vec3<u32>, f: u32) -> f32 {
    var h = p.x * 1973u + p.y * 9277u + p.z * 5867u + f * 26699u;
    h = (h ^ (h >> 13u)) * 0x5bd1e995u;
    h = h ^ (h >> 15u);
    return f32(h & 0xffffffu) / 16777216.0;
}

// The ray through the centre of froxel column (x, y), clamped to the viewport.
fn column_dir(x: u32, y: u32) -> vec3<f32> {
    let ps = f32(froxel.pixel_size);
    let frag = min(vec2<f32>(f32(x) + 0.5, f32(y) + 0.5) * ps, camera.viewport.xy);
    return camera_ray_dir(camera, frag);
}

// Distance along a ray of far distance `far_t` to depth fraction u ∈ [0, 1] of the grid.
fn slice_distance(far_t: f32, u: f32) -> f32 {
    return far_t * pow(u, froxel.depth_exponent);
}

// The light this pipeline injects (one dispatch per light that reaches the frustum, so a light
// that cannot costs nothing), and whether it is the first one this frame: the first stores its
// source, the others add theirs. Both fold away as pipeline constants.
override LIGHT: u32 = 0u;
override FIRST: bool = true;

// Light k's in-scatter source at x for a camera ray along dir, per unit σ_s:
// p(θ) V I(ω) e^(−σ_t r)/r² (local lights) or p(θ) V E (directional light, not attenuated).
fn light_source(k: u32, x: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        let dir_l = lights.lights[k].direction.xyz;
        return lights.lights[k].intensity.rgb * phase(medium, dot(dir_l, -dir)) * shadow_visibility(k, x);
    }
    let w = x - lights.lights[k].position.xyz;
    let r2 = max(dot(w, w), 1e-12);
    let r = sqrt(r2);
    let i = light_intensity(k, w);
    return i * phase(medium, dot(w / r, -dir)) * shadow_visibility(k, x) * transmittance(medium, r) / r2;
}

@compute @workgroup_size(4, 4, 4)
fn inject(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y || id.z >= froxel.slices) {
        return;
    }
    let dir = column_dir(id.x, id.y);
    let far_t = camera_far_distance(camera, dir);
    let offset = select(0.5, hash01(id, froxel.frame), froxel.jitter != 0u);
    let n = f32(froxel.slices);
    let t0 = slice_distance(far_t, f32(id.z) / n);
    let t1 = slice_distance(far_t, f32(id.z + 1u) / n);
    let t = mix(t0, t1, offset);
    let i = (id.z * froxel.grid_y + id.y) * froxel.grid_x + id.x;
    var s = medium.sigma_s.rgb * light_source(LIGHT, camera.position.xyz + dir * t, dir);
    if (!FIRST) {
        s += source[i].rgb;
    }
    source[i] = vec4<f32>(s, 0.0);
}

@compute @workgroup_size(8, 8, 1)
fn integrate(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y) {
        return;
    }
    let far_t = camera_far_distance(camera, column_dir(id.x, id.y));
    let n = f32(froxel.slices);
    let sigma_t = medium.sigma_t.rgb;
    var l = vec3<f32>(0.0);
    var tr = vec3<f32>(1.0);
    var t0 = 0.0;
    for (var k = 0u; k < froxel.slices; k++) {
        let t1 = slice_distance(far_t, f32(k + 1u) / n);
        let d = t1 - t0;
        let s = source[(k * froxel.grid_y + id.y) * froxel.grid_x + id.x].rgb;
        let slice_tr = exp(-sigma_t * d);
        // Hillaire 2015: ∫_0^d S e^(−σt x) dx = (S − S e^(−σt d)) / σt; → S d as σt → 0.
        let safe = max(sigma_t, vec3<f32>(1e-12));
        let integral = select(s * (vec3<f32>(1.0) - slice_tr) / safe, s * d, sigma_t * d < vec3<f32>(1e-5));
        l += tr * integral;
        tr *= slice_tr;
        t0 = t1;
        textureStore(volume, tile_texel(froxel, id.x, id.y, k), vec4<f32>(l, 1.0));
    }
}
