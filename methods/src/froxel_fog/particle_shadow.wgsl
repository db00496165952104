// Particle media: the cloud's shadow on surfaces, per light (common::particles::surface_shadow).
// The shared
// surface pass summed every light unshadowed by the cloud; this fragment removes light
// SURFACE_LIGHT's contribution times 1 − e^(−τ), τ the particle optical depth toward that light
// from its extinction grid, so that after one pass per light each light's term carries its own
// cloud transmittance. Needs PRELUDE, extinction.wgsl and the shared surface_pass.wgsl.

@group(1) @binding(0) var<uniform> particle_medium: ParticleMedium;
@group(1) @binding(1) var<storage, read> optical_depth: array<f32>;

@fragment
fn fs_cloud_shadow(i: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let s = seen(i, front);
    let lit = shade_light_shadowed(SURFACE_LIGHT, s.x, s.n, s.v, s.o) * eye_transmittance(s.x, s.d);
    // A hair toward the eye, so that the surface does not shadow itself through the grid.
    let tau = particle_depth_to_light(SURFACE_LIGHT, s.x + s.v * (s.d * 1e-4));
    return vec4<f32>(-lit * (1.0 - exp(-tau)), 0.0);
}
