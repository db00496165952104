// particle-march: the camera ray streamed through the particle grid (particle_trace.wgsl), each
// sphere's piece in each cell integrated per light by Gauss–Legendre quadrature, exact optical
// depth on every leg; the background medium's in-scatter marched over the whole ray. Writes the
// in-scatter and the eye-attenuated surface (common::particles::surfaces). Needs PRELUDE,
// FULLSCREEN, particle_trace.wgsl and particle_resolve.wgsl.

// Gauss–Legendre nodes per piece and light: 1, 2, 4 or 8 (the `points` knob).
override POINTS: u32 = 4u;
// Equal panels per piece and light, each with POINTS nodes (the `panels` knob).
override PANELS: u32 = 1u;
// Midpoint steps of the background medium's march per light; 0: no background scattering.
override BACKGROUND_STEPS: u32 = 64u;

// Gauss–Legendre node i on [0, 1] and its weight (the weights of a rule sum to 1); the rule of
// order n is at i = n − 1 … 2n − 2 (n = 1, 2, 4, 8). A switch, not a const array: lavapipe
// (Mesa 22.3) read a dynamically indexed const array wrongly (the error grew with the order).
fn gauss_legendre(i: u32) -> vec2<f32> {
    switch i {
        case 0u: { return vec2<f32>(0.5, 1.0); }
        case 1u: { return vec2<f32>(0.21132487, 0.5); }
        case 2u: { return vec2<f32>(0.78867513, 0.5); }
        case 3u: { return vec2<f32>(0.06943184, 0.17392742); }
        case 4u: { return vec2<f32>(0.33000948, 0.32607258); }
        case 5u: { return vec2<f32>(0.66999052, 0.32607258); }
        case 6u: { return vec2<f32>(0.93056816, 0.17392742); }
        case 7u: { return vec2<f32>(0.01985507, 0.05061427); }
        case 8u: { return vec2<f32>(0.10166676, 0.11119052); }
        case 9u: { return vec2<f32>(0.23723380, 0.15685332); }
        case 10u: { return vec2<f32>(0.40828268, 0.18134189); }
        case 11u: { return vec2<f32>(0.59171732, 0.18134189); }
        case 12u: { return vec2<f32>(0.76276620, 0.15685332); }
        case 13u: { return vec2<f32>(0.89833324, 0.11119052); }
        default: { return vec2<f32>(0.98014493, 0.05061427); }
    }
}

// Light k's radiance scattered toward the eye per unit σ_s at x on the ray along dir: p(θ),
// I(ω) / r² (or E), shadow-map visibility, the particles' exact transmittance toward the light
// and, for a local light, the background's e^(−σ_t r) (ARCHITECTURE §1: directional light is
// not attenuated by the background on the light leg).
fn light_at(k: u32, x: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    let cloud = exp(-light_leg_depth(k, x)) * shadow_visibility(k, x);
    let w = x - lights.lights[k].position.xyz;
    let r2 = max(dot(w, w), 1e-12);
    let r = sqrt(r2);
    // One exit for both kinds (no early return in the hot loops).
    var out = vec3<f32>(0.0);
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        let l = lights.lights[k].direction.xyz;
        out = lights.lights[k].intensity.rgb * phase(medium, dot(l, -dir)) * cloud;
    } else {
        let i = light_intensity(k, w);
        out = i * phase(medium, dot(w / r, -dir)) * transmittance(medium, r) * (cloud / r2);
    }
    return out;
}

// Where light k's integration variable puts node u ∈ [0, 1] of [a, b] on the ray from the eye
// along dir: (t, dt/du). Equal steps in t for directional light; for a local light in Biri's
// angle φ = atan((t − t₀)/h) (t₀ the ray's closest approach to the light, h the distance
// there), where dt/r² = dφ/h: the 1/r² peak of a light near the ray becomes smooth.
fn light_node(k: u32, dir: vec3<f32>, a: f32, b: f32, u: f32) -> vec2<f32> {
    var node = vec2<f32>(a + (b - a) * u, b - a);
    let to_light = lights.lights[k].position.xyz - camera.position.xyz;
    let t0 = dot(to_light, dir);
    let h = length(to_light - dir * t0);
    if (light_kind(k) != LIGHT_DIRECTIONAL && h > 1e-6 * max(b - a, 1e-6)) {
        let pa = atan((a - t0) / h);
        let span = atan((b - t0) / h) - pa;
        let phi = pa + span * u;
        // sin/cos, not tan(): lavapipe crashes compiling tan() in a loop.
        let c = cos(phi);
        node = vec2<f32>(t0 + h * sin(phi) / c, span * h / (c * c));
    }
    return node;
}

// ∫ over piece `b` of the batch of f(t) dt by PANELS × POINTS nodes in light k's variable, f =
// light k's radiance at t times the eye leg's transmittance: the depth at the piece's cell
// entry, the cell's own pieces up to t (exact, from the grid's list of that cell) and the
// background's e^(−σ_t t). The caller multiplies by the piece's σ_s.
fn piece_light(k: u32, dir: vec3<f32>, b: u32) -> vec3<f32> {
    let eye = camera.position.xyz;
    let piece = batch_t[b];
    let cell = batch_id[b].y;
    let first = POINTS - 1u;
    var sum = vec3<f32>(0.0);
    // Panels and points in one loop (lavapipe mishandles loops nested too deep; see trace_particles).
    for (var n = 0u; n < PANELS * POINTS; n++) {
        let gl = gauss_legendre(first + n % POINTS);
        let u = (f32(n / POINTS) + gl.x) / f32(PANELS);
        let node = light_node(k, dir, piece.x, piece.y, u);
        let tau = piece.z + cell_depth(cell, eye, dir, piece.w, node.x);
        let eye_leg = transmittance(medium, node.x) * exp(-tau);
        sum += light_at(k, eye + dir * node.x, dir) * eye_leg * (gl.y * node.y);
    }
    return sum / f32(PANELS);
}

// The particles' in-scatter along the ray [0, d] and their optical depth over it.
struct Traced {
    inscatter: vec3<f32>,
    depth: f32,
};

// A batch of the camera ray's pieces, front to back cell by cell: (entry, exit, the eye's
// particle depth at the cell's entry, the cell's entry t) and (sphere, cell).
const BATCH: u32 = 32u;
var<private> batch_t: array<vec4<f32>, BATCH>;
var<private> batch_id: array<vec2<u32>, BATCH>;

// The camera ray in two phases per batch: the walk collects up to BATCH pieces, then each is
// integrated. Integrating inside the walk put a shadow ray's walk inside the camera ray's walk,
// and lavapipe (Mesa 22.3) then dropped lanes from the outer loop (too deeply nested divergent
// loops): the optical depth came out short.
fn trace_particles(dir: vec3<f32>, d: f32) -> Traced {
    let eye = camera.position.xyz;
    var w = grid_walk(eye, dir, 0.0, d);
    var out = Traced(vec3<f32>(0.0), 0.0);
    // The current cell's items not yet visited, and the eye's depth at its entry.
    var item = 0u;
    var item_end = 0u;
    var cell_depth = 0.0;
    loop {
        var n = 0u;
        loop {
            if (n >= BATCH) { break; }
            if (item >= item_end) {
                if (!grid_walk_more(w)) { break; }
                w = grid_walk_step(w);
                item = cell_start[w.index];
                item_end = cell_start[w.index + 1u];
                cell_depth = out.depth;
                continue;
            }
            let j = cell_items[item];
            item++;
            let piece = sphere_piece(j, eye, dir, w.enter, w.exit);
            if (piece.y > piece.x) {
                batch_t[n] = vec4<f32>(piece, cell_depth, w.enter);
                batch_id[n] = vec2<u32>(j, w.index);
                n++;
                out.depth += spheres[j].albedo_tau.w * (piece.y - piece.x);
            }
        }
        if (n == 0u) { break; }
        for (var b = 0u; b < n; b++) {
            var lit = vec3<f32>(0.0);
            for (var k = 0u; k < light_count(); k++) {
                lit += piece_light(k, dir, b);
            }
            let s = spheres[batch_id[b].x].albedo_tau;
            out.inscatter += s.rgb * s.w * lit;
        }
    }
    return out;
}

// The background medium's in-scatter over [0, d]: BACKGROUND_STEPS midpoint steps per light in
// its variable (light_node), the eye leg through the particles (exact, accumulated step to
// step) and the background.
fn background_inscatter(dir: vec3<f32>, d: f32) -> vec3<f32> {
    let eye = camera.position.xyz;
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        var t_prev = 0.0;
        var tau = 0.0;
        for (var s = 0u; s < BACKGROUND_STEPS; s++) {
            let node = light_node(k, dir, 0.0, d, (f32(s) + 0.5) / f32(BACKGROUND_STEPS));
            tau += optical_depth(eye, dir, t_prev, node.x);
            t_prev = node.x;
            let eye_leg = transmittance(medium, node.x) * exp(-tau);
            sum += light_at(k, eye + dir * node.x, dir) * eye_leg * node.y;
        }
    }
    return medium.sigma_s.rgb * sum / f32(max(BACKGROUND_STEPS, 1u));
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let ray = pixel_ray(px, frag.xy);
    let traced = trace_particles(ray.dir, ray.d);
    var l_in = traced.inscatter;
    if (BACKGROUND_STEPS > 0u) {
        l_in += background_inscatter(ray.dir, ray.d);
    }
    // `total` here is the harness's surface AOV (ParticleSurfaces::resolve_targets).
    return Out(vec4<f32>(l_in, 1.0), vec4<f32>(surface_or_sky(px, ray) * exp(-traced.depth), 1.0));
}
