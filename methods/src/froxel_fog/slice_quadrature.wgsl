// A local light's in-scatter over a whole froxel slice (knob `falloff` = quadrature). Near the
// light the source varies along the slice faster than one sample resolves it: 1/r² peaks where
// the ray passes the light, and the light leg's optical depth and the attenuation toward the eye
// inside the slice change with it, so Hillaire's slice integral of one constant sample is off
// (a point light deep in a dense particle read 1.12× the reference's mean in-scatter at 64 slices,
// 1.01× at 256). Where the slice spans more than QUADRATURE_SPAN rad seen from the light, the
// source is instead ∫ f(t) e^(−σ_t (t − t0)) / r² dt over the slice, f = I(ω) p(θ) V e^(−σ_t r)
// e^(−τ_particles), by QUADRATURE_PANELS two-node Gauss–Legendre panels uniform in the angle
// ψ = atan((t − t_c)/h) (dt / r² = dψ / h, as common light_segments.wgsl's local_quadrature), and
// stored as the constant S whose slice integral is that; elsewhere the one sample of `slice`.
// Needs volume.wgsl (light_source, froxel_visibility, particle_transmittance).

// Knob `falloff` = quadrature.
override SLICE_QUADRATURE: bool = false;
const QUADRATURE_PANELS: u32 = 4u;
// Slices seen from the light under less than this (rad) keep the one sample: 1/r² changes by
// less than ~10 % across them.
const QUADRATURE_SPAN: f32 = 0.2;

// The ray e + dir t's closest approach to c: (t_c, h), h widened by the froxel column's
// footprint (a disc of radius spread · t_c; mean_inverse_square).
fn closest_approach(e: vec3<f32>, dir: vec3<f32>, c: vec3<f32>, spread: f32) -> vec2<f32> {
    let w0 = e - c;
    let tc = -dot(w0, dir);
    let a = spread * max(tc, 0.0);
    let h2 = max(dot(w0, w0) - tc * tc, 0.0) + 0.25 * a * a;
    return vec2<f32>(tc, max(sqrt(h2), 1e-4 * length(w0) + 1e-9));
}

// The extinction toward the eye inside one slice: the background's σ_t over all of it and the
// particles' over the span [a, b] they occupy (their mean τ over the slice gathered there).
struct SliceExtinction {
    t0: f32,
    background: vec3<f32>,
    a: f32,
    b: f32,
    particles: f32,
};

// ∫_lo^hi f(t) e^(−τ(t0 → t)) / r² dt along the ray along dir for local light k (g: the ray's
// closest approach (t_c, h) to it), f = I(ω) p(θ) V e^(−σ_t r) e^(−τ_particles(light → x)), by
// QUADRATURE_PANELS two-node Gauss–Legendre panels uniform in ψ = atan((t − t_c)/h).
fn light_integral(k: u32, dir: vec3<f32>, g: vec2<f32>, lo: f32, hi: f32, x: SliceExtinction) -> vec3<f32> {
    let e = view.position.xyz;
    let c = lights.lights[k].position.xyz;
    let p0 = atan((lo - g.x) / g.y);
    let dp = (atan((hi - g.x) / g.y) - p0) / f32(QUADRATURE_PANELS);
    var sum = vec3<f32>(0.0);
    for (var n = 0u; n < 2u * QUADRATURE_PANELS; n++) {
        // Nodes ±1/√3 of each panel's half-width around its middle.
        let node = select(-0.28867513459, 0.28867513459, (n & 1u) == 1u);
        let psi = p0 + (f32(n / 2u) + 0.5 + node) * dp;
        // sin/cos, not tan(): lavapipe crashed compiling tan() in a loop (light_segments.wgsl).
        let t = g.x + g.y * sin(psi) / cos(psi);
        let p = e + dir * t;
        let w = p - c;
        let r = max(length(w), 1e-9);
        let f = light_intensity(k, w) * phase(medium, dot(w / r, -dir)) * froxel_visibility(k, p)
            * transmittance_along(medium, p, -w / r, r) * particle_transmittance(k, p);
        let to_eye = x.background * max(t - x.t0, 0.0) + x.particles * clamp(t - x.a, 0.0, x.b - x.a);
        sum += f * exp(-to_eye);
    }
    // dt / r² = dψ / h; each node weighs half its panel.
    return sum * (0.5 * dp / g.y);
}

// Light k's in-scatter source S of froxel i (the slice [t0, t1] of the ray along dir, sampled at
// t; `fog` the slice's mean height-fog density), as the slice integral wants it.
fn slice_source(k: u32, i: u32, dir: vec3<f32>, t0: f32, t1: f32, t: f32, spread: f32, fog: f32) -> vec3<f32> {
    let e = view.position.xyz;
    let sigma_s = froxel_sigma_s(i) * fog;
    let one_sample = sigma_s * light_source(k, dir, t0, t1, t, spread) * particle_transmittance(k, e + dir * t);
    if (!SLICE_QUADRATURE || light_kind(k) == LIGHT_DIRECTIONAL) {
        return one_sample;
    }
    let g = closest_approach(e, dir, lights.lights[k].position.xyz, spread);
    if (atan((t1 - g.x) / g.y) - atan((t0 - g.x) / g.y) <= QUADRATURE_SPAN) {
        return one_sample;
    }
    let d = max(t1 - t0, 1e-9);
    var x = SliceExtinction(t0, medium.sigma_t.rgb * fog, t0, t0, 0.0);
    var s = medium.sigma_s.rgb * fog * light_integral(k, dir, g, t0, t1, x);
    let tau = froxel_particle_tau(i);
    if (tau > 0.0) {
        // The particles' σ_s and τ, gathered from the whole slice into the span they occupy.
        let v = density[i];
        x.a = clamp(v.moment.y, t0, t1);
        x.b = max(clamp(v.moment.z, t0, t1), x.a + 1e-6 * d);
        let gather = d / (x.b - x.a);
        x.particles = tau * gather;
        s += v.medium.rgb * gather * light_integral(k, dir, g, x.a, x.b, x);
    }
    // The slice integral of a constant S is S (1 − e^(−σ_t d)) / σ_t (S d where σ_t d → 0).
    let sd = (medium.sigma_t.rgb * fog + tau) * d;
    let per_s = select(d * (vec3<f32>(1.0) - exp(-sd)) / max(sd, vec3<f32>(1e-30)), vec3<f32>(d), sd < vec3<f32>(1e-5));
    return s / per_s;
}
