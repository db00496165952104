// Biri et al. 2006, eq. 7 in the project convention (∫ p dω = 1): the direct single scattering
// of point light k over [0, d] of the view ray `dir` from the eye is
//   σ_s I e^(−σ_t t) / h · [Γ(σ_t h, w(d − t)) − Γ(σ_t h, w(−t))],
// with the Γ table indexed by u = λ/(1 + λ) (rows) and w = s/(1 + s), s = (r + y)/h = tan(γ/2 + π/4)
// (columns; y: signed distance along the ray from the light's foot, r = √(y² + h²)).
// Needs PRELUDE and light_segments.wgsl (`wgsl::LDSS` composes both). Mirrors common::gamma.

// Bilinear Γ lookup (R32Float is not filterable without an optional feature).
fn gamma_lookup(tab: texture_2d<f32>, lambda: f32, w: f32) -> f32 {
    let dims = vec2<f32>(textureDimensions(tab));
    let fi = clamp(lambda / (1.0 + lambda) * dims.y, 0.0, dims.y - 1.0);
    let fj = clamp(w * (dims.x - 1.0), 0.0, dims.x - 1.0);
    let i0 = u32(fi);
    let j0 = u32(fj);
    let i1 = min(i0 + 1u, u32(dims.y) - 1u);
    let j1 = min(j0 + 1u, u32(dims.x) - 1u);
    let a = fi - f32(i0);
    let b = fj - f32(j0);
    let r0 = mix(textureLoad(tab, vec2<u32>(j0, i0), 0).r, textureLoad(tab, vec2<u32>(j1, i0), 0).r, b);
    let r1 = mix(textureLoad(tab, vec2<u32>(j0, i1), 0).r, textureLoad(tab, vec2<u32>(j1, i1), 0).r, b);
    return mix(r0, r1, a);
}

// Γ(σ_t h, w) per channel (λ = σ_t h): one bilinear lookup where the scene's σ_t is grey
// (GREY_SIGMA_T, baked: the three channels' λ are then equal, and lavapipe would run all three
// lookups behind a uniform test), else three. Each lookup is four texel loads.
fn gamma_rgb(tab: texture_2d<f32>, lambda: vec3<f32>, w: f32) -> vec3<f32> {
    if (GREY_SIGMA_T) { return vec3<f32>(gamma_lookup(tab, lambda.r, w)); }
    return vec3<f32>(gamma_lookup(tab, lambda.r, w), gamma_lookup(tab, lambda.g, w), gamma_lookup(tab, lambda.b, w));
}

// w = s/(1 + s) with s = (r + y)/h; r + y = h²/(r − y) when y < 0 (no cancellation).
fn gamma_w(y: f32, h: f32) -> f32 {
    let r = sqrt(y * y + h * h);
    let n = select(h * h / (r - y), r + y, y >= 0.0);
    return n / (n + h);
}

// Geometry of light k seen along `dir`: x = t (foot distance), y = h (distance to the ray).
fn ldss_geometry(k: u32, dir: vec3<f32>) -> vec2<f32> {
    let sp = lights.lights[k].position.xyz - camera.position.xyz;
    let t = dot(sp, dir);
    let h = max(length(sp - dir * t), 1e-6);
    return vec2<f32>(t, h);
}

// σ_s I e^(−σ_t t)/h · Γ(σ_t h, w(d − t)) per channel: the term a crossing at distance d adds
// (and what the eye's own term, d = 0, takes away).
fn ldss_term(tab: texture_2d<f32>, k: u32, dir: vec3<f32>, d: f32) -> vec3<f32> {
    let g = ldss_geometry(k, dir);
    let w = gamma_w(d - g.x, g.y);
    let st = medium.sigma_t.rgb;
    let lam = st * g.y;
    let gam = gamma_rgb(tab, lam, w);
    return medium.sigma_s.rgb * lights.lights[k].intensity.rgb * exp(-st * g.x) / g.y * gam;
}

// L_dss over [a, b] of the view ray (eq. 14's lit pieces; eq. 7 for [0, d]):
// Γ(w(b − t)) − Γ(w(a − t)).
fn ldss_between(tab: texture_2d<f32>, k: u32, dir: vec3<f32>, a: f32, d: f32) -> vec3<f32> {
    let g = ldss_geometry(k, dir);
    let w0 = gamma_w(a - g.x, g.y);
    let wd = gamma_w(d - g.x, g.y);
    let st = medium.sigma_t.rgb;
    let lam = st * g.y;
    let diff = gamma_rgb(tab, lam, wd) - gamma_rgb(tab, lam, w0);
    // With the light behind the eye (t < 0) e^(−σ_t t) grows while the Γ difference shrinks into
    // f32 rounding: cap the exponent and clamp to a bound that holds exactly (x + r ≥ |OS| = D by the
    // triangle inequality, and ∫ dx/r² ≤ π/h), so f32 noise can never exceed the physics.
    let dist = sqrt(g.x * g.x + g.y * g.y);
    let pmax = max(phase(medium, 1.0), phase(medium, -1.0));
    let scale = medium.sigma_s.rgb * lights.lights[k].intensity.rgb / g.y;
    let bound = scale * pmax * PI * exp(-st * dist);
    return min(scale * exp(min(-st * g.x, vec3<f32>(80.0))) * max(diff, vec3<f32>(0.0)), bound);
}

// The ONE per-interval function of both resolves (the per-pixel walk calls it per lit interval,
// the stencil planes through `crossing_term`): the unshadowed in-scatter of light k over [a, b]
// of the view ray, dispatched on the light's kind (the scene's kinds baked: every pass that calls
// it sets the renderer's specialisation constants).
// Point: eq. 7's two Γ lookups (the paper). Directional (modernised; the paper only says it is
// easier): σ_s E p(θ) (e^(−σ_t a) − e^(−σ_t b))/σ_t, the scattering angle being constant along
// the ray. Spot (modernised): `spot_panels` two-node Gauss–Legendre panels in the angle seen from
// the light over [a, b] ∩ the outer cone, falloff and pattern at every node (light_segments.wgsl).
fn lit_between(tab: texture_2d<f32>, k: u32, dir: vec3<f32>, a: f32, b: f32, spot_panels: u32) -> vec3<f32> {
    if (b <= a) { return vec3<f32>(0.0); }
    // The scene's kinds are baked (common::specialize): lavapipe would otherwise run every kind's
    // branch for every light (measured on point-light scenes: the stencil resolve up to 3×).
    let kind = light_kind(k);
    if (scene_has_light_kind(LIGHT_DIRECTIONAL) && kind == LIGHT_DIRECTIONAL) {
        return sunlight_between(k, dir, a, b);
    }
    if (scene_has_light_kind(LIGHT_SPOT) && kind == LIGHT_SPOT) {
        return spot_between(k, dir, a, b, spot_panels);
    }
    return ldss_between(tab, k, dir, a, b);
}

// What a shadow-plane crossing at distance d adds (front face) or subtracts (back face) in the
// stencil resolve, an antiderivative of `lit_between` in d: point lights Γ's term at d
// (`ldss_term`; the resolve adds the eye's −ldss_term(0) once), other kinds ∫ from the eye to d
// (0 at the eye, so they need no eye term).
fn crossing_term(tab: texture_2d<f32>, k: u32, dir: vec3<f32>, d: f32, spot_panels: u32) -> vec3<f32> {
    let others = scene_has_light_kind(LIGHT_DIRECTIONAL) || scene_has_light_kind(LIGHT_SPOT);
    if (!others || light_kind(k) == LIGHT_POINT) { return ldss_term(tab, k, dir, d); }
    return lit_between(tab, k, dir, 0.0, d, spot_panels);
}
