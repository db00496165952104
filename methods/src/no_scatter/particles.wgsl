// no-scatter in particle media: the surface (its lights' cloud shadows already removed,
// common::particles::surfaces) or the sky, attenuated on the eye leg by the particles' exact
// optical depth (particle_trace.wgsl) and the background's e^(−σ_t d); no in-scattering. Needs
// PRELUDE, FULLSCREEN, particle_trace.wgsl and particle_resolve.wgsl.

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let ray = pixel_ray(px, frag.xy);
    let cloud = exp(-optical_depth(camera.position.xyz, ray.dir, 0.0, ray.d));
    // `total` here is the harness's surface AOV (ParticleSurfaces::resolve_targets).
    return Out(vec4<f32>(0.0, 0.0, 0.0, 1.0), vec4<f32>(surface_or_sky(px, ray) * cloud, 1.0));
}
