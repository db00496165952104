// The cloud's shadow on surfaces, per light: the scene drawn again over the surface pass's depth
// (additive), removing light SURFACE_LIGHT's contribution times 1 − e^(−τ), τ the particle
// optical depth toward that light from its slices. The shared surface pass summed every light
// unshadowed by the cloud, so after one such pass per light each light's contribution carries
// its own cloud transmittance. Needs PRELUDE, blocks.wgsl and the shared surface_pass.wgsl.

@fragment
fn fs_cloud_shadow(i: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let s = seen(i, front);
    let lit = shade_light_shadowed(SURFACE_LIGHT, s.x, s.n, s.v, s.o) * transmittance(medium, s.d);
    let blocked = 1.0 - exp(-light_optical_depth(SURFACE_LIGHT, s.x));
    return vec4<f32>(-lit * blocked, 0.0);
}
