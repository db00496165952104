// Froxel volume passes (Wronski 2014; Hillaire 2015): `inject` adds σ_s p V I e^(−σ_t r)/r² of one
// light at one (optionally jittered) point per froxel; `integrate` accumulates each froxel column
// front to back with Hillaire's per-slice integral (S − S e^(−σ_t d)) / σ_t. Needs PRELUDE,
// grid.wgsl, extinction.wgsl and temporal.wgsl (the history bindings).

@group(1) @binding(0) var<uniform> froxel: Froxel;
// In-scatter source S (rgb, W m⁻³ sr⁻¹ per unit radiance) per froxel, x fastest then y then slice;
// a: with history revisit and a moved camera, this frame's lighting (summed over channels) at
// the centre of the froxel of the previous frame's grid with the same index (temporal.wgsl).
@group(1) @binding(1) var<storage, read_write> source: array<vec4<f32>>;
// Integrated in-scatter at each slice's far boundary, slice k in tile (k % tiles_x, k / tiles_x).
@group(1) @binding(2) var volume: texture_storage_2d<rgba32float, write>;
// Particle media (PARTICLES): per froxel the particles' mean σ_s (rgb) and τ (a), the light grids
// and their optical depths (extinction.wgsl, filled by particles.wgsl).
@group(1) @binding(5) var<storage, read> density: array<Voxel>;
@group(1) @binding(6) var<uniform> particle_medium: ParticleMedium;
@group(1) @binding(7) var<storage, read> optical_depth: array<f32>;

// The camera the froxel grid is laid out for: this frame's (`camera`, set first by every entry
// point), or the previous frame's while `inject` revisits its grid (history revisit).
var<private> view: Camera;

// Whether the scene's medium has particles (voxelised into `density`); false: homogeneous.
override PARTICLES: bool = false;

// Index of froxel (x, y, slice k) in the source and history buffers.
fn froxel_index(x: u32, y: u32, k: u32) -> u32 {
    return (k * froxel.grid_y + y) * froxel.grid_x + x;
}

// A fixed per-froxel rotation in [0, 1)³ of the jitter sequence (Cranley–Patterson), so that
// neighbouring froxels do not sample the same sub-position in the same frame.
fn froxel_rotation(p: vec3<u32>) -> vec3<f32> {
    var h = p.x * 1973u + p.y * 9277u + p.z * 5867u + 26699u;
    var out = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        h = (h ^ (h >> 13u)) * 0x5bd1e995u;
        h = h ^ (h >> 15u);
        out[c] = f32(h & 0xffffffu) / 16777216.0;
    }
    return out;
}

// The sample position within froxel id, in cell units, of point u of its jittered range
// (`jitter_unit`): its centre without temporal accumulation; else u over the cell (jitter 2) or
// along the centre ray (jitter 1), in depth within the slice's share in front of the column's
// nearest surface (surface_bound.wgsl).
fn sample_offset(id: vec3<u32>, u: vec3<f32>) -> vec3<f32> {
    var o = u;
    o.z *= front_share(id.x, id.y, id.z);
    let centre = vec3<f32>(0.5);
    return select(select(centre, vec3<f32>(0.5, 0.5, o.z), froxel.jitter == 1u), o, froxel.jitter == 2u);
}

// This frame's jittered point u in [0, 1)³ of froxel id (Halton, rotated per froxel).
fn jitter_unit(id: vec3<u32>) -> vec3<f32> {
    return fract(froxel.offset.xyz + froxel_rotation(id));
}

// Knob `jitter_pair` (with temporal accumulation): each frame also injects the mirror image
// 1 − u of its jittered point u through the froxel's centre and takes the pair's mean
// (antithetic variates): where the source varies linearly across the froxel the pair's mean is
// the froxel's mean exactly, so a frame's estimate carries only the source's curvature, not the jitter's first-order error — the
// frame-to-frame change a single jittered sample adds (flicker) is gone, and a history dropped by
// reject, range or revisit can restart from this frame's pair (temporal.wgsl).
override JITTER_PAIR: bool = false;


// The ray through screen position (x + o.x, y + o.y) · pixel_size of the grid, clamped to the
// viewport (o = ½: the froxel column's centre).
fn grid_ray(x: u32, y: u32, o: vec2<f32>) -> vec3<f32> {
    let ps = froxel.pixel_size;
    let frag = min((vec2<f32>(f32(x), f32(y)) + o) * ps, view.viewport.xy);
    return camera_ray_dir(view, frag);
}

// The ray through the centre of froxel column (x, y).
fn column_dir(x: u32, y: u32) -> vec3<f32> {
    return grid_ray(x, y, vec2<f32>(0.5));
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
// Knob `falloff`: a local light's 1/r² averaged over the froxel in closed form (true) or taken
// at the sample point (false, Wronski's point sample).
override SLICE_FALLOFF: bool = true;

// The mean of 1/r² (r the distance to a light at c) over the slice [t0, t1] of the ray e + dir t
// and over the froxel column's footprint around it, a disc of radius a = spread · t_c at the
// ray's closest approach t_c (spread 0: the ray alone). Along the ray
// ∫ dt / (h² + (t − t_c)²) = (atan((t1 − t_c)/h) − atan((t0 − t_c)/h)) / h; the footprint
// replaces h² by h² + a²/4, which keeps the far field (h ≫ a) and gives the disc's exact mean of
// the whole line's integral π/h on the axis (π · 2/a): a ray through the light reads what the
// pixels around it average, not the 1/h peak of the one ray.
fn mean_inverse_square(e: vec3<f32>, dir: vec3<f32>, c: vec3<f32>, t0: f32, t1: f32, spread: f32) -> f32 {
    let g = closest_approach(e, dir, c, spread);
    let angle = atan((t1 - g.x) / g.y) - atan((t0 - g.x) / g.y);
    return angle / (g.y * max(t1 - t0, 1e-9));
}

// Shadow-map visibility with the `shadow_filter` knob: one texel (none) or 3 × 3 PCF.
override SHADOW_PCF: bool = false;

fn froxel_visibility(k: u32, x: vec3<f32>) -> f32 {
    if (SHADOW_PCF) { return shadow_visibility_pcf(k, x); }
    return shadow_visibility(k, x);
}

// Light k's in-scatter source per unit σ_s on the slice [t0, t1] of the camera ray along dir,
// evaluated at t (the sample point): p(θ) V I(ω) e^(−σ_t r) / r² for local lights (1/r² the
// froxel mean with SLICE_FALLOFF, `spread` as in mean_inverse_square), p(θ) V E for directional
// light (not attenuated).
fn light_source(k: u32, dir: vec3<f32>, t0: f32, t1: f32, t: f32, spread: f32) -> vec3<f32> {
    let e = view.position.xyz;
    let x = e + dir * t;
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        let dir_l = lights.lights[k].direction.xyz;
        return lights.lights[k].intensity.rgb * phase(medium, dot(dir_l, -dir)) * froxel_visibility(k, x);
    }
    let c = lights.lights[k].position.xyz;
    let w = x - c;
    let r2 = max(dot(w, w), 1e-12);
    let r = sqrt(r2);
    var falloff = 1.0 / r2;
    if (SLICE_FALLOFF) {
        falloff = mean_inverse_square(e, dir, c, t0, t1, spread);
    }
    let i = light_intensity(k, w);
    let light_leg = transmittance_along(medium, x, -w / r, r);
    return i * phase(medium, dot(w / r, -dir)) * froxel_visibility(k, x) * light_leg * falloff;
}

// The particles' transmittance between light k and x (their self-shadowing); 1 without particles.
fn particle_transmittance(k: u32, x: vec3<f32>) -> f32 {
    if (!PARTICLES) {
        return 1.0;
    }
    return exp(-particle_depth_to_light(k, x));
}

// σ_s of froxel i: the background medium's plus the particles' mean.
fn froxel_sigma_s(i: u32) -> vec3<f32> {
    if (!PARTICLES) {
        return medium.sigma_s.rgb;
    }
    return medium.sigma_s.rgb + density[i].medium.rgb;
}

// Where the slice [t0, t1] of froxel i is sampled: at fraction o of it, or, where it holds
// particles, at their extinction-weighted mean distance (a slice thicker than a smoke column
// would otherwise light all of it as its middle is lit).
fn sample_distance(i: u32, t0: f32, t1: f32, o: f32) -> f32 {
    let t = mix(t0, t1, o);
    if (!PARTICLES) {
        return t;
    }
    let v = density[i];
    return select(t, clamp(v.moment.x / max(v.medium.a, 1e-30), t0, t1), v.medium.a > 0.0);
}

// Extinction of froxel i contributed by particles (grey; the background's is medium.sigma_t).
fn froxel_particle_tau(i: u32) -> f32 {
    if (!PARTICLES) {
        return 0.0;
    }
    return density[i].medium.a;
}

// The angular radius of a disc with a froxel column's cross-section near screen position frag
// (rad): √(area / π) of the column's spacing² — 0 when the jitter already spreads the sample
// over the column (jitter 2, temporal accumulation).
fn footprint_spread(frag: vec2<f32>) -> f32 {
    let ps = froxel.pixel_size;
    let d0 = camera_ray_dir(view, frag);
    let dx = length(camera_ray_dir(view, frag + vec2<f32>(ps, 0.0)) - d0);
    let dy = length(camera_ray_dir(view, frag + vec2<f32>(0.0, ps)) - d0);
    return select(sqrt(dx * dy / PI), 0.0, froxel.jitter == 2u);
}

// World position of point o (cell units) of froxel id.
fn froxel_point(id: vec3<u32>, o: vec3<f32>) -> vec3<f32> {
    let dir = grid_ray(id.x, id.y, o.xy);
    let far_t = camera_far_distance(view, dir);
    let n = f32(froxel.slices);
    let t = slice_distance(far_t, (f32(id.z) + o.z) / n);
    return view.position.xyz + dir * t;
}

// Light LIGHT's source S at point o (cell units) of froxel id, or 0 where the froxel scatters
// nothing (particle media without a background).
fn froxel_source(id: vec3<u32>, o: vec3<f32>) -> vec3<f32> {
    let dir = grid_ray(id.x, id.y, o.xy);
    let far_t = camera_far_distance(view, dir);
    let n = f32(froxel.slices);
    // The point moves within the slice's depth interval (linearly in depth, as before).
    let t0 = slice_distance(far_t, f32(id.z) / n);
    let t1 = slice_distance(far_t, f32(id.z + 1u) / n);
    let i = froxel_index(id.x, id.y, id.z);
    let t = sample_distance(i, t0, t1, o.z);
    // Height fog: the slice's mean σ_s along the sample's ray, as `integrate` takes its mean σ_t,
    // so that Hillaire's slice integral gives σ_s/σ_t (1 − e^(−τ)) exactly.
    let fog = fog_mean_density(medium, view.position.xyz + dir * t0, dir, t1 - t0);
    if (all(froxel_sigma_s(i) * fog <= vec3<f32>(0.0))) {
        return vec3<f32>(0.0);
    }
    let spread = footprint_spread((vec2<f32>(f32(id.x), f32(id.y)) + o.xy) * froxel.pixel_size);
    return slice_source(LIGHT, i, dir, t0, t1, t, spread, fog);
}

@compute @workgroup_size(4, 4, 4)
fn inject(@builtin(global_invocation_id) id: vec3<u32>) {
    view = camera;
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y || id.z >= froxel.slices) {
        return;
    }
    let i = froxel_index(id.x, id.y, id.z);
    let u = jitter_unit(id);
    var s = froxel_source(id, sample_offset(id, u));
    if (TEMPORAL && JITTER_PAIR) {
        s = 0.5 * (s + froxel_source(id, sample_offset(id, 1.0 - u)));
    }
    if (!FIRST) {
        s += source[i].rgb;
    }
    source[i] = vec4<f32>(s, select(source[i].a, 0.0, FIRST) + revisited(id));
    // History reject, range (temporal.wgsl): the source at the froxel's centre too, and its sum
    // over channels — deterministic, so a change in it is a change in the lighting, not the jitter.
    if (TEMPORAL && HISTORY >= 2u) {
        var c = froxel_source(id, vec3<f32>(0.5));
        if (!FIRST) {
            c += centre.at[i].rgb;
        }
        centre.at[i] = vec4<f32>(c, c.r + c.g + c.b);
    }
}

// History revisit (temporal.wgsl) with a moved camera: light LIGHT's source at the centre of
// froxel id of the previous frame's grid, where its history was sampled, summed over channels;
// else 0.
fn revisited(id: vec3<u32>) -> f32 {
    if (!TEMPORAL || HISTORY != 4u || froxel.moved == 0u) {
        return 0.0;
    }
    view = previous_camera();
    let r = froxel_source(id, vec3<f32>(0.5));
    view = camera;
    return r.r + r.g + r.b;
}

// Whether `integrate` reads the temporally accumulated source (temporal.wgsl) or this frame's.
override TEMPORAL: bool = false;

fn injected(i: u32) -> vec3<f32> {
    if (TEMPORAL && HISTORY >= 2u) {
        // History reject, range, revisit: the centre sample plus the accumulated residual (the
        // residual, reprojected from a neighbouring point, may exceed a dark centre: no source is
        // negative).
        return max(centre.at[i].rgb + accumulated[i].rgb, vec3<f32>(0.0));
    }
    if (TEMPORAL) {
        return accumulated[i].rgb;
    }
    return source[i].rgb;
}

@compute @workgroup_size(8, 8, 1)
fn integrate(@builtin(global_invocation_id) id: vec3<u32>) {
    view = camera;
    if (id.x >= froxel.grid_x || id.y >= froxel.grid_y) {
        return;
    }
    let far_t = camera_far_distance(camera, column_dir(id.x, id.y));
    let n = f32(froxel.slices);
    var l = vec3<f32>(0.0);
    var tr = vec3<f32>(1.0);
    // The particles' transmittance alone (grey), for the surfaces behind (particle_surface.wgsl).
    var tr_particles = 1.0;
    var t0 = 0.0;
    let dir = column_dir(id.x, id.y);
    for (var k = 0u; k < froxel.slices; k++) {
        let t1 = slice_distance(far_t, f32(k + 1u) / n);
        let d = t1 - t0;
        let i = froxel_index(id.x, id.y, k);
        let s = injected(i);
        let tau = froxel_particle_tau(i);
        // Height fog: the slice's mean σ_t, so e^(−σ_t d) is its exact transmittance.
        let fog = fog_mean_density(medium, camera.position.xyz + dir * t0, dir, d);
        let sigma_t = medium.sigma_t.rgb * fog + tau;
        let slice_tr = exp(-sigma_t * d);
        // Hillaire 2015: ∫_0^d S e^(−σt x) dx = (S − S e^(−σt d)) / σt; → S d as σt → 0.
        let safe = max(sigma_t, vec3<f32>(1e-12));
        let integral = select(s * (vec3<f32>(1.0) - slice_tr) / safe, s * d, sigma_t * d < vec3<f32>(1e-5));
        l += tr * integral;
        tr *= slice_tr;
        tr_particles *= exp(-tau * d);
        t0 = t1;
        // rgb: in-scatter from the eye to the slice's far end; a: the particles' transmittance.
        textureStore(volume, tile_texel(froxel, id.x, id.y, k), vec4<f32>(l, tr_particles));
    }
}
