// Homogeneous medium and phase functions, normalised so that ∫ p dω = 1 (ARCHITECTURE §1).
// Mirrors common::uniforms::MediumUniform.
struct Medium {
    sigma_a: vec4<f32>,
    // rgb: σ_s (1/m); w: phase kind (0 isotropic, 1 Henyey–Greenstein, 2 Rayleigh, 3 hazy Mie, 4 murky Mie)
    sigma_s: vec4<f32>,
    // rgb: σ_t = σ_a + σ_s (1/m); w: Henyey–Greenstein g
    sigma_t: vec4<f32>,
    // rgb: ambient radiance L_a; w: unused
    ambient: vec4<f32>,
    // exponential height fog (height_fog.wgsl): x: base height y₀ (m); y: 1/H (1/m), 0 = none
    height_fog: vec4<f32>,
};

const PI: f32 = 3.14159265358979;

// Scene-baked phase-function kind (common::specialize); the default reads the medium uniform.
const UNBAKED_PHASE: u32 = 0xffffffffu;
override PHASE_KIND: u32 = UNBAKED_PHASE;

// Scene-baked: σ_t is the same in every channel (common::specialize), so a per-channel table
// lookup needs doing once. False (the default) is always correct, only slower.
override GREY_SIGMA_T: bool = false;

// The phase function's kind: the baked constant, else the uniform's.
fn phase_kind(m: Medium) -> u32 {
    if (PHASE_KIND != UNBAKED_PHASE) { return PHASE_KIND; }
    return u32(m.sigma_s.w + 0.5);
}

// p(θ) from cos θ, θ between the light's propagation direction and the direction to the eye.
fn phase(m: Medium, cos_theta: f32) -> f32 {
    let c = clamp(cos_theta, -1.0, 1.0);
    let kind = phase_kind(m);
    switch kind {
        case 1u: {
            let g = m.sigma_t.w;
            let d = max(1.0 + g * g - 2.0 * g * c, 1e-12);
            return (1.0 - g * g) / (4.0 * PI * d * sqrt(d));
        }
        case 2u: { return 3.0 / (16.0 * PI) * (1.0 + c * c); }
        case 3u: {
            // cos¹⁶(θ/2) = ((1 + cos θ)/2)⁸
            let h = pow(0.5 * (1.0 + c), 8.0);
            return (1.0 + 9.0 * h) / (8.0 * PI);
        }
        case 4u: {
            let h = pow(0.5 * (1.0 + c), 32.0);
            return (1.0 + 50.0 * h) / (4.0 * PI + 400.0 * PI / 66.0);
        }
        default: { return 1.0 / (4.0 * PI); }
    }
}

// e^(−σ_t d) per channel.
fn transmittance(m: Medium, d: f32) -> vec3<f32> {
    return exp(-m.sigma_t.rgb * d);
}
