// The classic fog model: no in-scattering; total = attenuated surface + ambient.
// Needs PRELUDE and FULLSCREEN.

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> Out {
    let px = vec2<i32>(frag.xy);
    let dir = camera_ray_dir(camera, frag.xy);
    let d = pixel_ray_length(px, dir);
    let ambient = ambient_fog(dir, d);
    return Out(vec4<f32>(0.0, 0.0, 0.0, 1.0), vec4<f32>(textureLoad(surface, px, 0).rgb + ambient, 1.0));
}
