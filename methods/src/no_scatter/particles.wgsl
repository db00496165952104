// no-scatter in particle media: the surface (its lights' cloud shadows already removed,
// common::particle_surfaces) or the sky, attenuated on the eye leg by the particles' exact
// optical depth (particle_trace.wgsl) and the background's e^(−σ_t d); no in-scattering. Needs
// PRELUDE, FULLSCREEN and particle_trace.wgsl.

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let hit = textureLoad(ray_distance, px, 0).r;
    let d = camera_ray_length(camera, dir, hit);
    var surf = grid.sky.rgb * transmittance(medium, d);
    if (hit >= 0.0) {
        surf = textureLoad(surface, px, 0).rgb;
    }
    let cloud = exp(-optical_depth(camera.position.xyz, dir, 0.0, d));
    // `total` here is the harness's surface AOV (ParticleSurfaces::resolve_targets).
    return Out(vec4<f32>(0.0, 0.0, 0.0, 1.0), vec4<f32>(surf * cloud, 1.0));
}
