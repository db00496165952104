// Exponential height fog (ARCHITECTURE §1): σ(y) = σ · e^(−(y − y₀)/H), σ the medium's
// coefficients at the base height y₀. The optical depth of a segment is σ_t · L, L its *fog
// length* ∫ e^(−(y − y₀)/H) ds, which has a closed form along a straight segment (taken from
// its lower end, so the exponent cannot overflow on a rising segment). Composed right after
// medium.wgsl (common::wgsl::MEDIUM); harness/src/reference/height_fog.rs is the f64 twin.

// Scene-baked: 1 when the scene has height fog, 0 when σ is constant (common::specialize);
// the default reads the medium uniform (height_fog.y = 1/H, 0 without fog).
const UNBAKED_HEIGHT_FOG: u32 = 0xffffffffu;
override HEIGHT_FOG: u32 = UNBAKED_HEIGHT_FOG;

fn has_height_fog(m: Medium) -> bool {
    if (HEIGHT_FOG != UNBAKED_HEIGHT_FOG) { return HEIGHT_FOG != 0u; }
    return m.height_fog.y > 0.0;
}

// σ(y)/σ(y₀): the factor every coefficient carries at height y (1 without height fog).
fn fog_density(m: Medium, y: f32) -> f32 {
    if (!has_height_fog(m)) { return 1.0; }
    return exp(-(y - m.height_fog.x) * m.height_fog.y);
}

// (1 − e^(−z))/z for z ≥ 0: a series below 0.1, where 1 − e^(−z) would cancel in f32
// (truncation error < z⁵/720 ≈ 1.4e-8).
fn fog_rise_factor(z: f32) -> f32 {
    if (z < 0.1) {
        return 1.0 - z * (0.5 - z * (1.0 / 6.0 - z * (1.0 / 24.0 - z / 120.0)));
    }
    return (1.0 - exp(-z)) / z;
}

// The fog length (m) of the segment from a along the unit direction d for s metres: its
// optical depth over σ_t(y₀). Exactly s without height fog.
fn fog_length(m: Medium, a: vec3<f32>, d: vec3<f32>, s: f32) -> f32 {
    if (!has_height_fog(m)) { return s; }
    let rise = d.y * s;
    let y_low = a.y + min(rise, 0.0);
    return fog_density(m, y_low) * s * fog_rise_factor(abs(rise) * m.height_fog.y);
}

// e^(−τ) per channel over the segment from a along unit d for s metres (e^(−σ_t s) without
// height fog, computed exactly as `transmittance`).
fn transmittance_along(m: Medium, a: vec3<f32>, d: vec3<f32>, s: f32) -> vec3<f32> {
    if (!has_height_fog(m)) { return transmittance(m, s); }
    return exp(-m.sigma_t.rgb * fog_length(m, a, d, s));
}

// The factors of a local light's in-scatter integrand that height fog changes, at distance t
// along the unit ray dir from the eye, r from the light in the unit direction to_light:
// (σ_s(x)/σ_s(y₀)) · e^(−τ(eye → x) − τ(x → light)); e^(−σ_t (t + r)) without height fog.
fn scattering_path(m: Medium, eye: vec3<f32>, dir: vec3<f32>, t: f32, to_light: vec3<f32>, r: f32) -> vec3<f32> {
    if (!has_height_fog(m)) { return transmittance(m, t + r); }
    let x = eye + dir * t;
    let l = fog_length(m, eye, dir, t) + fog_length(m, x, to_light, r);
    return fog_density(m, x.y) * exp(-m.sigma_t.rgb * l);
}

// The same for a directional light, whose light leg is not attenuated (ARCHITECTURE §1):
// (σ_s(x)/σ_s(y₀)) · e^(−τ(eye → x)) at x = eye + dir t; e^(−σ_t t) without height fog.
fn sun_path(m: Medium, eye: vec3<f32>, dir: vec3<f32>, t: f32) -> vec3<f32> {
    if (!has_height_fog(m)) { return transmittance(m, t); }
    return fog_density(m, eye.y + dir.y * t) * exp(-m.sigma_t.rgb * fog_length(m, eye, dir, t));
}

// The mean of σ(y)/σ(y₀) over the segment from a along unit d for s metres (1 without fog).
fn fog_mean_density(m: Medium, a: vec3<f32>, d: vec3<f32>, s: f32) -> f32 {
    if (!has_height_fog(m)) { return 1.0; }
    return fog_length(m, a, d, s) / max(s, 1e-30);
}

// ∫ (σ(x)/σ(y₀)) e^(−τ(eye → x)) dt over [ta, tb] of the unit ray dir from the eye (a
// directional light's unshadowed in-scatter per unit σ_s E p): σ_s(x) dt = σ_s dL in the fog
// length L, so it is (e^(−τ(ta)) − e^(−τ(tb))) / σ_t, and the fog length of [ta, tb] where
// σ_t times it is below 1e-5 (no cancellation); tb − ta and e^(−σ_t t) without height fog.
fn attenuated_fog_length(m: Medium, eye: vec3<f32>, dir: vec3<f32>, ta: f32, tb: f32) -> vec3<f32> {
    let st = m.sigma_t.rgb;
    let e = (transmittance_along(m, eye, dir, ta) - transmittance_along(m, eye, dir, tb)) / max(st, vec3<f32>(1e-12));
    let l = fog_length(m, eye + dir * ta, dir, tb - ta);
    return select(e, vec3<f32>(l), st * l < vec3<f32>(1e-5));
}
