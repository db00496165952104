// The cloud's shadow on surfaces, per light (common::particles::surfaces): the scene redrawn over
// the surface pass's depth (additive), removing light SURFACE_LIGHT's contribution times
// 1 − e^(−τ), τ the particles' exact optical depth toward that light (particle_trace.wgsl). The
// shared surface pass summed every light unshadowed by the cloud, so after one such pass per
// light each light's term carries its own transmittance. Needs PRELUDE, SURFACE_PASS and
// particle_trace.wgsl.

@fragment
fn fs_cloud_shadow(i: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let s = seen(i, front);
    let lit = shade_light_shadowed(SURFACE_LIGHT, s.x, s.n, s.v, s.o) * eye_transmittance(s.x, s.d);
    let blocked = 1.0 - exp(-light_leg_depth(SURFACE_LIGHT, s.x));
    return vec4<f32>(-lit * blocked, 0.0);
}
