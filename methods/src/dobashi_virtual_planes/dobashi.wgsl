// Dobashi, Yamamoto & Nishita (2000), eq. 5: I_s ≈ Σ_k I(θ_k, φ_k) ξ(t_k) H(t_k) Δt. The smooth
// factor ξ is evaluated on the planes' lattice (or per fragment), the light map I(θ, φ) and the
// visibility H per fragment. Shared by the plane, resolve and probe passes. Needs PRELUDE.

// Mirrors `PlanesUniform` in passes.rs, field for field.
struct Planes {
    count: u32,     // the `planes` knob: virtual planes n, 1 … 4096
    nu: u32,        // the `lattice` knob: lattice points per row, 2 … 1024
    nv: u32,        // lattice points per column
    flags: u32,     // FLAG_JITTER | FLAG_CLIP_LAST
    frame: u32,     // frame index (jitter seed)
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    scale: f32,     // accumulation scale s (the target holds s·L_in; 1 for float targets)
    _pad3: f32,
    _pad4: f32,
    _pad5: f32,
};

const FLAG_JITTER: u32 = 1u;
const FLAG_CLIP_LAST: u32 = 4u;

// ξ of light k at world point x, distance t from the eye along the unit ray `dir` (eye → x):
// σ_s p(α) e^(−σt (t + r)) / r² for point and spot lights (eq. 5), σ_s p(α) e^(−σt t) for a
// parallel light, whose light leg is not attenuated (ARCHITECTURE §1).
fn xi(k: u32, x: vec3<f32>, dir: vec3<f32>, t: f32) -> vec3<f32> {
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        let l = lights.lights[k].direction.xyz;
        let path = sun_path(medium, camera.position.xyz, dir, t);
        return medium.sigma_s.rgb * phase(medium, dot(l, -dir)) * path;
    }
    let w = x - lights.lights[k].position.xyz;
    let r2 = max(dot(w, w), 1e-12);
    let r = sqrt(r2);
    let path = scattering_path(medium, camera.position.xyz, dir, t, -w / r, r);
    return medium.sigma_s.rgb * phase(medium, dot(w / r, -dir)) * path / r2;
}

// The light map: I(θ, φ) of light k toward world point x, W/sr (the irradiance E for a parallel
// light). For a spot, the pattern texture is projected from the light onto the plane — projective
// texturing with slide coordinates ((w·right)/(w·axis), (w·up)/(w·axis)) — times the cone falloff.
fn light_map(k: u32, x: vec3<f32>) -> vec3<f32> {
    return light_intensity(k, x - lights.lights[k].position.xyz);
}
